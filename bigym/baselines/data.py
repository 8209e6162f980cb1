"""Training data from replayed demos: observation features, normalisation, action chunks.

Every method here predicts a *chunk* of the next ``H`` actions from one observation. A
sample pairs observation ``t`` with actions ``t .. t+H-1``; near the end of a demo the
chunk is padded with its last action and the padding is masked out of the loss, or (with
``tail``) filled from what the recording holds after the episode's end.

The env's base actions are per-step moves (deltas) even in the absolute action mode. A
policy that predicts moves lets its errors add up: a base that drifts keeps drifting, out
of what the demos showed. The models therefore learn the base as *targets*, the servo
targets after each action (``proprioception_floating_base_actions`` of the next
observation), like the arms' absolute joint targets; the policy turns a predicted target
back into the move from the current target (:mod:`bigym.baselines.policy`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch

from bigym.baselines.modes import demo_modes
from bigym.observations import is_image_key

BASE_TARGETS = "proprioception_floating_base_actions"
DEPTH_RANGE = 5.0  # metres mapped to [0, 1] for the image encoders


@dataclass
class Normalizer:
    """State features to zero mean and unit spread; actions to [-1, 1] per entry.

    Entries that never change in the demos (an idle arm's target, say) get a unit scale,
    so they map to a constant instead of a division by zero.
    """

    state_mean: np.ndarray
    state_std: np.ndarray
    action_center: np.ndarray
    action_half_range: np.ndarray

    @classmethod
    def fit(cls, states: np.ndarray, actions: np.ndarray) -> Normalizer:
        std = states.std(axis=0)
        low, high = actions.min(axis=0), actions.max(axis=0)
        half = (high - low) / 2
        return cls(
            state_mean=states.mean(axis=0).astype(np.float32),
            state_std=np.where(std > 1e-6, std, 1.0).astype(np.float32),
            action_center=((high + low) / 2).astype(np.float32),
            action_half_range=np.where(half > 1e-6, half, 1.0).astype(np.float32),
        )

    def states(self, states: np.ndarray) -> np.ndarray:
        return ((states - self.state_mean) / self.state_std).astype(np.float32)

    def actions(self, actions: np.ndarray) -> np.ndarray:
        return ((actions - self.action_center) / self.action_half_range).astype(np.float32)

    def unnormalize_actions(self, actions: np.ndarray) -> np.ndarray:
        return actions * self.action_half_range + self.action_center

    def to_dict(self) -> dict:
        return {k: torch.from_numpy(np.asarray(v)) for k, v in vars(self).items()}

    @classmethod
    def from_dict(cls, data: dict) -> Normalizer:
        return cls(**{k: np.asarray(v.numpy() if isinstance(v, torch.Tensor) else v) for k, v in data.items()})


def base_indices(action_names: list[str]) -> list[int]:
    """Where the base moves sit in the action vector."""
    return [i for i, name in enumerate(action_names) if name.startswith("base_")]


def target_actions(demo, base: list[int]) -> np.ndarray:
    """A demo's actions with the base moves replaced by the base targets they led to."""
    steps = len(demo.actions)
    actions = demo.actions.astype(np.float32).copy()
    if base:
        actions[:, base] = demo.observations[BASE_TARGETS][1 : steps + 1]
    return actions


def state_keys(observations: dict) -> list[str]:
    """The non-image observation keys, in a fixed order."""
    return sorted(k for k in observations if not is_image_key(k))


def state_vector(obs: dict, keys: list[str]) -> np.ndarray:
    """Concatenate the named state entries of one observation (or of a batch, last axis)."""
    return np.concatenate([np.asarray(obs[k], np.float32).reshape(*np.shape(obs[k])[:-1], -1) for k in keys], axis=-1)


def image_tensor(obs: dict, key: str) -> np.ndarray:
    """One camera's image as float32 in [0, 1], channels first (depth as one channel)."""
    image = np.asarray(obs[key])
    if key.startswith("depth_"):
        return (np.clip(image, 0.0, DEPTH_RANGE) / DEPTH_RANGE)[..., None, :, :].astype(np.float32)
    return image.astype(np.float32) / 255.0


class ChunkDataset:
    """All (observation, action chunk) samples of a list of replayed demos, held in memory."""

    def __init__(
        self, demos: list, chunk: int, image_keys: list[str], normalizer: Normalizer | None = None,
        hold_end: bool = False, modes: int = 0, tail: bool = False,
    ) -> None:  # fmt: skip
        if not demos:
            raise ValueError("no demos to train on")
        self.state_keys = state_keys(demos[0].observations)
        self.image_keys = list(image_keys)
        missing = [k for k in self.image_keys if k not in demos[0].observations]
        if missing:
            raise ValueError(f"the replayed demos have no {missing}: replay them with those cameras")
        self.base_indices = base_indices(demos[0].metadata.action_names)
        if self.base_indices and BASE_TARGETS not in demos[0].observations:
            raise ValueError(f"the floating base is learned as targets: the demos need {BASE_TARGETS} (proprioception)")
        states, actions, chunks, pads, images = [], [], [], [], {k: [] for k in self.image_keys}
        for demo in demos:
            recorded = len(demo.actions)  # the episode, and with ``tail`` the steps after it
            steps = demo.report.episode_steps if tail and demo.report.episode_steps else recorded
            if tail and recorded < demo.report.replayed_steps:
                raise ValueError(f"demo {demo.uuid} was replayed without the steps after its episode's end")
            obs = {k: v[:steps] for k, v in demo.observations.items()}
            states.append(state_vector(obs, self.state_keys))
            targets = target_actions(demo, self.base_indices)
            actions.append(targets)  # (the normaliser's range covers the chunks' targets)
            index = np.arange(steps)[:, None] + np.arange(chunk)[None, :]
            pads.append(np.zeros_like(index, dtype=bool) if hold_end else index >= recorded)
            chunks.append(targets[np.minimum(index, recorded - 1)])
            for key in self.image_keys:
                images[key].append(obs[key])
        all_states, all_actions = np.concatenate(states), np.concatenate(actions)
        self.normalizer = normalizer if normalizer is not None else Normalizer.fit(all_states, all_actions)
        self.states = torch.from_numpy(self.normalizer.states(all_states))
        self.chunks = torch.from_numpy(self.normalizer.actions(np.concatenate(chunks)))
        self.pad = torch.from_numpy(np.concatenate(pads))
        self.images = {k: np.concatenate(v) for k, v in images.items()}  # kept compact (uint8 RGB)
        self.chunk = chunk
        # each demo's mode (bigym.baselines.modes), repeated for each of its samples
        self.demo_modes = (
            demo_modes([self.normalizer.actions(a) for a in actions], modes) if modes else np.zeros(0, dtype=np.int64)
        )
        self.modes = torch.from_numpy(np.repeat(self.demo_modes, [len(s) for s in states])) if modes else None

    def __len__(self) -> int:
        return len(self.states)

    @property
    def state_dim(self) -> int:
        return self.states.shape[1]

    @property
    def action_dim(self) -> int:
        return self.chunks.shape[2]

    def samples(self, index: torch.Tensor) -> dict[str, torch.Tensor]:
        """The samples at ``index``: state, action chunk, its padding, mode and images."""
        batch = {"state": self.states[index], "actions": self.chunks[index], "pad": self.pad[index]}
        if self.modes is not None:
            batch["mode"] = self.modes[index]
        for key in self.image_keys:
            batch[key] = torch.from_numpy(image_tensor({key: self.images[key][index.numpy()]}, key))
        return batch

    def batch(self, size: int, generator: torch.Generator, state_noise: float = 0.0) -> dict[str, torch.Tensor]:
        """``size`` random samples; ``state_noise`` > 0 adds Gaussian noise of that spread
        to their normalised states (drawn after the indices, so 0 leaves the draws as they were)."""
        batch = self.samples(torch.randint(len(self), (size,), generator=generator))
        if state_noise > 0:
            batch["state"] = batch["state"] + state_noise * torch.randn(batch["state"].shape, generator=generator)
        return batch
