"""Dishwasher demonstrators: the door and the two sliding trays (scene ``dishwasher``).

The robot starts beside the door's sweep and works from there, like a person who does
not want to trip over an open dishwasher door:

* a tray comes out by its handle: the low handles are taken from above and in front,
  the rear finger hooking behind the tray's front rail; it goes back in with a push of
  the fist on its handle bar;
* the door opens by its handle part of the way, then a fist on its inner face pushes
  it down flat; it closes by lifting its free edge, then a push on its outer face.

Choices drawn per demo: the hand (mostly the one nearer the dishwasher, sometimes the
far one), which tray first, where the base stands, how far the door is pulled before
the hand changes grip.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.experts.expert import FIRM, LEFT, RIGHT, SIDE_NAMES, Expert, Script

PROP = "dishwasher"
#: pelvis clearance (m) in front of the dishwasher's front, and beside the door
FRONT_CLEARANCE = 0.3
SIDE_CLEARANCE = 0.42
DONE_MARGIN = 0.05
#: how often the middle tray is worked with the hand away from the door
FAR_HAND_PROBABILITY = 0.15
OVERSHOOT = 0.04
#: approach tilt (rad, from horizontal, downwards) for each tray handle
TRAY_TILT = {"tray_bottom": 0.95, "tray_mid": 0.55}
#: where the pinch point goes relative to a tray's handle bar
TRAY_GRASP_OFFSET = np.array([0.0, 0.0, -0.005])
#: the open door's free edge is taken from above-front at this tilt (rad below level),
#: the pinch point (along the door from the edge, along the outer normal) at this offset
EDGE_TILT = 0.95
EDGE_GRASP = (-0.04, -0.012)
#: speed factor of the door lift by its edge
LIFT_SPEED = 0.6


class DishwasherExpert(Expert):
    """Opens and closes the dishwasher door and trays."""

    tasks = ("DishwasherOpen", "DishwasherClose", "DishwasherOpenTrays", "DishwasherCloseTrays")
    pace: ClassVar[dict[str, float]] = {"DishwasherOpen": 1.35, "DishwasherClose": 1.3}

    def plan(self) -> Script:
        env = self.env
        goal = float(env.goal)
        opening = goal > 0.5
        near = self.work_from_side()
        # the middle tray pulled out covers the bottom one: bottom out first, middle in first
        trays = [k for k in ("tray_bottom", "tray_mid") if k in env.targets]
        if not opening:
            trays.reverse()
        self.choices["order"] = (
            (["door"] if "door" in env.targets and opening else [])
            + trays
            + (["door"] if "door" in env.targets and not opening else [])
        )
        # the near hand; the far one reaches across for the middle tray now and then (the
        # bottom tray is too low and the door too heavy-handed for a reach across the body)
        sides = [
            1 - near if job == "tray_mid" and self.rng.random() < FAR_HAND_PROBABILITY else near
            for job in self.choices["order"]
        ]
        self.choices["hands"] = [f"{job}:{SIDE_NAMES[side]}" for job, side in zip(self.choices["order"], sides)]
        yield from self.wait(self.human.reaction())
        for idle in (LEFT, RIGHT):
            if idle not in sides[:1]:
                self.relax_arm(idle, start=self.time + abs(self.human.jitter(0.15)), joint_space=True)
        for job, side in zip(self.choices["order"], sides):
            if job == "door":
                yield from self.dishwasher_door(side, goal)
            else:
                yield from self.tray(side, job, goal)
            yield from self.hesitate()
        while True:
            yield

    def work_from_side(self) -> int:
        """From now on keep the base out of the dishwasher and off its door's sweep, on the
        side of it where the base stands; returns the hand on the dishwasher's side."""
        self.keep_base_behind(self.front_point(), self.facing(), FRONT_CLEARANCE)
        base = self.commanded_base()
        self._side_sign = float(np.sign((base[:2] - self.front_point()[:2]) @ self.lateral()[:2]) or -1.0)
        self.keep_base_behind(self.front_point(), -self._side_sign * self.lateral(), SIDE_CLEARANCE)
        return LEFT if self._side_sign < 0 else RIGHT

    # ------------------------------------------------------------------ geometry
    def facing(self) -> np.ndarray:
        frame = self.data.xmat[self.env.props[PROP].root_body_id].reshape(3, 3)
        return frame[:, 0].copy()

    def lateral(self) -> np.ndarray:
        """Unit vector along the dishwasher's width (its local +y)."""
        frame = self.data.xmat[self.env.props[PROP].root_body_id].reshape(3, 3)
        return frame[:, 1].copy()

    def front_point(self) -> np.ndarray:
        """A point on the dishwasher's front plane, at its centre line."""
        root = self.data.xpos[self.env.props[PROP].root_body_id]
        return root - self.facing() * 0.6

    def door_open(self) -> bool:
        return self.joint_state(PROP, "door") > 0.5

    def side_stance(self, side: int, point: np.ndarray, distance: float, height: float) -> np.ndarray:
        """Beside the door, facing the dishwasher, level with ``point`` minus ``distance``."""
        facing = self.facing()
        lateral = self.lateral() * self._side_sign
        centre = self.front_point()
        along = float((point - centre) @ facing) - distance
        pos = (
            centre
            + facing * along
            + lateral * (SIDE_CLEARANCE + 0.04 + abs(self.human.jitter(self.style.stance_spread * 0.5)))
        )
        z = float(np.clip(point[2] + height + self.human.jitter(0.02), 0.58, 1.0442))
        yaw = float(
            np.arctan2(facing[1], facing[0]) - self._side_sign * 0.35 + self.human.jitter(self.style.stance_yaw_spread)
        )
        return np.array([pos[0], pos[1], z, yaw])

    # ------------------------------------------------------------------ trays
    def tray(self, side: int, key: str, goal: float, attempts: int = 3) -> Script:
        for attempt in range(attempts):
            state = self.joint_state(PROP, key)
            if abs(state - goal) < DONE_MARGIN:
                return
            if attempt:
                self.note(f"correct {key} at {state:.2f}")
            centre, bar, approach = self.handle_frame(PROP, f"{key}_handle", "y")
            stance = self.side_stance(side, centre, 0.25, 0.2)
            tilt = TRAY_TILT[key] + self.human.jitter(0.05)
            if goal > 0.5:
                # from above and in front: the rear finger hooks behind the tray's rail
                yield from self.grasp_bar(
                    side, centre + TRAY_GRASP_OFFSET, bar, approach, tilt=tilt, depth=0.006, base_goal=stance
                )
                yield from self.drag([side], PROP, key, 1.0 + OVERSHOOT, base_follow=0.8, orientation_cost=FIRM * 0.4)
                away = None
            else:
                point = centre - approach * 0.006
                fingers = approach + np.array([0.0, 0.0, -np.tan(tilt)])
                yield from self.press(
                    side, point, approach, across=bar, base_goal=stance, fingers=fingers, contact=0.014
                )
                yield from self.drag([side], PROP, key, -OVERSHOOT, base_follow=0.8, orientation_cost=FIRM * 0.3)
                away = -approach
            done = abs(self.joint_state(PROP, key) - goal) < DONE_MARGIN
            yield from self.release(side, back=0.08, away=away, relax=done)

    # ------------------------------------------------------------------ door
    def door_frame(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(edge, up, front)``: the centre of the door's free (top) edge face, the
        direction from the hinge to that edge, and the door's outer face normal."""
        edge = self.site(PROP, "door_edge")
        body = self.model.site_bodyid[self.env.props[PROP].site_id("door_edge")]
        frame = self.data.xmat[body].reshape(3, 3)
        return edge, frame[:, 2].copy(), -frame[:, 0].copy()

    def dishwasher_door(self, side: int, goal: float, attempts: int = 3) -> Script:
        """Opening: pull the handle down part of the way, let go, push the inner face
        down flat. Closing: take the free edge (fingers either side of it, from above
        and in front), lift the door part of the way, let go, push the outer face shut."""
        for attempt in range(attempts):
            state = self.joint_state(PROP, "door")
            if abs(state - goal) < DONE_MARGIN:
                return
            if attempt:
                self.note(f"correct door at {state:.2f}")
            if goal > 0.5:
                if state < 0.3:
                    switch = float(np.clip(self.rng.normal(0.42, 0.04), 0.35, 0.5))
                    centre, bar, approach = self.handle_frame(PROP, "door_handle", "y")
                    stance = self.side_stance(side, centre, 0.3, 0.25)
                    yield from self.grasp_bar(
                        side, centre, bar, approach, tilt=0.35 + self.human.jitter(0.05), base_goal=stance
                    )
                    yield from self.drag([side], PROP, "door", switch, base_follow=0.5, orientation_cost=FIRM * 0.3)
                    yield from self.release(side, back=0.06)
                direction = yield from self.press_dishwasher_door(side, inner=True)
                yield from self.drag(
                    [side], PROP, "door", 1.0 + 2 * OVERSHOOT, base_follow=0.5, orientation_cost=FIRM * 0.2
                )
            else:
                if state > 0.7:
                    switch = float(np.clip(self.rng.normal(0.5, 0.04), 0.42, 0.58))
                    yield from self.grasp_edge(side)
                    # lifted slowly: a pinch on the edge slips under the coarser target steps of
                    # a replay at 20 Hz when the lift is brisk
                    yield from self.drag(
                        [side], PROP, "door", switch, base_follow=0.5, orientation_cost=FIRM * 0.4, speed=LIFT_SPEED
                    )
                    yield from self.release(side, back=0.06)
                direction = yield from self.press_dishwasher_door(side, inner=False)
                yield from self.drag([side], PROP, "door", -OVERSHOOT, base_follow=0.5, orientation_cost=FIRM * 0.2)
            done = abs(self.joint_state(PROP, "door") - goal) < DONE_MARGIN
            yield from self.release(side, back=0.08, away=-direction, relax=done)

    def grasp_edge(self, side: int) -> Script:
        """Fingers either side of the open door's free edge, coming from above and in
        front (the edge is too low for a level approach): one pad under the edge's
        front, the other on the door's top."""
        edge, up, front = self.door_frame()
        bar = np.cross(up, -front)
        bar /= np.linalg.norm(bar)
        lateral = self.lateral() * self._side_sign * (0.12 + abs(self.human.jitter(0.04)))
        centre = edge + lateral + up * EDGE_GRASP[0] + front * EDGE_GRASP[1]
        stance = self.side_stance(side, centre, 0.1, 0.45)
        yield from self.grasp_bar(
            side, centre, bar, -up, tilt=EDGE_TILT + self.human.jitter(0.04), depth=0.0, base_goal=stance
        )

    def press_dishwasher_door(self, side: int, inner: bool) -> Script:
        """A fist on the door near its top edge: on the inner face pushing it open, on
        the outer face pushing it shut. Returns the push direction."""
        edge, up, front = self.door_frame()
        inset = 0.06 + abs(self.human.jitter(0.03))
        lateral = self.lateral() * self._side_sign * (0.12 + abs(self.human.jitter(0.04)))
        # door_edge is on the middle of the 4 cm thick free edge
        if inner:
            point, direction = edge - up * inset + lateral - front * 0.02, front
            fingers = np.array([0.0, 0.0, -1.0]) + 0.3 * self.facing()
        else:
            point, direction = edge - up * inset + lateral + front * 0.02, -front
            fingers = -front + 0.5 * self.facing()
        hand, _ = self.hand_pose(side)
        via = None
        side_now = float(np.sign((hand - edge) @ front))
        if (side_now > 0.0) == inner:  # round the free edge, well clear of it
            clear = 0.18 + abs(self.human.jitter(0.02))
            via = [
                edge + up * clear + side_now * front * 0.08 + lateral,
                edge + up * clear - side_now * front * 0.12 + lateral,
            ]
        stance = self.side_stance(side, point, 0.15, 0.45)
        yield from self.press(
            side, point, direction, base_goal=stance, fingers=fingers, contact=0.016, via=via, depth=0.015
        )
        return direction
