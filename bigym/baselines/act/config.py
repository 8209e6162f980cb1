from __future__ import annotations

from dataclasses import dataclass

from bigym.baselines.common import TrainConfig


@dataclass
class ACTConfig(TrainConfig):
    # smaller than ACT's (512 wide, 4 + 7 layers) so that it trains on a laptop CPU in minutes
    hidden: int = 128  # transformer width
    heads: int = 4
    encoder_layers: int = 2
    decoder_layers: int = 2
    feedforward: int = 512
    dropout: float = 0.1
    latent: int = 32
    kl_weight: float = 10.0  # ACT's beta
