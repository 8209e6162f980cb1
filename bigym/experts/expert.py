"""The scripted, human-like demonstrator: task scripts, skills, IK and actions.

An :class:`Expert` is a callable ``expert(obs) -> action`` for one env. Its task script
(:meth:`Expert.plan`, a generator) reads the privileged simulator state and sets
*references*: where each hand should be as a function of time (minimum-jerk paths
through randomised via-points, with tremor), where the base should stand, how each idle
arm should hang, and what each gripper does. Every control step the script advances
one step, a whole-body mink IK turns the references into a commanded configuration
(solved at ``ik_rate`` and interpolated in between), and the action is built in the
env's action mode: absolute arm joint targets, base *deltas* of the base servo
targets, and gripper commands.

Skills are generators too (``yield from self.wait(0.3)``), so a script reads like what
a person does: look, reach, grasp, pull, let go, step back.
"""

from __future__ import annotations

from collections.abc import Callable, Generator, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from bigym.experts.geometry import JointMotion, axis_angle_matrix, frame_from_axes, interpolate_rotation
from bigym.experts.ik import IkAction, WholeBodyIK
from bigym.experts.motion import Human, HumanStyle, MinimumJerkSpline
from bigym.robot.h1 import ARM_JOINTS, STANDING_HEIGHT

LEFT, RIGHT = 0, 1
SIDE_INDEX = {"left": LEFT, "right": RIGHT}
SIDE_NAMES = ("left", "right")  # by side index
Script = Generator[None, None, None]

#: orientation costs (per pinch-frame axis: x = across the fingers' faces, y = closing
#: direction, z = approach) of a free hand, a hand lining up with a bar, a firm grasp
FREE = np.zeros(3)
ALIGN_BAR = np.array([0.6, 0.8, 2.0])  # the pinch x axis along the bar, the approach roughly as planned
FIRM = np.array([1.0, 1.0, 1.0])
#: base posture costs while standing still and while the hands pull the base along
BASE_COST = {"x": 2.5, "y": 2.5, "z": 1.5, "rz": 2.0}
ARM_ACTIVE_COST = 0.06
#: the plan waits while a hand is this far (m) from where the IK commands it ...
LAG_LIMIT = 0.04
#: ... but never longer than this (s) at a time
MAX_WAIT = 0.3
ARM_IDLE_COST = 2.0
#: idle arm posture (hands held loosely in front of the belly, clear of open drawers), left
#: arm; the right arm mirrors roll and yaw
IDLE_ARM = {"shoulder_pitch": 0.5, "shoulder_roll": 0.12, "shoulder_yaw": -0.15, "elbow": -0.5, "wrist": 0.0}


@dataclass
class HandReference:
    """Where one hand should be: functions of time, plus IK weights."""

    position: Callable[[float], np.ndarray]
    rotation: Callable[[float], np.ndarray]
    orientation_cost: np.ndarray
    tremor: float = 1.0
    position_scale: float = 1.0
    frame: str = "pinch"
    #: from this time on the hand goes idle (its arm follows the idle posture)
    idle_at: float | None = None


class Piecewise:
    """Concatenation of time functions: ``pieces[i]`` holds from ``starts[i]`` on."""

    def __init__(self) -> None:
        self.starts: list[float] = []
        self.pieces: list[Callable[[float], Any]] = []

    def add(self, start: float, piece: Callable[[float], Any]) -> None:
        self.starts.append(start)
        self.pieces.append(piece)

    def __call__(self, t: float):
        index = 0
        for i, start in enumerate(self.starts):
            if t >= start:
                index = i
        return self.pieces[index](t)


def together(*scripts: Script) -> Script:
    """Run scripts side by side, one step of each per control step, until all have ended:
    what a person does with two hands at once (each script drives its own hand)."""
    live = list(scripts)
    while True:
        for script in list(live):
            try:
                next(script)
            except StopIteration:
                live.remove(script)
        if not live:
            return
        yield


def _constant(value: np.ndarray) -> Callable[[float], np.ndarray]:
    value = np.array(value, float)
    return lambda t: value


def _shifted(spline: MinimumJerkSpline, t0: float) -> Callable[[float], np.ndarray]:
    return lambda t: spline(t - t0)


