"""DishwasherUnloadCutlery demonstrator (scene counter_dishwasher): take the knife and the
fork out of the cutlery basket and lay them in the cutlery tray on the counter.

The open door lies flat in front of the dishwasher with the bottom tray pulled out over it,
and the basket stands on that tray's +y side. A person walks round the door's free end to
the front of the tray, crouches facing the basket, and takes each piece near its top with
the hand on its side (from there the flat of a blade or of the tines faces sideways, so the
fingers close across it from behind); they lift both out, stand up holding them apart in
front of the chest, walk back round the door to the counter, and put each piece down in a
compartment of the tray on its hand's side: they stand it on its end and tip it over
towards themselves about that end until it nearly lies flat, then let go.

The tip-over is what keeps the piece in the tray: let go standing, a 19-23 cm piece falls
whichever way it leans, often over the tray's near wall and off the counter; and
the hand cannot turn a piece held near its end flat in the air (it pivots between the pads:
the closing axis carries its whole weight as a torque), while a piece resting on its end
carries its weight on the tray.

Choices drawn per demo: which hand lifts its piece and lays it first, each piece's
compartment, where the body stands at the basket and at the counter, the crouch, how flat
a piece is tipped before it is let go, the timing, and every path's via-points.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.experts.expert import LEFT, RIGHT, SIDE_NAMES, HandReference, Script
from bigym.experts.geometry import axis_angle_matrix, yaw_matrix
from bigym.experts.grasping import GRASP, HOLD, GraspingExpert

ITEMS = ("knife", "fork")
TRAY = "cutlery_tray"
#: how far (m) below its top end a piece is taken
TOP_GRIP = 0.03
#: how steeply (rad below level) the hand comes in from behind a standing piece
PICK_TILT = 1.1
#: how high (m) a piece is lifted out of the basket
LIFT = 0.22
#: how far (m) behind the nearer piece's top the pelvis stands at the basket, and how high
FRONT_REACH = 0.32
BASKET_CROUCH = 0.6
#: the walk round the door's free end (x of the pelvis; the door reaches x = -0.19)
ROUND_THE_DOOR_X = -0.5
#: pelvis height while carrying, and where the hands hold the pieces then (pelvis frame, m):
#: high enough for a piece's lower end to pass over the tray's walls
CARRY_HEIGHT = 1.02
CARRY_AHEAD = 0.35
CARRY_APART = 0.17
CARRY_ABOVE = 0.2
#: where the body stands at the counter: the hands' midpoint this far (m) in front of the
#: tray's middle (the near half)
TRAY_NEAR = -0.08
#: where a piece's lower end is stood: this far (m) past its compartment's middle, and
#: first held this high (m) over the floor (the walls stand 5.1 cm over it)
PIVOT_AHEAD = 0.04
OVER_WALLS = 0.09
#: a piece is tipped over until it rises this steeply (rad) from its end, then let go
LAY_ELEVATION = 0.3
TIP_DURATION = 1.2  # s
#: how much further out (m) than usual a free hand goes beside the hip (its fingers
#: brushed the torso on the way there)
FREE_HAND_OUT = 0.07
#: each hand's compartments (slot 1 at the tray's +y end, the body's left), nearest the
#: middle of its side most often
SLOTS = {LEFT: (2, 1, 3), RIGHT: (5, 6, 4)}
SLOT_WEIGHTS = (0.6, 0.25, 0.15)


class CutleryUnloadExpert(GraspingExpert):
    """Moves the knife and the fork of ``DishwasherUnloadCutlery`` into the cutlery tray."""

    tasks = ("DishwasherUnloadCutlery",)
    #: let go 15-20 deg from flat, a piece falls the rest of the way onto the tray's floor:
    #: its origin moves down at up to about 0.8 m/s (a drop from a hand is faster)
    drop_speeds: ClassVar[dict[str, float]] = {"knife": 1.0, "fork": 1.0}
    #: a piece stood upright, tipped over and let go falls flat by itself (35 deg and more
    #: from how it was let go): laid down on purpose, not knocked over
    may_tip: ClassVar[tuple[str, ...]] = ("knife", "fork")
    #: how far past its compartment's middle (m) a piece's lower end is stood
    pivot_ahead: ClassVar[float] = PIVOT_AHEAD
    #: each hand's compartments, and how often each is chosen
    slots: ClassVar[dict[int, tuple[int, ...]]] = SLOTS
    slot_weights: ClassVar[tuple[float, ...]] = SLOT_WEIGHTS

    def plan(self) -> Script:
        yield from self.wait(self.human.reaction())
        yield from self.walk_to_basket()
        hands = self.assign_hands()
        first = LEFT if self.rng.random() < 0.5 else RIGHT
        self.choices["first"] = SIDE_NAMES[first]
        for side in (first, 1 - first):
            yield from self.take_from_basket(side, hands[side])
        yield from self.stand_up_holding_apart()
        yield from self.walk_to_tray()
        for side in (first, 1 - first):
            yield from self.lay_in_tray(side, hands[side])
        while True:
            yield

    # ------------------------------------------------------------------ geometry
    def axis(self, item: str) -> np.ndarray:
        """A piece's long axis, handle to head (world)."""
        return self.data.xmat[self.env.props[item].root_body_id].reshape(3, 3)[:, 1].copy()

    def end(self, item: str, sign: float) -> np.ndarray:
        """A piece's head end (``sign`` 1) or handle end (-1) on its axis (world)."""
        body = self.env.props[item].root_body_id
        return self.data.xpos[body] + sign * self.axis(item) * 0.5 * self.env.props[item].length

    def assign_hands(self, yaw: float | None = None) -> dict[int, str]:
        """Each hand takes the piece on its side, for the body facing ``yaw`` (default: as
        it stands)."""
        yaw = self.base_pose()[3] if yaw is None else yaw
        left = np.array([-np.sin(yaw), np.cos(yaw)])
        on_left = max(ITEMS, key=lambda item: float(self.end(item, 1.0)[:2] @ left))
        self.choices["left hand"] = on_left
        return {LEFT: on_left, RIGHT: ITEMS[1 - ITEMS.index(on_left)]}

    # ------------------------------------------------------------------ steps
    def walk_to_basket(self, lateral: float = 0.0) -> Script:
        """Round the door's free end to the front of the pulled-out tray, crouching, facing
        the basket (+x), the pieces' middle ``lateral`` (m) to the left of the body's."""
        base = self.commanded_base()
        tops = np.array([self.end(item, 1.0) for item in self.env.items])
        x = float(np.min(tops[:, 0])) - FRONT_REACH + self.human.jitter(0.02)
        y = float(np.mean(tops[:, 1])) - lateral + self.human.jitter(0.03)
        self.choices["basket stance"] = [round(x, 2), round(y, 2)]
        route = [
            (ROUND_THE_DOOR_X + self.human.jitter(0.04), base[1] + 0.2, base[2], 0.5),
            (x, y, BASKET_CROUCH + self.human.jitter(0.02), self.human.jitter(0.06)),
        ]
        yield from self.walk(route)

    def take_from_basket(self, side: int, item: str) -> Script:
        """Take a piece near its top, the fingers closing across its flat, and lift it out."""

        def aim() -> tuple[np.ndarray, np.ndarray]:
            flat = self.data.xmat[self.env.props[item].root_body_id].reshape(3, 3)[:, 2]
            return self.end(item, 1.0) - self.axis(item) * TOP_GRIP, flat

        held = yield from self.pick(side, aim, lift=LIFT + abs(self.human.jitter(0.02)), prop=item, tilt=PICK_TILT)
        self.choices[f"{item} held"] = bool(held)

    def stand_up_holding_apart(self) -> Script:
        """Stand up, then hold the pieces apart in front of the chest, high enough to carry
        them over the tray's walls."""
        base = self.commanded_base()
        yield from self.walk([(base[0], base[1], CARRY_HEIGHT, base[3])], carrying=(LEFT, RIGHT))
        base = self.commanded_base()
        ends = []
        for side in (LEFT, RIGHT):
            _, rotation = self.hand_pose(side)
            local = np.array([CARRY_AHEAD, CARRY_APART * (1.0 if side == LEFT else -1.0), CARRY_ABOVE])
            goal = base[:3] + yaw_matrix(base[3]) @ (local + self.human.jitter(0.02, 3))
            ends.append(self.move_hand(side, goal, rotation, HOLD, spread=0.2, tremor=0.5))
        yield from self.until(max(ends))

    def walk_to_tray(self) -> Script:
        """Back round the door's free end to the counter, facing it, the hands over the
        tray's near half."""
        tray = self.data.xpos[self.env.props[TRAY].root_body_id]
        yaw = self.human.jitter(0.05)
        middle = tray + np.array([TRAY_NEAR + self.human.jitter(0.02), self.human.jitter(0.03), 0.0])
        stance = middle[:2] - (yaw_matrix(yaw) @ np.array([CARRY_AHEAD, 0.0, 0.0]))[:2]
        self.choices["counter stance"] = [round(float(stance[0]), 2), round(float(stance[1]), 2)]
        route = [
            (ROUND_THE_DOOR_X + self.human.jitter(0.04), tray[1] + 0.25, CARRY_HEIGHT, -0.4),
            (stance[0], stance[1], CARRY_HEIGHT, yaw),
        ]
        yield from self.walk(route, carrying=(LEFT, RIGHT))

    def lay_in_tray(self, side: int, item: str) -> Script:
        """Stand the piece on its end in a compartment on the hand's side, tip it over
        towards the body about that end until it nearly lies flat, let go."""
        if not self.env.held(item):
            return
        self.note(f"lay {'LR'[side]}")
        base = self.base_pose()
        forward = yaw_matrix(base[3]) @ np.array([1.0, 0.0, 0.0])
        left = yaw_matrix(base[3]) @ np.array([0.0, 1.0, 0.0])
        slot = int(self.rng.choice(self.slots[side], p=self.slot_weights))
        self.choices[f"{item} slot"] = slot
        floor = self.env.props[TRAY].site_pos(self.data, f"slot_{slot}")
        foot = floor + forward * (self.pivot_ahead + self.human.jitter(0.015)) + left * self.human.jitter(0.008)
        # over the spot, the lower end clear of the walls, then down until it touches
        p, rotation = self.hand_pose(side)
        above = p + foot + np.array([0.0, 0.0, OVER_WALLS]) - self.end(item, -1.0)
        end = self.move_hand(side, above, rotation, HOLD, correct=True, precision=0.02)
        yield from self.until(end)
        piece, tray = self.env.mask(item), self.env.mask(TRAY)
        yield from self.lower_until(side, rotation, OVER_WALLS + 0.03, 0.5, lambda: self.env.touching(piece, tray))
        self.hold_hand(side, HOLD, tremor=0.2)
        yield from self.tip_over(side, item, -forward)
        yield from self.set_grip(side, 0.0, max_wait=0.6, min_wait=0.3)
        p, rotation = self.hand_pose(side)
        end = self.move_hand(side, p + np.array([0.0, 0.0, 0.1]) - forward * 0.05, rotation, GRASP * 0.5, spread=0.2)
        yield from self.until(end)
        self.hand_to_hip(side, wider=FREE_HAND_OUT)

    def tip_over(self, side: int, item: str, towards: np.ndarray) -> Script:
        """Turn the hand about the piece's resting lower end, its head going ``towards`` (a
        horizontal direction), until the piece rises only about ``LAY_ELEVATION`` from it."""
        p0, r0 = self.hand_pose(side)
        foot = self.end(item, -1.0)
        elevation = float(np.arcsin(np.clip(self.axis(item)[2], -1.0, 1.0)))
        angle = max(0.0, elevation - (LAY_ELEVATION + self.human.jitter(0.04)))
        turn_axis = np.cross([0.0, 0.0, 1.0], towards)
        turn_axis /= np.linalg.norm(turn_axis)
        duration = TIP_DURATION * float(np.exp(self.human.jitter(0.15)))
        t0 = self.time

        def turn(t: float) -> np.ndarray:
            return axis_angle_matrix(turn_axis, angle * self.human.profile(min(max((t - t0) / duration, 0.0), 1.0)))

        self.hands[side] = HandReference(
            lambda t: foot + turn(t) @ (p0 - foot), lambda t: turn(t) @ r0, HOLD, tremor=0.2
        )
        yield from self.until(t0 + duration + 0.1)


__all__ = ["CutleryUnloadExpert"]
