"""Success detection of the reach tasks, driven by a small damped-least-squares IK.

The IK runs on a scratch copy of the simulation; the resulting joint targets are then
commanded through ``JointPositionActionMode(absolute=True)`` (base entries are deltas of
the base servo targets even in absolute mode) and the env alone decides success.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.reach_target import (
    SUCCESS_TOLERANCE,
    ReachTargetDual,
    ReachTargetMultiModal,
    ReachTargetSingle,
)

from testkit import REACH_TASKS, fresh_kinematics

ARM = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist")
BASE_JOINTS = ("pelvis_x", "pelvis_y", "pelvis_z", "pelvis_rz")
BASE_ACTION = {"pelvis_x": "base_dx", "pelvis_y": "base_dy", "pelvis_z": "base_dz", "pelvis_rz": "base_dyaw"}
ABSOLUTE = JointPositionActionMode(absolute=True)


# ------------------------------------------------------------------ IK and driving
def solve_ik(env, goals: dict[str, np.ndarray], base_weight: float = 0.4, iterations: int = 400) -> dict[str, float]:
    """Joint positions (base DOFs + arms of the sides in ``goals``) putting each wrist site on its goal.

    ``goals`` maps a side ("left"/"right") to a world position for ``<side>_wrist_site``.
    """
    model = env.model
    data = fresh_kinematics(env)
    mujoco.mj_comPos(model, data)
    joints = [j for j in BASE_JOINTS] + [f"{side}_{part}" for side in goals for part in ARM]
    joint_ids = [model.joint(name).id for name in joints]
    dofs = np.array([model.jnt_dofadr[j] for j in joint_ids])
    qadr = np.array([model.jnt_qposadr[j] for j in joint_ids])
    limited = np.array([bool(model.jnt_limited[j]) for j in joint_ids])
    ranges = model.jnt_range[joint_ids]
    weights = np.array([base_weight if name in BASE_JOINTS else 1.0 for name in joints])
    sites = [model.site(f"{side}_wrist_site").id for side in goals]
    targets = np.concatenate([np.asarray(goals[side], float) for side in goals])
    jacp = np.zeros((3, model.nv))
    error = np.inf
    for _ in range(iterations):
        current = np.concatenate([data.site_xpos[s] for s in sites])
        delta = targets - current
        error = np.linalg.norm(delta)
        if error < 1e-4:
            break
        rows = []
        for site in sites:
            mujoco.mj_jacSite(model, data, jacp, None, site)
            rows.append(jacp[:, dofs] * weights)
        jac = np.vstack(rows)
        step = jac.T @ np.linalg.solve(jac @ jac.T + 0.05**2 * np.eye(len(delta)), delta)
        step *= weights
        largest = np.abs(step).max()
        if largest > 0.1:
            step *= 0.1 / largest
        qpos = data.qpos[qadr] + step
        qpos[limited] = np.clip(qpos[limited], ranges[limited, 0] + 1e-3, ranges[limited, 1] - 1e-3)
        data.qpos[qadr] = qpos
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
    assert error < 2e-3, f"test IK did not converge ({error:.4f} m left) for goals {goals}"
    return {name: float(data.qpos[adr]) for name, adr in zip(joints, qadr)}


def absolute_action(env, joint_targets: dict[str, float]) -> np.ndarray:
    """An absolute-mode action: arm targets as given (else current), base deltas toward targets."""
    layout = env.action_layout
    low, high = env.action_space.low.astype(np.float64), env.action_space.high.astype(np.float64)
    action = np.zeros(env.action_space.shape, np.float64)
    for entry in layout.entries:
        if entry.group in ("left_arm", "right_arm"):
            action[entry.index] = joint_targets.get(entry.name, env.data.ctrl[entry.index])
    for joint, name in BASE_ACTION.items():
        if joint in joint_targets and name in layout:
            index = layout[name]
            action[index] = joint_targets[joint] - env.data.ctrl[index]  # ctrl[index] is the base target
    return np.clip(action, low, high).astype(np.float32)


def wrist_distances(env, target: np.ndarray) -> np.ndarray:
    """Distances of the (left, right) wrist sites to ``target``, from the current qpos."""
    scratch = fresh_kinematics(env)
    sites = [env.model.site(f"{side}_wrist_site").id for side in ("left", "right")]
    return np.linalg.norm(scratch.site_xpos[sites] - target, axis=1)


def drive(env, joint_targets, steps: int):
    """Command ``joint_targets`` for up to ``steps`` steps; yields each step's result."""
    for _ in range(steps):
        result = env.step(absolute_action(env, joint_targets))
        yield result
        if result[2] or result[3]:
            return


@pytest.fixture(scope="module")
def single_env():
    env = ReachTargetSingle(action_mode=ABSOLUTE)
    yield env
    env.close()


# ------------------------------------------------------------------ not at reset
@pytest.mark.parametrize("task", REACH_TASKS)
def test_not_success_at_reset(task):
    cls = {"ReachTargetSingle": ReachTargetSingle, "ReachTargetMultiModal": ReachTargetMultiModal, "ReachTargetDual": ReachTargetDual}[task]
    env = cls()
    try:
        for seed in range(6):
            obs, info = env.reset(seed=seed)
            assert info["is_success"] is False
            obs, reward, terminated, truncated, info = env.step(np.zeros(env.action_space.shape, np.float32))
            assert not info["is_success"]
            assert reward == 0.0
            assert not terminated and not truncated
            # Sanity of the premise: every wrist is far from every target at the start.
            for target in env.target_positions:
                assert wrist_distances(env, target).min() > SUCCESS_TOLERANCE
    finally:
        env.close()


