"""The desktop front end: MuJoCo's own viewer window, driven in real time.

The viewer reports key *presses* only (no releases), so in the window each press holds
its key for :data:`KEY_NUDGE` seconds: a tap nudges the hand by about 5 cm, the
keyboard's auto-repeat moves it on while the key stays down. Other devices with a
desktop reader (a SpaceMouse through ``pyspacemouse``) are polled every frame. The
gamepad and VR controllers are read by the browser front end (``--ui browser``).
"""

from __future__ import annotations

import queue
import time
from collections.abc import Callable, Sequence

#: seconds each key press holds its key in the window
KEY_NUDGE = 0.2
#: frames per second of the window, and the most control steps one frame may catch up on
FRAME_RATE = 60.0
MAX_CATCH_UP = 50

#: GLFW key codes -> the browser's KeyboardEvent.code names the keyboard device reads
GLFW_KEYS = {
    32: "Space", 44: "Comma", 46: "Period", 257: "Enter", 258: "Tab", 259: "Backspace",
    262: "ArrowRight", 263: "ArrowLeft", 264: "ArrowDown", 265: "ArrowUp", 266: "PageUp", 267: "PageDown",
    340: "ShiftLeft", 344: "ShiftRight",
    **{code: f"Key{chr(code)}" for code in range(ord("A"), ord("Z") + 1)},
    **{code: f"Digit{chr(code)}" for code in range(ord("0"), ord("9") + 1)},
}  # fmt: skip


def key_event(glfw_key: int) -> dict | None:
    """The keyboard device's raw event for a key pressed in the window (None: not ours)."""
    code = GLFW_KEYS.get(int(glfw_key))
    return None if code is None else {"type": "keydown", "code": code, "hold": KEY_NUDGE}


def status_lines(session) -> tuple[str, str]:
    status = session.status
    left = "task\nseed\ntime\nsuccess\nkept / aside / dropped\nhands\n"
    right = (
        f"{status.task}\n{status.seed}\n{status.time:.1f} s\n{'yes' if status.success else 'no'}\n"
        f"{status.kept} / {status.rejected} / {status.dropped}\n{', '.join(status.active_hands)}\n"
    )
    return left + status.message, right


def run_window(session, readers: Sequence[Callable[[], dict]] = (), launch: Callable | None = None) -> None:
    """Show ``session`` in a MuJoCo viewer window and drive it in real time until the
    window closes. ``readers``: functions polled every frame for raw device events.
    ``launch``: what opens the window (default ``mujoco.viewer.launch_passive``)."""
    import mujoco

    if launch is None:
        import mujoco.viewer

        launch = mujoco.viewer.launch_passive
    events: queue.SimpleQueue = queue.SimpleQueue()

    def on_key(glfw_key: int) -> None:  # runs on the viewer's thread
        event = key_event(glfw_key)
        if event is not None:
            events.put(event)

    env = session.env
    with launch(env.model, env.data, key_callback=on_key, show_left_ui=False, show_right_ui=False) as viewer:
        viewer.cam.type = mujoco.mjtCamera.mjCAMERA_TRACKING
        viewer.cam.trackbodyid = env.model.body("pelvis").id
        viewer.cam.distance, viewer.cam.elevation, viewer.cam.azimuth = 2.6, -25.0, 200.0
        start, done = time.perf_counter(), 0
        while viewer.is_running():
            frame_start = time.perf_counter()
            with viewer.lock():
                while not events.empty():
                    session.handle(events.get())
                for read in readers:
                    session.handle(read())
                due = int((frame_start - start) * session.env.control_frequency) - done
                steps = min(max(due, 0), MAX_CATCH_UP)
                session.advance(steps)
                done += steps if due <= MAX_CATCH_UP else due  # never try to catch up a stall
                viewer.set_texts((None, None, *status_lines(session)))
            viewer.sync()
            time.sleep(max(0.0, 1.0 / FRAME_RATE - (time.perf_counter() - frame_start)))


__all__ = ["GLFW_KEYS", "KEY_NUDGE", "key_event", "run_window"]
