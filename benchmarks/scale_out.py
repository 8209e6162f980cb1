"""Scale-out cost figures: one process, the process pool and Ray (local), in one run.

Run: ``python benchmarks/scale_out.py [--workers 2] [--demos 6] [--episodes 12]
[--replay-task DrawerTopOpen] [--eval-task DrawerTopOpen]`` (needs the ``ray`` extra).

Prints, measured in this one run on the same jobs:

* demo replay with the three robot cameras (84x84 RGB + depth) at 50 Hz: demo steps per
  second on one process, on a spawn process pool of ``--workers`` and on Ray (a local
  instance with ``--workers`` CPUs), each as a user calls ``replay_many`` (worker start-up
  and env builds included), and that the three give the same observations;
* evaluation episodes (the expert on the first ``--episodes`` official seeds): episodes per
  second on the same three, and that their records are equal;
* Ray's start-up: ``ray.init`` of the local instance, and a first trivial task's round trip;
* the shipped dataset's size per task: the lightweight files (the shipped manifest), and the
  raw arrays a replay to the official observations holds (proprioception + object state +
  the three robot cameras RGB-D at 84x84, 50 Hz; from the observation space, checked
  against one real replay), for the demos as recorded (the replayed episodes end at the
  first success, so a little shorter).

These 2-core machines are shared and noisy: compare numbers within one run.
"""

from __future__ import annotations

import argparse
import json
import os
import time

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np  # noqa: E402

from bigym.demonstrations import Demo, replay_many  # noqa: E402
from bigym.evaluation import evaluate  # noqa: E402
from bigym.experts.dataset import shipped_manifest_path  # noqa: E402
from bigym.experts.generate import record_attempt  # noqa: E402
from bigym.observations import ObservationConfig  # noqa: E402

OFFICIAL_RATE = 50.0


def official_pixels() -> ObservationConfig:
    return ObservationConfig.robot_cameras((84, 84), True, privileged_information=True)


def replay_rates(demos, workers: int) -> list[tuple[str, float]]:
    config = official_pixels()
    steps = sum(len(d) for d in demos)
    rows, reference = [], None
    for name, options in (("1 process", dict(workers=1, backend="serial")),
                          (f"process pool of {workers}", dict(workers=workers, backend="process")),
                          (f"Ray, local, {workers} CPUs", dict(workers=workers, backend="ray"))):  # fmt: skip
        start = time.perf_counter()
        results = replay_many(demos, config, OFFICIAL_RATE, progress=False, **options)
        seconds = time.perf_counter() - start
        frames = [r.observations for r in results]
        if reference is None:
            reference = frames
        elif not all(all(np.array_equal(a[k], b[k]) for k in a) for a, b in zip(reference, frames)):
            raise SystemExit(f"{name}: the replayed observations differ from one process's")
        rows.append((name, steps / seconds))
    return rows


def evaluation_rates(task: str, episodes: int, workers: int) -> list[tuple[str, float]]:
    rows, reference = [], None
    for name, options in (("1 process", dict(workers=1)),
                          (f"process pool of {workers}", dict(workers=workers)),
                          (f"Ray, local, {workers} CPUs", dict(workers=workers, backend="ray"))):  # fmt: skip
        result = evaluate("bigym.experts:make_expert", task, episodes=episodes, **options)
        records = [r.comparable() for r in result.episodes]
        reference = reference or records
        if records != reference:
            raise SystemExit(f"{name}: the episode records differ from one process's")
        rows.append((name, episodes / result.wall_time))
    return rows


def ray_start_up(workers: int) -> tuple[float, float]:
    import ray

    start = time.perf_counter()
    ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False)
    initialised = time.perf_counter() - start
    start = time.perf_counter()
    ray.get(ray.remote(lambda: 1).remote())
    return initialised, time.perf_counter() - start


