"""Robot behaviour under the action modes: standing, grippers, floating-base servos."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.robot.h1 import FLOATING_Z_RANGE

from testkit import zero_action


@pytest.fixture(scope="module")
def floating_env():
    env = gym.make("bigym/ReachTargetSingle-v0").unwrapped
    yield env
    env.close()


@pytest.fixture(scope="module")
def whole_body_env():
    env = gym.make("bigym/ReachTargetSingle-v0", action_mode=JointPositionActionMode(floating_base=False)).unwrapped
    yield env
    env.close()


def _upright(env) -> float:
    """z component of the pelvis' up axis in the world (1 = upright)."""
    return float(env.data.xmat[env.robot.pelvis_id][8])


# ------------------------------------------------------------------ whole body
def test_whole_body_stands_for_ten_seconds(whole_body_env):
    env = whole_body_env
    obs, _ = env.reset(seed=0)
    z0 = env.data.qpos[2]
    assert obs["proprioception_floating_base"][2] == pytest.approx(z0, abs=1e-6)
    assert z0 > 0.95, "the robot should spawn standing"
    action = zero_action(env)
    steps = int(round(10.0 * env.control_frequency))
    heights = []
    for step in range(steps):
        obs, reward, terminated, truncated, info = env.step(action)
        assert "unstable" not in info, info
        assert not terminated, f"terminated at step {step}"
        assert not truncated or info.get("time_limit"), info
        heights.append(env.data.qpos[2])
        assert abs(env.data.qpos[2] - z0) < 0.05, f"pelvis height {env.data.qpos[2]:.3f} at t={env.data.time:.2f}s"
        assert abs(obs["proprioception_floating_base"][2] - z0) < 0.05
    assert env.data.time == pytest.approx(10.0)
    assert _upright(env) > 0.98, "the pelvis tilted: the robot is falling"
    assert np.hypot(*env.data.qpos[:2]) < 0.1, "the robot drifted away"


def test_whole_body_zero_torque_falls():
    """The counterpart of the standing test: without leg servos the same robot falls."""
    from bigym.action_modes import TorqueActionMode
    from bigym.envs.reach_target import ReachTargetSingle

    env = ReachTargetSingle(action_mode=TorqueActionMode(floating_base=False))
    try:
        env.reset(seed=0)
        z0 = env.data.qpos[2]
        for _ in range(100):
            *_, info = env.step(zero_action(env))
            if "unstable" in info:
                break
        assert env.data.qpos[2] < z0 - 0.05
    finally:
        env.close()


def test_whole_body_base_pose_observation_matches_state(whole_body_env):
    """``proprioception_floating_base`` must be the pelvis pose of the returned state.

    The joint part of the observation comes from qpos after the step; the base pose must
    describe the same instant, not the start of the last physics step.
    """
    env = whole_body_env
    env.reset(seed=0)
    rng = np.random.default_rng(1)
    for _ in range(10):
        action = rng.uniform(env.action_space.low, env.action_space.high).astype(np.float32)
        obs, *_ = env.step(action)
    w, x, y, z = env.data.qpos[3:7]
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    expected = np.array([*env.data.qpos[:3], yaw], np.float32)
    assert np.linalg.norm(env.data.qvel[:3]) > 0.05, "premise: the pelvis is moving"
    np.testing.assert_allclose(obs["proprioception_floating_base"], expected, atol=1e-5)


# ------------------------------------------------------------------ grippers
def test_grippers_close_and_open(floating_env):
    env = floating_env
    obs, _ = env.reset(seed=0)
    grippers = env.action_layout.group("grippers")
    np.testing.assert_allclose(obs["proprioception_grippers"], [0.0, 0.0], atol=0.05)
    steps = int(round(1.0 * env.control_frequency))
    # Close only the left gripper: the layout order is (left, right).
    action = zero_action(env)
    action[env.action_layout["left_gripper"]] = 1.0
    for _ in range(steps):
        obs, *_ = env.step(action)
    left, right = obs["proprioception_grippers"]
    assert left > 0.9 and right < 0.05, obs["proprioception_grippers"]
    # Close both.
    action[grippers] = 1.0
    for _ in range(steps):
        obs, *_ = env.step(action)
    assert np.all(obs["proprioception_grippers"] > 0.9), obs["proprioception_grippers"]
    assert np.all(obs["proprioception_grippers"] <= 1.0)
    # Open both.
    action[grippers] = 0.0
    for _ in range(steps):
        obs, *_ = env.step(action)
    assert np.all(obs["proprioception_grippers"] < 0.1), obs["proprioception_grippers"]
    assert np.all(obs["proprioception_grippers"] >= 0.0)


