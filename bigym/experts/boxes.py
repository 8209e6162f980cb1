"""Box demonstrators (scene cabinet_door): lift the box from the floor onto the counter
(``PickBox``).

The box (0.25 x 0.20 x 0.12 m, 5 kg) is wider than the gripper opens on every side, so a
person does what they do with any big box: stands square to two opposite faces, presses
a hand on each and squeezes, lifts with straight arms, carries it low in front of the
body, raises it over the counter, lowers it until it rests, and lets go by moving the
hands apart. Here the hands are closed fists pointing along the arms; the fingers'
knuckles press on the box. The hands move as one rigid hold while the box is carried,
so the squeeze never slackens.

Why the arms stay straight: the arm servos are torque-limited (elbows 18 N m). With the
elbows bent, the box's weight and the squeeze together saturate them and the squeeze
falls to ~35 N, and the box slips out when the body turns; with straight arms the
weight runs along the arms, the shoulders (40 N m) squeeze, and the hold survives the
walk. A squeeze is commanded as the hands deep inside the box's faces: the arms stop at
the faces and press.

Where the knuckles press: on the box's centre line (in depth), above its centre of mass,
so that it hangs level between them; pressed off that line it hangs tilted by ~20 degrees
and swings out of the hands when the body moves.

Choices drawn per demo: which pair of faces the hands take (the wide faces or the
narrow ones), which side of the box the body takes it from (the one nearer the counter),
where on the counter it goes, the timing, and every path's via-points.

Why this needs bigym 0.3.0: replayed at 25 or 20 Hz with each new base target held over
the control step, the floating base took every step in a jolt (2 g at 50 Hz, 7 g at 20 Hz
on a 0.47 m/s walk; ``benchmarks/base_jolt.py``) that shook the box out of the squeeze;
with targets ramped over the control step the replays at every rate keep it.
"""

from __future__ import annotations

import numpy as np

from bigym.experts.expert import LEFT, RIGHT, HandReference, Script
from bigym.experts.grasping import LOWER_SPEED, GraspingExpert, from_base, to_base
from bigym.robot.h1 import STANDING_HEIGHT

BOX = "box"
#: where the knuckles of a closed finger pair (the driver links, the part that touches a
#: face beside the hand) lie from the pinch point: this far (m) out across the closing
#: axis, and this far back along the fingers (measured from the contacts)
KNUCKLES = 0.062
KNUCKLES_BACK = 0.07
#: how far (m) inside the box's face each hand is aimed: the arms stop at the face and press
SQUEEZE = 0.14
#: how far (m) outside the face a hand comes in from, and moves out to when letting go
OPEN_GAP = 0.06
#: how far (m) below the box's top the hands press: above its middle, so that it hangs
HOLD_BELOW_TOP = 0.06
#: the hands point along the arms, this far (rad) below the horizontal
HAND_TILT = 0.96
#: orientation costs of the hold about the pinch axes: the closing axis stays across the
#: box; the tilt (about that axis) follows the arm
HOLD_COST = np.array([1.0, 0.1, 1.0])
#: the elbows' joint angle (rad) for a straight arm, and how firmly the IK keeps to it
STRAIGHT_ELBOW = 1.45
STRAIGHT_COST = 3.0
#: the lowest pelvis height (m): the floating base's limit
CROUCH = 0.4
#: how far (m) the pelvis stands from the box's centre while taking it off the floor
FLOOR_REACH = 0.3
#: the counter: its front (x) and top (z); the box goes on it this far (m) behind its front
COUNTER_FRONT = 0.58
COUNTER_TOP = 0.86
PLACE_MARGIN = 0.05
#: how long (s) the hands take to come down beside the box, at the end of the walk to it
HANDS_DOWN = 1.2
#: how far (m) above the counter the box's bottom is planned to be raised before it is
#: lowered: it hangs several centimetres lower than planned (the arms sag, it turns in the hands)
ENTRY_HEIGHT = 0.12
#: how the box is carried: the hands this far (m) ahead of the pelvis and this high, the
#: arms hanging near straight; the box's front stays this far (m) short of the counter
CARRY_X = 0.4
CARRY_HANDS_Z = 0.85
COUNTER_MARGIN = 0.05
#: how fast (relative to the demonstrator's pace) the body walks carrying the box (and
#: stands up with it), and how fast the arms raise it: slowly. Chosen when replays at low
#: control rates held each new base target over the control step and the base took it in
#: a jolt that a quicker step made strong enough to shake the box out of the squeeze
#: (``benchmarks/base_jolt.py``); the ramp since bigym 0.3.0 removes the jolt, and a
#: quicker carry has not been tried.
CARRY_SPEED = 0.2
RAISE_SPEED = 0.4
#: how far (m) the hands go on down once the box touches the counter before they let go:
#: in a replay at a lower rate the box hangs up to a few centimetres higher
PRESS = 0.02
#: the shoulders' height (m) standing and their distance ahead of the pelvis, and the
#: reach (m) of a straight arm to the pinch point
SHOULDER_HEIGHT = 1.48
SHOULDER_AHEAD = 0.03
ARM_REACH = 0.72


