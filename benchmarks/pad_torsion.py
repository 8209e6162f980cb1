"""How far an object held off its centre of mass twists in the gripper, per pad contact setting.

Run: ``python benchmarks/pad_torsion.py [--seconds 2]``.

The saucepan of ``SaucepanToHob`` (0.3 kg, its centre of mass ~0.2 m from the grip) is put
with its handle between the open fingers of the right gripper, oriented so that gravity
twists it about the closing axis (the worst case: no finger edge resists it), with gravity
off while the fingers close. Then gravity comes on and the pan is watched for ``--seconds``:
how many degrees it turns about the closing axis and how far the handle creeps along the
pads. Each row changes only the four pad geoms' ``condim`` and torsional friction; the
shipped setting (condim 4, 0.01 m) is marked.
"""

from __future__ import annotations

import argparse
import os

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

from bigym.action_modes import JointPositionActionMode  # noqa: E402
from bigym.envs.pick_and_place import SaucepanToHob  # noqa: E402
from bigym.robot.h1 import PAD_TORSIONAL_FRICTION  # noqa: E402

HAND_DOWN = {"shoulder_pitch": -0.3, "elbow": 1.8, "wrist": np.pi / 2}
SETTINGS = ((3, 0.0), (4, 0.002), (4, 0.005), (4, PAD_TORSIONAL_FRICTION), (4, 0.02))


def _frame(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    z = np.cross(x, y)
    matrix = np.stack([x, y, z], axis=1)
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, matrix.ravel())
    return quat


def hold(condim: int, torsion: float, seconds: float, side: int = 1) -> tuple[float, float]:
    """Degrees turned about the closing axis and mm of creep at the handle after ``seconds``."""
    env = SaucepanToHob(action_mode=JointPositionActionMode(absolute=True), control_frequency=500)
    env.reset(seed=0)
    model, data = env.model, env.data
    pads = [i for i in range(model.ngeom) if (model.geom(i).name or "").endswith(("_pad1", "_pad2"))]
    model.geom_condim[pads] = condim
    model.geom_friction[pads, 1] = torsion
    robot = env.robot
    pan = env.props["saucepan"]
    body = pan.root_body_id
    joint = model.body_jntadr[body]
    qpos = model.jnt_qposadr[joint]
    handle = model.site(pan.site_names["handle"]).id
    pinch = robot.pinch_site_ids[side]

    # The hand points down with the fingers closing horizontally, as when taking a handle from above.
    side_name = ("left", "right")[side]
    for joint_name, angle in HAND_DOWN.items():
        data.qpos[model.joint(f"{side_name}_{joint_name}").qposadr[0]] = angle
    mujoco.mj_forward(model, data)
    pad_bodies = [model.body(f"{side_name}_gripper/{finger}_pad").id for finger in ("left", "right")]
    closing = data.xpos[pad_bodies[0]] - data.xpos[pad_bodies[1]]
    closing /= np.linalg.norm(closing)
    lever = np.cross(closing, [0.0, 0.0, -1.0])  # offset direction with the largest twist about the axis
    lever /= np.linalg.norm(lever)
    x_axis = -lever  # the handle points from the pan towards the grip
    y_axis = closing if np.cross(x_axis, closing)[2] >= 0 else -closing
    quat = _frame(x_axis, y_axis)
    data.qpos[qpos + 3 : qpos + 7] = quat
    data.qpos[qpos : qpos + 3] = 0.0
    mujoco.mj_forward(model, data)
    data.qpos[qpos : qpos + 3] = data.site_xpos[pinch] - data.site_xpos[handle]
    data.qvel[model.jnt_dofadr[joint] : model.jnt_dofadr[joint] + 6] = 0.0
    mujoco.mj_forward(model, data)

    gravity = model.opt.gravity.copy()
    model.opt.gravity[:] = 0.0
    action = np.zeros(env.action_space.shape, np.float32)
    robot.hold_current_pose(data)
    action[:-2] = data.ctrl[: len(action) - 2]  # hold the arms where they are
    action[:4] = 0.0  # base actions are always moves: stay
    action[-2 + side] = 1.0  # close this gripper
    for _ in range(400):  # 0.8 s: the fingers close on the handle
        env.step(action)
    model.opt.gravity[:] = gravity
    for _ in range(100):  # 0.2 s: the load comes on
        env.step(action)
    start_rot = data.xmat[body].reshape(3, 3).copy()
    start_offset = data.site_xpos[handle] - data.site_xpos[pinch]
    for _ in range(int(seconds * 500)):
        env.step(action)
    relative = data.xmat[body].reshape(3, 3) @ start_rot.T
    angle = np.degrees(np.arccos(np.clip((np.trace(relative) - 1) / 2, -1, 1)))
    creep = np.linalg.norm((data.site_xpos[handle] - data.site_xpos[pinch]) - start_offset) * 1000
    env.close()
    return float(angle), float(creep)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=2.0)
    args = parser.parse_args()
    print(f"saucepan held by its handle, twisted by gravity about the closing axis, over {args.seconds:g} s")
    print(f"{'pad condim':>10s} {'torsional (m)':>14s} {'turned (deg)':>13s} {'creep (mm)':>11s}")
    for condim, torsion in SETTINGS:
        angle, creep = hold(condim, torsion, args.seconds)
        mark = "  <- shipped" if (condim, torsion) == (4, PAD_TORSIONAL_FRICTION) else ""
        print(f"{condim:10d} {torsion:14.3f} {angle:13.2f} {creep:11.2f}{mark}")


if __name__ == "__main__":
    main()
