"""Helpers shared by the demonstration tests."""

from __future__ import annotations

import numpy as np

from bigym.action_modes import JointPositionActionMode
from bigym.demonstrations import record_episode
from bigym.policies import ReachPolicy

STEPS_AFTER_SUCCESS = 100  # 0.2 s of margin after the first success at 500 Hz


def record_reach(cls, absolute: bool, seed: int, frequency: float = 500, **kwargs):
    env = cls(action_mode=JointPositionActionMode(absolute=absolute), control_frequency=frequency)
    try:
        return record_episode(
            env, ReachPolicy(env), seed=seed, source="expert", steps_after_success=STEPS_AFTER_SUCCESS, **kwargs
        )
    finally:
        env.close()


def same_observations(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)
