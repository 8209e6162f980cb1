from __future__ import annotations

from dataclasses import dataclass

from bigym.baselines.common import TrainConfig


@dataclass
class DPConfig(TrainConfig):
    hidden: int = 256  # observation embedding
    channels: tuple[int, ...] = (128, 256)  # widths of the 1-D U-Net's levels
    train_timesteps: int = 100
    inference_steps: int = 10  # DDIM steps at run time
    lr: float = 3e-4
