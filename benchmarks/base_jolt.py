"""How hard the floating base jolts when its position targets come at a low control rate.

Run: ``python benchmarks/base_jolt.py [--distance 1.0] [--seconds 4.0]``.

The base walks ``--distance`` metres forward along a minimum-jerk path in ``--seconds``
(peak speed 1.875 x the mean), its target updated at each control rate, as a policy at
that rate or a demo replayed at that rate drives it. The physics runs at 500 Hz; each row
prints the base's peak acceleration along the walk (what a carried object must follow),
and how many times the same walk's at 500 Hz it is. Rows:

* ``bigym`` - ``env.step`` itself, the shipped base servo (kp 1e5, critically damped);
  since bigym 0.3.0 it ramps each new target over the control step's physics steps;
* ``held`` - the same servo with each new target held over the control step (a step,
  what bigym 0.2.0 did);
* ``kp 1e4 held`` - the original BiGym's stiffness (critically damped), targets held.

Why it matters: the experts' box carry (``bigym/experts/boxes.py``) holds a 5 kg box by
squeezing it between the hands; the jolts of held targets at 20 Hz shook it out of the
hands where the 500 Hz recording held it.
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


def _path(start: float, distance: float, seconds: float, k: int) -> float:
    progress = float(minimum_jerk_profile(min(k / PHYSICS_RATE / seconds, 1.0)))
    return start + distance * progress


def _base_env() -> ReachTargetSingle:
    env = ReachTargetSingle(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=PHYSICS_RATE
    )
    env.reset(seed=0)
    return env


def walk_env_step(rate: float, distance: float, seconds: float) -> float:
    """Peak forward acceleration (m/s^2) with ``env.step`` at ``rate`` Hz driving the base,
    read after every physics step inside it."""
    env = ReachTargetSingle(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=rate
    )
    peak = 0.0
    original = mujoco.mj_step2
    try:
        obs, _ = env.reset(seed=0)
        data = env.data
        dof = env.model.joint("pelvis_x").dofadr[0]
        actuator = env.model.actuator("pelvis_x").id

        def watched(model, data_):
            nonlocal peak
            original(model, data_)
            peak = max(peak, abs(float(data_.qacc[dof])))

        start = float(data.ctrl[actuator])
        substeps = env.substeps
        action = np.zeros(env.action_space.shape)
        for arm in ("left_arm", "right_arm"):  # the arms keep their start targets
            action[env.action_layout.group(arm)] = data.ctrl[env.action_layout.group(arm)]
        mujoco.mj_step2 = watched
        target = start
        for step in range(round((seconds + 1.0) * rate)):
            nxt = _path(start, distance, seconds, (step + 1) * substeps)
            action[env.action_layout["base_dx"]] = nxt - target
            target = nxt
            env.step(action)
        return peak
    finally:
        mujoco.mj_step2 = original
        env.close()


def walk_held(rate: float, distance: float, seconds: float, kp: float | None) -> float:
    """Peak forward acceleration (m/s^2) with each new target held over the control step."""
    env = _base_env()
    try:
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
        peak = 0.0
        for k in range(round((seconds + 1.0) * PHYSICS_RATE)):
            if k % substeps == 0:  # the target at the control step's end, from its start
                data.ctrl[actuator] = _path(start, distance, seconds, k + substeps)
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
    print(f"{'servo':<13}" + "".join(f"{f'{r:g} Hz':>16}" for r in RATES))
    rows = {
        "bigym": lambda rate: walk_env_step(rate, args.distance, args.seconds),
        "held": lambda rate: walk_held(rate, args.distance, args.seconds, None),
        "kp 1e4 held": lambda rate: walk_held(rate, args.distance, args.seconds, 1.0e4),
    }
    for name, walk in rows.items():
        peaks = [walk(rate) for rate in RATES]
        cells = "".join(f"{p:8.1f} ({p / peaks[0]:4.0f}x)" for p in peaks)
        print(f"{name:<13}{cells}   peak m/s^2 (x the 500 Hz walk)")


if __name__ == "__main__":
    main()
