"""TakeCups demonstrator (scene counter_base_wall_1x1): open the glass wall cabinet and take
the two mugs off its bottom shelf onto the counter.

What a person does: stands in front of the cabinet and opens both glass doors, one hand
each, the second once the first door is pushed open (the mugs stand across the whole
shelf, often one right behind where the doors meet); draws both hands straight back
from the doors, steps in and raises them between the open doors to the handles' height,
reaches in and takes each mug by the top of its handle's upright bar, both at once (when
the handles are close, or one is further in, one mug is taken first and moved aside or
forward along the shelf to make room for the other hand), lifts them off the shelf, steps back until they are out of
the cabinet, drawing them in towards the middle, crouches with them held out in front
until they are just over the counter, and puts both down, one a moment after the other,
each lowered until it rests upright, let go.

Why the body stands back to reach in, and steps back and crouches to bring the mugs out
and down: the H1's wrist only rolls, so the hand points where the forearm does and is
level (comes at an upright bar level, and holds the mug upright) only with the arm nearly
straight out; so each hand comes at its handle along the line from its shoulder, the
arms stay straight and the body does the moving, the mugs coming down no faster than the
body does. The hand slides in round the handle slowly: faster, the stretched-out arm
lagged behind its path and the fingers caught the handle's side and spun the mug away. Why the hands keep between the doors' free edges and
leave the doors straight back: a hand or a mug that brushed an open door's edge from
outside swung it shut.

Choices drawn per demo: which door is opened first and the second hand's delay, which
hand takes its mug first (or which mug is moved aside), which mug is put down first,
where the body stands, the timing, and every path's via-points; where each mug stands
on the counter follows from where it was on the shelf.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.pick_and_place import COUNTER_TOP
from bigym.experts.expert import ALIGN_BAR, FREE, LEFT, RIGHT, SIDE_NAMES, Script, together
from bigym.experts.grasping import HOLD, to_base
from bigym.experts.put_cups import DOORS, GRIP_ABOVE, PutCupsExpert

MUGS = ("mug_1", "mug_2")
#: how much faster than usual the demonstrator works: 26 s for two doors and two mugs
PACE = 1.5
#: a door within this (normalised) of fully open is open enough (a door left further
#: closed caught the hand reaching for the mug beside it)
DOOR_MARGIN = 0.1
#: the doors are opened from one place, one hand each, the second hand starting this long
#: (s) after the first: once the first door is pushed open (sooner, the second arm knocked
#: the half-open first door shut in 4 of 20 trials; one door after the other, each from
#: its own place, takes 3-4 s longer)
SECOND_DOOR_AFTER = (3.0, 3.5)
#: how far (m) in front of the further handle (x) the pelvis stands to take the mugs,
#: standing
REACH_IN = 0.70
STANDING = 1.03
#: how far (m) to the side of the pelvis the shoulders are
SHOULDER_HALF_WIDTH = 0.21
#: a hand that missed its handle tries again, the body first stepping in by as much as
#: the fingers were short of it, at most this far (m)
MAX_STEP_IN = 0.06
#: the hands are first drawn back from the doors to this x, in front of the open doors'
#: free edges
CLEAR_OF_DOORS = 0.45
#: the hand reaching for a mug comes up to the handle's height between the open doors,
#: this far (m) in front of the pelvis (a hand held nearer, level, pushed the body back),
#: then this far (m) in front of the handle (from below, it caught on the shelf's front
#: edge)
CLEAR_REACH = 0.4
FRONT = 0.25
#: the hand comes in no further out (|y|, m) than this past the doors' free edges: the
#: fingers, shaped to the thin handle (closed this far), stay clear of them
INSIDE_DOORS = 0.12
OPENING = 0.5
#: the hand slides in round the handle over this long at least (s): faster, the arm
#: stretched out lagged behind and the fingers caught the handle's side
INSERT_TIME = 0.7
#: the two hands come up between the doors at least this far (m) apart
HANDS_APART = 0.16
#: handles at least this far apart (y, m) are taken with both hands at once; nearer, one
#: mug is taken first and moved aside along the shelf, its middle no further than
#: SHELF_SPAN from the shelf's middle
SIDE_BY_SIDE = 0.2
SHELF_SPAN = 0.21
#: handles whose depths (x) differ by more than this (m) are taken one after the other,
#: the further one first, brought forward to the other's depth
ONE_DEPTH = 0.035
#: how far (m) the mugs are lifted off the shelf before they come out
LIFT = 0.03
#: how far (m) the pelvis steps back with the mugs (they come out of the cabinet), and how
#: low it then crouches
STEP_BACK = 0.28
#: the mugs come out no further (|y|, m) from the cabinet's middle than this (a hand out
#: there caught on an open door), at least this far apart
OUT_OF_DOORS = 0.13
MUG_SPACING = 0.12
CROUCH = 0.65
#: how far (m) over the counter the mugs' bases come as the body crouches
OVER_COUNTER = 0.05
#: a mug that touches the counter is let go once it is within this (rad) of upright
COUNTER_TILT = np.deg2rad(20.0)


class TakeCupsExpert(PutCupsExpert):
    """Opens the glass wall cabinet and takes the two mugs of ``TakeCups`` onto the counter."""

    tasks = ("TakeCups",)
    pace: ClassVar[dict[str, float]] = {"TakeCups": PACE}

    def plan(self) -> Script:
        centres = {mug: self.data.xpos[self.env.props[mug].root_body_id].copy() for mug in MUGS}
        # the mug further along +y is the left hand's
        left_mug, right_mug = sorted(MUGS, key=lambda mug: -centres[mug][1])
        mug_of = {LEFT: left_mug, RIGHT: right_mug}
        yield from self.wait(self.human.reaction())
        yield from self.wall_doors(
            list(DOORS), 1.0, margin=DOOR_MARGIN, both_hands=1.0, second_after=SECOND_DOOR_AFTER, relax=False
        )
        yield from self.back_from_doors()
        yield from self.take_from_shelf(mug_of)
        yield from self.bring_out(mug_of)
        # both mugs are put down at once, one hand a moment after the other
        first = LEFT if self.rng.random() < 0.5 else RIGHT
        self.choices["first put down"] = SIDE_NAMES[first]
        delay = float(self.rng.uniform(0.1, 0.6))
        yield from together(
            self.put_on_counter(first, mug_of[first]),
            self.after(delay, self.put_on_counter(1 - first, mug_of[1 - first])),
        )
        while True:
            yield

    def back_from_doors(self) -> Script:
        """Draw both hands straight back from the doors they pushed open, to in front of the
        doors' free edges (a hand that pushed a door open may be on either side of it; the
        open door lies along the way back)."""
        ends = []
        for side in (LEFT, RIGHT):
            p, r = self.hand_pose(side)
            if p[0] > CLEAR_OF_DOORS:
                goal = np.array([CLEAR_OF_DOORS - abs(self.human.jitter(0.03)), p[1], p[2]])
                ends.append(self.move_hand(side, goal, r, FREE, spread=0.0, tremor=0.5))
        yield from self.until(max(ends, default=self.time))

    def put_on_counter(self, side: int, mug: str) -> Script:
        """Put the held mug down upright where it hangs over the counter, give or take."""
        if not self.env.held(mug):
            return
        target = self.data.xpos[self.env.props[mug].root_body_id].copy() + self.human.jitter(0.01, 3)
        target[2] = COUNTER_TOP
        yield from self.put_down(
            side,
            mug,
            target,
            self.env.target_mask,
            feel_all_the_way=True,
            upright=True,
            looks=1,
            seen_off=0.02,
            tilt=COUNTER_TILT,
        )

    def take_from_shelf(self, mug_of: dict[int, str]) -> Script:
        """Stand back from the cabinet between the mugs and take both handles, one hand a
        moment after the other (a hand that missed tries once more); lift both a little."""
        handles = {side: self.site(mug, "handle") + np.array([0.0, 0.0, GRIP_ABOVE]) for side, mug in mug_of.items()}
        stance = (
            max(h[0] for h in handles.values()) - REACH_IN + self.human.jitter(0.015),
            float(np.mean([h[1] for h in handles.values()])) + self.human.jitter(0.02),
            STANDING,
            self.human.jitter(0.04),
        )
        # the hands come up in front of the chest, inside the open doors, as the body steps
        # in: a hand left beside the body (the one that pushed a door open is outside it)
        # swept the door shut as the body moved
        ends = [self.move_base(stance)]
        clear = self.apart({side: float(h[1]) for side, h in handles.items()}, INSIDE_DOORS, HANDS_APART)
        for side in (LEFT, RIGHT):
            up = handles[side][2] + 0.02 + abs(self.human.jitter(0.02))
            point = np.array(
                [stance[0] + CLEAR_REACH + self.human.jitter(0.03), clear[side] + self.human.jitter(0.01), up]
            )
            # (the hand turns as it likes: held level this close to the body, the arm pushed
            # the body back)
            ends.append(self.move_hand(side, point, None, FREE, spread=0.3))
        yield from self.until(max(ends))
        deeper = float(handles[LEFT][0] - handles[RIGHT][0])  # how much further in the left one is
        if handles[LEFT][1] - handles[RIGHT][1] >= SIDE_BY_SIDE and abs(deeper) <= ONE_DEPTH:
            first = LEFT if self.rng.random() < 0.5 else RIGHT
            self.choices["first taken"] = SIDE_NAMES[first]
            delay = float(self.rng.uniform(0.1, 0.5))
            yield from together(
                self.reach_in(first, mug_of[first]),
                self.after(delay, self.reach_in(1 - first, mug_of[1 - first])),
            )
        else:
            # one mug first, moved out of the other hand's way: the further one (both arms
            # nearly straight, the body stood too far back for it, or too near for the
            # other), else, the handles too close for both hands at once, the one with
            # more room beside it
            if abs(deeper) > ONE_DEPTH:
                first = LEFT if deeper > 0 else RIGHT
            else:
                centre = {
                    side: float(self.data.xpos[self.env.props[mug].root_body_id][1]) for side, mug in mug_of.items()
                }
                first = LEFT if SHELF_SPAN - centre[LEFT] > centre[RIGHT] + SHELF_SPAN else RIGHT
            self.choices["first taken"] = SIDE_NAMES[first]
            yield from self.reach_in(first, mug_of[first])
            if self.env.held(mug_of[first]):
                yield from self.move_aside(first, mug_of[first], handles[1 - first])
            yield from self.reach_in(1 - first, mug_of[1 - first])
        for side in (first, 1 - first):
            if not self.env.held(mug_of[side]):
                # mostly the fingers closed short of the bar: the hand could not reach it
                # level from where the body stood; the body steps in by as much
                self.note(f"missed {mug_of[side]}")
                short = float(
                    self.site(mug_of[side], "handle")[0] - self.data.site_xpos[self.env.robot.pinch_site_ids[side]][0]
                )
                base = self.base_pose()
                step = float(np.clip(short, 0.0, MAX_STEP_IN)) + abs(self.human.jitter(0.01))
                self.move_base(base + np.array([step, 0.0, 0.0, 0.0]))
                yield from self.release(side, back=0.06, up=0.02)
                yield from self.take_handle_of(side, mug_of[side], OPENING, INSERT_TIME)
        ends = []
        for side in (LEFT, RIGHT):
            p, r = self.hand_pose(side)
            lift = LIFT + abs(self.human.jitter(0.01))
            ends.append(self.move_hand(side, p + np.array([0.0, 0.0, lift]), r, HOLD, duration=0.6, spread=0.0))
        yield from self.until(max(ends))

    def move_aside(self, side: int, mug: str, other_handle: np.ndarray) -> Script:
        """Lift the held mug a little and move it along the shelf away from the other mug's
        handle until the handles are ``SIDE_BY_SIDE`` apart (or it is at the end of the
        shelf), and forward to the other handle's depth, the body stepping back as much."""
        away = 1.0 if side == LEFT else -1.0
        centre = self.data.xpos[self.env.props[mug].root_body_id]
        handle = self.site(mug, "handle")
        wanted = other_handle[1] + away * (SIDE_BY_SIDE + abs(self.human.jitter(0.01)))
        across = 0.0
        if away * (wanted - handle[1]) > 0.0:
            across = float(np.clip(wanted - handle[1] + centre[1], -SHELF_SPAN, SHELF_SPAN) - centre[1])
        back = min(0.0, float(other_handle[0] - handle[0]))
        p, r = self.hand_pose(side)
        goal = p + np.array([back, across, LIFT + abs(self.human.jitter(0.01))])
        ends = [self.move_hand(side, goal, r, HOLD, spread=0.0, tremor=0.3)]
        if back < 0.0:
            ends.append(self.move_base(self.base_pose() + np.array([back, 0.0, 0.0, 0.0])))
        yield from self.until(max(ends))

    def handle_approach(self, side: int, mug: str) -> tuple[np.ndarray, np.ndarray]:
        """As PutCups', but the hand comes at the handle along the line from its shoulder
        (where the body is to stand): with the arm straight along it, the hand is level.
        (Turned towards the mug's middle instead, the fingers caught the handle's arm and
        spun the mug away.)"""
        handle = self.site(mug, "handle") + np.array([0.0, 0.0, GRIP_ABOVE])
        base = self.base_pose(self.time + 10.0)  # where the body is going to stand
        sign = 1.0 if side == LEFT else -1.0
        shoulder = base[:2] + SHOULDER_HALF_WIDTH * sign * np.array([-np.sin(base[3]), np.cos(base[3])])
        line = handle[:2] - shoulder
        line /= np.linalg.norm(line)
        return handle, np.array([line[0], line[1], 0.0])

    def reach_in(self, side: int, mug: str) -> Script:
        """From in front of the chest, bring the hand just in front of the handle at its
        height, then take it."""
        handle, level = self.handle_approach(side, mug)
        front = handle - level * FRONT
        front[2] = self.hand_pose(side)[0][2]
        rotation = self.bar_grasp_rotation(side, np.array([0.0, 0.0, 1.0]), level)
        self.grip[side] = OPENING
        yield from self.until(self.move_hand(side, front, rotation, ALIGN_BAR, spread=0.3))
        yield from self.take_handle_of(side, mug, OPENING, INSERT_TIME)

    def bring_out(self, mug_of: dict[int, str]) -> Script:
        """Step back with the mugs held out until they are out of the cabinet, drawing them
        in towards the middle (clear of the open doors), then crouch, bringing each mug down
        to just over its place on the counter (the arms stay nearly straight: the body does
        most of the lowering)."""
        self.note("bring out")
        base = self.base_pose()
        out = np.array(
            [base[0] - STEP_BACK - abs(self.human.jitter(0.02)), base[1] + self.human.jitter(0.02), base[2], base[3]]
        )
        across = self.apart(
            {side: float(self.data.xpos[self.env.props[mug].root_body_id][1]) for side, mug in mug_of.items()},
            OUT_OF_DOORS,
            MUG_SPACING,
        )
        end = yield from self.walk([out], from_plan=True, wait=False)
        for side, mug in mug_of.items():
            p, r = self.hand_pose(side)
            goal = p + np.array(
                [out[0] - base[0], across[side] - self.data.xpos[self.env.props[mug].root_body_id][1], 0.0]
            )
            local, _ = to_base(out, goal, r)
            self.move_hand_with_body(side, local, HOLD, base, duration=end - self.time)
        yield from self.until(end)
        low = out + np.array([0.0, 0.0, CROUCH - out[2] + self.human.jitter(0.02), self.human.jitter(0.04)])
        # the hands go down with the body, over the same time: the mugs come down no
        # faster than the body does
        end = yield from self.walk([low], from_plan=True, wait=False)
        for side, mug in mug_of.items():
            p, r = self.hand_pose(side)
            mug_at = self.data.xpos[self.env.props[mug].root_body_id]
            goal = p + np.array([0.0, 0.0, COUNTER_TOP + OVER_COUNTER - mug_at[2]]) + self.human.jitter(0.01, 3)
            local, _ = to_base(low, goal, r)
            self.move_hand_with_body(side, local, HOLD, out, duration=end - self.time)
        yield from self.until(end)

    def apart(self, across: dict[int, float], limit: float, spacing: float) -> dict[int, float]:
        """Places across (y) for the left and right hands' things, now at ``across``: no
        further out than ``limit`` from the cabinet's middle, and ``spacing`` apart."""
        left = min(across[LEFT], limit)
        right = max(across[RIGHT], -limit)
        if left - right < spacing:
            middle = float(np.clip(0.5 * (left + right), spacing / 2 - limit, limit - spacing / 2))
            left, right = middle + spacing / 2, middle - spacing / 2
        return {LEFT: left, RIGHT: right}


__all__ = ["TakeCupsExpert"]
