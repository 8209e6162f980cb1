"""MovePlate demonstrator: take the plate by its rim from one dish drainer to the other.

A person takes the standing plate by the top of its rim, fingers closing across its
thickness, lifts it out of the slot, steps sideways to the other drainer carrying it, and
lowers it into a free slot, standing as it stood; then lets go and draws the hand back.

Choices drawn per demo: the hand (mostly the one on the start rack's side), the target
slot, where along the rim the fingers close.

With two plates (MoveTwoPlates, 14 s) a person carries both at once, one per hand; the
left hand takes the plate further left, the right hand the other (the hands never cross).
The robot steps up to the start rack with the first hand reaching out and the other at
its hip, takes the first plate, side-steps (its plate going with it, out of the way)
while the other hand reaches for the second, walks across carrying both and puts them in
one after the other, each as it arrives over its slot. These plates are taken by their
flat well near the front, the hand coming in level: a hand that cannot point down meets
the top of a standing plate with its palm before its fingers are round the rim, and a
plate held by its thin, sloped rim off its top is squeezed out of the fingers. Held off
centre, a plate may turn a little in the fingers about its own axis; it is put in with
its face as it stood, whatever its turn. Fingers going in beside a neighbouring plate
are half-closed. Drawn per demo: which hand takes its plate first and which plate goes
in first (mostly the right hand's: the body then keeps stepping one way, towards the
target rack), the two target slots (one free slot between them, so that the opening
fingers miss the other plate), the grasp points, the stances and the timing.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.move_plates import PLATE_IN_SLOT_OFFSET
from bigym.experts.expert import LEFT, RIGHT, SIDE_NAMES, Script
from bigym.experts.geometry import aligning_rotation
from bigym.experts.grasping import HOLD, TABLE_CLEARANCE, GraspingExpert
from bigym.props import DishDrainer

TABLE_FRONT = 0.4  # x of the table's front edge
#: the fingers close this far (m) below the top of the rim
RIM_DEPTH = 0.022
#: how high (m) a plate is lifted out of its slot: above the rack's holders
LIFT = 0.13
#: how often a single plate is taken with the hand on the start rack's side
NEAR_HAND_PROBABILITY = 0.85
#: two plates go in with at least this many free slots between them (the opening fingers
#: reach 4 cm either side of a plate, one slot's pitch)
SLOT_GAP = 1
#: how far the fingers are closed (0 open, 1 shut) going in beside a neighbouring plate:
#: the finger between the two then misses both
NEIGHBOUR_OPENING = 0.6
#: a plate's flat well is taken this far (m) from its centre and this far (rad) round
#: from its top towards the robot: the hand, level, passes over the rim onto the well
WELL_RADIUS = 0.064
WELL_ANGLE = 1.3
#: orientation costs of a grasp on the well: the hand comes in level, as it can
WELL_GRASP = np.array([2.0, 1.0, 2.0])
#: how much further down (m, at most) a hand goes until its plate stands in the slot
LAND = 0.03
#: how long (s) before the end of a step the hand sets off for the next plate or slot
ARRIVING = 0.5
#: how often the right hand takes its plate first, and puts it in first
RIGHT_FIRST = 0.8
#: how far (m) to the side of the pelvis a hand takes or puts a plate
LATERAL = 0.18


class MovePlateExpert(GraspingExpert):
    """Moves the plate of ``MovePlate``, or both plates of ``MoveTwoPlates``, to the target drainer."""

    tasks = ("MovePlate", "MoveTwoPlates")
    pace: ClassVar[dict[str, float]] = {"MovePlate": 1.6, "MoveTwoPlates": 1.8}
    #: the drainer the plates go into, and where a plate's origin rests in one of its slots
    #: (relative to the slot's site)
    target_drainer: ClassVar[str] = "drainer_target"
    slot_offset: ClassVar[np.ndarray] = PLATE_IN_SLOT_OFFSET

    def plan(self) -> Script:
        if len(self.env.plates) == 2:
            yield from self.plan_two()
            return
        env = self.env
        (plate,) = env.plates
        start, target = env.props["drainer_start"], env.props["drainer_target"]
        near = LEFT if self.data.xpos[start.root_body_id][1] > 0.0 else RIGHT  # mostly the hand on the rack's side
        side = near if self.rng.random() < NEAR_HAND_PROBABILITY else 1 - near
        slot = target.slot_keys[int(self.rng.integers(len(target.slot_keys)))]
        self.choices["hands"] = [f"{plate}:{SIDE_NAMES[side]}"]
        self.choices["slots"] = [slot]

        start_xy = self.data.xpos[start.root_body_id][:2].copy()
        target_xy = self.data.xpos[target.root_body_id][:2].copy()
        yield from self.wait(self.human.reaction())
        base = self.commanded_base()
        lateral = LATERAL if side == LEFT else -LATERAL
        stance = np.array(
            [TABLE_FRONT - TABLE_CLEARANCE - abs(self.human.jitter(0.02)),
             start_xy[1] - lateral + self.human.jitter(0.03), base[2], self.human.jitter(0.05)]
        )  # fmt: skip
        self.move_base(stance)  # steps up to the rack while the hand reaches out
        yield from self.take_plate(side, plate)
        # step across to the target drainer, carrying
        base = self.commanded_base()
        across = base.copy()
        across[1] = target_xy[1] + (base[1] - start_xy[1]) + self.human.jitter(0.03)
        yield from self.walk([across], carrying=[side])
        yield from self.put_in_slot(side, plate, slot)
        self.relax_arm(side)
        while True:
            yield

    def plan_two(self) -> Script:
        """Both plates at once, one per hand (see the module docstring)."""
        env = self.env
        target = env.props["drainer_target"]
        ys = [float(self.data.xpos[env.props[p].root_body_id][1]) for p in env.plates]
        plate_of = dict(zip((LEFT, RIGHT), sorted(env.plates, key=lambda p: -ys[env.plates.index(p)]), strict=True))
        # mostly the right hand first, and its plate put in first: the body then keeps
        # stepping one way, from the start rack towards the target
        first = RIGHT if self.rng.random() < RIGHT_FIRST else LEFT
        # slot keys run from +y to -y: the left plate takes the first of the pair
        n = len(target.slot_keys)
        pairs = [(i, j) for i in range(n) for j in range(i + 1 + SLOT_GAP, n)]
        i, j = pairs[int(self.rng.integers(len(pairs)))]
        slot_of = {LEFT: target.slot_keys[i], RIGHT: target.slot_keys[j]}
        self.choices["hands"] = [f"{plate_of[s]}:{SIDE_NAMES[s]}" for s in (first, 1 - first)]
        self.choices["order"] = [plate_of[s] for s in (first, 1 - first)]

        self.keep_base_behind(np.array([TABLE_FRONT, 0.0]), np.array([1.0, 0.0]), TABLE_CLEARANCE)
        # neighbours one slot apart leave room only for half-open fingers
        opening = NEIGHBOUR_OPENING if abs(ys[0] - ys[1]) < 1.5 * DishDrainer.PITCH else 0.0
        yield from self.wait(self.human.reaction())
        base = self.commanded_base()
        stance = np.array(
            [TABLE_FRONT - TABLE_CLEARANCE - abs(self.human.jitter(0.02)), self.lateral_stance(first, plate_of[first]),
             base[2], self.human.jitter(0.05)]
        )  # fmt: skip
        self.move_base(stance)
        self.hand_to_hip(1 - first)  # the other hand, held out, would come up against the plates
        yield from self.take_plate(first, plate_of[first], opening, well=True)
        # a side step takes the first plate away from the second and brings the other hand to it
        second = 1 - first
        across = self.commanded_base()
        across[1] = self.lateral_stance(second, plate_of[second])
        arrive = yield from self.walk([across], carrying=[first], wait=False)
        yield from self.until(arrive - ARRIVING)  # the hand reaches out as the body arrives
        yield from self.take_plate(second, plate_of[second], well=True)

        put_first = RIGHT if self.rng.random() < RIGHT_FIRST else LEFT
        self.choices["slots"] = [slot_of[s] for s in (put_first, 1 - put_first)]
        carrying = [LEFT, RIGHT]
        for side in (put_first, 1 - put_first):
            # step across so that the plate hangs over its slot as it hung over the rack
            goal = self.site_of(target, slot_of[side]) + PLATE_IN_SLOT_OFFSET
            held = self.data.xpos[env.props[plate_of[side]].root_body_id]
            across = self.commanded_base()
            across[1] += goal[1] - held[1] + self.human.jitter(0.02)
            across[0] += self.human.jitter(0.01)
            arrive = yield from self.walk([across], carrying=carrying, wait=False)
            yield from self.until(arrive - ARRIVING)  # the plate comes over its slot as the body arrives
            yield from self.put_in_slot(side, plate_of[side], slot_of[side], spin_free=True)
            self.relax_arm(side)
            carrying = [1 - side]
        while True:
            yield

    def lateral_stance(self, side: int, plate: str) -> float:
        """Where (y) the pelvis stands for ``side``'s hand to take ``plate``: the plate a
        little outside that shoulder."""
        y = float(self.data.xpos[self.env.props[plate].root_body_id][1])
        return y - (LATERAL if side == LEFT else -LATERAL) + self.human.jitter(0.03)

    def take_plate(
        self, side: int, plate: str, opening: float = 0.0, well: bool = False, adjust: int = 0, firm: float = 0.0
    ) -> Script:
        """Take ``plate`` by the top of its rim, or (``well``) by its flat well near the
        front (see the module docstring); ``adjust`` and ``firm`` as for :meth:`pick`."""
        body = self.env.props[plate].root_body_id
        grasp = {}
        if well:
            grasp = {"tilt": 0.0, "cost": WELL_GRASP}
            well_angle = WELL_ANGLE + self.human.jitter(0.1)

        def aim() -> tuple[np.ndarray, np.ndarray]:
            frame = self.data.xmat[body].reshape(3, 3)
            normal = frame[:, 2]  # the plate's face normal: the fingers close along it
            centre = self.data.xpos[body] + normal * self.env.props[plate].height / 2
            up = np.array([0.0, 0.0, 1.0]) - normal * normal[2]
            up /= np.linalg.norm(up)
            along = np.cross(normal, up)
            if not well:
                radius = self.env.props[plate].radius
                return centre + up * (radius - RIM_DEPTH) + along * self.human.jitter(0.012), normal
            toward = along if along[:2] @ (self.base_pose()[:2] - centre[:2]) > 0.0 else -along
            angle = well_angle + self.human.jitter(0.05)
            radius = WELL_RADIUS + self.human.jitter(0.004)
            return centre + (np.cos(angle) * up + np.sin(angle) * toward) * radius, normal

        lift = LIFT + abs(self.human.jitter(0.01))
        if not (
            yield from self.pick(side, aim, lift=lift, prop=plate, opening=opening, adjust=adjust, firm=firm, **grasp)
        ):
            self.note(f"gave up on {plate}")
            while True:
                yield
        self.hold_hand(side, HOLD)

    def put_in_slot(self, side: int, plate: str, slot: str, spin_free: bool = False) -> Script:
        """Lower the plate into ``slot`` standing as it stood in its first slot. With
        ``spin_free`` only its face is turned back as it stood: a plate turned in its own
        plane is the same plate, and the hand cannot pitch it back."""
        env = self.env
        # a plate stands in a slot as the task puts it in at the start (the drainers are not rotated)
        goal = self.site_of(env.props[self.target_drainer], slot) + self.slot_offset
        orientation = self._initial_rotation[plate]
        if spin_free:
            frame = self.data.xmat[env.props[plate].root_body_id].reshape(3, 3)
            orientation = aligning_rotation(frame[:, 2], orientation[:, 2]) @ frame
        land = LAND if spin_free else 0.0
        yield from self.place(side, goal, prop=plate, level=False, orientation=orientation, feel=False, land=land)

    def site_of(self, prop, key: str) -> np.ndarray:
        return self.data.site_xpos[prop.site_id(key)].copy()

    def start(self) -> None:
        super().start()
        self._initial_rotation = {
            p: self.data.xmat[self.env.props[p].root_body_id].reshape(3, 3).copy() for p in self.plates()
        }

    def plates(self) -> tuple[str, ...]:
        """The task's plates."""
        return tuple(self.env.plates)


__all__ = ["MovePlateExpert"]
