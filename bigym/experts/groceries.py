"""Groceries demonstrator (scene counter_base_2): put the four groceries from the counter
into the cupboard under it (``StoreGroceriesLower``).

What a person does: opens the cupboard's door (pulls the handle, pushes the door round)
and keeps clear of it; then, one item at a time, steps up to the counter with both hands
at the hips, takes the item round its body (the fingers closing across it, or across a
box's narrow faces; a long box near its end, as far in as the fingers reach) a little
above its base, lifts it, backs away until it is clear of the counter, crouches until it
hangs just above the middle shelf, steps across in front of its place, carries it in
under the counter, puts it down, draws the hand out and steps back as it rises.

The middle shelf takes the four items side by side, in the order they are taken: the
left hand fills the left half of the shelf, the right hand the right half (a hand
reaching across the body into the low cupboard turns the item over). The open door keeps
the body from stepping as far left as the right hand's places need: that hand carries its
item across in front of the cupboard before going in, and an item too far left for the
right hand to be taken from beside it goes to the left hand. A box goes to the hand that
takes it without turning the body towards that hand (the right hand then takes it from
the door's edge, across the body, and the left hand puts it on the right half, the body
standing further right); the cereal box goes to the right hand where either would do.
Under the counter a tall
item is not raised above its place before it is lowered (its top would touch the counter,
which the hand would take for the shelf).

Why the hands go to the hips before the body moves: crouched at the counter, a hand held
in front of the belly would be inside the counter. Why the body steps back as it rises
from the cupboard: the hand that comes out from under the counter is in front of the
belly, and on its way to the hip it brushed the torso (such contacts make replays at
other rates part from the recording). Why the door arm is relaxed in joint space after
the door: pushing the door round leaves the arm in a turned-over posture from which the
IK reaches the next item with the elbow up. Why the arms then keep to a plane just inside
the open door (``keep_arms_clear_of_open_door``): the IK knows no scene, and crouched
beside the door it swung the left elbow out into the door's inner face, which held the
arm while the body carried on, so that the item swung down out of the hand's line.
Why the boxes' hands: the fingers close across a box's narrow faces, so the body turns
with the box's yaw, and turned towards the hand that takes it, that shoulder draws back
from the counter: the hand fell 15-40 cm short three times running and the pick gave up
(most of the time limits before). The cereal box given to the left hand was dropped,
left tilted on the shelf or not taken at all in 6 of 7 seeds (0-39), given to the right
hand in 2 of 6.

Known limits (dataset v2's build record has the figures per failure reason): the items
stand 0.1-0.3 m in on the counter, at the edge of the crouched arm's reach, so a grasp
can land 3-4 cm off and push or tip the item. The boxes are the hardest. A box beside
the door that suits only the right hand, from further than ``BOX_STANCE_SLACK``, still
goes to the left hand, which falls short of it (the pick gives up). The cereal box
(0.07 x 0.19 x 0.24 m) fills most of the 0.35 m under the counter: the body crouches to
its lowest to carry it in, where the IK lets the hand's orientation go and the box tilts
by 10-40 degrees and swings down (read as a drop), or is let go tilted and falls over.
Nearest the door the right hand cannot take it, and the left hand still does. A person
would carry it in with both hands, or lay it down; neither is done here. At the place
furthest right the fingers met the cupboard's side wall on the way in (seed 53) and the
item was let go on the shelf's front edge, from which it fell. The detergent
jug (1 kg, 0.26 m tall) was squeezed out of a grasp on its edge. Replays at 25
or 50 Hz that parted from the recording while the hand pushed the door round (the arm's
joints 0.2-0.6 rad apart) were mostly the fist brushing the door as it came round its free
edge (``doors.ROUND_EDGE_STANDOFF``). Replays at 20-50 Hz that parted late in the demo
(the right arm, 44-64 s) followed a brush of the right gripper's root on the torso a few
seconds before, as the hand rose from the hip across the body to an item left of its
shoulder, or lifted it (seeds 0, 9 and 33): the IK now keeps the grippers off the torso
(``grippers_off_torso``), which took seeds 0-39 from 28 to 32 kept.

Choices drawn per demo: the order of the items (mostly nearest the cupboard first), and
with it the hand and the place on the shelf of each; where the body stands, how high the
fingers close, the timing, and every path's via-points.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import ClassVar

import mujoco
import numpy as np

from bigym.experts.doors import DoorSkills
from bigym.experts.expert import FREE, LEFT, RIGHT, SIDE_NAMES, Script
from bigym.experts.geometry import yaw_matrix
from bigym.experts.grasping import HOLD, TABLE_CLEARANCE, GraspingExpert

CUPBOARD = "cabinet_1"
DOOR = "door_right"
#: x of the cupboard's front (its door's outer face, closed) and of the counter's underside
FRONT = 0.5
COUNTER_UNDERSIDE = 0.83
#: top of the cupboard's middle shelf, and the x the items are put down at
SHELF_TOP = 0.48
SHELF_X = 0.8
#: where on the shelf (y) the items go, left to right
SHELF_SPOTS = (0.19, 0.065, -0.065, -0.19)
#: pelvis height (m) at the counter: the forearm about level with the items' lower parts
COUNTER_CROUCH = 0.8
#: how far (m) above an item's base the fingers close (low: the item stands in the hand
#: and the body needs less room under the counter)
GRIP_HEIGHT = 0.07
#: how steeply (rad below the horizontal) the hand comes at an item
GRIP_TILT = 0.2
#: how far (m) past an item's near face the pinch point goes: a long box is taken near its
#: end, since the fingers reach no further into it
GRIP_DEPTH = 0.05
#: how far (m) the item is lifted off the counter
LIFT = 0.06
#: how far (m) the pelvis stays behind the pinch point when reaching into the cupboard
CUPBOARD_REACH = 0.5
#: how far (m) the pelvis keeps from the cupboard's front while reaching in
FRONT_CLEARANCE = 0.14
#: least and most clearance (m) under an item carried in (the room under the counter is
#: shared between its base and its top)
ENTRY_CLEARANCE = (0.015, 0.06)
#: how far (m) the body steps back as it rises from the cupboard
STEP_BACK = 0.12
#: how much further out (m) than usual each hand (left, right) goes to the hip: the right
#: hand, coming from in front of the belly, brushed the torso (such contacts part replays
#: at other rates); the left has the open door beside it
HIP_WIDER = (0.0, 0.07)
#: how far (m) left of the pelvis the left hand takes an item (the right hand: right of it)
HAND_OFFSET = 0.2
#: how far (m) the open door may push the body from where the right hand would take an item
STANCE_SLACK = 0.06
#: how far for a box: the right hand takes one from the door's edge, across the body, if
#: it suits that hand and not the left (see :meth:`GroceriesExpert.box_hand`)
BOX_STANCE_SLACK = 0.32
#: how far for the cereal box, if it suits both hands (the right hand takes it then; from
#: further away it fell short of it)
LONG_BOX_STANCE_SLACK = 0.2
#: how far (rad) the body may turn towards the hand that takes a box (:meth:`GroceriesExpert.suits`)
TURN_TOWARDS = 0.2
#: how often two neighbouring items in the nearest-first order are taken the other way round
SWAP = 0.3


class GroceriesExpert(GraspingExpert, DoorSkills):
    """Stores the groceries of ``StoreGroceriesLower`` on the cupboard's middle shelf."""

    tasks = ("StoreGroceriesLower",)
    pace: ClassVar[dict[str, float]] = {"StoreGroceriesLower": 1.2}
    # the fingers' contacts with the last item come and go as it touches the shelf and is
    # let go: the task counted as done at such a moment, with the item still in the fingers,
    # and a replay at another rate rarely repeated it
    success_must_last = True
    # reaching across the body from the hip to an item left of the right shoulder, and
    # lifting it, the right gripper brushed the torso: the replays at 20-50 Hz that parted
    # from the recording mostly did so a few seconds after such a brush
    grippers_off_torso = True

    def plan(self) -> Script:
        yield from self.wait(self.human.reaction())
        door_side = self.door_side(CUPBOARD, DOOR)
        yield from self.open_cabinet_door(CUPBOARD, DOOR)
        yield from self.until(self.relax_arm(door_side, joint_space=True))
        self.keep_arms_clear_of_open_door(CUPBOARD, DOOR)
        order = self.item_order()
        self.choices["order"] = order
        for item, y in zip(order, SHELF_SPOTS, strict=False):
            # the left hand can also put a box it suits on the right half (the body stands
            # further right); the right hand cannot stand far enough left for the left half
            side = LEFT if y > 0.0 or self.box_hand(item) == LEFT else RIGHT
            self.choices["hands"].append(f"{item}:{SIDE_NAMES[side]}")
            yield from self.take_item(side, item)
            yield from self.put_in_cupboard(side, item, np.array([SHELF_X, y, SHELF_TOP]))
        while True:
            yield

    # ------------------------------------------------------------------ choices
    def item_order(self) -> list[str]:
        """Nearest the cupboard first (largest y), with neighbours sometimes swapped; the
        first half goes to the left hand, the second to the right. A box goes to the hand
        it suits (:meth:`suits`), the cereal box to the right hand where that hand can take
        it (see the module's notes); an item the right hand cannot stand beside (the open
        door keeps the body right of it) goes to the left hand."""
        order = sorted(self.env.chosen, key=lambda n: -self.item_y(n))
        for i in range(len(order) - 1):
            if self.rng.random() < SWAP:
                order[i], order[i + 1] = order[i + 1], order[i]
        half = (len(order) + 1) // 2
        for item in [n for n in order if self.is_box(n)]:
            i = order.index(item)
            if i >= half or self.box_hand(item) != RIGHT:
                continue
            # trade places with an item of the right half that is not a box
            j = next((k for k in range(half, len(order)) if not self.is_box(order[k])), None)
            if j is not None:
                order[i], order[j] = order[j], order[i]
        for i in range(half, len(order)):
            if not self.right_hand_reaches(order[i]):
                j = min(range(half), key=lambda k: self.item_y(order[k]))
                if self.item_y(order[j]) < self.item_y(order[i]):
                    order[i], order[j] = order[j], order[i]
        return order

    def box_hand(self, item: str) -> int | None:
        """The hand a box should go to (None: either): the right one if the box suits it
        and not the left and the right hand can take it from the door's edge, or if it is
        the cereal box and the right hand stands nearer it than that; the left one if the
        box suits only that."""
        if not self.is_box(item):
            return None
        left, right = self.suits(LEFT, item), self.suits(RIGHT, item)
        if right and not left and self.right_hand_reaches(item, BOX_STANCE_SLACK):
            return RIGHT
        if right and self.is_long_box(item) and self.right_hand_reaches(item, LONG_BOX_STANCE_SLACK):
            return RIGHT
        if left and not right:
            return LEFT
        return None

    def suits(self, side: int, item: str) -> bool:
        """Whether ``side``'s hand takes a box with the body (square to the counter) turned
        no more than ``TURN_TOWARDS`` towards that hand: turned further towards it, that
        shoulder draws back from the counter and the hand fell short of the box three
        times running (the other hand turns the body the other way for the same box)."""
        _, turn = self.face_closing(side, self.narrow_faces_yaw(item), faces=2, facing_yaw=0.0)
        return turn <= TURN_TOWARDS if side == LEFT else turn >= -TURN_TOWARDS

    def is_box(self, item: str) -> bool:
        """A box-shaped item (the fingers close across its narrow faces)."""
        return _narrow_axis_yaw(self.env.props[item]) is not None

    def is_long_box(self, item: str) -> bool:
        """The cereal box: taken near one end, it fills most of the room under the counter."""
        return type(self.env.props[item]).__name__ == "Cereals"

    def item_y(self, item: str) -> float:
        return float(self.data.xpos[self.env.props[item].root_body_id][1])

    def right_hand_reaches(self, item: str, slack: float | None = None) -> bool:
        """Whether the body can stand where the right hand takes the item from, give or take
        ``slack`` (default: ``BOX_STANCE_SLACK`` for a box, else ``STANCE_SLACK``)."""
        stance = np.array([FRONT - TABLE_CLEARANCE, self.item_y(item) + HAND_OFFSET, COUNTER_CROUCH, 0.0])
        if slack is None:
            slack = BOX_STANCE_SLACK if self.is_box(item) else STANCE_SLACK
        return float(np.linalg.norm(self.clamp_to_region(stance)[:2] - stance[:2])) < slack

    def closing(self, side: int, item: str) -> tuple[np.ndarray, float]:
        """The fingers' closing direction (and how far the body turns for it): across a
        box's narrow faces, any way round a round item (the hand's comfortable one)."""
        if not self.is_box(item):
            return self.face_closing(side, self.base_pose()[3], faces=8)
        return self.face_closing(side, self.narrow_faces_yaw(item), faces=2)

    def narrow_faces_yaw(self, item: str) -> float:
        """The world yaw (rad) of a box's narrow faces' normal, as it stands now."""
        prop = self.env.props[item]
        frame = self.data.xmat[prop.root_body_id].reshape(3, 3)
        return float(np.arctan2(frame[1, 0], frame[0, 0])) + _narrow_axis_yaw(prop)

    def item_height(self, item: str) -> float:
        """Height (m) of an item's colliders above its base."""
        body = self.env.props[item].root_body_id
        model = self.model
        top = 0.0
        for g in np.flatnonzero(model.body_rootid[model.geom_bodyid] == body):
            if not model.geom_contype[g]:
                continue
            size = model.geom_size[g]
            half = size[1] if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_CYLINDER else size[2]
            top = max(top, float(self.data.geom_xpos[g][2]) + float(half))
        return top - float(self.data.xpos[body][2])

    def item_reach(self, item: str, direction: np.ndarray) -> float:
        """How far (m) an item's colliders reach from its origin along the horizontal
        ``direction``."""
        body = self.env.props[item].root_body_id
        model, data = self.model, self.data
        reach = 0.0
        for g in np.flatnonzero(model.body_rootid[model.geom_bodyid] == body):
            if not model.geom_contype[g]:
                continue
            size = model.geom_size[g]
            if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX:
                extent = float(np.abs(data.geom_xmat[g].reshape(3, 3).T @ direction) @ size)
            else:  # upright cylinders and capsules
                extent = float(size[0])
            reach = max(reach, float((data.geom_xpos[g] - data.xpos[body]) @ direction) + extent)
        return reach

    # ------------------------------------------------------------------ steps
    def item_stance(self, side: int, item: str) -> np.ndarray:
        """Where the body stands (x, y, z, yaw) to take an item with ``side``'s hand: at the
        counter, the hand's shoulder in line with the item, turned as the grasp needs."""
        position = self.data.xpos[self.env.props[item].root_body_id]
        lateral = HAND_OFFSET if side == LEFT else -HAND_OFFSET
        _, turn = self.closing(side, item)
        return np.array(
            [
                FRONT - TABLE_CLEARANCE - 0.02 - abs(self.human.jitter(0.02)),
                position[1] - lateral + self.human.jitter(0.03),
                COUNTER_CROUCH + self.human.jitter(0.02),
                turn + self.human.jitter(0.04),
            ]
        )

    def take_item(self, side: int, item: str, holding: Sequence[int] = ()) -> Script:
        """Step up to the counter in line with the item, the free hands at the hips (the
        ``holding`` hands keep what they hold where they hold it), and take it."""
        self.note(f"to {item}")
        body = self.env.props[item].root_body_id
        position = self.data.xpos[body].copy()
        stance = self.item_stance(side, item)
        for hand in (LEFT, RIGHT):
            if hand not in holding:
                self.hand_to_hip(hand, wider=HIP_WIDER[hand])
        yield from self.walk([self.clamp_to_region(stance)], carrying=holding)
        height = GRIP_HEIGHT + self.human.jitter(0.008)

        def aim() -> tuple[np.ndarray, np.ndarray]:
            closing, _ = self.closing(side, item)
            forward = yaw_matrix(self.base_pose()[3]) @ np.array([1.0, 0.0, 0.0])
            across = np.array([closing[0], closing[1], 0.0]) / np.linalg.norm(closing[:2])
            ahead = forward - (forward @ across) * across
            ahead /= np.linalg.norm(ahead)
            shift = max(0.0, self.item_reach(item, -ahead) - GRIP_DEPTH)
            return self.data.xpos[body] + np.array([0.0, 0.0, height]) - shift * ahead, closing

        hand, _ = self.hand_pose(side)
        top = position[2] + height
        # up in front of the counter's edge, then over it to behind the item
        via = [
            np.array([FRONT - 0.1, 0.5 * (hand[1] + position[1]), top + 0.12]),
            position + np.array([-0.2, 0.0, height + 0.15]),
        ]
        grasp = {"tilt": GRIP_TILT, "thin": False, "upright": True}
        if not (yield from self.pick(side, aim, lift=LIFT, prop=item, via=via, **grasp)):
            self.note(f"gave up on {item}")
            while True:  # the demo fails and is not kept
                yield
        self.hold_hand(side, HOLD)

    def put_in_cupboard(self, side: int, item: str, spot: np.ndarray) -> Script:
        """Back away until the item is clear of the counter, crouch until it hangs just
        above the shelf and step in front of its place, carry it in, put it down, and draw
        the open hand out under the counter's edge."""
        body = self.env.props[item].root_body_id
        offset = self.held_offset(side, body)
        base = self.commanded_base()
        self.note(f"back off with {item}")
        back = base.copy()
        # as far behind a mark 0.25 m out from the cupboard as the item's far side (0.06 past
        # its origin) is in past the cupboard's front
        jut = float(self.data.xpos[body][0]) + 0.06 - FRONT
        back[0] = min(base[0], FRONT - 0.25 - jut) - abs(self.human.jitter(0.02))
        yield from self.walk([back], carrying=[side])
        # the item's base and top share the room under the counter
        room = COUNTER_UNDERSIDE - SHELF_TOP - self.item_height(item)
        entry = SHELF_TOP + float(np.clip(0.5 * room, *ENTRY_CLEARANCE))
        pinch_goal = spot + offset
        shift = HAND_OFFSET if side == LEFT else -HAND_OFFSET
        down = back.copy()
        down[1] = pinch_goal[1] - shift + self.human.jitter(0.02)
        down[2] = float(np.clip(back[2] - (float(self.data.xpos[body][2]) - entry), 0.42, back[2]))
        self.note("crouch")
        yield from self.walk([self.clamp_to_region(down)], carrying=[side])
        # where the open door keeps the body from lining the shoulder up with the place,
        # the hand carries the item across in front of the cupboard
        p, r = self.hand_pose(side)
        if abs(p[1] - pinch_goal[1]) > 0.03:
            across = np.array([p[0], pinch_goal[1], p[2]])
            yield from self.until(self.move_hand(side, across, r, HOLD, spread=0.2, precision=0.02))
        inside = self.commanded_base()
        inside[0] = min(FRONT - FRONT_CLEARANCE, pinch_goal[0] - CUPBOARD_REACH) - abs(self.human.jitter(0.02))
        inside[3] = self.human.jitter(0.05)  # square to the cupboard
        self.note("in")
        yield from self.walk([self.clamp_to_region(inside)], carrying=[side])
        # not raised into the counter before it is lowered
        yield from self.place(side, spot, prop=item, level=True, tip_down=0.05, headroom=max(room - 0.01, 0.01))
        p, r = self.hand_pose(side)
        # just out from under the counter (further back, the gripper's base would be in
        # the torso), and the body steps back as it rises, leaving the hand room to come
        # round to the hip
        out = np.array([FRONT - 0.06, p[1], min(p[2], COUNTER_UNDERSIDE - 0.15)])
        yield from self.until(self.move_hand(side, out, r, FREE, spread=0.2, precision=0.05))
        up = self.commanded_base()
        up[0] = min(up[0], FRONT - FRONT_CLEARANCE - 0.05) - STEP_BACK
        up[2] = COUNTER_CROUCH
        self.note("up")
        yield from self.walk([self.clamp_to_region(up)])


def _narrow_axis_yaw(prop) -> float | None:
    """For a box-shaped item, the yaw (rad, in the item's frame) of the normal of its
    narrow faces, across which the fingers close; None for a round item."""
    name = type(prop).__name__
    if name == "Cereals":  # 0.07 (x) x 0.19 (y)
        return 0.0
    if name == "Detergent":  # 0.1 (x) x 0.065 (y)
        return 0.5 * np.pi
    return None


__all__ = ["GroceriesExpert"]
