"""Action layout, action validation and control frequency."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode, TorqueActionMode
from bigym.envs.reach_target import ReachTargetSingle
from bigym.robot.h1 import TORQUE_LIMITS

from testkit import zero_action

ARM = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist")
LEGS = ("hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle")


@pytest.fixture(scope="module")
def floating_env():
    env = gym.make("bigym/ReachTargetSingle-v0")
    yield env.unwrapped
    env.close()


@pytest.fixture(scope="module")
def whole_body_env():
    env = gym.make("bigym/ReachTargetSingle-v0", action_mode=JointPositionActionMode(floating_base=False))
    yield env.unwrapped
    env.close()


@pytest.fixture(scope="module")
def absolute_env():
    env = gym.make("bigym/ReachTargetSingle-v0", action_mode=JointPositionActionMode(absolute=True))
    yield env.unwrapped
    env.close()


def _check_layout_matches_space(env):
    layout = env.action_layout
    assert len(layout) == env.action_space.shape[0]
    assert [e.index for e in layout.entries] == list(range(len(layout)))
    np.testing.assert_array_equal(np.float32([e.low for e in layout.entries]), env.action_space.low)
    np.testing.assert_array_equal(np.float32([e.high for e in layout.entries]), env.action_space.high)
    for entry in layout.entries:
        assert layout[entry.name] == entry.index
        assert entry.name in layout
        group = layout.group(entry.group)
        assert group.start <= entry.index < group.stop


# ------------------------------------------------------------------ layout
def test_floating_layout(floating_env):
    env = floating_env
    assert env.action_space.shape == (16,)
    layout = env.action_layout
    expected = (
        ["base_dx", "base_dy", "base_dz", "base_dyaw"]
        + [f"left_{j}_delta" for j in ARM]
        + [f"right_{j}_delta" for j in ARM]
        + ["left_gripper", "right_gripper"]
    )
    assert list(layout.names) == expected
    assert layout.groups == {
        "base": slice(0, 4),
        "left_arm": slice(4, 9),
        "right_arm": slice(9, 14),
        "grippers": slice(14, 16),
    }
    assert layout.group("grippers") == slice(14, 16)
    assert layout["left_elbow_delta"] == 7
    _check_layout_matches_space(env)
    np.testing.assert_array_equal(env.action_space.low[14:], [0.0, 0.0])
    np.testing.assert_array_equal(env.action_space.high[14:], [1.0, 1.0])
    with pytest.raises(KeyError, match="no group"):
        layout.group("legs")
    with pytest.raises(KeyError, match="no entry"):
        layout["left_knee"]


@pytest.mark.parametrize("dofs", [["x", "y", "rz"], ["pelvis_x", "pelvis_y", "pelvis_rz"], ["rz", "y", "x"]])
def test_floating_dofs_subset(dofs):
    env = ReachTargetSingle(action_mode=JointPositionActionMode(floating_dofs=dofs))
    try:
        assert env.action_space.shape == (15,)
        assert env.action_layout.names[:3] == ("base_dx", "base_dy", "base_dyaw")
        assert env.action_layout.group("base") == slice(0, 3)
        assert env.action_layout.group("grippers") == slice(13, 15)
        _check_layout_matches_space(env)
        obs, _ = env.reset(seed=0)
        assert obs["proprioception_floating_base_actions"].shape == (3,)
        assert env.observation_space["proprioception_floating_base_actions"].shape == (3,)
        # No z DOF: the pelvis stays at its standing height.
        height = obs["proprioception_floating_base"][2]
        assert height == pytest.approx(1.0442, abs=1e-3)
        assert "pelvis_z" not in [env.model.joint(i).name for i in range(env.model.njnt)]
    finally:
        env.close()


def test_unknown_floating_dof_rejected():
    with pytest.raises(ValueError, match="unknown floating DOFs"):
        ReachTargetSingle(action_mode=JointPositionActionMode(floating_dofs=["x", "pitch"]))


def test_whole_body_layout(whole_body_env):
    env = whole_body_env
    assert env.action_space.shape == (23,)
    layout = env.action_layout
    expected = (
        [f"{s}_{j}_delta" for s in ("left", "right") for j in LEGS]
        + ["torso_delta"]
        + [f"left_{j}_delta" for j in ARM]
        + [f"right_{j}_delta" for j in ARM]
        + ["left_gripper", "right_gripper"]
    )
    assert list(layout.names) == expected
    assert layout.groups == {
        "legs": slice(0, 10),
        "torso": slice(10, 11),
        "left_arm": slice(11, 16),
        "right_arm": slice(16, 21),
        "grippers": slice(21, 23),
    }
    _check_layout_matches_space(env)
    assert "proprioception_floating_base_actions" not in env.observation_space.spaces


def test_absolute_layout_bounds_are_joint_ranges(absolute_env):
    env = absolute_env
    layout = env.action_layout
    assert layout.names[:4] == ("base_dx", "base_dy", "base_dz", "base_dyaw")
    for side in ("left", "right"):
        for part in ARM:
            name = f"{side}_{part}"
            entry = layout.entries[layout[name]]
            low, high = env.model.jnt_range[env.model.joint(name).id]
            assert entry.low == pytest.approx(low, abs=1e-6)
            assert entry.high == pytest.approx(high, abs=1e-6)
            assert entry.unit == "rad"
    _check_layout_matches_space(env)


def test_torque_layout():
    env = ReachTargetSingle(action_mode=TorqueActionMode())
    try:
        layout = env.action_layout
        assert env.action_space.shape == (16,)
        assert layout.group("left_arm") == slice(4, 9)
        for part in ARM:
            entry = layout.entries[layout[f"right_{part}"]]
            assert entry.unit == "Nm"
            assert entry.high == pytest.approx(TORQUE_LIMITS[part])
            assert entry.low == pytest.approx(-TORQUE_LIMITS[part])
        _check_layout_matches_space(env)
    finally:
        env.close()


@pytest.mark.parametrize("fixture", ["floating_env", "whole_body_env"])
def test_observation_layout(fixture, request):
    env = request.getfixturevalue(fixture)
    obs, _ = env.reset(seed=0)
    layout = env.observation_layout
    assert len(layout) == obs["proprioception"].shape[0] == env.observation_space["proprioception"].shape[0]
    n = len(layout) // 2
    assert layout.group("qpos") == slice(0, n)
    assert layout.group("qvel") == slice(n, 2 * n)
    # Step a little so velocities are non-zero, then check names against the model.
    rng = np.random.default_rng(0)
    for _ in range(3):
        action = rng.uniform(env.action_space.low, env.action_space.high).astype(np.float32)
        obs, *_ = env.step(action)
    for name in ("left_elbow", "right_shoulder_roll", "left_wrist"):
        joint = env.model.joint(name)
        assert obs["proprioception"][layout[f"{name}_qpos"]] == pytest.approx(env.data.qpos[joint.qposadr[0]], abs=1e-6)
        assert obs["proprioception"][layout[f"{name}_qvel"]] == pytest.approx(env.data.qvel[joint.dofadr[0]], abs=1e-4)
    if env.robot.floating_base:
        assert "pelvis_x_qpos" in layout
    else:
        assert "left_knee_qpos" in layout and "torso_qpos" in layout


# ------------------------------------------------------------------ validation
def _assert_rejected(env, action, *must_name, must_not_name=()):
    ctrl_before = env.data.ctrl.copy()
    qpos_before = env.data.qpos.copy()
    time_before = env.data.time
    with pytest.raises(ValueError) as error:
        env.step(action)
    message = str(error.value)
    for name in must_name:
        assert name in message, message
    for name in must_not_name:
        assert name not in message, message
    np.testing.assert_array_equal(env.data.ctrl, ctrl_before)
    np.testing.assert_array_equal(env.data.qpos, qpos_before)
    assert env.data.time == time_before
    return message


def test_wrong_shape_rejected(floating_env):
    env = floating_env
    env.reset(seed=0)
    for shape in [(15,), (17,), (1, 16), (16, 1), ()]:
        message = _assert_rejected(env, np.zeros(shape, np.float32), "shape")
        assert "16" in message


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_rejected(floating_env, bad):
    env = floating_env
    env.reset(seed=0)
    action = zero_action(env)
    action[env.action_layout["left_elbow_delta"]] = bad
    message = _assert_rejected(env, action, "left_elbow", must_not_name=("right_elbow", "base_dx"))
    assert "finite" in message


def test_out_of_bounds_rejected(floating_env):
    env = floating_env
    env.reset(seed=0)
    layout = env.action_layout
    cases = {
        "left_elbow_delta": env.action_space.high[layout["left_elbow_delta"]] * 1.01,
        "base_dyaw": env.action_space.low[layout["base_dyaw"]] * 1.01,
        "right_gripper": 1.5,
        "left_gripper": -0.1,
    }
    for name, value in cases.items():
        action = zero_action(env)
        action[layout[name]] = value
        others = [n for n in layout.names if n != name and n not in name]
        _assert_rejected(env, action, name, must_not_name=others)
    # Several bad entries: every one is named.
    action = zero_action(env)
    action[layout["left_elbow_delta"]] = 10.0
    action[layout["right_wrist_delta"]] = np.nan
    _assert_rejected(env, action, "left_elbow", "right_wrist")


def test_absolute_out_of_range_rejected(absolute_env):
    env = absolute_env
    env.reset(seed=0)
    action = np.zeros(env.action_space.shape, np.float64)
    action[env.action_layout["left_elbow"]] = 4.0  # elbow range is about -1.25 .. 2.61
    _assert_rejected(env, action, "left_elbow", must_not_name=("right_elbow",))


def test_actions_at_exact_bounds_accepted(floating_env, absolute_env):
    for env in (floating_env, absolute_env):
        env.reset(seed=0)
        for bound in (env.action_space.high, env.action_space.low):
            assert bound.dtype == np.float32
            env.step(bound.copy())
            env.step(bound.astype(np.float64))
    # Bounds written in float64 (the joint ranges themselves) are accepted too.
    env = absolute_env
    env.reset(seed=0)
    action = np.zeros(env.action_space.shape, np.float64)
    for entry in env.robot.description.actuators:
        if entry.kind == "arm":
            action[env.action_layout[entry.name]] = entry.joint_range[1]
    env.step(action)


def test_valid_action_is_applied(floating_env):
    """The counterpart of the 'ctrl unchanged' checks: a valid action does change ctrl."""
    env = floating_env
    env.reset(seed=0)
    before = env.data.ctrl.copy()
    action = zero_action(env)
    action[env.action_layout["left_elbow_delta"]] = 0.2
    action[env.action_layout["base_dx"]] = 0.05
    env.step(action)
    index = env.action_layout["left_elbow_delta"]
    assert env.data.ctrl[index] == pytest.approx(before[index] + 0.2)
    assert env.data.ctrl[0] == pytest.approx(before[0] + 0.05)


# ------------------------------------------------------------------ control frequency
@pytest.mark.parametrize("frequency", [20, 50, 100.0, 500, np.int64(50), np.float32(100)])
def test_control_frequency_accepted(frequency):
    env = ReachTargetSingle(control_frequency=frequency)
    try:
        assert env.substeps == round(500 / float(frequency))
        assert env.control_frequency == pytest.approx(float(frequency))
        assert env.metadata["render_fps"] == pytest.approx(float(frequency))
        env.reset(seed=0)
        env.step(zero_action(env))
        assert env.data.time == pytest.approx(1.0 / float(frequency))
    finally:
        env.close()


@pytest.mark.parametrize("frequency", [10, 19.9, 500.1, 600, 0, -50, float("nan"), "50", None])
def test_control_frequency_rejected(frequency):
    with pytest.raises(ValueError, match="control_frequency"):
        ReachTargetSingle(control_frequency=frequency)


def test_base_delta_bounds_scale_with_substeps():
    fast = ReachTargetSingle(control_frequency=500)
    slow = ReachTargetSingle(control_frequency=50)
    try:
        assert slow.substeps == 10 * fast.substeps == 10
        for name in fast.action_layout.names:
            index = fast.action_layout[name]
            if name.startswith("base_") or name.endswith("_delta"):
                assert fast.action_space.high[index] > 0
                np.testing.assert_allclose(slow.action_space.high[index], 10 * fast.action_space.high[index], rtol=1e-6)
                np.testing.assert_allclose(slow.action_space.low[index], 10 * fast.action_space.low[index], rtol=1e-6)
            else:  # grippers: 0 .. 1 whatever the rate
                assert slow.action_space.high[index] == fast.action_space.high[index] == 1.0
        assert slow.action_space.high[slow.action_layout["base_dx"]] == pytest.approx(0.1)
        assert fast.action_space.high[fast.action_layout["base_dx"]] == pytest.approx(0.01)
        # A delta that is legal at 50 Hz is too large at 500 Hz.
        fast.reset(seed=0)
        action = zero_action(fast)
        action[0] = 0.05
        with pytest.raises(ValueError, match="base_dx"):
            fast.step(action)
    finally:
        fast.close()
        slow.close()


def test_substep_timing_for_uneven_frequency():
    env = ReachTargetSingle(control_frequency=30)
    try:
        assert env.substeps == 17
        env.reset(seed=0)
        for _ in range(3):
            env.step(zero_action(env))
        assert env.data.time == pytest.approx(3 / env.control_frequency)
        assert env.data.time == pytest.approx(3 * 17 * env.model.opt.timestep)
    finally:
        env.close()


# ------------------------------------------------------------------ targets within a control step
def _raw_copy(env):
    """A bare MjData in the env's current state, to step by hand with chosen controls."""
    import mujoco

    data = mujoco.MjData(env.model)
    spec = mujoco.mjtState.mjSTATE_INTEGRATION
    state = np.empty(mujoco.mj_stateSize(env.model, spec))
    mujoco.mj_getState(env.model, env.data, state, spec)
    mujoco.mj_setState(env.model, data, state, spec)
    mujoco.mj_forward(env.model, data)
    return data


