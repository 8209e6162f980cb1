"""``bigym eval``: run the evaluation protocol on a task and report success with its interval."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.progress import Progress

from bigym.cli.backend import RayAddressOption, start_backend
from rich.table import Table

#: policy names the command knows, and the factory each stands for
BUILT_IN_POLICIES = {
    "expert": "bigym.experts:make_expert",
    "random": "bigym.policies:RandomPolicy",
    "hold": "bigym.policies:HoldPolicy",
    "reach": "bigym.policies:ReachPolicy",
}


def is_checkpoint(policy: str) -> bool:
    return ":" not in policy and Path(policy).suffix == ".pt"


def policy_spec(policy: str, task: str, ensemble_decay: float | None = None):
    """The factory for ``--policy`` (a built-in name, ``module:function`` or a checkpoint
    file), checked here so that a typo fails before any worker starts. ``ensemble_decay``:
    a checkpoint's temporal ensembling (default ACT's); refused for any other policy."""
    from bigym.evaluation import PolicyLoadError, load_factory

    if is_checkpoint(policy):
        from bigym.baselines import checkpoint_factory

        if not Path(policy).is_file():
            raise PolicyLoadError(f"no checkpoint at {policy}")
        if ensemble_decay is None:
            return checkpoint_factory(policy)
        return checkpoint_factory(policy, ensemble_decay)
    if ensemble_decay is not None:
        raise PolicyLoadError("--ensemble-decay is a setting of a trained checkpoint (.pt) and needs one as --policy")
    if policy in BUILT_IN_POLICIES:
        if policy == "expert":
            from bigym.experts import EXPERTS

            if task not in EXPERTS:
                raise PolicyLoadError(f"{task} has no expert yet; experts exist for {', '.join(EXPERTS)}")
        return BUILT_IN_POLICIES[policy]
    if ":" not in policy:
        raise PolicyLoadError(
            f"--policy {policy!r}: give one of {', '.join(BUILT_IN_POLICIES)}, a checkpoint (.pt) of "
            "`bigym train`, or a factory as 'package.module:function' or 'path/to/file.py:function'"
        )
    load_factory(policy)
    return policy


def eval_command(
    task: Annotated[str, typer.Argument(help="Task name, e.g. ReachTargetDual or reach_target_dual.")],
    policy: Annotated[
        str,
        typer.Option(help="expert | random | hold | reach | CHECKPOINT.pt | module:factory | path/to/file.py:factory."),
    ] = "expert",
    episodes: Annotated[
        int, typer.Option(min=1, help="Episodes: the first N seeds of the official block (100).")
    ] = 100,
    workers: Annotated[
        int | None, typer.Option(min=1, help="Worker processes (default: CPU count, at most 8).")
    ] = None,
    vector: Annotated[str | None, typer.Option(help="Run a gymnasium vector env per worker: sync | async.")] = None,
    envs_per_worker: Annotated[int, typer.Option(min=1, help="Sub-envs per vector env.")] = 2,
    backend: Annotated[str, typer.Option(help="process (a local pool) | ray (Ray actors, local or a cluster).")] = (
        "process"
    ),
    ray_address: RayAddressOption = None,
    control_frequency: Annotated[
        float | None, typer.Option(help="Control rate in Hz (the protocol's: 50; a checkpoint's own).")
    ] = None,
    delta: Annotated[bool, typer.Option(help="Delta joint targets instead of absolute ones.")] = False,
    cameras: Annotated[
        str | None, typer.Option(help="Robot cameras the policy sees, comma-separated: head,left_wrist,right_wrist.")
    ] = None,
    depth: Annotated[bool, typer.Option(help="Depth images too (with --cameras).")] = False,
    privileged: Annotated[bool, typer.Option(help="Give the policy the task's object state.")] = False,
    trained_observations: Annotated[
        bool, typer.Option(help="With a checkpoint: the observations, action mode and rate it was trained with.")
    ] = True,
    ensemble_decay: Annotated[
        float | None,
        typer.Option(
            help="With a checkpoint: weight step of its temporal ensembling, exp(-decay * i) from the oldest "
            "chunk's prediction (ACT's 0.01; larger commits to older predictions)."
        ),
    ] = None,
    video: Annotated[Path | None, typer.Option(help="Folder for mp4 videos of the first episodes.")] = None,
    videos: Annotated[int, typer.Option(min=0, help="How many episodes to film (with --video).")] = 3,
    json_out: Annotated[Path | None, typer.Option("--json", help="Write the full record (every episode) here.")] = None,
) -> None:
    """Evaluate a policy on a task's official seeds; print success with its 95% interval."""
    from bigym.action_modes import JointPositionActionMode
    from bigym.cli.app import _fail, camera_names, console, progress_columns, task_class
    from bigym.evaluation import EvaluationError, PolicyLoadError, evaluate
    from bigym.observations import CameraConfig, ObservationConfig
    from bigym.scale_out import RayUnavailableError

    cls = task_class(task)
    try:
        spec = policy_spec(policy, cls.__name__, ensemble_decay)
    except ImportError as error:
        _fail(f"checkpoints need torch: pip install 'bigym[train]' ({error})")
    except (PolicyLoadError, ValueError) as error:
        _fail(str(error))
    names = camera_names(cameras, depth)
    if json_out is not None and json_out.exists() and json_out.is_dir():
        _fail(f"--json {json_out} is a folder; give a file name")
    config = ObservationConfig(
        cameras=tuple(CameraConfig(n, rgb=True, depth=depth, resolution=(84, 84)) for n in names),
        privileged_information=privileged,
    )
    action_mode = JointPositionActionMode(floating_base=True, absolute=not delta)
    if is_checkpoint(policy) and trained_observations:
        if names or depth or privileged or delta:
            _fail(
                "a checkpoint brings its own observations and action mode: drop --cameras, --depth, "
                "--privileged and --delta, or pass --no-trained-observations"
            )
        from bigym.action_modes import action_mode_from_dict
        from bigym.baselines import Checkpoint

        try:
            trained = Checkpoint.load(policy)
        except (OSError, ValueError) as error:
            _fail(str(error))
        config = ObservationConfig.from_dict(trained.observation_config)
        action_mode = action_mode_from_dict(trained.action_mode)
        control_frequency = control_frequency if control_frequency is not None else trained.frequency
    columns = progress_columns("{task.fields[successes]} successes")
    try:
        start_backend(backend, ray_address, workers, _fail)
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
                control_frequency=control_frequency if control_frequency is not None else 50.0,
                action_mode=action_mode,
                observation_config=config,
                video_dir=video,
                videos=videos if video is not None else 0,
                progress=advance,
                backend=backend,
            )
    except (EvaluationError, ValueError, RayUnavailableError) as error:
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
        "wall time": f"{result.wall_time:.1f} s on {result.workers} worker(s)"
        + (" (Ray)" if result.backend == "ray" else ""),
    }
    for name, value in rows.items():
        table.add_row(name, value)
    return table
