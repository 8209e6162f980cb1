"""DishwasherLoadCups demonstrator: put the two upside-down mugs from the counter onto the
dishwasher's pulled-out upper tray.

The mugs are wider than the gripper opens, so a person takes each by its handle, which
faces them, the way :mod:`bigym.experts.flip_cup` does: hand turned thumb-down, elbow
out, fingers round the handle's bar. The left hand takes its mug and lifts it a little,
then the right hand takes the other; holding both in front of the body they step back and
walk round to the front of the tray, crouch, and put each mug on the tray's front half:
turned so that the hand comes from the mug's outer side, looked at and moved over its
place, lowered until its rim rests on the floor, let go. The mugs stay upside down, as
they dry in a dishwasher.

Choices drawn per demo: which mug is put down first, where each goes on the tray, how low
the body crouches, where it stands, the timing, and every path's via-points.
"""

from __future__ import annotations

import numpy as np

from bigym.experts.expert import LEFT, RIGHT, SIDE_NAMES, Script
from bigym.experts.flip_cup import WRIST_START, FlipCupExpert
from bigym.experts.geometry import yaw_matrix
from bigym.experts.grasping import HOLD

MUGS = ("mug_1", "mug_2")
DISHWASHER = "dishwasher"
#: x of the front edge of the counter beside the dishwasher
COUNTER_FRONT = 0.38
#: how far (m) to the side of the handle the pelvis stands when taking a mug: the right
#: hand's mug stands in front of the dishwasher's edge, so its pelvis stays nearer, clear
#: of the pulled-out tray
SHOULDER_OFFSET = {LEFT: 0.2, RIGHT: 0.1}
#: how many times at most a hand reaches for a handle it missed
TAKES = 2
#: how high (m) a mug is lifted off the counter before the body moves
LIFT = 0.08
#: how much slower than a free movement the lift is
LIFT_SLOWNESS = 1.5
#: where on the upper tray's front half the mugs' middles go: this far (m) behind the front
#: of its floor (the back of the half, so that the hands behind the handles stay clear of
#: the tray's front wall, but not on the divider behind it), at y = +-TRAY_Y
TRAY_IN = 0.165
TRAY_Y = 0.16
#: pelvis height at the tray
TRAY_CROUCH = 0.58
#: the hand's approach to the handle when it puts a mug down: this far (rad) from +x,
#: coming from the mug's outer side
PUT_TURN = np.deg2rad(45.0)
#: how many times at most a mug is looked at and moved over its place before it is lowered,
#: and how far off (m) its place it must be seen to be moved
LOOKS = 2
SEEN_OFF = 0.008
#: a mug that touches the tray's floor is let go once it is within this (rad) of upside
#: down: it settles flat by itself (pressed on down, its low edge shoved the tray along)
SET_DOWN_TILT = np.deg2rad(10.0)
#: how far (m) over the surface the rim is brought before it is lowered onto it
OVER_TRAY = 0.04


