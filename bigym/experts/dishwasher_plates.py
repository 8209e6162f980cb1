"""DishwasherUnloadPlates demonstrator (scene counter_dishwasher): take the two plates out of
the dishwasher's bottom tray and stand them in the dish drainer on the counter.

The open door lies flat in front of the dishwasher with the bottom tray pulled out over
it; the plates stand in its front row, their faces towards the sides. A person walks
round the door's free end to the front of the tray, crouches, takes each plate by the top
of its rim with the hand on its side (the fingers closing across its thickness; one that
slips back into the tray is taken again), stands up stepping back, and walks back round
the door to the counter holding both low beside the body; short of the drainer they raise
one plate over its holders (the other one over the counter's height), step so that it
hangs over its slot, lower it in upright (lifting it a little and moving it over if it
sticks on a holder: the gaps leave it 7 mm either way) and let go; then the other.

What makes it work (measured with the dev scripts of the closing note): a plate raised
over the drainer is out of the arm's comfortable reach, and the IK moved the body up to
40 cm off its plan to reach it; the step that followed, started from there, jerked the
held plates and they slipped. So while the plates are held the body keeps closer to its
plan (``PLATES_BODY_ON_PLAN``), they are carried low (``CARRY_AT``) where the arms hold
them without help, and the steps at the drainer start from the planned body. Over the
slot the IK leaves the held plate some degrees and up to 9 cm off what the hand is asked
for, and the slot takes it only within 7 mm, less as it leans: the hand turns it upright
and moves it over the slot by what it sees, and lowers it where it fits as it leans
(:meth:`PlateUnloadExpert.fit_error`). Before it did, 8 of the 20 failures on seeds 0-39
let a plate go on the holders or off its slot (23 of 40 succeeded with this alone).

Choices drawn per demo: which hand takes its plate first and which puts it in first, the
two slots (one free slot at least between them), where along the rim the fingers close,
the stances, the crouch, the timing and every path's via-points.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.dishwasher_plates import PLATE_IN_SLOT
from bigym.experts.dishwasher_cutlery import CARRY_HEIGHT, ROUND_THE_DOOR_X
from bigym.experts.expert import LEFT, RIGHT, SIDE_NAMES, Script
from bigym.experts.geometry import aligning_rotation, yaw_matrix
from bigym.experts.grasping import GRASP, HOLD, LANDED, PRE_GRASP_HEIGHT
from bigym.experts.move_plates import ARRIVING, LAND, SLOT_GAP, MovePlateExpert

DRAINER = "drainer"
#: how far (m) behind the plates the pelvis stands at the tray, and how high
TRAY_REACH = 0.36
TRAY_CROUCH = 0.72
#: how often a hand takes its plate at most
TAKE_ATTEMPTS = 2
#: where the hands hold the plates while carrying (pelvis frame, m)
CARRY_AT = np.array([0.25, 0.3, -0.12])
#: how fast (x a free movement) a held plate is raised: a brisk lift turns it in the fingers
RAISE_SPEED = 0.5
#: where the other plate is held meanwhile (pelvis frame): over the counter's height
OVER_COUNTER = np.array([0.18, 0.3, 0.1])
#: where a plate is raised (pelvis frame) before the step that brings it over its slot
LIFTED = np.array([0.32, 0.2, 0.24])
#: how far (m) in front of the drainer's middle the pelvis stops, the plates clear of it
DRAINER_REACH = 0.72
#: IK costs of the base's deviation from its plan while the plates are held: a plate
#: raised over the drainer is out of the arm's comfortable reach, and the default costs let
#: the body drift 40 cm towards it (a later step, starting from there, then jerks the hand)
PLATES_BODY_ON_PLAN = {"x": 5.0, "y": 5.0, "z": 6.0, "rz": 4.0}
#: a plate whose origin stops this far (m) over its rest has stuck on the holders: it is
#: lifted this far (m) and put in again, at most this often
STUCK = 0.012
RESEAT_LIFT = 0.03
RESEATS = 2
#: over the slot, the plate is turned upright (within ``STRAIGHT`` rad) and moved over it
#: (within ``ALIGNED`` m along x, y) at most this often
STRAIGHTEN_TRIES = 2
STRAIGHT = np.deg2rad(3.0)
ALIGNED = np.array([0.02, 0.003])
#: where a plate goes down between the holders, measured by posing it over a slot in the
#: scene (dev script of the closing note): upright, its origin 1 mm to -y of the slot's
#: (7 mm either way); leaning, its lower rim shifts by this lever (m) times the lean's sine
SLOT_CENTRE = -0.001
SLOT_LEVER = 0.09
#: how often a hand corrects its pinch on the rim before closing, and how long the closed
#: fingers hold still before the lift (on the dev probe's seeds 0-39, 26 successes with
#: both against 23 without; a plate still slips back into the tray in about one take in
#: five, and is taken again)
TAKE_ADJUSTS = 2
TAKE_FIRM = 0.3
#: how often the right hand takes its plate first, and puts it in first
RIGHT_FIRST = 0.6


class PlateUnloadExpert(MovePlateExpert):
    """Moves the plates of ``DishwasherUnloadPlates`` into the dish drainer."""

    tasks = ("DishwasherUnloadPlates",)
    target_drainer: ClassVar[str] = DRAINER
    #: the plates go in upright, as the dishwasher holds them (not leaning, as in MovePlate)
    slot_offset: ClassVar[np.ndarray] = PLATE_IN_SLOT
    #: pinch corrections and the still moment before the lift when taking a plate (see
    #: ``TAKE_ADJUSTS``)
    take_adjusts: ClassVar[int] = TAKE_ADJUSTS
    take_firm: ClassVar[float] = TAKE_FIRM

    def plates(self) -> tuple[str, ...]:
        return tuple(self.env.items)

    def plan(self) -> Script:
        env = self.env
        ys = {p: float(self.data.xpos[env.props[p].root_body_id][1]) for p in env.items}
        plate_of = dict(zip((LEFT, RIGHT), sorted(env.items, key=lambda p: -ys[p]), strict=True))
        first = RIGHT if self.rng.random() < RIGHT_FIRST else LEFT
        self.choices["hands"] = [f"{plate_of[s]}:{SIDE_NAMES[s]}" for s in (first, 1 - first)]
        drainer = env.props[DRAINER]
        n = len(drainer.slot_keys)
        pairs = [(i, j) for i in range(n) for j in range(i + 1 + SLOT_GAP, n)]
        i, j = pairs[int(self.rng.integers(len(pairs)))]
        slot_of = {LEFT: drainer.slot_keys[i], RIGHT: drainer.slot_keys[j]}
        yield from self.wait(self.human.reaction())
        yield from self.walk_to_tray(plate_of)
        self.note("at tray")
        for side in (first, 1 - first):
            yield from self.take_until_held(side, plate_of[side])
        # while the plates are held in the body's frame the body keeps to its plan (see
        # :mod:`bigym.experts.dishwasher_unload_cutlery_long`)
        self.base_cost.update(PLATES_BODY_ON_PLAN)
        yield from self.walk_to_drainer()
        self.note("at drainer")
        put_first = RIGHT if self.rng.random() < RIGHT_FIRST else LEFT
        self.choices["slots"] = [slot_of[s] for s in (put_first, 1 - put_first)]
        carrying = [LEFT, RIGHT]
        for side in (put_first, 1 - put_first):
            # the plate up over the rack's holders, then a step brings it over its slot
            # (the other plate, held beside the hip, up over the counter's height too)
            base = self.base_pose()
            ends = []
            for hand, where in ((side, LIFTED), *((s, OVER_COUNTER) for s in carrying if s != side)):
                goal = where * np.array([1.0, 1.0 if hand == LEFT else -1.0, 1.0]) + self.human.jitter(0.015, 3)
                ends.append(self.move_hand_with_body(hand, goal, HOLD, base, speed=RAISE_SPEED))
            yield from self.until(max(ends))
            goal = self.site_of(drainer, slot_of[side]) + self.slot_offset
            held = self.data.xpos[env.props[plate_of[side]].root_body_id]
            step = self.base_pose()
            step[:2] += (goal - held)[:2] + self.human.jitter(0.015, 2)
            others = [s for s in carrying if s != side]
            arrive = yield from self.walk([step], carrying=others, wait=False, from_plan=True)
            yield from self.until(arrive - ARRIVING)
            yield from self.slot_in(side, plate_of[side], slot_of[side])
            self.relax_arm(side)
            carrying = others
        while True:
            yield

    def take_until_held(self, side: int, plate: str, opening: float = 0.0) -> Script:
        """Take ``plate`` by its rim; one that slipped back into its rack is taken again (at
        most ``TAKE_ATTEMPTS`` times in all)."""
        for _ in range(TAKE_ATTEMPTS):
            yield from self.take_plate(side, plate, opening=opening, adjust=self.take_adjusts, firm=self.take_firm)
            if self.env.held(plate):
                break
            self.note(f"slipped {'LR'[side]}")
        self.note(f"took {'LR'[side]}")

    def slot_in(self, side: int, plate: str, slot: str) -> Script:
        """Hold the plate upright over ``slot`` of the drainer and lower it in; if it sticks
        on the holders, lift it a little, move it by how far it is off and lower it again,
        as a person jiggles a plate into a rack; then let go.

        Over the slot the hand turns the plate upright and moves it over the slot by what it
        sees (:data:`STRAIGHTEN_TRIES`): the IK leaves the held plate some degrees and
        centimetres off what it is asked for, and the slot takes it only within 7 mm. The
        plate goes down where it fits as it leans (:meth:`fit_error`).
        """
        self.note(f"place {'LR'[side]}")
        body = self.env.props[plate].root_body_id
        origin = self.data.xpos[body]
        goal = self.site_of(self.env.props[DRAINER], slot) + self.slot_offset
        frame = self.data.xmat[body].reshape(3, 3)
        target_normal = self._initial_rotation[plate][:, 2]
        upright = aligning_rotation(frame[:, 2], target_normal) @ frame
        rotation = self.turned_rotation(side, body, upright)
        above = goal + np.array([0.0, 0.0, PRE_GRASP_HEIGHT * 0.8 + abs(self.human.jitter(0.02))])
        yield from self.until(
            self.move_hand(side, above + self.held_offset(side, body), rotation, HOLD, correct=True, precision=0.02)
        )
        for _ in range(STRAIGHTEN_TRIES):
            normal = self.data.xmat[body].reshape(3, 3)[:, 2]
            tilt = float(np.arccos(np.clip(normal @ target_normal, -1.0, 1.0)))
            off = self.fit_error(body, goal)
            if tilt <= STRAIGHT and np.all(np.abs(off) <= ALIGNED):
                break
            self.note(f"straighten {'LR'[side]} {np.degrees(tilt):.0f}")
            p, r = self.hand_pose(side)
            turn = aligning_rotation(normal, target_normal) if tilt > STRAIGHT else np.eye(3)
            target = p - np.append(off, 0.0)
            end = self.move_hand(side, target, turn @ r, HOLD, spread=0.0, precision=0.005, speed=0.6)
            yield from self.until(end + 0.1)
        for attempt in range(RESEATS + 1):
            p, r = self.hand_pose(side)
            off = self.fit_error(body, goal)
            point = p - np.append(off, 0.0)
            point[2] = goal[2] + self.held_offset(side, body)[2]
            end = self.move_hand(side, point, r, HOLD, spread=0.0, precision=0.004, speed=0.5, tremor=0.3)
            yield from self.until(end + 0.15)
            yield from self.lower_until(side, r, LAND, 0.3, lambda: origin[2] <= goal[2] + LANDED)
            if origin[2] <= goal[2] + STUCK or attempt == RESEATS:
                break
            self.note(f"reseat {'LR'[side]}")
            off = self.fit_error(body, goal)
            p, _ = self.hand_pose(side)
            lift = p - np.append(off, -RESEAT_LIFT)
            yield from self.until(self.move_hand(side, lift, r, HOLD, spread=0.0, precision=0.004, speed=0.5))
        _, r = self.hand_pose(side)
        yield from self.let_go(side, r)

    def fit_error(self, body: int, goal: np.ndarray) -> np.ndarray:
        """How far (x, y) the plate's origin is from where the plate goes down into the
        slot at ``goal`` as it leans now: a plate whose face tips up by an angle has its
        lower rim, the part between the holders, further along its face
        (:data:`SLOT_LEVER` times the sine; the drainer's slots run along world y)."""
        normal = self.data.xmat[body].reshape(3, 3)[:, 2]
        fits = goal[:2] + np.array([0.0, SLOT_CENTRE - SLOT_LEVER * normal[2] * np.sign(normal[1])])
        return self.data.xpos[body][:2] - fits

    def let_go(self, side: int, rotation: np.ndarray) -> Script:
        """Let go of a plate standing in its slot and draw the hand back out along its
        approach, and up."""
        self.hold_hand(side, HOLD, tremor=0.2)
        yield from self.wait(0.1)
        yield from self.set_grip(side, 0.0, max_wait=0.6, min_wait=0.3)
        p, _ = self.hand_pose(side)
        back = p - rotation[:, 2] * 0.06 + np.array([0.0, 0.0, 0.08])
        yield from self.until(self.move_hand(side, back, rotation, GRASP * 0.5, spread=0.2, tremor=0.5))

    def walk_to_tray(self, plate_of: dict[int, str]) -> Script:
        """Round the door's free end to the front of the pulled-out tray, crouching, facing it."""
        base = self.commanded_base()
        centres = np.array([self.data.xpos[self.env.props[p].root_body_id] for p in plate_of.values()])
        x = float(np.min(centres[:, 0])) - TRAY_REACH + self.human.jitter(0.02)
        y = float(np.mean(centres[:, 1])) + self.human.jitter(0.03)
        self.choices["tray stance"] = [round(x, 2), round(y, 2)]
        route = [
            (ROUND_THE_DOOR_X + self.human.jitter(0.04), base[1] + 0.2, base[2], 0.5),
            (x, y, TRAY_CROUCH + self.human.jitter(0.02), self.human.jitter(0.06)),
        ]
        yield from self.walk(route)

    def walk_to_drainer(self) -> Script:
        """Stand up, hold the plates apart in front of the body, walk back round the door to
        the counter in front of the drainer."""
        base = self.commanded_base()
        yield from self.walk([(base[0] - 0.1, base[1], CARRY_HEIGHT, base[3])], carrying=(LEFT, RIGHT))
        base = self.base_pose()
        ends = []
        for side in (LEFT, RIGHT):
            goal = CARRY_AT * np.array([1.0, 1.0 if side == LEFT else -1.0, 1.0]) + self.human.jitter(0.02, 3)
            ends.append(self.move_hand_with_body(side, goal, HOLD, base))
        drainer = self.data.xpos[self.env.props[DRAINER].root_body_id]
        yaw = self.human.jitter(0.05)
        stance = drainer[:2] - yaw_matrix(yaw)[:2, :2] @ np.array([DRAINER_REACH + self.human.jitter(0.02), 0.0])
        stance[1] += self.human.jitter(0.03)
        route = [
            (ROUND_THE_DOOR_X + self.human.jitter(0.04), drainer[1] + 0.25, CARRY_HEIGHT, -0.4),
            (stance[0], stance[1], CARRY_HEIGHT, yaw),
        ]
        arrival = yield from self.walk(route, wait=False)
        yield from self.until(max(arrival, *ends))


__all__ = ["PlateUnloadExpert"]