def bytes_per_step(task: str) -> int:
    """Raw bytes of one step of the official pixel observations (all keys, as replayed)."""
    from bigym.demonstrations.player import resolve_task

    env = resolve_task(task)(observation_config=official_pixels(), control_frequency=OFFICIAL_RATE)
    size = sum(int(np.prod(space.shape)) * space.dtype.itemsize for space in env.observation_space.values())
    env.close()
    return size


def dataset_sizes(check_demo) -> list[tuple[str, int, float, float, float]]:
    demos = json.loads(shipped_manifest_path().read_text())["demos"]
    tasks = sorted({d["task"] for d in demos})
    replayed = replay_many([check_demo], official_pixels(), OFFICIAL_RATE, progress=False)[0]
    real = sum(v.nbytes for v in replayed.observations.values()) / len(replayed.observations[next(iter(replayed.observations))])
    predicted = bytes_per_step(check_demo.metadata.task)
    if abs(real - predicted) > 1e-6 * predicted:
        raise SystemExit(f"a replay holds {real:.0f} bytes per step, the observation space says {predicted}")
    rows = []
    for task in tasks:
        of_task = [d for d in demos if d["task"] == task]
        seconds = sum(d["num_steps"] / d["frequency"] for d in of_task)
        light = sum(d["size"] for d in of_task)
        replayed_bytes = bytes_per_step(task) * seconds * OFFICIAL_RATE
        rows.append((task, len(of_task), light / 1e6, replayed_bytes / 1e9, seconds))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--demos", type=int, default=6)
    parser.add_argument("--episodes", type=int, default=12)
    parser.add_argument("--replay-task", default="DrawerTopOpen")
    parser.add_argument("--eval-task", default="DrawerTopOpen")
    args = parser.parse_args()
    print(f"{os.cpu_count()} CPUs; {args.workers} workers per backend\n")

    initialised, round_trip = ray_start_up(args.workers)
    print(f"Ray start-up: ray.init (local, {args.workers} CPUs) {initialised:.1f} s; first task round trip "
          f"{round_trip:.2f} s\n")  # fmt: skip

    demos = [Demo.from_bytes(record_attempt(args.replay_task, 0, seed, verify=False).data) for seed in range(args.demos)]
    print(f"demo replay, three robot cameras 84x84 RGB-D at 50 Hz ({args.demos} {args.replay_task} demos, "
          f"{sum(len(d) for d in demos)} demo steps; start-up included)")  # fmt: skip
    print("| backend | demo steps/s | vs 1 process |\n|---|---:|---:|")
    rows = replay_rates(demos, args.workers)
    for name, rate in rows:
        print(f"| {name} | {rate:.0f} | {rate / rows[0][1]:.2f}x |")

    print(f"\nevaluation, expert on {args.eval_task}, first {args.episodes} official seeds (start-up included)")
    print("| backend | episodes/s | vs 1 process |\n|---|---:|---:|")
    rows = evaluation_rates(args.eval_task, args.episodes, args.workers)
    for name, rate in rows:
        print(f"| {name} | {rate:.2f} | {rate / rows[0][1]:.2f}x |")
    print("(the observations and the episode records were equal across the three)")

    print("\ndataset v2 per task: lightweight files, and the raw arrays of a replay to the official observations")
    print("| task | demos | demo time (min) | lightweight (MB) | replayed, 3 cameras RGB-D 84x84, 50 Hz (GB) | ratio |")
    print("|---|---:|---:|---:|---:|---:|")
    sizes = dataset_sizes(demos[0])
    for task, count, light, replayed, seconds in sizes:
        print(f"| {task} | {count} | {seconds / 60:.1f} | {light:.1f} | {replayed:.2f} | {replayed * 1e3 / light:.0f}x |")
    light, replayed = sum(r[2] for r in sizes), sum(r[3] for r in sizes)
    print(f"| all | {sum(r[1] for r in sizes)} | {sum(r[4] for r in sizes) / 60:.0f} | {light:.0f} | {replayed:.1f} "
          f"| {replayed * 1e3 / light:.0f}x |")  # fmt: skip


if __name__ == "__main__":
    main()