class CupLoadExpert(FlipCupExpert):
    """Loads the two mugs of ``DishwasherLoadCups`` onto the upper tray."""

    tasks = ("DishwasherLoadCups",)
    counter_front = COUNTER_FRONT

    def plan(self) -> Script:
        tray = self.env.props[DISHWASHER].part_geom_ids("tray_mid")
        self.floor = int(tray[np.argmax(np.prod(self.model.geom_size[tray, :2], axis=1))])  # its widest geom
        self.tray_floor = np.zeros(self.model.ngeom, bool)
        self.tray_floor[self.floor] = True
        self.floor_top = float(self.data.geom_xpos[self.floor, 2] + self.model.geom_size[self.floor, 2])
        centres = {mug: self.data.xpos[self.env.props[mug].root_body_id].copy() for mug in MUGS}
        # the mug further along +y is the left hand's
        left_mug, right_mug = sorted(MUGS, key=lambda mug: -centres[mug][1])
        mug_of = {LEFT: left_mug, RIGHT: right_mug}
        # the left hand first: its mug, held still in the air, is then in front of the body
        # while the right hand takes the other (the other way round, the right arm ends up
        # stretched across the body)
        yield from self.wait(self.human.reaction())
        for side in (LEFT, RIGHT):
            yield from self.take_mug(side, mug_of[side])
        yield from self.walk_to_tray(mug_of)
        first = LEFT if self.rng.random() < 0.5 else RIGHT
        self.choices["first put down"] = SIDE_NAMES[first]
        for side in (first, 1 - first):
            if self.env.held(mug_of[side]):  # (a mug a hand never got stays where it is)
                yield from self.put_on_tray(side, mug_of[side])
        while True:
            yield

    def tray_front(self) -> float:
        """x of the front edge of the upper tray's floor, where the tray is now."""
        return float(self.data.geom_xpos[self.floor, 0] - self.model.geom_size[self.floor, 0])

    # ------------------------------------------------------------------ steps
    def take_mug(self, side: int, mug: str) -> Script:
        """Take the mug's handle, thumb down, and lift the mug a little."""
        for attempt in range(TAKES):
            self.note(f"take {mug} {'LR'[side]}")
            handle = self.site(mug, "handle")
            approach = self.data.xpos[self.env.props[mug].root_body_id] - handle
            approach[2] = 0.0
            approach /= np.linalg.norm(approach)
            wrist = -WRIST_START if side == LEFT else WRIST_START
            line = np.array([0.0, 0.0, 1.0])
            yield from self.take_bar(side, wrist, handle, line, approach, 0.75, SHOULDER_OFFSET[side])
            if self.env.held(mug) or attempt == TAKES - 1:
                break
            self.note(f"missed {mug}")  # the fingers closed beside the handle: open, try again
            yield from self.release(side, back=0.06, up=0.03)
        p, r = self.hand_pose(side)
        lift = LIFT + abs(self.human.jitter(0.02))
        duration = self.human.duration(lift, 0.02, minimum=0.6) * LIFT_SLOWNESS  # gently: it hangs off-centre
        end = self.move_hand(side, p + np.array([0.0, 0.0, lift]), r, HOLD, duration=duration, spread=0.0, tremor=0.3)
        yield from self.until(end)

    def walk_to_tray(self, mug_of: dict[int, str]) -> Script:
        """Step back from the counter and walk to the front of the tray, crouching."""
        self.note("walk to tray")
        base = self.commanded_base()
        # the held mugs go with the body: stand where their middle comes over the tray's front half
        held = np.mean([self.data.xpos[self.env.props[mug].root_body_id] for mug in mug_of.values()], axis=0)
        x = self.tray_front() + TRAY_IN - (held[0] - base[0]) + self.human.jitter(0.015)
        y = -(held[1] - base[1]) + self.human.jitter(0.03)
        self.choices["tray stance"] = [round(float(x), 2), round(float(y), 2)]
        route = [
            (base[0] - 0.3, base[1] + 0.1, base[2], 0.0),
            (x, y, TRAY_CROUCH + self.human.jitter(0.02), 0.0),
        ]
        yield from self.walk(route, carrying=(LEFT, RIGHT))

    def put_on_tray(self, side: int, mug: str) -> Script:
        """Put the mug down on its place on the tray's front half, the hand coming from the
        mug's outer side: behind the mug, its knuckles would sit on the tray's front wall."""
        self.note(f"put {mug} {'LR'[side]}")
        target = np.array(
            [
                self.tray_front() + TRAY_IN + self.human.jitter(0.01),
                (TRAY_Y if side == LEFT else -TRAY_Y) + self.human.jitter(0.02),
                self.floor_top,
            ]
        )
        approach = PUT_TURN * (-1.0 if side == LEFT else 1.0) + self.human.jitter(0.1)
        yield from self.put_down(side, mug, target, self.tray_floor, approach)

    def put_down(
        self,
        side: int,
        mug: str,
        target: np.ndarray,
        support: np.ndarray,
        approach: float | None = None,
        feel_all_the_way: bool = False,
        relax: bool = True,
        upright: bool = False,
        looks: int = LOOKS,
        seen_off: float = SEEN_OFF,
        tilt: float = SET_DOWN_TILT,
        nearer: float = 0.0,
    ) -> Script:
        """Bring the held mug upside down (``upright``: the right way up) over ``target``
        (x, y, and the top z of the ``support`` geoms' surface), look at it and move it over
        its place (``looks`` times at most, until it is within ``seen_off`` m), lower it
        until it rests there (touches the support within ``tilt`` rad of straight), let go.
        With ``approach`` (rad, from +x), the hand turns the mug about its axis so that it
        comes at the handle that way. The hand lowers it at most a few centimetres past
        where it should rest; ``feel_all_the_way``: past where it is seen to be (a hand
        that did not get down to where it was sent), and one that is not resting then is
        lifted, straightened and lowered again; ``nearer``: brought this far (m) nearer the
        body as it is lifted, and lowered as far as the first time (a hand at full stretch
        stops short of the shelf: nearer, the arm has the reach to go down). ``relax``: the
        arm relaxes afterwards."""
        body = self.env.props[mug].root_body_id
        # the mug's origin is at its base: upside down, a mug's height above its rim
        bottom = 0.0 if upright else self.env.props[mug].height
        up = 1.0 if upright else -1.0
        target = np.array([target[0], target[1], target[2] + bottom + OVER_TRAY])
        p, _ = self.hand_pose(side)
        level = self.level_rotation(side, body)  # straight, as it is put down
        turn = np.eye(3)
        if approach is not None:
            now = level[:2, 2] / np.linalg.norm(level[:2, 2])
            turn = yaw_matrix(approach - float(np.arctan2(now[1], now[0])))
        level = turn @ level
        goal = target + turn @ (p - self.data.xpos[body])
        yield from self.until(self.move_hand(side, goal, level, HOLD, spread=0.1, tremor=0.3))
        for _ in range(looks):  # the arm sags a little reaching this low: look, and correct
            off = target - self.data.xpos[body]
            off[2] = 0.0
            if np.linalg.norm(off) < seen_off:
                break
            p, _ = self.hand_pose(side)
            yield from self.until(self.move_hand(side, p + off, level, HOLD, duration=0.4, spread=0.0, tremor=0.2))
        frame = self.data.xmat[body]

        def resting() -> bool:
            return self.env.touching(self.env.mask(mug), support) and up * frame[8] >= np.cos(tilt)

        depth = OVER_TRAY + 0.03
        if feel_all_the_way:
            depth = max(depth, float(self.data.xpos[body][2] - target[2]) + OVER_TRAY + 0.03)
        yield from self.lower_until(side, level, depth, 0.4, resting)
        if feel_all_the_way and not resting():
            self.note(f"again {mug}")  # it hangs tilted, or stands on an edge: up, straight, down
            p, _ = self.hand_pose(side)
            level = self.level_rotation(side, body)
            lift = np.array([0.0, 0.0, 0.03])
            if nearer:
                towards = self.base_pose()[:2] - p[:2]
                lift[:2] = nearer * towards / np.linalg.norm(towards)
            yield from self.until(self.move_hand(side, p + lift, level, HOLD, spread=0.0))
            depth = 0.03 + OVER_TRAY
            if nearer:  # as far as the first time, from where it is now
                depth = float(self.data.xpos[body][2] - target[2]) + OVER_TRAY + 0.03
            yield from self.lower_until(side, level, depth, 0.4, resting)
        self.hold_hand(side, HOLD, tremor=0.2)
        yield from self.wait(0.1)
        yield from self.release(side, back=0.08, up=0.06, relax=relax)


__all__ = ["CupLoadExpert"]
