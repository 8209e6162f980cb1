"""SandwichToast demonstrator (scene counter_base_2_hob): the raw sandwich from the chopping
board into the frying pan, swept in with the spatula while the other hand holds the pan.

What a person does with something a spatula will not go under: holds the pan at the
counter's edge and sweeps it in. Takes the spatula out of the empty pan (left hand, as for
``SandwichRemove``), stands at the board and, the blade held at 60 degrees behind the
sandwich, draws it until it juts 4 cm over the board's near edge, stepping back as the
blade comes in; goes back to the hob and takes the pan by its handle (right hand, as pots
are taken off the hob in ``bigym/experts/cookware.py``); carries it slowly to the counter's
front in front of the sandwich and holds it there level, its rim 6 mm below the counter's
top, the handle turned back to the right; sweeps the sandwich off the board, over the
counter's edge and into the pan (again, if it did not get in); if it came to lean on the
pan's wall, presses its raised side down with the blade's tip until it lies flat, the other
hand still holding the pan; carries the pan back to the burner and sets it down level, then
lets go.

Why a sweep: the raw sandwich has square edges and lies flush on the board, so a blade
pushed at it has nothing to slide under and shoves it along (its friction on the blade,
0.8, is larger than on the board, 0.3), even against a stop; drawn over the counter's edge
by a steep blade it drops flat into a pan held level just below the edge
(``benchmarks/sandwich_toast_probe.py`` and its ``--sweep``). Why the pan is watched: held by
its handle, it turns in the fingers (about the axis they close along when the body moves,
and tips onto its far edge when let go of mid-air), so the hand's aim is corrected by how
far the pan is off its path and tilted (``HeldSteer`` in ``spatula_and_pan.py``, shared with
``SandwichFlip``'s demonstrator), as a person keeps a pan level by looking at it; walking
with it is slow.

Choices drawn per demo: the timing, the stances, the sweep's line and every path's via
points. Always the left hand for the spatula and the right for the pan: the pan's handle
points to the robot's right.
"""

from __future__ import annotations

import itertools
from typing import ClassVar

import numpy as np

from bigym.experts.cookware import FRONT_CLEARANCE, HOB_OPENING, HOB_TILT
from bigym.experts.expert import LEFT, RIGHT, SIDE_NAMES, HandReference, Script
from bigym.experts.geometry import clamp
from bigym.experts.grasping import HOLD
from bigym.experts.sandwich import ATTEMPTS, BOARD, PAN, SANDWICH, TIP
from bigym.experts.spatula_and_pan import (
    BURNER,
    COUNTER_FRONT,
    COUNTER_TOP,
    HOB,
    STEER_GAIN,
    SpatulaAndPan,
)
from bigym.props import Sandwich

