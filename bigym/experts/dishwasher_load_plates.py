"""DishwasherLoadPlates demonstrator (scene counter_dishwasher): take the two plates out of
the dish drainer on the counter and stand them in the front row of the dishwasher's
bottom tray.

The unloading of :mod:`bigym.experts.dishwasher_plates` run backwards. A person steps up
to the counter and takes each plate by the top of its rim with the hand on its side (the
fingers closing across its thickness; one that slips back into the drainer is taken
again), holding the first one out to the side while the other hand takes the second.
They step back from the counter, lower both plates beside the hips and walk round the
open door's free end to the front of the pulled-out tray, crouching. There each plate in
turn is lifted over the tray, brought over its gap between the tines and squared up,
upright with its face along them, looking and correcting up to three times; then it is
lowered in, the hand following where its foot is seen to be off the gap's middle, and
let go.

What makes it work (measured with the dev scripts of the closing note): the gap between
two tines leaves a plate about 1 cm of play at its foot and a few degrees of turn; the
arm's sideways error grows by up to a centimetre as it reaches down, and a plate held by
its rim turns a little in the fingers. Hence the watching: lining up on the plate's
lowest point (not its centre: 5 deg of lean moves the foot 1 cm) and correcting on the
way down, with firmer IK orientation costs (``SQUARE_HOLD``). Plates carried beside the
hips are held nearer the body than when unloading, or they run into the tray's front as
the body arrives and push the tray in.

Choices drawn per demo: which hand takes its plate first and which puts it in first, the
two slots (one free slot at least between them, so that the opening fingers miss the
other plate), where along the rim the fingers close, the stances, the crouch, the timing
and every path's via-points.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.dishwasher_plates import DISHWASHER, FRONT_ROW, PLATE_IN_SLOT
from bigym.experts.dishwasher_cutlery import CARRY_HEIGHT, ROUND_THE_DOOR_X
from bigym.experts.dishwasher_plates import (
    PLATES_BODY_ON_PLAN,
    RAISE_SPEED,
    RIGHT_FIRST,
    TRAY_REACH,
    PlateUnloadExpert,
)
from bigym.experts.expert import LEFT, RIGHT, SIDE_NAMES, HandReference, Script
from bigym.experts.geometry import aligning_rotation
from bigym.experts.grasping import HOLD, TABLE_CLEARANCE
from bigym.experts.move_plates import NEIGHBOUR_OPENING, SLOT_GAP
from bigym.props import DishDrainer

#: where (m; forward, outward, up) the first plate taken is held aside from where it was
#: lifted, while the other hand takes its plate
AWAY = np.array([-0.06, 0.12, 0.03])
#: x of the counter's front
COUNTER_FRONT = 0.4
#: how far (m) the body steps back from the counter before the plates come down beside
#: the hips: clear of the counter's front (a plate standing edge-on reaches 11 cm to it)
STEP_BACK = 0.3
#: where the hands hold the plates while carrying (pelvis frame, m): nearer the body than
#: when unloading, or a plate standing edge-on beside the hip runs into the tray's front
#: (and pushes the tray in) as the body arrives
LOAD_CARRY_AT = np.array([0.1, 0.3, -0.12])
#: how fast (x a free movement) the plates come down beside the hips: a brisk half-metre
#: swing moves them down faster than a dropped plate falls
CARRY_LOWER_SPEED = 0.5
#: the slots plates are put in: the front row but its outermost slot, whose gap beside the
#: tray's side wall is 2.4 cm wide instead of 2.6 (a plate dropped upright over it falls in
#: upright only from a 5 mm wide band instead of 10 mm; held ones mostly went in leaning
#: against the wall or into the next gap)
LOAD_SLOTS = FRONT_ROW[1:]
#: where (x, y) a plate's lowest point goes relative to its slot's site: the middle of
#: the 1 cm in which a plate dropped upright over the slot falls in (measured by dropping
#: plates from offsets 2.5 mm apart), and 1.2 cm further in than the task's start poses,
#: clear of the tray's front wall
FOOT_IN_SLOT = np.array([0.012, -0.002])
#: where the plate's origin rests in its slot, relative to the slot's site
LOAD_IN_SLOT = PLATE_IN_SLOT + np.array([FOOT_IN_SLOT[0], 0.0, 0.0])
#: how high (m) over its rest a plate is lifted from beside the hip to come in over the
#: tray (clear of the cutlery basket in its left rear, 2 cm higher than the plate's rest
#: top), and how high it hangs over its gap before it goes in (the tines stand 7 cm)
OVER_TINES = 0.18
OVER_GAP = 0.085
#: a plate is lined up over its gap when its foot is this close (m) and its face within
#: this angle (rad) of the tines; it is lined up this often at most
LINED_UP = 0.004
SQUARE = 0.05
LINE_UPS = 3
#: how fast (x a free movement) the hand moves a plate lining it up
LINE_UP_SPEED = 0.8
#: IK orientation costs while a plate goes in: its face must stay along the tines
SQUARE_HOLD = np.array([8.0, 4.0, 8.0])
#: how fast (m/s) a plate is lowered into its gap, and how fast (1/s) the hand follows
#: what the eye sees of its foot being off the gap's middle on the way
GUIDE_SPEED = 0.05
GUIDE_GAIN = 3.0
#: a plate is in when its origin is this close (m) over its rest; the hand goes this much
#: (m) deeper at most
IN_SLOT = 0.006
DEEPER = 0.02
#: how high (m) the pelvis is at the tray: lower than to take plates out, as a plate held
#: upright goes 4 cm deeper into the tines than the fingers reach from 0.72 m
LOAD_CROUCH = 0.64


class PlateLoadExpert(PlateUnloadExpert):
    """Moves the plates of ``DishwasherLoadPlates`` into the dishwasher's bottom tray."""

    tasks = ("DishwasherLoadPlates",)
    pace: ClassVar[dict[str, float]] = {"DishwasherLoadPlates": 1.25}
    #: plates are taken from the drainer as before the unloading expert corrected its pinch
    #: (its shipped demos were recorded so)
    take_adjusts: ClassVar[int] = 0
    take_firm: ClassVar[float] = 0.0

    def plan(self) -> Script:
        env = self.env
        ys = {p: float(self.data.xpos[env.props[p].root_body_id][1]) for p in env.items}
        plate_of = dict(zip((LEFT, RIGHT), sorted(env.items, key=lambda p: -ys[p]), strict=True))
        first = RIGHT if self.rng.random() < RIGHT_FIRST else LEFT
        self.choices["hands"] = [f"{plate_of[s]}:{SIDE_NAMES[s]}" for s in (first, 1 - first)]
        # the front row runs from -y to +y: the left hand's plate takes the second of the pair
        n = len(LOAD_SLOTS)
        pairs = [(i, j) for i in range(n) for j in range(i + 1 + SLOT_GAP, n)]
        i, j = pairs[int(self.rng.integers(len(pairs)))]
        slot_of = {RIGHT: LOAD_SLOTS[i], LEFT: LOAD_SLOTS[j]}

        self.keep_base_behind(np.array([COUNTER_FRONT, 0.0]), np.array([1.0, 0.0]), TABLE_CLEARANCE)
        # neighbours in the drainer leave room only for half-open fingers (the first plate
        # out leaves the other one room)
        opening = NEIGHBOUR_OPENING if abs(ys[plate_of[LEFT]] - ys[plate_of[RIGHT]]) < 1.5 * DishDrainer.PITCH else 0.0
        yield from self.wait(self.human.reaction())
        base = self.commanded_base()
        stance = np.array(
            [COUNTER_FRONT - TABLE_CLEARANCE - abs(self.human.jitter(0.02)),
             float(np.mean(list(ys.values()))) + self.human.jitter(0.03), base[2], self.human.jitter(0.05)]
        )  # fmt: skip
        self.move_base(stance)
        for side in (first, 1 - first):
            yield from self.take_until_held(side, plate_of[side], opening)
            opening = 0.0
            if side == first:  # held out to its side, clear of the other plate and hand
                p, rotation = self.hand_pose(side)
                aside = p + AWAY * np.array([1.0, 1.0 if side == LEFT else -1.0, 1.0]) + self.human.jitter(0.015, 3)
                self.move_hand(side, aside, rotation, HOLD)
        # while the plates are held in the body's frame the body keeps to its plan (see
        # :mod:`bigym.experts.dishwasher_unload_cutlery_long`)
        self.base_cost.update(PLATES_BODY_ON_PLAN)
        yield from self.carry_to_tray([slot_of[LEFT], slot_of[RIGHT]])
        self.note("at tray")
        put_first = RIGHT if self.rng.random() < RIGHT_FIRST else LEFT
        self.choices["slots"] = [slot_of[s] for s in (put_first, 1 - put_first)]
        for side in (put_first, 1 - put_first):
            yield from self.slot_in(side, plate_of[side], slot_of[side])
            self.relax_arm(side)
        while True:
            yield

    def slot_in(self, side: int, plate: str, slot: str) -> Script:
        """Put the plate in upright between its slot's tines: lift it clear of them, bring it
        over its gap, line it up, lower it in watching its foot, let go."""
        self.note(f"place {'LR'[side]}")
        body = self.env.props[plate].root_body_id
        p, rotation = self.hand_pose(side)
        over = self.rest_in(slot)[2] + OVER_TINES + abs(self.human.jitter(0.02))
        up = np.array([p[0], p[1], over + self.held_offset(side, body)[2]])
        yield from self.until(self.move_hand(side, up, rotation, HOLD, speed=RAISE_SPEED))
        rotation = self.squared_rotation(side, plate)
        above = self.rest_in(slot) + np.array([0.0, 0.0, over - self.rest_in(slot)[2]])
        end = self.move_hand(side, above + self.held_offset(side, body), rotation, SQUARE_HOLD, correct=True)
        yield from self.until(end)
        for _ in range(LINE_UPS):
            off = self.off_slot(plate, slot)
            if float(np.linalg.norm(off)) < LINED_UP and self.turned(plate) < SQUARE:
                break
            rotation = self.squared_rotation(side, plate)
            p, _ = self.hand_pose(side)
            p[:2] -= off
            # down to just over the tines on the first look
            p[2] = min(p[2], self.rest_in(slot)[2] + OVER_GAP + self.held_offset(side, body)[2])
            end = self.move_hand(side, p, rotation, SQUARE_HOLD, spread=0.0, precision=0.004, speed=LINE_UP_SPEED)
            yield from self.until(end + 0.1)
        yield from self.guide_in(side, plate, slot, rotation)
        yield from self.let_go(side, rotation)

    def guide_in(self, side: int, plate: str, slot: str, rotation: np.ndarray) -> Script:
        """Lower the plate into its gap at ``GUIDE_SPEED``, the hand following where its
        foot is seen off the gap's middle (the arm drifts a centimetre sideways on the way
        down), until it stands in the tray or the hand has gone ``DEEPER`` than needed."""
        origin = self.data.xpos[self.env.props[plate].root_body_id]
        target, _ = self.hand_pose(side)
        target = target.copy()
        bottom = target[2] - (origin[2] - self.rest_in(slot)[2]) - DEEPER
        self.hands[side] = HandReference(lambda t: target.copy(), lambda t: rotation, SQUARE_HOLD, tremor=0.3)
        while origin[2] > self.rest_in(slot)[2] + IN_SLOT and target[2] > bottom:
            target[:2] -= GUIDE_GAIN * self.dt * self.off_slot(plate, slot)
            target[2] -= GUIDE_SPEED * self.dt
            yield

    def rest_in(self, slot: str) -> np.ndarray:
        """Where a plate's origin rests in ``slot`` now (the tray slides when pushed)."""
        return self.site_of(self.env.props[DISHWASHER], slot) + LOAD_IN_SLOT

    def off_slot(self, plate: str, slot: str) -> np.ndarray:
        """How far (x, y) the plate's lowest point hangs off the middle of its gap: a plate
        leaning 5 deg in the hand has its foot 1 cm off its centre, and the gap leaves 1 cm."""
        body = self.env.props[plate].root_body_id
        normal = self.data.xmat[body].reshape(3, 3)[:, 2]
        centre = self.data.xpos[body] + normal * self.env.props[plate].height / 2
        down = np.array([0.0, 0.0, -1.0]) + normal * normal[2]
        lowest = centre + down / np.linalg.norm(down) * self.env.props[plate].radius
        return (lowest - self.site_of(self.env.props[DISHWASHER], slot))[:2] - FOOT_IN_SLOT

    def squared_rotation(self, side: int, plate: str) -> np.ndarray:
        """The hand's rotation that stands the plate upright with its face along the tray's
        tines (world y), whichever way it faces now, from how it sits in the hand now (it
        turns a little in the fingers)."""
        body = self.env.props[plate].root_body_id
        frame = self.data.xmat[body].reshape(3, 3)
        face = np.array([0.0, 1.0 if frame[1, 2] >= 0.0 else -1.0, 0.0])
        return self.turned_rotation(side, body, aligning_rotation(frame[:, 2], face) @ frame)

    def turned(self, plate: str) -> float:
        """How far (rad) the plate's face is turned off the tines (world y)."""
        normal = self.data.xmat[self.env.props[plate].root_body_id].reshape(3, 3)[:, 2]
        return float(np.arccos(min(1.0, abs(float(normal[1])))))

    def carry_to_tray(self, slots: list[str]) -> Script:
        """Step back from the counter, lower the plates beside the hips and walk round the
        door's free end to the front of the pulled-out tray, crouching, facing it."""
        base = self.commanded_base()
        back = (base[0] - STEP_BACK + self.human.jitter(0.03), base[1], CARRY_HEIGHT, base[3])
        yield from self.walk([back], carrying=(LEFT, RIGHT))
        base = self.base_pose()
        ends = []
        for side in (LEFT, RIGHT):
            goal = LOAD_CARRY_AT * np.array([1.0, 1.0 if side == LEFT else -1.0, 1.0]) + self.human.jitter(0.02, 3)
            ends.append(self.move_hand_with_body(side, goal, HOLD, base, speed=CARRY_LOWER_SPEED))
        dishwasher = self.env.props[DISHWASHER]
        goals = np.array([self.site_of(dishwasher, slot) for slot in slots])
        x = float(np.min(goals[:, 0])) - TRAY_REACH + self.human.jitter(0.02)
        y = float(np.mean(goals[:, 1])) + self.human.jitter(0.03)
        self.choices["tray stance"] = [round(x, 2), round(y, 2)]
        route = [
            (ROUND_THE_DOOR_X + self.human.jitter(0.04), base[1] + 0.2, CARRY_HEIGHT, 0.5),
            (x, y, LOAD_CROUCH + self.human.jitter(0.02), self.human.jitter(0.06)),
        ]
        arrival = yield from self.walk(route, wait=False)  # the hands go with the body
        yield from self.until(max(arrival, *ends))


__all__ = ["PlateLoadExpert"]
