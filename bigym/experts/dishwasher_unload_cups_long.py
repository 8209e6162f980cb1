"""DishwasherUnloadCupsLong demonstrator (scene counter_dishwasher_wall_cabinet): open one
door of the glass wall cabinet, take the upside-down mug off the dishwasher's upper tray,
put it on the cabinet's bottom shelf, shut the door, then push the tray in and close the
dishwasher.

A person opens the cabinet door first, while both hands are free, on the side where the
mug will go; takes the mug by its handle as :mod:`bigym.experts.dishwasher_unload_cups`
does (round the open dishwasher door to the front of the pulled-out tray, crouching, the
hand coming down onto the handle's bar tilted towards the mug); walks back round the door
holding it up at the chest, and stops a step further back from the counter than for a
plate; holds the mug up in front of the cabinet, steps in so that it comes over its place
on the shelf, lowers it until it rests on its rim and lets go; draws the hand straight
back out, and shuts the cabinet and the dishwasher as :mod:`bigym.experts.wall_cabinet`
does.

What makes it work (measured with the dev scripts of the closing note):

* **The mug turns with the hand.** Held by the handle's bar it turns with the hand about
  the fingers' closing axis, and near shoulder height the 5-joint arm points the hand up
  (the IK trades the pitch for reach): raised close to the body, the mug tilted by 55-75
  degrees and slipped out of the fingers. So the body stands further back and raises it
  with the arm held further out, where the hand stays nearer its grasping pitch (25
  degrees down), and steps in with the arm as it is (``MUG_STANCE_X``, ``RAISE_AHEAD``).
  Of seeds 0-9 at 500 Hz, 3 succeeded raised close to the body, 5 with the body 10 cm
  back, 7 with it 20 cm back.
* **The door is pushed only just past its stop** (``DOOR_PUSH_PAST``, as a base cabinet's):
  a hand aiming far past a stopped door strains the arm against it, and how it strains
  differs at other control rates: of seeds 0-39, 5 replays at 50, 25 or 20 Hz parted from
  the recording by more than the tolerance while the door was pushed open or shut, 2 with
  the short push (generator success on those seeds 52% -> 57%).
* **Let go only resting.** A mug that touches the shelf tilted by more than ``TILT``
  tipped over when let go; it is lifted, turned straight by what is seen and lowered
  again (``AGAIN`` times at most).

Choices drawn per demo: which half of the cabinet (and so which door and which hand),
where on the shelf, the stances, the crouch, the timing and every path's via-points.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.dishwasher_plates import WALL_SHELF_TOP
from bigym.experts.dishwasher_cutlery import ROUND_THE_DOOR_X
from bigym.experts.dishwasher_unload_cups import NEAREST_X, TRAY_CROUCH, TRAY_REACH, CupUnloadExpert
from bigym.experts.doors import DOOR_PUSH_PAST
from bigym.experts.expert import LEFT, RIGHT, SIDE_NAMES, Script
from bigym.experts.geometry import aligning_rotation, frame_from_axes
from bigym.experts.wall_cabinet import CABINET, IN_HOLD, WallCabinetSkills

#: where on the shelf the mug goes: x of its middle (the shelf runs from 0.68 to 0.98),
#: and how far (m) from the cabinet's middle (y) into the open door's half
SHELF_X = 0.82
ACROSS = (0.1, 0.2)
#: where (x, m) the pelvis stands in front of the cabinet with the mug: well back, so that
#: the arm holds it up further out (see the module docstring)
MUG_STANCE_X = -0.2
#: how far (m) ahead of the pelvis the mug's middle is raised, but no nearer the cabinet
#: than ``RAISE_X_MAX`` (the mug's far side clear of the shelf's front edge at 0.68)
RAISE_AHEAD = 0.82
RAISE_X_MAX = 0.62
#: how far (rad) the hand points down into the cabinet: about its grasping pitch, so the
#: mug is held as it was taken
DOWN_PITCH = 0.4
#: how far (m) over the shelf the mug's rim is carried in
OVER = 0.11
#: a mug resting on the shelf is let go within this tilt (rad) of upside down; one tilted
#: further is lifted, turned straight and lowered again, at most ``AGAIN`` times
TILT = np.deg2rad(35.0)
AGAIN = 2
#: IK costs of the base's deviation from its plan while the mug is held (as for the plates
#: of :mod:`bigym.experts.dishwasher_plates`: a body the IK moves off its plan jerks the
#: held hand when the next step starts from the plan)
MUG_BODY_ON_PLAN = {"x": 5.0, "y": 5.0, "z": 6.0, "rz": 4.0}
#: how fast (x a free movement) the mug is brought up to the chest after the take: a brisk
#: move swung it out of the fingers
HOLD_SPEED = 0.6


class MugCabinetExpert(CupUnloadExpert, WallCabinetSkills):
    """Moves the mug of ``DishwasherUnloadCupsLong`` onto the wall cabinet's bottom shelf and
    closes everything."""

    tasks = ("DishwasherUnloadCupsLong",)
    pace: ClassVar[dict[str, float]] = {"DishwasherUnloadCupsLong": 1.3}

    def plan(self) -> Script:
        mug = self.env.items[0]
        yield from self.wait(self.human.reaction())
        half = 1.0 if self.rng.random() < 0.5 else -1.0
        side = LEFT if half > 0 else RIGHT
        self.first = side  # (``take_mug`` waits for the first hand only)
        door = self.door_of_half(half)
        door_hand = self.door_side(CABINET, door)
        self._note_hand(f"{CABINET}/{door}", door_hand)
        across = half * float(self.rng.uniform(*ACROSS))
        place_y = self.cabinet_middle() + across
        self.choices["mug hand"] = SIDE_NAMES[side]
        self.choices["across"] = round(abs(across), 3)
        yield from self.door(door_hand, CABINET, door, 1.0, push_past=DOOR_PUSH_PAST)
        self.note("cabinet open")
        yield from self.walk_to_mug(mug)
        yield from self.take_mug(side, mug)
        self.note("took")
        default_cost = dict(self.base_cost)
        self.base_cost.update(MUG_BODY_ON_PLAN)
        yield from self.walk_to_cabinet(side, place_y, MUG_STANCE_X, hold_speed=HOLD_SPEED)
        self.note("at cabinet")
        place = np.array([SHELF_X + self.human.jitter(0.02), place_y, WALL_SHELF_TOP])
        yield from self.onto_shelf(side, mug, place)
        self.note("placed")
        self.base_cost = default_cost
        yield from self.close_up(door, "tray_mid")
        while True:
            yield

    def walk_to_mug(self, mug: str) -> Script:
        """Round the dishwasher door's free end to the front of the tray, crouching, the mug's
        handle ahead."""
        base = self.commanded_base()
        handle = self.site(mug, "handle")
        x = min(float(handle[0]) - TRAY_REACH, NEAREST_X) + self.human.jitter(0.02)
        stance = (
            x,
            float(handle[1]) + self.human.jitter(0.03),
            TRAY_CROUCH + self.human.jitter(0.02),
            self.human.jitter(0.05),
        )
        yield from self.walk([(ROUND_THE_DOOR_X, base[1] + 0.2, base[2], 0.5), stance])

    def onto_shelf(self, side: int, mug: str, place: np.ndarray) -> Script:
        """Hold the mug up in front of the cabinet, step in with it over ``place`` (x, y and
        the shelf's top), lower it until it rests on its rim and let go."""
        body = self.env.props[mug].root_body_id
        origin = self.data.xpos[body]
        frame = self.data.xmat[body]
        # the hand pointing into the cabinet, down about as it took the handle, closing as it does
        _, r = self.hand_pose(side)
        closing = r[:, 1].copy()
        closing[2] = 0.0
        closing /= np.linalg.norm(closing)
        approach = np.array([np.cos(DOWN_PITCH), 0.0, -np.sin(DOWN_PITCH)])
        approach -= closing * (approach @ closing)
        rotation = frame_from_axes(np.cross(closing, approach), approach / np.linalg.norm(approach))
        # upside down, a mug's origin (its base) is its height over the rim
        over = place + np.array([0.0, 0.0, self.env.props[mug].height + OVER])
        ahead = min(float(self.base_pose()[0]) + RAISE_AHEAD, RAISE_X_MAX)
        end = self.move_hand(
            side,
            self.pinch_for(side, body, np.array([ahead, over[1], over[2]]), rotation),
            rotation,
            IN_HOLD,
            speed=0.5,
        )
        yield from self.until(end)
        self.note("raised")
        base = self.base_pose()
        step = float(place[0] - origin[0])
        yield from self.walk([(base[0] + step, base[1], base[2], base[3])], carrying=(side,), from_plan=True)
        shelf = self.env.mask(CABINET, "shelf_bottom")

        def resting() -> bool:
            return self.env.touching(self.env.mask(mug), shelf) and -frame[8] >= np.cos(TILT)

        _, r = self.hand_pose(side)
        yield from self.lower_until(side, r, float(origin[2] - over[2]) + OVER + 0.04, 0.4, resting)
        for _ in range(AGAIN):
            if resting():
                break
            self.note("again")
            down = self.data.xmat[body].reshape(3, 3)[:, 2]
            turn = aligning_rotation(down, np.array([0.0, 0.0, -1.0]))
            _, r = self.hand_pose(side)
            target = self.turned_in_hand(side, body, turn, np.array([0.0, 0.0, 0.03]))  # lifted 3 cm
            end = self.move_hand(side, target, turn @ r, IN_HOLD, spread=0.0, precision=0.004, speed=0.5)
            yield from self.until(end + 0.1)
            _, r = self.hand_pose(side)
            yield from self.lower_until(side, r, 0.06, 0.4, resting)
        yield from self.let_go_inside(side)


__all__ = ["MugCabinetExpert"]
