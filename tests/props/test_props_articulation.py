"""Drawers, doors and trays move through their range under a pull on their handle,
stop at their limits and hold position when released."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from propkit import compile_bound, make_world

from bigym.props import ArticulatedProp, BaseCabinet, Dishwasher, WallCabinet

CASES = {
    "base_doors": lambda: BaseCabinet("cab", door_left=True, shelf=True),
    "base_door_right_hob": lambda: BaseCabinet("cab", door_right=True, hob=True),
    "big_drawers": lambda: BaseCabinet("cab", big_drawers=(True, True)),
    "small_drawers": lambda: BaseCabinet("cab", small_drawers=(True, True, True, True)),
    "mixed_drawers": lambda: BaseCabinet("cab", big_drawers=(True, False), small_drawers=(False, False, True, True)),
    "wall_glass": lambda: WallCabinet("wall", glass=True),
    "wall_doors_vent": lambda: WallCabinet("wall", doors=True, vent=True),
    "dishwasher": lambda: Dishwasher("dw"),
}
JOINTS = [
    ("base_doors", "door_left"),
    ("base_door_right_hob", "door_right"),
    ("big_drawers", "drawer_big_1"),
    ("big_drawers", "drawer_big_2"),
    ("small_drawers", "drawer_small_1"),
    ("small_drawers", "drawer_small_2"),
    ("small_drawers", "drawer_small_3"),
    ("small_drawers", "drawer_small_4"),
    ("mixed_drawers", "drawer_big_1"),
    ("mixed_drawers", "drawer_small_4"),
    ("wall_glass", "door_left"),
    ("wall_glass", "door_right"),
    ("wall_doors_vent", "door_left"),
    ("dishwasher", "door"),
    ("dishwasher", "tray_bottom"),
    ("dishwasher", "tray_mid"),
]
#: pull force at the handle (N)
FORCE = {"door": 12.0, "drawer": 20.0, "tray": 8.0}


def _build(case: str) -> tuple[mujoco.MjModel, mujoco.MjData, ArticulatedProp]:
    spec = make_world()
    prop = CASES[case]()
    prop.attach_to(spec.worldbody, (1.2, 0.0, 0.0))
    model, data = compile_bound(spec, [prop])
    return model, data, prop


def _pull(model, data, prop: ArticulatedProp, key: str, sign: float, force: float, seconds: float) -> list[float]:
    """Pull (sign +1, opening) or push (-1) at the handle along the direction the handle
    moves when the joint opens; returns the joint's normalised trajectory."""
    sid = prop.site_id(f"{key}_handle")
    body = model.site_bodyid[sid]
    dof = prop._jd[prop.joint_index(key)]
    jac = np.zeros((3, model.nv))
    traj = []
    for _ in range(int(seconds / model.opt.timestep)):
        mujoco.mj_jacSite(model, data, jac, None, sid)
        direction = jac[:, dof] / np.linalg.norm(jac[:, dof])
        f = sign * force * direction
        data.xfrc_applied[body, :3] = f
        data.xfrc_applied[body, 3:] = np.cross(data.site_xpos[sid] - data.xipos[body], f)
        mujoco.mj_step(model, data)
        traj.append(prop.get_state(data)[prop.joint_index(key)])
    data.xfrc_applied[:] = 0.0
    return traj


def _initial_state(prop: ArticulatedProp, key: str, value: float) -> np.ndarray:
    state = np.zeros(len(prop.joint_keys))
    if isinstance(prop, Dishwasher) and key != "door":
        state[prop.joint_index("door")] = 1.0  # trays move with the door open
    state[prop.joint_index(key)] = value
    return state


