from __future__ import annotations

from dataclasses import dataclass

from bigym.baselines.common import TrainConfig


@dataclass
class BCConfig(TrainConfig):
    layers: int = 3
    hidden: int = 512
    lr: float = 3e-4
