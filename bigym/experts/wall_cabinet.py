"""The glass wall cabinet above the counter beside the dishwasher, and the dishwasher, as the
long unloading tasks use them (scene counter_dishwasher_wall_cabinet).

A person puts a thing away into the wall cabinet through one of its two doors: the door
over the half the thing goes into. Standing in front of the counter they hold it up at
the chest, reach up into the cabinet, let go and draw the hand straight back out; then
they push the door shut (and the other one if an elbow nudged it open on the way), step
back to the dishwasher's side and close its tray and its door.

Shared by :mod:`bigym.experts.dishwasher_unload_plates_long` and
:mod:`bigym.experts.dishwasher_unload_cups_long`.
"""

from __future__ import annotations

import numpy as np

from bigym.experts.cupboards import CupboardExpert
from bigym.experts.dishwasher import DishwasherExpert
from bigym.experts.dishwasher_cutlery import CARRY_HEIGHT, ROUND_THE_DOOR_X
from bigym.experts.expert import LEFT, Script
from bigym.experts.grasping import GRASP, HOLD

CABINET = "wall_cabinet"
DOORS = ("door_left", "door_right")
#: a cabinet door open further than this (normalised) is pushed shut (the task wants both
#: within 0.1 of closed)
DOOR_SHUT = 0.05
#: how far (m) to the hand's side of where the held thing goes the pelvis stands in front
#: of the cabinet, and how high
CABINET_LATERAL = 0.1
STANDING = 1.03
#: where a held thing is carried (pelvis frame, m; y towards the holding hand's side) on
#: the way to the cabinet: up at the chest, its lower end over the counter's height, so
#: that it passes over the counter's front as the body steps up to it
HOLD_AT = np.array([0.28, 0.15, 0.15])
#: the IK's orientation costs of a hand reaching into the cabinet: the pitch (about the
#: fingers' closing axis) is held more loosely, the IK trading some of it for reach
IN_HOLD = np.array([4.0, 1.0, 4.0])
#: where (x, m) the open hand draws back to after letting go: out of the cabinet, clear of
#: the door handles
OUT_X = 0.45


class WallCabinetSkills(CupboardExpert, DishwasherExpert):
    """The wall cabinet's doors and halves, carrying a thing to it, and closing the cabinet
    and the dishwasher at the end."""

    def cabinet_middle(self) -> float:
        return float(self.data.xpos[self.env.props[CABINET].root_body_id][1])

    def door_of_half(self, half: float) -> str:
        """The cabinet door that covers the ``half`` (+1: +y) of its front."""
        middle = self.cabinet_middle()
        for key in DOORS:
            if np.sign(float(self.site(CABINET, f"{key}_handle")[1]) - middle) == half:
                return key
        raise ValueError(f"no door on the {half:+.0f} half of the cabinet")

    def walk_to_cabinet(self, side: int, y: float, stance_x: float, hold_speed: float = 1.0) -> Script:
        """Stand up stepping back, the held thing up at the chest (``HOLD_AT``, brought there
        ``hold_speed`` times as fast as a free movement), walk back round the dishwasher
        door to ``stance_x`` in front of the cabinet, the hand's side of the body at ``y``."""
        base = self.commanded_base()
        yield from self.walk([(base[0] - 0.1, base[1], CARRY_HEIGHT, base[3])], carrying=(side,))
        base = self.base_pose()
        goal = HOLD_AT * np.array([1.0, 1.0 if side == LEFT else -1.0, 1.0]) + self.human.jitter(0.02, 3)
        held = self.move_hand_with_body(side, goal, HOLD, base, speed=hold_speed)
        lateral = CABINET_LATERAL if side == LEFT else -CABINET_LATERAL
        stance = (
            stance_x + self.human.jitter(0.02),
            y - lateral + self.human.jitter(0.02),
            STANDING + self.human.jitter(0.01),
            self.human.jitter(0.04),
        )
        route = [
            (ROUND_THE_DOOR_X + self.human.jitter(0.04), stance[1] + 0.25, CARRY_HEIGHT, -0.4),
            stance,
        ]
        arrival = yield from self.walk(route, wait=False)
        yield from self.until(max(arrival, held))

    def pinch_for(self, side: int, body: int, origin: np.ndarray, rotation: np.ndarray) -> np.ndarray:
        """Where the pinch point goes for the held body's origin to be at ``origin`` with
        the hand turned to ``rotation``: the body turns with the hand (the pads hold it)."""
        hand = self.data.site_xmat[self.env.robot.pinch_site_ids[side]].reshape(3, 3)
        return origin + rotation @ hand.T @ self.held_offset(side, body)

    def turned_in_hand(self, side: int, body: int, turn: np.ndarray, shift: np.ndarray) -> np.ndarray:
        """Where the pinch point goes to turn the held body by ``turn`` about its own origin
        and move it by ``shift``: the body turns with the hand about the pinch point, so the
        hand moves as the turn requires."""
        p, _ = self.hand_pose(side)
        held = self.data.site_xpos[self.env.robot.pinch_site_ids[side]] - self.data.xpos[body]
        return p + shift + (turn - np.eye(3)) @ held

    def let_go_inside(self, side: int) -> Script:
        """Let go of what the hand put down in the cabinet, draw the open hand straight back
        out (not along the hand, which the corrections may have left turned: the open
        fingers caught the other door's handle) and relax the arm."""
        self.hold_hand(side, IN_HOLD, tremor=0.2)
        yield from self.wait(0.1)
        yield from self.set_grip(side, 0.0, max_wait=0.6, min_wait=0.3)
        p, r = self.hand_pose(side)
        back = p - np.array([float(p[0]) - OUT_X, 0.0, 0.0])
        yield from self.until(self.move_hand(side, back, r, GRASP * 0.5, spread=0.1, tremor=0.5))
        self.relax_arm(side)

    def close_up(self, door: str, tray: str) -> Script:
        """Push the cabinet door shut (the one opened, then the other if an elbow nudged it
        open on the way), step back to the dishwasher's side, push ``tray`` in and shut
        its door."""
        for key in (door, *(k for k in DOORS if k != door)):
            if self.joint_state(CABINET, key) > DOOR_SHUT:
                yield from self.door(self.door_side(CABINET, key), CABINET, key, 0.0)
        self.note("cabinet shut")
        base = self.commanded_base()
        yield from self.walk([(base[0] - 0.1, -0.62 + self.human.jitter(0.03), base[2], 0.35)])
        near = self.work_from_side()
        yield from self.tray(near, tray, 0.0)
        self.note("tray in")
        yield from self.dishwasher_door(near, 0.0)
        self.note("door shut")


__all__ = ["CABINET", "DOORS", "WallCabinetSkills"]
