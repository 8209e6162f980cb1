"""``bigym teleop``: record your own demos by driving the robot from an input device."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from bigym.cli.demos import StoreOption, VersionOption, _fail, _handle_errors, _store, console
from bigym.demonstrations.store import DATASET_VERSION


@_handle_errors
def teleop_command(
    task: Annotated[str, typer.Argument(help="Task name, e.g. ReachTargetSingle or reach_target_single.")],
    device: Annotated[
        str, typer.Option(help="Input device(s), comma-separated: keyboard, gamepad, spacemouse, vr.")
    ] = "keyboard",
    ui: Annotated[
        str, typer.Option(help="browser (a page on a local web server) or window (MuJoCo's viewer).")
    ] = "browser",
    seed: Annotated[
        int | None, typer.Option(help="Seed of the first scene; the next scenes count up (default: random).")
    ] = None,
    host: Annotated[
        str, typer.Option(help="--ui browser: address to serve on (127.0.0.1: this machine only).")
    ] = "127.0.0.1",
    port: Annotated[int, typer.Option(min=0, max=65535, help="--ui browser: port (0: any free one).")] = 8765,
    auto_keep: Annotated[bool, typer.Option(help="Keep a demo 1 s after its first success without asking.")] = True,
    script: Annotated[
        Path | None, typer.Option(help="Play a recorded input script headless instead of a live session.")
    ] = None,
    save_input: Annotated[
        Path | None, typer.Option(help="Write the session's input events to this script file.")
    ] = None,
    aside: Annotated[
        Path | None,
        typer.Option(help="Folder for demos that fail verification (default: $BIGYM_HOME/demonstrations/rejected)."),
    ] = None,
    store: StoreOption = None,
    version: VersionOption = DATASET_VERSION,
) -> None:
    """Teleoperate the robot and record demos (source "human") into the store.

    Each kept demo is verified like the shipped ones (replayed at 500, 50, 25 and 20 Hz
    from its file, succeeding every time); a demo that fails goes to --aside with the
    reason, never into the store.
    """
    from bigym.teleop import InputScript, TeleopSession, make_devices, play

    if ui not in ("browser", "window"):
        _fail(f"--ui must be 'browser' or 'window', got {ui!r}")
    if script is not None:
        recorded = InputScript.load(script)
        task, seed, device = recorded.task, recorded.seed, ",".join(recorded.devices)
    devices = make_devices(device)
    session = TeleopSession(task, devices, _store(store, version), seed=seed, aside=aside, auto_keep=auto_keep)
    try:
        if script is not None:
            outcomes = play(recorded, session, extra_steps=round(session.env.max_episode_steps))
            for outcome in outcomes:
                console.print(outcome.describe(), highlight=False)
        elif ui == "browser":
            _serve(session, host, port)
        else:
            _window(session, devices)
    finally:
        if save_input is not None:
            InputScript.from_session(session).save(save_input)
            console.print(f"input written to {save_input}")
        session.close()
    status = session.status
    console.print(f"{status.kept} demos kept in {session.store.url} (version {session.store.version}), "
                  f"{status.rejected} put aside in {session.aside}, {status.dropped} dropped")  # fmt: skip


def _serve(session, host: str, port: int) -> None:
    from bigym.teleop.browser import TeleopServer

    server = TeleopServer(session, host=host, port=port)
    url = server.start().replace("127.0.0.1", "localhost")
    console.print(
        f"open {url} in a browser (Ctrl-C to stop; from another machine: ssh -L {server.port}:localhost:{server.port} ...)"
    )
    try:
        server.wait()
    except KeyboardInterrupt:
        console.print("stopping")
    finally:
        server.stop()


def _window(session, devices) -> None:
    from bigym.teleop.window import run_window

    readers = []
    for device in devices:
        if device.name == "spacemouse":
            from bigym.teleop.devices.spacemouse import SpaceMouseReader

            readers.append(SpaceMouseReader().poll)
        elif device.name != "keyboard":
            _fail(f"the window reads the keyboard and a SpaceMouse; use --ui browser for the {device.name}")
    run_window(session, readers)


__all__ = ["teleop_command"]
