"""What an input device asks of the robot over one control step.

Every device, whatever its raw events (keys, sticks, a 6-axis puck, tracked VR
controllers), produces the same :class:`TeleopCommand` per control step: for each hand a
small rigid motion (a translation in metres and a rotation vector in radians) and
possibly a new gripper command, a motion of the base, and session events. Motions are
expressed in the robot's *heading frame*: x forward, y to the robot's left, z up, turning
with the base's yaw, so "forward" means the same thing wherever the robot faces.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: what a person can ask of the recording session (besides moving the robot)
SESSION_EVENTS = ("keep", "discard", "retry")


@dataclass
class HandCommand:
    """One hand's motion over a step, in the heading frame."""

    translation: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rotation: np.ndarray = field(default_factory=lambda: np.zeros(3))  # rotation vector (rad)
    gripper: float | None = None  # None keeps the current command; 0 open .. 1 closed

    def is_still(self) -> bool:
        return not (np.any(self.translation) or np.any(self.rotation)) and self.gripper is None


@dataclass
class TeleopCommand:
    """Both hands (left, right), the base and session events, for one control step."""

    hands: tuple[HandCommand, HandCommand] = field(default_factory=lambda: (HandCommand(), HandCommand()))
    #: forward, left, up (m) and yaw (rad, counter-clockwise) in the heading frame
    base: np.ndarray = field(default_factory=lambda: np.zeros(4))
    events: tuple[str, ...] = ()

    @staticmethod
    def combine(commands: list[TeleopCommand]) -> TeleopCommand:
        """Several devices used together: motions add up, the last gripper command wins."""
        if len(commands) == 1:
            return commands[0]
        hands = []
        for side in (0, 1):
            parts = [c.hands[side] for c in commands]
            grips = [p.gripper for p in parts if p.gripper is not None]
            hands.append(
                HandCommand(
                    sum((p.translation for p in parts), np.zeros(3)),
                    sum((p.rotation for p in parts), np.zeros(3)),
                    grips[-1] if grips else None,
                )
            )
        events = tuple(e for c in commands for e in c.events)
        return TeleopCommand((hands[0], hands[1]), sum((c.base for c in commands), np.zeros(4)), events)


__all__ = ["SESSION_EVENTS", "HandCommand", "TeleopCommand"]
