"""What every baseline shares: the settings of a training run and the chunk loss."""

from __future__ import annotations

from dataclasses import dataclass

import torch
from torch import nn


@dataclass
class TrainConfig:
    """Settings common to the methods (each method's config adds its own)."""

    chunk: int = 16  # actions predicted per observation (the paper: 16)
    batch_size: int = 64
    steps: int = 20_000
    lr: float = 1e-4  # the paper's Adam learning rate
    weight_decay: float = 1e-4
    hidden: int = 256
    # Demos end at their first success. False: a chunk that reaches past the end is masked
    # there (ACT's is_pad); True: it is trained to hold the demo's last action, what the
    # robot does if the episode goes on. Neither won on every task (README, "Baselines").
    hold_end: bool = False
    # Expert recordings go on about 1 s past the episode's end (its first success), so that
    # slower replays still reach it. True: a chunk that reaches past the end is trained on
    # those recorded steps (what the demonstrator went on doing: into the target, the drawer
    # further shut) instead of being masked or held; the samples are still the episode's.
    tail: bool = False
    # Decay of a moving average of the weights (bigym.baselines.ema) that then acts instead
    # of the last weights; 0 keeps none. 0.999 averages over about the last 1,000 steps.
    ema: float = 0.0
    # Standard deviation of Gaussian noise added to the normalised state of every training
    # sample (in units of each entry's spread in the demos); 0 adds none. It asks the model
    # to act alike on nearby states, what 50 demos over a region of targets cannot show.
    state_noise: float = 0.0


class ChunkModel(nn.Module):
    """What a method's model offers training and acting: ``loss(batch, generator)`` ->
    (loss, logged figures), ``predict(batch, generator)`` -> a normalised chunk per sample,
    and ``start_episode(batch, generator)``, the draws that stay fixed for an episode given
    its first observation's batch, added to every batch of it (none here; ACT's sampled
    latent and demo mode)."""

    def start_episode(self, batch: dict[str, torch.Tensor], generator: torch.Generator) -> dict[str, torch.Tensor]:
        return {}


def masked_l1(predicted: torch.Tensor, target: torch.Tensor, pad: torch.Tensor) -> torch.Tensor:
    """Mean absolute error over the real (not padded) steps of each chunk."""
    keep = (~pad).unsqueeze(-1).float()
    return ((predicted - target).abs() * keep).sum() / (keep.sum() * predicted.shape[-1]).clamp(min=1.0)
