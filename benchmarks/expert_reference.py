"""The scripted experts on every task's official evaluation: the reference the README quotes.

Run: ``python benchmarks/expert_reference.py [--out results/expert] [--task T ...]
[--workers W] [--force]``. Each task's full record (every episode) is written to
``<out>/<Task>.json`` by the same code as ``bigym eval TASK --policy expert --json``; a
task whose record exists for this bigym version is not run again, and says so, so the
command resumes where it stopped; a record of another version is replaced. The record does
not know which version of the expert made it: after changing an expert, run its task with
``--force``. It ends by printing the Markdown table of all records in ``<out>``.
"""

from __future__ import annotations

import argparse
import os
import platform
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import bigym  # noqa: E402
from bigym.evaluation import EvaluationResult, evaluate  # noqa: E402
from bigym.experts import EXPERTS  # noqa: E402


def table(out: Path) -> str:
    lines = [
        "| task | expert success | 95% interval | mean episode | time limit | outcomes other than success | bigym |",
        "|---|---:|---:|---:|---:|---|---|",
    ]
    for task in EXPERTS:
        path = out / f"{task}.json"
        if not path.exists():
            continue
        result = EvaluationResult.load(path)
        s = result.summary
        low, high = s.interval
        others = ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in s.outcomes.items() if v and k != "success")
        official = "" if result.official else " (unofficial)"
        lines.append(
            f"| {task}{official} | {s.successes}/{s.episodes} | {100 * low:.0f}-{100 * high:.0f}% "
            f"| {s.mean_sim_time:.1f} s | {result.fingerprint['time_limit']:g} s | {others or '-'} "
            f"| {result.fingerprint['bigym_version']} |"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/expert"))
    parser.add_argument("--task", action="append", help="only these tasks (class names); default: every expert's")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--force", action="store_true", help="run again tasks that have a record of this version")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    unknown = sorted(set(args.task or ()) - set(EXPERTS))
    if unknown:
        parser.error(f"no expert for {', '.join(unknown)} (experts: {', '.join(EXPERTS)})")
    for task in args.task or list(EXPERTS):
        path = args.out / f"{task}.json"
        # a record of another bigym version (other physics) is run again
        current = path.exists() and EvaluationResult.load(path).fingerprint["bigym_version"] == bigym.__version__
        if current and not args.force:
            print(f"{task}: kept its record of bigym {bigym.__version__} ({path}; --force runs it again)", flush=True)
            continue
        result = evaluate("bigym.experts:make_expert", task, workers=args.workers)
        result.save(path)
        print(f"{task}: {result.summary.line()} ({result.wall_time:.0f} s wall)", flush=True)
    print(f"\nMachine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs\n")
    print(table(args.out))


if __name__ == "__main__":
    main()
