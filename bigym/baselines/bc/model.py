"""An MLP that maps the state (and camera features) to a chunk of actions, trained with L1."""

from __future__ import annotations

import torch
from torch import nn

from bigym.baselines.bc.config import BCConfig
from bigym.baselines.common import ChunkModel, masked_l1
from bigym.baselines.vision import Cameras


class BCModel(ChunkModel):
    def __init__(self, config: BCConfig, state_dim: int, action_dim: int, image_shapes: dict) -> None:
        super().__init__()
        self.config, self.action_dim = config, action_dim
        self.cameras = Cameras(image_shapes, config.hidden) if image_shapes else None
        width = state_dim + config.hidden * len(image_shapes)
        layers: list[nn.Module] = []
        for _ in range(config.layers):
            layers += [nn.Linear(width, config.hidden), nn.LayerNorm(config.hidden), nn.SiLU()]
            width = config.hidden
        layers.append(nn.Linear(width, config.chunk * action_dim))
        self.net = nn.Sequential(*layers)

    def _features(self, batch: dict[str, torch.Tensor]) -> torch.Tensor:
        if self.cameras is None:
            return batch["state"]
        return torch.cat([batch["state"], self.cameras(batch).flatten(1)], dim=1)

    def predict(self, batch: dict[str, torch.Tensor], generator: torch.Generator | None = None) -> torch.Tensor:
        return self.net(self._features(batch)).view(-1, self.config.chunk, self.action_dim)

    def loss(self, batch: dict[str, torch.Tensor], generator: torch.Generator) -> tuple[torch.Tensor, dict]:
        loss = masked_l1(self.predict(batch), batch["actions"], batch["pad"])
        return loss, {"l1": loss.item()}
