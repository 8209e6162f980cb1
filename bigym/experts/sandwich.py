"""SandwichRemove demonstrator (scene counter_base_2_hob): the toasted sandwich from the
frying pan onto the chopping board, with the spatula.

What a person does: takes the spatula lying in the pan by the end of its handle, the
handle pointing along the forearm like a pen's (the fingers close on the handle's top and
bottom faces, where a flat handle is held stiffly: closed on its sides, it would pivot
between the pads under the blade's load), and opens them a little and slides the hand
further up if it closed on the handle's very end; lifts it off the sandwich; stands up
and holds the blade steeply in the gap between the sandwich and the pan's near wall, square to the
sandwich's edge; pushes it in along the pan's floor, flattening it only as far as the
rim lets the blade and then the handle pass over it. The sandwich slides until it meets
the far wall, and its rounded edge rides up onto the blade. They lift it over the rim,
the blade turned level (the tip a little up, so that it cannot slide off over the tip),
look, and push in again if it is not lying on the blade; walk sideways holding the
spatula still until the sandwich is over the board, lower the blade to just over it,
tip the blade down about its tip so that the sandwich slides off forward onto the board,
draw the blade back out from under it, flatter, and lift it away.

Why the blade goes in so steeply: the 9 cm blade has to reach the floor in a gap of 1-4
cm between the sandwich and the wall, its back end over the rim (4.5 cm high): at first
about 60 degrees down, 10-15 degrees by the end of the push (:meth:`slide_under`). Why
the arm is told what posture to take: pointing the forearm down at the pan from above
needs the upper arm raised forward and the elbow bent; left to find its own way from the
grasp, the IK reached by moving the body half a metre forward instead, and the blade
never got down into the pan.

Choices drawn per demo: which face of the sandwich the blade goes in at (the one facing
the person most nearly, and the push up to a few degrees off square to it), where the
body stands, how steeply the blade is tipped over the board, where over the board the
sandwich is brought, the timing, and every path's via-points. Always the left hand: the
pan stands to the robot's left, the board to its right (the right hand was not tried).

``SandwichFlip``'s demonstrator (``bigym/experts/sandwich_flip.py``) turns the sandwich
over slowly about one of its edges and settles it by tilting the pan. Tossed over by
rolling the blade half a turn instead, the sandwich turned upside down in about half the
episodes at 500 Hz, but how it landed varied with the slightest change, so that a replay
at 50, 25 or 20 Hz repeated the flip in only about one in six (3 of 40 seeds kept). Turned
about a side edge (the blade rolled about its length, so that no rim limits where the edge
goes down), it slid down the blade once that was rolled past about 39 degrees (the blade's
friction, 0.8) before its edge touched the floor, landing 2-4 cm nearer the middle than
aimed; rolled less, the blade under its middle met the rim before the edge was down (seeds
0-3, both ways: one turned over, onto the wall). Turned in over the rim from outside the
pan, it slid off the blade into the pan right side up (8 of 8).

``SandwichToast``'s demonstrator sweeps the raw sandwich into the pan held at the counter's
edge instead (``bigym/experts/sandwich_toast.py``): a blade pushed at it shoves it along,
even against a stop (``benchmarks/sandwich_toast_probe.py``).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.sandwich import PAN_FLOOR
from bigym.experts.expert import ARM_ACTIVE_COST, LEFT, SIDE_NAMES, HandReference, Script
from bigym.experts.geometry import axis_angle_matrix, frame_from_axes
from bigym.experts.grasping import EMPTY_GRIP, HOLD, GraspingExpert
from bigym.props import FryingPan, Sandwich
from bigym.robot.h1 import ARM_JOINTS

PAN = "pan"
SPATULA = "spatula"
SANDWICH = "sandwich"
BOARD = "board"
#: the spatula (``bigym/props/cookware.py``), in its frame (y along it, handle to blade; z
#: up from the blade): the blade's tip, where the fingers close on the handle, and the
#: point on the handle's line over the blade's middle
TIP = np.array([0.0, 0.1325, 0.0])
GRIP = np.array([0.0, -0.105, 0.0255])
OVER_BLADE = np.array([0.0, 0.0875, 0.024])
#: the blade's length (m) and how much higher (m) the handle's underside is
BLADE = 0.09
HANDLE_RISE = 0.0175
#: the wall's inner face at the pan's rim is this far (m) out from the bottom's edge; how
#: far (m) over the rim the blade and the handle pass
PAN_FLARE = FryingPan.FLARE - FryingPan.WALL
RIM_CLEARANCE = 0.008
#: how far (m) before the sandwich's near edge the blade's tip goes down, and the blade's
#: steepest and flattest pitch (rad below the horizontal) while it goes in
GAP = 0.015
STEEP = np.deg2rad(62.0)
FLAT = np.deg2rad(10.0)
#: the face of the sandwich (its own axis, and which end) the blade goes in at, in the
#: order of :meth:`SandwichRemoveExpert.slide_under`'s pushes (along -x, +x, -y, +y)
FACE_NAMES = ("+x", "-x", "+y", "-y")
#: how far (rad, one sd) the push may stray from square to the sandwich's face
FACE_JITTER = 0.08
#: how far (m) the tip is pushed along the floor, in about how long (s), and how far
#: below the floor (m) it is aimed: it presses lightly on it. Slowly: the spatula, pressed
#: on the floor by its tip, can turn a little in the hand, and a quick push (1.5 s) turned
#: it differently in the replays at 50, 25 and 20 Hz than in the recording (their blade
#: flatter, riding over the sandwich instead of under it): 13 of 40 seeds' replays failed
#: so, against 6 of 40 at 2.5 s
PUSH = 0.12
PUSH_TIME = 2.5
PRESS = 0.002
#: the pelvis while pushing: this far (m) behind the blade's tip, the shoulder (SHOULDER_Y
#: to the side of the pelvis) near the line of the push; standing up while the forearm
#: points steeply down, crouching as the blade flattens
BODY_BACK = 0.62
SHOULDER_Y = 0.155
HIGH = 1.0
LOW = 0.86
#: the arm's posture the IK leans towards while the blade goes in (left arm): the upper
#: arm raised forward, the elbow bent, the forearm pointing down at the pan; and how
#: firmly (the wrist: GRIP_WRIST_COST)
PUSH_ARM = {"shoulder_pitch": -1.6, "shoulder_roll": 0.25, "shoulder_yaw": 0.48, "elbow": 2.37}
PUSH_ARM_COST = 0.3
#: the wrist's angle (rad, left hand) that closes the fingers on the handle's top and
#: bottom faces with the forearm along the handle, which the IK keeps to while reaching
GRIP_WRIST = 1.1
GRIP_WRIST_COST = 1.0
#: pelvis height (m) while taking the spatula
STANCE_HEIGHT = 0.8
#: a hand that closed more than this (m) short of GRIP, on the handle's last centimetres
#: (it shoved the spatula along as it slid in), opens to REGRIP_OPENING, slides up the
#: handle and closes again, at most REGRIP_TRIES times: held by its end, the spatula
#: pivots in the hand under the push (10 of the 12 such seeds of 40 failed)
REGRIP_SHORT = 0.012
REGRIP_OPENING = 0.3
REGRIP_TRIES = 2
#: how long (s) the hand may take, at most, to point the blade down as planned (within
#: OVER_ALIGNED rad) before it goes down into the pan
OVER_WAIT = 1.5
OVER_ALIGNED = np.deg2rad(8.0)
#: how far (m) the blade is lifted straight up after the push, then how far more, level
#: (LEVEL_PITCH: the tip a little up), to clear the rim
LIFT = 0.04
RAISE = 0.07
LEVEL_PITCH = np.deg2rad(-4.0)
#: the sandwich rides on the blade when it is clear of the floor, within this (rad) of
#: level and its middle within this (m) of the blade's middle line
ON_BLADE_TILT = np.deg2rad(15.0)
ON_BLADE_SIDEWAYS = 0.025
#: how often the hand takes the handle, or the blade is pushed in under the sandwich,
#: before the person gives up
ATTEMPTS = 3
#: over the board: how steeply (rad) the blade is tipped down to let the sandwich slide
#: off, and how far (m) forward of where it lay on the blade it comes to rest
SLIDE_PITCH = np.deg2rad(45.0)
SLIDE_AHEAD = 0.08


class SandwichRemoveExpert(GraspingExpert):
    """Takes the sandwich of ``SandwichRemove`` out of the pan onto the board with the spatula."""

    tasks = ("SandwichRemove",)
    #: the sandwich slides off the tipped blade and drops onto the board, turning flat
    #: (its middle comes down at up to about 1.1 m/s); the spatula, held throughout, swings
    #: down with the hand as the blade is tipped (its origin, at the neck, at up to 1.1 m/s)
    drop_speeds: ClassVar[dict[str, float]] = {SANDWICH: 1.3, SPATULA: 1.2}
    #: turning flat as it slides off the blade (25-37 deg in the demos looked at) is the
    #: way it is put down, not a knock
    may_tip: ClassVar[tuple[str, ...]] = (SANDWICH,)

    def plan(self) -> Script:
        side = LEFT
        self.choices["hand"] = SIDE_NAMES[side]
        yield from self.wait(self.human.reaction())
        self.hand_to_hip(1 - side)
        yield from self.take_spatula(side)
        for attempt in range(ATTEMPTS):
            if attempt:
                self.note(f"push in again ({attempt})")
            yield from self.slide_under(side)
            yield from self.raise_level(side)
            if self.on_blade():
                break
        else:
            while True:  # the person gives up
                yield
        yield from self.carry_to_board(side)
        yield from self.slide_off(side)
        while True:
            yield

    # ------------------------------------------------------------------ geometry
    def spatula_frame(self) -> tuple[np.ndarray, np.ndarray]:
        body = self.env.props[SPATULA].root_body_id
        return self.data.xpos[body].copy(), self.data.xmat[body].reshape(3, 3).copy()

    def spatula_rotation(self, direction: np.ndarray, pitch: float) -> np.ndarray:
        """The spatula's orientation pointing along horizontal ``direction``, the blade
        ``pitch`` rad below the horizontal, its face up."""
        u = np.array([direction[0], direction[1], 0.0])
        u /= np.linalg.norm(u)
        y = np.cos(pitch) * u + np.sin(pitch) * np.array([0.0, 0.0, -1.0])
        x = np.cross(y, np.array([0.0, 0.0, 1.0]))
        x /= np.linalg.norm(x)
        return np.column_stack([x, y, np.cross(x, y)])

    def measure_hold(self, side: int) -> None:
        """Remember how the spatula sits in the hand (it may have turned a little)."""
        site = self.env.robot.pinch_site_ids[side]
        pos, rot = self.spatula_frame()
        hand_p, hand_r = self.data.site_xpos[site], self.data.site_xmat[site].reshape(3, 3)
        self.held = (rot.T @ (hand_p - pos), rot.T @ hand_r)

    def hand_for(self, pos: np.ndarray, rot: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The pinch pose that holds the spatula at (``pos``, ``rot``) as it is held."""
        p, r = self.held
        return pos + rot @ p, rot @ r

    def on_blade(self) -> bool:
        """The sandwich rides on the lifted blade: clear of the pan's floor, about level,
        over the blade."""
        body = self.env.props[SANDWICH].root_body_id
        centre = self.data.xpos[body]
        floor = self.data.xpos[self.env.props[PAN].root_body_id][2] + PAN_FLOOR
        pos, rot = self.spatula_frame()
        raised = centre[2] - floor - Sandwich.SIZE[2] / 2 > 0.5 * RAISE
        flat = abs(self.data.xmat[body][8]) > np.cos(ON_BLADE_TILT)  # either side up
        over_blade = abs(float(rot[:, 0] @ (centre - pos))) < ON_BLADE_SIDEWAYS
        return bool(raised and flat and over_blade)

    # ------------------------------------------------------------------ steps
    def take_spatula(self, side: int) -> Script:
        """Take the spatula's handle near its end, the hand coming in along the handle
        with the fingers above and below it (and again if they closed on nothing), and
        lift it off the sandwich."""
        posture = np.zeros(len(ARM_JOINTS))
        posture[-1] = GRIP_WRIST
        cost = np.full(len(ARM_JOINTS), ARM_ACTIVE_COST)
        cost[-1] = GRIP_WRIST_COST
        self.arm_posture[side] = (posture, cost)
        for attempt in range(ATTEMPTS):
            self.note(f"take spatula {'LR'[side]}" + (f" again ({attempt})" if attempt else ""))
            pos, rot = self.spatula_frame()
            grip = pos + rot @ GRIP
            if not attempt:
                along = np.array([rot[0, 1], rot[1, 1], 0.0])
                height = STANCE_HEIGHT - grip[2]
                self.move_base(self.stance(side, grip, along, distance=0.35, lateral=0.15, height=height))
            approach = rot[:, 1]
            rotation = frame_from_axes(np.cross(rot[:, 2], approach), approach)
            self.grip[side] = 0.5  # half closed: the open lower finger would touch the hob
            pre = grip - approach * 0.08 + np.array([0.0, 0.0, 0.02])
            end = self.move_hand(side, pre, rotation, HOLD, lift=0.05, precision=0.02, correct=not attempt)
            yield from self.until(end)
            yield from self.hesitate()
            yield from self.until(self.move_hand(side, grip, rotation, HOLD, duration=0.5, spread=0.05, tremor=0.3))
            yield from self.settle(side, grip, 0.008, 0.5)
            yield from self.set_grip(side, 1.0)
            if float(self.env.robot.gripper_state(self.data)[side]) < EMPTY_GRIP:
                break
            self.grip[side] = 0.5
            p, r = self.hand_pose(side)
            yield from self.until(self.move_hand(side, p - r[:, 2] * 0.06 + np.array([0.0, 0.0, 0.03]), r, HOLD))
        self.measure_hold(side)
        for _ in range(REGRIP_TRIES):
            short = GRIP[1] - float(self.held[0][1])
            if short <= REGRIP_SHORT:
                break
            yield from self.regrip(side, short)
        p, r = self.hand_pose(side)
        yield from self.until(self.move_hand(side, p + np.array([0.0, 0.0, 0.07]), r, HOLD, duration=0.6, spread=0.0))

    def regrip(self, side: int, short: float) -> Script:
        """Open the fingers a little around the handle, slide the hand ``short`` m up it
        towards the blade, and close them again."""
        self.note(f"take spatula {'LR'[side]} further up")
        yield from self.set_grip(side, REGRIP_OPENING, max_wait=0.5, min_wait=0.2)
        _, rot = self.spatula_frame()
        site = self.env.robot.pinch_site_ids[side]
        goal = self.data.site_xpos[site] + rot[:, 1] * short
        rotation = self.data.site_xmat[site].reshape(3, 3).copy()
        yield from self.until(self.move_hand(side, goal, rotation, HOLD, duration=0.5, spread=0.0, tremor=0.3))
        yield from self.settle(side, goal, 0.006, 0.4)
        yield from self.set_grip(side, 1.0)
        self.measure_hold(side)

    def slide_under(self, side: int) -> Script:
        """Stand up behind the pan, put the blade's tip down steeply between the sandwich
        and the near wall, square to the sandwich's edge, and push it in along the floor,
        flattening it as far as the rim lets it; lift it a little."""
        self.note("slide under")
        self.measure_hold(side)
        sandwich = self.env.props[SANDWICH].root_body_id
        centre = self.data.xpos[sandwich].copy()
        frame = self.data.xmat[sandwich].reshape(3, 3)
        # square to the face that faces the person most nearly (they stand square to the
        # counter): the edge is nearest there, and meets the blade along its length
        facing = self.module_facing("cabinet_1")
        normals = [sign * frame[:, k] * np.array([1.0, 1.0, 0.0]) for k in (0, 1) for sign in (-1.0, 1.0)]
        face = int(np.argmax([float(n @ facing) / float(np.linalg.norm(n)) for n in normals]))
        self.choices["face"] = FACE_NAMES[face]
        u = normals[face] / np.linalg.norm(normals[face])
        u = axis_angle_matrix(np.array([0.0, 0.0, 1.0]), self.human.jitter(FACE_JITTER)) @ u
        half = 0.5 * np.array(Sandwich.SIZE[:2])
        extent = abs(frame[:, 0] @ u) * half[0] + abs(frame[:, 1] @ u) * half[1]
        pan = self.env.props[PAN]
        pan_pos = self.data.xpos[pan.root_body_id].copy()
        tip0 = centre - u * (extent + GAP)
        tip0[2] = pan_pos[2] + PAN_FLOOR - PRESS
        rim = pan.radius + PAN_FLARE  # the wall's inner face at the rim, from the pan's axis

        def clear_pitch(tip: np.ndarray) -> float:
            """How steep the blade must be for it (or, once the blade is inside the pan, the
            handle) to pass over the near rim."""
            behind = float((tip - pan_pos) @ u) + rim  # the tip's distance from the near rim
            height = pan.DEPTH + RIM_CLEARANCE
            if behind > BLADE * np.cos(STEEP):
                height -= HANDLE_RISE
            return float(np.clip(np.arctan2(height, max(behind, 1e-3)), FLAT, STEEP))

        def hand_at(tip: np.ndarray, pitch: float | None = None) -> tuple[np.ndarray, np.ndarray]:
            rot = self.spatula_rotation(u, clear_pitch(tip) if pitch is None else pitch)
            return self.hand_for(tip - rot @ TIP, rot)

        left = np.array([-u[1], u[0], 0.0])
        body = tip0 - u * BODY_BACK - left * SHOULDER_Y * 0.8
        yaw = float(np.arctan2(u[1], u[0]))
        posture = np.array([*(PUSH_ARM[j] for j in ARM_JOINTS[:-1]), GRIP_WRIST])
        cost = np.array([PUSH_ARM_COST] * (len(ARM_JOINTS) - 1) + [GRIP_WRIST_COST])
        self.arm_posture[side] = (posture, cost)
        over = hand_at(tip0 + np.array([0.0, 0.0, 0.06]), clear_pitch(tip0))
        end = self.move_base(np.array([body[0], body[1], HIGH, yaw]))
        yield from self.until(max(end, self.move_hand(side, *over, HOLD, precision=0.02, spread=0.3)))
        # the arm turns over into the posture that points the blade down: wait for it
        deadline = self.time + OVER_WAIT
        while self.time < deadline and self.ik.pose(side)[1][:, 2] @ over[1][:, 2] < np.cos(OVER_ALIGNED):
            yield
        down = hand_at(tip0)
        yield from self.until(self.move_hand(side, *down, HOLD, duration=0.6, spread=0.0, tremor=0.2))
        self.note("push")
        t0 = self.time
        duration = PUSH_TIME * float(np.exp(self.human.jitter(0.1)))
        profile = self.human.profile

        def pose(t: float) -> tuple[np.ndarray, np.ndarray]:
            return hand_at(tip0 + u * PUSH * profile(min(max((t - t0) / duration, 0.0), 1.0)))

        self.hands[side] = HandReference(lambda t: pose(t)[0], lambda t: pose(t)[1], HOLD, tremor=0.2)
        self.move_base(np.array([body[0], body[1], LOW, yaw]), duration=duration)
        yield from self.until(t0 + duration)
        self.hold_hand(side, HOLD, tremor=0.2)
        p, r = self.hand_pose(side)
        yield from self.until(self.move_hand(side, p + np.array([0.0, 0.0, LIFT]), r, HOLD, duration=0.5, spread=0.0))

    def raise_level(self, side: int) -> Script:
        """Lift the blade over the rim, turning it level."""
        self.arm_posture[side] = None
        pos, rot = self.spatula_frame()
        along = np.array([rot[0, 1], rot[1, 1], 0.0])
        self.along = along / np.linalg.norm(along)
        over_blade = pos + rot @ OVER_BLADE + np.array([0.0, 0.0, RAISE + self.human.jitter(0.008)])
        level = self.spatula_rotation(self.along, LEVEL_PITCH)
        p, r = self.hand_for(over_blade - level @ OVER_BLADE, level)
        yield from self.until(self.move_hand(side, p, r, HOLD, duration=0.8, spread=0.0, tremor=0.2))

    def carry_to_board(self, side: int) -> Script:
        """Walk sideways, the spatula held still, until the sandwich is over the board
        (short of its middle by about as far as it will slide off forward)."""
        self.note("carry")
        sandwich = self.data.xpos[self.env.props[SANDWICH].root_body_id]
        ahead = SLIDE_AHEAD + self.human.jitter(0.01)
        goal = self.site(BOARD, "top") - self.along * ahead + self.human.jitter(0.015, 3)
        shift = goal - sandwich
        yield from self.walk(
            [self.base_pose() + np.array([shift[0], shift[1], 0.0, 0.0])], carrying=[side], speed=0.6, from_plan=True
        )

    def slide_off(self, side: int) -> Script:
        """Lower the blade to just over the board, tip it down about its tip until the
        sandwich slides off forward onto the board, draw it back out from under it,
        flatter, and lift it away."""
        self.note("slide off")
        pos, rot = self.spatula_frame()
        tip = pos + rot @ TIP
        board_top = self.site(BOARD, "top")[2]
        tipped = SLIDE_PITCH + self.human.jitter(np.deg2rad(2.0))
        # (duration, tip's height over the board, how far the tip is drawn back, pitch)
        steps = [
            (0.6, 0.016, 0.0, LEVEL_PITCH),  # down to just over the board, level
            (0.8, 0.004, 0.0, tipped),  # tipped about the tip: the sandwich slides off
            (0.8, 0.004, 0.10, np.deg2rad(20.0)),  # drawn back, flatter: its back comes down
            (0.6, 0.08, 0.16, np.deg2rad(20.0)),  # up and away
        ]
        for duration, height, back, pitch in steps:
            rotation = self.spatula_rotation(self.along, pitch)
            goal = np.array([tip[0], tip[1], board_top + height]) - self.along * back
            p, r = self.hand_for(goal - rotation @ TIP, rotation)
            duration *= float(np.exp(self.human.jitter(0.08)))
            yield from self.until(self.move_hand(side, p, r, HOLD, duration=duration, spread=0.0, tremor=0.2))


__all__ = ["SandwichRemoveExpert"]
