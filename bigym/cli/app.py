"""The ``bigym`` command line."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

import bigym
from bigym.task_docs import snake_case

app = typer.Typer(help="BiGym: humanoid bi-manual kitchen benchmark in MuJoCo.", no_args_is_help=True)
console = Console()
err_console = Console(stderr=True)


def _fail(message: str) -> None:
    from rich.markup import escape

    err_console.print(f"[bold red]error:[/] {escape(message)}", highlight=False)
    raise typer.Exit(code=1)


def progress_columns(*fields: str) -> tuple:
    """The columns of every long command's bar: what, bar, done/total, ``fields``, times."""
    from rich.progress import TimeRemainingColumn

    extra = tuple(TextColumn(f) for f in fields)
    return (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), *extra, TimeElapsedColumn(),
            TimeRemainingColumn())  # fmt: skip


def camera_names(cameras: str | None, depth: bool) -> list[str]:
    """``--cameras head,left_wrist`` as a list of robot cameras (exit 1 on unknown names)."""
    from bigym.robot.h1 import CAMERAS

    names = [n.strip() for n in cameras.split(",") if n.strip()] if cameras else []
    unknown = [n for n in names if n not in CAMERAS]
    if unknown:
        _fail(f"unknown camera(s) {', '.join(unknown)}; the robot's cameras are {', '.join(CAMERAS)}")
    if depth and not names:
        _fail("--depth needs --cameras")
    return names


def task_class(name: str) -> type:
    """Resolve a task by class name, snake_case name or gymnasium id (exit 1 if unknown)."""
    from bigym.demonstrations.errors import DemoError
    from bigym.demonstrations.player import resolve_task

    try:
        return resolve_task(name)
    except DemoError:
        _fail(f"unknown task {name!r}. Known tasks: {', '.join(bigym.TASKS)}")


@app.command()
def tasks(
    markdown: Annotated[Path | None, typer.Option(help="Write the task documentation (docs/tasks.md) here.")] = None,
    previews: Annotated[Path | None, typer.Option(help="Render one preview PNG per task into this folder.")] = None,
    readme: Annotated[Path | None, typer.Option(help="Regenerate the task table of this README.")] = None,
) -> None:
    """List every task with its id, action sizes and time limit."""
    from bigym.action_modes import JointPositionActionMode
    from bigym.task_docs import render_previews, task_infos, tasks_markdown, update_readme

    if readme is not None:
        try:
            update_readme(readme)
        except (OSError, ValueError) as error:
            _fail(str(error))
        console.print(f"updated the task table in {readme}")
        return
    if markdown is not None:
        markdown.parent.mkdir(parents=True, exist_ok=True)
        markdown.write_text(tasks_markdown())
        console.print(f"wrote {markdown}")
        return
    infos = task_infos()
    if previews is not None:
        columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
        with Progress(*columns, console=console) as progress:
            bar = progress.add_task("rendering previews", total=len(infos))
            paths = render_previews(previews, progress=lambda name: progress.advance(bar))
        console.print(f"wrote {len(paths)} previews to {previews}")
        return
    # The action layout depends on the action mode only, not on the task.
    sizes = {
        "floating": len(_layout_of(infos[0].cls, JointPositionActionMode())),
        "whole body": len(_layout_of(infos[0].cls, JointPositionActionMode(floating_base=False))),
    }
    table = Table("id", "task", "actions (floating)", "actions (whole body)", "time limit (s)")
    for info in infos:
        table.add_row(
            info.env_id,
            info.snake,
            str(sizes["floating"]),
            str(sizes["whole body"]),
            f"{info.cls.time_limit:g}",
        )
    console.print(table)


def _layout_of(cls: type, mode) -> list:
    env = cls(action_mode=mode)
    try:
        return list(env.action_layout.entries)
    finally:
        env.close()


