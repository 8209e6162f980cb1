"""Helpers shared across the test suite (imported as ``testkit``; ``tests/`` is on the path).

Kept out of ``conftest.py`` on purpose: several folders have a conftest, and a plain
``from conftest import ...`` resolves to whichever one was imported first.
"""

from __future__ import annotations

import mujoco
import numpy as np

import bigym

ALL_TASKS = tuple(bigym.TASKS)
REACH_TASKS = ("ReachTargetSingle", "ReachTargetMultiModal", "ReachTargetDual")


def task_state(env) -> np.ndarray:
    """What a task randomises, without the robot: the world pose of every prop's root body
    (free and static props alike), the joint state of every articulated prop, and the
    mocap bodies (the reach targets). The robot's random start offset is left out, so two
    resets differ here only if the task itself placed its objects differently."""
    from bigym.props.base import ArticulatedProp

    unwrapped = env.unwrapped
    data = unwrapped.data
    parts = [data.mocap_pos.ravel(), data.mocap_quat.ravel()]
    for _, prop in sorted(unwrapped.props.items()):
        body = prop.root_body_id
        parts += [data.xpos[body], data.xquat[body]]
        if isinstance(prop, ArticulatedProp) and prop.joint_keys:
            parts.append(prop.get_state(data))
    return np.concatenate(parts).copy()


def zero_action(env) -> np.ndarray:
    """An action that changes nothing in delta mode: zero deltas, grippers open."""
    return np.zeros(env.action_space.shape, np.float32)


def hold_action(env) -> np.ndarray:
    """An action that keeps every servo where it is, in delta or absolute mode."""
    unwrapped = env.unwrapped
    action = np.zeros(unwrapped.action_space.shape, np.float64)
    if unwrapped.action_mode.absolute:
        layout = unwrapped.action_layout
        for entry in layout.entries:
            if entry.group in ("left_arm", "right_arm", "legs", "torso"):
                action[entry.index] = unwrapped.data.ctrl[entry.index]
    return np.clip(action, unwrapped.action_space.low, unwrapped.action_space.high).astype(np.float32)


def fresh_kinematics(env) -> mujoco.MjData:
    """A scratch MjData holding the env's current state with kinematics recomputed from qpos."""
    model = env.unwrapped.model
    scratch = mujoco.MjData(model)
    scratch.qpos[:] = env.unwrapped.data.qpos
    scratch.mocap_pos[:] = env.unwrapped.data.mocap_pos
    scratch.mocap_quat[:] = env.unwrapped.data.mocap_quat
    mujoco.mj_kinematics(model, scratch)
    return scratch


def touch_with_gripper(env, prop: str) -> None:
    """Translate the floating base so that a gripper pad dips 2 mm into ``prop``.

    A static check for "still held" near-misses: nothing is integrated, only the
    kinematics and contacts are recomputed.
    """
    model, data = env.model, env.data
    pad = model.geom("left_gripper/right_pad1").id
    fromto = np.zeros(6)
    best, vector = np.inf, None
    for geom in env.props[prop].collision_geom_ids:
        distance = mujoco.mj_geomDistance(model, data, pad, int(geom), 10.0, fromto)
        if distance < best:
            best, vector = distance, fromto[3:] - fromto[:3]
    vector = vector + 0.002 * vector / np.linalg.norm(vector)
    for k, dof in enumerate(("x", "y", "z")):
        data.qpos[env.robot.base_qpos[dof]] += vector[k]
    mujoco.mj_forward(model, data)
