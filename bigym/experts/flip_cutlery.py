"""FlipCutlery demonstrator (scene cabinet): turn the spoon standing in the mug bowl-down.

A person takes the spoon by its bowl, the hand coming from in front, draws it out of the
mug along its own line, rolls the forearm over so the bowl points down, holds it upright over the
mug, lowers it bowl first into the mug and lets go; the spoon leans against the rim.

The half turn is the forearm roll of :mod:`bigym.experts.flip_cup`: the hand is turned to
one end of the wrist's range before it takes the spoon (the H1's wrist rolls +-90 deg),
the arm held out to the side rolls the rest. Rolled about a horizontal axis, any spoon
comes bowl-down whatever way it leaned; the hand then stands it upright.

The fingers cannot follow the spoon into the mug (they stop about 2 cm over the rim), so
it is let go with the tip of its bowl about 8 cm over the mug's bottom and falls in; the
demo generator allows it that fall (:attr:`drop_speeds`).

Choices drawn per demo: the hand (mostly the one on the spoon's side), how low the body
crouches, where it stands, the approach's direction, how high the spoon is lifted, the
timing, and every path's via-points.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.experts.expert import LEFT, SIDE_NAMES, Script
from bigym.experts.flip_cup import WRIST_START, FlipCupExpert
from bigym.experts.geometry import aligning_rotation, axis_angle_matrix
from bigym.experts.grasping import HOLD

MUG = "mug"
SPOON = "spoon"
#: pelvis height (m) while taking the spoon: the forearm about level with the bowl
CROUCH = 0.85
#: how far (m) the spoon is drawn out along its line: the handle's end leaves the mug
LIFT = 0.17
#: how high (m) above the mug's rim the bowl's middle is held before it goes in
OVER_RIM = 0.05
#: how far (m) over the mug's rim the pinch is lowered to let go (the finger links touch
#: the rim at about 1.1 cm)
DIP = 0.02
#: how much further out (m) than usual the free hand goes beside the hip: its fingers
#: brushed the torso on the way there
FREE_HAND_OUT = 0.07
#: how sharply the hand choice follows the spoon's side (m)
HAND_CHOICE_SOFTNESS = 0.06


class FlipCutleryExpert(FlipCupExpert):
    """Turns the spoon of ``FlipCutlery`` bowl-down in its mug."""

    tasks = ("FlipCutlery",)
    #: let go with its tip ~8 cm over the mug's bottom (the fingers stop at the rim), the
    #: spoon falls in and tips against the rim: its origin moves down at up to 1.5 m/s
    drop_speeds: ClassVar[dict[str, float]] = {SPOON: 1.6}
    #: let go upright over the mug, the spoon falls in and comes to lean against the rim,
    #: 40-42 degrees from how it was held in the demos looked at: the way it is put down,
    #: not a knock (the mug is still watched)
    may_tip: ClassVar[tuple[str, ...]] = (SPOON,)

    def plan(self) -> Script:
        head = self.site(SPOON, "head")
        base = self.base_pose()
        lateral = float(-np.sin(base[3]) * (head[0] - base[0]) + np.cos(base[3]) * (head[1] - base[1]))
        side = self.hand_on_side(lateral, HAND_CHOICE_SOFTNESS)
        # the hand is turned thumb-down before it takes the spoon (left clockwise, right
        # anticlockwise, mirror images); the right hand's other way, which FlipCup uses,
        # pulled the body down onto the counter when the spoon stood near its edge
        start = -WRIST_START if side == LEFT else WRIST_START
        self.choices["hand"] = SIDE_NAMES[side]
        yield from self.wait(self.human.reaction())
        # the other hand out of the way of the counter while crouching, clear of the body
        self.hand_to_hip(1 - side, wider=FREE_HAND_OUT)
        yield from self.take_spoon(side, start)
        yield from self.turn_spoon(side, start)
        yield from self.put_back(side)
        while True:
            yield

    # ------------------------------------------------------------------ steps
    def spoon_axis(self) -> np.ndarray:
        """The spoon's long axis, handle to bowl (world)."""
        return self.data.xmat[self.env.props[SPOON].root_body_id].reshape(3, 3)[:, 1].copy()

    def take_spoon(self, side: int, wrist: float) -> Script:
        """Crouch in front of the mug and take the spoon's bowl, the hand coming in
        level from the body's side and already turned to one end of the wrist's range."""
        head = self.site(SPOON, "head")
        base = self.base_pose()
        approach = np.array([head[0] - base[0], head[1] - base[1], 0.0])
        approach /= np.linalg.norm(approach)
        approach = axis_angle_matrix(np.array([0.0, 0.0, 1.0]), self.human.jitter(0.15)) @ approach
        yield from self.take_bar(side, wrist, head, self.spoon_axis(), approach, CROUCH)

    def turn_spoon(self, side: int, wrist: float) -> Script:
        """Draw the spoon out of the mug along its own line (straight up, its handle would
        drag on the mug), then roll the forearm half a turn: the bowl comes down."""
        self.note(f"turn over {'LR'[side]}")
        lift = LIFT + abs(self.human.jitter(0.02))
        lift_time = self.human.duration(lift, 0.01, minimum=0.6)
        roll_time = self.human.duration(np.pi * 0.1, 0.01, minimum=0.9) * 1.3
        # the roll starts once the handle's end is nearly out of the mug
        yield from self.roll_over(side, wrist, self.spoon_axis() * lift, lift_time, lift_time * 0.8, roll_time)

    def put_back(self, side: int) -> Script:
        """Stand the spoon upright over the mug, lower it bowl first into the mug until the
        fingers are just over the rim, let go and draw the hand back out."""
        self.note(f"put back {'LR'[side]}")
        site = self.env.robot.pinch_site_ids[side]
        hand = self.data.site_xmat[site].reshape(3, 3)
        upright = aligning_rotation(self.spoon_axis(), np.array([0.0, 0.0, -1.0])) @ hand
        inside = self.site(MUG, "inside")
        rim = self.site(MUG, "rim")
        head_in_hand = self.data.site_xpos[site] - self.site(SPOON, "head")
        over = np.array([inside[0], inside[1], rim[2] + OVER_RIM]) + self.human.jitter(0.005, 3)
        yield from self.until(
            self.move_hand(side, over + head_in_hand, upright, HOLD, correct=True, precision=0.01, tremor=0.3)
        )
        yield from self.hesitate()
        # look again, the spoon hanging still, then down into the mug
        head_in_hand = self.data.site_xpos[site] - self.site(SPOON, "head")
        down = np.array([inside[0], inside[1], 0.0]) + head_in_hand
        down[2] = rim[2] + DIP + abs(self.human.jitter(0.005))
        yield from self.until(
            self.move_hand(side, down, upright, HOLD, spread=0.0, precision=0.004, speed=0.5, tremor=0.3)
        )
        self.hold_hand(side, HOLD, tremor=0.2)
        yield from self.wait(0.1 + abs(self.human.jitter(0.05)))
        yield from self.release(side, back=0.1, up=0.05, relax=True)


__all__ = ["FlipCutleryExpert"]
