"""Train and evaluate the baselines, task by task: the results table of the README.

Run: ``python benchmarks/baselines.py --store STORE [--method bc --method act ...]
[--task DrawerTopOpen ...] [--work DIR] [--out results/baselines]``. For every method and
task it trains on 50 demos (``bigym train``), evaluates the checkpoint on the official 100
seeds (``bigym eval``) and writes ``<out>/<method>-<Task>.json`` (the evaluation record and
how it was trained). Checkpoints go to ``--work`` (default ``$BIGYM_HOME/baselines``); a
pair whose record exists is skipped and an interrupted training resumes, so the command can
be stopped and started again. ``--set name=value`` (repeatable) changes a training setting
of every method run, as ``bigym train --set`` does; its records are named after the settings
given (``act-DrawerTopOpen-dropout=0-ema=0.json``), so runs of other settings sit beside the
defaults'. It ends by printing the Markdown table of all records in ``<out>``, whose
"settings" column lists where a record's training differed from its method's defaults of
today (records from before a setting existed are read as they ran: see
``bigym.baselines.checkpoint.LEGACY_SETTINGS``). ``--ensemble-decay D`` evaluates with
another temporal ensembling (as ``bigym eval --ensemble-decay``): the same checkpoint, a
record named ``...-ensemble_decay=D.json``. ``--all-tasks`` runs every task the store
has demos for (on a GPU machine, set ``--steps`` higher and ``--workers`` to the CPU count).
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
from bigym.baselines.checkpoint import with_legacy_settings  # noqa: E402
from bigym.baselines.methods import config_dict, make_config  # noqa: E402
from bigym.baselines.policy import ENSEMBLE_DECAY  # noqa: E402
from bigym.cli.train import parse_settings  # noqa: E402
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


def record_name(method: str, task: str, cameras: tuple[str, ...], settings: dict) -> str:
    """``act-DrawerTopOpen``, ``act-pixels-DrawerTopClose``, ``act-DrawerTopOpen-dropout=0-ema=0``."""
    given = "".join(f"-{name}={json.dumps(value)}" for name, value in sorted(settings.items()))
    return f"{method}{'-pixels' if cameras else ''}-{task}{given}"


def acting_suffix(ensemble_decay: float) -> str:
    """``-ensemble_decay=1.0`` for a record that acted with other than ACT's ensembling."""
    return "" if ensemble_decay == ENSEMBLE_DECAY else f"-ensemble_decay={json.dumps(float(ensemble_decay))}"


