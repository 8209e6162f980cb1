"""``bigym eval``: run the evaluation protocol on a task and report success with its interval."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn
from rich.table import Table

#: policy names the command knows, and the factory each stands for
BUILT_IN_POLICIES = {
    "expert": "bigym.experts:make_expert",
    "random": "bigym.policies:RandomPolicy",
    "hold": "bigym.policies:HoldPolicy",
    "reach": "bigym.policies:ReachPolicy",
}


def policy_spec(policy: str, task: str) -> str:
    """The factory name for ``--policy`` (a built-in name or ``module:function``), checked here
    so that a typo fails before any worker starts."""
    from bigym.evaluation import PolicyLoadError, load_factory

    if policy in BUILT_IN_POLICIES:
        if policy == "expert":
            from bigym.experts import EXPERTS

            if task not in EXPERTS:
                raise PolicyLoadError(f"{task} has no expert yet; experts exist for {', '.join(EXPERTS)}")
        return BUILT_IN_POLICIES[policy]
    if ":" not in policy:
        raise PolicyLoadError(
            f"--policy {policy!r}: give one of {', '.join(BUILT_IN_POLICIES)}, or a factory as "
            "'package.module:function' or 'path/to/file.py:function'"
        )
    load_factory(policy)
    return policy


def eval_command(
    task: Annotated[str, typer.Argument(help="Task name, e.g. ReachTargetDual or reach_target_dual.")],
    policy: Annotated[
        str, typer.Option(help="expert | random | hold | reach | module:factory | path/to/file.py:factory.")
    ] = "expert",
    episodes: Annotated[
        int, typer.Option(min=1, help="Episodes: the first N seeds of the official block (100).")
    ] = 100,
    workers: Annotated[
        int | None, typer.Option(min=1, help="Worker processes (default: CPU count, at most 8).")
    ] = None,
    vector: Annotated[str | None, typer.Option(help="Run a gymnasium vector env per worker: sync | async.")] = None,
    envs_per_worker: Annotated[int, typer.Option(min=1, help="Sub-envs per vector env.")] = 2,
    control_frequency: Annotated[float, typer.Option(help="Control rate in Hz (the protocol's: 50).")] = 50,
    delta: Annotated[bool, typer.Option(help="Delta joint targets instead of absolute ones.")] = False,
    cameras: Annotated[
        str | None, typer.Option(help="Robot cameras the policy sees, comma-separated: head,left_wrist,right_wrist.")
    ] = None,
    depth: Annotated[bool, typer.Option(help="Depth images too (with --cameras).")] = False,
    privileged: Annotated[bool, typer.Option(help="Give the policy the task's object state.")] = False,
    video: Annotated[Path | None, typer.Option(help="Folder for mp4 videos of the first episodes.")] = None,
    videos: Annotated[int, typer.Option(min=0, help="How many episodes to film (with --video).")] = 3,
    json_out: Annotated[Path | None, typer.Option("--json", help="Write the full record (every episode) here.")] = None,
) -> None:
    """Evaluate a policy on a task's official seeds; print success with its 95% interval."""
    from bigym.action_modes import JointPositionActionMode
    from bigym.cli.app import _fail, console, task_class
    from bigym.evaluation import EvaluationError, PolicyLoadError, evaluate
    from bigym.observations import CameraConfig, ObservationConfig
    from bigym.robot.h1 import CAMERAS

    cls = task_class(task)
    try:
        spec = policy_spec(policy, cls.__name__)
    except PolicyLoadError as error:
        _fail(str(error))
    names = [n.strip() for n in cameras.split(",") if n.strip()] if cameras else []
    unknown = [n for n in names if n not in CAMERAS]
    if unknown:
        _fail(f"unknown camera(s) {', '.join(unknown)}; the robot's cameras are {', '.join(CAMERAS)}")
    if depth and not names:
        _fail("--depth needs --cameras")
    if json_out is not None and json_out.exists() and json_out.is_dir():
        _fail(f"--json {json_out} is a folder; give a file name")
    config = ObservationConfig(
        cameras=tuple(CameraConfig(n, rgb=True, depth=depth, resolution=(84, 84)) for n in names),
        privileged_information=privileged,
    )
    columns = (
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[successes]} successes"),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
    )
    try:
        with Progress(*columns, console=console) as progress:
            bar = progress.add_task(f"{cls.__name__} ({policy})", total=episodes, successes=0)
            successes = 0

            def advance(record) -> None:
                nonlocal successes
                successes += record.success
                progress.update(bar, advance=1, successes=successes)

            result = evaluate(
                spec,
                cls.__name__,
                episodes=episodes,
                workers=workers,
                vector=vector,
                envs_per_worker=envs_per_worker,
                control_frequency=control_frequency,
                action_mode=JointPositionActionMode(floating_base=True, absolute=not delta),
                observation_config=config,
                video_dir=video,
                videos=videos if video is not None else 0,
                progress=advance,
            )
    except (EvaluationError, ValueError) as error:
        _fail(str(error))
    console.print(summary_table(result))
    if not result.official:
        console.print("[yellow]unofficial:[/] " + "; ".join(result.unofficial_reasons))
    if json_out is not None:
        console.print(f"record: {result.save(json_out)}")
    filmed = [r.video for r in result.episodes if r.video]
    if filmed:
        console.print(f"videos: {', '.join(filmed)}")


def summary_table(result) -> Table:
    """One row per figure: narrow terminals keep it readable."""
    summary = result.summary
    low, high = summary.interval
    table = Table(title=f"{result.task}: {result.policy}", show_header=False)
    table.add_column(style="bold")
    table.add_column()
    outcomes = ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in summary.outcomes.items() if v)
    rows = {
        "success": f"{summary.successes}/{summary.episodes} = {100 * summary.success_rate:.1f}%",
        "95% interval": f"{100 * low:.1f}-{100 * high:.1f}% (Wilson)",
        "mean length": f"{summary.mean_sim_time:.2f} s ({summary.mean_steps:.0f} steps)",
        "outcomes": outcomes,
        "observations": result.fingerprint["track"],
        "official": "yes" if result.official else "no",
        "wall time": f"{result.wall_time:.1f} s on {result.workers} worker(s)",
    }
    for name, value in rows.items():
        table.add_row(name, value)
    return table
