"""Groceries demonstrator for the wall shelf (scene counter_base_wall_2x2): put the four
groceries from the counter onto the open shelf beside the wall cabinet
(``StoreGroceriesUpper``).

What a person does: takes the items two at a time, one in each hand, and puts both on the
shelf at once. Crouched at the counter, the right hand takes the item nearest the shelf
(lowest y) and lifts it well clear of the counter; the body steps along the counter, away
from the shelf, to the next item, which the left hand takes. Holding both, the person
stands up and steps back as the arms come up, so that the items rise in front of the
shelf's edge (not under it), steps in with the arms held out level, puts both down side
by side, draws the hands back out, steps back and lowers the arms; then the next two.

Why this order: a held item goes where the body goes. The right hand's item moves away
from the shelf side while the left hand takes its item further along, over a counter
that has nothing more on that side; the pair nearest the shelf goes first, so the second
pair's walk sweeps over the empty end of the counter too.

Why the arms come down in front, in two steps: the 5-joint arm holds an item level only
with the forearm pointing the way it grasped it, so an item at shelf height is held out
at nearly arm's length. Brought straight back to the hip in the body's frame, the arm
passed near its singular posture and the IK threw the body about (down to a 0.4 m pelvis);
relaxed in joint space straight from shelf height, the arm swung forward through the
items on the shelf. So the hands first come down to the chest while the body steps back,
then the arms relax.

Choices drawn per demo: which pair of places on the shelf the first two items take (the
inner or the outer), which hand lets go first, where the body stands at the counter, how
high the fingers close, the timing, and every path's via-points. The items' order and
hands follow from where they stand (see above).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.experts.expert import FREE, LEFT, RIGHT, SIDE_NAMES, Script, together
from bigym.experts.geometry import yaw_matrix
from bigym.experts.grasping import HOLD, TABLE_CLEARANCE, from_base, to_base
from bigym.experts.groceries import COUNTER_CROUCH, FRONT, HAND_OFFSET, GroceriesExpert

#: top of the open shelf's board, and the x the items' middles are put down at (its front
#: edge is at 0.78, its back at 1.1)
SHELF_TOP = 1.47
SHELF_X = 0.88
#: where along the shelf (y) the items go: two pairs of places, (left hand, right hand),
#: one pair 0.15 m further along than the other, so the second pair's items go down
#: between the first pair's
PLACES = ((-0.38, -0.68), (-0.53, -0.83))
#: pelvis height standing at the shelf
STAND = 1.03
#: how far (m) ahead of the pelvis the pinch point is when an item is taken from the
#: counter (the body stands back as far, turned as the grasp needs)
TAKE_AHEAD = 0.38
#: how far (m) the first item is lifted off the counter, and drawn back, while the other
#: hand takes the second (its base then clears the counter whatever the body does)
FIRST_LIFT = 0.1
FIRST_BACK = 0.05
#: the items rise at this x (m, the pinch point), in front of the shelf's edge; then they
#: go in this far (m) over the board before they are lowered
OUT_X = 0.56
CLEAR = 0.025
#: how far (m) the pelvis stays behind the pinch point at shelf height (the arm held out)
REACH = 0.68
#: how far (m) the body steps back from the shelf as the arms come down
BACK_AWAY = 0.15
#: where (body frame, m) the hands come down to before the arms relax: in front of the
#: chest, clear of the counter
ARMS_DOWN = np.array([0.3, 0.25, 0.05])


class UpperGroceriesExpert(GroceriesExpert):
    """Puts the groceries of ``StoreGroceriesUpper`` on the open shelf, two at a time."""

    tasks = ("StoreGroceriesUpper",)
    pace: ClassVar[dict[str, float]] = {"StoreGroceriesUpper": 1.2}
    # not measured here, and its shipped demos were recorded without (see GroceriesExpert)
    grippers_off_torso = False

    def plan(self) -> Script:
        yield from self.wait(self.human.reaction())
        order = sorted(self.env.chosen, key=self.item_y)  # nearest the shelf first
        self.choices["order"] = order
        inner_first = self.rng.random() < 0.5
        self.choices["first places"] = "inner" if inner_first else "outer"
        places = PLACES if inner_first else PLACES[::-1]
        self.choices["hands"] = []
        self.choices["first let go"] = []
        for k in range(2):
            right, left = order[2 * k], order[2 * k + 1]
            self.choices["hands"] += [f"{right}:right", f"{left}:left"]
            yield from self.take_item(RIGHT, right)
            p, r = self.hand_pose(RIGHT)
            lifted = p + np.array([-FIRST_BACK, 0.0, FIRST_LIFT])
            yield from self.until(self.move_hand(RIGHT, lifted, r, HOLD, spread=0.0, tremor=0.5))
            yield from self.take_item(LEFT, left, holding=(RIGHT,))
            yield from self.onto_shelf({LEFT: left, RIGHT: right}, places[k])
            yield from self.arms_down()
        while True:
            yield

    def item_stance(self, side: int, item: str) -> np.ndarray:
        """Behind the item along the direction the body faces for the grasp (turned, the
        hand's side of the body swings forward), no nearer the counter than the lower
        cupboard's expert stands."""
        position = self.data.xpos[self.env.props[item].root_body_id]
        _, turn = self.closing(side, item)
        yaw = turn + self.human.jitter(0.04)
        lateral = HAND_OFFSET if side == LEFT else -HAND_OFFSET
        reach = yaw_matrix(yaw) @ np.array([TAKE_AHEAD + self.human.jitter(0.02), lateral, 0.0])
        return np.array(
            [
                min(float(position[0] - reach[0]), FRONT - TABLE_CLEARANCE - 0.02 - abs(self.human.jitter(0.02))),
                float(position[1] - reach[1]) + self.human.jitter(0.03),
                COUNTER_CROUCH + self.human.jitter(0.02),
                yaw,
            ]
        )

    def onto_shelf(self, items: dict[int, str], places: tuple[float, float]) -> Script:
        """Stand up and step back as the arms lift both items in front of the shelf's edge,
        step in with them held out over the board, and put both down, one hand a moment
        after the other."""
        self.note("rise")
        base = self.base_pose()
        across = {LEFT: places[0], RIGHT: places[1]}
        offsets = {side: self.held_offset(side, self.env.props[item].root_body_id) for side, item in items.items()}
        rise = np.array(
            [
                OUT_X - REACH + self.human.jitter(0.02),
                0.5 * (places[0] + places[1]) + self.human.jitter(0.02),
                STAND,
                self.human.jitter(0.03),
            ]
        )
        end = yield from self.walk([rise], from_plan=True, wait=False)
        for side in items:
            _, r = self.hand_pose(side)
            goal = np.array([OUT_X, across[side], SHELF_TOP + CLEAR + 0.02]) + offsets[side]
            local, _ = to_base(rise, goal, r)
            self.move_hand_with_body(side, local, HOLD, base, duration=end - self.time)
        yield from self.until(end)
        self.note("in")
        x = SHELF_X + self.human.jitter(0.015)
        stand = rise.copy()
        stand[0] = x - REACH + self.human.jitter(0.02)
        yield from self.walk([stand], carrying=(LEFT, RIGHT), from_plan=True)
        first = LEFT if self.rng.random() < 0.5 else RIGHT
        self.choices["first let go"].append(SIDE_NAMES[first])
        delay = float(self.rng.uniform(0.1, 0.5))

        def put(side: int) -> Script:
            spot = np.array([x, across[side] + self.human.jitter(0.01), SHELF_TOP])
            yield from self.place(side, spot, prop=items[side], level=True, headroom=0.02)

        yield from together(put(first), self.after(delay, put(1 - first)))

    def arms_down(self) -> Script:
        """Draw both hands straight back out over the shelf's edge, bring them down in
        front of the chest as the body steps back, and relax the arms."""
        ends = []
        for side in (LEFT, RIGHT):
            p, r = self.hand_pose(side)
            ends.append(self.move_hand(side, np.array([OUT_X + 0.06, p[1], p[2]]), r, FREE, spread=0.0))
        yield from self.until(max(ends))
        self.note("arms down")
        base = self.base_pose() - np.array([BACK_AWAY + abs(self.human.jitter(0.02)), 0.0, 0.0, 0.0])
        ends = [self.move_base(base)]
        for side in (LEFT, RIGHT):
            _, r = self.hand_pose(side)
            local = ARMS_DOWN * np.array([1.0, 1.0 if side == LEFT else -1.0, 1.0]) + self.human.jitter(0.02, 3)
            ends.append(self.move_hand(side, from_base(base, local, None)[0], r, FREE, spread=0.2))
        yield from self.until(max(ends))
        yield from self.until(max(self.relax_arm(side, joint_space=True) for side in (LEFT, RIGHT)))


__all__ = ["UpperGroceriesExpert"]
