"""How hard the floating base jolts when its position targets come at a low control rate.

Run: ``python benchmarks/base_jolt.py [--distance 1.0] [--seconds 4.0]``.

The base walks ``--distance`` metres forward along a minimum-jerk path in ``--seconds``
(peak speed 1.875 x the mean), its target updated at each control rate and held in
between, as a policy at that rate or a demo replayed at that rate drives it. The physics
runs at 500 Hz; each row prints the base's peak acceleration along the walk (what a
carried object must follow), and how many times the same walk's at 500 Hz it is. Rows:

* ``bigym`` - the shipped base servo (kp 1e5, critically damped);
* ``kp 1e4`` - the original BiGym's stiffness (critically damped);
* ``ramped`` - the shipped servo with each new target ramped over the control step
  (a first-order hold instead of a step).

Why it matters: the experts' box carry (``bigym/experts/boxes.py``) holds a 5 kg box by
squeezing it between the hands; the jolts of a 20 Hz replay shake it out of the hands
where the 500 Hz recording holds it.
"""

from __future__ import annotations

import argparse
import os

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

from bigym.action_modes import JointPositionActionMode  # noqa: E402
from bigym.envs.reach_target import ReachTargetSingle  # noqa: E402
from bigym.experts.motion import minimum_jerk_profile  # noqa: E402

PHYSICS_RATE = 500.0
RATES = (500.0, 50.0, 25.0, 20.0)


def walk(rate: float, distance: float, seconds: float, kp: float | None, ramped: bool) -> float:
    """The base's peak forward acceleration (m/s^2) on the walk, targets at ``rate`` Hz."""
    env = ReachTargetSingle(action_mode=JointPositionActionMode(floating_base=True, absolute=True))
    try:
        env.reset(seed=0)
        model, data = env.model, env.data
        actuator = model.actuator("pelvis_x").id
        dof = model.joint("pelvis_x").dofadr[0]
        if kp is not None:  # critically damped at the base's mass, as the shipped servo
            mass = float(model.body_subtreemass[model.jnt_bodyid[model.joint("pelvis_x").id]])  # all it carries
            model.actuator_gainprm[actuator, 0] = kp
            model.actuator_biasprm[actuator, 1] = -kp
            model.actuator_biasprm[actuator, 2] = -2.0 * np.sqrt(kp * mass)
        start = float(data.ctrl[actuator])
        substeps = round(PHYSICS_RATE / rate)
        steps = round((seconds + 1.0) * PHYSICS_RATE)
        peak = 0.0
        previous = current = start  # the last control step's target and this one's
        for k in range(steps):
            if k % substeps == 0:
                progress = float(minimum_jerk_profile(min(k / PHYSICS_RATE / seconds, 1.0)))
                previous, current = current, start + distance * progress
            fraction = (k % substeps + 1) / substeps if ramped else 1.0
            data.ctrl[actuator] = previous + fraction * (current - previous)
            mujoco.mj_step(model, data)
            peak = max(peak, abs(float(data.qacc[dof])))
        return peak
    finally:
        env.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--distance", type=float, default=1.0)
    parser.add_argument("--seconds", type=float, default=4.0)
    args = parser.parse_args()
    mean = args.distance / args.seconds
    print(f"base walk: {args.distance:g} m in {args.seconds:g} s (peak speed {1.875 * mean:.2f} m/s)")
    print(f"{'servo':<10}" + "".join(f"{f'{r:g} Hz':>16}" for r in RATES))
    for name, kp, ramped in (("bigym", None, False), ("kp 1e4", 1.0e4, False), ("ramped", None, True)):
        peaks = [walk(rate, args.distance, args.seconds, kp, ramped) for rate in RATES]
        cells = "".join(f"{p:8.1f} ({p / peaks[0]:4.0f}x)" for p in peaks)
        print(f"{name:<10}{cells}   peak m/s^2 (x the 500 Hz walk)")


if __name__ == "__main__":
    main()
