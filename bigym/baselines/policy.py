"""A trained checkpoint as a policy for :mod:`bigym.evaluation`: one chunk predicted per
step, the overlapping chunks averaged (ACT's temporal ensembling)."""

from __future__ import annotations

import functools
import math
from collections import deque
from pathlib import Path

import numpy as np
import torch

from bigym.baselines.checkpoint import Checkpoint
from bigym.baselines.data import BASE_TARGETS, image_tensor, state_vector

#: ACT's weight step between successive chunks' predictions for one step (README, "Baselines")
ENSEMBLE_DECAY = 0.01


def temporal_ensemble(predictions: list[np.ndarray], decay: float) -> np.ndarray:
    """Average the actions that chunks predicted for this step, oldest first, weighted
    ``exp(-decay * i)``: the oldest prediction weighs most, as in ACT, which keeps the
    motion smooth while newer chunks steer it."""
    weights = np.exp(-decay * np.arange(len(predictions)))
    return (np.stack(predictions) * weights[:, None]).sum(axis=0) / weights.sum()


class ChunkPolicy:
    """Runs a checkpoint in an env whose action mode, rate and observations match it."""

    def __init__(self, env, checkpoint: Checkpoint, ensemble_decay: float = ENSEMBLE_DECAY) -> None:
        base = env.unwrapped
        _check_env(base, checkpoint)
        self.checkpoint = checkpoint
        self.model = checkpoint.build_model().eval()
        self.normalizer = checkpoint.make_normalizer()
        self.image_keys = sorted(checkpoint.image_shapes)
        self.decay = ensemble_decay
        self.chunk = checkpoint.config.get("chunk", 16)
        self._low, self._high = base.action_space.low, base.action_space.high
        self._base = np.array(checkpoint.base_indices, dtype=int)
        self._generator = torch.Generator()
        self.reset(0)

    def reset(self, seed: int | None) -> None:
        self._generator.manual_seed(0 if seed is None else int(seed))
        self._episode: dict[str, torch.Tensor] | None = None  # drawn at the episode's first step
        self._chunks: deque[tuple[int, np.ndarray]] = deque()
        self._t = 0

    @torch.no_grad()
    def __call__(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        state = self.normalizer.states(state_vector(obs, self.checkpoint.state_keys))
        batch = {"state": torch.from_numpy(state)[None]}
        for key in self.image_keys:
            batch[key] = torch.from_numpy(image_tensor({key: obs[key]}, key))[None]
        if self._episode is None:
            self._episode = self.model.start_episode(batch, self._generator)
        batch.update(self._episode)
        # within the demos' range of every entry (the normalised [-1, 1]): a model that
        # extrapolates cannot command a target, or a base position, no demo ever reached
        chunk = self.model.predict(batch, self._generator)[0].clamp(-1.0, 1.0).numpy()
        self._chunks.append((self._t, self.normalizer.unnormalize_actions(chunk)))
        while self._chunks[0][0] + self.chunk <= self._t:
            self._chunks.popleft()
        action = temporal_ensemble([c[self._t - start] for start, c in self._chunks], self.decay)
        if len(self._base):  # predicted base targets -> the move from the current targets
            action[self._base] -= obs[BASE_TARGETS]
        self._t += 1
        return np.clip(action, self._low, self._high).astype(np.float32)


def _check_env(env, checkpoint: Checkpoint) -> None:
    problems = []
    if env.task_name != checkpoint.task:
        problems.append(f"it was trained on {checkpoint.task}, the env runs {env.task_name}")
    mode = env.action_mode.to_dict()
    if mode != checkpoint.action_mode:
        problems.append(f"action mode {checkpoint.action_mode} expected, the env has {mode}")
    if abs(env.control_frequency - checkpoint.frequency) > 1e-9:
        problems.append(f"trained at {checkpoint.frequency:g} Hz, the env runs at {env.control_frequency:g} Hz")
    keys = set(env.observation_space.spaces)
    needed = [*checkpoint.state_keys, *checkpoint.image_shapes, *([BASE_TARGETS] if checkpoint.base_indices else [])]
    missing = [k for k in dict.fromkeys(needed) if k not in keys]
    if missing:
        problems.append(f"the env's observations lack {', '.join(missing)}")
    if problems:
        raise ValueError("this checkpoint does not fit the env: " + "; ".join(problems))


def load_policy(env, checkpoint: str | Path, ensemble_decay: float = ENSEMBLE_DECAY) -> ChunkPolicy:
    """The policy factory of a checkpoint file: ``load_policy(env, path)``."""
    return ChunkPolicy(env, Checkpoint.load(checkpoint), ensemble_decay)


def checkpoint_factory(path: str | Path, ensemble_decay: float = ENSEMBLE_DECAY) -> functools.partial:
    """``factory(env)`` for :func:`bigym.evaluation.evaluate` (picklable, for its workers);
    ``ensemble_decay`` as for :func:`temporal_ensemble` (named in the record's policy only
    when it is not ACT's)."""
    if not (isinstance(ensemble_decay, (int, float)) and math.isfinite(ensemble_decay)):
        raise ValueError(f"ensemble_decay must be a finite number, got {ensemble_decay!r}")
    keywords: dict = {"checkpoint": str(Path(path).resolve())}
    if ensemble_decay != ENSEMBLE_DECAY:
        keywords["ensemble_decay"] = float(ensemble_decay)
    return functools.partial(load_policy, **keywords)
