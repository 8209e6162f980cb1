"""``bigym demos``: list, inspect, download, verify, replay, convert, export, delete, record.

Every command takes ``--store URL`` (default ``$BIGYM_DEMO_STORE`` or the local folder
``$BIGYM_HOME/demonstrations/store``) and ``--version``. Every error ends with a readable
message on stderr and exit status 1.
"""

from __future__ import annotations

import functools
import json
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from bigym.cli.backend import RayAddressOption, start_backend
from bigym.demonstrations.store import DATASET_VERSION

demos_app = typer.Typer(help="Demonstrations: list, download, verify, replay, convert, export.", no_args_is_help=True)
console = Console()
err_console = Console(stderr=True)

StoreOption = Annotated[
    str | None, typer.Option("--store", help="Store URL or folder (default: $BIGYM_DEMO_STORE or the local store).")
]
VersionOption = Annotated[str, typer.Option("--version", help="Dataset version in the store ('latest' allowed).")]
TaskOption = Annotated[str | None, typer.Option("--task", help="Only demos of this task.")]
FrequencyOption = Annotated[float | None, typer.Option("--frequency", "-f", help="Control rate in Hz (20-500).")]
DemosArgument = Annotated[list[str] | None, typer.Argument(help="Demo files or uuids (default: every demo of --task).")]
CamerasOption = Annotated[
    str | None,
    typer.Option("--cameras", help="Comma-separated cameras (head, left_wrist, right_wrist, external) or 'robot'."),
]


def _fail(message: str) -> None:
    from rich.markup import escape

    err_console.print(f"[bold red]error:[/] {escape(message)}", highlight=False)
    raise typer.Exit(code=1)


def _handle_errors(command):
    """Turn every expected failure into a one-line message and exit status 1."""

    @functools.wraps(command)
    def wrapper(*args, **kwargs):
        from bigym.demonstrations.errors import DemoError

        try:
            return command(*args, **kwargs)
        except typer.Exit:
            raise
        except (DemoError, ValueError, OSError, RuntimeError, KeyError) as error:
            _fail(f"{type(error).__name__}: {error}")

    return wrapper


def _store(url: str | None, version: str):
    from bigym.demonstrations.store import DemoStore

    return DemoStore(url, version=version)


def _observation_config(cameras: str | None, resolution: int, depth: bool, privileged: bool):
    from bigym.observations import CameraConfig, ObservationConfig

    if cameras is None or cameras == "":
        return ObservationConfig(privileged_information=privileged)
    if cameras == "robot":
        return ObservationConfig.robot_cameras((resolution, resolution), depth, privileged_information=privileged)
    names = [name.strip() for name in cameras.split(",") if name.strip()]
    return ObservationConfig(
        cameras=tuple(CameraConfig(n, True, depth, (resolution, resolution)) for n in names),
        privileged_information=privileged,
    )


def _load_demos(store, demos: list[str] | None, task: str | None):
    """Demos named by file path or uuid prefix, or every demo of ``task`` in the store."""
    from bigym.demonstrations.demo import Demo

    if demos:
        loaded = []
        for name in demos:
            path = Path(name)
            if path.is_file():
                loaded.append(Demo.load(path))
            elif path.suffix == ".safetensors" or "/" in name:
                raise FileNotFoundError(f"no demo file {name}")
            else:
                loaded.append(store.load(name))
        return loaded
    if task is None:
        _fail("name demos (files or uuids) or pass --task")
    return [store.load(entry) for entry in _task_entries(store, task)]


def _task_entries(store, task: str, hint: str = "") -> list:
    """Every demo of ``task`` in the store; a task it lacks is first completed from the
    shipped dataset when one covers it (demos on demand). ``hint``: what to do otherwise."""
    entries = store.entries(task=task)
    if not entries and store.on_demand:
        store.provide(task)
        entries = store.entries(task=task)
    if not entries:
        _fail(f"no demos of {task} in {store.url} (version {store.version}){hint}")
    return entries


