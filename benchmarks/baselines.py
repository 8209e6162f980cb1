"""Train and evaluate the baselines, task by task: the results table of the README.

Run: ``python benchmarks/baselines.py --store STORE [--method bc --method act ...]
[--task DrawerTopOpen ...] [--work DIR] [--out results/baselines]``. For every method and
task it trains on 50 demos (``bigym train``), evaluates the checkpoint on the official 100
seeds (``bigym eval``) and writes ``<out>/<method>-<Task>.json`` (the evaluation record and
how it was trained). Checkpoints go to ``--work`` (default ``$BIGYM_HOME/baselines``); a
pair whose record exists is skipped and an interrupted training resumes, so the command can
be stopped and started again. It ends by printing the Markdown table of all records in
``<out>``, with how chunks past a demo's end were trained (masked, the default, or held
with ``--hold-end``, whose records are named ``*-held.json``) and which weights acted (the
last, or with ``--ema 0.999`` a moving average of them, records ``*-ema.json``).
``--all-tasks`` runs every task the store has demos for (on a GPU machine, set ``--steps``
higher and ``--workers`` to the CPU count).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

from bigym.baselines import checkpoint_factory, train  # noqa: E402
from bigym.demonstrations import DemoStore  # noqa: E402
from bigym.evaluation import EvaluationResult, evaluate  # noqa: E402
from bigym.observations import ObservationConfig  # noqa: E402

TASKS = (
    "ReachTargetMultiModal",
    "ReachTargetDual",
    "DrawerTopOpen",
    "DrawerTopClose",
    "DishwasherClose",
    "WallCupboardOpen",
)
#: training steps per method on a 2-core CPU (a few minutes to a quarter of an hour per task)
STEPS = {"bc": 20_000, "act": 10_000, "dp": 10_000}


def run(
    method: str, task: str, store, work: Path, out: Path, steps: int, cameras: tuple[str, ...], workers: int,
    device: str, hold_end: bool = False, ema: float = 0.0,
):  # fmt: skip
    name = f"{method}{'-pixels' if cameras else ''}-{task}{'-held' if hold_end else ''}{'-ema' if ema else ''}"
    record = out / f"{name}.json"
    if record.exists():
        return
    checkpoint_path = work / f"{name}.pt"
    started = time.perf_counter()
    checkpoint = train(
        method, task, checkpoint_path, demos=50, cameras=cameras, privileged=not cameras, store=store,
        settings={"steps": steps, "hold_end": hold_end, "ema": ema}, checkpoint_every=1000, workers=workers,
        device=device,
    )  # fmt: skip
    config = ObservationConfig.from_dict(checkpoint.observation_config)
    result = evaluate(checkpoint_factory(checkpoint_path), task, workers=workers, observation_config=config)
    data = {
        "method": method,
        "task": task,
        "training": {
            "demos": len(checkpoint.demos),
            "steps": checkpoint.step,
            "seconds": checkpoint.train_seconds,
            "final_loss": checkpoint.losses[-1][1],
            "config": checkpoint.config,
        },
        "machine": machine(device),
        "evaluation": result.to_dict(),
    }
    record.parent.mkdir(parents=True, exist_ok=True)
    record.write_text(json.dumps(data, indent=1) + "\n")
    print(f"{name}: {result.summary.line()} ({(time.perf_counter() - started) / 60:.1f} min)", flush=True)


def machine(device: str) -> str:
    """Where a result was trained: the CPU count, and the GPU when training ran on one."""
    import torch

    from bigym.baselines.train import resolve_device

    where = f"{platform.machine()}, {os.cpu_count()} CPUs"
    if resolve_device(device).type == "cuda":
        where += f", {torch.cuda.get_device_name(0)}"
    return where


def chunk_end(config: dict) -> str:
    """How the chunks that reach past a demo's end were trained (records from before the
    setting existed were masked)."""
    return "held" if config.get("hold_end", False) else "masked"


def acting_weights(config: dict) -> str:
    """Which weights acted: the last ones, or the moving average (records from before the
    setting existed acted with the last)."""
    return f"EMA {config['ema']:g}" if config.get("ema", 0.0) else "last"


def table(out: Path) -> str:
    lines = [
        "| task | method | observations | chunk end | weights | success | 95% interval | demos | steps | training |",
        "|---|---|---|---|---|---:|---:|---:|---:|---:|",
    ]
    for path in sorted(out.glob("*.json")):
        data = json.loads(path.read_text())
        result = EvaluationResult.from_dict(data["evaluation"])
        s, training = result.summary, data["training"]
        low, high = s.interval
        official = "" if result.official else " (unofficial)"
        track = result.fingerprint["track"]
        lines.append(
            f"| {data['task']} | {data['method']} | {track} | {chunk_end(training['config'])} "
            f"| {acting_weights(training['config'])} "
            f"| {s.successes}/{s.episodes}{official} "
            f"| {100 * low:.0f}-{100 * high:.0f}% | {training['demos']} | {training['steps']} "
            f"| {training['seconds'] / 60:.0f} min |"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--store", help="demo store with the dataset (default: the local store)")
    parser.add_argument("--method", action="append", choices=sorted(STEPS), help="default: bc, act, dp")
    parser.add_argument("--task", action="append", help=f"default: {', '.join(TASKS)}")
    parser.add_argument("--all-tasks", action="store_true", help="every task the store has demos for")
    parser.add_argument("--pixels", action="append", default=[], help="also train ACT from the 3 cameras on this task")
    parser.add_argument("--hold-end", action="store_true", help="train chunks past a demo's end to hold its last action")
    parser.add_argument("--ema", type=float, default=0.0, help="act with a moving average of the weights, this decay")
    parser.add_argument("--steps", type=int, help="training steps for every method (default: per method)")
    parser.add_argument("--work", type=Path, default=None, help="checkpoints (default: $BIGYM_HOME/baselines)")
    parser.add_argument("--out", type=Path, default=Path("results/baselines"))
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--device", default="auto", help="training device: auto (CUDA when there is a GPU), cpu, cuda")
    parser.add_argument("--table-only", action="store_true", help="print the table of the existing records")
    args = parser.parse_args()
    if not args.table_only:
        home = Path(os.environ.get("BIGYM_HOME", Path.home() / ".cache" / "bigym"))
        work = args.work or home / "baselines"
        store = DemoStore(args.store)
        tasks = args.task or list(TASKS)
        if args.all_tasks:
            tasks = sorted({entry.task for entry in store.entries()})
        for task in tasks:
            for method in args.method or ["bc", "act", "dp"]:
                steps = args.steps or STEPS[method]
                run(method, task, store, work, args.out, steps, (), args.workers, args.device, args.hold_end,
                    args.ema)
        for task in args.pixels:
            cameras = ("head", "left_wrist", "right_wrist")
            steps = args.steps or STEPS["act"]
            run("act", task, store, work, args.out, steps, cameras, args.workers, args.device, args.hold_end, args.ema)
    print(f"\nMachine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs\n")
    print(table(args.out))


if __name__ == "__main__":
    main()
