"""SpaceMouse (3Dconnexion): the puck moves and turns the active hand in all six axes.

Raw events are the puck's state, axes in [-1, 1] as the reader reports them (x right,
y away from the person, z up; roll, pitch, yaw about those axes) and its two buttons::

    {"type": "spacemouse", "axes": [x, y, z, roll, pitch, yaw], "buttons": [left, right]}

Mapping: the puck's translation moves the active hand (pushing it away moves the hand
forward), its rotation turns the hand about the same axes; the left button closes or
opens the active hand's gripper, the right button switches hands. Keep, discard and
retry come from the keyboard or the page's buttons (the puck has only two buttons).

:class:`SpaceMouseReader` reads a real puck through ``pyspacemouse`` (``pip install
pyspacemouse``; it needs the hidapi library and access to the USB device).
"""

from __future__ import annotations

import numpy as np

from bigym.teleop.command import TeleopCommand
from bigym.teleop.devices.base import LEFT, RIGHT, Device, numbers

#: puck deflections below this count as rest (the puck never rests exactly at 0)
DEADZONE = 0.05


class SpaceMouseDevice(Device):
    """A 6-axis SpaceMouse."""

    name = "spacemouse"
    event_types = ("spacemouse",)

    def __init__(self) -> None:
        super().__init__()
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.axes = np.zeros(6)
        self.buttons = np.zeros(2)
        self.grip = [0.0, 0.0]
        self._grip_changed = [False, False]

    def handle(self, event: dict) -> None:
        self.check_type(event)
        axes = np.clip(numbers(event, "axes", length=6), -1.0, 1.0)
        buttons = numbers(event, "buttons", minimum=2)[:2]
        pressed = (buttons > 0.5) & ~(self.buttons > 0.5)
        if pressed[0]:
            for side in self.active:
                self.grip[side] = 0.0 if self.grip[side] > 0.5 else 1.0
                self._grip_changed[side] = True
        if pressed[1]:
            self.active = (RIGHT,) if self.active == (LEFT,) else (LEFT,)
        self.axes = np.where(np.abs(axes) < DEADZONE, 0.0, axes)
        self.buttons = buttons

    def command(self, dt: float) -> TeleopCommand:
        x, y, z, roll, pitch, yaw = self.axes
        # the person's frame (x right, y away, z up) in the robot's heading frame (x forward, y left, z up)
        velocity = np.array([y, -x, z])
        turn = np.array([pitch, -roll, yaw])
        grips = tuple(self.grip[s] if self._grip_changed[s] else None for s in (LEFT, RIGHT))
        self._grip_changed = [False, False]
        return self.rate_command(dt, velocity, turn, np.zeros(4), grips)


class SpaceMouseReader:
    """Polls a connected SpaceMouse through ``pyspacemouse``; yields raw events."""

    def __init__(self) -> None:
        try:
            import pyspacemouse
        except ImportError as error:
            raise RuntimeError(
                "reading a SpaceMouse needs pyspacemouse: pip install pyspacemouse (and the hidapi library)"
            ) from error
        self._module = pyspacemouse
        opened = pyspacemouse.open()
        if not opened:
            raise RuntimeError("no SpaceMouse found (is it plugged in, and may this user read its USB device?)")
        self._device = opened if hasattr(opened, "read") else pyspacemouse

    def poll(self) -> dict:
        """The puck's current state as a raw event."""
        state = self._device.read()
        axes = [float(getattr(state, k)) for k in ("x", "y", "z", "roll", "pitch", "yaw")]
        buttons = [float(b) for b in list(getattr(state, "buttons", []))[:2]] + [0.0, 0.0]
        return {"type": "spacemouse", "axes": axes, "buttons": buttons[:2]}


__all__ = ["SpaceMouseDevice", "SpaceMouseReader"]
