"""Env step throughput next to raw ``mj_step`` throughput on the same compiled model.

Run: ``python benchmarks/step_speed.py [--task ReachTargetMultiModal] [--seconds 3]``.

Every ratio is measured within this one run, with env and raw blocks interleaved so
that machine noise hits both alike:

* (a) 500 Hz control, no cameras: env.step/s over mj_step/s (one physics step each);
* (b) 50 Hz control, no cameras: physics steps/s through env.step over raw mj_step/s;
* (c) 50 Hz with the three robot cameras at 84x84 RGB + depth: env steps/s;
* env construction time with the low-poly mesh cache warm.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

import bigym  # noqa: E402
from bigym.cli import task_class  # noqa: E402
from bigym.observations import ObservationConfig  # noqa: E402


def _rate(block, seconds: float) -> float:
    """Calls per second of ``block(n)`` measured over about ``seconds``."""
    n, elapsed = 1, 0.0
    while elapsed < 0.05:  # find a batch size that takes a measurable time
        start = time.perf_counter()
        block(n)
        elapsed = time.perf_counter() - start
        n *= 2
    n = max(1, int(n / 2 * seconds / max(elapsed, 1e-9)))
    start = time.perf_counter()
    block(n)
    return n / (time.perf_counter() - start)


def measure_env(cls, control_frequency: float, observation_config: ObservationConfig, seconds: float, rounds: int):
    env = cls(observation_config=observation_config, control_frequency=control_frequency)
    env.reset(seed=0)
    action = np.zeros(env.action_space.shape, np.float32)  # hold still: no terminations
    raw_data = mujoco.MjData(env.model)
    mujoco.mj_copyData(raw_data, env.model, env.data)
    model = env.model

    def env_block(n: int) -> None:
        for _ in range(n):
            env.step(action)

    def raw_block(n: int) -> None:
        for _ in range(n):
            mujoco.mj_step(model, raw_data)

    env_rates, raw_rates = [], []
    for _ in range(rounds):  # interleave: both see the same machine load
        env_rates.append(_rate(env_block, seconds / rounds))
        raw_rates.append(_rate(raw_block, seconds / rounds))
    env.close()
    return statistics.median(env_rates), statistics.median(raw_rates), env.substeps


def measure_construction(cls, repeats: int = 3) -> float:
    cls().close()  # warm the mesh cache and imports
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        env = cls()
        times.append(time.perf_counter() - start)
        env.close()
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--task", default="ReachTargetMultiModal", help="task to measure")
    parser.add_argument("--seconds", type=float, default=3.0, help="time per measurement")
    parser.add_argument("--rounds", type=int, default=3, help="interleaved rounds per measurement")
    args = parser.parse_args()
    cls = task_class(args.task)
    cameras = ObservationConfig.robot_cameras(resolution=(84, 84), depth=True)

    rows = []
    for label, frequency, config in (
        ("(a) 500 Hz, no cameras", 500, ObservationConfig()),
        ("(b) 50 Hz, no cameras", 50, ObservationConfig()),
        ("(c) 50 Hz, 3 cameras 84x84 RGB+D", 50, cameras),
    ):
        env_rate, raw_rate, substeps = measure_env(cls, frequency, config, args.seconds, args.rounds)
        physics_rate = env_rate * substeps
        rows.append((label, env_rate, physics_rate, raw_rate, physics_rate / raw_rate))
    construction = measure_construction(cls)

    print(f"bigym {bigym.__version__}, MuJoCo {mujoco.__version__}, task {cls.__name__}")
    print(f"{'case':36s} {'env steps/s':>12s} {'physics/s':>10s} {'raw mj_step/s':>14s} {'ratio':>6s}")
    for label, env_rate, physics_rate, raw_rate, ratio in rows:
        print(f"{label:36s} {env_rate:12.0f} {physics_rate:10.0f} {raw_rate:14.0f} {ratio:6.2f}")
    print(f"env construction (mesh cache warm): {construction:.2f} s")
    print("targets: (a) ratio >= 0.8; (c) >= 25 env steps/s; construction <= 2 s")


if __name__ == "__main__":
    main()
