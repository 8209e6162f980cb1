"""Demos as flat transition arrays: the layout offline-RL libraries read (d3rlpy, ...).

Offline-RL libraries want one float vector per observation and actions in [-1, 1]: d3rlpy's
policies are tanh-bounded and its evaluator rejects Dict observations, while bigym's actions
are absolute joint targets (about [-1.6, 1.0] rad) and its observations a dict.
:class:`FlatSpaces` fixes both maps for one env: observations flattened in the observation
space's key order (the vector gymnasium's ``FlattenObservation`` gives), actions scaled from the
action space's bounds to [-1, 1]. :func:`transitions` lays replayed demos out in those
spaces with the rewards, terminals and timeouts the env gave; :meth:`Transitions.to_d3rlpy`
hands them to d3rlpy (imported there only). A policy trained on them acts through the same
:class:`FlatSpaces`: ``spaces.env_action(model(spaces.flatten(obs)), obs)``.

The floating base's actions are per-step *moves* even in the absolute action mode. A policy
that outputs moves adds up its errors: a small bias walks the robot away (an IQL actor
trained on moves drove the base at 2-5 m/s and left the workspace within 2 s, on every
episode). By default (``base="targets"``) the model's actions therefore hold the base's
servo *targets* after each step, absolute like the arms' joint targets, bounded by what the
demos visited; :meth:`FlatSpaces.env_action` turns a predicted target back into the move
from the target observed now (``proprioception_floating_base_actions``). The bigym
baselines learn the base the same way.
"""

from __future__ import annotations

import json
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bigym.demonstrations.demo import ReplayedDemo
from bigym.demonstrations.errors import DemoError
from bigym.observations import is_image_key

#: the observation that holds the base's servo targets (floating base)
BASE_TARGETS = "proprioception_floating_base_actions"


