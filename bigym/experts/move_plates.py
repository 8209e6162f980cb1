"""MovePlate demonstrator: take the plate by its rim from one dish drainer to the other.

A person takes the standing plate by the top of its rim, fingers closing across its
thickness, lifts it out of the slot, steps sideways to the other drainer carrying it, and
lowers it into a free slot, standing as it stood; then lets go and draws the hand back.

Choices drawn per demo: the hand (mostly the one on the start rack's side), the target
slot, where along the rim the fingers close. (MoveTwoPlates, both hands in 14 s, is not
scripted yet.)
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.move_plates import PLATE_IN_SLOT_OFFSET
from bigym.experts.expert import LEFT, RIGHT, Script
from bigym.experts.grasping import HOLD, TABLE_CLEARANCE, GraspingExpert

TABLE_FRONT = 0.4  # x of the table's front edge
#: the fingers close this far (m) below the top of the rim
RIM_DEPTH = 0.022
#: how high (m) a plate is lifted out of its slot: above the rack's holders
LIFT = 0.13
#: how often a single plate is taken with the hand on the start rack's side
NEAR_HAND_PROBABILITY = 0.85


class MovePlateExpert(GraspingExpert):
    """Moves the plate of ``MovePlate`` to the target drainer."""

    tasks = ("MovePlate",)
    pace: ClassVar[dict[str, float]] = {"MovePlate": 1.6}

    def plan(self) -> Script:
        env = self.env
        (plate,) = env.plates
        start, target = env.props["drainer_start"], env.props["drainer_target"]
        near = LEFT if self.data.xpos[start.root_body_id][1] > 0.0 else RIGHT  # mostly the hand on the rack's side
        side = near if self.rng.random() < NEAR_HAND_PROBABILITY else 1 - near
        slot = target.slot_keys[int(self.rng.integers(len(target.slot_keys)))]
        self.choices["hands"] = [f"{plate}:{'left' if side == LEFT else 'right'}"]
        self.choices["slots"] = [slot]

        start_xy = self.data.xpos[start.root_body_id][:2].copy()
        target_xy = self.data.xpos[target.root_body_id][:2].copy()
        yield from self.wait(self.human.reaction())
        base = self.commanded_base()
        lateral = 0.18 if side == LEFT else -0.18
        stance = np.array(
            [TABLE_FRONT - TABLE_CLEARANCE - abs(self.human.jitter(0.02)), start_xy[1] - lateral + self.human.jitter(0.03),
             base[2], self.human.jitter(0.05)]
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

    def take_plate(self, side: int, plate: str) -> Script:
        body = self.env.props[plate].root_body_id

        def aim() -> tuple[np.ndarray, np.ndarray]:
            frame = self.data.xmat[body].reshape(3, 3)
            normal = frame[:, 2]  # the plate's face normal: the fingers close along it
            centre = self.data.xpos[body] + normal * self.env.props[plate].height / 2
            up = np.array([0.0, 0.0, 1.0]) - normal * normal[2]
            up /= np.linalg.norm(up)
            along = np.cross(normal, up)
            radius = self.env.props[plate].radius
            point = centre + up * (radius - RIM_DEPTH) + along * self.human.jitter(0.012)
            return point, normal

        if not (yield from self.pick(side, aim, lift=LIFT + abs(self.human.jitter(0.01)), prop=plate)):
            self.note(f"gave up on {plate}")
            while True:
                yield
        self.hold_hand(side, HOLD)

    def put_in_slot(self, side: int, plate: str, slot: str) -> Script:
        """Lower the plate into ``slot`` standing as it stood in its first slot."""
        env = self.env
        # a plate stands in a slot as the task puts it in at the start (the drainers are not rotated)
        goal = self.site_of(env.props["drainer_target"], slot) + PLATE_IN_SLOT_OFFSET
        yield from self.place(side, goal, prop=plate, level=False, orientation=self._initial_rotation[plate], feel=False)

    def site_of(self, prop, key: str) -> np.ndarray:
        return self.data.site_xpos[prop.site_id(key)].copy()

    def start(self) -> None:
        super().start()
        self._initial_rotation = {
            p: self.data.xmat[self.env.props[p].root_body_id].reshape(3, 3).copy() for p in self.env.plates
        }


__all__ = ["MovePlateExpert"]
