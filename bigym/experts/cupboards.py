"""Kitchen-counter demonstrators: drawers and cupboard doors (scene counter_base_wall_3x1).

How a person does it, and so how these scripts do it:

* a drawer opens by its handle (fingers around the bar, pull, step back) and closes
  with a push of the fist on its handle bar;
* a hinged door opens by its handle only part of the way (the hand cannot follow the
  handle round a quarter turn); the hand then lets go, takes the door by its free
  edge and swings it fully open. Closing goes the other way round: take the open
  door by its edge, swing it most of the way, then push the handle bar home.

Choices drawn per demo: the hand for each drawer or door (for the wall cupboard also
both hands at once, one per door), the order of the jobs (drawers are opened from the
bottom up and closed from the top down, so that an open drawer never hangs over the
hand; groups of jobs come in a random order), where the base stands, how far a door is
pulled before the hand changes grip.
"""

from __future__ import annotations

from typing import ClassVar

import mujoco
import numpy as np

from bigym.experts.expert import FIRM, LEFT, RIGHT, Expert, Script

DRAWERS_PROP = "cabinet_drawers"
DRAWER_ORDER = ("drawer_big_1", "drawer_small_3", "drawer_small_4")  # bottom to top
WALL_PROP = "wall_cabinet"
#: how close the pelvis may come to the counter's front (m): the feet stay in front of it
BASE_CLEARANCE = 0.3
#: a joint this close to its goal is done (the task's tolerance is 0.1)
DONE_MARGIN = 0.06
#: pushes aim this far (normalised) past the goal, into the joint's stop
OVERSHOOT = 0.04
#: a base-cabinet door's width (m) and how far (m) the pelvis keeps out of its sweep
DOOR_WIDTH = 0.6
SWEEP_CLEARANCE = 0.25
#: how often a base-cabinet door is pushed shut with the hand away from its free edge
FAR_HAND_PROBABILITY = 0.15
#: orientation costs while taking a door's upright handle (the yaw about the bar is held too)
HANDLE_ALIGN = np.array([1.5, 0.8, 2.0])