@app.command()
def run(
    task: Annotated[str, typer.Argument(help="Task name, e.g. ReachTargetDual or reach_target_dual.")],
    policy: Annotated[str, typer.Option(help="auto | random | hold | reach (auto: reach on reach tasks).")] = "auto",
    episodes: Annotated[int, typer.Option(min=1, help="Episodes to roll out.")] = 5,
    seed: Annotated[int, typer.Option(help="Seed of the first episode; episode k uses seed + k.")] = 0,
    control_frequency: Annotated[float, typer.Option(help="Control rate in Hz (20-500).")] = 50,
    absolute: Annotated[bool, typer.Option(help="Absolute joint targets instead of deltas.")] = False,
    whole_body: Annotated[
        bool, typer.Option(help="Whole-body mode (legs actuated) instead of the floating base.")
    ] = False,
    video: Annotated[Path | None, typer.Option(help="Write an mp4 of the external camera here.")] = None,
) -> None:
    """Roll out a policy, print the success rate, optionally write a video."""
    from bigym.action_modes import JointPositionActionMode
    from bigym.policies import POLICIES, make_policy

    if policy not in POLICIES:
        _fail(f"unknown policy {policy!r}; choose from {', '.join(POLICIES)}")
    cls = task_class(task)
    if video is not None and video.suffix.lower() not in (".mp4", ".gif", ".webm", ".mkv"):
        _fail(f"--video must end in .mp4, .gif, .webm or .mkv, got {video}")
    try:
        env = cls(
            action_mode=JointPositionActionMode(floating_base=not whole_body, absolute=absolute),
            render_mode="rgb_array" if video is not None else None,
            control_frequency=control_frequency,
        )
        agent = make_policy(policy, env, seed)
    except (ValueError, RuntimeError) as error:
        _fail(str(error))
    writer = None
    if video is not None:
        import imageio.v2 as imageio

        video.parent.mkdir(parents=True, exist_ok=True)
        frame_every = max(1, round(env.control_frequency / 30))
        writer = imageio.get_writer(video, fps=env.control_frequency / frame_every)
    successes = 0
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    try:
        with Progress(*columns, console=console) as progress:
            bar = progress.add_task(f"{cls.__name__} ({policy})", total=episodes)
            for episode in range(episodes):
                obs, info = env.reset(seed=seed + episode)
                if writer is not None:
                    writer.append_data(env.render())
                success = False
                for step in range(env.max_episode_steps):
                    obs, reward, terminated, truncated, info = env.step(agent(obs))
                    if writer is not None and step % frame_every == 0:
                        writer.append_data(env.render())
                    success = success or bool(info["is_success"])
                    if terminated or truncated:
                        if "unstable" in info:
                            console.print(f"episode {episode}: {info['unstable']}")
                        break
                successes += success
                progress.advance(bar)
    finally:
        if writer is not None:
            writer.close()
        env.close()
    rate = successes / episodes
    console.print(f"success rate: {successes}/{episodes} ({100 * rate:.0f}%)")
    if video is not None:
        console.print(f"video: {video}")


props_app = typer.Typer(help="The procedural prop library.", no_args_is_help=True)
app.add_typer(props_app, name="props")


@props_app.command("gallery")
def props_gallery(out_dir: Annotated[Path, typer.Argument(help="Folder for the PNGs (created if missing).")]) -> None:
    """Render every prop and every scene to PNG, plus one contact sheet."""
    from bigym.props.gallery import render_gallery

    if out_dir.exists() and not out_dir.is_dir():
        _fail(f"{out_dir} exists and is not a folder")
    out_dir.mkdir(parents=True, exist_ok=True)
    with console.status("rendering props and scenes"):
        paths = render_gallery(out_dir)
    console.print(f"wrote {len(paths)} images to {out_dir}")


from bigym.cli.demos import demos_app  # noqa: E402
from bigym.cli.evaluate import eval_command  # noqa: E402
from bigym.cli.teleop import teleop_command  # noqa: E402
from bigym.cli.train import train_command  # noqa: E402

app.add_typer(demos_app, name="demos")
app.command("eval")(eval_command)
app.command("train")(train_command)
app.command("teleop")(teleop_command)


def main() -> None:
    np.set_printoptions(precision=4, suppress=True)
    app()


if __name__ == "__main__":
    main()
