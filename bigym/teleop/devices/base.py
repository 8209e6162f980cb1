"""The one interface every input device implements, and what rate devices share.

A device receives *raw events* (JSON-able dicts: what a browser page, a window's key
callback or a hardware reader produced, in that device's own terms) through
:meth:`Device.handle`, and turns them into one :class:`TeleopCommand` per control step
through :meth:`Device.command`. Because raw events are plain dicts, a live session's
input can be recorded and played back exactly (:mod:`bigym.teleop.script`), and the
browser, the window and the tests feed the same code path.

*Rate devices* (keyboard, gamepad, SpaceMouse) ask for velocities; at full deflection
they all move a hand at :data:`HAND_SPEED` and turn it at :data:`HAND_TURN_SPEED`, so a
key held for a second and a stick pushed fully for a second move the hand alike.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.teleop.command import HandCommand, TeleopCommand

#: full-deflection speeds of the rate devices: hand (m/s, rad/s), base (m/s, rad/s, m/s)
HAND_SPEED = 0.25
HAND_TURN_SPEED = 1.0
BASE_SPEED = 0.3
BASE_TURN_SPEED = 0.6
BASE_LIFT_SPEED = 0.15
#: speed factor of the precision mode (e.g. Shift held)
PRECISION = 0.3

LEFT, RIGHT = 0, 1
HAND_NAMES = ("left", "right")


class DeviceEventError(ValueError):
    """A raw event this device cannot read (wrong type, missing or malformed field)."""


class Device:
    """Base class of the input devices: raw events in, one command per control step out."""

    #: the name used on the command line (``--device``)
    name: ClassVar[str] = ""
    #: the raw event types (``event["type"]``) this device reads
    event_types: ClassVar[tuple[str, ...]] = ()

    def __init__(self) -> None:
        self.time = 0.0  # the device's clock: simulated seconds since the episode began
        #: the hands that rate motions move (left, right, or both)
        self.active: tuple[int, ...] = (RIGHT,)

    def reset(self) -> None:
        """A new episode: release everything held, back to the right hand."""
        self.time = 0.0
        self.active = (RIGHT,)

    def handle(self, event: dict) -> None:  # pragma: no cover - subclasses
        raise NotImplementedError

    def command(self, dt: float) -> TeleopCommand:  # pragma: no cover - subclasses
        raise NotImplementedError

    # ------------------------------------------------------------------ helpers
    def check_type(self, event: dict) -> str:
        kind = event.get("type") if isinstance(event, dict) else None
        if kind not in self.event_types:
            raise DeviceEventError(f"the {self.name} device reads {', '.join(self.event_types)} events, got {event!r}")
        return kind

    def rate_command(
        self,
        dt: float,
        velocity: np.ndarray,
        turn: np.ndarray,
        base: np.ndarray,
        grippers: tuple[float | None, float | None] = (None, None),
        events: tuple[str, ...] = (),
    ) -> TeleopCommand:
        """The command of velocities in [-1, 1] of full deflection held for ``dt`` seconds:
        ``velocity``/``turn`` move the active hand(s), ``base`` is (forward, left, up, yaw)."""
        hands = []
        for side in (LEFT, RIGHT):
            moving = side in self.active
            hands.append(
                HandCommand(
                    velocity * (HAND_SPEED * dt) if moving else np.zeros(3),
                    turn * (HAND_TURN_SPEED * dt) if moving else np.zeros(3),
                    grippers[side],
                )
            )
        speeds = np.array([BASE_SPEED, BASE_SPEED, BASE_LIFT_SPEED, BASE_TURN_SPEED])
        self.time += dt
        return TeleopCommand((hands[0], hands[1]), base * speeds * dt, events)


def number(event: dict, key: str, default: float | None = None) -> float:
    """``event[key]`` as a finite float (a clear error otherwise)."""
    value = event.get(key, default)
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise DeviceEventError(f"{event.get('type')} event: {key!r} must be a number, got {value!r}") from None
    if not np.isfinite(value):
        raise DeviceEventError(f"{event.get('type')} event: {key!r} must be finite, got {value!r}")
    return value


def numbers(event: dict, key: str, length: int | None = None, minimum: int = 0) -> np.ndarray:
    """``event[key]`` as a finite float vector (of ``length``, or at least ``minimum`` long)."""
    value = event.get(key)
    try:
        array = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise DeviceEventError(f"{event.get('type')} event: {key!r} must be a list of numbers, got {value!r}") from None
    if (length is not None and array.size != length) or array.size < minimum or not np.all(np.isfinite(array)):
        wanted = f"{length}" if length is not None else f"at least {minimum}"
        raise DeviceEventError(f"{event.get('type')} event: {key!r} must hold {wanted} finite numbers, got {value!r}")
    return array


__all__ = [
    "BASE_LIFT_SPEED",
    "BASE_SPEED",
    "BASE_TURN_SPEED",
    "HAND_SPEED",
    "HAND_TURN_SPEED",
    "PRECISION",
    "Device",
    "DeviceEventError",
    "number",
    "numbers",
]
