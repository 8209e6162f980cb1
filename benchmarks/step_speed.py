"""Env step throughput next to raw ``mj_step`` throughput on the same compiled model.

Run: ``python benchmarks/step_speed.py [--task ReachTargetMultiModal] [--seconds 3]``, or
``python benchmarks/step_speed.py --all`` for the no-camera cases (a) and (b) on all 40
tasks as a Markdown table (the one the README quotes).

Every ratio is measured within this one run, as the median ratio of short env and raw
blocks run one after the other, so that machine noise hits both alike:

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


def _batch(block, seconds: float) -> int:
    """How many calls of ``block`` take about ``seconds``."""
    n, elapsed = 1, 0.0
    while elapsed < 0.05:  # find a batch size that takes a measurable time
        start = time.perf_counter()
        block(n)
        elapsed = time.perf_counter() - start
        n *= 2
    return max(1, int(n / 2 * seconds / max(elapsed, 1e-9)))


def _rate(block, seconds: float, n: int | None = None) -> float:
    """Calls per second of ``block(n)`` measured over about ``seconds`` (or ``n`` calls)."""
    n = n or _batch(block, seconds)
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

    # Short blocks, interleaved, and the median of each adjacent pair's ratio: machine load
    # that drifts over seconds hits both sides of a pair alike.
    env_rates, raw_rates, ratios = [], [], []
    env_n, raw_n = _batch(env_block, seconds / rounds), _batch(raw_block, seconds / rounds)
    for _ in range(rounds):
        env_rates.append(_rate(env_block, seconds / rounds, env_n))
        raw_rates.append(_rate(raw_block, seconds / rounds, raw_n))
        ratios.append(env_rates[-1] * env.substeps / raw_rates[-1])
    env.close()
    return statistics.median(env_rates), statistics.median(raw_rates), env.substeps, statistics.median(ratios)


def measure_construction(cls, repeats: int = 3) -> float:
    cls().close()  # warm the mesh cache and imports
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        env = cls()
        times.append(time.perf_counter() - start)
        env.close()
    return statistics.median(times)


def all_tasks(seconds: float, rounds: int) -> None:
    """Cases (a) and (b) for every task: env steps/s, raw mj_step/s and their ratio."""
    import platform

    print(f"bigym {bigym.__version__}, MuJoCo {mujoco.__version__}, {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} CPUs; no cameras; ratios of rates measured in this run")
    print()
    print("| task | 500 Hz env steps/s | raw mj_step/s | ratio | 50 Hz env steps/s | physics/s | raw mj_step/s | ratio |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    worst = {500: 1.0, 50: 1.0}
    for name in bigym.TASKS:
        cls = task_class(name)
        cells = []
        for frequency in (500, 50):
            env_rate, raw_rate, substeps, ratio = measure_env(cls, frequency, ObservationConfig(), seconds, rounds)
            worst[frequency] = min(worst[frequency], ratio)
            if frequency == 500:
                cells += [f"{env_rate:.0f}", f"{raw_rate:.0f}", f"{ratio:.2f}"]
            else:
                cells += [f"{env_rate:.0f}", f"{env_rate * substeps:.0f}", f"{raw_rate:.0f}", f"{ratio:.2f}"]
        print(f"| {name} | " + " | ".join(cells) + " |", flush=True)
    print()
    print(f"lowest ratio: {worst[500]:.2f} at 500 Hz (target >= 0.85), {worst[50]:.2f} at 50 Hz (target >= 0.97)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--task", default="ReachTargetMultiModal", help="task to measure")
    parser.add_argument("--all", action="store_true", help="cases (a) and (b) on every task, as a Markdown table")
    parser.add_argument("--seconds", type=float, default=None, help="time per measurement (default 3, --all 1)")
    parser.add_argument("--rounds", type=int, default=9, help="interleaved rounds per measurement")
    args = parser.parse_args()
    if args.all:
        all_tasks(args.seconds or 1.0, args.rounds)
        return
    args.seconds = args.seconds or 3.0
    cls = task_class(args.task)
    cameras = ObservationConfig.robot_cameras(resolution=(84, 84), depth=True)

    rows = []
    for label, frequency, config in (
        ("(a) 500 Hz, no cameras", 500, ObservationConfig()),
        ("(b) 50 Hz, no cameras", 50, ObservationConfig()),
        ("(c) 50 Hz, 3 cameras 84x84 RGB+D", 50, cameras),
    ):
        env_rate, raw_rate, substeps, ratio = measure_env(cls, frequency, config, args.seconds, args.rounds)
        rows.append((label, env_rate, env_rate * substeps, raw_rate, ratio))
    construction = measure_construction(cls)

    print(f"bigym {bigym.__version__}, MuJoCo {mujoco.__version__}, task {cls.__name__}")
    print(f"{'case':36s} {'env steps/s':>12s} {'physics/s':>10s} {'raw mj_step/s':>14s} {'ratio':>6s}")
    for label, env_rate, physics_rate, raw_rate, ratio in rows:
        print(f"{label:36s} {env_rate:12.0f} {physics_rate:10.0f} {raw_rate:14.0f} {ratio:6.2f}")
    print(f"env construction (mesh cache warm): {construction:.2f} s")
    print("targets: (a) ratio >= 0.85; (b) >= 0.97; (c) >= 25 env steps/s; construction <= 2 s")


if __name__ == "__main__":
    main()
