"""Recording demos while any policy, expert or input device drives the env."""

from __future__ import annotations

import secrets
from collections.abc import Callable
from pathlib import Path

import gymnasium as gym
import mujoco
import numpy as np

from bigym.demonstrations.demo import Demo
from bigym.demonstrations.metadata import CHECKPOINT_SPEC, INITIAL_STATE_SPEC, SOURCES, Metadata
from bigym.env import BiGymEnv

# One state checkpoint every 50 actions (0.1 s at 500 Hz): about 11% on top of the actions'
# bytes whatever the rate, and at 500 Hz aligned with every rate dividing it by 1, 2, 5, 10,
# 25 or 50 physics steps (500, 250, 100, 50, 20, 10 Hz), so down-sampled replays are checked too.
CHECKPOINT_INTERVAL = 50


def default_checkpoint_interval(control_frequency: float) -> int:
    """Actions between two state checkpoints (the same at every rate, see CHECKPOINT_INTERVAL)."""
    return CHECKPOINT_INTERVAL


class DemoRecorder(gym.Wrapper):
    """Wraps a BiGym env and records every episode; nothing is written until you ask.

    Use it like the env: ``reset(seed=...)`` starts a new recording (a seed is drawn when
    none is given, so every recording can be replayed), each ``step`` appends the applied
    action (as float64, exactly as the env used it) and every ``checkpoint_interval``
    steps a state checkpoint. Then :meth:`to_demo`, :meth:`save` or :meth:`discard`.
    """

    def __init__(
        self,
        env: gym.Env,
        source: str = "unknown",
        checkpoint_interval: int | None = None,
        task_kwargs: dict | None = None,
    ) -> None:
        super().__init__(env)
        base = env.unwrapped
        if not isinstance(base, BiGymEnv):
            raise TypeError(f"DemoRecorder records BiGym envs, got {type(base).__name__}")
        inner = env
        while isinstance(inner, gym.Wrapper):
            if isinstance(inner, gym.ActionWrapper):
                raise TypeError(
                    f"{type(inner).__name__} changes actions before they reach the env, so the recorded "
                    "actions would not replay: wrap the env in DemoRecorder first, then add action wrappers"
                )
            inner = inner.env
        if source not in SOURCES:
            raise ValueError(f"source must be one of {SOURCES}, got {source!r}")
        self._base = base
        self.source = source
        self.task_kwargs = dict(task_kwargs or getattr(base, "task_kwargs", {}) or {})
        self.checkpoint_interval = int(checkpoint_interval or default_checkpoint_interval(base.control_frequency))
        if self.checkpoint_interval < 1:
            raise ValueError("checkpoint_interval must be at least 1")
        model = base.model
        self._initial_buffer = np.zeros(mujoco.mj_stateSize(model, INITIAL_STATE_SPEC))
        self._checkpoint_size = mujoco.mj_stateSize(model, CHECKPOINT_SPEC)
        self._recording = False
        self._clear()

    # ------------------------------------------------------------------ state
    def _clear(self) -> None:
        self._actions: list[np.ndarray] = []
        self._checkpoint_steps: list[int] = []
        self._checkpoint_states: list[np.ndarray] = []
        self._seed: int | None = None
        self._initial_state: np.ndarray | None = None
        self._success = False
        self._first_success: int | None = None
        self._unstable: str | None = None

    def _checkpoint(self) -> None:
        state = np.empty(self._checkpoint_size)
        mujoco.mj_getState(self._base.model, self._base.data, state, CHECKPOINT_SPEC)
        self._checkpoint_steps.append(len(self._actions))
        self._checkpoint_states.append(state)

    @property
    def recording(self) -> bool:
        """True between ``reset`` and the next ``to_demo``/``save``/``discard``."""
        return self._recording

    @property
    def num_steps(self) -> int:
        return len(self._actions)

    @property
    def success(self) -> bool:
        """Whether the env reported success on the latest step."""
        return self._success

    @property
    def first_success_step(self) -> int | None:
        return self._first_success

    # ------------------------------------------------------------------ gym API
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        if seed is None:
            seed = secrets.randbits(31)  # a replay must be able to reset to the same state
        self._clear()
        obs, info = self.env.reset(seed=seed, options=options)
        self._seed = int(seed)
        mujoco.mj_getState(self._base.model, self._base.data, self._initial_buffer, INITIAL_STATE_SPEC)
        self._initial_state = self._initial_buffer.copy()
        self._recording = True
        return obs, info

    def step(self, action):
        if not self._recording:
            raise RuntimeError("call reset() before step(): a recording starts at reset")
        recorded = np.array(action, dtype=np.float64)  # what the env's validation applies
        obs, reward, terminated, truncated, info = self.env.step(action)  # raises on invalid actions
        if "unstable" in info and self._unstable is None:
            self._unstable = str(info["unstable"])
        self._actions.append(recorded.reshape(-1))
        self._success = bool(info.get("is_success", False))
        if self._success and self._first_success is None:
            self._first_success = len(self._actions)
        if len(self._actions) % self.checkpoint_interval == 0:
            self._checkpoint()
        return obs, reward, terminated, truncated, info

    # ------------------------------------------------------------------ output
    def to_demo(
        self,
        success: bool | None = None,
        source: str | None = None,
        keep: bool = False,
        uuid: str | None = None,
        date: str | None = None,
        **extra,
    ) -> Demo:
        """The current recording as a :class:`Demo` (then cleared unless ``keep``).

        ``success`` defaults to whether the env reported success at any step (the env
        terminates the episode there; steps recorded after it are a margin). ``uuid`` and
        ``date`` default to a random uuid and now; a generator whose files must come out
        byte-identical on every run passes fixed ones.
        """
        if self._initial_state is None:
            raise RuntimeError("nothing recorded: call reset() and step() first")
        if not self._actions:
            raise RuntimeError("the recording has no steps")
        steps, states = list(self._checkpoint_steps), list(self._checkpoint_states)
        if not steps or steps[-1] != len(self._actions):
            state = np.empty(self._checkpoint_size)
            mujoco.mj_getState(self._base.model, self._base.data, state, CHECKPOINT_SPEC)
            steps.append(len(self._actions))
            states.append(state)
        if self._unstable is not None:
            extra["unstable"] = self._unstable
        if self._first_success is not None:
            extra.setdefault("first_success_step", self._first_success)
        metadata = Metadata.from_env(
            self._base,
            observation_config=None,
            task_kwargs=self.task_kwargs,
            seed=self._seed,
            source=source or self.source,
            success=(self._first_success is not None and self._unstable is None) if success is None else bool(success),
            num_steps=len(self._actions),
            checkpoint_interval=self.checkpoint_interval,
            extra=extra,
            uuid=uuid,
        )
        if date is not None:
            metadata.date = date
        demo = Demo(metadata, np.stack(self._actions), self._initial_state, np.array(steps), np.stack(states))
        if not keep:
            self.discard()
        return demo

    def save(self, path: Path | str, **kwargs) -> Path:
        """Write the current recording (to a file, or ``<uuid>.safetensors`` in a folder)."""
        return self.to_demo(**kwargs).save(path)

    def discard(self) -> None:
        """Drop the current recording."""
        self._clear()
        self._recording = False