# ------------------------------------------------------------------ reaching
def _reach_until_success(env, joint_targets, steps=80):
    for count, (obs, reward, terminated, truncated, info) in enumerate(drive(env, joint_targets, steps), 1):
        assert not truncated, info
        if info["is_success"]:
            assert reward == 1.0
            assert terminated
            return count
        assert reward == 0.0
        assert not terminated, "terminated without success"
    pytest.fail(f"no success within {steps} steps")


def test_single_left_hand_success(single_env):
    env = single_env
    for seed in (0, 1):
        env.reset(seed=seed)
        target = env.target_positions[0].copy()
        joints = solve_ik(env, {"left": target})
        _reach_until_success(env, joints)
        assert wrist_distances(env, target)[0] <= SUCCESS_TOLERANCE + 0.01


def test_multimodal_success_with_either_hand():
    env = ReachTargetMultiModal(action_mode=ABSOLUTE)
    try:
        sides_seen = set()
        for seed in range(20):
            env.reset(seed=seed)
            target = env.target_positions[0].copy()
            side = "left" if target[1] > 0.1 else "right" if target[1] < -0.1 else None
            if side is None or side in sides_seen:
                continue
            sides_seen.add(side)
            _reach_until_success(env, solve_ik(env, {side: target}))
            if sides_seen == {"left", "right"}:
                break
        assert sides_seen == {"left", "right"}
    finally:
        env.close()


def test_dual_needs_both_hands():
    env = ReachTargetDual(action_mode=ABSOLUTE)
    try:
        env.reset(seed=3)
        left_target, right_target = env.target_positions.copy()
        # Left wrist alone on its target: not a success.
        left_only = solve_ik(env, {"left": left_target})
        for obs, reward, terminated, truncated, info in drive(env, left_only, 50):
            assert not info["is_success"] and reward == 0.0 and not terminated
        assert wrist_distances(env, left_target)[0] < 0.05
        # Both wrists on their targets: success.
        both = solve_ik(env, {"left": left_target, "right": right_target})
        _reach_until_success(env, both)
    finally:
        env.close()


def test_near_miss_is_not_success(single_env):
    env = single_env
    env.reset(seed=4)
    target = env.target_positions[0].copy()
    wrist = env.robot.wrist_positions(env.data)[0].copy()
    away = (wrist - target) / np.linalg.norm(wrist - target)
    joints = solve_ik(env, {"left": target + 0.15 * away})
    for obs, reward, terminated, truncated, info in drive(env, joints, 60):
        assert not info["is_success"] and reward == 0.0 and not terminated
    distance = wrist_distances(env, target)[0]
    assert 0.13 < distance < 0.17, f"the near miss ended {distance:.3f} m from the target"


def test_single_left_ignores_right_hand(single_env):
    env = single_env
    env.reset(seed=5)
    target = env.target_positions[0].copy()
    joints = solve_ik(env, {"right": target})
    for obs, reward, terminated, truncated, info in drive(env, joints, 60):
        assert not info["is_success"] and reward == 0.0 and not terminated
    left, right = wrist_distances(env, target)
    assert right < 0.05, f"right wrist did not reach the target ({right:.3f} m)"
    # Well outside the tolerance (the near-miss test shows 0.15 m is not a success).
    assert left > 0.15, f"left wrist unexpectedly near the target ({left:.3f} m)"


def test_single_right_hand_variant():
    env = ReachTargetSingle(action_mode=ABSOLUTE, hand="right")
    try:
        env.reset(seed=0)
        target = env.target_positions[0].copy()
        assert target[1] < 0, "right-hand targets lie on the right"
        _reach_until_success(env, solve_ik(env, {"right": target}))
    finally:
        env.close()
    with pytest.raises(ValueError, match="hand"):
        ReachTargetSingle(hand="both")


def test_success_matches_returned_state():
    """``info["is_success"]`` must describe the state the step returns.

    At 500 Hz one step is one physics step. If success is computed from sensor data of
    the start of the last physics step, it lags the returned state by a whole step: the
    step on which the wrist enters the tolerance is reported as not successful.
    """
    env = ReachTargetSingle(action_mode=ABSOLUTE, control_frequency=500)
    try:
        env.reset(seed=0)
        target = env.target_positions[0].copy()
        joints = solve_ik(env, {"left": target})
        mismatches = []
        for step, (obs, reward, terminated, truncated, info) in enumerate(drive(env, joints, 1500), 1):
            within = wrist_distances(env, target)[0] <= SUCCESS_TOLERANCE
            if within != info["is_success"]:
                mismatches.append((step, float(wrist_distances(env, target)[0]), info["is_success"]))
            if info["is_success"]:
                break
        assert info["is_success"], "never reached the target"
        assert not mismatches, (
            "is_success disagrees with the returned state (step, wrist distance, is_success): "
            f"{mismatches}; success is computed from data one physics step older than the observation"
        )
    finally:
        env.close()
