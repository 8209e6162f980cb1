"""Episode control: unstable physics, time limits, the paper's API, close()."""

from __future__ import annotations

import math
from typing import ClassVar

import gymnasium as gym
import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.reach_target import ReachTargetSingle

from testkit import hold_action, zero_action


@pytest.fixture(scope="module")
def env():
    env = gym.make("bigym/ReachTargetSingle-v0").unwrapped
    yield env
    env.close()


# ------------------------------------------------------------------ instability
def _blow_up_qvel(env):
    env.data.qvel[:] = 1e12


def _blow_up_warmstart(env):
    env.data.qacc_warmstart[0] = np.nan


def _blow_up_force(env):
    env.data.xfrc_applied[env.robot.pelvis_id] = [1e20, 0.0, 0.0, 0.0, 0.0, 0.0]


@pytest.mark.parametrize("blow_up", [_blow_up_qvel, _blow_up_warmstart, _blow_up_force], ids=["qvel", "warmstart", "xfrc"])
def test_instability_truncates_and_recovers(env, blow_up):
    obs, _ = env.reset(seed=0)
    for _ in range(2):
        good_obs, *_ = env.step(zero_action(env))
    blow_up(env)
    obs, reward, terminated, truncated, info = env.step(zero_action(env))
    assert truncated is True
    assert terminated is False
    assert reward == 0.0
    assert info["is_success"] is False
    assert isinstance(info.get("unstable"), str) and info["unstable"].strip()
    assert "unstable" in info["unstable"]
    # The observation is the last good one: finite and inside the observation space.
    assert env.observation_space.contains(obs)
    for key in obs:
        assert np.all(np.isfinite(obs[key])), key
        np.testing.assert_array_equal(obs[key], good_obs[key])
    # Stepping again before reset stays truncated and raises nothing.
    obs2, reward2, terminated2, truncated2, info2 = env.step(zero_action(env))
    assert truncated2 is True and terminated2 is False and reward2 == 0.0
    assert info2["unstable"] == info["unstable"]
    # reset() restores a normal episode.
    obs, info = env.reset(seed=1)
    assert env.observation_space.contains(obs)
    assert not env.data.warning.number.any()
    for _ in range(3):
        obs, reward, terminated, truncated, info = env.step(zero_action(env))
        assert truncated is False and not terminated
        assert "unstable" not in info
        assert env.observation_space.contains(obs)


def test_whole_body_instability():
    env = ReachTargetSingle(action_mode=JointPositionActionMode(floating_base=False))
    try:
        env.reset(seed=0)
        env.data.qvel[:] = np.inf
        obs, reward, terminated, truncated, info = env.step(zero_action(env))
        assert truncated and not terminated and info["unstable"]
        env.reset(seed=0)
        obs, reward, terminated, truncated, info = env.step(zero_action(env))
        assert not truncated and "unstable" not in info
    finally:
        env.close()


# ------------------------------------------------------------------ time limit
class _ShortReach(ReachTargetSingle):
    time_limit: ClassVar[float] = 0.5


@pytest.mark.parametrize("frequency", [50, 30])
def test_short_time_limit(frequency):
    env = _ShortReach(control_frequency=frequency)
    try:
        expected = math.ceil(0.5 * env.control_frequency)
        assert env.max_episode_steps == expected
        for episode in range(2):  # the counter restarts on reset
            env.reset(seed=episode)
            for step in range(1, expected + 1):
                obs, reward, terminated, truncated, info = env.step(zero_action(env))
                if step < expected:
                    assert truncated is False, f"truncated early at step {step}"
                    assert "time_limit" not in info
                else:
                    assert truncated is True
                    assert info["time_limit"] is True
                    assert not terminated
            assert env.data.time >= 0.5 - 1e-9
    finally:
        env.close()


def test_registered_env_time_limit(env):
    """The reach tasks run 10 s: 500 steps at 50 Hz, the last one truncated."""
    assert env.max_episode_steps == 500
    env.reset(seed=0)
    action = zero_action(env)
    for step in range(1, 501):
        obs, reward, terminated, truncated, info = env.step(action)
        assert truncated == (step == 500), step
        assert not terminated
    assert info["time_limit"] is True
    assert env.data.time == pytest.approx(10.0)


# ------------------------------------------------------------------ paper API
def test_paper_api():
    from bigym.action_modes import JointPositionActionMode as PaperMode
    from bigym.envs.reach_target import ReachTarget, ReachTargetMultiModal

    assert issubclass(ReachTarget, ReachTargetMultiModal)
    env = ReachTarget(action_mode=PaperMode(floating_base=True, absolute=True))
    try:
        obs, info = env.reset(seed=0)
        assert env.observation_space.contains(obs)
        assert info["is_success"] is False
        # Holding the current pose: nothing moves.
        start = obs["proprioception"].copy()
        for _ in range(5):
            obs, reward, terminated, truncated, info = env.step(hold_action(env))
        assert env.observation_space.contains(obs)
        np.testing.assert_allclose(obs["proprioception"][: len(start) // 2], start[: len(start) // 2], atol=2e-2)
        # Arbitrary in-bounds absolute actions step fine.
        env.action_space.seed(0)
        for _ in range(5):
            obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
            assert env.observation_space.contains(obs)
            assert "unstable" not in info
        # Absolute arm actions are joint targets: the elbow goes where it is told.
        layout = env.action_layout
        action = hold_action(env)
        action[layout["left_elbow"]] = 1.0
        for _ in range(40):
            obs, *_ = env.step(action)
        elbow = obs["proprioception"][env.observation_layout["left_elbow_qpos"]]
        assert elbow == pytest.approx(1.0, abs=0.05)
    finally:
        env.close()


def test_close_is_idempotent():
    env = gym.make("bigym/ReachTargetSingle-v0", render_mode="rgb_array", render_resolution=(16, 16))
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (16, 16, 3)
    env.close()
    env.close()  # a second close is a no-op, not an error
    assert env.unwrapped.render_mode == "rgb_array"
