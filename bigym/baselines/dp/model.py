"""A 1-D convolutional U-Net that predicts the noise added to an action chunk, conditioned
(FiLM) on the observation and the diffusion step; trained as DDPM, sampled with DDIM."""

from __future__ import annotations

import math

import torch
from torch import nn
from torch.nn import functional as F

from bigym.baselines.common import ChunkModel
from bigym.baselines.dp.config import DPConfig
from bigym.baselines.vision import Cameras


def cosine_alphas_cumprod(steps: int) -> torch.Tensor:
    """The squared-cosine noise schedule (Nichol and Dhariwal, 2021), betas capped at 0.999."""
    t = torch.linspace(0, steps, steps + 1, dtype=torch.float64) / steps
    f = torch.cos((t + 0.008) / 1.008 * math.pi / 2) ** 2
    betas = (1 - f[1:] / f[:-1]).clamp(max=0.999)
    return torch.cumprod(1 - betas, dim=0).float()


def step_embedding(step: torch.Tensor, dim: int) -> torch.Tensor:
    half = dim // 2
    frequencies = torch.exp(-math.log(10_000) * torch.arange(half, dtype=torch.float32, device=step.device) / half)
    angles = step.float()[:, None] * frequencies[None]
    return torch.cat([angles.sin(), angles.cos()], dim=1)


class FiLMBlock(nn.Module):
    """Two convolutions; the condition scales and shifts the features between them."""

    def __init__(self, inputs: int, outputs: int, condition: int) -> None:
        super().__init__()
        self.first = nn.Sequential(nn.Conv1d(inputs, outputs, 5, padding=2), nn.GroupNorm(8, outputs), nn.Mish())
        self.second = nn.Sequential(nn.Conv1d(outputs, outputs, 5, padding=2), nn.GroupNorm(8, outputs), nn.Mish())
        self.film = nn.Sequential(nn.Mish(), nn.Linear(condition, 2 * outputs))
        self.skip = nn.Conv1d(inputs, outputs, 1) if inputs != outputs else nn.Identity()

    def forward(self, x: torch.Tensor, condition: torch.Tensor) -> torch.Tensor:
        scale, shift = self.film(condition)[..., None].chunk(2, dim=1)
        return self.second(self.first(x) * (1 + scale) + shift) + self.skip(x)


class NoiseNet(nn.Module):
    def __init__(self, action_dim: int, condition: int, channels: tuple[int, ...]) -> None:
        super().__init__()
        widths = [action_dim, *channels]
        self.down = nn.ModuleList(FiLMBlock(a, b, condition) for a, b in zip(widths[:-1], widths[1:]))
        self.middle = FiLMBlock(channels[-1], channels[-1], condition)
        self.up = nn.ModuleList(FiLMBlock(a + b, a, condition) for a, b in zip(channels[:-1][::-1], channels[1:][::-1]))
        self.out = nn.Conv1d(channels[0], action_dim, 1)

    def forward(self, x: torch.Tensor, condition: torch.Tensor) -> torch.Tensor:
        skips = []
        for i, block in enumerate(self.down):
            x = block(x, condition)
            skips.append(x)
            if i < len(self.down) - 1:
                x = F.avg_pool1d(x, 2)
        x = self.middle(x, condition)
        skips.pop()
        for block in self.up:
            skip = skips.pop()
            x = F.interpolate(x, size=skip.shape[-1], mode="nearest")
            x = block(torch.cat([x, skip], dim=1), condition)
        return self.out(x)


class DPModel(ChunkModel):
    def __init__(self, config: DPConfig, state_dim: int, action_dim: int, image_shapes: dict) -> None:
        super().__init__()
        self.config, self.action_dim = config, action_dim
        d = config.hidden
        self.cameras = Cameras(image_shapes, d) if image_shapes else None
        self.observation = nn.Sequential(nn.Linear(state_dim + d * len(image_shapes), d), nn.Mish(), nn.Linear(d, d))
        self.step = nn.Sequential(nn.Linear(d, d), nn.Mish(), nn.Linear(d, d))
        self.net = NoiseNet(action_dim, 2 * d, config.channels)
        self.register_buffer("alphas_cumprod", cosine_alphas_cumprod(config.train_timesteps))

    def _condition(self, batch: dict[str, torch.Tensor]) -> torch.Tensor:
        features = batch["state"]
        if self.cameras is not None:
            features = torch.cat([features, self.cameras(batch).flatten(1)], dim=1)
        return self.observation(features)

    def _noise(self, chunk: torch.Tensor, steps: torch.Tensor, observation: torch.Tensor) -> torch.Tensor:
        condition = torch.cat([observation, self.step(step_embedding(steps, self.config.hidden))], dim=1)
        return self.net(chunk.transpose(1, 2), condition).transpose(1, 2)

    def loss(self, batch: dict[str, torch.Tensor], generator: torch.Generator) -> tuple[torch.Tensor, dict]:
        actions = batch["actions"]
        n = len(actions)
        # drawn on the CPU generator (seeded, resumable), then moved to the model's device
        steps = torch.randint(self.config.train_timesteps, (n,), generator=generator).to(actions.device)
        noise = torch.randn(actions.shape, generator=generator).to(actions.device)
        alpha = self.alphas_cumprod[steps][:, None, None]
        noisy = alpha.sqrt() * actions + (1 - alpha).sqrt() * noise
        error = (self._noise(noisy, steps, self._condition(batch)) - noise) ** 2
        keep = (~batch["pad"]).unsqueeze(-1).float()
        loss = (error * keep).sum() / (keep.sum() * self.action_dim).clamp(min=1.0)
        return loss, {"mse": loss.item()}

    @torch.no_grad()
    def predict(self, batch: dict[str, torch.Tensor], generator: torch.Generator | None = None) -> torch.Tensor:
        """DDIM (deterministic given the starting noise) from pure noise to a chunk."""
        observation = self._condition(batch)
        n = len(observation)
        device = observation.device
        x = torch.randn((n, self.config.chunk, self.action_dim), generator=generator).to(device)
        total, count = self.config.train_timesteps, self.config.inference_steps
        schedule = torch.linspace(total - 1, 0, count).round().long()
        for i, t in enumerate(schedule):
            alpha = self.alphas_cumprod[t]
            alpha_next = self.alphas_cumprod[schedule[i + 1]] if i + 1 < count else torch.tensor(1.0, device=device)
            noise = self._noise(x, t.repeat(n).to(device), observation)
            clean = ((x - (1 - alpha).sqrt() * noise) / alpha.sqrt()).clamp(-1.0, 1.0)
            x = alpha_next.sqrt() * clean + (1 - alpha_next).sqrt() * noise
        return x