def _step_by_hand(env, data, controls):
    import mujoco

    n = env.robot.num_actuators
    for row in controls:
        data.ctrl[:n] = row
        mujoco.mj_step(env.model, data)


def test_servo_targets_ramp_over_the_control_step():
    """At 50 Hz each physics step's target is start + k/10 * (end - start), the last exactly end."""
    env = ReachTargetSingle(control_frequency=50)
    try:
        env.reset(seed=3)
        rng = np.random.default_rng(0)
        for _ in range(5):
            data = _raw_copy(env)
            start = env.data.ctrl[: env.robot.num_actuators].copy()
            action = (0.5 * rng.uniform(env.action_space.low, env.action_space.high)).astype(np.float32)
            env.step(action)
            end = env.data.ctrl[: env.robot.num_actuators].copy()
            assert not np.array_equal(start, end)
            k = (np.arange(1, 10) / 10)[:, None]
            _step_by_hand(env, data, [*(start + k * (end - start)), end])
            np.testing.assert_array_equal(data.qpos, env.data.qpos)
            np.testing.assert_array_equal(data.qvel, env.data.qvel)
    finally:
        env.close()


def test_torques_are_held_over_the_control_step():
    env = ReachTargetSingle(control_frequency=50, action_mode=TorqueActionMode(floating_base=True))
    try:
        env.reset(seed=1)
        torque = env.unwrapped._controller.torque
        assert torque.any() and not torque.all()  # arm torques; the base and grippers are targets
        rng = np.random.default_rng(1)
        for _ in range(3):
            data = _raw_copy(env)
            start = env.data.ctrl[: env.robot.num_actuators].copy()
            env.step((0.3 * rng.uniform(env.action_space.low, env.action_space.high)).astype(np.float32))
            end = env.data.ctrl[: env.robot.num_actuators].copy()
            k = (np.arange(1, 10) / 10)[:, None]
            ramp = start + k * (end - start)
            ramp[:, torque] = end[torque]
            _step_by_hand(env, data, [*ramp, end])
            np.testing.assert_array_equal(data.qpos, env.data.qpos)
    finally:
        env.close()


