"""FlipCup demonstrator (scene cabinet): turn the upside-down mug on the counter upright.

The mug is wider (86-94 mm) than the gripper opens (85 mm), so a person takes it by its
handle, which faces them: they turn the hand over first (thumb down, elbow out), take the
handle's bar, lift the mug a little and roll the forearm over, so that the mug turns
about the line from the handle to its middle and comes up the right way in about the
place it was; then they set it down, feel it rest flat, let go and draw the hand back.

Why the hand is turned before it takes the handle: the H1's wrist rolls +-90 degrees, so
it gives the half turn only when it starts at one end of its range; the shoulder makes
up the rest (an arm held out sideways rolls the forearm). The roll is about the
horizontal part of the hand's approach, which passes close to the mug's centre of mass:
the mug hangs almost still in the fingers while it turns (held off that line, it would
pivot about the fingers' closing axis, the one way the pads hold weakly).

Choices drawn per demo: the hand (mostly the one on the mug's side), which way the
forearm rolls (the hand starting thumb-down or thumb-up), how low the body crouches,
where it stands, how high the mug is lifted, the timing, and every path's via-points.
"""

from __future__ import annotations

import numpy as np

from bigym.experts.expert import ARM_ACTIVE_COST, LEFT, RIGHT, SIDE_NAMES, HandReference, Script
from bigym.experts.geometry import axis_angle_matrix
from bigym.experts.grasping import FLAT, HOLD, TABLE_CLEARANCE, GraspingExpert
from bigym.robot.h1 import ARM_JOINTS

MUG = "mug"
#: x of the counter's front edge (scene cabinet)
COUNTER_FRONT = 0.58
#: the hand takes the handle with the wrist this far (rad) into one end of its range ...
WRIST_START = 1.5
#: ... which the IK keeps to this firmly while the hand reaches (the other arm joints stay
#: as relaxed as usual)
WRIST_START_COST = 1.0
#: the arm's posture (left arm; the right one mirrors roll and yaw) the IK leans towards
#: while the hand reaches, turned over: shoulder rolled out, elbow out to the side
TURNED_ARM = {"shoulder_pitch": -0.6, "shoulder_roll": 1.35, "shoulder_yaw": -0.8, "elbow": -0.3}
#: how firmly (IK posture cost) the IK keeps to that posture, per joint (others: as usual)
TURNED_ARM_COST = {"shoulder_roll": 0.5, "shoulder_yaw": 0.2}
#: pelvis height (m) while working at the counter: low enough that the forearm is
#: about level with the handle
CROUCH = 0.75
#: how far (m) sideways of the handle the hand's shoulder stands
SHOULDER_OFFSET = 0.2
#: how high (m) the mug is lifted to turn it (the lowest corner of a mug turning about its
#: middle sweeps ~7 cm below it)
LIFT = 0.1
#: how sharply the hand choice follows the mug's side (m)
HAND_CHOICE_SOFTNESS = 0.08


