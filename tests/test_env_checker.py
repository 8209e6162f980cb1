"""Gymnasium's own env checker on every registered task and every action/observation mode."""

from __future__ import annotations

import re
import warnings

import gymnasium as gym
import pytest
from gymnasium.utils.env_checker import check_env

import bigym
from bigym.action_modes import JointPositionActionMode, TorqueActionMode
from bigym.observations import CameraConfig, ObservationConfig

from testkit import ALL_TASKS

# Warnings check_env may emit that say nothing about correctness: infinite Box bounds of
# proprioception, the SB3 advice on normalised action spaces, and anything about render.
_HARMLESS = re.compile(
    r"infinity\. This is probably too (low|high)"
    r"|symmetric and normalized space"
    r"|render",
    re.IGNORECASE,
)


def _run_check_env(env_id: str, **kwargs) -> None:
    env = gym.make(env_id, **kwargs)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            check_env(env.unwrapped, skip_render_check=True)
        problems = [str(w.message) for w in caught if not _HARMLESS.search(str(w.message))]
        # Any other warning (obs not within the observation space, wrong dtype, precision,
        # non-deterministic reset, ...) is a failure.
        assert not problems, f"check_env warned about {env_id} {kwargs}:\n" + "\n".join(problems)
    finally:
        env.close()


def test_every_task_is_registered():
    assert set(bigym.TASKS) >= {"ReachTargetSingle", "ReachTargetMultiModal", "ReachTargetDual"}
    for name in bigym.TASKS:
        assert f"bigym/{name}-v0" in gym.registry


@pytest.mark.parametrize("task", ALL_TASKS)
@pytest.mark.parametrize(
    "action_mode",
    [JointPositionActionMode(), JointPositionActionMode(floating_base=False)],
    ids=["floating", "whole_body"],
)
def test_check_env_every_task(task, action_mode):
    _run_check_env(f"bigym/{task}-v0", action_mode=action_mode)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"action_mode": JointPositionActionMode(absolute=True)},
        {"action_mode": JointPositionActionMode(floating_base=False, absolute=True)},
        {"action_mode": TorqueActionMode()},
        {"action_mode": JointPositionActionMode(floating_dofs=["x", "y", "rz"])},
        {"observation_config": ObservationConfig(privileged_information=True)},
        {
            "observation_config": ObservationConfig(
                cameras=[CameraConfig("head", rgb=True, depth=True, resolution=(32, 32))]
            )
        },
    ],
    ids=["absolute", "whole_body_absolute", "torque", "floating_xy_yaw", "privileged", "camera"],
)
def test_check_env_modes(kwargs):
    _run_check_env("bigym/ReachTargetSingle-v0", **kwargs)


def test_check_env_really_rejects_obs_outside_space():
    """The warning filter above must not swallow an obs-space violation."""
    env = gym.make("bigym/ReachTargetSingle-v0")
    unwrapped = env.unwrapped
    original = unwrapped._observe

    def broken_observe():
        obs = original()
        obs["proprioception_grippers"] = obs["proprioception_grippers"] + 5.0  # outside [0, 1]
        return obs

    unwrapped._observe = broken_observe
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                check_env(unwrapped, skip_render_check=True)
            except AssertionError:
                return  # check_env itself failed: good
        problems = [str(w.message) for w in caught if not _HARMLESS.search(str(w.message))]
        assert any("observation space" in p for p in problems), problems
    finally:
        env.close()