@pytest.mark.parametrize("case, key", JOINTS)
def test_handle_pull_opens_fully_and_push_closes(case, key):
    model, data, prop = _build(case)
    kind = "tray" if key.startswith("tray") else key.split("_")[0]
    force = FORCE[kind]
    i = prop.joint_index(key)
    jid = prop.joint_ids[i]
    lo, hi = model.jnt_range[jid]
    tol = 0.005 if model.jnt_type[jid] == mujoco.mjtJoint.mjJNT_HINGE else 0.004  # rad / m

    prop.set_state(data, _initial_state(prop, key, 0.0))
    mujoco.mj_forward(model, data)
    traj = _pull(model, data, prop, key, +1.0, force, 2.0)
    assert max(traj) > 0.99, f"only reached {max(traj):.3f}"
    assert np.argmax(np.asarray(traj) > 0.99) * model.opt.timestep < 1.5, "too stiff to open"
    q = data.qpos[prop._jq[i]]
    assert q < hi + tol, "went through the open limit"
    assert abs(data.qvel[prop._jd[i]]) < 1e-3, "not stopped at the limit"
    # the other joints did not move
    others = np.delete(prop.get_state(data), i)
    np.testing.assert_allclose(others, np.delete(_initial_state(prop, key, 0.0), i), atol=1e-3)

    traj = _pull(model, data, prop, key, -1.0, force, 2.0)
    assert min(traj) < 0.01
    assert data.qpos[prop._jq[i]] > lo - tol, "went through the closed limit"
    assert abs(data.qvel[prop._jd[i]]) < 1e-3


@pytest.mark.parametrize("case", sorted(CASES))
def test_released_joints_hold_their_position(case):
    """Released anywhere in their range (no load), doors/drawers/trays stay put."""
    model, data, prop = _build(case)
    rng = np.random.default_rng(0)
    for _ in range(3):
        state = rng.uniform(0.05, 0.95, len(prop.joint_keys))
        if isinstance(prop, Dishwasher):
            state[prop.joint_index("door")] = 1.0  # trays out need the door open
        prop.set_state(data, state)
        mujoco.mj_forward(model, data)
        for _ in range(1500):
            mujoco.mj_step(model, data)
        np.testing.assert_allclose(prop.get_state(data), state, atol=1e-3)


@pytest.mark.parametrize("value", [0.05, 0.25, 0.5, 0.75, 0.95])
def test_dishwasher_door_holds_when_released(value):
    """The door's weight is balanced: released part-open it stays there for 10 s."""
    model, data, dw = _build("dishwasher")
    dw.set_state(data, [value, 0.0, 0.0])
    mujoco.mj_forward(model, data)
    traj = []
    for _ in range(5000):
        mujoco.mj_step(model, data)
        traj.append(dw.get_state(data)[0])
    assert np.abs(np.asarray(traj) - value).max() < 0.002
    assert dw.door_residual_torque < 0.1 * Dishwasher.DOOR_FRICTION


def test_dishwasher_door_is_light_to_move():
    """A gentle 5 N at the handle is enough to open and close the balanced door."""
    model, data, dw = _build("dishwasher")
    dw.set_state(data, [0.3, 0.0, 0.0])
    mujoco.mj_forward(model, data)
    assert _pull(model, data, dw, "door", +1.0, 5.0, 2.0)[-1] > 0.99
    assert _pull(model, data, dw, "door", -1.0, 5.0, 2.0)[-1] < 0.01


def test_dishwasher_door_cannot_close_through_open_trays():
    model, data, dw = _build("dishwasher")
    dw.set_state(data, [1.0, 1.0, 0.0])
    mujoco.mj_forward(model, data)
    traj = _pull(model, data, dw, "door", -1.0, 12.0, 1.0)
    assert min(traj) > 0.5, "the door went through the bottom tray"
    assert dw.get_state(data)[1] > 0.9


def test_handles_face_the_robot():
    """Every handle sits in front of its module (towards -x) at a reachable height."""
    for case in CASES:
        _model, data, prop = _build(case)
        for key in prop.joint_keys:
            p = prop.site_pos(data, f"{key}_handle")
            front = 1.2 - (0.6 if isinstance(prop, (BaseCabinet, Dishwasher)) else 0.34)
            if key.startswith("tray"):
                front += 0.06  # tray handles are just behind the closed door
            assert p[0] < front, (case, key, p)
            assert 0.1 < p[2] < 1.7, (case, key, p)
