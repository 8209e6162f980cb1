"""The env.step fast paths keep their promises: fresh observation arrays, views of MjData that
stay valid across resets, and float32 action validation identical to the float64 one."""

from __future__ import annotations

import itertools

import mujoco
import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.reach_target import ReachTargetMultiModal, ReachTargetSingle
from bigym.observations import ProprioceptionReader
from bigym.robot.robot import GRIPPER_DRIVER_MAX

from testkit import zero_action

MODES = {
    "floating": JointPositionActionMode(),
    "floating_xy_yaw": JointPositionActionMode(floating_dofs=["x", "y", "rz"]),  # z is a constant
    "whole_body": JointPositionActionMode(floating_base=False),
}


@pytest.fixture(scope="module", params=list(MODES), ids=list(MODES))
def env(request):
    env = ReachTargetSingle(action_mode=MODES[request.param], control_frequency=100)
    yield env
    env.close()


def _reference_proprioception(env) -> dict[str, np.ndarray]:
    """The proprioception keys computed the slow, obvious way from MjData."""
    data, robot = env.data, env.robot
    joints = np.concatenate([data.qpos[robot.proprio_qpos], data.qvel[robot.proprio_qvel]])
    grippers = np.clip(data.qpos[robot.driver_qpos].sum(axis=1) * (0.5 / GRIPPER_DRIVER_MAX), 0.0, 1.0)
    if robot.floating_base:
        fixed = {"x": 0.0, "y": 0.0, "z": robot.fixed_height, "rz": 0.0}
        base = [data.qpos[robot.base_qpos[d]] if d in robot.base_qpos else fixed[d] for d in ("x", "y", "z", "rz")]
    else:
        base = robot.base_pose(data)
    expected = {
        "proprioception": joints,
        "proprioception_grippers": grippers,
        "proprioception_floating_base": np.asarray(base, float),
    }
    if robot.floating_base:
        expected["proprioception_floating_base_actions"] = data.ctrl[list(robot.base_ctrl.values())]
    return {key: value.astype(np.float32) for key, value in expected.items()}


def _assert_matches_data(env, obs) -> None:
    expected = _reference_proprioception(env)
    assert set(expected) <= set(obs)
    for key, value in expected.items():
        np.testing.assert_allclose(obs[key], value, rtol=1e-6, atol=1e-6, err_msg=key)


def test_observations_are_fresh_arrays_every_step(env):
    obs, _ = env.reset(seed=0)
    kept = [obs]
    copies = [{k: v.copy() for k, v in obs.items()}]
    rng = np.random.default_rng(0)
    for _ in range(5):
        action = rng.uniform(env.action_space.low, env.action_space.high).astype(np.float32) * 0.5
        obs, *_ = env.step(action)
        kept.append(obs)
        copies.append({k: v.copy() for k, v in obs.items()})
    # Arrays handed out earlier are never overwritten, and no two steps share memory.
    for obs, copy in zip(kept, copies):
        for key in obs:
            np.testing.assert_array_equal(obs[key], copy[key], err_msg=key)
    for earlier, later in itertools.combinations(kept, 2):
        for key in earlier:
            assert not np.shares_memory(earlier[key], later[key]), key
    assert not np.array_equal(copies[0]["proprioception"], copies[-1]["proprioception"]), "the robot never moved"


def test_cached_views_read_live_data_across_resets(env):
    """The reader, success and failure checks hold views of MjData made at construction:
    they must see every reset and every state written into the env's MjData."""
    rng = np.random.default_rng(1)
    for seed in range(3):
        obs, info = env.reset(seed=seed)
        _assert_matches_data(env, obs)
        for _ in range(3):
            action = rng.uniform(env.action_space.low, env.action_space.high).astype(np.float32) * 0.5
            obs, reward, terminated, truncated, info = env.step(action)
            _assert_matches_data(env, obs)
        assert not info["is_success"] and not terminated
    # A state copied in from elsewhere (as demo replay does) is read too.
    env.reset(seed=5)
    other = mujoco.MjData(env.model)
    mujoco.mj_copyData(other, env.model, env.data)
    for _ in range(20):
        mujoco.mj_step(env.model, other)
    mujoco.mj_copyData(env.data, env.model, other)
    _assert_matches_data(env, env._observe())
    # Success sees the target moved onto the wrist, failure sees the pelvis leave the workspace.
    mocap = env._mocap_ids[0]
    env.data.mocap_pos[mocap] = env.robot.wrist_positions(env.data)[0]
    mujoco.mj_forward(env.model, env.data)
    assert env._success()
    env.reset(seed=6)
    assert not env._success() and not env._failure()
    if env.robot.floating_base:
        env.data.qpos[env.robot.base_qpos["x"]] += 2 * env.workspace_radius
    else:
        env.data.qpos[env.robot.root_qpos] += 2 * env.workspace_radius
    mujoco.mj_forward(env.model, env.data)
    assert env._failure()
    env.reset(seed=6)
    assert not env._failure()