class Expert:
    """Base class of the task demonstrators. Subclasses write :meth:`plan`."""

    #: tasks (class names) this expert solves
    tasks: ClassVar[tuple[str, ...]] = ()
    #: speed-up per task (1 = the style's own pace)
    pace: ClassVar[dict[str, float]] = {}
    #: the expert plans from the simulator state (env.data), not from observations
    reads_simulator: ClassVar[bool] = True
    #: objects the demonstrator lets fall the last few centimetres into place, by name:
    #: the fastest fall (m/s down) that is not a dropped object (default
    #: :data:`bigym.experts.incidents.DROP_SPEED`)
    drop_speeds: ClassVar[dict[str, float]] = {}
    #: objects the demonstrator tips over on purpose without holding them (turned by a
    #: tool, stood up and tipped over to lie flat), by name: not "knocked over" (see
    #: :class:`bigym.experts.incidents.IncidentWatch`)
    may_tip: ClassVar[tuple[str, ...]] = ()
    #: the task's success can flicker before the job is done (a hold whose contacts come
    #: and go while the object touches its target): a recording of this expert ends only
    #: once the task has been successful for a whole ``AFTER_SUCCESS`` (see
    #: :func:`bigym.experts.generate.record_attempt`), not that long after the first success
    success_must_last: ClassVar[bool] = False
    #: the task can be met on the way, in a state a replay at another rate may just miss
    #: (a turned sandwich that comes to rest almost flat, which the demonstrator then settles
    #: anyway): a recording of this expert ends only once its plan has returned
    #: (:attr:`finished`) and the task has then been successful for a whole ``AFTER_SUCCESS``
    success_after_plan: ClassVar[bool] = False
    #: the IK also keeps the grippers' roots off the torso (:func:`bigym.experts.ik.self_collision_pairs`):
    #: for tasks whose hands come close in front of the chest, where a brush of gripper
    #: on torso parts replays at other rates from the recording
    grippers_off_torso: ClassVar[bool] = False

    def __init__(self, env, seed: int | None = None, style: HumanStyle | None = None, ik_rate: float = 100.0) -> None:
        self.env = env.unwrapped
        if not getattr(self.env.action_mode, "absolute", False) or self.env.action_mode.torque:
            raise ValueError("the experts emit JointPositionActionMode(floating_base=True, absolute=True) actions")
        self.seed = seed
        self.style = style if style is not None else HumanStyle()
        self.dt = 1.0 / self.env.control_frequency
        self.ik_every = max(1, round(self.env.control_frequency / ik_rate))
        self.ik = WholeBodyIK(self.env, grippers_off_torso=self.grippers_off_torso)
        self._action = IkAction(self.env, self.ik)
        self.model, self.data = self.env.model, self.env.data
        self._started = False
        self.choices: dict[str, Any] = {}

    # ------------------------------------------------------------------ lifecycle
    def reset(self, seed: int | None) -> None:
        """Draw the next episode's choices from ``seed`` (the policy interface of
        :mod:`bigym.evaluation`); the plan starts on the first step."""
        self.seed = seed
        self._started = False

    def start(self) -> None:
        """(Re)start for the env's current episode (called on the first step after reset)."""
        self.rng = np.random.default_rng(self.seed)
        self.human = Human(self.style, self.rng)
        # some tasks leave little time: the demonstrator hurries a little there
        self.human.speed *= self.pace.get(self.env.task_name, 1.0)
        self.ik.reset(self.data.qpos)
        self.ik.base_region.planes.clear()
        self.ik.arm_planes.planes.clear()
        self.step_index = 0
        self.time = 0.0  # the plan's clock: it stops while the body catches up
        self._lag = 0.0
        self._waited = 0.0
        self.grip = np.zeros(2)
        self.hands: list[HandReference | None] = [None, None]
        #: per arm, (joint targets, costs) the IK prefers while its hand is active (None: relaxed)
        self.arm_posture: list[tuple[np.ndarray, np.ndarray] | None] = [None, None]
        self.tremors = [self.human.tremor(), self.human.tremor()]
        self.idle_arm = [self._idle_posture(side) for side in (LEFT, RIGHT)]
        q = self.ik.q
        self.arm_refs: list[Callable[[float], np.ndarray]] = [
            _constant(q[self.ik.arm_index[side]]) for side in (LEFT, RIGHT)
        ]
        self.base_ref: Callable[[float], np.ndarray] = _constant(self._base_vector(q))
        self.base_cost = dict(BASE_COST)
        self._q_from = q.copy()
        self.choices = {}
        self.events: list[tuple[float, str]] = []
        self.finished = False
        self._script = self.plan()
        self._started = True

    def _idle_posture(self, side: int) -> np.ndarray:
        sign = 1.0 if side == LEFT else -1.0
        posture = np.array(
            [IDLE_ARM[p] * (sign if p in ("shoulder_roll", "shoulder_yaw") else 1.0) for p in ARM_JOINTS]
        )
        return posture + self.human.jitter(self.style.posture_spread, len(ARM_JOINTS)) * np.array(
            [1.0, 0.5, 0.5, 1.0, 0.5]
        )

    def _base_vector(self, q: np.ndarray) -> np.ndarray:
        b = self.ik.base_dofs
        z = q[b["z"]] if "z" in b else STANDING_HEIGHT
        return np.array([q[b["x"]], q[b["y"]], z, q[b["rz"]]])

    def keep_base_behind(self, point: np.ndarray, facing: np.ndarray, clearance: float) -> None:
        """Keep the pelvis at least ``clearance`` in front of a furniture front through
        ``point`` facing the robot (``facing`` points into the furniture)."""
        a = np.array([facing[0], facing[1]], float)
        a /= np.linalg.norm(a)
        self.ik.base_region.planes.append((a, float(a @ np.asarray(point, float)[:2]) - clearance))

    def clamp_to_region(self, base: np.ndarray) -> np.ndarray:
        """A planned base pose pushed back inside the allowed region (with 2 cm to spare)."""
        base = np.array(base, float)
        for a, b in self.ik.base_region.planes:
            excess = float(a @ base[:2]) - (b - 0.02)
            if excess > 0.0:
                base[:2] -= a * excess
        return base

    def plan(self) -> Script:  # pragma: no cover - subclasses
        raise NotImplementedError
        yield

    # ------------------------------------------------------------------ the policy
    def __call__(self, obs: dict | None = None) -> np.ndarray:
        if not self._started or (self.data.time == 0.0 and self.step_index > 0):
            self.start()
        frozen = self._lagging()
        if not self.finished and not frozen:
            try:
                next(self._script)
            except StopIteration:
                self.finished = True
        for side in (LEFT, RIGHT):
            ref = self.hands[side]
            if ref is not None and ref.idle_at is not None and self.time >= ref.idle_at:
                self.relax_arm(side, duration=0.35, joint_space=True)
        k = self.step_index % self.ik_every
        if k == 0:
            self._q_from = self.ik.q.copy()
            self._solve(self.time + self.ik_every * self.dt, self.ik_every * self.dt)
        q = self._q_from + (k + 1) / self.ik_every * (self.ik.q - self._q_from)
        self.step_index += 1
        if not frozen:
            self.time += self.dt
        # on the action grid: a regenerated dataset has the same bytes on any CPU
        return self._action(q, self.grip)

    def _lagging(self) -> bool:
        """Whether the plan should wait for the body to catch up (a person slows down
        when a hand lags behind or is held up), for at most ``MAX_WAIT`` seconds at a time."""
        if self.step_index % self.ik_every == 0:
            lag = 0.0
            for side in (LEFT, RIGHT):
                if self.hands[side] is not None:
                    commanded, _ = self.ik.pose(side)
                    actual = self.data.site_xpos[self.env.robot.pinch_site_ids[side]]
                    lag = max(lag, float(np.linalg.norm(commanded - actual)))
            self._lag = lag
        if self._lag > LAG_LIMIT and self._waited < MAX_WAIT:
            self._waited += self.dt
            return True
        if self._lag < 0.5 * LAG_LIMIT:
            self._waited = 0.0
        return False

    def _solve(self, t: float, dt: float) -> None:
        goals = []
        for side in (LEFT, RIGHT):
            ref = self.hands[side]
            if ref is None:
                goals.append(None)
                continue
            position = ref.position(t)
            if ref.tremor:
                position = position + ref.tremor * self.tremors[side](t)
            goals.append((ref.frame, position, ref.rotation(t), ref.orientation_cost, ref.position_scale))
        base = self.base_ref(t)
        base_target = {"x": base[0], "y": base[1], "z": base[2], "rz": base[3]}
        posture = np.zeros(len(self.ik.joint_names))
        cost = np.zeros(len(self.ik.joint_names))
        for side in (LEFT, RIGHT):
            index = self.ik.arm_index[side]
            if self.hands[side] is None:
                posture[index] = self.arm_refs[side](t)
                cost[index] = ARM_IDLE_COST
            elif self.arm_posture[side] is not None:  # a posture the task asks for (arms straight under a load)
                posture[index], cost[index] = self.arm_posture[side]
            else:
                posture[index] = self.idle_arm[side] * 0.3  # relaxed, elbows slightly down
                cost[index] = ARM_ACTIVE_COST
        self.ik.solve(dt, goals, base_target, self.base_cost, posture, cost)

    # ------------------------------------------------------------------ state helpers
    def hand_pose(self, side: int, t: float | None = None, frame: str = "pinch") -> tuple[np.ndarray, np.ndarray]:
        """The hand's reference pose at ``t`` (now by default), or its commanded pose when
        idle or referenced through another frame."""
        t = self.time if t is None else t
        ref = self.hands[side]
        if ref is None or ref.frame != frame:
            return self.ik.pose(side, frame)
        return np.array(ref.position(t), float), np.array(ref.rotation(t), float)

    def commanded_base(self) -> np.ndarray:
        """The base (x, y, z, yaw) the IK commands now (the plan, unless the hands needed more)."""
        return self._base_vector(self.ik.q)

    def base_pose(self, t: float | None = None) -> np.ndarray:
        """Planned base (x, y, z, yaw) at ``t``."""
        return np.array(self.base_ref(self.time if t is None else t), float)

    def site(self, prop: str, key: str) -> np.ndarray:
        """World position of a prop's site in the current (measured) state."""
        return self.data.site_xpos[self.env.props[prop].site_id(key)].copy()

    def module_facing(self, prop: str) -> np.ndarray:
        """Direction a person faces when working at a module: into its front (local +x)."""
        frame = self.data.xmat[self.env.props[prop].root_body_id].reshape(3, 3)
        return frame[:, 0].copy()

    def joint_state(self, prop: str, key: str) -> float:
        p = self.env.props[prop]
        return float(p.get_state(self.data)[p.joint_index(key)])

    def joint_motion(self, prop: str, key: str) -> JointMotion:
        p = self.env.props[prop]
        return JointMotion(self.model, self.data, int(p.joint_ids[p.joint_index(key)]))

    def hand_on_side(self, lateral: float, softness: float) -> int:
        """The hand a person uses for something ``lateral`` metres to the left (negative:
        right) of their middle: left with a probability rising smoothly with it (one draw),
        so that things near the middle are taken with either."""
        p_left = 1.0 / (1.0 + np.exp(-lateral / softness))
        return LEFT if self.rng.random() < p_left else RIGHT

    def note(self, event: str) -> None:
        """Log a phase of the demo (time, text): for debugging and statistics."""
        self.events.append((round(self.time, 3), event))

    # ------------------------------------------------------------------ time
    def wait(self, seconds: float) -> Script:
        end = self.time + max(0.0, seconds)
        while self.time < end - 1e-9:
            yield

    def until(self, t_end: float) -> Script:
        while self.time < t_end - 1e-9:
            yield

    def hesitate(self) -> Script:
        yield from self.wait(self.human.hesitation())

    def after(self, delay: float, script: Script) -> Script:
        """``script``, started ``delay`` seconds from now (to stagger it in :func:`together`)."""
        yield from self.wait(delay)
        yield from script

    # ------------------------------------------------------------------ reference setters
    def move_hand(
        self,
        side: int,
        goal: np.ndarray,
        rotation: np.ndarray | None = None,
        orientation_cost: np.ndarray = FREE,
        duration: float | None = None,
        lift: float = 0.0,
        spread: float = 1.0,
        precision: float = 0.02,
        correct: bool = False,
        start: float | None = None,
        via: Sequence[np.ndarray] | None = None,
        tremor: float = 1.0,
        speed: float = 1.0,
        frame: str = "pinch",
        stops: bool = False,
    ) -> float:
        """Send a hand to ``goal`` along a minimum-jerk path through random via-points.

        With ``correct`` the first sub-movement may end a little off (drawn by the
        human's style) and a short corrective sub-movement follows. ``via`` adds fixed
        via-points (e.g. a pre-grasp point) before the goal; with ``stops`` the hand
        comes (almost) to rest at each of them, so that a path round an obstacle does
        not swing out at its corners. Returns the end time.
        """
        t0 = self.time if start is None else start
        p0, r0 = self.hand_pose(side, t0, frame)
        if start is None:
            commanded, commanded_rotation = self.ik.pose(side, frame)
            if np.linalg.norm(commanded - p0) > 0.02:  # the reference ran ahead of the body
                p0, r0 = commanded, commanded_rotation
        goal = np.asarray(goal, float)
        r1 = r0 if rotation is None else np.asarray(rotation, float)
        waypoints = [p0, *([] if via is None else [np.asarray(v, float) for v in via]), goal]
        error = self.human.endpoint_error(goal - waypoints[-2]) if correct else None
        primary_goal = goal if error is None else goal + error
        segments = [
            self.human.via_points(a, b, lift=lift if a is waypoints[0] else 0.0, spread_scale=spread)
            for a, b in zip(waypoints[:-1], [*waypoints[1:-1], primary_goal])
        ]
        position = Piecewise()
        if stops and len(segments) > 1:
            end = t0
            for index, segment in enumerate(segments):
                length = float(np.linalg.norm(np.diff(segment, axis=0), axis=1).sum())
                piece = self.human.duration(length, precision if index == len(segments) - 1 else 0.05) * 0.75 / speed
                position.add(-np.inf if index == 0 else end, _shifted(self.human.path(segment, piece), end))
                end += piece
            duration = end - t0
        else:
            points = [segments[0][0]] + [p for segment in segments for p in segment[1:]]
            distance = float(sum(np.linalg.norm(np.diff(np.array(points), axis=0), axis=1)))
            if duration is None:
                duration = self.human.duration(distance, precision) / speed
            position.add(-np.inf, _shifted(self.human.path(points, duration), t0))
            end = t0 + duration
        rotation_end = end
        if error is not None:
            dwell = 0.05 + abs(self.human.jitter(0.06))
            fix = max(0.22, self.human.duration(float(np.linalg.norm(error)), 0.005, minimum=0.22) * 0.7)
            position.add(end + dwell, _shifted(self.human.path([primary_goal, goal], fix), end + dwell))
            end = end + dwell + fix

        def rot(t: float, r0=r0, r1=r1, t0=t0, span=rotation_end - t0) -> np.ndarray:
            return interpolate_rotation(r0, r1, self.human.profile((t - t0) / span))

        self.hands[side] = HandReference(position, rot, np.asarray(orientation_cost, float), tremor, frame=frame)
        return end

    def hold_hand(self, side: int, orientation_cost: np.ndarray = FREE, tremor: float = 1.0) -> None:
        """Keep a hand where its reference is now."""
        frame = self.hands[side].frame if self.hands[side] is not None else "pinch"
        p, r = self.hand_pose(side, frame=frame)
        self.hands[side] = HandReference(
            _constant(p), _constant(r), np.asarray(orientation_cost, float), tremor, frame=frame
        )

    def relax_arm(
        self, side: int, duration: float | None = None, start: float | None = None, joint_space: bool = False
    ) -> float:
        """Let a hand go idle: the arm ends in its idle posture.

        By default the hand first moves (a free minimum-jerk movement, so in a sensible
        Cartesian path, clear of what it was working on) to where the idle posture
        puts it, then the arm settles into that posture. ``joint_space`` interpolates
        the joints directly (fine away from furniture, e.g. at the start).
        """
        t0 = self.time if start is None else start
        if not joint_space:
            q = self.ik.q.copy()
            base = self.base_pose(t0 + 1.0)
            b = self.ik.base_dofs
            for i, key in enumerate(("x", "y", "z", "rz")):
                if key in b:
                    q[b[key]] = base[i]
            q[self.ik.arm_index[side]] = self.idle_arm[side]
            rest, rest_rotation = self.ik.pose_at(q, side)
            end = self.move_hand(
                side, rest, rest_rotation, FREE, start=t0, precision=0.1, spread=0.6, duration=duration
            )
            self.hands[side].idle_at = end
            return end + 0.35
        q0 = self.ik.q[self.ik.arm_index[side]].copy()
        q1 = self.idle_arm[side]
        if duration is None:
            duration = self.human.duration(0.4, 0.1, minimum=0.6)
        spline = MinimumJerkSpline(np.stack([q0, q1]), np.array([0.0, duration]))
        self.arm_refs[side] = _shifted(spline, t0)
        self.hands[side] = None
        return t0 + duration

    def move_base(self, goal: Sequence[float], duration: float | None = None, start: float | None = None) -> float:
        """Walk the base (x, y, z, yaw) to ``goal`` with a minimum-jerk profile; returns the end time."""
        t0 = self.time if start is None else start
        b0 = self.commanded_base() if start is None else self.base_pose(t0)
        b1 = self.clamp_to_region(goal)
        b1[3] = b0[3] + np.arctan2(np.sin(b1[3] - b0[3]), np.cos(b1[3] - b0[3]))
        step = float(np.linalg.norm(b1[:2] - b0[:2]) + 1.2 * abs(b1[2] - b0[2]) + 0.3 * abs(b1[3] - b0[3]))
        if duration is None:
            # a step or two: about 0.5 s plus 1.2 s per metre, at the demonstrator's pace
            jitter = float(np.exp(self.human.jitter(self.style.movement_jitter)))
            duration = (0.5 + 1.2 * step) * jitter * self.style.slowness / self.human.speed if step > 1e-4 else 0.0
        if duration <= 0.0:
            self.base_ref = _constant(b1)
            return t0
        self.base_ref = _shifted(self.human.path([b0, b1], duration), t0)
        return t0 + duration

    # ------------------------------------------------------------------ skills
    def set_grip(self, side: int, value: float, max_wait: float = 0.9, min_wait: float = 0.3) -> Script:
        """Open (0) or close (1) a gripper and wait until the fingers stop moving."""
        self.note(f"grip {'LR'[side]} {value:g}")
        self.grip[side] = value
        start = self.time
        previous = None
        while self.time - start < max_wait:
            yield
            state = float(self.env.robot.gripper_state(self.data)[side])
            if self.time - start >= min_wait:
                if abs(state - value) < 0.05:
                    break
                if previous is not None and abs(state - previous) < 2e-4:
                    break  # stalled on the handle
            previous = state

    def drag(
        self,
        sides: Sequence[int],
        prop: str,
        key: str,
        goal: float,
        duration: float | None = None,
        base_follow: float = 1.0,
        base_yaw_follow: float = 0.0,
        orientation_cost: np.ndarray = FIRM,
        speed: float = 1.0,
    ) -> Script:
        """Move grasping (or pushing) hands along the path of one prop joint to ``goal``.

        The hands stay rigidly attached to the moving part: their references are the
        poses they have now, carried along by the joint's slide or rotation as the joint
        goes from its measured value to ``goal`` (normalised) with a minimum-jerk
        profile. The base follows the hands' mean displacement by ``base_follow``.
        """
        self.note(f"drag {prop}/{key} -> {goal:.2f}")
        motion = self.joint_motion(prop, key)
        q0, q1 = motion.q0, motion.value(goal)
        t0 = self.time
        poses = {side: self.hand_pose(side, t0) for side in sides}
        first = poses[sides[0]][0]
        travel = float(np.linalg.norm(motion.move_point(first, q1) - first))
        if duration is None:
            duration = max(0.8, self.human.duration(travel, 0.04) * 1.35) / speed
        base0 = self.commanded_base()

        def q_at(t: float) -> float:
            return q0 + (q1 - q0) * self.human.profile((t - t0) / duration)

        for side, (p, r) in poses.items():
            self.hands[side] = HandReference(
                (lambda t, p=p, r=r: motion.move_frame(p, r, q_at(t))[0]),
                (lambda t, p=p, r=r: motion.move_frame(p, r, q_at(t))[1]),
                np.asarray(orientation_cost, float),
                tremor=0.3,
            )
        mean0 = np.mean([p for p, _ in poses.values()], axis=0)

        def base_at(t: float) -> np.ndarray:
            q = q_at(t)
            mean = np.mean([motion.move_point(p, q) for p, _ in poses.values()], axis=0)
            out = base0.copy()
            out[:2] += base_follow * (mean - mean0)[:2]
            if motion.hinge and base_yaw_follow:
                out[3] += base_yaw_follow * (q - q0) * float(np.sign(motion.axis[2]))
            return out

        self.base_ref = base_at
        yield from self.until(t0 + duration)
        # freeze the references where they ended
        for side in sides:
            self.hold_hand(side, orientation_cost, tremor=0.3)
        self.base_ref = _constant(base_at(t0 + duration))

    # ------------------------------------------------------------------ handles
    def handle_frame(self, prop: str, key: str, bar: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(centre, bar axis, approach)`` of a handle bar in the measured state.

        Prop fronts face their local ``-x``: a hand approaches along local ``+x``; ``bar``
        names the local axis ("y" or "z") the bar lies along.
        """
        site = self.env.props[prop].site_id(key)
        body = self.model.site_bodyid[site]
        frame = self.data.xmat[body].reshape(3, 3)
        return self.data.site_xpos[site].copy(), frame[:, {"y": 1, "z": 2}[bar]].copy(), frame[:, 0].copy()

    def grasp_bar(
        self,
        side: int,
        centre: np.ndarray,
        bar_axis: np.ndarray,
        approach: np.ndarray,
        tilt: float = 0.0,
        offset: float = 0.0,
        depth: float = 0.01,
        base_goal: Sequence[float] | None = None,
        close: bool = True,
        via: Sequence[np.ndarray] | None = None,
        align: np.ndarray = ALIGN_BAR,
        opening: float = 0.0,
        keep_sign: bool = False,
        insert_time: float = 0.35,
    ) -> Script:
        """Reach a bar handle, straddle it with the open fingers, and close them.

        ``tilt`` rotates the approach about the bar (e.g. from above for a low handle),
        ``offset`` slides the grasp along the bar. The hand first goes to a pre-grasp
        point in front of the bar (a free minimum-jerk movement, maybe with a
        correction), then slides in slowly. ``opening`` pre-closes the fingers that far (0 =
        wide open), as a hand shapes itself to a thin handle near a surface. With
        ``keep_sign`` the pinch x axis points along ``bar_axis`` as given (a grasp chosen for
        what the hand does next), not the way nearer to the hand. ``insert_time``: the
        slide in takes at least this long (s).
        """
        self.note(f"reach bar {'LR'[side]}")
        approach = axis_angle_matrix(bar_axis, tilt) @ approach
        rotation = frame_from_axes(bar_axis, approach) if keep_sign else self.bar_grasp_rotation(side, bar_axis, approach)
        grasp = centre + bar_axis * offset + approach * depth
        standoff = 0.09 + abs(self.human.jitter(0.02))
        pre = grasp - approach * standoff + self.human.jitter(0.006, 3)
        self.grip[side] = opening
        if via is None:
            # come in along the approach, from in front of the furniture
            hand, _ = self.hand_pose(side)
            if np.linalg.norm(hand - pre) > 0.25:
                via = [pre - approach * (0.1 + abs(self.human.jitter(0.03))) + np.array([0.0, 0.0, 0.04])]
        ends = [
            self.move_hand(
                side, pre, rotation, align, lift=abs(self.human.jitter(0.04)), precision=0.03, correct=True, via=via
            )
        ]
        if base_goal is not None:
            ends.append(self.move_base(base_goal))
        yield from self.until(max(ends))
        yield from self.hesitate()
        self.note(f"insert {'LR'[side]}")
        insert = max(insert_time, self.human.duration(standoff, 0.004) * 0.6)
        yield from self.until(self.move_hand(side, grasp, rotation, align, duration=insert, spread=0.05, tremor=0.5))
        # a settled hand before the fingers close: a replay at a lower control rate may close
        # them up to one control step (50 ms at 20 Hz) earlier than recorded
        yield from self.wait(0.15 + abs(self.human.jitter(0.05)))
        if close:
            yield from self.set_grip(side, 1.0)

    def press(
        self,
        side: int,
        point: np.ndarray,
        direction: np.ndarray,
        across: np.ndarray | None = None,
        base_goal: Sequence[float] | None = None,
        contact: float = 0.012,
        depth: float = 0.006,
        via: Sequence[np.ndarray] | None = None,
        fingers: np.ndarray | None = None,
        standoff: float = 0.08,
    ) -> Script:
        """Bring a closed fist against a surface at ``point``, pushing along ``direction``.

        The closed fingertips end ``depth`` past first contact (the pads stick out about
        ``contact`` beyond the pinch point), so the hand presses gently. ``across`` is the
        fingers' closing direction (any horizontal one by default); ``fingers`` is where
        the fingers point (``direction`` by default: knuckles first, a tilted fist otherwise);
        ``standoff``: how far (m, plus a little) in front of the surface the fist comes
        before it moves in.
        """
        self.note(f"press {'LR'[side]}")
        direction = np.asarray(direction, float) / np.linalg.norm(direction)
        pointing = direction if fingers is None else np.asarray(fingers, float) / np.linalg.norm(fingers)
        if across is None:
            across = np.cross(pointing, [0.0, 0.0, 1.0])
            if np.linalg.norm(across) < 1e-6:
                across = np.array([0.0, 1.0, 0.0])
        x_axis = np.cross(across, pointing)
        _, r = self.hand_pose(side)
        if r[:, 0] @ x_axis < 0.0:
            x_axis = -x_axis
        rotation = frame_from_axes(x_axis, pointing)
        touch = point - direction * (contact - depth)
        standoff = standoff + abs(self.human.jitter(0.02))
        pre = point - direction * (contact + standoff) + self.human.jitter(0.006, 3)
        self.grip[side] = 1.0
        ends = [
            self.move_hand(
                side,
                pre,
                rotation,
                ALIGN_BAR,
                lift=abs(self.human.jitter(0.03)),
                precision=0.03,
                correct=True,
                via=via,
                stops=via is not None,
                spread=1.0 if via is None else 0.3,
            )
        ]
        if base_goal is not None:
            ends.append(self.move_base(base_goal))
        yield from self.until(max(ends))
        yield from self.hesitate()
        approach = max(0.3, self.human.duration(standoff, 0.01) * 0.6)
        yield from self.until(
            self.move_hand(side, touch, rotation, ALIGN_BAR, duration=approach, spread=0.05, tremor=0.5)
        )
        yield from self.wait(0.05 + abs(self.human.jitter(0.04)))

    def release(
        self, side: int, back: float = 0.1, up: float = 0.03, relax: bool = False, away: np.ndarray | None = None
    ) -> Script:
        """Open the fingers and draw the hand back out of the handle; or, after a push,
        draw the fist ``away`` from the surface (opening it on the way)."""
        p, r = self.hand_pose(side)
        approach = r[:, 2] if away is None else -np.asarray(away, float) / np.linalg.norm(away)
        if away is None:
            # ease off the handle while the fingers open: opening linkages must not lever
            # against the part they held
            self.move_hand(side, p - approach * 0.015, r, ALIGN_BAR, duration=0.3, spread=0.0, tremor=0.3)
            yield from self.set_grip(side, 0.0, max_wait=0.6, min_wait=0.25)
            p, r = self.hand_pose(side)
        else:
            self.grip[side] = 0.0
        goal = p - approach * (back + abs(self.human.jitter(0.02))) + np.array([0.0, 0.0, up])
        end = self.move_hand(side, goal, r, ALIGN_BAR * 0.3, spread=0.3, precision=0.05)
        yield from self.until(end)
        if relax:
            self.relax_arm(side)

    def stance(
        self,
        side: int | None,
        point: np.ndarray,
        facing: np.ndarray,
        distance: float = 0.42,
        lateral: float = 0.2,
        height: float = 0.27,
    ) -> np.ndarray:
        """A base pose (x, y, z, yaw) from which ``side``'s hand comfortably reaches ``point``.

        The robot faces ``facing`` (horizontal part used), stands ``distance`` behind the
        point and shifted sideways so that the hand's shoulder is in line with it
        (``lateral``; none for ``side=None``, both hands), and crouches so that its
        pelvis is about ``height`` above the point. All with the style's random spread.
        """
        style = self.style
        f = np.array([facing[0], facing[1], 0.0])
        f /= np.linalg.norm(f)
        left = np.array([-f[1], f[0], 0.0])
        shift = 0.0 if side is None else (lateral if side == LEFT else -lateral)
        pos = (
            point
            - f * (distance + self.human.jitter(style.stance_spread * 0.5))
            - left * (shift + self.human.jitter(style.stance_spread))
        )
        z = float(np.clip(point[2] + height + self.human.jitter(style.stance_spread * 0.5), 0.58, STANDING_HEIGHT))
        yaw = float(np.arctan2(f[1], f[0]) + self.human.jitter(style.stance_yaw_spread))
        return np.array([pos[0], pos[1], z, yaw])

    # ------------------------------------------------------------------ grasp geometry
    def bar_grasp_rotation(self, side: int, bar_axis: np.ndarray, approach: np.ndarray) -> np.ndarray:
        """Pinch frame for grasping a bar: x along the bar (the sign the hand is nearer
        to), z (approach) along ``approach`` made orthogonal to the bar."""
        _, r = self.hand_pose(side)
        bar = np.asarray(bar_axis, float)
        if r[:, 0] @ bar < 0.0:
            bar = -bar
        return frame_from_axes(bar, approach)


__all__ = ["ALIGN_BAR", "FIRM", "FREE", "LEFT", "RIGHT", "SIDE_INDEX", "SIDE_NAMES", "Expert", "HandReference", "together"]