def _mode_of(store, task: str, mode: str | None) -> dict:
    """The action mode to use for ``task``: the one the store has, or the one named by ``mode``."""
    from bigym.demonstrations.metadata import describe_action_mode, normalise_action_mode

    modes = {json.dumps(normalise_action_mode(e.action_mode), sort_keys=True) for e in _task_entries(store, task)}
    candidates = [json.loads(m) for m in sorted(modes)]
    if mode is not None:
        if mode not in ("absolute", "delta"):
            _fail("--mode must be 'absolute' or 'delta'")
        wanted = [m for m in candidates if m["absolute"] == (mode == "absolute")]
        if wanted:
            return wanted[0]
        base = dict(candidates[0])
        base["absolute"] = mode == "absolute"
        return base  # get_demos(convert=True) converts to it
    if len(candidates) > 1:
        listing = ", ".join(describe_action_mode(m) for m in candidates)
        _fail(f"{task} has demos for several action modes ({listing}); choose one with --mode absolute|delta")
    return candidates[0]


# ---------------------------------------------------------------------- list / info
@demos_app.command("list")
@_handle_errors
def list_demos(
    task: TaskOption = None,
    each: Annotated[bool, typer.Option("--each", help="One row per demo instead of per group.")] = False,
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """List the demos of a store: per task, action mode and rate (or each demo with --each)."""
    from bigym.demonstrations.metadata import describe_action_mode

    demo_store = _store(store, version)
    entries = demo_store.entries(task=task)
    title = f"{demo_store.url} (version {demo_store.version}): {len(entries)} demos"
    if not entries:
        console.print(f"{title}.")
        return
    if each:
        table = Table("uuid", "task", "action mode", "rate", "steps", "success", "source", "date", title=title)
        for e in entries:
            table.add_row(e.uuid[:12], e.task, describe_action_mode(e.action_mode), f"{e.frequency:g} Hz",
                          str(e.num_steps), str(e.success), e.source, e.date or "")  # fmt: skip
    else:
        groups: dict[tuple, list] = {}
        for e in entries:
            groups.setdefault((e.task, describe_action_mode(e.action_mode), e.frequency), []).append(e)
        table = Table("task", "action mode", "rate", "demos", "successful", "steps", "size", title=title)
        for (name, mode, rate), items in sorted(groups.items()):
            table.add_row(name, mode, f"{rate:g} Hz", str(len(items)), str(sum(bool(e.success) for e in items)),
                          str(sum(e.num_steps for e in items)), _size(sum(e.size for e in items)))  # fmt: skip
    console.print(table)


def _size(count: float) -> str:
    for unit in ("B", "kB", "MB", "GB"):
        if count < 1000 or unit == "GB":
            return f"{count:.0f} {unit}" if unit == "B" else f"{count:.1f} {unit}"
        count /= 1000
    return f"{count:.1f} GB"


@demos_app.command()
@_handle_errors
def info(
    demo: Annotated[str, typer.Argument(help="A demo file, or a uuid (prefix) in the store.")],
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """Show a demo's metadata and tensors."""
    from bigym.demonstrations.metadata import describe_action_mode

    loaded = _load_demos(_store(store, version), [demo], None)[0]
    meta = loaded.metadata
    table = Table("field", "value", title=f"demo {loaded.uuid}", show_header=False)
    rows = {
        "task": meta.task + (f" {meta.task_kwargs}" if meta.task_kwargs else ""),
        "action mode": describe_action_mode(meta.action_mode),
        "recording rate": f"{meta.frequency:g} Hz ({meta.substeps} physics steps per action)",
        "steps": f"{len(loaded)} ({loaded.duration:.2f} s)",
        "reset seed": str(meta.seed),
        "source": meta.source,
        "success": str(meta.success),
        "date": str(meta.date),
        "bigym / MuJoCo": f"{meta.bigym_version} / {meta.mujoco_version}",
        "model fingerprint": str(meta.model_fingerprint),
        "checkpoints": f"{len(loaded.checkpoint_steps)} (every {meta.checkpoint_interval} steps)",
        "tensors": ", ".join(
            f"{name} {tuple(getattr(loaded, name).shape)} {getattr(loaded, name).dtype}"
            for name in ("actions", "initial_state", "checkpoint_steps", "checkpoint_states")
        ),
    }
    if meta.extra:
        rows["extra"] = json.dumps(meta.extra)
    for key, value in rows.items():
        table.add_row(key, value)
    console.print(table)


# ---------------------------------------------------------------------- download / verify
@demos_app.command()
@_handle_errors
def download(
    task: Annotated[list[str] | None, typer.Option("--task", help="Only these tasks (repeatable).")] = None,
    refresh: Annotated[bool, typer.Option(help="Fetch the manifest again.")] = False,
    shipped: Annotated[
        bool, typer.Option("--shipped", help="Local store: complete every task of the shipped dataset.")
    ] = False,
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """Download (and verify the sha256 of) the demos of a store into the local cache.

    For a local store, the tasks named with --task (every task with --shipped) are first
    completed with their slice of the shipped dataset: downloaded from a hosted copy
    ($BIGYM_DATASET_MIRROR) or built on this machine.
    """
    demo_store = _store(store, version)
    if demo_store.is_local and (task or shipped):
        from bigym.demonstrations.provision import shipped_tasks

        names = task or shipped_tasks(demo_store.version)
        if not names:
            _fail(f"this bigym ships no dataset {demo_store.version} to complete {demo_store.url} from")
        for name in names:
            report = demo_store.provide(name)
            if report is None:
                _fail(f"the shipped dataset {demo_store.version} has no demos of {name}")
            console.print(report.summary())
    elif shipped:
        _fail(f"--shipped completes a local store; {demo_store.url} is remote (its files download as they are)")
    demo_store.manifest(refresh=refresh)
    entries = [e for name in task for e in demo_store.entries(task=name)] if task else demo_store.entries()
    if not entries:
        _fail(f"no demos to download from {demo_store.url}")
    paths = demo_store.download(entries, progress=True)
    where = "already local" if demo_store.is_local else str(demo_store.download_dir)
    console.print(f"{len(paths)} demos verified ({where})")


@demos_app.command()
@_handle_errors
def verify(
    demos: DemosArgument = None,
    task: TaskOption = None,
    frequency: FrequencyOption = None,
    workers: Annotated[int, typer.Option(min=1, help="Parallel replay processes.")] = 1,
    backend: Annotated[str, typer.Option(help="process | ray | serial")] = "process",
    ray_address: RayAddressOption = None,
    tolerance: Annotated[float | None, typer.Option(help="Joint tolerance for replays at another rate.")] = None,
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """Replay demos and check every checkpoint and the final success; exit 1 if any fails."""
    from rich.markup import escape

    from bigym.demonstrations.player import replay_many

    start_backend(backend, ray_address, workers, _fail, allowed=("process", "ray", "serial"))
    loaded = _load_demos(_store(store, version), demos, task)
    results = replay_many(loaded, None, frequency, workers=workers, backend=backend, tolerance=tolerance,
                          errors="return", description="verifying demos")  # fmt: skip
    table = Table("uuid", "task", "rate", "steps", "checkpoints", "max divergence", "success", "result")
    failures = 0
    for demo, result in zip(loaded, results):
        if isinstance(result, Exception):
            failures += 1
            table.add_row(demo.uuid[:12], demo.metadata.task, "", str(len(demo)), "", "", "",
                          f"[red]{type(result).__name__}[/]")  # fmt: skip
        else:
            report = result.report
            table.add_row(demo.uuid[:12], demo.metadata.task, f"{report.frequency:g} Hz", str(len(result)),
                          str(report.checkpoints_checked), f"{report.max_divergence:.3g}",
                          str(report.first_success_step is not None), "[green]ok[/]")  # fmt: skip
    console.print(table)
    for demo, result in zip(loaded, results):
        if isinstance(result, Exception):
            err_console.print(f"[red]{demo.uuid}[/]: {escape(str(result))}", highlight=False)
    if failures:
        _fail(f"{failures} of {len(loaded)} demos failed verification")
    console.print(f"all {len(loaded)} demos verified")


# ---------------------------------------------------------------------- replay
@demos_app.command("replay")
@_handle_errors
def replay_command(
    demo: Annotated[str, typer.Argument(help="A demo file, or a uuid (prefix) in the store.")],
    frequency: FrequencyOption = None,
    cameras: CamerasOption = None,
    resolution: Annotated[int, typer.Option(min=8, help="Camera resolution (square).")] = 84,
    depth: Annotated[bool, typer.Option(help="Also render depth.")] = False,
    privileged: Annotated[bool, typer.Option(help="Add the task's privileged observations.")] = False,
    video: Annotated[Path | None, typer.Option(help="Write an mp4 of the external camera here.")] = None,
    output: Annotated[Path | None, typer.Option(help="Save the replayed demo (safetensors) here.")] = None,
    tolerance: Annotated[float | None, typer.Option(help="Joint tolerance for replays at another rate.")] = None,
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """Replay one demo (verified), optionally writing a video and the replayed observations."""
    from bigym.demonstrations.player import replay

    if video is not None and video.suffix.lower() not in (".mp4", ".gif", ".webm", ".mkv"):
        _fail(f"--video must end in .mp4, .gif, .webm or .mkv, got {video}")
    loaded = _load_demos(_store(store, version), [demo], None)[0]
    config = _observation_config(cameras, resolution, depth, privileged)
    with console.status(f"replaying {loaded.uuid}"):
        result = replay(loaded, config, frequency, video=video, tolerance=tolerance)
    report = result.report
    console.print(
        f"replayed {len(result)} steps at {report.frequency:g} Hz "
        f"({'bit-identical' if report.exact else f'max divergence {report.max_divergence:.3g}'}, "
        f"{report.checkpoints_checked} checkpoints); success at step {report.first_success_step}"
    )
    if output is not None:
        console.print(f"saved {result.save(output)}")
    if video is not None:
        console.print(f"video: {video}")


# ---------------------------------------------------------------------- convert
@demos_app.command()
@_handle_errors
def convert(
    demos: DemosArgument = None,
    to: Annotated[str | None, typer.Option("--to", help="absolute | delta")] = None,
    frequency: FrequencyOption = None,
    task: TaskOption = None,
    output: Annotated[Path | None, typer.Option(help="Write the converted demos into this folder.")] = None,
    add_to_store: Annotated[bool, typer.Option(help="Add the converted demos to the store.")] = False,
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """Convert demos between absolute and delta actions and/or to another recording rate."""
    from bigym.demonstrations.convert import convert_demo
    from bigym.demonstrations.player import progress_bar

    if to is None and frequency is None:
        _fail("nothing to convert: pass --to absolute|delta and/or --frequency")
    if output is None and not add_to_store:
        _fail("say where the converted demos go: --output FOLDER or --add-to-store")
    demo_store = _store(store, version)
    loaded = _load_demos(demo_store, demos, task)
    written = []
    with progress_bar(True, "converting demos", len(loaded)) as advance:
        for demo in loaded:
            converted = convert_demo(demo, to=to, frequency=frequency)
            if output is not None:
                output.mkdir(parents=True, exist_ok=True)
                written.append(str(converted.save(output / converted.filename)))
            if add_to_store:
                written.append(demo_store.add(converted, overwrite=True).path)
            advance()
    console.print(f"converted {len(loaded)} demos:")
    for path in written:
        console.print(f"  {path}")


# ---------------------------------------------------------------------- export
@demos_app.command()
@_handle_errors
def export(
    format: Annotated[str, typer.Argument(help="lerobot | robomimic")],
    output: Annotated[Path, typer.Argument(help="Dataset folder (lerobot) or .hdf5 file (robomimic).")],
    task: Annotated[str, typer.Option("--task", help="Task to export.")],
    mode: Annotated[str | None, typer.Option(help="absolute | delta (needed when the store has both).")] = None,
    frequency: Annotated[float, typer.Option("--frequency", "-f", help="Control rate in Hz.")] = 50,
    cameras: CamerasOption = None,
    resolution: Annotated[int, typer.Option(min=8, help="Camera resolution (square).")] = 84,
    depth: Annotated[bool, typer.Option(help="Also render depth (robomimic only).")] = False,
    amount: Annotated[int, typer.Option(help="Number of demos (-1: all).")] = -1,
    workers: Annotated[int, typer.Option(min=1, help="Parallel replay processes.")] = 1,
    backend: Annotated[str, typer.Option(help="process | ray")] = "process",
    ray_address: RayAddressOption = None,
    overwrite: Annotated[bool, typer.Option(help="Replace an existing output.")] = False,
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """Replay demos with the chosen observations and rate and export them (LeRobot v3 or robomimic HDF5)."""
    from bigym.demonstrations.export import export_lerobot, export_robomimic
    from bigym.demonstrations.metadata import Metadata
    from bigym.demonstrations.store import canonical_task

    if format not in ("lerobot", "robomimic"):
        _fail(f"format must be 'lerobot' or 'robomimic', got {format!r}")
    if output.exists() and not overwrite:
        _fail(f"{output} exists; pass --overwrite to replace it")
    rate = 500.0 / max(1, round(500.0 / frequency))
    if format == "lerobot" and abs(rate - round(rate)) > 1e-9:
        _fail(f"LeRobot needs whole frames per second; {frequency:g} Hz runs at {rate:g} Hz. Use 20, 25, 50, 100...")
    start_backend(backend, ray_address, workers, _fail)
    demo_store = _store(store, version)
    name = canonical_task(task)
    action_mode = _mode_of(demo_store, name, mode)
    config = _observation_config(cameras, resolution, depth, False)
    query = Metadata(task=name, action_mode=action_mode, frequency=frequency, observation_config=config.to_dict())
    replayed = demo_store.get_demos(query, amount, frequency, convert=True, workers=workers, backend=backend,
                                    progress=True)  # fmt: skip
    if format == "lerobot":
        path = export_lerobot(replayed, output, overwrite=overwrite, progress=True)
    else:
        path = export_robomimic(replayed, output, overwrite=overwrite, progress=True)
    console.print(f"exported {len(replayed)} demos of {name} at {frequency:g} Hz to {path}")


# ---------------------------------------------------------------------- delete
@demos_app.command()
@_handle_errors
def delete(
    demos: Annotated[list[str] | None, typer.Argument(help="Demo uuids (default: every demo of --task).")] = None,
    task: TaskOption = None,
    replays: Annotated[bool, typer.Option(help="Delete cached replays.")] = True,
    downloads: Annotated[bool, typer.Option(help="Delete downloaded copies (remote stores).")] = True,
    from_store: Annotated[bool, typer.Option(help="Also delete the demos from the store itself.")] = False,
    all_cached: Annotated[bool, typer.Option("--all", help="Every cached replay and download of the store.")] = False,
    yes: Annotated[bool, typer.Option("--yes", "-y", help="Do not ask for confirmation.")] = False,
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """Delete cached replays and downloads (and, with --from-store, the demos themselves)."""
    demo_store = _store(store, version)
    if all_cached:
        if from_store:
            _fail("--all clears caches only; name demos or --task to delete them from the store")
        removed = (demo_store.replays.clear() if replays else 0) + (demo_store.clear_downloads() if downloads else 0)
        console.print(f"deleted {removed} cached files")
        return
    if demos:
        entries = [demo_store.manifest().by_uuid(prefix) for prefix in demos]
    elif task is not None:
        entries = demo_store.entries(task=task)
    else:
        _fail("name demos (uuids), pass --task, or --all")
    if not entries:
        _fail("no matching demos")
    if from_store and not yes:
        typer.confirm(f"delete {len(entries)} demos from {demo_store.url}?", abort=True)
    removed = demo_store.replays.clear([e.uuid for e in entries]) if replays else 0
    if downloads and not demo_store.is_local:
        for entry in entries:
            path = demo_store.local_path(entry)
            if path.is_file():
                path.unlink()
                removed += 1
    if from_store:
        demo_store.remove([e.uuid for e in entries])
        console.print(f"deleted {len(entries)} demos from {demo_store.url}")
    console.print(f"deleted {removed} cached files")


# ---------------------------------------------------------------------- record
@demos_app.command()
@_handle_errors
def record(
    task: Annotated[str, typer.Argument(help="Task name.")],
    policy: Annotated[str, typer.Option(help="auto | random | hold | reach")] = "auto",
    episodes: Annotated[int, typer.Option(min=1, help="Episodes to record.")] = 5,
    seed: Annotated[int, typer.Option(help="Seed of the first episode; episode k uses seed + k.")] = 0,
    absolute: Annotated[bool, typer.Option(help="Absolute joint targets instead of deltas.")] = True,
    frequency: Annotated[float, typer.Option("--frequency", "-f", help="Recording rate in Hz.")] = 500,
    steps_after_success: Annotated[int, typer.Option(help="Steps kept after the first success.")] = 100,
    keep_failures: Annotated[bool, typer.Option(help="Also keep episodes that did not succeed.")] = False,
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """Record episodes of a scripted policy into the store (only successful ones by default)."""
    from bigym.action_modes import JointPositionActionMode
    from bigym.demonstrations.player import progress_bar, resolve_task
    from bigym.demonstrations.recorder import record_episode
    from bigym.policies import POLICIES, make_policy

    if policy not in POLICIES:
        _fail(f"unknown policy {policy!r}; choose from {', '.join(POLICIES)}")
    demo_store = _store(store, version)
    env = resolve_task(task)(action_mode=JointPositionActionMode(absolute=absolute), control_frequency=frequency)
    source = "random" if policy == "random" else "expert" if policy in ("reach", "auto") else "policy"
    kept = 0
    try:
        with progress_bar(True, f"recording {env.task_name}", episodes) as advance:
            for k in range(episodes):
                agent = make_policy(policy, env, seed + k)
                demo = record_episode(env, agent, seed=seed + k, source=source,
                                      steps_after_success=steps_after_success)  # fmt: skip
                if demo.metadata.success or keep_failures:
                    demo_store.add(demo)
                    kept += 1
                advance()
    finally:
        env.close()
    console.print(f"recorded {episodes} episodes, kept {kept} in {demo_store.url} (version {demo_store.version})")


# ---------------------------------------------------------------------- expert demos
@demos_app.command()
@_handle_errors
def generate(
    task: Annotated[str, typer.Argument(help="Task with an expert (see bigym.experts.EXPERTS).")],
    n: Annotated[int, typer.Option("-n", "--n", min=1, help="Verified demos to keep.")] = 50,
    seed: Annotated[int, typer.Option(help="First seed; attempt k uses seed + k (env reset and demonstrator).")] = 0,
    workers: Annotated[int | None, typer.Option(min=1, help="Processes (default: CPU count, at most 8).")] = None,
    max_attempts: Annotated[int | None, typer.Option(min=1, help="Give up after this many (default 3n+5).")] = None,
    plain: Annotated[bool, typer.Option(help="The plain controller: straight lines, constant speed.")] = False,
    output: Annotated[Path | None, typer.Option(help="Write the demos into this folder instead of the store.")] = None,
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """Generate human-like expert demos: record, replay each from its file, keep verified successes.

    The report gives the generator's success rate and why the others failed.
    """
    from bigym.experts import EXPERTS, HumanStyle
    from bigym.experts.generate import generate_demos

    from bigym.demonstrations.store import canonical_task

    name = canonical_task(task)
    if name not in EXPERTS:
        _fail(f"no expert for {name}; experts exist for {', '.join(EXPERTS)}")
    demo_store = None if output is not None else _store(store, version)
    report = generate_demos(name, n=n, seed=seed, workers=workers, max_attempts=max_attempts,
                            style=HumanStyle.plain() if plain else None, out_dir=output, store=demo_store)  # fmt: skip
    console.print(report.summary(), highlight=False)
    reasons = report.failure_summary()
    if reasons:
        console.print("failures: " + ", ".join(f"{reason} ({count})" for reason, count in reasons.items()))
    where = str(output) if output is not None else f"{demo_store.url} (version {demo_store.version})"
    console.print(f"{report.kept} verified demos in {where}")
    if report.kept < n:
        _fail(f"kept only {report.kept} of {n} demos within {len(report.attempts)} attempts")


@demos_app.command()
@_handle_errors
def stats(
    task: Annotated[str, typer.Argument(help="Task name.")],
    n: Annotated[int, typer.Option("-n", "--n", min=2, help="Demos to measure.")] = 20,
    seed: Annotated[int, typer.Option(help="First seed of fresh expert episodes.")] = 0,
    source: Annotated[
        str, typer.Option(help="store: the store's demos of the task; fresh: new expert episodes.")
    ] = "store",
    plain: Annotated[
        bool, typer.Option(help="Compare with the plain straight-line, constant-speed controller.")
    ] = True,
    plot: Annotated[Path | None, typer.Option(help="PNG of the wrist paths seen from above.")] = None,
    as_json: Annotated[Path | None, typer.Option("--json", help="Also write the figures as JSON here.")] = None,
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """Diversity and human-likeness of a task's demos (hand split, durations, straightness,
    smoothness) next to a plain straight-line controller, and a top view of the wrist paths."""
    from bigym.experts.stats import demo_stats

    from bigym.demonstrations.store import canonical_task

    if source not in ("store", "fresh"):
        _fail("--source must be 'store' or 'fresh'")
    name = canonical_task(task)
    demos = None
    if source == "store":
        demo_store = _store(store, version)
        hint = "; generate some (`bigym demos generate`) or pass --source fresh"
        entries = [e for e in _task_entries(demo_store, name, hint) if e.success][:n]
        if not entries:
            _fail(f"no successful demos of {name} in {demo_store.url} (version {demo_store.version}){hint}")
        demos = [demo_store.load(entry) for entry in entries]
    with console.status(f"measuring {name}"):
        report = demo_stats(name, demos=demos, n=n, seed=seed, plain=plain, plot=plot, progress=False)
    console.print(report.table(), highlight=False, soft_wrap=True)
    if as_json is not None:
        as_json.parent.mkdir(parents=True, exist_ok=True)
        as_json.write_text(json.dumps(report.to_dict(), indent=1) + "\n")
        console.print(f"figures: {as_json}")


dataset_app = typer.Typer(help="The shipped expert dataset: rebuild it, check a copy.", no_args_is_help=True)
demos_app.add_typer(dataset_app, name="dataset")


@dataset_app.command("build")
@_handle_errors
def dataset_build(
    out: Annotated[Path, typer.Argument(help="Store folder to write the dataset version into.")],
    task: Annotated[list[str] | None, typer.Option("--task", help="Only these tasks (repeatable).")] = None,
    workers: Annotated[int | None, typer.Option(min=1, help="Processes (default: CPU count, at most 8).")] = None,
    backend: Annotated[str, typer.Option(help="process | ray")] = "process",
    ray_address: RayAddressOption = None,
    resume: Annotated[bool, typer.Option(help="Skip tasks whose files OUT already holds complete.")] = True,
    update_manifest: Annotated[
        bool,
        typer.Option(
            help="Maintainers: merge the result into the shipped manifest (resuming against what "
            "this bigym version built in OUT, not against the manifest it replaces)."
        ),
    ] = False,
) -> None:
    """Regenerate the expert dataset into OUT, task by task (an interrupted build resumes
    where it stopped), and compare it, file by file, with the manifest this bigym ships."""
    from bigym.demonstrations.store import canonical_task
    from bigym.experts.dataset import DATASET_TASKS, DATASET_VERSION, build_dataset, check_dataset

    tasks = tuple(canonical_task(t) for t in task) if task else DATASET_TASKS
    unknown = [t for t in tasks if t not in DATASET_TASKS]
    if unknown:
        _fail(f"not in the dataset: {', '.join(unknown)}; it holds {', '.join(DATASET_TASKS)}")

    def done(name, report) -> None:
        if report is None:
            console.print(f"{name}: already complete in {out}, skipped", highlight=False)
        else:
            console.print(report.summary(), highlight=False)

    start_backend(backend, ray_address, workers, _fail)
    build_dataset(
        out, tasks, workers=workers, on_task=done, resume=resume, backend=backend, against_shipped=not update_manifest
    )
    console.print(f"dataset {DATASET_VERSION} written to {out}: serve it with DemoStore({str(out)!r})")
    if update_manifest:
        from bigym.experts.dataset import write_shipped_manifest

        console.print(f"merged {', '.join(tasks)} into the shipped manifest {write_shipped_manifest(out, tasks)}")
        return
    check = check_dataset(out, tasks)
    console.print(check.summary(), highlight=False)
    if not check.identical:
        _fail("the rebuilt dataset differs from the shipped manifest")


@dataset_app.command("table")
@_handle_errors
def dataset_table_command(
    store: Annotated[
        str | None, typer.Argument(help="Store URL or folder holding the dataset (default: the local store).")
    ] = None,
    task: Annotated[list[str] | None, typer.Option("--task", help="Only these tasks (repeatable).")] = None,
) -> None:
    """Print the README's dataset table (Markdown): generator success and build time from
    the shipped build record, and the demos' figures next to the plain controller's; then
    the shipped manifest's size."""
    from bigym.demonstrations.store import canonical_task
    from bigym.experts.dataset import dataset_size, dataset_table

    tasks = tuple(canonical_task(t) for t in task) if task else None
    with console.status("measuring the demos"):
        table = dataset_table(_store(store, DATASET_VERSION), tasks, progress=False)
    print(table)
    print()
    print(dataset_size())


@dataset_app.command("check")
@_handle_errors
def dataset_check(
    store: Annotated[str | None, typer.Argument(help="Store URL or folder (default: the local store).")] = None,
    task: Annotated[list[str] | None, typer.Option("--task", help="Only these tasks (repeatable).")] = None,
) -> None:
    """Compare a copy of the expert dataset (regenerated or downloaded) with the shipped
    manifest: every file's path, size and sha256."""
    from bigym.demonstrations.store import canonical_task
    from bigym.experts.dataset import DATASET_VERSION, check_dataset

    tasks = tuple(canonical_task(t) for t in task) if task else None
    check = check_dataset(_store(store, DATASET_VERSION), tasks)
    console.print(check.summary(), highlight=False)
    if not check.identical:
        _fail("the copy differs from the shipped manifest")
