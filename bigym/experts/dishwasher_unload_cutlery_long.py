"""DishwasherUnloadCutleryLong demonstrator (scene counter_dishwasher_cutlery_cabinet): take
the fork out of the dishwasher's cutlery basket, lay it in the cutlery tray in the top
drawer of the cabinet beside the dishwasher, push the drawer shut, then close the
dishwasher's bottom tray and its door.

A person takes the fork as :mod:`bigym.experts.dishwasher_cutlery` does (round the open
door to the front of the pulled-out tray, crouching, the fork in front of the hand that
takes it), stands up stepping back and walks round the door's free end to the drawer,
holding the fork low in front of the hip; pulls the drawer open with the free hand and
brings that hand back beside the hip (not through the open drawer); stands up lifting the
fork over the drawer's front, steps up to the drawer and lays the fork in the tray the way
it is laid on the counter (stood on its end, tipped over towards the body, let go); pushes
the drawer shut with either hand; and closes the dishwasher from beside its door as
:mod:`bigym.experts.dishwasher` does.

What makes it work (measured with the dev scripts of the closing note):

* **The fork is held where the arm holds it without help from the body.** A top-down
  pinch in front of the chest is out of the arm's comfortable range: the IK pulled the
  body 20-30 cm off its plan to reach it, and the drawer hand then missed the handle.
  Low in front of the hip (``HOLD_AT``) it needs no help.
* **While the fork is held, the body keeps to its plan** (``BODY_ON_PLAN``). The held hand
  moves with the planned body, and a skill that starts from where the IK put the body
  (a reach, a drag) otherwise jerks it by the difference: the fork moved down at over
  1 m/s, which the generator rejects as a drop.
* **The drawer's back half is under the counter top**, so the fork's end is stood in the
  middle of its compartment, and not in the outer compartments (the hand lands it within
  a few cm, and beside those are the drawer's side walls).

Choices drawn per demo: which hand takes the fork (the right one more often), which hand
pushes the drawer shut, the fork's compartment, every stance, crouch, timing and
via-point.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.experts.dishwasher import DishwasherExpert
from bigym.experts.dishwasher_cutlery import (
    CARRY_AHEAD,
    CARRY_HEIGHT,
    ROUND_THE_DOOR_X,
    TRAY,
    TRAY_NEAR,
    CutleryUnloadExpert,
)
from bigym.experts.drawers import DrawerSkills
from bigym.experts.expert import LEFT, RIGHT, SIDE_NAMES, Script
from bigym.experts.geometry import yaw_matrix
from bigym.experts.grasping import HOLD

ITEM = "fork"
CABINET = "cutlery_cabinet"
DRAWER = "drawer_small_4"
#: where the fork is held while walking and while the other hand works the drawer
#: (pelvis frame, m; y towards the holding hand's side)
HOLD_AT = np.array([0.32, 0.3, -0.12])
#: where the fork is held (pelvis frame) to be carried over the open drawer's front
OVER_DRAWER = np.array([0.45, 0.22, 0.0])
#: how much further ahead (m) the held fork goes on its way to ``HOLD_AT``
HOLD_VIA_AHEAD = 0.12
#: how close (m) the pelvis may come to the cabinet's front
CABINET_CLEARANCE = 0.3
#: how high (m) the pelvis stands over the drawer's handle while working it
DRAWER_CROUCH = 0.0
#: how often the right hand takes the fork
RIGHT_HAND_PROBABILITY = 0.6
#: IK costs of the base's deviation from its plan (the default lets the body crouch and
#: lean well away from it to help a hand reach)
BODY_ON_PLAN = {"z": 6.0}
#: how far (m) to the side of the body's middle the fork is, in front of the hand that takes it
FORK_IN_FRONT = 0.12


class CutleryDrawerExpert(CutleryUnloadExpert, DrawerSkills, DishwasherExpert):
    """Moves the fork of ``DishwasherUnloadCutleryLong`` into the drawer's tray and closes
    everything."""

    tasks = ("DishwasherUnloadCutleryLong",)
    pace: ClassVar[dict[str, float]] = {"DishwasherUnloadCutleryLong": 1.3}
    #: laid as on the counter (see :class:`CutleryUnloadExpert`), the fork falls the last
    #: 15-20 degrees onto the tray's floor: its origin moved down at up to 1.05 m/s in the
    #: drawer (a drop from a carrying hand is well over 1.5 m/s)
    drop_speeds: ClassVar[dict[str, float]] = {"fork": 1.1}
    #: the fork alone, laid flat the same way (this task has no knife)
    may_tip: ClassVar[tuple[str, ...]] = ("fork",)
    #: the fork's lower end at its compartment's middle: the drawer's back half is under
    #: the counter top, and the fork is stood upright before it is tipped over
    pivot_ahead: ClassVar[float] = 0.0
    #: not the outer compartments: the hand lands the fork's end within a few cm, and
    #: beside the outer ones are the drawer's side walls
    slots: ClassVar[dict[int, tuple[int, ...]]] = {LEFT: (2, 3), RIGHT: (5, 4)}
    slot_weights: ClassVar[tuple[float, ...]] = (0.7, 0.3)

    def plan(self) -> Script:
        yield from self.wait(self.human.reaction())
        side = self.choose_hand()
        free = 1 - side
        self.relax_arm(free, start=self.time + abs(self.human.jitter(0.15)), joint_space=True)
        yield from self.walk_to_basket(lateral=FORK_IN_FRONT * (1.0 if side == LEFT else -1.0))
        yield from self.take_from_basket(side, ITEM)
        self.note("picked")
        # while the fork is held in the body's frame the body keeps to its plan: the hand
        # moves with the plan, so the body the IK commands must not stray from it
        default_cost = dict(self.base_cost)
        self.base_cost.update(BODY_ON_PLAN)
        yield from self.walk_to_drawer(side)
        self.note("at drawer")
        # never into the cabinet: the feet stay in front of its drawers
        front = self.site(CABINET, f"{DRAWER}_handle") + self.module_facing(CABINET) * 0.035
        self.keep_base_behind(front, self.module_facing(CABINET), CABINET_CLEARANCE)
        yield from self.drawer(free, CABINET, DRAWER, 1.0, height=DRAWER_CROUCH, relax=False)
        self.hand_to_hip(free)  # back past the drawer's front, not through the open drawer
        self.note("drawer open")
        yield from self.step_to_tray(side)
        yield from self.lay_in_tray(side, ITEM)
        self.note("laid")
        closer = side if self.rng.random() < 0.5 else free
        self.choices["drawer closed by"] = SIDE_NAMES[closer]
        yield from self.drawer(closer, CABINET, DRAWER, 0.0, height=DRAWER_CROUCH)
        self.note("drawer closed")
        self.base_cost = default_cost
        yield from self.walk_to_dishwasher()
        near = self.work_from_side()
        yield from self.tray(near, "tray_bottom", 0.0)
        self.note("tray in")
        yield from self.dishwasher_door(near, 0.0)
        self.note("door shut")
        while True:
            yield

    def choose_hand(self) -> int:
        """Either hand takes the fork (the right one more often)."""
        side = RIGHT if self.rng.random() < RIGHT_HAND_PROBABILITY else LEFT
        self.choices["fork hand"] = SIDE_NAMES[side]
        return side

    def hold_with_body(self, side: int) -> float:
        """The fork hand to ``HOLD_AT`` in front of the chest, where it stays as the body moves."""
        base = self.base_pose()
        goal = HOLD_AT * np.array([1.0, 1.0 if side == LEFT else -1.0, 1.0]) + self.human.jitter(0.02, 3)
        p, _ = self.hand_pose(side)
        local = yaw_matrix(base[3]).T @ (p - base[:3])
        # out in front of the chest first: a hand taken across the body goes round it
        via = 0.5 * (local + goal) + np.array([HOLD_VIA_AHEAD, 0.0, 0.0])
        return self.move_hand_with_body(side, goal, HOLD, base, via=[via])

    def walk_to_drawer(self, side: int) -> Script:
        """Stand up stepping back, round the door's free end to the drawer, facing it; the
        fork hand goes to ``HOLD_AT`` on the way and stays with the body."""
        base = self.commanded_base()
        handle = self.site(CABINET, f"{DRAWER}_handle")
        stance_x = handle[0] - 0.55 + self.human.jitter(0.03)
        stance_y = handle[1] + (0.15 if side == LEFT else -0.15) + self.human.jitter(0.03)
        route = [
            (base[0] - 0.1, base[1], CARRY_HEIGHT, base[3]),
            (ROUND_THE_DOOR_X + self.human.jitter(0.04), -0.35 + self.human.jitter(0.03), CARRY_HEIGHT, -0.6),
            (stance_x, stance_y, handle[2] + DRAWER_CROUCH + 0.05, self.human.jitter(0.05)),
        ]
        arrival = yield from self.walk(route, wait=False)
        self.hold_with_body(side)
        self.relax_arm(1 - side, joint_space=True)
        yield from self.until(arrival)

    def step_to_tray(self, side: int) -> Script:
        """Stand up lifting the fork over the open drawer's front and its tray's walls, then
        step up to the drawer so that the hands are over the tray's near half."""
        base = self.base_pose()
        goal = OVER_DRAWER * np.array([1.0, 1.0 if side == LEFT else -1.0, 1.0]) + self.human.jitter(0.015, 3)
        up = yield from self.walk([(base[0], base[1], CARRY_HEIGHT, base[3])], wait=False)
        lifted = self.move_hand_with_body(side, goal, HOLD, base)
        yield from self.until(max(up, lifted))
        tray = self.data.xpos[self.env.props[TRAY].root_body_id]
        yaw = self.human.jitter(0.05)
        middle = tray + np.array([TRAY_NEAR + self.human.jitter(0.02), self.human.jitter(0.03), 0.0])
        stance = middle[:2] - (yaw_matrix(yaw) @ np.array([CARRY_AHEAD, 0.0, 0.0]))[:2]
        yield from self.walk([(stance[0], stance[1], CARRY_HEIGHT, yaw)])

    def walk_to_dishwasher(self) -> Script:
        """Back and to the dishwasher's side, turned towards it, where its door is worked."""
        base = self.commanded_base()
        yield from self.walk([(base[0] - 0.1, -0.62 + self.human.jitter(0.03), base[2], 0.35)])


__all__ = ["CutleryDrawerExpert"]