def run(
    method: str, task: str, store, work: Path, out: Path, steps: int, cameras: tuple[str, ...], workers: int,
    device: str, settings: dict, ensemble_decay: float = ENSEMBLE_DECAY,
):  # fmt: skip
    trained = record_name(method, task, cameras, settings)
    name = trained + acting_suffix(ensemble_decay)
    record = out / f"{name}.json"
    if record.exists():
        return
    checkpoint_path = work / f"{trained}.pt"  # one training serves every acting setting
    started = time.perf_counter()
    checkpoint = train(
        method, task, checkpoint_path, demos=50, cameras=cameras, privileged=not cameras, store=store,
        settings={**settings, "steps": steps}, checkpoint_every=1000, workers=workers,
        device=device,
    )  # fmt: skip
    config = ObservationConfig.from_dict(checkpoint.observation_config)
    factory = checkpoint_factory(checkpoint_path, ensemble_decay)
    result = evaluate(factory, task, workers=workers, observation_config=config)
    data = {
        "method": method,
        "task": task,
        "training": {
            "demos": len(checkpoint.demos),
            "steps": checkpoint.step,
            "seconds": checkpoint.train_seconds,
            "final_loss": checkpoint.losses[-1][1],
            "final_loss_terms": checkpoint.loss_terms[-1] if checkpoint.loss_terms else {},
            "config": checkpoint.config,
        },
        "acting": {"ensemble_decay": float(ensemble_decay)},
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


def changed_settings(method: str, config: dict) -> dict:
    """The settings of a record's training that differ from the method's defaults of today
    (the step count aside, which has its own column)."""
    config = with_legacy_settings(method, config)
    defaults = config_dict(make_config(method))
    return {name: value for name, value in config.items() if name != "steps" and defaults.get(name) != value}


def record_decay(data: dict) -> float:
    """How a record's policy ensembled its chunks (records from before the setting: ACT's)."""
    return data.get("acting", {}).get("ensemble_decay", ENSEMBLE_DECAY)


def differences(method: str, config: dict, ensemble_decay: float = ENSEMBLE_DECAY) -> str:
    """The table's settings column: ``defaults``, or what differed (``dropout 0, ema 0``),
    acting included (``ensemble_decay 1.0``)."""
    changed = changed_settings(method, config)
    if ensemble_decay != ENSEMBLE_DECAY:
        changed["ensemble_decay"] = float(ensemble_decay)
    return ", ".join(f"{name} {json.dumps(value)}" for name, value in changed.items()) or "defaults"


def name_for_today(data: dict) -> str:
    """The name a record would get if run again today with ``--set`` for what it changed:
    a record named otherwise would make the benchmark skip a run it never did."""
    cameras = ("cameras",) if "pixels" in data["evaluation"]["fingerprint"]["track"] else ()
    changed = changed_settings(data["method"], data["training"]["config"])
    trained = record_name(data["method"], data["task"], cameras, changed)
    return trained + acting_suffix(record_decay(data))


def on_gpu(machine: str) -> str:
    """`` on NVIDIA H100 80GB HBM3`` for a record trained on a GPU (see :func:`machine`), else ``""``."""
    parts = machine.split(", ")
    return f" on {parts[2]}" if len(parts) > 2 else ""


def table(out: Path) -> str:
    lines = [
        "| task | method | observations | settings | success | 95% interval | demos | steps | training | bigym |",
        "|---|---|---|---|---:|---:|---:|---:|---:|---|",
    ]
    for path in sorted(out.glob("*.json")):
        data = json.loads(path.read_text())
        result = EvaluationResult.from_dict(data["evaluation"])
        s, training = result.summary, data["training"]
        low, high = s.interval
        official = "" if result.official else " (unofficial)"
        track = result.fingerprint["track"]
        lines.append(
            f"| {data['task']} | {data['method']} | {track} "
            f"| {differences(data['method'], training['config'], record_decay(data))} "
            f"| {s.successes}/{s.episodes}{official} "
            f"| {100 * low:.0f}-{100 * high:.0f}% | {training['demos']} | {training['steps']} "
            f"| {training['seconds'] / 60:.0f} min{on_gpu(data.get('machine', ''))} "
            f"| {result.fingerprint['bigym_version']} |"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--store", help="demo store with the dataset (default: the local store)")
    parser.add_argument("--method", action="append", choices=sorted(STEPS), help="default: bc, act, dp")
    parser.add_argument("--task", action="append", help=f"default: {', '.join(TASKS)}")
    parser.add_argument("--all-tasks", action="store_true", help="every task the store has demos for")
    parser.add_argument("--pixels", action="append", default=[], help="also train ACT from the 3 cameras on this task")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="a training setting of every method run (repeatable), as bigym train --set")  # fmt: skip
    parser.add_argument("--steps", type=int, help="training steps for every method (default: per method)")
    parser.add_argument("--work", type=Path, default=None, help="checkpoints (default: $BIGYM_HOME/baselines)")
    parser.add_argument("--out", type=Path, default=Path("results/baselines"))
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--device", default="auto", help="training device: auto (CUDA when there is a GPU), cpu, cuda")
    parser.add_argument("--ensemble-decay", type=float, default=ENSEMBLE_DECAY,
                        help="acting: the temporal ensembling's weight step (ACT's 0.01), as bigym eval --ensemble-decay")  # fmt: skip
    parser.add_argument("--table-only", action="store_true", help="print the table of the existing records")
    args = parser.parse_args()
    methods = args.method or list(STEPS)
    try:
        settings = parse_settings(args.set)
        for method in set(methods) | ({"act"} if args.pixels else set()):
            config = config_dict(make_config(method, settings))
            settings = {name: config[name] for name in settings}  # as stored: ema=0 is 0.0
    except (ValueError, TypeError) as error:
        parser.error(str(error))
    if not args.table_only:
        home = Path(os.environ.get("BIGYM_HOME", Path.home() / ".cache" / "bigym"))
        work = args.work or home / "baselines"
        store = DemoStore(args.store)
        tasks = args.task or list(TASKS)
        if args.all_tasks:
            tasks = sorted({entry.task for entry in store.entries()})
        for task in tasks:
            for method in methods:
                steps = args.steps or STEPS[method]
                run(method, task, store, work, args.out, steps, (), args.workers, args.device, settings,
                    args.ensemble_decay)  # fmt: skip
        for task in args.pixels:
            cameras = ("head", "left_wrist", "right_wrist")
            steps = args.steps or STEPS["act"]
            run("act", task, store, work, args.out, steps, cameras, args.workers, args.device, settings,
                args.ensemble_decay)  # fmt: skip
    print(f"\nMachine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs\n")
    print(table(args.out))


if __name__ == "__main__":
    main()
