"""Gamepad: the sticks move the active hand, the triggers close the grippers.

Raw events are the state of a pad in the W3C Gamepad API's *standard mapping* (what a
browser's ``navigator.getGamepads()`` gives; a desktop reader maps its pad to the same
layout), sent whenever it changes::

    {"type": "gamepad", "axes": [lx, ly, rx, ry], "buttons": [b0, ..., b16]}

with stick axes in [-1, 1] (y down positive) and buttons in [0, 1]. Mapping:

* left stick: active hand forward / back and left / right; with Y held, its pitch and roll;
* right stick: active hand up / down and its yaw;
* left / right trigger: left / right gripper, as far as it is pressed (0 open .. 1 closed);
* LB / RB: control the left / right hand; d-pad: walk forward / back, turn;
  Back / Start held: crouch / stand up;
* A: keep the demo, B: discard it, X: retry the same scene.
"""

from __future__ import annotations

import numpy as np

from bigym.teleop.command import TeleopCommand
from bigym.teleop.devices.base import LEFT, RIGHT, Device, numbers

#: the standard mapping's button indices
A, B, X, Y, LB, RB, LT, RT, BACK, START = range(10)
DPAD_UP, DPAD_DOWN, DPAD_LEFT, DPAD_RIGHT = 12, 13, 14, 15
#: stick positions below this count as centred (worn sticks do not rest at 0)
DEADZONE = 0.12
#: a trigger change smaller than this is not a new gripper command
TRIGGER_STEP = 0.02
EVENT_BUTTONS = {A: "keep", B: "discard", X: "retry"}


def _deadzone(value: float) -> float:
    """Stick value with the dead zone removed (continuous at its edge)."""
    magnitude = abs(value)
    if magnitude <= DEADZONE:
        return 0.0
    return float(np.sign(value) * min(1.0, (magnitude - DEADZONE) / (1.0 - DEADZONE)))


class GamepadDevice(Device):
    """A gamepad in the standard mapping."""

    name = "gamepad"
    event_types = ("gamepad",)

    def __init__(self) -> None:
        super().__init__()
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.axes = np.zeros(4)
        self.buttons = np.zeros(17)
        self._grip_sent = [0.0, 0.0]
        self._events: list[str] = []

    def handle(self, event: dict) -> None:
        self.check_type(event)
        axes = numbers(event, "axes", minimum=4)[:4]
        buttons = numbers(event, "buttons", minimum=16)[:17]
        buttons = np.pad(buttons, (0, 17 - buttons.size))
        pressed = (buttons > 0.5) & ~(self.buttons > 0.5)
        for button, name in EVENT_BUTTONS.items():
            if pressed[button]:
                self._events.append(name)
        if pressed[LB]:
            self.active = (LEFT,)
        if pressed[RB]:
            self.active = (RIGHT,)
        self.axes = np.clip(axes, -1.0, 1.0)
        self.buttons = np.clip(buttons, 0.0, 1.0)

    def command(self, dt: float) -> TeleopCommand:
        lx, ly, rx, ry = (_deadzone(v) for v in self.axes)
        b = self.buttons > 0.5
        velocity, turn = np.zeros(3), np.zeros(3)
        if b[Y]:
            turn[1], turn[0] = -ly, lx
        else:
            velocity[0], velocity[1] = -ly, -lx
        velocity[2] = -ry
        turn[2] = -rx
        base = np.array(
            [float(b[DPAD_UP]) - b[DPAD_DOWN], 0.0, float(b[START]) - b[BACK], float(b[DPAD_LEFT]) - b[DPAD_RIGHT]]
        )
        grips: list[float | None] = [None, None]
        for side, trigger in ((LEFT, LT), (RIGHT, RT)):
            value = float(self.buttons[trigger])
            if abs(value - self._grip_sent[side]) >= TRIGGER_STEP or (
                value in (0.0, 1.0) and value != self._grip_sent[side]
            ):
                grips[side] = value
                self._grip_sent[side] = value
        events = tuple(self._events)
        self._events.clear()
        return self.rate_command(dt, velocity, turn, base, (grips[0], grips[1]), events)


__all__ = ["GamepadDevice"]
