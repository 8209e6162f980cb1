"""Simple policies for `bigym run`: random, hold, and a scripted reacher for the reach tasks.

These are baselines and smoke tests, not the demonstrators (those live in ``bigym.experts``).
"""

from __future__ import annotations

from typing import Protocol

import mujoco
import numpy as np

from bigym.env import BiGymEnv


class Policy(Protocol):
    """See :mod:`bigym.evaluation.policy`: ``policy.reset(seed)``, ``policy(obs) -> action``."""

    def reset(self, seed: int | None) -> None: ...

    def __call__(self, obs: dict[str, np.ndarray]) -> np.ndarray: ...


class RandomPolicy:
    """Uniform samples from the action space, from a seeded generator."""

    def __init__(self, env: BiGymEnv, seed: int | None = None) -> None:
        self._low = env.action_space.low.astype(np.float64)
        self._high = env.action_space.high.astype(np.float64)
        self._rng = np.random.default_rng(seed)

    def reset(self, seed: int | None) -> None:
        """Restart the draws for an episode: the same seed gives the same actions."""
        self._rng = np.random.default_rng(seed)

    def __call__(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        return self._rng.uniform(self._low, self._high).astype(np.float32)


class HoldPolicy:
    """Keeps every servo at its current target: zero deltas, or the current targets when absolute."""

    reads_simulator = True  # the current targets come from env.data

    def __init__(self, env: BiGymEnv) -> None:
        self._env = env
        self._keep_target = bool(env.action_mode.absolute)
        self._base = env.action_layout.groups.get("base")

    def reset(self, seed: int | None) -> None:
        """Nothing to restart: the policy has no state."""

    def __call__(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        n = len(self._env.action_layout)
        if not self._keep_target:
            return np.zeros(n, np.float32)
        action = self._env.data.ctrl[:n].astype(np.float32)
        if self._base is not None:
            action[self._base] = 0.0  # base actions are always deltas
        return action


class ReachPolicy:
    """Damped least-squares reaching on privileged target positions (reach tasks only).

    Each step moves the wrist(s) a bounded distance toward their target using the
    wrist-site Jacobian over the base DOFs and the arm joints; the base is weighted to
    move less than the arms, as a person steps only when the arm alone falls short.
    """

    reads_simulator = True  # targets and Jacobians come from env.data

    def __init__(self, env: BiGymEnv, gain: float = 25.0, max_joint_speed: float = 2.5, damping: float = 0.05) -> None:
        if not hasattr(env, "target_positions"):
            raise ValueError(f"{env.task_name} has no targets: the reach policy only drives the reach tasks")
        if not env.robot.floating_base:
            raise ValueError("the reach policy drives the floating base; use floating_base=True")
        self._env = env
        model = env.model
        layout = env.action_layout
        # Gain (1/s) and speed limit (rad/s) become per-step amounts at the env's control rate.
        dt = 1.0 / env.control_frequency
        self._gain, self._max_step, self._damping = min(1.0, gain * dt), max_joint_speed * dt, damping
        self._absolute = bool(env.action_mode.absolute)
        self._torque = env.action_mode.torque
        if self._torque:
            raise ValueError("the reach policy emits joint positions; use JointPositionActionMode")
        # Action index -> model DOF index for every base and arm entry.
        actuators = env.robot.description.actuators
        self._action_index = np.array([i for i, a in enumerate(actuators) if a.kind in ("base", "arm")])
        self._dofs = np.array([model.joint(actuators[i].joint).dofadr[0] for i in self._action_index])
        self._qpos = np.array([model.joint(actuators[i].joint).qposadr[0] for i in self._action_index])
        self._is_base = np.array([actuators[i].kind == "base" for i in self._action_index])
        self._weights = np.where(self._is_base, 0.3, 1.0)
        self._step_limit = np.minimum(
            np.where(self._is_base, layout_bound(layout, self._action_index), self._max_step),
            layout_bound(layout, self._action_index),
        )
        self._jacobian = np.zeros((3, model.nv))
        self._sides = {"left": 0, "right": 1}
        self._n = len(layout)

    def reset(self, seed: int | None) -> None:
        """Nothing to restart: the policy has no state."""

    def _goals(self) -> list[tuple[int, np.ndarray]]:
        env = self._env
        wrists = env.robot.wrist_positions(env.data)
        goals = []
        for target, hand in zip(env.target_positions, env.target_hands):
            if hand == "any":
                side = int(np.argmin(np.linalg.norm(wrists - target, axis=1)))
            else:
                side = self._sides[hand]
            goals.append((side, target.copy()))
        return goals

    def __call__(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        env = self._env
        model, data = env.model, env.data
        rows, errors = [], []
        for side, target in self._goals():
            site = env.robot.wrist_site_ids[side]
            mujoco.mj_jacSite(model, data, self._jacobian, None, site)
            rows.append(self._jacobian[:, self._dofs] * self._weights)
            errors.append(target - data.site_xpos[site])
        jac = np.vstack(rows)
        error = np.concatenate(errors) * self._gain
        step = jac.T @ np.linalg.solve(jac @ jac.T + self._damping**2 * np.eye(len(error)), error)
        step = np.clip(step * self._weights, -self._step_limit, self._step_limit)
        action = np.zeros(self._n)
        if self._absolute:
            arm = ~self._is_base
            current = data.qpos[self._qpos]
            action[self._action_index[arm]] = current[arm] + step[arm]
            action[self._action_index[self._is_base]] = step[self._is_base]
            low, high = env.action_space.low, env.action_space.high
            action = np.clip(action, low, high)
        else:
            action[self._action_index] = step
        return action.astype(np.float32)


def layout_bound(layout, indices: np.ndarray) -> np.ndarray:
    """The symmetric per-step bound of each action entry (the smaller side for asymmetric ones)."""
    return np.array([min(abs(layout.entries[i].low), abs(layout.entries[i].high)) or np.inf for i in indices])


POLICIES = ("auto", "random", "hold", "reach")


def make_policy(name: str, env: BiGymEnv, seed: int | None = None) -> Policy:
    """Build a policy by name; ``auto`` picks the scripted reacher where it applies, else random."""
    if name == "auto":
        name = "reach" if hasattr(env, "target_positions") and env.robot.floating_base else "random"
    if name == "random":
        return RandomPolicy(env, seed)
    if name == "hold":
        return HoldPolicy(env)
    if name == "reach":
        return ReachPolicy(env)
    raise ValueError(f"unknown policy {name!r}; choose from {', '.join(POLICIES)}")