class FlipCupExpert(GraspingExpert):
    """Turns the mug of ``FlipCup`` upright by its handle."""

    tasks = ("FlipCup",)
    #: x of the front edge of the counter the mug stands on
    counter_front = COUNTER_FRONT

    def plan(self) -> Script:
        handle = self.site(MUG, "handle")
        base = self.base_pose()
        lateral = float(-np.sin(base[3]) * (handle[0] - base[0]) + np.cos(base[3]) * (handle[1] - base[1]))
        side = self.hand_on_side(lateral, HAND_CHOICE_SOFTNESS)
        # the roll's direction, which end of its range the wrist starts at: either for the
        # right hand; the left one's mirror of the second (wrist at +WRIST_START) took the
        # handle in a contorted posture and dropped it in trials, so the left rolls one way
        start = -WRIST_START if side == LEFT or self.rng.random() < 0.5 else WRIST_START
        self.choices["hand"] = SIDE_NAMES[side]
        # seen from behind the hand (the angle of :meth:`turn_over` about an axis pointing away)
        self.choices["roll"] = "clockwise" if start < 0 else "anticlockwise"
        yield from self.wait(self.human.reaction())
        yield from self.take_handle(side, start)
        yield from self.turn_over(side, start)
        yield from self.set_down(side)
        yield from self.release(side, back=0.08, up=0.04, relax=True)
        while True:
            yield

    # ------------------------------------------------------------------ steps
    def take_handle(self, side: int, wrist: float) -> Script:
        """Crouch in front of the mug and take its handle's bar, the hand already turned
        to one end of the wrist's range."""
        handle = self.site(MUG, "handle")
        approach = self.data.xpos[self.env.props[MUG].root_body_id] - handle  # towards the mug's axis
        approach[2] = 0.0
        approach /= np.linalg.norm(approach)
        yield from self.take_bar(side, wrist, handle, np.array([0.0, 0.0, 1.0]), approach, CROUCH)

    def take_bar(
        self,
        side: int,
        wrist: float,
        point: np.ndarray,
        line: np.ndarray,
        approach: np.ndarray,
        crouch: float,
        shoulder_offset: float = SHOULDER_OFFSET,
    ) -> Script:
        """Crouch in front of the counter, ``side``'s shoulder beside ``point`` (the pelvis
        ``shoulder_offset`` to the side of it), and take the bar through ``point`` along
        ``line`` (either way), the hand coming in along the horizontal ``approach`` with the
        wrist already at ``wrist``, one end of its range."""
        shift = shoulder_offset if side == LEFT else -shoulder_offset
        stance = np.array(
            [
                self.counter_front - TABLE_CLEARANCE - 0.16 - abs(self.human.jitter(0.02)),
                point[1] - shift + self.human.jitter(0.03),
                crouch + self.human.jitter(0.02),
                self.human.jitter(0.05),
            ]
        )
        self.move_base(stance)
        mirror = 1.0 if side == LEFT else -1.0
        posture = np.array(
            [TURNED_ARM[j] * (mirror if j in ("shoulder_roll", "shoulder_yaw") else 1.0) for j in ARM_JOINTS[:-1]]
            + [wrist]
        )
        cost = np.array([TURNED_ARM_COST.get(j, ARM_ACTIVE_COST) for j in ARM_JOINTS[:-1]] + [WRIST_START_COST])
        self.arm_posture[side] = (posture, cost)
        bar = np.asarray(line, float) / np.linalg.norm(line)
        if bar @ self.bar_direction(side, wrist) < 0.0:
            bar = -bar
        yield from self.grasp_bar(side, point, bar, approach, depth=0.0, close=False, keep_sign=True)
        yield from self.settle(side, point, 0.008, 0.5)
        yield from self.set_grip(side, 1.0)
        self.arm_posture[side] = None

    def bar_direction(self, side: int, wrist: float) -> np.ndarray:
        """The way (up or down) the pinch x axis points along the handle's bar: the one that
        makes the wrist start at ``wrist``."""
        return np.array([0.0, 0.0, -np.sign(wrist) * (1.0 if side == RIGHT else -1.0)])

    def turn_over(self, side: int, wrist: float) -> Script:
        """Lift the mug and roll the forearm half a turn in one movement, about the
        horizontal part of the hand's approach."""
        self.note(f"turn over {'LR'[side]}")
        lift = LIFT + abs(self.human.jitter(0.02))
        duration = self.human.duration(np.pi * 0.1 + lift, 0.02, minimum=0.9) * 1.3
        yield from self.roll_over(side, wrist, np.array([0.0, 0.0, lift]), duration * 0.6, 0.0, duration)

    def roll_over(
        self, side: int, wrist: float, lift: np.ndarray, lift_time: float, roll_start: float, roll_time: float
    ) -> Script:
        """Move the hand by ``lift`` (m) over ``lift_time`` s and, from ``roll_start`` s on,
        roll the forearm half a turn over ``roll_time`` s about the horizontal part of the
        hand's approach: the wrist turns from ``wrist`` towards its other end (the arms are
        mirror images)."""
        site = self.env.robot.pinch_site_ids[side]
        p0 = self.data.site_xpos[site].copy()
        r0 = self.data.site_xmat[site].reshape(3, 3).copy()
        axis = np.array([r0[0, 2], r0[1, 2], 0.0])
        axis /= np.linalg.norm(axis)
        angle = -np.sign(wrist) * np.pi
        position = self.human.path([p0, p0 + lift], lift_time)
        t0 = self.time
        profile = self.human.profile

        def rotation(t: float) -> np.ndarray:
            return axis_angle_matrix(axis, angle * profile((t - t0 - roll_start) / roll_time)) @ r0

        self.hands[side] = HandReference(
            lambda t: position(min(max(t - t0, 0.0), lift_time)), rotation, HOLD, tremor=0.3
        )
        yield from self.until(t0 + roll_start + roll_time)
        self.hold_hand(side, HOLD, tremor=0.3)

    def set_down(self, side: int) -> Script:
        """Straighten the mug in the hand, lower it until it rests flat on the counter."""
        self.note(f"set down {'LR'[side]}")
        body = self.env.props[MUG].root_body_id
        level = self.level_rotation(side, body)
        p, _ = self.hand_pose(side)
        yield from self.until(self.move_hand(side, p, level, HOLD, duration=0.4, spread=0.0, tremor=0.3))
        frame = self.data.xmat[body]
        yield from self.lower_until(
            side, level, LIFT + 0.06, 0.5, lambda: self.touches_support(MUG) and frame[8] >= np.cos(FLAT)
        )
        self.hold_hand(side, HOLD, tremor=0.2)
        yield from self.wait(0.1)


__all__ = ["FlipCupExpert"]
