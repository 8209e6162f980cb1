"""VR controllers (WebXR): each controller moves its hand while its grip button is held.

Raw events are what a WebXR page reads each frame, in the session's ``local-floor``
reference space (metres; x right, y up, -z ahead of where the person first looked) and
the ``xr-standard`` gamepad layout of each controller::

    {"type": "xr", "controllers": [
        {"hand": "left", "position": [x, y, z], "orientation": [qx, qy, qz, qw],
         "buttons": [trigger, squeeze, touchpad, stick, x_or_a, y_or_b], "axes": [tx, ty, sx, sy]},
        ...]}

Mapping, like holding the robot's hands: while a controller's grip (squeeze) is held, its
hand follows the controller's motion one to one (translation and rotation, turned into
the robot's heading frame); let go to re-centre your arm, grip again to go on (a
clutch). The trigger closes the gripper as far as it is pulled. Left stick: walk; right
stick: turn (x) and crouch or stand (y). A: keep the demo, B: discard it, X: retry.
"""

from __future__ import annotations

import mujoco
import numpy as np

from bigym.experts.geometry import rotation_log
from bigym.teleop.command import HandCommand, TeleopCommand
from bigym.teleop.devices.base import (
    BASE_LIFT_SPEED,
    BASE_SPEED,
    BASE_TURN_SPEED,
    HAND_NAMES,
    Device,
    DeviceEventError,
    numbers,
)

#: rows: the robot's heading axes (forward, left, up) in WebXR's (x right, y up, z back)
XR_TO_ROBOT = np.array([[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
TRIGGER, SQUEEZE, TOUCHPAD, STICK, LOWER, UPPER = range(6)
#: squeeze pressed beyond this engages the clutch
CLUTCH = 0.5
STICK_DEADZONE = 0.15
TRIGGER_STEP = 0.02
#: button events: (hand, button) -> session event
EVENT_BUTTONS = {("right", LOWER): "keep", ("right", UPPER): "discard", ("left", LOWER): "retry"}


def xr_rotation(quaternion_xyzw: np.ndarray) -> np.ndarray:
    """A WebXR orientation (x, y, z, w) as a rotation matrix in the robot's heading frame."""
    wxyz = np.array([quaternion_xyzw[3], *quaternion_xyzw[:3]], float)
    norm = np.linalg.norm(wxyz)
    if norm < 1e-9:
        raise DeviceEventError(f"xr event: orientation {list(quaternion_xyzw)} is not a rotation")
    matrix = np.empty(9)
    mujoco.mju_quat2Mat(matrix, wxyz / norm)
    return XR_TO_ROBOT @ matrix.reshape(3, 3) @ XR_TO_ROBOT.T


class VRDevice(Device):
    """Two tracked VR controllers, one per hand."""

    name = "vr"
    event_types = ("xr",)

    def __init__(self) -> None:
        super().__init__()
        self.reset()

    def reset(self) -> None:
        super().reset()
        self.active = (0, 1)
        #: per hand: the controller's last pose (robot frame) while the clutch is engaged
        self._last: list[tuple[np.ndarray, np.ndarray] | None] = [None, None]
        self._moved = [np.zeros(3), np.zeros(3)]
        self._turned = [np.zeros(3), np.zeros(3)]
        self._grip_sent = [0.0, 0.0]
        self._grip: list[float | None] = [None, None]
        self._buttons = {name: np.zeros(6) for name in HAND_NAMES}
        self._sticks = {name: np.zeros(2) for name in HAND_NAMES}
        self._events: list[str] = []

    def handle(self, event: dict) -> None:
        self.check_type(event)
        controllers = event.get("controllers")
        if not isinstance(controllers, list):
            raise DeviceEventError(f"xr event: 'controllers' must be a list, got {controllers!r}")
        for controller in controllers:
            self._controller(controller)

    def _controller(self, controller: dict) -> None:
        if not isinstance(controller, dict) or controller.get("hand") not in HAND_NAMES:
            raise DeviceEventError(f"xr event: each controller needs 'hand': 'left' or 'right', got {controller!r}")
        hand = controller["hand"]
        side = HAND_NAMES.index(hand)
        event = {"type": "xr", **controller}
        buttons = np.pad(numbers(event, "buttons", minimum=2)[:6], (0, 6))[:6]
        axes = np.pad(numbers(event, "axes"), (0, 4))[:4] if "axes" in controller else np.zeros(4)
        pressed = (buttons > 0.5) & ~(self._buttons[hand] > 0.5)
        for button in (LOWER, UPPER):
            name = EVENT_BUTTONS.get((hand, button))
            if name is not None and pressed[button]:
                self._events.append(name)
        self._buttons[hand] = buttons
        self._sticks[hand] = np.array([v if abs(v) > STICK_DEADZONE else 0.0 for v in axes[2:4]])
        trigger = float(np.clip(buttons[TRIGGER], 0.0, 1.0))
        if abs(trigger - self._grip_sent[side]) >= TRIGGER_STEP or (
            trigger in (0.0, 1.0) and trigger != self._grip_sent[side]
        ):
            self._grip[side] = trigger
            self._grip_sent[side] = trigger
        if "position" not in controller or buttons[SQUEEZE] <= CLUTCH:
            self._last[side] = None  # clutch released (or not tracked): the hand stays
            return
        position = XR_TO_ROBOT @ numbers(event, "position", length=3)
        rotation = xr_rotation(numbers(event, "orientation", length=4))
        last = self._last[side]
        if last is not None:
            self._moved[side] += position - last[0]
            self._turned[side] += rotation_log(rotation @ last[1].T)
        self._last[side] = (position, rotation)

    def command(self, dt: float) -> TeleopCommand:
        hands = tuple(HandCommand(self._moved[s], self._turned[s], self._grip[s]) for s in (0, 1))
        self._moved = [np.zeros(3), np.zeros(3)]
        self._turned = [np.zeros(3), np.zeros(3)]
        self._grip = [None, None]
        walk, turn = self._sticks["left"], self._sticks["right"]
        base = np.array(
            [-walk[1] * BASE_SPEED, -walk[0] * BASE_SPEED, -turn[1] * BASE_LIFT_SPEED, -turn[0] * BASE_TURN_SPEED]
        )
        events = tuple(self._events)
        self._events.clear()
        self.time += dt
        return TeleopCommand((hands[0], hands[1]), base * dt, events)


__all__ = ["XR_TO_ROBOT", "VRDevice", "xr_rotation"]
