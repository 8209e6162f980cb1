"""DishwasherUnloadCups demonstrator: move the two upside-down mugs from the dishwasher's
pulled-out upper tray onto the counter beside it.

The mugs are wider than the gripper opens, so a person takes each by its handle, which
faces them. Crouching in front of the tray, they shape the hand to the handle's thin bar
and come straight down onto it, the hand tilted down towards the mug a little (coming in
level, the fingers caught the tray's front wall and pushed the tray in), close, lift the
mug out and hold it back and out to the side, out of the other hand's way; the front
mug's hand goes first when one mug stands behind the other. Holding both, they raise them
over the counter's height, stand up, walk round the open door to the counter beside the
dishwasher and put the mugs down on it one after the other, still upside down, each
lowered until it rests flat (one that hangs tilted is lifted, straightened and lowered
again).

Choices drawn per demo: which mug is put down first, where each goes on the counter, how
low the body crouches, where it stands, the timing, and every path's via-points.
"""

from __future__ import annotations

import numpy as np

from bigym.envs.dishwasher_plates import COUNTER_TOP
from bigym.experts.dishwasher_load_cups import CupLoadExpert
from bigym.experts.expert import ALIGN_BAR, LEFT, RIGHT, SIDE_NAMES, Script
from bigym.experts.geometry import axis_angle_matrix
from bigym.experts.grasping import HOLD, to_base

MUGS = ("mug_1", "mug_2")
#: how far (rad) the hand is tilted down towards the mug as it takes the handle's bar: a
#: steeper hand keeps its fingers further over the tray's front wall but holds the mug
#: less firmly about the fingers' closing axis (at 45-55 degrees carried mugs tilted by
#: 35-65 degrees in the fingers and could not be set down flat)
SLANT = np.deg2rad(25.0)
#: how far the fingers are closed beforehand (0: wide open), the hand shaped to the thin
#: bar: wide open, a finger came down on the tray's front wall beside the handle
OPENING = 0.5
#: how far (m) over the handle the shaped hand comes before it goes down onto it
DESCENT = 0.07
#: pelvis height at the tray, and how far (m) behind the handles (their middle) it stands
TRAY_CROUCH = 0.72
TRAY_REACH = 0.4
#: the pelvis comes no nearer the tray than this (x): its hips would push the tray's handle
NEAREST_X = -0.24
#: how high (m) a mug is lifted out of the tray (its rim clears the walls, 4.5 cm)
LIFT = 0.09
#: where (m: back, out, up) a mug lifted out is held while the other hand takes its mug
ASIDE = (0.12, 0.08, 0.06)
#: how many times at most a hand reaches for a handle it missed
TAKES = 2
#: how far (m) the held mugs are raised (in the body's frame) before the walk: over the
#: counter's edge
RAISE = 0.2
#: where the robot stands at the counter (x; y beside the dishwasher) and how high
COUNTER_STANCE = (0.0, -0.62)
COUNTER_HEIGHT = 0.85
#: where on the counter the mugs go: x, and y either side of the pelvis
COUNTER_X = 0.56
COUNTER_APART = 0.16


