"""The frying pan in one hand and the spatula in the other (scene counter_base_2_hob): what
``SandwichToast``'s and ``SandwichFlip``'s demonstrators both do.

A pan held by its handle turns in the fingers (about the axis they close along when the body
moves, and onto its far edge when let go of mid-air), so the hand's aim is corrected by how
far the pan is off its path and tilted (:class:`HeldSteer`), as a person keeps a pan level by
looking at it, and it is let go of only once set down on the burner. The spatula is carried
about level, clear over the counter, while the body walks.
"""

from __future__ import annotations

import numpy as np

from bigym.experts.cookware import PotHandles
from bigym.experts.expert import HandReference, Script
from bigym.experts.geometry import axis_angle_matrix, clamp
from bigym.experts.grasping import HOLD
from bigym.experts.sandwich import (
    GRIP_WRIST,
    GRIP_WRIST_COST,
    OVER_BLADE,
    PUSH_ARM,
    PUSH_ARM_COST,
    TIP,
    SandwichRemoveExpert,
)
from bigym.robot.h1 import ARM_JOINTS

#: the hob's cabinet and the burner the pan stands on
HOB = "cabinet_1"
BURNER = "hob_site_1"
#: the counter's front edge (x) and top (z)
COUNTER_FRONT = 0.48
COUNTER_TOP = 0.86
#: the spatula carried about level (the tip a little up): its blade's middle raised this far
#: (m), to at least this high, and drawn back this far
STOW_PITCH = np.deg2rad(-10.0)
STOW_RISE = 0.1
STOW_BACK = 0.08
STOW_HEIGHT = 1.06
#: how fast the blade's aim is corrected by what its tip misses (1/s)
STEER_GAIN = 6.0
#: how fast a held pan's tilt is corrected (1/s)
LEVEL_GAIN = 3.0
HEADING_GAIN = 1.5
#: the most (m) a held pan's aim is corrected
MAX_HELD_AIM = 0.04


class HeldSteer:
    """Keeps a held body on a path, as a person watching it does: the hand's aim is
    corrected by what the body misses, and (``level``) the hand turns by how far the body's
    z axis is off :attr:`up` (world up: held level; tipped: held tilted that way),
    (``heading``) and about the vertical until the body's x axis points that way. Call
    :meth:`update` once per control step."""

    def __init__(self, expert: SpatulaAndPan, side: int, body: int) -> None:
        self.expert, self.body = expert, body
        self.offset = expert.held_offset(side, body)
        _, self.r0 = expert.hand_pose(side)
        self.aim = np.zeros(3)
        self.turn = np.eye(3)
        self.level = False
        #: with ``level``: where the body's z axis is turned to (world up: held level)
        self.up = np.array([0.0, 0.0, 1.0])
        self.heading: float | None = None
        here = expert.data.xpos[body].copy()
        self.path = lambda t: here
        expert.hands[side] = HandReference(
            lambda t: self.path(t) + self.turn @ self.offset + self.aim, lambda t: self.turn @ self.r0, HOLD, tremor=0.2
        )

    def update(self) -> None:
        e = self.expert
        frame = e.data.xmat[self.body].reshape(3, 3)
        miss = self.path(e.time) - e.data.xpos[self.body]
        self.aim = clamp(self.aim + STEER_GAIN * e.dt * miss, MAX_HELD_AIM)
        if self.heading is not None:
            error = float(np.angle(np.exp(1j * (self.heading - np.arctan2(frame[1, 0], frame[0, 0])))))
            self.turn = axis_angle_matrix(np.array([0.0, 0.0, 1.0]), HEADING_GAIN * e.dt * error) @ self.turn
        if self.level:
            axis = np.cross(frame[:, 2], self.up)
            angle = float(np.arcsin(min(1.0, np.linalg.norm(axis))))
            if angle > 1e-4:
                self.turn = axis_angle_matrix(axis, LEVEL_GAIN * e.dt * angle) @ self.turn


class SpatulaAndPan(SandwichRemoveExpert, PotHandles):
    """The spatula's skills (:class:`~bigym.experts.sandwich.SandwichRemoveExpert`) and a pan
    held by its handle on a path (:attr:`held_steer`, ``None`` while no hand holds it)."""

    held_steer: HeldSteer | None = None

    def tip(self) -> np.ndarray:
        pos, rot = self.spatula_frame()
        return pos + rot @ TIP

    def sweep_posture(self, side: int) -> None:
        posture = np.array([*(PUSH_ARM[j] for j in ARM_JOINTS[:-1]), GRIP_WRIST])
        cost = np.array([PUSH_ARM_COST] * (len(ARM_JOINTS) - 1) + [GRIP_WRIST_COST])
        self.arm_posture[side] = (posture, cost)

    def steer_held(
        self,
        side: int,
        body: int,
        path,
        duration: float,
        settle: float = 0.3,
        level: bool = False,
        heading: float | None = None,
    ) -> Script:
        """Move the held body's origin along ``path(x)`` (x from 0 to 1) as a :class:`HeldSteer`
        does, which then goes on holding it at the path's end."""
        steer = self.held_steer if self.held_steer is not None else HeldSteer(self, side, body)
        self.held_steer = steer
        steer.level, steer.heading = level, heading
        t0 = self.time

        def progress(t: float) -> float:
            return self.human.profile(min(max((t - t0) / duration, 0.0), 1.0))

        steer.path = lambda t: path(progress(t))
        while self.time < t0 + duration + settle:
            yield
            steer.update()

    def stow_spatula(self, side: int, aside: np.ndarray | None = None) -> float:
        """Raise the spatula, turned level (its tip a little up), to be carried about clear
        over the counter, moved ``aside`` (m, world) out of the other hand's way; returns
        when it is there."""
        pos, rot = self.spatula_frame()
        along = np.array([rot[0, 1], rot[1, 1], 0.0])
        level = self.spatula_rotation(along, STOW_PITCH)
        blade = pos + rot @ OVER_BLADE
        spot = np.array([blade[0], blade[1], max(float(blade[2]) + STOW_RISE, STOW_HEIGHT)]) - along * STOW_BACK
        if aside is not None:
            spot = spot + aside
        p, r = self.hand_for(spot - level @ OVER_BLADE, level)
        return self.move_hand(side, p, r, HOLD, precision=0.03, spread=0.3)

    def set_pan_down(self, side: int, body: int, start: np.ndarray, spot: np.ndarray) -> Script:
        """From ``start`` down onto the burner at ``spot``, level, and let go (let go of
        above it, a pan held by its handle would tip onto its far edge and the sandwich
        slide to the wall)."""
        down = spot + np.array([0.0, 0.0, 0.004])
        yield from self.steer_held(side, body, lambda x: start + x * (down - start), 1.2, 0.2, True)
        sunk = spot - np.array([0.0, 0.0, 0.005])
        yield from self.steer_held(side, body, lambda x: down + x * (sunk - down), 0.4, 0.1, True)
        self.held_steer = None
        self.hold_hand(side, HOLD, tremor=0.2)
        yield from self.release(side, back=0.06, up=0.05)


__all__ = ["HeldSteer", "SpatulaAndPan"]
