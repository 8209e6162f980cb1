"""How the spatula can (and cannot) move the raw ``SandwichToast`` sandwich: two probes.

Run: ``python benchmarks/sandwich_toast_probe.py`` (against a stop) and
``python benchmarks/sandwich_toast_probe.py --sweep`` (swept into a pan held below the
counter's edge).

Why ``SandwichToast``'s expert sweeps (``bigym/experts/sandwich_toast.py``): on the board,
a blade pushed at the raw sandwich (box collider, square edges; the blade grips it at 0.8,
the board at 0.3) shoves it along. Both
probes use nothing but the props: the spatula welded to a mocap "hand" (a soft weld, as an
arm's grip is), the pan (``--sweep``) welded to another.

Against a stop: the sandwich stands against a step (a box ``--step`` m high, the hob's edge
is 1 cm), and the blade's tip is pushed along the floor at ``--pitch`` degrees, pressed
``--press`` m into it, up to the step; then lifted 6 cm. Each row: where the tip stopped,
the sandwich's middle after the push and after the lift, and whether it rode up.
Measured on 2026-12-06 (x86_64, 2 CPUs), the defaults: at 5-30 degrees and 0-2 mm of press
the tip stops at the sandwich's bottom edge (x = -0.121; its face is at -0.123), the
sandwich does not move, and the lift leaves it on the floor: a flush square edge gives the
blade nothing to slide under, stop or not. ``--rounded`` (the pan tasks' collider), 12
degrees: the blade gets under, and the sandwich rides up over the 1 cm step (the pan's
4.5 cm wall holds it in ``SandwichRemove``).

Swept (``--sweep``): a counter (top 0.86 m, front at x = 0) with the board 7.5 cm behind its
front, the sandwich on the board (``--yaw``: its headings), the pan held level in front
of the counter (its rim ``--rim-below`` m under the counter's top, ``--pan-gap`` m out from
it, ``--pan-side`` m off the sweep's line); the blade, held at ``--pitch`` degrees, goes
down behind the sandwich and draws it 5 mm over the board, off its edge, over the counter
and off its edge. Each row: where the sandwich came to rest (from the pan's middle), its
tilt, and whether it lies flat in the pan. Measured on 2026-12-06, the defaults (pitch 60,
rim 5 mm under, 1.5 cm out, on the line): flat in the pan at 6 of 6 headings; also at pitch
72, at twice the speed, the rim 2 cm under, 3 cm out; leaning on the pan's wall (20-25
degrees) at 1-2 of 3 headings with the pan 4-5 cm off the line or the blade at 45 degrees.
``bigym/experts/sandwich_toast.py`` is the robot doing it.
"""

from __future__ import annotations

import argparse
import itertools
import os

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

from bigym.experts.sandwich import TIP  # noqa: E402
from bigym.props import ChoppingBoard, FryingPan, Sandwich, Spatula  # noqa: E402
from bigym.props.base import quat_yaw  # noqa: E402
from bigym.world import add_world  # noqa: E402

#: how soft the hand's weld is (s): about what the arm's grip and stance give
WELD_TIMECONST = 0.01
PUSH_SPEED = 0.04


def blade_rotation(pitch: float) -> np.ndarray:
    """The spatula pointing along +x, the blade ``pitch`` rad below the horizontal."""
    y = np.array([np.cos(pitch), 0.0, -np.sin(pitch)])
    x = np.array([0.0, 1.0, 0.0])
    return np.column_stack([x, y, np.cross(x, y)])


def weld_to_hand(spec: mujoco.MjSpec, hand: str, body: str) -> None:
    """A mocap body ``hand`` and a soft weld that holds ``body`` where it is."""
    spec.worldbody.add_body(name=hand, mocap=True)
    weld = spec.add_equality()
    weld.type, weld.objtype = mujoco.mjtEq.mjEQ_WELD, mujoco.mjtObj.mjOBJ_BODY
    weld.name1, weld.name2 = hand, body
    weld.solref = [WELD_TIMECONST, 1.0]
    weld.data[0:11] = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]  # the body is where the hand is


