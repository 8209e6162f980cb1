"""Env step throughput next to raw ``mj_step`` throughput on the same compiled model.

Run: ``python benchmarks/step_speed.py [--task ReachTargetMultiModal] [--seconds 3]``, or
``python benchmarks/step_speed.py --all`` for the no-camera cases (a) and (b) on all 40
tasks as a Markdown table (the one the README quotes).

Every ratio is measured within this one run, from many short env and raw blocks run in
turn, both from the same state over the same physics steps on the same MjData (so only
env.step's own cost tells them apart), as the ratio of each side's fast blocks (machine
noise only ever adds time; the 10th percentile of each side's block times, and with
``--all`` the median of three such measurements):

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

BLOCK_SECONDS = 0.005  # short: many chances of a block that nothing else interrupts


def measure_env(cls, control_frequency: float, observation_config: ObservationConfig, seconds: float, rounds: int):
    """Env steps/s, raw mj_step/s, substeps and their ratio, from the fast end of ``rounds`` blocks each.

    Both blocks of a pair start from the same state and run the same physics steps (holding
    still, env.step's physics is mj_step's bit for bit): the ratio then measures env.step's
    own cost, not a difference between the states the two happen to be in (objects that
    are still settling cost the solver more than resting ones).
    """
    env = cls(observation_config=observation_config, control_frequency=control_frequency)
    env.reset(seed=0)
    action = np.zeros(env.action_space.shape, np.float32)  # hold still: no terminations
    for _ in range(max(1, round(0.2 * env.control_frequency))):  # let the start pose settle a little
        env.step(action)
    model, substeps = env.model, env.substeps
    start = mujoco.MjData(model)
    mujoco.mj_copyData(start, model, env.data)

    def env_block(n: int) -> float:
        mujoco.mj_copyData(env.data, model, start)  # in place: the env's views stay valid
        begin = time.perf_counter()
        for _ in range(n):
            env.step(action)
        return time.perf_counter() - begin

    def raw_block(n: int) -> float:
        # on the env's own MjData: the same memory, so its layout cannot favour either side
        data = env.data
        mujoco.mj_copyData(data, model, start)
        begin = time.perf_counter()
        for _ in range(n * substeps):
            mujoco.mj_step(model, data)
        return time.perf_counter() - begin

    n = 1
    while env_block(n) < BLOCK_SECONDS:
        n *= 2
    rounds = max(rounds, round(seconds / (2 * env_block(n))))
    # Many short blocks in turn (the order alternating, so neither side always runs first)
    # and each side's fast end: on a shared machine interference only ever adds time, and a
    # short block has a fair chance to run without any.
    env_times, raw_times = [], []
    for k in range(rounds):
        if k % 2:
            raw_times.append(raw_block(n))
            env_times.append(env_block(n))
        else:
            env_times.append(env_block(n))
            raw_times.append(raw_block(n))
    env.close()
    env_time, raw_time = _fast(env_times), _fast(raw_times)
    return n / env_time, n * substeps / raw_time, substeps, raw_time / env_time


def _fast(times: list[float]) -> float:
    """The 10th percentile: near the fastest, but not one lucky block."""
    return statistics.quantiles(times, n=10)[0]


def measure_env_repeated(cls, control_frequency, observation_config, seconds: float, rounds: int, repeats: int):
    """:func:`measure_env` ``repeats`` times (a fresh env each), the median of each figure."""
    runs = [measure_env(cls, control_frequency, observation_config, seconds, rounds) for _ in range(repeats)]
    env_rate, raw_rate, substeps, ratio = (statistics.median(column) for column in zip(*runs))
    return env_rate, raw_rate, int(substeps), ratio


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
            env_rate, raw_rate, substeps, ratio = measure_env_repeated(
                cls, frequency, ObservationConfig(), seconds, rounds, repeats=3
            )
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
    parser.add_argument("--seconds", type=float, default=None, help="time per measurement (default 3; --all 1, three times)")
    parser.add_argument("--rounds", type=int, default=30, help="at least this many blocks per side (more if --seconds allows)")
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
