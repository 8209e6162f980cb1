"""A small image encoder per camera, as the paper's BC and RL baselines use."""

from __future__ import annotations

import torch
from torch import nn


class CameraEncoder(nn.Module):
    """Three 3x3 convolutions of 32 channels (stride 2) with SiLU and layer norm, then a
    linear map of the flattened features to ``dim``: cheap enough for CPU training."""

    def __init__(self, channels: int, resolution: tuple[int, int], dim: int) -> None:
        super().__init__()
        layers: list[nn.Module] = []
        h, w = resolution
        for i in range(3):
            layers += [nn.Conv2d(channels if i == 0 else 32, 32, 3, stride=2), nn.SiLU()]
            h, w = (h - 3) // 2 + 1, (w - 3) // 2 + 1
            layers.append(nn.LayerNorm([32, h, w]))
        self.convs = nn.Sequential(*layers)
        self.out = nn.Linear(32 * h * w, dim)

    def forward(self, image: torch.Tensor) -> torch.Tensor:
        return self.out(self.convs(image).flatten(1))


class Cameras(nn.Module):
    """One encoder per camera key; returns their features stacked as (batch, cameras, dim)."""

    def __init__(self, image_shapes: dict[str, tuple[int, int, int]], dim: int) -> None:
        super().__init__()
        self.keys = sorted(image_shapes)
        self.encoders = nn.ModuleDict(
            {k.replace(".", "_"): CameraEncoder(s[0], (s[1], s[2]), dim) for k, s in image_shapes.items()}
        )

    def forward(self, batch: dict[str, torch.Tensor]) -> torch.Tensor:
        return torch.stack([self.encoders[k.replace(".", "_")](batch[k]) for k in self.keys], dim=1)
