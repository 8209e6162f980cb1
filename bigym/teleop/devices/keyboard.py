"""Keyboard (and mouse): keys held move the active hand or the base; taps grip and switch.

Keys are named by the browser's ``KeyboardEvent.code`` (the physical key, whatever the
layout): ``KeyW``, ``ArrowUp``, ``Space``... A window's key callback translates its key
codes to these names. Raw events::

    {"type": "keydown", "code": "KeyW"}             # held until its keyup
    {"type": "keydown", "code": "KeyW", "hold": 0.2} # held for 0.2 s (windows that report presses only)
    {"type": "keyup", "code": "KeyW"}
    {"type": "mousemove", "dx": 4, "dy": -2, "buttons": 1}  # dragging turns the hand
    {"type": "wheel", "dy": -100}                   # the wheel raises or lowers the hand
"""

from __future__ import annotations

import math

import numpy as np

from bigym.teleop.command import TeleopCommand
from bigym.teleop.devices.base import LEFT, PRECISION, RIGHT, Device, DeviceEventError, number

#: hand motion keys: code -> (axis 0-2 of the translation, sign)
MOVE_KEYS = {"KeyW": (0, 1), "KeyS": (0, -1), "KeyA": (1, 1), "KeyD": (1, -1), "KeyR": (2, 1), "KeyF": (2, -1)}
#: hand rotation keys: code -> (axis of the rotation: 0 roll, 1 pitch, 2 yaw, sign)
TURN_KEYS = {"KeyU": (0, -1), "KeyO": (0, 1), "KeyI": (1, 1), "KeyK": (1, -1), "KeyJ": (2, 1), "KeyL": (2, -1)}
#: base keys: code -> (0 forward, 1 left, 2 up, 3 yaw, sign)
BASE_KEYS = {
    "ArrowUp": (0, 1), "ArrowDown": (0, -1), "Comma": (1, 1), "Period": (1, -1),
    "PageUp": (2, 1), "PageDown": (2, -1), "ArrowLeft": (3, 1), "ArrowRight": (3, -1),
}  # fmt: skip
#: keys that act once when pressed
SELECT_KEYS = {"Digit1": (LEFT,), "Digit2": (RIGHT,), "Digit3": (LEFT, RIGHT)}
EVENT_KEYS = {"Enter": "keep", "Backspace": "discard", "KeyT": "retry"}
GRIP_KEY, SWITCH_KEY = "Space", "Tab"
PRECISION_KEYS = ("ShiftLeft", "ShiftRight")
#: mouse: radians of hand rotation per pixel dragged, metres of height per wheel unit
TURN_PER_PIXEL = 0.004
LIFT_PER_WHEEL = 0.0002

#: every key this device reads, with what it does (for the help text and the page)
KEY_HELP = {
    "W / S": "hand forward / back", "A / D": "hand left / right", "R / F": "hand up / down",
    "J / L": "turn hand left / right (yaw)", "I / K": "tilt hand down / up (pitch)", "U / O": "roll hand",
    "Space": "close / open the gripper", "Tab": "switch hand", "1 / 2 / 3": "left / right / both hands",
    "Shift": "slow, precise motion", "arrows": "walk forward / back, turn", ", / .": "step left / right",
    "PageUp / PageDown": "stand up / crouch", "Enter": "keep the demo", "Backspace": "discard",
    "T": "retry the same scene", "mouse drag": "turn the hand", "wheel": "hand up / down",
}  # fmt: skip


class KeyboardDevice(Device):
    """A keyboard, with an optional mouse."""

    name = "keyboard"
    event_types = ("keydown", "keyup", "mousemove", "wheel")

    def __init__(self) -> None:
        super().__init__()
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.held: dict[str, float] = {}  # key code -> time it is released (inf: until keyup)
        self.grip = [0.0, 0.0]
        self._grip_changed = [False, False]
        self._events: list[str] = []
        self._mouse_turn = np.zeros(3)
        self._mouse_lift = 0.0

    def handle(self, event: dict) -> None:
        kind = self.check_type(event)
        if kind in ("keydown", "keyup"):
            code = event.get("code")
            if not isinstance(code, str) or not code:
                raise DeviceEventError(f"{kind} event: 'code' must be a key code such as 'KeyW', got {code!r}")
            if kind == "keyup":
                self.held.pop(code, None)
                return
            hold = event.get("hold")
            release = math.inf if hold is None else self.time + max(0.0, number(event, "hold"))
            if code not in self.held:
                self._press(code)
            self.held[code] = release
        elif kind == "mousemove":
            if int(number(event, "buttons", 0)) & 1:
                scale = self._scale()
                self._mouse_turn[2] -= number(event, "dx", 0.0) * TURN_PER_PIXEL * scale
                self._mouse_turn[1] += number(event, "dy", 0.0) * TURN_PER_PIXEL * scale
        else:
            self._mouse_lift -= number(event, "dy", 0.0) * LIFT_PER_WHEEL * self._scale()

    def _press(self, code: str) -> None:
        """What a key does once, when it goes down."""
        if code in SELECT_KEYS:
            self.active = SELECT_KEYS[code]
        elif code == SWITCH_KEY:
            self.active = (RIGHT,) if self.active == (LEFT,) else (LEFT,)
        elif code == GRIP_KEY:
            for side in self.active:
                self.grip[side] = 0.0 if self.grip[side] > 0.5 else 1.0
                self._grip_changed[side] = True
        elif code in EVENT_KEYS:
            self._events.append(EVENT_KEYS[code])

    def _scale(self) -> float:
        return PRECISION if any(k in self.held for k in PRECISION_KEYS) else 1.0

    def command(self, dt: float) -> TeleopCommand:
        velocity, turn, base = np.zeros(3), np.zeros(3), np.zeros(4)
        for code in self.held:
            if code in MOVE_KEYS:
                axis, sign = MOVE_KEYS[code]
                velocity[axis] += sign
            elif code in TURN_KEYS:
                axis, sign = TURN_KEYS[code]
                turn[axis] += sign
            elif code in BASE_KEYS:
                axis, sign = BASE_KEYS[code]
                base[axis] += sign
        scale = self._scale()
        grips = tuple(self.grip[s] if self._grip_changed[s] else None for s in (LEFT, RIGHT))
        command = self.rate_command(dt, velocity * scale, turn * scale, base * scale, grips, tuple(self._events))
        for side in self.active:  # the mouse's motion, as it came
            hand = command.hands[side]
            command.hands[side].rotation = hand.rotation + self._mouse_turn
            command.hands[side].translation = hand.translation + np.array([0.0, 0.0, self._mouse_lift])
        self._mouse_turn = np.zeros(3)
        self._mouse_lift = 0.0
        self._grip_changed = [False, False]
        self._events.clear()
        self.held = {code: until for code, until in self.held.items() if until > self.time + 1e-9}
        return command


__all__ = ["KEY_HELP", "KeyboardDevice"]
