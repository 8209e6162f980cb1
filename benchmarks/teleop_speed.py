"""Can teleoperation run in real time here? Costs of one session's parts, in one run.

Run: ``python benchmarks/teleop_speed.py [--task ReachTargetSingle] [--seconds 4]``.

Prints, for a keyboard session with a hand and the base moving all the time:

* control: simulated seconds per wall-clock second of ``session.advance`` (device command,
  controller with the whole-body IK at 100 Hz, env step at 500 Hz, recording), i.e. how
  many times faster than real time the robot can be driven;
* views: the browser front end's two views (scene 480x360 and head camera 320x240,
  rendered and JPEG-encoded), frames per second;
* the share of one core a live session takes at the browser's 15 frames per second;
* keep: seconds to verify a demo (replays from its file at 500, 50, 25, 20 Hz), per
  second of demo.

These 2-core machines are shared and noisy: compare numbers within one run.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

os.environ.setdefault("MUJOCO_GL", "egl")

from bigym.demonstrations import DemoStore
from bigym.demonstrations.player import VERIFY_RATES, verification_failure
from bigym.teleop import TeleopSession, make_devices
from bigym.teleop.browser.server import ViewRenderer

FRAME_RATE = 15.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--task", default="ReachTargetSingle")
    parser.add_argument("--seconds", type=float, default=4.0, help="simulated seconds to drive")
    args = parser.parse_args()
    folder = tempfile.mkdtemp()
    session = TeleopSession(args.task, make_devices("keyboard"), DemoStore(folder, on_demand=False), seed=0,
                            aside=folder, auto_keep=False)  # fmt: skip
    try:
        steps = round(args.seconds * session.env.control_frequency)
        for code in ("KeyW", "KeyR", "ArrowLeft"):
            session.handle({"type": "keydown", "code": code})
        session.advance(10)  # warm up
        start = time.perf_counter()
        session.advance(steps)
        control = time.perf_counter() - start
        realtime = args.seconds / control
        views = ViewRenderer(session.env)
        views.frames()
        start = time.perf_counter()
        frames = 30
        for _ in range(frames):
            views.frames()
        frame_time = (time.perf_counter() - start) / frames
        views.close()
        demo = session.recorder.to_demo(keep=True)
        start = time.perf_counter()
        verification_failure(demo, VERIFY_RATES)
        verify = (time.perf_counter() - start) / (demo.num_steps / session.env.control_frequency)
        load = 1.0 / realtime + FRAME_RATE * frame_time
        print(f"task {session.task}, {args.seconds:g} s simulated, machine: {os.cpu_count()} cores")
        print(f"control (device + IK + step + record): {realtime:.1f}x real time")
        print(
            f"browser views (render + JPEG, 2 views): {1.0 / frame_time:.1f} frames/s ({frame_time * 1e3:.1f} ms each)"
        )
        print(f"a live browser session at {FRAME_RATE:g} frames/s: {load:.0%} of one core")
        print(f"keeping a demo (verify at 500/50/25/20 Hz): {verify:.2f} s per demo-second")
    finally:
        session.close()


if __name__ == "__main__":
    main()