def test_gripper_observation_follows_the_joints(floating_env):
    env = floating_env
    env.reset(seed=0)
    action = zero_action(env)
    action[env.action_layout.group("grippers")] = 1.0
    for _ in range(5):  # half closed: mid-range values
        obs, *_ = env.step(action)
    np.testing.assert_allclose(obs["proprioception_grippers"], env.robot.gripper_state(env.data), atol=1e-5)
    assert 0.0 < obs["proprioception_grippers"][0] < 1.0


# ------------------------------------------------------------------ floating base
def test_floating_base_tracks_x(floating_env):
    env = floating_env
    obs, _ = env.reset(seed=0)
    start = obs["proprioception_floating_base"].copy()
    action = zero_action(env)
    action[env.action_layout["base_dx"]] = 0.05
    for _ in range(20):
        obs, *_ = env.step(action)
    assert obs["proprioception_floating_base_actions"][0] == pytest.approx(start[0] + 1.0, abs=1e-5)
    action[:] = 0.0
    for _ in range(25):  # settle for 0.5 s
        obs, *_ = env.step(action)
    pose = obs["proprioception_floating_base"]
    assert pose[0] - start[0] == pytest.approx(1.0, abs=0.05)
    assert pose[1] == pytest.approx(start[1], abs=0.02)
    assert pose[2] == pytest.approx(start[2], abs=0.02)
    assert pose[3] == pytest.approx(start[3], abs=0.02)
    assert env.data.xpos[env.robot.pelvis_id][0] == pytest.approx(start[0] + 1.0, abs=0.05)


def test_floating_base_yaw(floating_env):
    env = floating_env
    obs, _ = env.reset(seed=0)
    action = zero_action(env)
    action[env.action_layout["base_dyaw"]] = 0.25
    for _ in range(4):
        obs, *_ = env.step(action)
    action[:] = 0.0
    for _ in range(25):
        obs, *_ = env.step(action)
    assert obs["proprioception_floating_base"][3] == pytest.approx(1.0, abs=0.03)


def test_floating_base_z_is_clipped_without_windup(floating_env):
    env = floating_env
    obs, _ = env.reset(seed=0)
    z_low, z_high = FLOATING_Z_RANGE
    z_index = env.action_layout["base_dz"]
    assert obs["proprioception_floating_base_actions"][2] == pytest.approx(z_high, abs=1e-5)
    action = zero_action(env)
    action[z_index] = env.action_space.high[z_index]  # +0.1 m per step
    for _ in range(10):
        obs, *_ = env.step(action)
        assert obs["proprioception_floating_base_actions"][2] == pytest.approx(z_high, abs=1e-5)
        assert obs["proprioception_floating_base"][2] <= z_high + 0.005
    # One step down moves the target down at once: no wind-up above the range.
    action[z_index] = -0.1
    obs, *_ = env.step(action)
    assert obs["proprioception_floating_base_actions"][2] == pytest.approx(z_high - 0.1, abs=1e-5)
    assert obs["proprioception_floating_base"][2] < z_high - 0.01
    # And the same at the bottom of the range.
    for _ in range(10):
        obs, *_ = env.step(action)
    assert obs["proprioception_floating_base_actions"][2] == pytest.approx(z_low, abs=1e-5)
    action[z_index] = 0.1
    obs, *_ = env.step(action)
    assert obs["proprioception_floating_base_actions"][2] == pytest.approx(z_low + 0.1, abs=1e-5)
    action[z_index] = 0.0
    for _ in range(25):
        obs, *_ = env.step(action)
    assert obs["proprioception_floating_base"][2] == pytest.approx(z_low + 0.1, abs=0.01)


def test_arm_delta_targets_do_not_wind_up(floating_env):
    env = floating_env
    env.reset(seed=0)
    index = env.action_layout["left_elbow_delta"]
    low, high = env.model.jnt_range[env.model.joint("left_elbow").id]
    action = zero_action(env)
    action[index] = env.action_space.high[index]
    for _ in range(10):
        env.step(action)
    assert env.data.ctrl[index] == pytest.approx(high)
    action[index] = -0.5
    env.step(action)
    assert env.data.ctrl[index] == pytest.approx(high - 0.5)