class CupUnloadExpert(CupLoadExpert):
    """Unloads the two mugs of ``DishwasherUnloadCups`` onto the counter."""

    tasks = ("DishwasherUnloadCups",)

    def plan(self) -> Script:
        centres = {mug: self.data.xpos[self.env.props[mug].root_body_id].copy() for mug in MUGS}
        # the mug further along +y is the left hand's (on a tie, the front one)
        left_mug, right_mug = sorted(MUGS, key=lambda mug: (-round(centres[mug][1], 3), centres[mug][0]))
        self.mug_of = mug_of = {LEFT: left_mug, RIGHT: right_mug}
        # the hand of the front mug first: the other may reach over it
        first = LEFT if centres[left_mug][0] <= centres[right_mug][0] + 0.01 else RIGHT
        self.choices["first taken"] = SIDE_NAMES[first]
        self.first = first
        yield from self.wait(self.human.reaction())
        yield from self.walk_to_tray()
        for side in (first, 1 - first):
            yield from self.take_mug(side, mug_of[side])
        yield from self.walk_to_counter()
        first = LEFT if self.rng.random() < 0.5 else RIGHT
        self.choices["first put down"] = SIDE_NAMES[first]
        base = self.base_pose()
        for side in (first, 1 - first):
            if self.env.held(mug_of[side]):  # (a mug a hand never got stays where it is)
                target = np.array(
                    [
                        COUNTER_X + self.human.jitter(0.02),
                        base[1] + (COUNTER_APART if side == LEFT else -COUNTER_APART) + self.human.jitter(0.02),
                        COUNTER_TOP,
                    ]
                )
                self.note(f"put {mug_of[side]} {'LR'[side]}")
                yield from self.put_down(
                    side, mug_of[side], target, self.env.target_mask, feel_all_the_way=True, relax=False
                )
        while True:
            yield

    def walk_to_tray(self) -> Script:
        """Round the door's free end to the front of the tray, crouching."""
        self.note("walk to tray")
        base = self.commanded_base()
        handles = np.array([self.site(mug, "handle") for mug in MUGS])
        x = min(float(np.mean(handles[:, 0])) - TRAY_REACH, NEAREST_X) + self.human.jitter(0.02)
        y = float(np.mean(handles[:, 1])) + self.human.jitter(0.03)
        stance = (x, y, TRAY_CROUCH + self.human.jitter(0.02), self.human.jitter(0.05))
        yield from self.walk([(base[0] - 0.3, base[1] + 0.1, base[2], 0.0), stance])

    def walk_to_counter(self) -> Script:
        """Raise the mugs over the counter's height, step back from the tray and walk round
        the door to the counter beside the dishwasher, standing up."""
        self.note("walk to counter")
        base = self.base_pose()  # the plan: the IK holds the crouching body higher, reaching in
        ends = []
        for side in (LEFT, RIGHT):
            p, r = self.hand_pose(side)
            local, _ = to_base(base, p, r)
            ends.append(self.move_hand_with_body(side, local + np.array([-0.1, 0.0, RAISE]), HOLD, base))
        yield from self.until(max(ends))
        route = [
            (base[0] - 0.15, base[1] - 0.4, base[2], -0.3),
            (
                COUNTER_STANCE[0] + self.human.jitter(0.03),
                COUNTER_STANCE[1] + self.human.jitter(0.03),
                COUNTER_HEIGHT + self.human.jitter(0.02),
                self.human.jitter(0.05),
            ),
        ]
        yield from self.walk(route, carrying=(LEFT, RIGHT), from_plan=True)

    def reach_down_to(self, side: int, point: np.ndarray, bar: np.ndarray, approach: np.ndarray) -> Script:
        """Shape the hand to the bar over ``point`` and come straight down onto it: coming
        in along the slant, the lower finger crossed the tray's front wall."""
        self.note(f"reach bar {'LR'[side]}")
        rotation = self.bar_grasp_rotation(side, bar, approach)
        above = point + np.array([0.0, 0.0, DESCENT + abs(self.human.jitter(0.02))]) + self.human.jitter(0.005, 3)
        self.grip[side] = OPENING
        yield from self.until(
            self.move_hand(
                side, above, rotation, ALIGN_BAR, lift=abs(self.human.jitter(0.03)), precision=0.03, correct=True
            )
        )
        yield from self.hesitate()
        self.note(f"insert {'LR'[side]}")
        down = max(0.35, self.human.duration(DESCENT, 0.004) * 0.6)
        yield from self.until(self.move_hand(side, point, rotation, ALIGN_BAR, duration=down, spread=0.05, tremor=0.5))
        yield from self.wait(0.15 + abs(self.human.jitter(0.05)))

    def take_mug(self, side: int, mug: str) -> Script:
        """Come down onto the handle's bar, close, lift the mug out and hold it aside."""
        for attempt in range(TAKES):
            self.note(f"take {mug} {'LR'[side]}")
            handle = self.site(mug, "handle")
            level = self.data.xpos[self.env.props[mug].root_body_id] - handle  # towards the mug's axis
            level[2] = 0.0
            level /= np.linalg.norm(level)
            closing = np.cross([0.0, 0.0, 1.0], level)  # horizontal, across the bar
            slant = SLANT + self.human.jitter(0.05)
            tilt = axis_angle_matrix(closing, slant)
            approach = tilt @ level  # forward and down
            bar = tilt @ np.array([0.0, 0.0, 1.0])  # the pads' width: the bar crosses it at the slant
            yield from self.reach_down_to(side, handle, bar, approach)
            yield from self.settle(side, handle, 0.008, 0.5)
            yield from self.set_grip(side, 1.0)
            if self.env.held(mug) or attempt == TAKES - 1:
                break
            self.note(f"missed {mug}")
            yield from self.release(side, back=0.06, up=0.04)
        p, r = self.hand_pose(side)
        lift = LIFT + abs(self.human.jitter(0.02))
        duration = self.human.duration(lift, 0.02, minimum=0.6) * 1.5
        end = self.move_hand(side, p + np.array([0.0, 0.0, lift]), r, HOLD, duration=duration, spread=0.0, tremor=0.3)
        yield from self.until(end)
        # drawn back towards the body and out to its side: out of the other hand's way
        aside = np.array([-ASIDE[0], ASIDE[1] if side == LEFT else -ASIDE[1], ASIDE[2]]) + self.human.jitter(0.02, 3)
        end = self.move_hand(side, p + np.array([0.0, 0.0, lift]) + aside, r, HOLD, spread=0.1, tremor=0.3)
        if side == self.first:
            yield from self.until(end)


__all__ = ["CupUnloadExpert"]
