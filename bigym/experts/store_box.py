"""The box from the counter into the base cabinet (``StoreBox``; scene cabinet_door).

What a person does: opens the cabinet door first (hands free; the door skill), stands
square to two opposite faces of the box on the counter (the pair that turns the body
least from the counter, either pair when both are easy), brings a fist down beside each
face and squeezes, lifts the box a little, draws it back off the counter while turning
square to the cabinet, crouches with it in front of the cabinet beside the open door,
carries it in at shelf height, lowers it until it rests flat, lets go and draws the
hands back out. The squeeze and the straight arms are the box carry's
(``bigym/experts/boxes.py``). Choices drawn per demo: which pair of faces (where both are
easy), where the box goes on the shelf, how low the body crouches, the timing, and every
path's via-points.

Known flaw: the box tilts in the fists. The flat box (0.12 m tall) can only be pressed
about 1 cm above its centre of mass (where the fists' contact patch lands; aimed higher,
the patch rose less and the box tilted more), so it hangs as a pendulum about the squeeze
axis with almost no restoring torque, and a few millimetres of fore-aft offset tilt it
15-45 degrees; the tilt swings when the body moves. A box carried in tilted touches the
shelf on an edge, so the expert lowers on until it lies flat before letting go.

While the box touches the shelf (scraping its front edge on the way in, or touching down
on an edge) one fist's contacts come and go, and the task counts as done at such a moment
with the box still in the fists. Recordings that ended 1 s after that moment still held
the box, and their replays at 50, 25 and 20 Hz, which rarely repeat it, never succeeded:
27 of the 36 recordings dropped by the first build (50 kept of 86, 58%). In 10 of the 11
dropped seeds looked at the first success was such a moment, and a success that held
came 2.4-3.9 s later, so this expert's recordings end only once the task has been
successful for a whole second
(``success_must_last``): 50 kept of 63 (79%), the rest replays whose arm, pushing the
door open, strays beyond the tolerance (``manifests/v2-build.json``). Carrying the box in
6 cm higher did not help (54%). Ideas not tried: keep the box's near edge on the counter
while drawing it back, or turn the knuckles up.
"""

from __future__ import annotations

import numpy as np

from bigym.experts.boxes import (
    ARM_REACH,
    BOX,
    HANDS_DOWN,
    KNUCKLES,
    SHOULDER_AHEAD,
    SHOULDER_HEIGHT,
    BoxExpert,
)
from bigym.experts.doors import DoorSkills
from bigym.experts.expert import LEFT, RIGHT, Script
from bigym.experts.grasping import LOWER_SPEED, from_base
from bigym.robot.h1 import STANDING_HEIGHT

CABINET = "cabinet"
DOOR = "door_left"
#: how far (m) the pelvis keeps inside the open door's hinge (the torso and the right arm)
DOOR_CLEARANCE = 0.40
#: the counter's front (x); the shelf's front (x) and top (z)
COUNTER_FRONT = 0.58
SHELF_FRONT = 0.64
SHELF_TOP = 0.48
#: how far (m) behind the shelf's front edge the box's front edge is aimed (it ends a few
#: centimetres short: it hangs back in the fists)
SHELF_MARGIN = 0.14
#: the box's y on the shelf: a little left of the middle, away from the open door
BOX_Y = 0.03
#: the box's bottom this high (m) over the shelf while it is carried in (it hangs lower)
ENTRY_CLEARANCE = 0.10
#: the pelvis height (m) when putting the box in: the shoulders below the counter's front
STORE_CROUCH = 0.5
#: how high (m) the box is lifted off the counter before it is drawn back
LIFT = 0.08
#: the box's far edge keeps this far (m) from the counter's front when lowered past it
CLEAR_MARGIN = 0.06
#: how fast (relative to the demonstrator's pace) the body moves with the box
STORE_SPEED = 0.4
#: the most (rad) the body turns from square to the counter to stand square to the box
MAX_TURN = np.deg2rad(50.0)
#: the knuckles are aimed this far (m) below the box's top (the contact patch lands about
#: 1 cm above the box's centre of mass; aimed higher, it rose less and the box tilted more)
PRESS_BELOW_TOP = 0.035
#: how much further (m) the hands may go down once the box touches the shelf, to lay it
#: flat, and when it counts as flat (its top up within this many rad)
FLATTEN = 0.08
FLAT_TILT = 0.05
#: how far (m) the fists move off the box's faces to let go, inside the cabinet's walls
RELEASE_GAP = 0.045
#: how far (m) the hands are drawn back out of the cabinet after letting go
WITHDRAW = 0.35
PELVIS_TO_SHOULDER = SHOULDER_HEIGHT - STANDING_HEIGHT


