"""DishwasherLoadCutlery demonstrator (scene counter_dishwasher): take the knife and the fork
out of the mug on the counter and stand them in the dishwasher's cutlery basket.

The two pieces lean apart in the free mug, each against the rim. A person turns to the mug
so that the two stand side by side in front of them, takes each near its top with the hand
on its side (both hands at once), draws both out along their own lines, holds them beside
the chest, walks round the open door's free end to the front of the pulled-out tray,
crouching, and stands each piece in a compartment of the basket on its hand's side: over
the basket's walls, down until its foot rests on the compartment's floor, let go leaning a
little towards the far wall, against which it comes to rest.

Why it is done this way (measured while building it):

* One piece at a time fails: drawing the first out jostles the light mug, and the other
  piece falls to a new lean, or out of the mug, before the hand gets there. Both are taken
  first, then drawn out together. With the body facing the counter squarely, the pieces
  often stand one behind the other; the body turns (up to :data:`MAX_TURN`) so that they
  stand side by side, and each hand has room.
* The pads must lie parallel to the face they close on, and the hand must come in square
  to the piece (the piece along the gap between the fingers). Otherwise the closing fingers
  tip the piece, and it drags the mug. The fingers close either across the flat or across
  the edges, whichever lets the hand come in along the line from its shoulder.
* Each piece is first eased a few millimetres off the rim it leans on, then drawn out
  along its own line (lifted straight up, it rubs on the rim and tips the mug).
* The 17 s time limit leaves no room for one hand after the other: the hands work at the
  same time, and the second starts putting its piece down while the first lets go.

Choices drawn per demo: how far the body turns at the mug (from where the pieces lean),
which hand takes its piece first and which puts it in first, each piece's compartment,
whether a piece is taken across its flat or its edges, where the body stands at the
basket, the lean the pieces are let go at, the timing, and every path's via-points.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.experts.dishwasher_cutlery import ROUND_THE_DOOR_X, CutleryUnloadExpert
from bigym.experts.expert import FREE, LEFT, RIGHT, SIDE_NAMES, Script, together
from bigym.experts.geometry import aligning_rotation, frame_from_axes, yaw_matrix
from bigym.experts.grasping import HOLD

MUG = "mug"
#: the body faces the mug from this far (m), its pelvis this high over the mug's base
MUG_DISTANCE = 0.5
MUG_CROUCH = 0.05
#: how far (rad) the body turns from facing the counter squarely, at most
MAX_TURN = 0.8
#: where the shoulders are (m beside the pelvis): a hand comes in along the line from its
#: shoulder to the piece
SHOULDER = 0.2
#: how far (m) below its top end a piece is taken
TOP_GRIP = 0.02
#: orientation costs of the grasp (see :data:`bigym.experts.grasping.GRASP`): the tilt
#: about the closing axis is kept too, so that the hand comes in square to the piece
PICK_COST = np.array([2.0, 1.0, 2.0])
#: a held piece is first eased this far (m) off the rim it leans on, then drawn out along
#: its line (at this speed factor) until its foot is this high (m) over the rim
OFF_RIM = 0.006
DRAW_SPEED = 0.8
OUT_CLEAR = 0.08
#: where a held piece is carried (pelvis frame, the left hand's; the right one mirrored)
CARRY = np.array([0.3, 0.2, 0.25])
#: the stance at the basket: the pelvis this far (m) behind the front compartments, this
#: high; the hands start down this long (s) before the body arrives
BASKET_BACK = 0.3
BASKET_CROUCH = 0.62
EARLY = 0.4
#: each hand's compartments (slot 1 at the basket's +y end, the body's left; 1-3 the front
#: row), the front one most often
SLOTS = {LEFT: (1, 4), RIGHT: (3, 6)}
SLOT_WEIGHTS = (0.7, 0.3)
#: the second hand starts putting its piece in this long (s) after the first
STAGGER = 1.0
#: a piece's foot is carried this high (m) over the compartment's floor (the basket's
#: walls stand 12 cm), then brought quickly down to this high, then lowered until it rests
OVER_WALLS = 0.16
NEAR_FLOOR = 0.02
LANDED = 0.015
#: a piece is let go leaning this much (rad) away from the body: it comes to rest against
#: the compartment's far wall
LEAN = np.deg2rad(8.0)
#: orientation costs while putting a piece in: its spin about its own line is left free
PLACE_COST = np.array([0.3, 1.0, 2.0])


class CutleryLoadExpert(CutleryUnloadExpert):
    """Moves the knife and the fork of ``DishwasherLoadCutlery`` from the mug into the basket."""

    tasks = ("DishwasherLoadCutlery",)
    #: a piece let go in the basket falls only from its small lean to the wall: the
    #: default drop allowance holds (unlike the unload expert's, which lays pieces flat)
    drop_speeds: ClassVar[dict[str, float]] = {}
    #: nor does it tip over by itself (unlike the unload expert's pieces, laid flat)
    may_tip: ClassVar[tuple[str, ...]] = ()

    def start(self) -> None:
        #: the body's yaw and stance at the mug, and the line of the piece being taken
        self.facing = 0.0
        self.mug_stance = np.zeros(4)
        self.piece_line = np.array([0.0, 0.0, 1.0])
        super().start()

    def plan(self) -> Script:
        yield from self.wait(self.human.reaction())
        self.face_the_mug()
        hands = self.assign_hands(self.facing)  # as the body will stand
        first = LEFT if self.rng.random() < 0.5 else RIGHT
        self.choices["first"] = SIDE_NAMES[first]
        yield from together(
            self.take_from_mug(first, hands[first]),
            self.after(self.human.reaction() * 0.5, self.take_from_mug(1 - first, hands[1 - first])),
        )
        yield from together(*(self.draw_out(side, hands[side]) for side in (first, 1 - first)))
        for side in (LEFT, RIGHT):
            if self.env.held(hands[side]):
                self.carry_beside_chest(side)
        yield from self.wait(0.2)
        arrival = yield from self.walk_to_basket()
        yield from self.until(arrival - EARLY)
        yield from together(
            self.put_in_basket(first, hands[first]),
            self.after(STAGGER + abs(self.human.jitter(0.2)), self.put_in_basket(1 - first, hands[1 - first])),
        )
        while True:
            yield

    # ------------------------------------------------------------------ at the mug
    def face_the_mug(self) -> None:
        """Step up to the mug turned so that the two pieces stand side by side."""
        mug = self.data.xpos[self.env.props[MUG].root_body_id]
        line = self.end("knife", 1.0) - self.end("fork", 1.0)
        facing = float(np.arctan2(line[1], line[0])) + 0.5 * np.pi
        facing = float(np.angle(np.exp(2j * facing)) / 2.0)  # either way round: the one nearest +x
        facing = float(np.clip(facing, -MAX_TURN, MAX_TURN))
        direction = np.array([np.cos(facing), np.sin(facing), 0.0])
        self.mug_stance = self.stance(None, mug, direction, distance=MUG_DISTANCE, height=MUG_CROUCH)
        self.facing = float(self.mug_stance[3])
        self.choices["facing"] = round(self.facing, 2)
        self.move_base(self.mug_stance)

    def grasp_rotation(self, side: int, closing: np.ndarray, tilt: float = 0.0, upright: bool = False) -> np.ndarray:
        """Pinch frame closing along ``closing`` as it is (the pads parallel to the face,
        even when it leans), the piece (:attr:`piece_line`) along the gap between the
        fingers, the hand coming in from the body's side."""
        y = np.asarray(closing, float) / np.linalg.norm(closing)
        approach = np.cross(y, self.piece_line)
        approach /= np.linalg.norm(approach)
        if approach @ (yaw_matrix(self.facing) @ np.array([1.0, 0.0, 0.0])) < 0.0:
            approach = -approach
        if self.hand_pose(side)[1][:, 1] @ y < 0.0:
            y = -y
        return frame_from_axes(np.cross(y, approach), approach)

    def natural_closing(self, side: int, point: np.ndarray, frame: np.ndarray) -> np.ndarray:
        """Across the flat (local z) or across the edges (local x) of a piece with axes
        ``frame``: whichever lets the hand come in along the line from its shoulder."""
        turn = yaw_matrix(self.facing)
        forward = turn @ np.array([1.0, 0.0, 0.0])
        shoulder = np.array([self.mug_stance[0], self.mug_stance[1], 0.0])
        shoulder = shoulder + turn @ np.array([0.0, SHOULDER if side == LEFT else -SHOULDER, 0.0])
        line = np.array([point[0], point[1], 0.0]) - shoulder
        line /= np.linalg.norm(line)

        def along_the_line(closing: np.ndarray) -> float:
            approach = np.cross(closing, frame[:, 1])
            approach[2] = 0.0
            approach /= max(float(np.linalg.norm(approach)), 1e-9)
            if approach @ forward < 0.0:
                approach = -approach
            return float(approach @ line)

        return max((frame[:, 2].copy(), frame[:, 0].copy()), key=along_the_line)

    def take_from_mug(self, side: int, item: str) -> Script:
        """Take a piece near its top."""

        def aim() -> tuple[np.ndarray, np.ndarray]:
            frame = self.data.xmat[self.env.props[item].root_body_id].reshape(3, 3)
            point = self.end(item, 1.0) - self.axis(item) * TOP_GRIP
            self.piece_line = frame[:, 1].copy()
            closing = self.natural_closing(side, point, frame)
            self.choices[f"{item} across"] = "flat" if abs(float(closing @ frame[:, 2])) > 0.5 else "edges"
            return point, closing

        held = yield from self.pick(side, aim, lift=0.0, prop=item, cost=PICK_COST)
        self.choices[f"{item} held"] = bool(held)

    def draw_out(self, side: int, item: str) -> Script:
        """Ease the held piece off the rim it leans on, then draw it out along its line."""
        if not self.env.held(item):
            return
        axis = self.axis(item)
        rim = self.site(MUG, "rim")[2]
        out = (rim + OUT_CLEAR - self.end(item, -1.0)[2]) / max(float(axis[2]), 0.5)
        lean = np.array([axis[0], axis[1], 0.0])
        off_rim = -lean / max(float(np.linalg.norm(lean)), 1e-6) * OFF_RIM
        p, r = self.hand_pose(side)
        yield from self.until(self.move_hand(side, p + off_rim, r, HOLD, spread=0.0, duration=0.15, tremor=0.2))
        goal = p + off_rim + axis * out + np.array([0.0, 0.0, abs(self.human.jitter(0.02))])
        yield from self.until(self.move_hand(side, goal, r, HOLD, spread=0.0, speed=DRAW_SPEED, tremor=0.3))

    def carry_beside_chest(self, side: int) -> None:
        """Bring a held piece beside the chest, where it stays as the body walks (measured
        from the planned base: a held piece must not jump)."""
        goal = CARRY * np.array([1.0, 1.0 if side == LEFT else -1.0, 1.0]) + self.human.jitter(0.02, 3)
        self.move_hand_with_body(side, goal, HOLD, self.base_pose())

    # ------------------------------------------------------------------ at the basket
    def walk_to_basket(self) -> Script:
        """Round the door's free end to the front of the pulled-out tray, crouching on the
        way; returns when the body will arrive (the hands may start before)."""
        base = self.commanded_base()
        dishwasher = self.env.props["dishwasher"]
        front = np.array([dishwasher.site_pos(self.data, f"basket_slot_{k}") for k in (1, 2, 3)])
        x = float(front[:, 0].mean()) - BASKET_BACK + self.human.jitter(0.02)
        y = float(front[:, 1].mean()) + self.human.jitter(0.03)
        self.choices["basket stance"] = [round(x, 2), round(y, 2)]
        route = [
            (ROUND_THE_DOOR_X + self.human.jitter(0.04), base[1] + 0.3, 0.5 * (base[2] + BASKET_CROUCH), 0.4),
            (x, y, BASKET_CROUCH + self.human.jitter(0.02), self.human.jitter(0.06)),
        ]
        return (yield from self.walk(route, wait=False))

    def put_in_basket(self, side: int, item: str) -> Script:
        """Stand the piece in a compartment on the hand's side, leaning a little away from
        the body, and let go once its foot rests on the floor."""
        if not self.env.held(item):
            return
        self.note(f"basket {'LR'[side]}")
        slot = int(self.rng.choice(SLOTS[side], p=SLOT_WEIGHTS))
        self.choices[f"{item} slot"] = slot
        floor = self.env.props["dishwasher"].site_pos(self.data, f"basket_slot_{slot}")
        body = self.env.props[item].root_body_id
        frame = self.data.xmat[body].reshape(3, 3)
        forward = yaw_matrix(self.base_pose()[3]) @ np.array([1.0, 0.0, 0.0])
        lean = LEAN + self.human.jitter(0.05)
        line = np.cos(lean) * np.array([0.0, 0.0, 1.0]) + np.sin(lean) * forward
        foot = floor + np.array([0.0, 0.0, 0.004]) + self.human.jitter(0.004, 3) * np.array([1.0, 1.0, 0.0])
        # turned to lean as it will rest, its foot over the compartment, clear of the walls
        rotation = self.turned_rotation(side, body, aligning_rotation(frame[:, 1], line) @ frame)
        p, r = self.hand_pose(side)
        foot_turned = p + rotation @ r.T @ (self.end(item, -1.0) - p)
        above = p + foot + np.array([0.0, 0.0, OVER_WALLS]) - foot_turned
        yield from self.until(self.move_hand(side, above, rotation, PLACE_COST, correct=True, precision=0.015))
        # look again: the foot straight over its spot, then quickly down near the floor, then
        # slowly until it rests there
        p, rotation = self.hand_pose(side)
        above = p + foot + np.array([0.0, 0.0, OVER_WALLS]) - self.end(item, -1.0)
        yield from self.until(self.move_hand(side, above, rotation, PLACE_COST, precision=0.006, speed=0.8, tremor=0.3))
        piece, basket = self.env.mask(item), self.env.mask("dishwasher", "basket")

        def resting() -> bool:
            return self.env.touching(piece, basket) and self.end(item, -1.0)[2] < floor[2] + LANDED

        down = above - np.array([0.0, 0.0, OVER_WALLS - NEAR_FLOOR])
        end = self.move_hand(side, down, rotation, PLACE_COST, spread=0.0, precision=0.005, speed=0.7, tremor=0.3)
        while self.time < end and not resting():
            yield
        if not resting():
            yield from self.lower_until(side, rotation, NEAR_FLOOR + 0.01, 0.2, resting)
        self.hold_hand(side, HOLD, tremor=0.2)
        yield from self.set_grip(side, 0.0, max_wait=0.6, min_wait=0.25)
        # up out of the basket, then out to the side, clear of the other piece
        p, rotation = self.hand_pose(side)
        end = self.move_hand(side, p + np.array([0.0, 0.0, 0.12]) - forward * 0.05, rotation, HOLD * 0.5, spread=0.2)
        yield from self.until(end - 0.2)
        p, rotation = self.hand_pose(side)
        outward = yaw_matrix(self.base_pose()[3]) @ np.array([-0.08, 0.12 if side == LEFT else -0.12, 0.05])
        self.move_hand(side, p + outward, rotation, FREE, spread=0.2)


__all__ = ["CutleryLoadExpert"]
