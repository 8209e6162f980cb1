"""PutCups demonstrator (scene counter_base_wall_1x1): open the glass wall cabinet and put
the two mugs from the counter on its bottom shelf.

What a person does: opens one of the glass doors (pulls its handle, pushes it round), takes
both mugs by their handles at once, the fingers round the top of each handle's upright
bar, lifts them a little, stands up with them held in front of the cabinet, and puts them
on the open door's half of the shelf one after the other: raised in front of the cabinet
until the base clears the shelf's front edge, carried in over it, looked at, lowered until
it rests flat, let go.

Why one door: the task leaves 21 s, and a second door takes about 4 s more; the half of
the shelf behind one door takes the two mugs one behind the other (side by side, the two
hands did not fit between the side wall and the closed door's handle). Why the body
stands back from the counter, low, to take the mugs, and back again at the cabinet: the
H1's wrist only rolls, so the hand points where the forearm does, and the forearm is level
(the hand comes at an upright bar level) only with the arm nearly straight out. Why the
fingers close near the top of the bar and the hand comes from nearly straight ahead: the
pads then also touch the handle's upper arm (the mugs swung less in the fingers in
trials), and the arm gives that level hand without straining.

A mug held by its handle's bar still turns about the bar (the pads hardly resist a turn
about it), so where each mug hangs from its hand is looked at before it goes in: that
decides where across the half it goes (its hand passes between the side wall and the
closed door's handle) and how far in (the hand reaches no further than the straight arm).
The body stands on the open half's side of the cabinet's middle before the mugs go up
(from further across, the elbow of the hand reaching in at the back met the open door).
The hand on the open half's side puts its mug at the back, first; the other mug goes up
once that arm is on its way down. A mug is let go once it touches the shelf within 30
degrees of upright: the hand, reaching far in, does not hold it quite level, and it
stands up by itself; one that does not get down onto the shelf is brought nearer the body
and lowered again.

Why a mug goes up slowly (``CARRY_SPEED``): held by its handle's bar, a mug swung up and
across the body at the usual pace slipped out of the fingers. Why the arms keep a plane
inside the open door once the mugs are held: a door left 0.75-0.9 open stands out over
where the mugs go up, and the wrist caught on its lower edge (the mug went in under the
cabinet and fell). Why the empty hand is drawn straight out of the cabinet before the
arm relaxes: relaxing from inside, the hand met the open door (and the demo did not
replay at 50 Hz).

Choices drawn per demo: the door (and with it the half of the shelf and which mug goes
first), which hand takes its mug first, where the body stands, the timing, and every
path's via-points; where each mug stands follows from how it hangs.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.pick_and_place import WALL_SHELF_BOTTOM_TOP
from bigym.experts.cupboards import CupboardExpert
from bigym.experts.dishwasher_load_cups import LIFT, LIFT_SLOWNESS, CupLoadExpert
from bigym.experts.expert import FREE, LEFT, RIGHT, SIDE_NAMES, Script, together
from bigym.experts.grasping import HOLD, to_base

MUGS = ("mug_1", "mug_2")
CABINET = "wall_cabinet"
DOORS = ("door_right", "door_left")
#: x of the front edge of the counter the mugs stand on, and of the wall cabinet's front
COUNTER_FRONT = 0.58
CABINET_FRONT = 0.88
#: how much faster than usual the demonstrator works: the task leaves 21 s for a door and
#: two mugs
PACE = 1.5
#: how far short of fully open (normalised) the door may stay: it need only be out of the
#: arm's way, and a door pushed open often springs back off its stop to 0.8-0.9 (a second
#: push took 2 s of the task's 21)
DOOR_MARGIN = 0.25
#: how far (m) behind the counter's front the pelvis stands, and how low, while taking
#: the mugs
TAKE_DISTANCE = 0.6
TAKE_CROUCH = 0.65
#: how far (m) above the middle of the handle's bar the fingers close
GRIP_ABOVE = 0.0175
#: how far (rad) at most the hand turns from straight ahead towards the mug's middle
APPROACH_TURN = np.deg2rad(10.0)
#: where the pelvis stands to reach into the cabinet: this far (m) behind the counter's
#: front, standing up
CABINET_STANCE = 0.47
STANDING = 1.03
#: how far (m) at least the pelvis stands on the open half's side of the cabinet's middle
#: (y): from further across, the hand reaching in at the back of the half was 3 cm outside
#: its shoulder, and the elbow, out beside it, met the open door (the mug, let go short of
#: the shelf, fell)
STAND_INTO_HALF = 0.06
#: where the mugs' middles (x) and bases (z) are held, standing, before each goes up
HELD_X = 0.72
HELD_Z = 1.22
#: how far (m) in front of the cabinet's front the mug's middle is raised before it goes
#: in, and how far over the shelf its base then is
RAISE_BEFORE = 0.09
OVER_SHELF = 0.03
#: where (x) the mugs' middles go: one at the back of the shelf, the other in front of it,
#: at least MUG_GAP (m) apart; the hand reaches no further in (x) than BACK_REACH for the
#: back one (the body steps in) and HAND_REACH_X for the front one
BACK_X = 1.09
FRONT_X = 0.97
MUG_GAP = 0.11
BACK_REACH = 1.03
HAND_REACH_X = 0.92
#: across the open door's half of the shelf (distances (m) from the shelf's middle, y): the
#: window the hands go in through (clear of the side wall and of the closed door's handle),
#: where a mug may stand, and where it goes when it hangs straight
HAND_WINDOW = (0.1, 0.225)
SHELF_SPAN = (0.05, 0.232)
HALF_MIDDLE = 0.16
#: how many times at most a mug is looked at and moved over its place, and how far off (m)
#: it must be seen to be moved (the shelf leaves room to spare)
SHELF_LOOKS = 1
SHELF_SEEN_OFF = 0.015
#: a mug that touches the shelf is let go once it is within this (rad) of upright: it
#: stands up by itself (the hand, reaching far in, does not hold it quite level)
SHELF_TILT = np.deg2rad(30.0)
#: how far (m) nearer the body a mug that did not get down onto the shelf is brought
#: before it is lowered again: a hand reaching far in, the arm nearly straight, stopped
#: 4-6 cm above the shelf, and the mug, let go there, fell
AGAIN_NEARER = 0.05
#: how much of the first arm's way down (share) the other mug waits for before it goes up
RELAX_HEAD_START = 0.3
#: the pelvis keeps this far (m) behind the counter's front
BASE_CLEARANCE = 0.18
#: how fast (m/s, on average) at most a mug is raised and carried to in front of its
#: place: held by the handle's bar, a mug swung up and across the body at the usual pace
#: (0.6-0.9 m/s at the peak) slipped out of the fingers (and fell on the other)
CARRY_SPEED = 0.3
#: how far (m) the arms keep from the open door's inner face once the mugs are held: the
#: wrist's gripper, raising its mug in front of a door left 0.75-0.9 open, caught on the
#: door's lower edge (and the mug went in under the cabinet, and fell)
DOOR_ARM_CLEARANCE = 0.08
#: how far (m) in front of the cabinet the hand is drawn back, level, after letting a mug
#: go, before the arm relaxes: an arm relaxing straight from inside the cabinet met the
#: open door with its hand (and the demo did not replay at 50 Hz)
WITHDRAW = 0.1


class PutCupsExpert(CupLoadExpert, CupboardExpert):
    """Opens the glass wall cabinet and puts the two mugs of ``PutCups`` on its shelf."""

    tasks = ("PutCups",)
    pace: ClassVar[dict[str, float]] = {"PutCups": PACE}

    def plan(self) -> Script:
        centres = {mug: self.data.xpos[self.env.props[mug].root_body_id].copy() for mug in MUGS}
        # the mug further along +y is the left hand's
        left_mug, right_mug = sorted(MUGS, key=lambda mug: -centres[mug][1])
        mug_of = {LEFT: left_mug, RIGHT: right_mug}
        yield from self.wait(self.human.reaction())
        # one door: the mugs both go on its half of the shelf (two doors take too long)
        door = DOORS[int(self.rng.integers(2))]
        half = 1.0 if door == "door_right" else -1.0  # the half's side (y) of the shelf
        door_hand = self.door_side(CABINET, door)
        self._note_hand(f"{CABINET}/{door}", door_hand)
        yield from self.door(door_hand, CABINET, door, 1.0, margin=DOOR_MARGIN)
        yield from self.take_mugs(mug_of)
        # the door may stand a little short of fully open, its lower edge out over where the
        # mugs go up in front of the cabinet
        self.keep_arms_clear_of_open_door(CABINET, door, DOOR_ARM_CLEARANCE)
        yield from self.stand_at_cabinet(mug_of, half)
        # the hand on the open half's side puts its mug at the back of the half, first; the
        # other one's goes in front of it
        back = LEFT if half > 0 else RIGHT
        order = [side for side in (back, 1 - back) if self.env.held(mug_of[side])]
        if order:
            self.choices["first put away"] = SIDE_NAMES[order[0]]
        front_end = FRONT_X
        for place, side in zip(("back", "front"), order):
            mug = mug_of[side]
            if place == "back":
                yield from self.put_on_shelf(side, mug, half, BACK_X, BACK_REACH, relax=False)
                # the arm comes down out of the way before the other mug goes up past it
                relaxed = self.relax_arm(side)
                yield from self.until(self.time + RELAX_HEAD_START * (relaxed - self.time))
                # the front mug keeps clear of where the back one stands
                front_end = min(FRONT_X, float(self.data.xpos[self.env.props[mug].root_body_id][0]) - MUG_GAP)
            else:
                yield from self.put_on_shelf(side, mug, half, front_end, HAND_REACH_X)
        while True:
            yield

    def hanging(self, side: int, mug: str) -> np.ndarray:
        """Where the hand is relative to the middle of the mug it holds (m, world axes)."""
        p, _ = self.hand_pose(side)
        return p - self.data.xpos[self.env.props[mug].root_body_id]

    def take_mugs(self, mug_of: dict[int, str]) -> Script:
        """Crouch in front of the counter between the mugs and take both handles, one hand
        a moment after the other; a hand that missed its handle tries once more; lift both
        mugs a little."""
        handles = {side: self.site(mug, "handle") + np.array([0.0, 0.0, GRIP_ABOVE]) for side, mug in mug_of.items()}
        stance = (
            COUNTER_FRONT - TAKE_DISTANCE - abs(self.human.jitter(0.02)),
            float(np.mean([h[1] for h in handles.values()])) + self.human.jitter(0.02),
            TAKE_CROUCH + self.human.jitter(0.02),
            self.human.jitter(0.05),
        )
        self.move_base(stance)
        first = LEFT if self.rng.random() < 0.5 else RIGHT
        self.choices["first taken"] = SIDE_NAMES[first]
        delay = float(self.rng.uniform(0.1, 0.5))
        yield from together(
            self.take_handle_of(first, mug_of[first]),
            self.after(delay, self.take_handle_of(1 - first, mug_of[1 - first])),
        )
        for side in (first, 1 - first):
            if not self.env.held(mug_of[side]):
                self.note(f"missed {mug_of[side]}")  # the fingers closed beside the handle
                yield from self.release(side, back=0.06, up=0.03)
                yield from self.take_handle_of(side, mug_of[side])
        ends = []
        for side in (LEFT, RIGHT):  # gently: the mugs hang off-centre
            p, r = self.hand_pose(side)
            lift = LIFT + abs(self.human.jitter(0.02))
            duration = self.human.duration(lift, 0.02, minimum=0.6) * LIFT_SLOWNESS
            ends.append(self.move_hand(side, p + np.array([0.0, 0.0, lift]), r, HOLD, duration=duration, spread=0.0))
        yield from self.until(max(ends))

    def take_handle_of(self, side: int, mug: str, opening: float = 0.0, insert_time: float = 0.35) -> Script:
        """Reach the top of the mug's handle bar, the hand level and nearly straight ahead,
        and close the fingers on it; ``opening``: how far the fingers are closed beforehand
        (0: wide open), the hand shaped to the thin bar; ``insert_time``: the least time
        (s) the hand takes to slide in round it."""
        self.note(f"take {mug} {'LR'[side]}")
        handle, level = self.handle_approach(side, mug)
        yield from self.grasp_bar(
            side,
            handle,
            np.array([0.0, 0.0, 1.0]),
            level,
            depth=0.0,
            close=False,
            opening=opening,
            insert_time=insert_time,
        )
        yield from self.settle(side, handle, 0.008, 0.5)
        yield from self.set_grip(side, 1.0)

    def handle_approach(self, side: int, mug: str) -> tuple[np.ndarray, np.ndarray]:
        """Where ``side``'s fingers close on the mug's handle (near the top of its bar), and
        the level direction the hand comes at it from."""
        handle = self.site(mug, "handle") + np.array([0.0, 0.0, GRIP_ABOVE])
        radial = self.data.xpos[self.env.props[mug].root_body_id] - handle
        # the arm's five joints give a level hand only about as it points from the body:
        # the hand comes at the bar from nearly straight ahead, not through the mug's middle
        forward = self.base_pose()[3]
        turn = np.clip(np.arctan2(radial[1], radial[0]) - forward, -APPROACH_TURN, APPROACH_TURN)
        return handle, np.array([np.cos(forward + turn), np.sin(forward + turn), 0.0])

    def stand_at_cabinet(self, mug_of: dict[int, str], half: float) -> Script:
        """Stand up, bringing the held mugs up in front of the cabinet (not under it: they
        go up into it from there), at least ``STAND_INTO_HALF`` on the open ``half``'s side
        of the cabinet's middle."""
        self.note("stand at cabinet")
        base = self.base_pose()
        across = base[1] + self.human.jitter(0.02)
        if half * across < STAND_INTO_HALF:
            across = half * (STAND_INTO_HALF + abs(self.human.jitter(0.02)))
        stance = np.array(
            [
                COUNTER_FRONT - CABINET_STANCE - abs(self.human.jitter(0.02)),
                across,
                STANDING + self.human.jitter(0.01),
                self.human.jitter(0.04),
            ]
        )
        ends = []
        for side, mug in mug_of.items():
            p, r = self.hand_pose(side)
            mug_at = self.data.xpos[self.env.props[mug].root_body_id]
            goal = p + np.array([HELD_X - mug_at[0], 0.0, HELD_Z - mug_at[2]]) + self.human.jitter(0.01, 3)
            local, _ = to_base(stance, goal, r)
            ends.append(self.move_hand_with_body(side, local, HOLD, base))
        yield from self.walk([stance], from_plan=True)
        yield from self.until(max(ends))
        # reaching into the cabinet, the body leans in, but the feet stay out of the counter
        self.keep_base_behind(np.array([COUNTER_FRONT, 0.0, 0.0]), np.array([1.0, 0.0, 0.0]), BASE_CLEARANCE)

    def put_on_shelf(self, side: int, mug: str, half: float, x: float, reach: float, relax: bool = True) -> Script:
        """Raise the mug in front of the cabinet over the shelf's height, carry it in and put
        it down at ``x`` (its middle; nearer, if the hand would have to reach beyond
        ``reach``) in the ``half`` (+1: +y) of the shelf behind the open door, the hand going
        in through the window between the side wall and the closed door; ``relax``: the arm
        relaxes afterwards."""
        self.note(f"put {mug} {'LR'[side]}")
        body = self.env.props[mug].root_body_id
        jitter = self.human.jitter(0.01, 2)

        def across() -> float:
            """Where across the half (y) the mug goes, given how it hangs from the hand now."""
            hand = half * float(self.hanging(side, mug)[1])
            start, end = max(SHELF_SPAN[0], HAND_WINDOW[0] - hand), min(SHELF_SPAN[1], HAND_WINDOW[1] - hand)
            if start > end:  # it hangs too far out of line: the hand's window comes first
                start = end = HAND_WINDOW[0] - hand if start > SHELF_SPAN[0] else HAND_WINDOW[1] - hand
            return half * float(np.clip(HALF_MIDDLE + jitter[0], start, end))

        raised = np.array(
            [CABINET_FRONT - RAISE_BEFORE, across(), WALL_SHELF_BOTTOM_TOP + OVER_SHELF + abs(self.human.jitter(0.01))]
        )
        level = self.level_rotation(side, body)
        goal = raised + self.hanging(side, mug)
        distance = float(np.linalg.norm(goal - self.hand_pose(side)[0]))
        duration = max(self.human.duration(distance), distance / CARRY_SPEED)
        yield from self.until(self.move_hand(side, goal, level, HOLD, duration=duration, spread=0.1, tremor=0.3))
        # look again: how it hangs now decides how far in and across it goes
        offset = self.hanging(side, mug)
        target = np.array([min(x + jitter[1], reach - offset[0]), across(), WALL_SHELF_BOTTOM_TOP])
        shelf = self.env.mask(CABINET, "shelf_bottom")
        yield from self.put_down(
            side,
            mug,
            target,
            shelf,
            feel_all_the_way=True,
            relax=False,
            upright=True,
            looks=SHELF_LOOKS,
            seen_off=SHELF_SEEN_OFF,
            tilt=SHELF_TILT,
            nearer=AGAIN_NEARER,
        )
        yield from self.withdraw(side)
        if relax:
            self.relax_arm(side)

    def withdraw(self, side: int) -> Script:
        """Draw the empty hand straight back out of the cabinet, level, to ``WITHDRAW`` in
        front of it: from there the arm relaxes clear of the open door."""
        p, r = self.hand_pose(side)
        out = np.array([min(p[0], CABINET_FRONT - WITHDRAW - abs(self.human.jitter(0.02))), p[1], p[2]])
        yield from self.until(self.move_hand(side, out, r, FREE, spread=0.2, precision=0.05))


__all__ = ["PutCupsExpert"]