class StoreBoxExpert(BoxExpert, DoorSkills):
    """Opens the cabinet and puts the box of ``StoreBox`` on its shelf."""

    tasks = ("StoreBox",)
    # the fists' contacts with the box come and go while it touches the shelf (carried in,
    # lowered on an edge): the task counts as done at such a moment with the box still
    # in the fists, and a replay at another rate rarely repeats it (see the module's notes)
    success_must_last = True

    def plan(self) -> Script:
        yield from self.wait(self.human.reaction())
        # its own keep-out (:meth:`stance_y`): the box is wider than the body
        yield from self.open_cabinet_door(CABINET, DOOR, keep_clear=False)
        yield from self.store_box()
        while True:
            yield

    def reach_at(self, pelvis_z: float, hands_z: float) -> float:
        """How far ahead of the pelvis straight arms hold the hands at height ``hands_z``."""
        drop = pelvis_z + PELVIS_TO_SHOULDER - hands_z
        return float(np.sqrt(max(ARM_REACH**2 - drop**2, 0.0))) + SHOULDER_AHEAD

    def beside_door(self) -> float:
        """The least pelvis y that keeps the body clear of the open door (hinged on the right)."""
        p = self.env.props[CABINET]
        hinge = self.data.xanchor[p.joint_ids[p.joint_index(DOOR)]]
        return float(hinge[1]) + DOOR_CLEARANCE

    def choose_faces(self, faces: list) -> tuple[str, float, float, np.ndarray]:
        """(which faces, their half width, the box's half depth in the hands, the facing)."""
        options = []
        for name in ("wide", "narrow"):
            pick = min if name == "wide" else max
            normal, half_width = pick(faces, key=lambda f: f[1])
            depth = (max if name == "wide" else min)(f[1] for f in faces)
            facing = np.array([-normal[1], normal[0]])
            facing = facing if facing[0] >= 0.0 else -facing
            options.append((name, half_width, depth, facing))
        easy = [o for o in options if abs(np.arctan2(o[3][1], o[3][0])) <= MAX_TURN]
        if len(easy) == 2:
            return easy[int(self.rng.integers(2))]
        return min(options, key=lambda o: abs(np.arctan2(o[3][1], o[3][0])))

    def store_box(self) -> Script:
        centre, faces, half_height = self.box_faces()
        name, half_width, depth, facing = self.choose_faces(faces)
        self.choices["faces"] = name
        hold_z = centre[2] + half_height - PRESS_BELOW_TOP
        stand_z = STANDING_HEIGHT - abs(self.human.jitter(0.02))
        point = centre[:2] - self.reach_at(stand_z, hold_z) * facing
        stance = np.array([point[0], point[1], stand_z, float(np.arctan2(facing[1], facing[0]))])
        self.note("walk to box")
        # the fists come over the box's sides from above and outside, not across its top
        hold_point = np.array([centre[0], centre[1], hold_z])
        yield from self.take_box(stance, hold_point, half_width, lead=0.5 * HANDS_DOWN, above=0.1, outside=0.22)
        self.note("lift")
        end = self.hold_box(self.box_local + np.array([0.0, 0.0, LIFT]), self.box_gap, 0.6)
        yield from self.until(end)
        # draw it back off the counter, turning square to the cabinet; crouch with it in
        # front of the cabinet, the body beside the open door; carry it in
        goal_x = SHELF_FRONT + depth + SHELF_MARGIN + abs(self.human.jitter(0.02))
        pelvis_y = self.beside_door() + abs(self.human.jitter(0.02))
        aside = BOX_Y + float(np.clip(self.human.jitter(0.015), -0.02, 0.02)) - pelvis_y
        clear_x = COUNTER_FRONT - depth - CLEAR_MARGIN
        stand = self.commanded_base()[2]
        world_z = float(from_base(self.commanded_base(), self.box_local, None)[0][2])
        reach = self.reach_at(stand, world_z)
        drawn = np.array([clear_x - reach, pelvis_y, stand, 0.0])
        self.note("draw back")
        yield from self.walk_holding(drawn, np.array([reach, aside, world_z - stand]))
        hands_z = SHELF_TOP + ENTRY_CLEARANCE + 2 * half_height - PRESS_BELOW_TOP
        crouch = STORE_CROUCH + abs(self.human.jitter(0.02))
        in_reach = self.reach_at(crouch, hands_z)
        low = np.array([clear_x - in_reach, pelvis_y, crouch, 0.0])
        self.note("crouch")
        yield from self.walk_holding(low, np.array([in_reach, aside, hands_z - crouch]))
        inside = low.copy()
        inside[0] = goal_x - in_reach
        self.note("carry in")
        yield from self.walk_holding(inside, self.box_local)
        yield from self.put_in(half_width)

    def walk_holding(self, base: np.ndarray, hold: np.ndarray) -> Script:
        """Walk to ``base`` while the hold moves to ``hold`` (base frame) on the way."""
        end_walk = yield from self.walk([base], wait=False, speed=STORE_SPEED)
        self.hold_box(hold, self.box_gap, end_walk - self.time)
        yield from self.until(end_walk)
        self.base_ref = lambda t, b=base: b

    def put_in(self, half_width: float) -> Script:
        """Lower the box until it rests flat on the shelf (it hangs tilted in the fists and
        touches down on an edge first), then let go and draw the hands back out."""
        self.note("lower")
        depth = ENTRY_CLEARANCE + 0.06
        end = self.hold_box(self.box_local - np.array([0.0, 0.0, depth]), self.box_gap, depth / LOWER_SPEED)
        while self.time < end and not self.touches_support(BOX):
            yield
        end = self.hold_box(self.box_local - np.array([0.0, 0.0, FLATTEN]), self.box_gap, FLATTEN / LOWER_SPEED)
        while self.time < end and not self.box_flat():
            yield
        self.hold_box(self.box_local - np.array([0.0, 0.0, 0.01]), self.box_gap, 0.01 / LOWER_SPEED)
        yield from self.wait(0.3)
        self.note("let go")
        self.straighten_arms(False)
        end = self.hold_box(self.box_local + np.array([0.0, 0.0, 0.02]), half_width + KNUCKLES + RELEASE_GAP, 0.6)
        yield from self.until(end)
        self.note("withdraw")
        end = self.hold_box(self.box_local - np.array([WITHDRAW, 0.0, 0.0]), self.box_gap, 1.0)
        yield from self.until(end)
        self.grip[:] = 0.0
        self.relax_arm(LEFT)
        self.relax_arm(RIGHT)

    def box_flat(self) -> bool:
        frame = self.data.xmat[self.env.props[BOX].root_body_id].reshape(3, 3)
        return float(np.max(np.abs(frame[2, :]))) > np.cos(FLAT_TILT)


__all__ = ["StoreBoxExpert"]