#: the board's half length along x
BOARD_HALF = 0.145
#: how steeply (rad below the horizontal) the blade is held while sweeping, and how far (m)
#: its tip keeps above the surface it sweeps
SWEEP_PITCH = np.deg2rad(60.0)
SWEEP_GAP = 0.005
#: the line of the second sweep (and the pan's middle on it) runs this way (rad from +x,
#: straight in from the counter's front), give or take the person's 3 degrees
SECOND_YAW = np.deg2rad(0.0)
#: the tip goes down this far (m) behind the sandwich's far edge
BEHIND = 0.015
#: how far (m) the tip follows the sandwich sideways as it drifts off the sweep's line
FOLLOW = 0.04
#: how fast (m/s) the sandwich is swept
SWEEP_SPEED = 0.06
#: the first sweep stops when the sandwich juts this far (m) out over the board's near edge
#: (its middle still on the board)
FIRST_OVERHANG = 0.04
#: how far (m) the body steps back during the first sweep
FIRST_STEP_BACK = 0.25
#: the pan held at the counter's front: this far (m) in front of it (outer rim), its rim
#: this far below the counter's top
PAN_GAP = 0.025
RIM_BELOW = 0.006
#: how far (m) past the counter's edge the second sweep goes
PAST_EDGE = 0.05
#: the pelvis: how far (m) behind the blade's tip at the start of the first sweep, and at
#: what height; how far behind the counter's front while holding the pan
SWEEP_BACK = 0.5
SWEEP_HEIGHT = 0.92
PAN_STANCE_BACK = 0.47
#: the pan lifted this high (m) off the hob, and carried with its origin this high (m)
CARRY_LIFT = 0.07
PAN_CARRY_HEIGHT = 0.98
#: walking with the pan, slowly: it turns in the fingers about their closing axis when the
#: hand is jerked sideways
PAN_WALK_SPEED = 0.5
#: the spatula's hand moved this far (m, world) to the robot's left (it faces the counter,
#: +x) while the other hand takes and carries the pan: left over the pan, the gripper's
#: links rubbed on its rim for seconds as it was lifted and carried (in every seed looked
#: at) and pushed it down or over (most of the pans dropped)
SPATULA_ASIDE = np.array([0.0, 0.12, 0.0])
#: the most (m) the blade's aim is corrected: a blade's tip held up by what it pushes must
#: not drive the hand on down
MAX_AIM = 0.04
#: a sandwich tilted more than this (rad) in the pan is pressed flat: where (m from its raised
#: edge's side of its middle), how steeply the blade points down (rad) and how deep it goes (m)
LAID_FLAT = np.deg2rad(7.0)
PRESS_OUT = 0.035
PRESS_PITCH = np.deg2rad(70.0)
PRESS_DEPTH = 0.05
PRESS_TIME = 1.2
#: the pan's handle turned to point this way (rad) while it is held at the counter: back
#: and to the right, the hand away from the counter
PAN_HANDLE_HEADING = np.deg2rad(-120.0)


