"""StackBlocks demonstrator: carry the three blocks round the tables and stack them on the pad.

The blocks lie on the near table, the pad on the far one, out of reach from the near
side: a person takes two blocks, one in each hand, walks round the tables to the far
end, stacks them on the pad, goes back for the third and puts it on top.

Choices drawn per demo: which block waits for the second trip (the other two go to the
hand on their side), which hand takes its block first, which of the two is put down
first, which hand takes the last block (the one on its side), and which side of the
tables the robot walks round (mostly the side nearer the pad).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.manipulation import TABLE_TOP
from bigym.experts.expert import LEFT, RIGHT, SIDE_NAMES, Script
from bigym.experts.grasping import HOLD, TABLE_CLEARANCE, GraspingExpert

NEAR_TABLE_FRONT = 0.4  # x of the near table's front edge
FAR_TABLE_BACK = 1.7  # x of the far table's back edge
TABLE_HALF_WIDTH = 0.6
#: how far the pelvis keeps from the side of the tables it walks past
WALK_CLEARANCE = 0.38
PAD_THICKNESS = 0.002


class StackBlocksExpert(GraspingExpert):
    """Stacks the three blocks of ``StackBlocks`` on the target pad."""

    tasks = ("StackBlocks",)
    pace: ClassVar[dict[str, float]] = {"StackBlocks": 1.2}

    def plan(self) -> Script:
        env = self.env
        blocks = list(env.BLOCKS)
        positions = {name: self.site_free(name) for name in blocks}
        pad = self.data.xpos[env.props["target_pad"].root_body_id].copy()
        size = env.props[blocks[0]].size
        later = blocks[int(self.rng.integers(len(blocks)))]
        first_two = [b for b in blocks if b != later]
        # the block further left goes to the left hand
        first_two.sort(key=lambda b: -positions[b][1])
        hands = dict(zip(first_two, (LEFT, RIGHT), strict=True))
        pick_order = first_two if self.rng.random() < 0.5 else first_two[::-1]
        place_order = first_two if self.rng.random() < 0.5 else first_two[::-1]
        side_sign = float(np.sign(pad[1]) or 1.0)
        if self.rng.random() < 0.3:
            side_sign = -side_sign
        self.choices["order"] = [*pick_order, later]
        self.choices["placed"] = [*place_order, later]
        self.choices["hands"] = [f"{b}:{SIDE_NAMES[hands[b]]}" for b in first_two]
        self.choices["route"] = "left" if side_sign > 0 else "right"

        yield from self.wait(self.human.reaction())
        for name in pick_order:
            yield from self.take_block(hands[name], name)
        yield from self.walk_round(side_sign, to_far=True, carrying=(LEFT, RIGHT), pad=pad)
        self.stack: list[str] = []
        for name in place_order:
            yield from self.put_on_stack(hands[name], name, pad, size)
            self.relax_arm(hands[name])
        yield from self.walk_round(side_sign, to_far=False, carrying=(), pad=pad)
        side = LEFT if self.site_free(later)[1] > self.base_pose()[1] else RIGHT
        self.choices["hands"].append(f"{later}:{SIDE_NAMES[side]}")
        yield from self.take_block(side, later)
        yield from self.walk_round(side_sign, to_far=True, carrying=(side,), pad=pad)
        yield from self.put_on_stack(side, later, pad, size)
        self.relax_arm(side)
        while True:
            yield

    # ------------------------------------------------------------------ steps
    def site_free(self, name: str) -> np.ndarray:
        """Centre of a free prop (its root body) in the measured state."""
        return self.data.xpos[self.env.props[name].root_body_id].copy()

    def block_yaw(self, name: str) -> float:
        frame = self.data.xmat[self.env.props[name].root_body_id].reshape(3, 3)
        return float(np.arctan2(frame[1, 0], frame[0, 0]))

    def take_block(self, side: int, name: str) -> Script:
        """Stand at the near table in line with the block and take it from above."""
        block = self.site_free(name)
        held = [s for s in (LEFT, RIGHT) if s != side and self.grip[s] > 0.5]
        base = self.commanded_base()
        lateral = 0.18 if side == LEFT else -0.18
        # face the table, turned just enough that the hand closes across two faces comfortably
        _, turn = self.face_closing(side, self.block_yaw(name), facing_yaw=0.0)
        yaw = turn + self.human.jitter(0.04)
        stance = np.array(
            [
                NEAR_TABLE_FRONT - TABLE_CLEARANCE - abs(self.human.jitter(0.02)),
                block[1] - lateral * np.cos(yaw) + self.human.jitter(0.04),  # the shoulder in line with the block
                base[2],
                yaw,
            ]
        )
        if np.linalg.norm(stance[:2] - base[:2]) > 0.03 or abs(stance[3] - base[3]) > 0.05:
            yield from self.walk([stance], carrying=held)

        def aim() -> tuple[np.ndarray, np.ndarray]:
            closing, _ = self.face_closing(side, self.block_yaw(name))
            return self.site_free(name) + self.human.jitter(0.002, 3) * np.array([1.0, 1.0, 0.0]), closing

        if not (yield from self.pick(side, aim, lift=0.1 + abs(self.human.jitter(0.02)))):
            self.note(f"gave up on {name}")
            while True:  # the demo fails and is not kept
                yield
        self.hold_hand(side, HOLD)

    def walk_round(self, sign: float, to_far: bool, carrying: tuple[int, ...], pad: np.ndarray) -> Script:
        """Walk past the tables' ``sign`` side, to the far end facing the pad or back."""
        base = self.commanded_base()
        z = base[2]
        lane = sign * (TABLE_HALF_WIDTH + WALK_CLEARANCE + abs(self.human.jitter(0.04)))
        near_x = NEAR_TABLE_FRONT - TABLE_CLEARANCE - 0.05
        far_x = FAR_TABLE_BACK + WALK_CLEARANCE
        if to_far:
            route = [
                (near_x + self.human.jitter(0.03), lane, z, sign * 0.3 * np.pi),
                (far_x + self.human.jitter(0.03), lane, z, sign * 0.6 * np.pi),
                (FAR_TABLE_BACK + TABLE_CLEARANCE + abs(self.human.jitter(0.02)), pad[1] + self.human.jitter(0.03), z,
                 sign * np.pi + self.human.jitter(self.style.stance_yaw_spread * 0.5)),
            ]  # fmt: skip
        else:
            route = [
                (far_x + self.human.jitter(0.03), lane, z, sign * 0.8 * np.pi),
                (near_x + self.human.jitter(0.03), lane, z, sign * 0.4 * np.pi),
                (near_x, 0.5 * lane, z, 0.0),
            ]
        yield from self.walk(route, carrying=carrying)

    def put_on_stack(self, side: int, name: str, pad: np.ndarray, size: float) -> Script:
        """Step to where this hand reaches the spot as it reached the block when it took
        it, and put the block on the pad, or on the block placed last (as it lies now)."""
        body = self.env.props[name].root_body_id
        centre_z = TABLE_TOP + PAD_THICKNESS + size * (len(self.stack) + 0.5)
        under = self.site_free(self.stack[-1]) if self.stack else pad
        target = np.array([under[0], under[1], centre_z]) + self.human.jitter(0.003, 3) * np.array([1.0, 1.0, 0.0])
        base = self.commanded_base()
        stance = self.stance_for(side, target + self.held_offset(side, body), base[3])
        stance[0] = max(stance[0], FAR_TABLE_BACK + TABLE_CLEARANCE)  # never into the table
        stance[2] = base[2]
        carrying = [s for s in (LEFT, RIGHT) if self.grip[s] > 0.5]
        if np.linalg.norm(stance[:2] - base[:2]) > 0.02:
            yield from self.walk([stance], carrying=carrying)
        yield from self.place(side, target, prop=name)
        self.stack.append(name)


__all__ = ["StackBlocksExpert"]