def test_a_50_hz_action_equals_its_500_hz_substeps():
    """One 50 Hz action moves the robot as the ten 500 Hz actions it stands for (to rounding).

    With targets held over the control step instead, the hands end about 2 cm apart.
    """
    slow = ReachTargetSingle(control_frequency=50)
    fast = ReachTargetSingle(control_frequency=500)
    try:
        slow.reset(seed=2)
        fast.reset(seed=2)
        np.testing.assert_array_equal(slow.data.qpos, fast.data.qpos)
        gripper = np.array(["gripper" in name for name in slow.action_layout.names])
        rng = np.random.default_rng(2)
        n = slow.robot.num_actuators
        low, high = slow._controller._ctrl_low, slow._controller._ctrl_high
        for _ in range(20):
            action = 0.1 * rng.uniform(slow.action_space.low, slow.action_space.high)
            action[gripper] = 0.0  # absolute: a gripper ramp is not a sum of deltas
            dz = slow.action_layout["base_dz"]
            action[dz] = -abs(action[dz])  # the base starts at its highest
            slow.step(action)
            for _ in range(10):
                fast.step(action / 10)
            targets = slow.data.ctrl[:n][~gripper]
            assert ((targets > low[~gripper]) & (targets < high[~gripper])).all()  # none clamped at its range
        np.testing.assert_allclose(slow.data.qpos, fast.data.qpos, atol=1e-9)
    finally:
        slow.close()
        fast.close()