def test_reader_follows_another_mjdata(env):
    """One reader used with two MjData reads each one's own state."""
    reader = ProprioceptionReader(env.model, env.robot)
    env.reset(seed=0)
    other = mujoco.MjData(env.model)
    mujoco.mj_copyData(other, env.model, env.data)
    other.qpos[env.robot.proprio_qpos] += 0.01
    obs_env, obs_other = {}, {}
    reader.read(env.data, obs_env)
    reader.read(other, obs_other)
    reader.read(env.data, {})
    n = len(env.robot.proprio_names)
    np.testing.assert_allclose(
        obs_other["proprioception"][:n] - obs_env["proprioception"][:n], 0.01, atol=1e-6
    )


# ------------------------------------------------------------------ float32 validation
@pytest.fixture(scope="module")
def reach_env():
    env = ReachTargetMultiModal(control_frequency=500)
    env.reset(seed=0)
    yield env
    env.close()


def _verdict(controller, action):
    try:
        controller.validate(action)
        return None
    except ValueError as error:
        return str(error)


def test_float32_validation_matches_float64(reach_env):
    """Float32 actions take a float32 comparison; it must accept and reject exactly what the
    float64 comparison does (the bounds are widened by one float32 ulp), and name the same
    entries."""
    controller = reach_env._controller
    low, high = reach_env.action_space.low, reach_env.action_space.high
    candidates = [np.float32(v) for v in (np.nan, np.inf, -np.inf, -0.0, 0.0)]
    for bound in (low, high):
        for i in range(len(bound)):
            value = bound[i]
            for steps in range(-3, 4):  # float32 neighbours around each bound
                candidate = value
                direction = np.float32(np.inf if steps > 0 else -np.inf)
                for _ in range(abs(steps)):
                    candidate = np.nextafter(candidate, direction)
                candidates.append((i, candidate))
    checked = 0
    for item in candidates:
        index, value = item if isinstance(item, tuple) else (None, item)
        for i in [index] if index is not None else range(len(low)):
            action = np.zeros(len(low), np.float32)
            action[i] = value
            as32, as64 = _verdict(controller, action), _verdict(controller, action.astype(np.float64))
            assert (as32 is None) == (as64 is None), (i, value, as32, as64)
            if as32 is not None:
                assert reach_env.action_layout.entries[i].name in as32
            checked += 1
    assert checked > 100
    # Exactly one float32 ulp beyond a bound is still accepted (the widening), two are not.
    action = np.zeros(len(low), np.float32)
    action[-1] = np.nextafter(np.float32(1.0), np.float32(2.0))
    assert _verdict(controller, action) is None
    action[-1] = np.nextafter(action[-1], np.float32(2.0))
    assert "right_gripper" in _verdict(controller, action)


def test_float32_fast_path_rejects_bad_shapes_and_dtypes(reach_env):
    env = reach_env
    for action in (np.zeros(15, np.float32), np.zeros((1, 16), np.float32), np.float32(0.0)):
        with pytest.raises(ValueError, match="shape"):
            env.step(action)
    # Other dtypes and containers go through the float64 path, with the same result.
    action = zero_action(env)
    for variant in (action.astype(np.float64), action.astype(np.float16), action.tolist(), tuple(action)):
        env.step(variant)
    bad = zero_action(env).astype(np.float16)
    bad[env.action_layout["left_gripper"]] = 2.0
    with pytest.raises(ValueError, match="left_gripper"):
        env.step(bad)
    strided = np.zeros(32, np.float32)[::2]  # a non-contiguous float32 view
    env.step(strided)
    strided[3] = np.nan
    with pytest.raises(ValueError, match="finite"):
        env.step(strided)