class SandwichToastExpert(SpatulaAndPan):
    """Sweeps the raw sandwich of ``SandwichToast`` from the board into the pan, held at the
    counter's edge, and puts the pan back on the hob."""

    tasks = ("SandwichToast",)
    #: the sandwich drops off the counter's edge into the pan
    drop_speeds: ClassVar[dict[str, float]] = {SANDWICH: 1.3, PAN: 1.2}
    #: tipping over the edges as it is swept off is how it gets into the pan
    may_tip: ClassVar[tuple[str, ...]] = (SANDWICH,)

    def plan(self) -> Script:
        self.held_steer = None
        self.choices["hands"] = {"spatula": SIDE_NAMES[LEFT], "pan": SIDE_NAMES[RIGHT]}
        yield from self.wait(self.human.reaction())
        self.hand_to_hip(RIGHT)
        yield from self.take_spatula(LEFT)
        yield from self.first_sweep(LEFT)
        yield from self.take_pan(RIGHT)
        yield from self.hold_pan_at_counter(RIGHT)
        for attempt in range(ATTEMPTS):
            if attempt:
                self.note(f"sweep again ({attempt})")
            yield from self.second_sweep(LEFT)
            if self.env.touching(self.env.mask(SANDWICH), self.env.mask(PAN)):
                break
        yield from self.lay_flat(LEFT)  # the other hand holding the pan
        yield from self.pan_to_burner(RIGHT)
        while True:
            yield

    def lay_flat(self, side: int) -> Script:
        """If the sandwich leans on the pan's wall, press its raised side down with the
        blade's tip until it lies flat, and lift the blade away (twice at most)."""
        body = self.env.props[SANDWICH].root_body_id
        for _ in range(2):
            frame = self.data.xmat[body].reshape(3, 3)
            up = frame[:, 2] * np.sign(frame[2, 2])
            if up[2] > np.cos(LAID_FLAT):
                return
            self.note("lay flat")
            down_side = np.array([up[0], up[1], 0.0]) / max(float(np.linalg.norm(up[:2])), 1e-6)
            press = self.data.xpos[body] + up * Sandwich.SIZE[2] / 2 - down_side * PRESS_OUT
            base = self.base_pose()
            heading = float(np.arctan2(press[1] - base[1], press[0] - base[0]))
            self.measure_hold(side)
            self.sweep_posture(side)
            self.aim = np.zeros(3)
            rot = self.spatula_rotation(np.array([np.cos(heading), np.sin(heading), 0.0]), PRESS_PITCH)
            p, r = self.hand_for(press + np.array([0.0, 0.0, 0.08]) - rot @ TIP, rot)
            yield from self.until(self.move_hand(side, p, r, HOLD, precision=0.02, spread=0.3))
            # onto it, then down through it until it lies flat, and up again from where the tip is
            start, top = self.tip(), press + np.array([0.0, 0.0, 0.01])
            yield from self.steer_tip(
                side, lambda x, start=start, top=top: start + x * (top - start), 0.6, 0.1, PRESS_PITCH, heading
            )
            yield from self.steer_tip(
                side,
                lambda x, top=top: top - np.array([0.0, 0.0, PRESS_DEPTH * x]),
                PRESS_TIME,
                0.3,
                PRESS_PITCH,
                heading,
                until=lambda body=body: self.data.xmat[body][8] ** 2 > np.cos(LAID_FLAT * 0.5) ** 2,
            )
            tip = self.tip()
            yield from self.steer_tip(
                side, lambda x, tip=tip: tip + x * np.array([0.0, 0.0, 0.1]), 0.6, 0.0, PRESS_PITCH, heading
            )
            self.arm_posture[side] = None

    # ------------------------------------------------------------------ geometry
    def sandwich_extent(self) -> tuple[float, float]:
        """The sandwich's far and near extents along x."""
        body = self.env.props[SANDWICH].root_body_id
        frame = self.data.xmat[body].reshape(3, 3)
        half = 0.5 * np.array(Sandwich.SIZE)
        ext = abs(frame[0, 0]) * half[0] + abs(frame[0, 1]) * half[1] + abs(frame[0, 2]) * half[2]
        x = float(self.data.xpos[body][0])
        return x + ext, x - ext

    def sandwich_extent_along(self, u: np.ndarray) -> float:
        """How far the sandwich reaches from its middle along horizontal ``u``."""
        frame = self.data.xmat[self.env.props[SANDWICH].root_body_id].reshape(3, 3)
        return float(np.abs(frame.T @ u) @ (0.5 * np.array(Sandwich.SIZE)))

    def steer_tip(
        self,
        side: int,
        path,
        duration: float,
        settle: float = 0.2,
        pitch: float = SWEEP_PITCH,
        heading: float = 0.0,
        until=None,
    ) -> Script:
        """The blade's tip along ``path(x)`` for x from 0 to 1 (the blade pointing along
        ``heading`` at ``pitch``), the hand's aim corrected by what the tip misses, as a
        person watching it; stopping where it is once ``until()`` holds."""
        rot = self.spatula_rotation(np.array([np.cos(heading), np.sin(heading), 0.0]), pitch)
        t0 = self.time

        def wanted(t: float) -> np.ndarray:
            return path(self.human.profile(min(max((t - t0) / duration, 0.0), 1.0)))

        def hand(t: float) -> np.ndarray:
            return self.hand_for(wanted(t) + self.aim - rot @ TIP, rot)[0]

        r = self.hand_for(np.zeros(3), rot)[1]
        self.hands[side] = HandReference(hand, lambda t: r, HOLD, tremor=0.2)
        while self.time < t0 + duration + settle:
            if until is not None and until():
                break
            yield
            self.aim = clamp(self.aim + STEER_GAIN * self.dt * (wanted(self.time) - self.tip()), MAX_AIM)
            if self.held_steer is not None:  # the other hand keeps the pan where it is
                self.held_steer.update()
        self.hold_hand(side, HOLD, tremor=0.2)

    def sweep(
        self,
        side: int,
        stops: list[np.ndarray],
        pitch: float = SWEEP_PITCH,
        heading: float = 0.0,
        posture: bool = True,
        step_back: float = 0.0,
    ) -> Script:
        """Put the tip down behind the sandwich and draw it through ``stops`` (tip points);
        ``posture``: the arm raised forward, the forearm pointing down (at arm's length);
        ``step_back``: the body steps back this far (m) as the blade is drawn in."""
        self.measure_hold(side)
        if posture:
            self.sweep_posture(side)
        self.aim = np.zeros(3)
        rot = self.spatula_rotation(np.array([np.cos(heading), np.sin(heading), 0.0]), pitch)
        above = stops[0] + np.array([0.0, 0.0, 0.08])
        p, r = self.hand_for(above - rot @ TIP, rot)
        yield from self.until(self.move_hand(side, p, r, HOLD, precision=0.02, spread=0.3))
        start = self.tip()
        yield from self.steer_tip(side, lambda x: start + x * (stops[0] - start), 0.8, 0.2, pitch, heading)
        if step_back:
            length = sum(float(np.linalg.norm(b - a)) for a, b in itertools.pairwise(stops))
            base = self.base_pose()
            back = np.array([-np.cos(heading), -np.sin(heading), 0.0, 0.0]) * step_back
            self.move_base(base + back, duration=length / SWEEP_SPEED)
        across = np.array([-np.sin(heading), np.cos(heading), 0.0])
        sandwich = self.data.xpos[self.env.props[SANDWICH].root_body_id]

        def behind(point: np.ndarray) -> np.ndarray:
            """The tip kept behind the sandwich's middle as it drifts sideways (watched)."""
            return point + across * float(np.clip((sandwich - point) @ across, -FOLLOW, FOLLOW))

        for a, b in itertools.pairwise(stops):
            duration = float(np.linalg.norm(b - a)) / SWEEP_SPEED * float(np.exp(self.human.jitter(0.08)))
            yield from self.steer_tip(
                side, lambda x, a=a, b=b: behind(a + x * (b - a)), max(duration, 0.4), 0.0, pitch, heading
            )
        end = self.tip()
        yield from self.steer_tip(side, lambda x: end + x * np.array([0.03, 0.0, 0.1]), 0.6, 0.2, pitch, heading)
        self.arm_posture[side] = None

    # ------------------------------------------------------------------ steps
    def surface_stops(self, begin: np.ndarray, end_x: float, u: np.ndarray) -> list[np.ndarray]:
        """Tip points from ``begin`` (on the board) back along ``-u`` to ``end_x``, over the
        board and then down its edge onto the counter."""
        board = self.site(BOARD, "top")
        board_near = float(board[0]) - BOARD_HALF
        top = float(board[2]) + SWEEP_GAP

        def at_x(x: float, z: float) -> np.ndarray:
            point = begin + u * (x - begin[0]) / u[0]
            return np.array([point[0], point[1], z])

        stops = [np.array([begin[0], begin[1], top])]
        if end_x < board_near - 0.03:
            stops += [at_x(board_near - 0.01, top), at_x(board_near - 0.03, COUNTER_TOP + SWEEP_GAP)]
            stops.append(at_x(end_x, COUNTER_TOP + SWEEP_GAP))
        else:
            stops.append(at_x(end_x, top))
        return stops

    def first_sweep(self, side: int) -> Script:
        """Stand at the board and draw the sandwich to its near edge, stepping back as the
        blade comes in."""
        self.note("first sweep")
        body = self.env.props[SANDWICH].root_body_id
        y = float(self.data.xpos[body][1]) + self.human.jitter(0.005)
        far, near = self.sandwich_extent()
        begin = np.array([far + BEHIND, y, 0.0])
        board_near = float(self.site(BOARD, "top")[0]) - BOARD_HALF
        end_x = begin[0] - (near - (board_near - FIRST_OVERHANG + self.human.jitter(0.005)))
        stops = self.surface_stops(begin, end_x, np.array([1.0, 0.0, 0.0]))
        stance = np.array([begin[0] - SWEEP_BACK, y - 0.12, SWEEP_HEIGHT, 0.0])
        stance[0] = min(stance[0], COUNTER_FRONT - 0.16)
        yield from self.walk([stance], carrying=[side])
        yield from self.sweep(side, stops, step_back=FIRST_STEP_BACK)

    def take_pan(self, side: int) -> Script:
        """Step back to the hob and take the pan by its handle, lifting it off the burner."""
        self.note("take pan")
        handle, along, approach, stance = self.hob_handle(PAN, side, COUNTER_FRONT - FRONT_CLEARANCE)
        self.lift_spatula(LEFT)
        yield from self.wait(0.3)
        yield from self.walk([stance], carrying=[LEFT])
        yield from self.take_handle(side, PAN, handle, along, approach, CARRY_LIFT, tilt=HOB_TILT, opening=HOB_OPENING)

    def lift_spatula(self, side: int) -> None:
        """Raise the spatula a little out of the other hand's way, as it is held (not turned
        level as :meth:`stow_spatula` does for a walk: stowed level here, the other hand's
        grasp of the pan's handle failed), and move it aside, clear of the pan."""
        p, r = self.hand_pose(side)
        self.move_hand(side, p + np.array([-0.05, 0.0, 0.1]) + SPATULA_ASIDE, r, HOLD, duration=0.5, spread=0.0)

    def hold_pan_at_counter(self, side: int) -> Script:
        """Carry the pan out over the counter's front edge in front of the sandwich, then
        down until its rim is just below the counter's top, and hold it there."""
        self.note("pan to counter")
        pan = self.env.props[PAN]
        body = pan.root_body_id
        sandwich = self.data.xpos[self.env.props[SANDWICH].root_body_id]
        x = COUNTER_FRONT - pan.radius - PAN_GAP
        heading = SECOND_YAW + self.human.jitter(np.deg2rad(3.0))
        self.choices["sweep heading"] = round(float(np.degrees(heading)), 1)
        goal = np.array(
            [x, float(sandwich[1]) - (float(sandwich[0]) - x) * np.tan(heading), COUNTER_TOP - RIM_BELOW - pan.DEPTH]
        )
        start = self.data.xpos[body].copy()
        high = np.array([goal[0], goal[1], max(float(start[2]), PAN_CARRY_HEIGHT)])
        stance = np.array([COUNTER_FRONT - PAN_STANCE_BACK, goal[1], SWEEP_HEIGHT, 0.0])
        yield from self.until(self.stow_spatula(LEFT, SPATULA_ASIDE))
        end = yield from self.walk([stance], carrying=[LEFT], speed=PAN_WALK_SPEED, wait=False, from_plan=True)
        heading = PAN_HANDLE_HEADING + self.human.jitter(np.deg2rad(5.0))
        yield from self.steer_held(
            side, body, lambda x: start + x * (high - start), max(end - self.time, 1.0), 0.6, True, heading
        )
        yield from self.steer_held(side, body, lambda x: high + x * (goal - high), 1.2, 0.5, True, heading)

    def second_sweep(self, side: int) -> Script:
        """Sweep the sandwich over the counter's edge into the pan, along the line from the
        pan's middle through the sandwich's."""
        self.note("second sweep")
        centre = self.data.xpos[self.env.props[SANDWICH].root_body_id].copy()
        pan = self.data.xpos[self.env.props[PAN].root_body_id]
        u = np.array([centre[0] - pan[0], centre[1] - pan[1], 0.0])
        u /= np.linalg.norm(u)
        begin = centre + u * (self.sandwich_extent_along(u) + BEHIND)
        stops = self.surface_stops(begin, COUNTER_FRONT - PAST_EDGE, u)
        # drawn in close to the body, the arm finds its own way
        yield from self.sweep(side, stops, SWEEP_PITCH, float(np.arctan2(u[1], u[0])), posture=False)

    def pan_to_burner(self, side: int) -> Script:
        """Lift the pan over the counter's top, carry it back over the burner and put it down."""
        self.note("pan to burner")
        pan = self.env.props[PAN]
        body = pan.root_body_id
        start = self.data.xpos[body].copy()
        up = start + np.array([0.0, 0.0, COUNTER_TOP + 0.06 - float(start[2])])
        yield from self.steer_held(side, body, lambda x: start + x * (up - start), 0.8, 0.1, True)
        spot = self.site(HOB, BURNER) + self.human.jitter(0.01, 3) * np.array([1.0, 1.0, 0.0])
        over = np.array([spot[0], spot[1], up[2]])
        stance = np.array([min(COUNTER_FRONT - 0.14, spot[0] - 0.45), spot[1] - 0.05, 0.92, 0.0])
        yield from self.until(self.stow_spatula(LEFT, SPATULA_ASIDE))
        end = yield from self.walk([stance], carrying=[LEFT], speed=PAN_WALK_SPEED, wait=False, from_plan=True)
        yield from self.steer_held(side, body, lambda x: up + x * (over - up), max(end - self.time, 1.2), 0.3, True)
        yield from self.set_pan_down(side, body, over, spot)


__all__ = ["SandwichToastExpert"]