class CupboardExpert(Expert):
    """Opens and closes the drawers and doors of the counter scene."""

    tasks = (
        "DrawerTopOpen",
        "DrawerTopClose",
        "DrawersOpenAll",
        "DrawersCloseAll",
        "WallCupboardOpen",
        "WallCupboardClose",
        "CupboardsOpenAll",
        "CupboardsCloseAll",
    )
    pace: ClassVar[dict[str, float]] = {
        "DrawersCloseAll": 1.3,
        "WallCupboardOpen": 1.5,
        "WallCupboardClose": 1.3,
        "CupboardsOpenAll": 1.3,
        "CupboardsCloseAll": 1.2,
    }

    def plan(self) -> Script:
        env = self.env
        goal = float(env.goal)
        opening = goal > 0.5
        groups: list[list[tuple[str, str]]] = []
        for prop, keys in env.targets:
            if prop == DRAWERS_PROP:
                ordered = sorted(keys, key=DRAWER_ORDER.index, reverse=not opening)
                groups.append([(prop, key) for key in ordered])
            elif prop == WALL_PROP:
                groups.append([(prop, key) for key in keys])
            else:
                groups.extend([[(prop, key)] for key in keys])
        # doors in a random order; the drawers last when opening (an open drawer is in the
        # way of everything), first when closing
        drawers = [g for g in groups if g[0][0] == DRAWERS_PROP]
        doors = [g for g in groups if g[0][0] != DRAWERS_PROP]
        doors = [doors[i] for i in self.rng.permutation(len(doors))]
        groups = doors + drawers if opening else drawers + doors
        self.choices["order"] = [f"{p}/{k}" for g in groups for p, k in g]
        # stand in front of the counter, never inside it (its front is at the drawers' fronts)
        front = self.site(DRAWERS_PROP, "drawer_big_1_handle") + self.module_facing(DRAWERS_PROP) * 0.035
        self.keep_base_behind(front, self.module_facing(DRAWERS_PROP), BASE_CLEARANCE)
        yield from self.wait(self.human.reaction())
        for side in (LEFT, RIGHT):
            self.relax_arm(side, start=self.time + abs(self.human.jitter(0.15)), joint_space=True)
        for group in groups:
            prop = group[0][0]
            if prop == DRAWERS_PROP:
                for _, key in group:
                    yield from self.drawer(key, goal)
            elif prop == WALL_PROP:
                yield from self.wall_doors([key for _, key in group], goal)
            else:
                key = group[0][1]
                # the hand on the door's free-edge side; closing, sometimes the other one
                side = self.door_side(prop, key)
                if not opening and self.rng.random() < FAR_HAND_PROBABILITY:
                    side = 1 - side
                self._note_hand(f"{prop}/{key}", side)
                yield from self.door(side, prop, key, goal)
            yield from self.hesitate()
        while True:
            yield

    # ------------------------------------------------------------------ helpers
    def _note_hand(self, job: str, side: int | str) -> None:
        name = side if isinstance(side, str) else ("left" if side == LEFT else "right")
        self.choices.setdefault("hands", []).append(f"{job}:{name}")

    def pick_hand(self, job: str) -> int:
        side = LEFT if self.rng.random() < 0.5 else RIGHT
        self._note_hand(job, side)
        return side

    def door_side(self, prop: str, key: str) -> int:
        """The hand on the door's free-edge side is the natural one for a base-cabinet door."""
        p = self.env.props[prop]
        hinge = self.data.xanchor[p.joint_ids[p.joint_index(key)]]
        centre = self.data.xpos[p.root_body_id]
        left = np.cross([0.0, 0.0, 1.0], self.module_facing(prop))
        return LEFT if (hinge - centre) @ left > 0.0 else RIGHT

    def module_facing(self, prop: str) -> np.ndarray:
        """Direction a person faces when working at a module: into its front (local +x)."""
        frame = self.data.xmat[self.env.props[prop].root_body_id].reshape(3, 3)
        return frame[:, 0].copy()

    def door_edge(self, prop: str, key: str, height: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(point, edge direction out of the door, front normal)`` of a door's free edge.

        The point is mid-way through the panel's thickness at world height ``height``;
        the edge direction points from the hinge towards the free edge.
        """
        p = self.env.props[prop]
        site = p.site_id(f"{key}_handle")
        body = int(self.model.site_bodyid[site])
        handle_local = self.model.site_pos[site]
        sign = 1.0 if handle_local[1] > 0 else -1.0
        panel = max(
            (
                g
                for g in range(self.model.ngeom)
                if self.model.geom_bodyid[g] == body and self.model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX
            ),
            key=lambda g: float(np.prod(self.model.geom_size[g])),
        )
        centre, half = self.model.geom_pos[panel], self.model.geom_size[panel]
        frame = self.data.xmat[body].reshape(3, 3)
        origin = self.data.xpos[body]
        local = np.array([centre[0], centre[1] + sign * half[1], 0.0])
        point = origin + frame @ local
        # on the panel, a hand's breadth from its top and bottom
        low, high = origin[2] + centre[2] - half[2] + 0.06, origin[2] + centre[2] + half[2] - 0.07
        point[2] = float(np.clip(height, low, high))
        return point, frame[:, 1] * sign, -frame[:, 0]

    # ------------------------------------------------------------------ drawers
    def drawer(self, key: str, goal: float, attempts: int = 3) -> Script:
        """Open a drawer by its handle, or close it by pushing its handle bar with a fist;
        if it stopped short, once more (a correction)."""
        side = self.pick_hand(key)
        for attempt in range(attempts):
            state = self.joint_state(DRAWERS_PROP, key)
            if abs(state - goal) < DONE_MARGIN:
                return
            if attempt:
                self.note(f"correct {key} at {state:.2f}")
            centre, bar, approach = self.handle_frame(DRAWERS_PROP, f"{key}_handle", "y")
            if goal > 0.5:
                stance = self.stance(side, centre, approach)
                tilt = float(np.clip((stance[2] - 0.27 - centre[2]) * 2.0, 0.0, 0.6)) + self.human.jitter(
                    self.style.approach_spread
                )
                yield from self.grasp_bar(
                    side, centre, bar, approach, tilt=tilt, offset=self.human.jitter(0.02), base_goal=stance
                )
                yield from self.hesitate()
                yield from self.drag(
                    [side], DRAWERS_PROP, key, 1.0 + OVERSHOOT, base_follow=0.85, orientation_cost=FIRM * 0.5
                )
                away = None
            else:
                # the fist on the bar's front (a hand on the front face below it would have
                # to reach under the counter's overhang for the top drawer)
                point = centre - approach * 0.008 + bar * self.human.jitter(0.03)
                stance = self.stance(side, point, approach)
                yield from self.press(side, point, approach, across=bar, base_goal=stance)
                yield from self.drag(
                    [side], DRAWERS_PROP, key, -OVERSHOOT, base_follow=0.85, orientation_cost=FIRM * 0.3
                )
                away = -approach
            done = abs(self.joint_state(DRAWERS_PROP, key) - goal) < DONE_MARGIN
            # out and up, clear of the open drawer's front, before anything else moves
            yield from self.release(side, back=0.12, up=0.06, away=away)
            if done:
                relaxed = self.relax_arm(side)
                yield from self.until(self.time + 0.6 * (relaxed - self.time))

    # ------------------------------------------------------------------ doors
    def door(self, side: int, prop: str, key: str, goal: float, base: bool = True, attempts: int = 3) -> Script:
        """Open or close one hinged door with one hand.

        Opening: pull the handle part of the way, let go, and push the door's inner face
        round to fully open. Closing: push the outer face near the free edge round to
        shut. A door that did not get there gets another push (a correction).
        ``base=False``: the base stays where it is (the other hand may be busy too).
        """
        follow = 0.4 if base else 0.0
        switch = float(np.clip(self.rng.normal(0.5, 0.05), 0.4, 0.6))
        keep_out = self.keep_out_of_sweep(prop, key) if base else None
        try:
            yield from self._door_attempts(side, prop, key, goal, base, follow, switch, attempts)
        finally:
            if keep_out is not None:
                planes = self.ik.base_region.planes
                planes[:] = [plane for plane in planes if plane is not keep_out]

    def keep_out_of_sweep(self, prop: str, key: str) -> tuple[np.ndarray, float] | None:
        """Keep the base out of a low door's sweep (the door would hit the robot): a
        half-plane tangent to the sweep circle, on the robot's side of the hinge."""
        if self.site(prop, f"{key}_handle")[2] > 1.2:
            return None  # a wall-cupboard door swings above the robot's body
        p = self.env.props[prop]
        hinge = self.data.xanchor[p.joint_ids[p.joint_index(key)]][:2].copy()
        facing = self.module_facing(prop)[:2]
        inward = self.data.xpos[p.root_body_id][:2] - hinge  # towards the module's middle
        inward -= facing * (inward @ facing)
        inward /= np.linalg.norm(inward)
        # the tangent half-plane on the bisector of the sweep's two edges (the closed door
        # and the fully open one): in front of the sweep, where the robot works from
        away = inward - facing
        away /= np.linalg.norm(away)
        radius = DOOR_WIDTH + SWEEP_CLEARANCE
        plane = (-away, float(-(away @ hinge) - radius))
        self.ik.base_region.planes.append(plane)
        return plane

    def _door_attempts(self, side, prop, key, goal, base, follow, switch, attempts) -> Script:
        for attempt in range(attempts):
            state = self.joint_state(prop, key)
            if abs(state - goal) < DONE_MARGIN:
                return
            if attempt:
                self.note(f"correct {prop}/{key} at {state:.2f}")
            if goal > 0.5:
                if state < 0.3:
                    yield from self.grasp_handle(side, prop, key, base=base)
                    yield from self.drag([side], prop, key, switch, base_follow=follow, orientation_cost=FIRM * 0.4)
                    yield from self.release(side, back=0.05)
                direction = yield from self.press_door(side, prop, key, inner=True, base=base)
                yield from self.drag(
                    [side], prop, key, 1.0 + 2.5 * OVERSHOOT, base_follow=follow, orientation_cost=FIRM * 0.3
                )
            else:
                direction = yield from self.press_door(side, prop, key, inner=False, base=base)
                yield from self.drag(
                    [side], prop, key, -2.5 * OVERSHOOT, base_follow=follow, orientation_cost=FIRM * 0.3
                )
            done = abs(self.joint_state(prop, key) - goal) < DONE_MARGIN
            yield from self.release(side, back=0.08, away=-direction, relax=done)

    def press_door(self, side: int, prop: str, key: str, inner: bool, base: bool = True) -> Script:
        """A fist against a door near its free edge: on the inner face to push it open,
        on the outer face to push it shut. Returns the push direction."""
        handle = self.site(prop, f"{key}_handle")
        height = handle[2] + 0.05 + abs(self.human.jitter(0.03))
        edge, out, front = self.door_edge(prop, key, height)
        inset = 0.05 + abs(self.human.jitter(0.02))
        facing = self.module_facing(prop)
        if inner:
            point, direction = edge - out * inset - front * 0.01, front
        else:
            point, direction = edge - out * inset + front * 0.01, -front
        # the fingers lean from the push direction towards the furniture
        fingers = direction + (0.4 + abs(self.human.jitter(0.1))) * facing
        hand, _ = self.hand_pose(side)
        via = None
        side_now = float(np.sign((hand - edge) @ front))
        if (side_now > 0.0) == inner:  # on the other side: round the free edge, well clear of it
            clear = 0.15 + abs(self.human.jitter(0.02))
            up = np.array([0.0, 0.0, 0.02])
            via = [edge + out * clear + side_now * front * 0.06 + up, edge + out * clear - side_now * front * 0.1 + up]
        stance = None
        if base:
            distance = 0.45 if handle[2] < 1.2 else (0.62 if inner else 0.5)
            stance = self.stance(side, point, facing, distance=distance, lateral=0.15)
        yield from self.press(
            side, point, direction, base_goal=stance, via=via, fingers=fingers, contact=0.016, depth=0.012
        )
        return direction

    def grasp_handle(self, side: int, prop: str, key: str, base: bool = True) -> Script:
        centre, bar, approach = self.handle_frame(prop, f"{key}_handle", "z")
        facing = self.module_facing(prop)
        distance = 0.4 if centre[2] < 1.2 else 0.66  # a high handle is reached from further back
        stance = self.stance(side, centre, facing, distance=distance, lateral=0.18) if base else None
        offset = self.human.jitter(0.02)
        # a door's handle stands only 3.5 cm off the door: the fingers come in square to it
        yield from self.grasp_bar(
            side,
            centre,
            bar,
            approach,
            tilt=self.human.jitter(self.style.approach_spread * 0.5),
            offset=offset,
            base_goal=stance,
            depth=0.0,
            align=HANDLE_ALIGN,
        )

    def grasp_edge(self, side: int, prop: str, key: str, base: bool = True) -> Script:
        handle = self.site(prop, f"{key}_handle")
        height = handle[2] + 0.05 + abs(self.human.jitter(0.03))
        point, out, front = self.door_edge(prop, key, height)
        approach = -out
        facing = self.module_facing(prop)
        facing = facing + 0.35 * (approach - facing)
        stance = self.stance(side, point, facing, distance=0.45, lateral=0.15) if base else None
        # round the free edge on the front side, never through the door
        hand, _ = self.hand_pose(side)
        via = None
        if (hand - point) @ front > -0.01:
            via = [point + out * 0.1 + front * 0.06 + np.array([0.0, 0.0, 0.02])]
        yield from self.grasp_bar(
            side, point, np.array([0.0, 0.0, 1.0]), approach, depth=0.012, base_goal=stance, via=via
        )

    def _after(self, delay: float, script: Script) -> Script:
        yield from self.wait(delay)
        yield from script

    def wall_doors(self, keys: list[str], goal: float) -> Script:
        """Both wall-cupboard doors: one hand each at once, or one after the other."""
        both = len(keys) == 2 and self.rng.random() < (0.4 if goal > 0.5 else 0.5)
        if both:
            self._note_hand(f"{WALL_PROP}/both", "both")
            sides = {key: self.door_side(WALL_PROP, key) for key in keys}
            # the base stands centred between the doors; each hand works its own door
            centre = 0.5 * (self.site(WALL_PROP, f"{keys[0]}_handle") + self.site(WALL_PROP, f"{keys[1]}_handle"))
            _, _, approach = self.handle_frame(WALL_PROP, f"{keys[0]}_handle", "z")
            stance = self.stance(None, centre, approach, distance=0.66, height=-0.45)
            yield from self.until(self.move_base(stance))
            # opening, the second hand waits until the first door has swung aside (the two
            # handles are side by side, too close for two grippers at once)
            first = int(self.rng.integers(2))
            delay = float(self.rng.uniform(1.6, 2.2)) if goal > 0.5 else abs(self.human.jitter(0.15))
            scripts = [
                self.door(sides[key], WALL_PROP, key, goal, base=False)
                if i == first
                else self._after(delay, self.door(sides[key], WALL_PROP, key, goal, base=False))
                for i, key in enumerate(keys)
            ]
            yield from run_together(scripts)
        else:
            order = list(keys) if self.rng.random() < 0.5 else list(reversed(keys))
            for key in order:
                # mostly the hand on the door's hinge side: the arm then never crosses
                # in front of the other, maybe open, door
                side = self.door_side(WALL_PROP, key)
                self._note_hand(f"{WALL_PROP}/{key}", side)
                yield from self.door(side, WALL_PROP, key, goal)
                yield from self.hesitate()


def run_together(scripts: list[Script]) -> Script:
    """Advance several scripts in lock-step until all have finished."""
    running = list(scripts)
    while running:
        for script in list(running):
            try:
                next(script)
            except StopIteration:
                running.remove(script)
        if running:
            yield
