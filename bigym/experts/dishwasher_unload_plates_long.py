"""DishwasherUnloadPlatesLong demonstrator (scene counter_dishwasher_wall_cabinet): open one
door of the glass wall cabinet, take the plate out of the dishwasher's bottom tray, stand
it in the dish drainer inside the cabinet, shut the door, then push the tray in and close
the dishwasher.

A person opens the cabinet door first, while both hands are free, on the side where the
plate will go; takes the plate by the top of its rim as :mod:`bigym.experts.dishwasher_plates`
does (round the open dishwasher door to the front of the pulled-out tray, crouching); walks
back round the door holding it up at the chest; in front of the cabinet turns the hand to
point up into it, raises the plate in front of the cabinet's front, lines it up with its
slot, slides it in over the drainer's base (the slots are open along the drainer's depth:
the plate passes between the front row of holders), lowers it in and lets go; draws the
hand straight back out, shuts the door with a push (and the other one, if an elbow nudged
it open), and closes the dishwasher from beside its door as :mod:`bigym.experts.dishwasher`
does (the cabinet and closing skills are :mod:`bigym.experts.wall_cabinet`'s, shared with
the mug of ``DishwasherUnloadCupsLong``).

What makes it work (measured with the dev scripts of the closing note):

* **The plate turns with the hand.** The pads hold the rim firmly enough (their torsional
  friction) that the plate turns with the hand about the fingers' closing axis: with the
  hand pointing up into the cabinet the plate is held out ahead of the fingers. So the
  hand goes where the plate must go plus how it sits in the fingers (:meth:`pinch_for`),
  and it is turned low in front of the cabinet, before the plate goes up: turned on the
  way up, the plate swung forward into the cabinet's bottom.
* **In under the shelf, not down from above.** The cabinet's lower compartment is 0.33 m
  high; a plate standing in the drainer reaches to 7 cm under the shelf over it, so a hand
  cannot bring it down from above. It slides in 4 cm over its rest, between the holders,
  and is lowered in (lifted and moved again if it sticks, as in ``slot_in``).
* **Lined up by eye, twice.** The IK leaves the hand some degrees off, and a slot takes a
  plate only within 7 mm (less as it leans): the plate is turned square to its slot and
  moved across by what is seen in front of the cabinet, and again just short of the front
  row of holders (the arm turns the hand a little as it reaches out). Lined up only in
  front of the cabinet, the plate caught the holders on its way in in 3 of the 7 seeds of
  0-7 that got there.
* **One door, and straight back out.** The hand and the plate go in through the open
  door's half, clear of the closed door's edge and of the side wall (``SLOT_WINDOW``); the
  open hand draws straight back (along the hand, which the corrections leave turned, the
  fingers caught the closed door's handle and pulled it open).

Choices drawn per demo: which half of the cabinet (and so which door and which hand), the
slot, the stances, the crouch, the timing and every path's via-points.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.experts.dishwasher_plates import (
    DRAINER,
    PLATES_BODY_ON_PLAN,
    RAISE_SPEED,
    RESEAT_LIFT,
    RESEATS,
    STRAIGHT,
    STUCK,
    PlateUnloadExpert,
)
from bigym.experts.expert import LEFT, RIGHT, SIDE_NAMES, Script
from bigym.experts.geometry import aligning_rotation, frame_from_axes
from bigym.experts.grasping import LANDED
from bigym.experts.move_plates import LAND
from bigym.experts.wall_cabinet import CABINET, IN_HOLD, WallCabinetSkills

#: across the open door's half (distance (m) of a slot from the cabinet's middle, y): the
#: hand and the plate pass clear of the closed door's edge and of the side wall
SLOT_WINDOW = (0.07, 0.21)
#: where (x, m) the pelvis stands to reach into the cabinet
CABINET_STANCE_X = 0.17
#: where (x, m) the plate's middle is raised in front of the cabinet before it goes in (its
#: rim clear of the cabinet's front), how high (m) it is turned towards the cabinet before
#: that (under the cabinet's bottom), and how far over its rest (m) the plate
#: slides in (its lower rim clear of the drainer's base)
RAISE_X = 0.48
UNDER_CABINET = 1.25
SLIDE_OVER = 0.04
#: how far (m) in front of the drainer's middle its front row of holders stands, and how
#: far (m) short of it the plate's rim stops to be lined up again
FRONT_ROW = 0.05
BEFORE_ROW = 0.02
#: how many times at most the plate is lined up with its slot (in front of the cabinet,
#: and again short of the holders), and how far off (m, y) it may be
LINE_UP_TRIES = 3
LINED_UP = 0.003
#: how far (rad) the hand points up into the cabinet (the arm reaches up to the plate's
#: height)
IN_PITCH = 0.35


class PlateCabinetExpert(PlateUnloadExpert, WallCabinetSkills):
    """Moves the plate of ``DishwasherUnloadPlatesLong`` into the wall cabinet's drainer and
    closes everything."""

    tasks = ("DishwasherUnloadPlatesLong",)
    pace: ClassVar[dict[str, float]] = {"DishwasherUnloadPlatesLong": 1.2}

    def plan(self) -> Script:
        env = self.env
        plate = env.items[0]
        yield from self.wait(self.human.reaction())
        half, slot = self.choose_slot()
        side = LEFT if half > 0 else RIGHT
        door = self.door_of_half(half)
        door_hand = self.door_side(CABINET, door)
        self._note_hand(f"{CABINET}/{door}", door_hand)
        self.choices["plate hand"] = SIDE_NAMES[side]
        self.choices["slot"] = slot
        yield from self.door(door_hand, CABINET, door, 1.0)
        self.note("cabinet open")
        yield from self.walk_to_tray({side: plate})
        yield from self.take_until_held(side, plate)
        default_cost = dict(self.base_cost)
        self.base_cost.update(PLATES_BODY_ON_PLAN)
        yield from self.walk_to_cabinet(side, float(self.site_of(self.env.props[DRAINER], slot)[1]), CABINET_STANCE_X)
        self.note("at cabinet")
        yield from self.slide_in(side, plate, slot)
        self.note("placed")
        self.base_cost = default_cost
        yield from self.close_up(door, "tray_bottom")
        while True:
            yield

    # ------------------------------------------------------------------ choices
    def choose_slot(self) -> tuple[float, str]:
        """A half of the cabinet (+1: +y) and a slot of the drainer in it that the hand
        reaches through that half's door (``SLOT_WINDOW``)."""
        drainer = self.env.props[DRAINER]
        middle = self.cabinet_middle()
        options = []
        for key in drainer.slot_keys:
            across = float(self.site_of(drainer, key)[1]) - middle
            if SLOT_WINDOW[0] <= abs(across) <= SLOT_WINDOW[1]:
                options.append((float(np.sign(across)), key))
        half = float(options[int(self.rng.integers(len(options)))][0])
        slots = [key for h, key in options if h == half]
        return half, slots[int(self.rng.integers(len(slots)))]

    # ------------------------------------------------------------------ moves
    def into_cabinet(self, side: int) -> np.ndarray:
        """The hand pointing into the cabinet, a little up (``IN_PITCH``), closing across
        the plate's face (along world y, the sign it closes with now)."""
        closing = np.array([0.0, 1.0, 0.0])
        if self.hand_pose(side)[1][:, 1] @ closing < 0.0:
            closing = -closing
        approach = np.array([np.cos(IN_PITCH), 0.0, np.sin(IN_PITCH)])
        return frame_from_axes(np.cross(closing, approach), approach)

    def line_up(self, side: int, body: int, goal: np.ndarray) -> Script:
        """Turn the held plate square to the slot at ``goal`` and move it across over it, by
        what the eye sees (the IK leaves the hand some degrees off), at most
        ``LINE_UP_TRIES`` times; the plate's origin stays where it is along the slot and in
        height (the hand moves as the turn requires)."""
        for _ in range(LINE_UP_TRIES):
            normal = self.data.xmat[body].reshape(3, 3)[:, 2]
            square = np.array([0.0, np.sign(normal[1]) or 1.0, 0.0])
            tilt = float(np.arccos(np.clip(normal @ square, -1.0, 1.0)))
            off = float(self.fit_error(body, goal)[1])
            if tilt <= STRAIGHT and abs(off) <= LINED_UP:
                break
            self.note(f"line up {'LR'[side]} {np.degrees(tilt):.0f} {off * 1000:.0f}")
            turn = aligning_rotation(normal, square) if tilt > STRAIGHT else np.eye(3)
            _, r = self.hand_pose(side)
            target = self.turned_in_hand(side, body, turn, np.array([0.0, -off, 0.0]))
            end = self.move_hand(side, target, turn @ r, IN_HOLD, spread=0.0, precision=0.004, speed=0.5)
            yield from self.until(end + 0.1)

    def slide_in(self, side: int, plate: str, slot: str) -> Script:
        """Raise the held plate in front of the cabinet, line it up with ``slot``, slide it
        in over the drainer's base, lower it in and let go."""
        self.note(f"place {'LR'[side]}")
        body = self.env.props[plate].root_body_id
        origin = self.data.xpos[body]
        goal = self.site_of(self.env.props[DRAINER], slot) + self.slot_offset
        rotation = self.into_cabinet(side)
        over = goal + np.array([0.0, 0.0, SLIDE_OVER])
        # turned towards the cabinet low in front of it, then raised straight up in front
        # of its front: the plate turns with the hand, and a plate turned on the way up
        # swings forward into the cabinet's bottom
        front = RAISE_X + self.human.jitter(0.02)
        for height in (UNDER_CABINET, float(over[2])):
            goal_origin = np.array([front, over[1], height])
            end = self.move_hand(
                side, self.pinch_for(side, body, goal_origin, rotation), rotation, IN_HOLD, speed=RAISE_SPEED
            )
            yield from self.until(end)
        short = float(goal[0]) - FRONT_ROW - self.env.props[plate].radius - BEFORE_ROW
        yield from self.line_up(side, body, goal)
        # in up to the front row of holders, lined up again (the arm turns the hand a
        # little as it reaches out, and a plate leaning by a few degrees has its lower rim
        # off the slot), then in over the slot
        for x in (short, float(goal[0])):
            p, r = self.hand_pose(side)
            shift = np.array([x - float(origin[0]), 0.0, float(over[2] - origin[2])])
            end = self.move_hand(side, p + shift, r, IN_HOLD, spread=0.0, precision=0.004, speed=0.4, tremor=0.3)
            yield from self.until(end + 0.15)
            if x == short:
                yield from self.line_up(side, body, goal)
        # over the slot: moved onto it by what is seen, lowered in; one that sticks on the
        # holders is lifted a little, moved and lowered again (as in ``slot_in``)
        for attempt in range(RESEATS + 1):
            off = self.fit_error(body, goal)
            p, r = self.hand_pose(side)
            end = self.move_hand(side, p - np.append(off, 0.0), r, IN_HOLD, spread=0.0, precision=0.004, speed=0.5)
            yield from self.until(end + 0.1)
            depth = float(origin[2] - goal[2]) + LAND
            yield from self.lower_until(side, r, depth, 0.3, lambda: origin[2] <= goal[2] + LANDED)
            if origin[2] <= goal[2] + STUCK or attempt == RESEATS:
                break
            self.note(f"reseat {'LR'[side]}")
            p, r = self.hand_pose(side)
            end = self.move_hand(side, p + np.array([0.0, 0.0, RESEAT_LIFT]), r, IN_HOLD, spread=0.0, speed=0.5)
            yield from self.until(end + 0.1)
        yield from self.let_go_inside(side)


__all__ = ["PlateCabinetExpert"]
