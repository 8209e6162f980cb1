"""Evaluation throughput: episodes per second on 1 worker, on W workers, and in vector envs.

Run: ``python benchmarks/eval_throughput.py [--task DrawerTopOpen] [--policy expert]
[--episodes 40] [--workers W]``. Every row runs the same seeds (the first ``--episodes`` of
the official block) with the same policy, in this one run, so the ratios compare like with
like; the wall time includes starting the workers, as a user sees it. The goal: W workers
give at least 0.8 W times one worker's episodes per second.
"""

from __future__ import annotations

import argparse
import os

os.environ.setdefault("MUJOCO_GL", "egl")

from bigym.cli.evaluate import BUILT_IN_POLICIES  # noqa: E402
from bigym.evaluation import evaluate  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--task", default="DrawerTopOpen")
    parser.add_argument("--policy", default="expert", help="a built-in policy name or module:factory")
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args()
    spec = BUILT_IN_POLICIES.get(args.policy, args.policy)
    cases = [("1 worker", dict(workers=1)), (f"{args.workers} workers", dict(workers=args.workers))]
    cases.append(
        (f"1 worker, sync vector env of {args.workers}", dict(workers=1, vector="sync", envs_per_worker=args.workers))
    )
    if args.policy not in ("expert", "hold", "reach"):  # those read the simulator: not in an async vector env
        cases.append(
            (
                f"1 worker, async vector env of {args.workers}",
                dict(workers=1, vector="async", envs_per_worker=args.workers),
            )
        )
    print(f"{args.task}, policy {spec}, {args.episodes} episodes, {os.cpu_count()} CPUs")
    print("| case | wall time (s) | episodes/s | vs 1 worker | per process vs 1 worker |")
    print("|---|---:|---:|---:|---:|")
    reference, first_records = None, None
    for name, options in cases:
        result = evaluate(spec, args.task, episodes=args.episodes, **options)
        records = [r.comparable() for r in result.episodes]
        first_records = first_records or records
        if records != first_records:
            raise SystemExit(f"{name}: the episode records differ from the first case's")
        rate = args.episodes / result.wall_time
        reference = reference or rate
        # processes stepping envs: the workers, or an async vector env's sub-processes
        processes = options["envs_per_worker"] if options.get("vector") == "async" else options["workers"]
        print(
            f"| {name} | {result.wall_time:.1f} | {rate:.2f} | {rate / reference:.2f}x "
            f"| {rate / reference / processes:.2f} |"
        )
    print(f"success: {result.summary.line()}")


if __name__ == "__main__":
    main()