def run(pitch_deg: float, press: float, step: float, rounded: bool) -> str:
    spec = mujoco.MjSpec()
    add_world(spec)
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.2, 0.3, step / 2], pos=[0.2, 0.0, step / 2])
    sandwich, spatula = Sandwich("sandwich", rounded=rounded), Spatula("spatula")
    for prop in (sandwich, spatula):
        prop.attach_to(spec.worldbody)
    weld_to_hand(spec, "hand", spatula.root_body_name)
    model = spec.compile()
    data = mujoco.MjData(model)
    for prop in (sandwich, spatula):
        prop.bind(model, data)
    half = Sandwich.SIZE[0] / 2
    sandwich.set_pose(data, (-half - 0.0005, 0.0, Sandwich.SIZE[2] / 2 + 0.0003))
    rot = blade_rotation(np.deg2rad(pitch_deg))
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, rot.ravel())
    start, end = np.array([-2 * half - 0.02, 0.0, -press]), np.array([-0.012, 0.0, -press])
    data.mocap_pos[0], data.mocap_quat[0] = start - rot @ TIP, quat
    spatula.set_pose(data, data.mocap_pos[0] + np.array([0.0, 0.0, press + 0.001]), quat)
    mujoco.mj_forward(model, data)
    steps = round((float(np.linalg.norm(end - start)) / PUSH_SPEED + 0.5) / model.opt.timestep)
    for i in range(steps):
        x = min(1.0, i * model.opt.timestep * PUSH_SPEED / float(np.linalg.norm(end - start)))
        data.mocap_pos[0] = start + x * (end - start) - rot @ TIP
        mujoco.mj_step(model, data)
    body = spatula.root_body_id
    tip = data.xpos[body] + data.xmat[body].reshape(3, 3) @ TIP
    pushed = data.xpos[sandwich.root_body_id].copy()
    lifted_from = data.mocap_pos[0].copy()
    for i in range(round(1.5 / model.opt.timestep)):
        data.mocap_pos[0] = lifted_from + np.array([-0.01, 0.0, 0.06]) * min(1.0, i * model.opt.timestep)
        mujoco.mj_step(model, data)
    lifted = data.xpos[sandwich.root_body_id]
    return (
        f"pitch {pitch_deg:4.1f} deg, press {press * 1000:.0f} mm: tip stopped at x = {tip[0]:+.3f}, "
        f"sandwich after the push {np.round(pushed, 3)}, after the lift {np.round(lifted, 3)}, "
        f"on the blade: {bool(lifted[2] > Sandwich.SIZE[2] / 2 + 0.02)}"
    )


COUNTER_TOP = 0.86
BOARD_MARGIN = 0.075  # the board's near edge behind the counter's front
SWEEP_SPEED = 0.05
SWEEP_GAP = 0.005  # the tip over the surface it sweeps


