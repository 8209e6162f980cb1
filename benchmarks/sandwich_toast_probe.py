"""Can the spatula's blade slide under the raw ``SandwichToast`` sandwich held by a stop?

Run: ``python benchmarks/sandwich_toast_probe.py``.

``SandwichToast`` has no expert yet (see the docstring of ``bigym/experts/sandwich.py``):
on the board, a blade pushed at the raw sandwich (box collider, square edges; the blade
grips it at 0.8, the board at 0.3) shoves it along. A stop on its far side, as the pan's
far wall is for the rounded sandwich of ``SandwichRemove``, was the untried remedy. This
probe tries it with nothing but the two props on a flat floor: the sandwich stands against
a step (a box ``--step`` m high), and the spatula, welded to a mocap "hand" (a soft weld,
as an arm's grip is), pushes its blade's tip along the floor at ``--pitch`` degrees, pressed
``--press`` m into it, up to the step; then lifts 6 cm. Each row: where the blade's tip
stopped, the sandwich's middle after the push and after the lift, and whether it rode up.

Measured on 2026-12-06 (x86_64, 2 CPUs), the defaults: at 5-30 degrees and 0-2 mm of press
the tip stops at the sandwich's bottom edge (x = -0.121; its face is at -0.123), the
sandwich does not move, and the lift leaves it on the floor (at 5 degrees the blade had
been forced into its edge, and the lift flings it away: an interpenetration, not physics).
A flush square edge gives the blade nothing to slide under, stop or not. ``--rounded`` (the
pan tasks' collider), 12 degrees: the blade gets under, and the sandwich rides up over the
1 cm step (the pan's 4.5 cm wall holds it in ``SandwichRemove``). So the raw sandwich needs
a tilt first: its near edge raised, or the board tipped so that it slides onto a blade held
still.
"""

from __future__ import annotations

import argparse
import os

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

from bigym.experts.sandwich import TIP  # noqa: E402
from bigym.props import Sandwich, Spatula  # noqa: E402
from bigym.world import add_world  # noqa: E402

#: how soft the hand's weld is (s): about what the arm's grip and stance give
WELD_TIMECONST = 0.01
PUSH_SPEED = 0.04


def blade_rotation(pitch: float) -> np.ndarray:
    """The spatula pointing along +x, the blade ``pitch`` rad below the horizontal."""
    y = np.array([np.cos(pitch), 0.0, -np.sin(pitch)])
    x = np.array([0.0, 1.0, 0.0])
    return np.column_stack([x, y, np.cross(x, y)])


def run(pitch_deg: float, press: float, step: float, rounded: bool) -> str:
    spec = mujoco.MjSpec()
    add_world(spec)
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.2, 0.3, step / 2], pos=[0.2, 0.0, step / 2])
    sandwich, spatula = Sandwich("sandwich", rounded=rounded), Spatula("spatula")
    for prop in (sandwich, spatula):
        prop.attach_to(spec.worldbody)
    spec.worldbody.add_body(name="hand", mocap=True)
    weld = spec.add_equality()
    weld.type, weld.objtype = mujoco.mjtEq.mjEQ_WELD, mujoco.mjtObj.mjOBJ_BODY
    weld.name1, weld.name2 = "hand", spatula.root_body_name
    weld.solref = [WELD_TIMECONST, 1.0]
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pitch", type=float, nargs="+", default=[5.0, 12.0, 20.0, 30.0], help="degrees, tip down")
    parser.add_argument("--press", type=float, nargs="+", default=[0.0, 0.002], help="m into the floor")
    parser.add_argument("--step", type=float, default=0.01, help="the stop's height (m): the hob's edge is 1 cm")
    parser.add_argument("--rounded", action="store_true", help="the rounded collider of the pan tasks instead")
    args = parser.parse_args()
    for pitch in args.pitch:
        for press in args.press:
            print(run(pitch, press, args.step, args.rounded), flush=True)


if __name__ == "__main__":
    main()
