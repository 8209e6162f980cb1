"""Grasping skills: take an object from above, carry it while walking, put it down.

What a person does, and so what these skills do: the hand comes to a point before the
object with the fingers open and already turned to the object's faces (pre-grasp), goes
in slowly, closes (and tries again if it closed on nothing), lifts it clear; the object
is carried with the hand held still relative to the body while the person walks; at the
goal the person stands where the arm reaches the spot as it reached the object, holds it
level over the spot, lowers it until it is felt to rest, opens, and draws the hand away.

The hand closes across two faces of the object (pinch y along their normal, kept
horizontal) and comes in from the front and above (pinch z tilted down from the body's
forward direction): the 5-joint arm cannot point the hand straight down at arm's length,
and a person does not either. The closing direction is turned only as far as the wrist
and the body turn comfortably, so for objects with symmetric faces (a cube: four) the
face pair nearest the hand's natural, across-the-body direction is chosen.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Generator, Sequence

import numpy as np

from bigym.experts.expert import FREE, LEFT, Expert, HandReference, Script
from bigym.experts.geometry import axis_angle_matrix, frame_from_axes, yaw_matrix
from bigym.robot.h1 import STANDING_HEIGHT

DOWN = np.array([0.0, 0.0, -1.0])
#: how far (m) before a grasp point, along the approach, the hand pauses before going in
PRE_GRASP_HEIGHT = 0.1
#: walking and turning speeds (m/s, rad/s) a leg's peak stays under: below the IK's base limits
WALK_SPEED = 0.7
TURN_SPEED = 1.0
#: how fast (m/s) the pelvis goes down or up at most while walking (crouching with a load)
CROUCH_SPEED = 0.35
PEAK = 1.875  # peak over mean speed of a minimum-jerk movement
#: how much of a walking leg overlaps the next (the corners are rounded, not stopped at)
LEG_OVERLAP = 0.3
#: how close (m) the pinch point comes to a thin object's grasp point before closing, and
#: how long (s) a hand may take to get there
SETTLE_DISTANCE = 0.008
MAX_SETTLE = 0.5
#: how far (m) the pelvis keeps from the edge of a table it works at: the hip collider's
#: front is 0.05 ahead of it
TABLE_CLEARANCE = 0.12
#: a gripper closed further than this holds nothing
EMPTY_GRIP = 0.85
#: where a free hand waits beside the hip (base frame, the left hand's; the right one
#: mirrored), out of the way of the furniture when crouching close to it
HAND_AT_HIP = np.array([0.0, 0.24, 0.15])
#: orientation costs of a grasp, about the pinch axes: turning about the closing axis (y)
#: only tilts the approach and is left almost free; turning about the other two moves the
#: closing direction off the object's face normal
GRASP = np.array([2.0, 0.1, 2.0])
#: a put-down object lies flat within this (rad) of level; an edge-first one is lowered
#: the rest of the way at this speed (m/s)
FLAT = np.deg2rad(4.0)
LOWER_SPEED = 0.08
#: an object lowered into a slot is down when its origin is within this (m) of its goal
LANDED = 0.003
#: orientation costs while holding an object: it turns with the hand, about every axis
HOLD = np.array([2.0, 1.0, 2.0])
#: orientation costs while carrying: the object stays level
CARRY = np.array([0.8, 0.8, 1.5])
#: how steeply (rad below the horizontal) the hand comes down onto an object: at arm's
#: length the arm gives 20-35 degrees
GRASP_TILT = 0.5
#: closing directions (rad from the body's lateral axis, counter-clockwise seen from above)
#: each hand reaches down to comfortably, measured with the IK on points 0.3-0.5 m ahead:
#: the right hand from -20 to +40 degrees, the left mirrored
COMFORT = {0: (-0.6, 0.3), 1: (-0.3, 0.6)}


class GraspingExpert(Expert):
    """An :class:`Expert` with pick, carry and place skills."""

    def start(self) -> None:
        #: per hand, the pinch pose in the base frame when it took what it holds
        self.grasp_pose: list[tuple[np.ndarray, np.ndarray] | None] = [None, None]
        self._not_robot: np.ndarray | None = None  # geoms that are not the robot's (built on first use)
        super().start()

    # ------------------------------------------------------------------ geometry
    def grasp_rotation(
        self, side: int, closing: np.ndarray, tilt: float = GRASP_TILT, upright: bool = False
    ) -> np.ndarray:
        """Pinch frame closing along ``closing`` (made horizontal; the sign that turns the
        wrist least, or with ``upright`` the one whose x axis points down: one wrist posture
        whichever sign, for a hand reaching far and nearly level) and approaching from the body's side, ``tilt`` rad
        below horizontal."""
        y = np.array([closing[0], closing[1], 0.0])
        y /= np.linalg.norm(y)
        forward = yaw_matrix(self.base_pose()[3]) @ np.array([1.0, 0.0, 0.0])
        ahead = forward - (forward @ y) * y
        ahead /= np.linalg.norm(ahead)
        approach = np.cos(tilt) * ahead + np.sin(tilt) * DOWN
        if upright:
            if np.cross(y, approach)[2] > 0.0:
                y = -y
        elif self.hand_pose(side)[1][:, 1] @ y < 0.0:
            y = -y
        return frame_from_axes(np.cross(y, approach), approach)

    def face_closing(
        self, side: int, object_yaw: float, faces: int = 4, facing_yaw: float | None = None
    ) -> tuple[np.ndarray, float]:
        """The closing direction for an object with ``faces`` symmetric faces (normals at
        yaw + k 2 pi / faces) nearest the middle of ``side``'s comfortable range, for the
        body facing ``facing_yaw`` (default: as it stands); and how far (rad) the body
        should turn for it to lie inside that range."""
        yaw = self.base_pose()[3] if facing_yaw is None else facing_yaw
        low, high = COMFORT[side]
        middle = 0.5 * (low + high)
        best_delta = np.inf
        for k in range(faces):
            normal = object_yaw + k * 2.0 * np.pi / faces
            delta = float(np.angle(np.exp(2j * (normal - (yaw + 0.5 * np.pi)))) / 2.0)  # the closing sign is free
            if abs(delta - middle) < abs(best_delta - middle):
                best_delta = delta
        turn = best_delta - float(np.clip(best_delta, low, high))
        direction = yaw_matrix(yaw + 0.5 * np.pi + best_delta) @ np.array([1.0, 0.0, 0.0])
        return direction, turn

    # ------------------------------------------------------------------ skills
    def pick(
        self,
        side: int,
        aim: Callable[[], tuple[np.ndarray, np.ndarray]],
        lift: float = 0.12,
        via: Sequence[np.ndarray] | None = None,
        attempts: int = 3,
        prop: str | None = None,
        opening: float = 0.0,
        tilt: float = GRASP_TILT,
        cost: np.ndarray = GRASP,
        thin: bool = True,
        upright: bool = False,
        adjust: int = 0,
        firm: float = 0.0,
    ) -> Generator[None, None, bool]:
        """Take an object from above and lift it ``lift`` metres; ``aim()`` gives the pinch
        point and the closing direction from the object as it lies now. A grasp that
        closes on nothing (the object slipped away or was missed) is tried again from
        above, as a person would, up to ``attempts`` times: it holds when the fingers
        stopped short of closing, or, given the object's ``prop`` name (thin objects: the
        fingers close almost fully on them), when the task sees it held. ``opening``
        half-closes the fingers on the way in (0 = wide open), for an object with a
        neighbour close beside it. ``tilt`` and ``cost``: how steeply the hand comes down and
        how firmly the IK keeps its orientation (see :data:`GRASP`). ``thin`` False: the
        named object is thick, so fingers closed almost fully hold nothing even if one
        touches it. ``upright``: see :meth:`grasp_rotation`. ``adjust``: how often at most the
        hand, seen to have stopped more than ``SETTLE_DISTANCE`` from the pinch point, moves by
        what it missed before closing (where the IK falls short of the point, a move by the
        error gets there). ``firm``: how long (s) the closed fingers hold still before the
        lift, so that the grip on a thin rim is firm. Returns whether it holds."""
        for attempt in range(attempts):
            self.note(f"pick {'LR'[side]}" + (f" again ({attempt})" if attempt else ""))
            point, closing = aim()
            rotation = self.grasp_rotation(side, closing, tilt, upright)
            approach = rotation[:, 2]
            above = point - approach * (PRE_GRASP_HEIGHT + abs(self.human.jitter(0.02)))
            self.grip[side] = opening
            end = self.move_hand(
                side,
                above,
                rotation,
                cost,
                lift=0.05,
                correct=not attempt,
                precision=0.03,
                via=None if attempt else via,
            )
            yield from self.until(end)
            yield from self.hesitate()
            end = self.move_hand(side, point, rotation, cost, spread=0.0, precision=0.004, speed=0.6, tremor=0.3)
            yield from self.until(end + 0.1)
            if prop is not None:  # a thin object is taken only once the fingers are round it
                yield from self.settle(side, point, SETTLE_DISTANCE, MAX_SETTLE)
            yield from self.adjust_pinch(side, point, adjust)
            yield from self.set_grip(side, 1.0, max_wait=0.8, min_wait=0.35)
            yield from self.wait(firm)
            closed_on_something = float(self.env.robot.gripper_state(self.data)[side]) < EMPTY_GRIP
            if prop is None:
                holds = closed_on_something
            else:
                holds = self.env.held(prop) and (thin or closed_on_something)
            goal = (point if holds else self.hand_pose(side)[0]) + np.array([0.0, 0.0, lift if holds else 0.06])
            if holds:  # from now on the hand keeps the orientation it grasped with: the object turns with it
                rotation = self.data.site_xmat[self.env.robot.pinch_site_ids[side]].reshape(3, 3).copy()
                pinch = self.data.site_xpos[self.env.robot.pinch_site_ids[side]].copy()
                self.grasp_pose[side] = to_base(self.commanded_base(), pinch, rotation)
            else:
                self.grip[side] = 0.0
            end = self.move_hand(side, goal, rotation, HOLD if holds else cost, spread=0.2, tremor=0.5)
            yield from self.until(end)
            if holds:
                return True
        return False

    def stance_for(self, side: int, pinch_target: np.ndarray, yaw: float) -> np.ndarray:
        """A base pose (x, y, z, yaw) from which ``side``'s hand reaches ``pinch_target`` the
        way it held the object when it took it: the arm then takes the same posture, and
        the object comes down as level as it went up."""
        local, _ = self.grasp_pose[side]
        rotation = yaw_matrix(yaw)
        origin = np.asarray(pinch_target, float) - rotation @ local
        return np.array([origin[0], origin[1], float(np.clip(origin[2], 0.6, STANDING_HEIGHT)), yaw])

    def turned_rotation(self, side: int, body: int, orientation: np.ndarray | None) -> np.ndarray:
        """The hand orientation that turns a held body level (``orientation`` None) or to
        ``orientation``."""
        if orientation is None:
            return self.level_rotation(side, body)
        hand = self.data.site_xmat[self.env.robot.pinch_site_ids[side]].reshape(3, 3)
        held = self.data.xmat[body].reshape(3, 3)
        return np.asarray(orientation, float) @ held.T @ hand

    def level_rotation(self, side: int, body: int) -> np.ndarray:
        """The hand orientation that puts a held body level (its most vertical axis along
        the world's), turning the hand as little as possible from where it is."""
        frame = self.data.xmat[body].reshape(3, 3)
        axis = frame[:, int(np.argmax(np.abs(frame[2, :])))]
        axis = axis * np.sign(axis[2])
        turn_axis = np.cross(axis, [0.0, 0.0, 1.0])
        angle = float(np.arcsin(min(1.0, np.linalg.norm(turn_axis))))
        hand = self.data.site_xmat[self.env.robot.pinch_site_ids[side]].reshape(3, 3)
        if angle < 1e-6:
            return hand.copy()
        return axis_angle_matrix(turn_axis / np.linalg.norm(turn_axis), angle) @ hand

    def held_offset(self, side: int, body: int) -> np.ndarray:
        """Where the pinch point is relative to a held body's origin (world axes): how the
        object sits in the hand, as a person sees it."""
        return self.data.site_xpos[self.env.robot.pinch_site_ids[side]] - self.data.xpos[body]

    def touches_support(self, prop: str) -> bool:
        """The prop touches something that is not the robot (what it is put down on)."""
        if self._not_robot is None:
            model = self.model
            robot_root = model.body_rootid[self.env.robot.pelvis_id]
            self._not_robot = model.body_rootid[model.geom_bodyid] != robot_root
        return self.env.touching(self.env.mask(prop), self._not_robot)

    def hand_to_hip(self, side: int, wider: float = 0.0) -> float:
        """Bring a free hand beside the hip (``wider``: this much further out, m), where it
        stays as the body moves; returns the end time."""
        hip = HAND_AT_HIP + np.array([0.0, wider, 0.0])
        goal = hip * np.array([1.0, 1.0 if side == LEFT else -1.0, 1.0]) + self.human.jitter(0.02, 3)
        # measured from the IK's commanded base, which can lag the plan a few centimetres (a
        # free hand does not mind the small jump; the shipped demos were recorded so)
        return self.move_hand_with_body(side, goal, FREE, self.commanded_base())

    def move_hand_with_body(
        self,
        side: int,
        goal: np.ndarray,
        orientation_cost: np.ndarray,
        base: np.ndarray,
        via: Sequence[np.ndarray] = (),
        speed: float = 1.0,
        duration: float | None = None,
    ) -> float:
        """Move a hand to ``goal`` in the body's frame (``base``: the body's pose it is
        measured from now), through the ``via`` points (also in the body's frame), keeping
        its orientation in that frame, ``speed`` times as fast as a free movement (or over
        ``duration`` s); it then stays there as the body moves, so it can start before a
        walk does. Returns the end time."""
        p, r = self.hand_pose(side)
        local_p, local_r = to_base(base, p, r)
        points = [local_p, *via, goal]
        if duration is None:
            length = sum(float(np.linalg.norm(b - a)) for a, b in itertools.pairwise(points))
            duration = self.human.duration(length, 0.05) / speed
        path = self.human.path(points, duration)
        t0 = self.time
        self.hands[side] = HandReference(
            (lambda t: from_base(self.base_ref(t), path(min(max(t - t0, 0.0), duration)), None)[0]),
            (lambda t: from_base(self.base_ref(t), None, local_r)[1]),
            orientation_cost,
            tremor=0.5,
        )
        return t0 + duration

    def adjust_pinch(self, side: int, point: np.ndarray, tries: int) -> Script:
        """Move the hand by how far its pinch point is from ``point`` (when more than
        ``SETTLE_DISTANCE``), at most ``tries`` times: a person sees the fingers short of
        the spot and moves them there."""
        site = self.env.robot.pinch_site_ids[side]
        for _ in range(tries):
            error = self.data.site_xpos[site] - point
            if np.linalg.norm(error) <= SETTLE_DISTANCE:
                break
            self.note(f"adjust {'LR'[side]} {np.linalg.norm(error) * 1000:.0f}")
            reference, rotation = self.hand_pose(side)
            end = self.move_hand(
                side, reference - error, rotation, GRASP, spread=0.0, precision=0.004, speed=0.5, tremor=0.3
            )
            yield from self.until(end + 0.1)

    def settle(self, side: int, point: np.ndarray, distance: float, max_wait: float) -> Script:
        """Wait (at most ``max_wait`` s) until the hand's pinch point is within ``distance``."""
        site = self.env.robot.pinch_site_ids[side]
        end = self.time + max_wait
        while self.time < end and float(np.linalg.norm(self.data.site_xpos[site] - point)) > distance:
            yield

    def place(
        self,
        side: int,
        point: np.ndarray,
        prop: str | None = None,
        sink: float = 0.015,
        level: bool = True,
        orientation: np.ndarray | None = None,
        feel: bool = True,
        tip_down: float = 0.0,
        land: float = 0.0,
        headroom: float | None = None,
    ) -> Script:
        """Put the held object down so that its origin (the pinch centre if ``prop`` is
        None) ends at ``point``, open, and rise away. With ``prop``, the hand goes on down
        slowly, up to ``sink`` metres past the point, until the object rests on something,
        as a person feels it land, so that the opening fingers cannot drag it along; with
        ``level``, the object is first turned level, or, given ``orientation`` (a rotation
        matrix), turned to it (else it keeps how it is held). Without ``feel`` the object
        is lowered to the point whatever it touches on the way (a plate sliding down
        between a rack's holders). ``tip_down``: an object held far from its middle (a pan
        by its handle) hangs tilted in the fingers and first rests on its low edge; the hand
        then goes on down, up to this far (m), turning it about that edge until it lies flat.
        ``land`` (without ``feel``): the object may hang a little higher in the hand than
        it did; the hand goes on down, up to this far (m), until the object is at ``point``,
        so that it is let go of resting, not dropped. ``headroom``: at most this far (m) above
        ``point`` before it is lowered (under a counter, a tall object has little room).
        """
        self.note(f"place {'LR'[side]}")
        _, rotation = self.hand_pose(side)
        body = None if prop is None else self.env.props[prop].root_body_id
        # held: close to the pinch (a block), or, for objects held far from their origin (a
        # plate by its rim), held as the task sees it
        holding = body is not None and (
            np.linalg.norm(self.held_offset(side, body)) < 0.08 if level else self.env.held(prop)
        )
        if holding and (level or orientation is not None):  # straighten it, as a person does
            rotation = self.turned_rotation(side, body, orientation)
        rise = PRE_GRASP_HEIGHT * 0.8 + abs(self.human.jitter(0.02))
        above = point + np.array([0.0, 0.0, rise if headroom is None else min(rise, headroom)])
        if holding:
            above = above + self.held_offset(side, body)
        end = self.move_hand(side, above, rotation, HOLD, correct=True, precision=0.02)
        yield from self.until(end)
        rest_height = float(point[2])
        if holding:  # look again, now that the object hangs still over the spot
            if level or orientation is not None:
                rotation = self.turned_rotation(side, body, orientation)
            point = point + self.held_offset(side, body)
        end = self.move_hand(side, point, rotation, HOLD, spread=0.0, precision=0.004, speed=0.5, tremor=0.3)
        if prop is None or not feel:
            yield from self.until(end + 0.15)
            if land and body is not None:
                origin = self.data.xpos[body]  # down until it stands at its rest height
                yield from self.lower_until(side, rotation, land, 0.3, lambda: origin[2] <= rest_height + LANDED)
                self.hold_hand(side, HOLD, tremor=0.2)
        else:
            while self.time < end and not self.touches_support(prop):
                yield
            if not self.touches_support(prop):
                end = self.move_hand(
                    side, point - np.array([0.0, 0.0, sink]), rotation, HOLD, duration=0.6, spread=0.0, tremor=0.2
                )
                while self.time < end and not self.touches_support(prop):
                    yield
            if tip_down:  # held off-centre, it hangs tilted: its low edge rests first
                frame = self.data.xmat[body]  # down until it lies within FLAT of level
                yield from self.lower_until(side, rotation, tip_down, 0.4, lambda: frame[8] >= np.cos(FLAT))
            self.hold_hand(side, HOLD, tremor=0.2)
            yield from self.wait(0.1)
        yield from self.set_grip(side, 0.0, max_wait=0.6, min_wait=0.3)
        p, _ = self.hand_pose(side)
        back = p - rotation[:, 2] * 0.06 + np.array([0.0, 0.0, 0.08])  # out along the approach, and up
        end = self.move_hand(side, back, rotation, GRASP * 0.5, spread=0.2, tremor=0.5)
        yield from self.until(end)

    def lower_until(
        self, side: int, rotation: np.ndarray, depth: float, shortest: float, done: Callable[[], bool]
    ) -> Script:
        """Lower the hand (at most ``depth`` m, at ``LOWER_SPEED``, over ``shortest`` s at
        least) until ``done()``: how a person lowers a held thing until they feel it right."""
        p, _ = self.hand_pose(side)
        duration = max(shortest, depth / LOWER_SPEED)
        end = self.move_hand(side, p - np.array([0.0, 0.0, depth]), rotation, HOLD, duration=duration, spread=0.0)
        while self.time < end and not done():
            yield

    def walk(
        self,
        route: Sequence[Sequence[float]],
        carrying: Sequence[int] = (),
        speed: float = 1.0,
        wait: bool = True,
        from_plan: bool = False,
    ) -> Generator[None, None, float]:
        """Walk the base through ``route`` (x, y, z, yaw waypoints), the ``carrying`` hands
        held still relative to the pelvis; returns the time the walk ends. Without ``wait``
        it returns at once, so that the hands can start on something else on the way (the
        carrying hands stay with the pelvis until they are given something else to do).

        The walk starts from where the IK has put the body, or, ``from_plan``, from where
        the body was planned to be: when a hand holds something out of the arm's easy
        reach the IK moves the body off its plan to help, and a hand held in the body's
        frame would jump by the difference if the plan restarted from there.

        Each leg is a minimum-jerk movement; the next one starts before the last ends (by
        ``LEG_OVERLAP`` of its duration), so the legs add up to one movement that rounds
        its corners, as a person's submovements blend, instead of stopping at each.
        """
        b0 = self.base_pose() if from_plan else self.commanded_base()
        for side in carrying:
            p, r = self.hand_pose(side)
            local_p, local_r = to_base(b0, p, r)
            cost = self.hands[side].orientation_cost if self.hands[side] is not None else CARRY
            self.hands[side] = HandReference(
                (lambda t, lp=local_p: from_base(self.base_ref(t), lp, None)[0]),
                (lambda t, lr=local_r: from_base(self.base_ref(t), None, lr)[1]),
                cost,
                tremor=0.5,
            )
        legs: list[tuple[float, float, np.ndarray]] = []  # start, duration, displacement
        start, t = b0, self.time
        for goal in route:
            b = np.array(goal, float)
            b[3] = start[3] + np.arctan2(np.sin(b[3] - start[3]), np.cos(b[3] - start[3]))
            distance = float(np.linalg.norm(b[:2] - start[:2]))
            turn = abs(float(b[3] - start[3]))
            jitter = float(np.exp(self.human.jitter(self.style.movement_jitter)))
            duration = (0.4 + 1.1 * (distance + 0.3 * turn)) * jitter * self.style.slowness / (self.human.speed * speed)
            # a minimum-jerk leg peaks at 1.875 x its mean speed: stay within what the base can do
            rise = abs(float(b[2] - start[2]))
            duration = max(
                duration, PEAK * distance / WALK_SPEED, PEAK * turn / TURN_SPEED, PEAK * rise / CROUCH_SPEED, 0.05
            )
            if legs:
                t -= LEG_OVERLAP * min(duration, legs[-1][1])
            legs.append((t, duration, b - start))
            t += duration
            start = b
        profile = self.human.profile

        def base_at(time: float) -> np.ndarray:
            out = b0.copy()
            for leg_start, duration, displacement in legs:
                out = out + displacement * profile((time - leg_start) / duration)
            return out

        self.base_ref = base_at
        if not wait:
            return t
        yield from self.until(t)
        self.base_ref = lambda time, end=start: end
        for side in carrying:
            self.hold_hand(side, self.hands[side].orientation_cost, tremor=0.5)
        return t


def to_base(base: np.ndarray, p: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    rotation = yaw_matrix(base[3])
    origin = np.array([base[0], base[1], base[2]])
    return rotation.T @ (p - origin), rotation.T @ r


def from_base(base: np.ndarray, p: np.ndarray | None, r: np.ndarray | None) -> tuple:
    rotation = yaw_matrix(base[3])
    origin = np.array([base[0], base[1], base[2]])
    return (None if p is None else rotation @ p + origin), (None if r is None else rotation @ r)


__all__ = ["GraspingExpert"]