def sweep(yaw_deg: float, pitch_deg: float, rim_below: float, pan_gap: float, pan_side: float, speed: float) -> str:
    spec = mujoco.MjSpec()
    add_world(spec)
    spec.worldbody.add_geom(
        type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.3, 0.6, COUNTER_TOP / 2], pos=[0.3, 0, COUNTER_TOP / 2]
    )
    board, sandwich, spatula, pan = ChoppingBoard("board"), Sandwich("sandwich"), Spatula("spatula"), FryingPan("pan")
    for prop in (board, sandwich, spatula, pan):
        prop.attach_to(spec.worldbody)
    weld_to_hand(spec, "hand", spatula.root_body_name)
    weld_to_hand(spec, "pan_hand", pan.root_body_name)
    model = spec.compile()
    data = mujoco.MjData(model)
    for prop in (board, sandwich, spatula, pan):
        prop.bind(model, data)
    board_x = BOARD_MARGIN + 0.145
    board.set_pose(data, (board_x, 0.0, COUNTER_TOP + 0.0003))
    board_top = COUNTER_TOP + 0.028
    sandwich.set_pose(data, (board_x, 0.0, board_top + Sandwich.SIZE[2] / 2 + 0.0003), quat_yaw(np.deg2rad(yaw_deg)))
    pan_pos = np.array([-pan.radius - pan_gap, pan_side, COUNTER_TOP - rim_below - pan.DEPTH])
    pan_quat = quat_yaw(-np.pi / 2)
    data.mocap_pos[1], data.mocap_quat[1] = pan_pos, pan_quat
    pan.set_pose(data, pan_pos, pan_quat)
    rot = blade_rotation(np.deg2rad(pitch_deg))
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, rot.ravel())
    mujoco.mj_forward(model, data)
    frame = data.xmat[sandwich.root_body_id].reshape(3, 3)
    far = data.xpos[sandwich.root_body_id][0] + float(np.abs(frame[0, :2]) @ (0.5 * np.array(Sandwich.SIZE[:2])))
    dt = model.opt.timestep

    def place(tip: np.ndarray) -> None:
        data.mocap_pos[0], data.mocap_quat[0] = tip - rot @ TIP, quat

    def go(a: np.ndarray, b: np.ndarray, duration: float) -> None:
        for i in range(int(duration / dt)):
            place(a + min(1.0, i * dt / duration) * (b - a))
            mujoco.mj_step(model, data)

    above = np.array([far + 0.02, 0.0, board_top + 0.10])
    place(above)
    spatula.set_pose(data, data.mocap_pos[0], quat)
    for _ in range(int(0.3 / dt)):
        mujoco.mj_step(model, data)
    # down behind it, over the board to its edge, down onto the counter, off the counter's edge
    path = [
        above,
        np.array([far + 0.015, 0.0, board_top + SWEEP_GAP]),
        np.array([BOARD_MARGIN - 0.01, 0.0, board_top + SWEEP_GAP]),
        np.array([BOARD_MARGIN - 0.03, 0.0, COUNTER_TOP + SWEEP_GAP]),
        np.array([-0.05, 0.0, COUNTER_TOP + SWEEP_GAP]),
    ]
    for a, b in itertools.pairwise(path):
        go(a, b, max(0.6, float(np.linalg.norm(b - a)) / speed))
    go(path[-1], path[-1] + np.array([0.05, 0.0, 0.1]), 1.0)
    go(path[-1] + np.array([0.05, 0.0, 0.1]), path[-1] + np.array([0.05, 0.0, 0.1]), 1.0)
    body = sandwich.root_body_id
    rest = data.xpos[body] - data.xpos[pan.root_body_id]
    tilt = float(np.degrees(np.arccos(min(1.0, abs(float(data.xmat[body][8]))))))
    in_pan = any(
        {int(model.geom_bodyid[c.geom1]), int(model.geom_bodyid[c.geom2])} == {body, pan.root_body_id}
        for c in data.contact[: data.ncon]
    )
    return (
        f"heading {yaw_deg:5.0f} deg: rests {np.round(rest, 3)} from the pan's middle, tilted {tilt:4.1f} deg, "
        f"flat in the pan: {in_pan and tilt < 10.0}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pitch", type=float, nargs="+", default=[5.0, 12.0, 20.0, 30.0], help="degrees, tip down")
    parser.add_argument("--press", type=float, nargs="+", default=[0.0, 0.002], help="m into the floor")
    parser.add_argument("--step", type=float, default=0.01, help="the stop's height (m): the hob's edge is 1 cm")
    parser.add_argument("--rounded", action="store_true", help="the rounded collider of the pan tasks instead")
    parser.add_argument("--sweep", action="store_true", help="the second probe: swept into a pan")
    parser.add_argument("--yaw", type=float, nargs="+", default=[0.0, 20.0, 45.0, 70.0, 100.0, 135.0], help="degrees")
    parser.add_argument("--rim-below", type=float, default=0.005, help="m under the counter's top")
    parser.add_argument("--pan-gap", type=float, default=0.015, help="m from the counter's front to the pan")
    parser.add_argument("--pan-side", type=float, default=0.0, help="m off the sweep's line")
    parser.add_argument("--speed", type=float, default=SWEEP_SPEED, help="m/s")
    args = parser.parse_args()
    if args.sweep:
        pitch = args.pitch[0] if args.pitch != parser.get_default("pitch") else 60.0
        for yaw in args.yaw:
            print(sweep(yaw, pitch, args.rim_below, args.pan_gap, args.pan_side, args.speed), flush=True)
        return
    for pitch in args.pitch:
        for press in args.press:
            print(run(pitch, press, args.step, args.rounded), flush=True)


if __name__ == "__main__":
    main()