class BoxExpert(GraspingExpert):
    """Carries the box of ``PickBox`` squeezed between both hands."""

    tasks = ("PickBox",)

    def plan(self) -> Script:
        yield from self.wait(self.human.reaction())
        yield from self.pick_box()
        while True:
            yield

    # ------------------------------------------------------------------ geometry
    def box_faces(self) -> tuple[np.ndarray, list[tuple[np.ndarray, float]], float]:
        """The box's centre, its horizontal face normals with their half widths, and its
        half height, as it lies now."""
        prop = self.env.props[BOX]
        frame = self.data.xmat[prop.root_body_id].reshape(3, 3)
        half = np.asarray(prop.SIZE, float) / 2.0
        vertical = int(np.argmax(np.abs(frame[2, :])))
        faces = []
        for axis in range(3):
            if axis != vertical:
                normal = np.array([frame[0, axis], frame[1, axis], 0.0])
                faces.append((normal / np.linalg.norm(normal), float(half[axis])))
        return self.data.xpos[prop.root_body_id].copy(), faces, float(half[vertical])

    @staticmethod
    def hold_rotation() -> np.ndarray:
        """A hand's pinch orientation (base frame) on the box's side: closing across the
        box, pointing forward and down along a straight arm."""
        approach = np.array([np.cos(HAND_TILT), 0.0, -np.sin(HAND_TILT)])
        closing = np.array([0.0, 1.0, 0.0])
        return np.stack([np.cross(closing, approach), closing, approach], axis=1)

    def straighten_arms(self, straight: bool) -> None:
        """Ask the IK for straight elbows (under the box's weight), or let them relax."""
        for side in (LEFT, RIGHT):
            if not straight:
                self.arm_posture[side] = None
                continue
            target, cost = np.zeros(5), np.zeros(5)
            target[3], cost[3] = STRAIGHT_ELBOW, STRAIGHT_COST
            self.arm_posture[side] = (target, cost)

    # ------------------------------------------------------------------ the hold
    def hold_box(self, centre: np.ndarray, gap: float, duration: float, cost: np.ndarray = HOLD_COST) -> float:
        """Move both hands as one: the hold point (midway between the knuckles, base frame)
        to ``centre`` and each hand's knuckles to ``gap`` metres beside it, over ``duration``
        s; returns the end time."""
        t0 = self.time
        start = self.box_now()
        goal = np.append(np.asarray(centre, float), gap)
        path = self.human.path([start, goal], duration) if duration > 0.0 else (lambda t, v=goal: v)
        self._box_path = (path, t0, duration)
        reach = KNUCKLES_BACK * self.hold_rotation()[:, 2]  # the pinch point lies ahead of the knuckles
        for side in (LEFT, RIGHT):
            sign = 1.0 if side == LEFT else -1.0
            rotation = self.hold_rotation()

            def position(t: float, sign: float = sign) -> np.ndarray:
                v = path(min(max(t - t0, 0.0), duration))
                return from_base(self.base_ref(t), v[:3] + np.array([0.0, sign * v[3], 0.0]) + reach, None)[0]

            def orientation(t: float, rotation: np.ndarray = rotation) -> np.ndarray:
                return from_base(self.base_ref(t), None, rotation)[1]

            self.hands[side] = HandReference(position, orientation, cost, tremor=0.3)
        return t0 + duration

    def box_now(self) -> np.ndarray:
        """The hold now: the hold point (base frame) and the hands' gap, stacked."""
        path, t0, duration = self._box_path
        return np.asarray(path(min(max(self.time - t0, 0.0), duration)), float)

    @property
    def box_local(self) -> np.ndarray:
        return self.box_now()[:3]

    @property
    def box_gap(self) -> float:
        return float(self.box_now()[3])

    def both_touch(self) -> bool:
        box = self.env.mask(BOX)
        return all(self.env.touching(box, self._side_mask(side)) for side in (LEFT, RIGHT))

    def _side_mask(self, side: int) -> np.ndarray:
        mask = np.zeros(self.model.ngeom, bool)
        mask[self.env.robot.gripper_geom_ids_by_side[side]] = True
        return mask

    # ------------------------------------------------------------------ PickBox
    def pick_box(self) -> Script:
        centre, faces, half_height = self.box_faces()
        wide = self.rng.random() < 0.5  # the hands on the wide faces (across the thin side)
        normal, half_width = min(faces, key=lambda f: f[1]) if wide else max(faces, key=lambda f: f[1])
        depth = max(f[1] for f in faces) if wide else min(f[1] for f in faces)  # the box's half depth in the hands
        self.choices["faces"] = "wide" if wide else "narrow"
        # where the box will go, and where the body stands to raise it over the counter:
        # straight arms raise it along an arc, so its front passes the counter's front only
        # once its bottom is above the counter
        goal_x = COUNTER_FRONT + depth + PLACE_MARGIN + abs(self.human.jitter(0.02))
        hands_z = COUNTER_TOP + ENTRY_HEIGHT + 2 * half_height - HOLD_BELOW_TOP
        raised_reach = float(np.sqrt(max(ARM_REACH**2 - (SHOULDER_HEIGHT - hands_z) ** 2, 0.0))) + SHOULDER_AHEAD
        yaw = self.human.jitter(0.05)
        ready_x = COUNTER_FRONT - COUNTER_MARGIN - depth - raised_reach
        ready = np.array([ready_x, self.human.jitter(0.08), STANDING_HEIGHT, yaw])
        # stand square to the chosen faces, crouched, on the side of the box nearer where
        # the box goes (less to carry)
        reach = FLOOR_REACH + self.human.jitter(0.02)
        stances = []
        for sign in (1.0, -1.0):
            facing = sign * np.array([-normal[1], normal[0]])
            point = centre[:2] - reach * facing + self.human.jitter(0.02, 2)
            crouch = CROUCH + abs(self.human.jitter(0.02))
            stances.append(np.array([point[0], point[1], crouch, np.arctan2(facing[1], facing[0])]))
        crouched = min(stances, key=lambda b: float(np.linalg.norm(b[:2] - ready[:2])))
        top = centre[2] + half_height
        self.note("walk to box")
        yield from self.take_box(crouched, np.array([centre[0], centre[1], top - HOLD_BELOW_TOP]), half_width)
        self.note("lift")
        end = self.hold_box(self.box_local + np.array([0.0, 0.0, 0.05]), self.box_gap, 0.6)
        yield from self.until(end)
        # stand up and carry it to the counter, hanging low in front, the arms near straight
        self.note("carry")
        end_walk = yield from self.walk([ready], wait=False, speed=CARRY_SPEED)
        carry = np.array([CARRY_X, 0.0, CARRY_HANDS_Z - STANDING_HEIGHT])
        self.hold_box(carry, self.box_gap, end_walk - self.time)
        yield from self.until(end_walk)
        self.base_ref = lambda t, b=ready: b
        self.note("raise")
        raised = np.array([raised_reach, 0.0, hands_z - STANDING_HEIGHT])
        end = self.hold_box(raised, self.box_gap, self.human.duration(0.4, 0.02) / RAISE_SPEED)
        yield from self.until(end)
        pelvis = ready.copy()
        pelvis[0] = goal_x - raised_reach
        end_walk = yield from self.walk([pelvis], wait=False, speed=CARRY_SPEED)
        self.hold_box(self.box_local, self.box_gap, end_walk - self.time)
        yield from self.until(end_walk)
        self.base_ref = lambda t, b=pelvis: b
        yield from self.put_down(half_width)

    # ------------------------------------------------------------------ skills
    def take_box(
        self, crouched: np.ndarray, hold_point: np.ndarray, half_width: float, lead: float = HANDS_DOWN,
        above: float = 0.12, outside: float | None = None,
    ) -> Script:  # fmt: skip
        """Walk and crouch to ``crouched`` (base pose); ``lead`` s before the walk ends the
        closed hands start down beside the box, one each side of ``hold_point`` (world), via a
        point ``above`` it (and first, when given, one ``outside`` m higher and 5 cm further
        out, so that they do not sweep across a box at chest height); then squeeze."""
        end_walk = yield from self.walk([crouched], wait=False)
        yield from self.until(end_walk - lead)
        self.grip[:] = 1.0  # fists
        local_centre, _ = to_base(crouched, hold_point, np.eye(3))
        ends = []
        for side in (LEFT, RIGHT):
            sign = 1.0 if side == LEFT else -1.0
            local = local_centre + np.array([0.0, sign * (half_width + KNUCKLES + OPEN_GAP), 0.0])
            local = local + KNUCKLES_BACK * self.hold_rotation()[:, 2]
            goal, rotation = from_base(crouched, local, self.hold_rotation())
            via = [goal + np.array([0.0, 0.0, above])]
            if outside is not None:
                via.insert(0, from_base(crouched, local + np.array([0.0, sign * 0.05, outside]), None)[0])
            duration = max(HANDS_DOWN, end_walk - self.time + 0.3)
            ends.append(self.move_hand(side, goal, rotation, HOLD_COST, via=via, duration=duration))
        yield from self.until(max(ends))
        self.base_ref = lambda t, b=crouched: b
        held = np.append(local_centre, half_width + KNUCKLES + OPEN_GAP)
        self._box_path = (lambda t, v=held: v, self.time, 0.0)
        yield from self.hesitate()
        self.straighten_arms(True)
        self.note("squeeze")
        end = self.hold_box(local_centre, half_width + KNUCKLES - SQUEEZE, 0.6)
        yield from self.until(end + 0.3)
        if not self.both_touch():
            self.note("missed the box")

    def put_down(self, half_width: float) -> Script:
        """Lower the held box until it rests, then let go: the hands apart, and away."""
        self.note("lower")
        over = self.box_local
        depth = ENTRY_HEIGHT + 0.04
        end = self.hold_box(over - np.array([0.0, 0.0, depth]), self.box_gap, depth / LOWER_SPEED)
        while self.time < end and not self.touches_support(BOX):
            yield
        self.hold_box(self.box_local - np.array([0.0, 0.0, PRESS]), self.box_gap, PRESS / LOWER_SPEED)
        yield from self.wait(0.3)
        self.note("let go")
        self.straighten_arms(False)
        end = self.hold_box(self.box_local + np.array([0.0, 0.0, 0.02]), half_width + KNUCKLES + OPEN_GAP, 0.6)
        yield from self.until(end)
        self.grip[:] = 0.0
        self.relax_arm(LEFT)
        self.relax_arm(RIGHT)


__all__ = ["BoxExpert"]
