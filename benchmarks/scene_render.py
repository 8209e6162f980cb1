"""Rendering cost of the kitchen scenes with the robot and its three cameras.

Run: ``python benchmarks/scene_render.py [--scene kitchen_full] [--seconds 3]``.

Prints, per scene, env steps/s at 50 Hz with the three robot cameras at 84x84 RGB + depth
next to the same env without cameras (both measured in this run), so the ratio shows
what the cameras cost. Target (issue 3): the fullest scene >= 20 env steps/s on a 2-core CPU.
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np  # noqa: E402

from bigym.env import BiGymEnv  # noqa: E402
from bigym.observations import ObservationConfig  # noqa: E402
from bigym.scenes import scene_names  # noqa: E402


def scene_env(scene: str) -> type[BiGymEnv]:
    """A task-less env class holding ``scene`` (the robot idles at the origin)."""
    return type(f"Idle_{scene}", (BiGymEnv,), {"scene_name": scene})


def steps_per_second(env: BiGymEnv, seconds: float) -> float:
    env.reset(seed=0)
    action = np.zeros(env.action_space.shape, np.float32)
    env.step(action)
    count, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        env.step(action)
        count += 1
    return count / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", action="append", help="scene(s) to measure (default: kitchen_full)")
    parser.add_argument("--all", action="store_true", help="measure every scene")
    parser.add_argument("--seconds", type=float, default=3.0)
    args = parser.parse_args()
    scenes = scene_names() if args.all else (args.scene or ["kitchen_full"])
    cameras = ObservationConfig.robot_cameras(resolution=(84, 84), depth=True)
    print(f"{'scene':36s} {'ngeom':>6s} {'no cams steps/s':>16s} {'3 cams steps/s':>15s} {'ratio':>6s}")
    for scene in scenes:
        cls = scene_env(scene)
        plain = cls(control_frequency=50)
        with_cameras = cls(control_frequency=50, observation_config=cameras)
        ngeom = plain.model.ngeom
        rate_plain = steps_per_second(plain, args.seconds)
        rate_cameras = steps_per_second(with_cameras, args.seconds)
        plain.close()
        with_cameras.close()
        print(f"{scene:36s} {ngeom:6d} {rate_plain:16.0f} {rate_cameras:15.1f} {rate_cameras / rate_plain:6.3f}")
    print("target: kitchen_full >= 20 env steps/s with 3 cameras")


if __name__ == "__main__":
    main()