@dataclass(frozen=True)
class FlatSpaces:
    """How one env's observations become a flat vector and its actions a vector in [-1, 1]."""

    keys: tuple[str, ...]
    sizes: tuple[int, ...]
    #: bounds of the model's actions, scaled to [-1, 1] (the env's, except base targets)
    action_low: np.ndarray
    action_high: np.ndarray
    #: with base targets: the base's action entries, the flat observation entries holding
    #: their current targets, and the env's bounds on a move (a predicted move is clipped there)
    base_actions: tuple[int, ...] = ()
    base_observed: tuple[int, ...] = ()
    move_low: np.ndarray | None = None
    move_high: np.ndarray | None = None

    @property
    def base_targets(self) -> bool:
        """Whether the model's base actions are servo targets (else the env's moves)."""
        return bool(self.base_actions)

    @classmethod
    def from_env(cls, env) -> FlatSpaces:
        """The maps for ``env``'s spaces; camera observations are refused (flat state only)."""
        space = env.observation_space
        images = [key for key in space.spaces if is_image_key(key)]
        if images:
            raise DemoError(
                f"flat transitions hold state observations only; this env also observes {', '.join(images)} "
                "(make the env without cameras, or export images with export_lerobot / export_robomimic)"
            )
        low, high = np.asarray(env.action_space.low, np.float64), np.asarray(env.action_space.high, np.float64)
        if not (np.all(np.isfinite(low)) and np.all(np.isfinite(high)) and np.all(high > low)):
            raise DemoError("the action space needs finite bounds with high > low to be scaled to [-1, 1]")
        keys = tuple(space.spaces)
        sizes = tuple(int(np.prod(space.spaces[key].shape)) for key in keys)
        return cls(keys, sizes, low, high)

    @property
    def observation_size(self) -> int:
        return sum(self.sizes)

    @property
    def action_size(self) -> int:
        return len(self.action_low)

    def flatten(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """One observation as a float32 vector."""
        self._check_keys(obs)
        return np.concatenate([np.asarray(obs[key], np.float32).reshape(-1) for key in self.keys])

    def flatten_steps(self, observations: dict[str, np.ndarray]) -> np.ndarray:
        """A sequence of observations (each entry with the steps as its first axis) as rows."""
        self._check_keys(observations)
        steps = len(observations[self.keys[0]])
        parts = [np.asarray(observations[k], np.float32).reshape(steps, n) for k, n in zip(self.keys, self.sizes)]
        return np.concatenate(parts, axis=1)

    def _check_keys(self, obs: dict) -> None:
        missing = [key for key in self.keys if key not in obs]
        if missing:
            raise DemoError(f"observation lacks {', '.join(missing)} (expected keys {', '.join(self.keys)})")

    def scale(self, actions: np.ndarray) -> np.ndarray:
        """Env actions to [-1, 1] (float32)."""
        actions = np.asarray(actions, np.float64)
        return (2.0 * (actions - self.action_low) / (self.action_high - self.action_low) - 1.0).astype(np.float32)

    def unscale(self, scaled: np.ndarray) -> np.ndarray:
        """Actions in [-1, 1] (clipped there first) back to env actions (float32)."""
        scaled = np.clip(np.asarray(scaled, np.float64), -1.0, 1.0)
        return (self.action_low + (scaled + 1.0) * 0.5 * (self.action_high - self.action_low)).astype(np.float32)

    def with_base_targets(self, env, targets: np.ndarray) -> FlatSpaces:
        """These spaces with the base's actions as servo targets, bounded by ``targets`` (rows
        of targets the demos visited) widened by a tenth of their span and 5 cm (or rad)."""
        layout = env.unwrapped.action_layout
        base_actions = tuple(e.index for e in layout.entries if e.group == "base")
        if not base_actions or BASE_TARGETS not in self.keys:
            raise DemoError(f"base targets need a floating base and the {BASE_TARGETS} observation")
        start = sum(self.sizes[: self.keys.index(BASE_TARGETS)])
        if self.sizes[self.keys.index(BASE_TARGETS)] != len(base_actions):
            raise DemoError(f"{BASE_TARGETS} has {self.sizes[self.keys.index(BASE_TARGETS)]} entries, "
                            f"the base takes {len(base_actions)} actions")  # fmt: skip
        low, high = targets.min(axis=0), targets.max(axis=0)
        margin = 0.1 * (high - low) + 0.05
        action_low, action_high = self.action_low.copy(), self.action_high.copy()
        index = list(base_actions)
        action_low[index], action_high[index] = low - margin, high + margin
        return FlatSpaces(self.keys, self.sizes, action_low, action_high, base_actions,
                          tuple(range(start, start + len(base_actions))),
                          self.action_low[index].copy(), self.action_high[index].copy())  # fmt: skip

    def model_actions(self, actions: np.ndarray, next_flat: np.ndarray) -> np.ndarray:
        """Env actions (rows) as the model's actions: base moves become the targets observed
        after each action (``next_flat``: the flat observations after them)."""
        out = np.array(actions, np.float64)
        if self.base_targets:
            out[:, list(self.base_actions)] = next_flat[:, list(self.base_observed)]
        return out

    def env_action(self, scaled: np.ndarray, obs: dict[str, np.ndarray]) -> np.ndarray:
        """A model's action (in [-1, 1]) as the env's action in the state ``obs``: unscaled and,
        with base targets, the base's targets turned into the moves that reach them."""
        action = self.unscale(scaled).astype(np.float64)
        if self.base_targets:
            index = list(self.base_actions)
            current = np.asarray(obs[BASE_TARGETS], np.float64).reshape(-1)
            action[index] = np.clip(action[index] - current, self.move_low, self.move_high)
        return action.astype(np.float32)

    def to_dict(self) -> dict:
        data = {
            "keys": list(self.keys),
            "sizes": list(self.sizes),
            "action_low": self.action_low.tolist(),
            "action_high": self.action_high.tolist(),
        }
        if self.base_targets:
            data.update(base_actions=list(self.base_actions), base_observed=list(self.base_observed),
                        move_low=self.move_low.tolist(), move_high=self.move_high.tolist())  # fmt: skip
        return data

    @classmethod
    def from_dict(cls, data: dict) -> FlatSpaces:
        targets = "base_actions" in data
        return cls(
            tuple(data["keys"]),
            tuple(int(s) for s in data["sizes"]),
            np.asarray(data["action_low"], np.float64),
            np.asarray(data["action_high"], np.float64),
            tuple(int(i) for i in data.get("base_actions", ())),
            tuple(int(i) for i in data.get("base_observed", ())),
            np.asarray(data["move_low"], np.float64) if targets else None,
            np.asarray(data["move_high"], np.float64) if targets else None,
        )

    def save(self, path: Path | str) -> None:
        Path(path).write_text(json.dumps(self.to_dict(), indent=1) + "\n")

    @classmethod
    def load(cls, path: Path | str) -> FlatSpaces:
        return cls.from_dict(json.loads(Path(path).read_text()))


@dataclass
class Transitions:
    """Replayed demos as flat arrays, one row per action, episodes one after another.

    Row ``t`` of an episode holds the observation before action ``t``, the action (the
    model's: scaled to [-1, 1], the base as targets unless laid out with ``base="moves"``), the reward it earned and whether it ended the episode: ``terminals`` where the
    env terminated (success or failure), ``timeouts`` where the episode stopped without
    terminating (time limit, or the end of the recording). ``next_observations`` hold the
    observation after each action, including the final one.
    """

    observations: np.ndarray
    next_observations: np.ndarray
    actions: np.ndarray
    rewards: np.ndarray
    terminals: np.ndarray
    timeouts: np.ndarray
    episode_ends: np.ndarray
    uuids: list[str]
    spaces: FlatSpaces

    def __len__(self) -> int:
        return len(self.actions)

    def episodes(self) -> Iterator[slice]:
        """The rows of each episode."""
        start = 0
        for end in self.episode_ends:
            yield slice(start, int(end))
            start = int(end)

    def to_d3rlpy(self):
        """A ``d3rlpy.dataset.MDPDataset`` of these transitions (needs ``pip install "bigym[rl]"``)."""
        try:
            from d3rlpy.dataset import MDPDataset
        except ImportError as error:
            raise ImportError(f'to_d3rlpy needs d3rlpy: pip install "bigym[rl]" ({error})') from error
        return MDPDataset(
            observations=self.observations,
            actions=self.actions,
            rewards=self.rewards,
            terminals=self.terminals,
            timeouts=self.timeouts,
        )


def transitions(demos: Sequence[ReplayedDemo], env, base: str = "targets") -> Transitions:
    """``demos`` (replayed into ``env``'s observations) as flat arrays in ``env``'s :class:`FlatSpaces`.

    ``base``: ``"targets"`` (default, where the env has a floating base) lays the base's
    actions out as its servo targets after each step, ``"moves"`` as the env's per-step moves
    (see the module's docstring for why targets)."""
    if not demos:
        raise DemoError("no demos to lay out as transitions")
    if base not in ("targets", "moves"):
        raise ValueError(f'base must be "targets" or "moves", not {base!r}')
    spaces = FlatSpaces.from_env(env)
    floating = any(e.group == "base" for e in env.unwrapped.action_layout.entries)
    if base == "targets" and floating:
        if any(BASE_TARGETS not in demo.observations for demo in demos):
            raise DemoError(f'base="targets" needs the {BASE_TARGETS} observation in the demos')
        visited = np.concatenate([np.asarray(demo.observations[BASE_TARGETS], np.float64) for demo in demos])
        spaces = spaces.with_base_targets(env, visited)
    columns: dict[str, list[np.ndarray]] = {k: [] for k in ("obs", "next", "act", "rew", "term", "time")}
    ends, total = [], 0
    for demo in demos:
        extra = sorted(set(demo.observations) - set(spaces.keys))
        if extra:
            raise DemoError(f"demo {demo.uuid} holds observations the env lacks: {', '.join(extra)}")
        steps = len(demo.actions)
        if demo.actions.shape[1] != spaces.action_size:
            raise DemoError(
                f"demo {demo.uuid} has {demo.actions.shape[1]} actions per step, the env takes {spaces.action_size}"
            )
        flat = spaces.flatten_steps(demo.observations)
        terminals = np.asarray(demo.terminated, np.float32)
        timeouts = np.zeros(steps, np.float32)
        if steps and not terminals[-1]:
            timeouts[-1] = 1.0  # truncated, or the recording ends: either way the episode stops here
        columns["obs"].append(flat[:steps])
        columns["next"].append(flat[1 : steps + 1])
        columns["act"].append(spaces.scale(spaces.model_actions(demo.actions, flat[1 : steps + 1])))
        columns["rew"].append(np.asarray(demo.rewards, np.float32))
        columns["term"].append(terminals)
        columns["time"].append(timeouts)
        total += steps
        ends.append(total)
    return Transitions(
        observations=np.concatenate(columns["obs"]),
        next_observations=np.concatenate(columns["next"]),
        actions=np.concatenate(columns["act"]),
        rewards=np.concatenate(columns["rew"]),
        terminals=np.concatenate(columns["term"]),
        timeouts=np.concatenate(columns["time"]),
        episode_ends=np.asarray(ends, np.int64),
        uuids=[demo.uuid for demo in demos],
        spaces=spaces,
    )
