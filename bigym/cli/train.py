"""``bigym train``: fit a baseline on a task's demos and write a checkpoint ``bigym eval`` runs."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.progress import Progress

TORCH_MISSING = "the baselines need torch: pip install 'bigym[train]' (here: pip install torch==2.13.0 first)"


def parse_settings(pairs: list[str]) -> dict:
    """``name=value`` pairs (values read as JSON where they parse: numbers, lists, booleans)."""
    import json

    settings = {}
    for pair in pairs:
        name, sep, text = pair.partition("=")
        if not sep or not name:
            raise ValueError(f"--set takes name=value, got {pair!r}")
        try:
            settings[name.replace("-", "_")] = json.loads(text)
        except json.JSONDecodeError:
            settings[name.replace("-", "_")] = text
    return settings


def train_command(
    method: Annotated[str, typer.Argument(help="bc | act | dp")],
    task: Annotated[str, typer.Argument(help="Task name, e.g. DrawerTopOpen or drawer_top_open.")],
    demos: Annotated[int, typer.Option(min=1, help="Demos to train on (the store's first, in file-name order).")] = 50,
    steps: Annotated[int | None, typer.Option(min=1, help="Training steps (default: the method's).")] = None,
    cameras: Annotated[
        str | None, typer.Option(help="Robot cameras to train on, comma-separated: head,left_wrist,right_wrist.")
    ] = None,
    depth: Annotated[bool, typer.Option(help="Depth images too (with --cameras).")] = False,
    privileged: Annotated[bool, typer.Option(help="Give the model the task's object state.")] = True,
    store: Annotated[str | None, typer.Option(help="Demo store URL or folder (default: the local store).")] = None,
    out: Annotated[Path | None, typer.Option(help="Checkpoint file (default: checkpoints/<method>-<task>.pt).")] = None,
    seed: Annotated[int, typer.Option(help="Seed of the weights, batches and noise.")] = 0,
    workers: Annotated[int, typer.Option(min=1, help="Processes replaying the demos.")] = 1,
    checkpoint_every: Annotated[int, typer.Option(min=1, help="Steps between checkpoints.")] = 1000,
    device: Annotated[str, typer.Option(help="auto (a CUDA GPU if there is one, else CPU), cpu, cuda.")] = "auto",
    setting: Annotated[list[str] | None, typer.Option("--set", help="Method setting name=value (repeatable).")] = None,
) -> None:
    """Train a baseline; run again with the same arguments to resume an interrupted run."""
    from bigym.cli.app import _fail, camera_names, console, progress_columns, task_class

    cls = task_class(task)
    try:
        from bigym.baselines import METHODS, train
    except ImportError as error:
        _fail(f"{TORCH_MISSING} ({error})")
    if method not in METHODS:
        _fail(f"unknown method {method!r}; choose from {', '.join(METHODS)}")
    names = camera_names(cameras, depth)
    if not names and not privileged:
        console.print("[yellow]note:[/] proprioception only: the policy cannot see where the objects are")
    try:
        settings = parse_settings(setting or [])
    except ValueError as error:
        _fail(str(error))
    if steps is not None:
        settings["steps"] = steps
    out = out or Path("checkpoints") / f"{method}-{cls.__name__}.pt"
    columns = progress_columns("loss {task.fields[loss]:.4f}")
    try:
        with Progress(*columns, console=console) as progress:
            bar = progress.add_task(f"{method} on {cls.__name__}", total=None, loss=float("nan"))

            def advance(step: int, total: int, loss: float) -> None:
                progress.update(bar, completed=step, total=total, loss=loss)
                # a log file (nohup, a batch job) gets no live bar: one line per checkpoint
                if not console.is_terminal and (step % checkpoint_every == 0 or step == total):
                    elapsed = progress.tasks[0].elapsed or 0.0
                    console.print(f"step {step}/{total}  loss {loss:.4f}  {elapsed / 60:.1f} min")

            checkpoint = train(
                method, cls.__name__, out, demos=demos, cameras=tuple(names), depth=depth, privileged=privileged,
                store=store, seed=seed, settings=settings, checkpoint_every=checkpoint_every, workers=workers,
                progress=advance, replay_progress=True, device=device,
            )  # fmt: skip
    except (ValueError, FileNotFoundError) as error:
        _fail(str(error))
    except Exception as error:  # the demo store's errors (none found, too few) read well as they are
        from bigym.demonstrations import DemoError

        if isinstance(error, DemoError):
            _fail(str(error))
        raise
    final = checkpoint.losses[-1][1] if checkpoint.losses else float("nan")
    terms = checkpoint.loss_terms[-1] if checkpoint.loss_terms else {}
    parts = f" ({', '.join(f'{name} {value:.4g}' for name, value in terms.items())})" if len(terms) > 1 else ""
    console.print(
        f"{out}: {checkpoint.step} steps on {len(checkpoint.demos)} demos, {checkpoint.train_seconds / 60:.1f} min, "
        f"last loss {final:.4f}{parts}"
    )
    console.print(f"evaluate it: bigym eval {cls.__name__} --policy {out}")