def record_episode(
    env: gym.Env,
    policy: Callable[[dict], np.ndarray],
    seed: int | None = None,
    source: str = "policy",
    max_steps: int | None = None,
    steps_after_success: int = 0,
    checkpoint_interval: int | None = None,
    observations: list | None = None,
) -> Demo:
    """Roll ``policy`` out for one episode in ``env`` and return the recorded :class:`Demo`.

    The episode ends at termination, truncation or ``max_steps``; after the first success it
    continues ``steps_after_success`` more steps (a margin that keeps success robust when the
    demo is later replayed at a lower rate). When ``observations`` is a list, every
    observation (the reset one first) is appended to it.
    """
    recorder = env if isinstance(env, DemoRecorder) else DemoRecorder(env, source, checkpoint_interval)
    obs, _ = recorder.reset(seed=seed)
    if observations is not None:
        observations.append(obs)
    limit = max_steps if max_steps is not None else recorder.unwrapped.max_episode_steps
    after = None
    for _ in range(limit):
        obs, _, terminated, truncated, info = recorder.step(policy(obs))
        if observations is not None:
            observations.append(obs)
        if "unstable" in info:
            break
        if info.get("is_success") and after is None:
            after = steps_after_success
        if after is not None:
            if after <= 0 or truncated:
                break
            after -= 1
            continue
        if terminated or truncated:
            break
    return recorder.to_demo(source=source)
