"""Policies for the evaluation tests, importable by name from worker processes."""

from __future__ import annotations

import mujoco
import numpy as np

from bigym.policies import ReachPolicy


class ObservedReach:
    """The scripted reacher driven by observations only: it poses a private copy of the
    robot from the proprioception and the target from the privileged state, so that it
    works wherever the simulation runs (an async vector env's sub-process too)."""

    def __init__(self, env) -> None:
        base = env.unwrapped
        self._env = type(base)(action_mode=base.action_mode, control_frequency=base.control_frequency)
        self._env.reset(seed=0)
        self._reach = ReachPolicy(self._env)
        model = self._env.model
        names = base.observation_layout.names
        joints = [n.removesuffix("_qpos") for n in names if n.endswith("_qpos")]
        self._qpos_index = np.array([model.joint(j).qposadr[0] for j in joints])
        self._n = len(joints)
        self._targets = [k for k in sorted(env.observation_space.keys()) if k.startswith("target_position")]

    def reset(self, seed: int) -> None:
        pass

    def __call__(self, obs):
        data = self._env.data
        data.qpos[self._qpos_index] = obs["proprioception"][: self._n]
        for i, key in enumerate(self._targets):
            data.mocap_pos[self._env._mocap_ids[i]] = obs[key]
        data.ctrl[: len(self._env.action_layout)] = 0.0
        mujoco.mj_kinematics(self._env.model, data)
        return self._reach(obs)


def observed_reach(env) -> ObservedReach:
    return ObservedReach(env)


def broken(env):
    """A factory whose policy raises on its first action."""

    def act(obs):
        raise RuntimeError("this policy is broken")

    return act


def not_callable(env):
    return 42
