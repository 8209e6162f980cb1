"""Hinged doors: open and close one by hand, as a person does.

A door opens by its handle only part of the way (the hand cannot follow the handle
round a quarter turn); the hand then lets go and pushes the door's inner face near its
free edge round to fully open. Closing goes the other way round: a fist on the outer
face near the free edge swings it shut. A door that stopped short gets another push.
Coming round the free edge to push, the fist keeps well back from the door's inner face
(the closed fingers reach ahead of the hand, and a door they brush swings on by itself)
but in front of the furniture (behind one half of a double door opened part of the way,
the other half is there).
A low door's sweep is kept clear of the base (it would hit the robot).
"""

from __future__ import annotations

import mujoco
import numpy as np

from bigym.experts.expert import FIRM, LEFT, RIGHT, SIDE_NAMES, Expert, Script

#: a joint this close to its goal is done (the tasks' tolerance is 0.1)
DONE_MARGIN = 0.06
#: pushes aim this far (normalised) past the goal, into the joint's stop
OVERSHOOT = 0.04
#: a base-cabinet door's width (m) and how far (m) the pelvis keeps out of its sweep
DOOR_WIDTH = 0.6
SWEEP_CLEARANCE = 0.25
#: a base-cabinet door opens to its stop: the push aims only this far (normalised) past it
#: (an arm pressing on against a stopped door strains)
DOOR_PUSH_PAST = 0.03
#: how far (m) from a door's face the fist moves along it after coming round the free
#: edge, before it moves in to push: the closed fingers reach about 0.1 m ahead of the
#: pinch point, and nearer than this they brushed the door, which then swung on its own
#: (by a different amount in a replay at another rate)
ROUND_EDGE_STANDOFF = 0.15
#: how far (m) in front of the furniture's front (the plane of its closed doors) the fist
#: stays while it moves in to push a door's inner face: a narrow door opened part of the way
#: leaves a narrow wedge, and further back the fist was behind the neighbouring closed door
#: of a double door and pushed against it
FRONT_MARGIN = 0.04
#: how far (m) the fist's pads reach ahead of the point a push aims at, at first contact
#: (the press's ``contact`` of 1.6 cm and the 1 cm the aim lies off the door's middle plane)
PAD_REACH = 0.026
#: how long (s) at most the plan waits for the door hand to come back to the body
HAND_BACK = 2.0
#: how far (m) the pelvis keeps inside an open base-cabinet door's plane (the torso and
#: the other arm)
DOOR_CLEARANCE = 0.36
#: how far (m) the arms keep from an open door's inner face (:meth:`DoorSkills.keep_arms_clear_of_open_door`)
ARM_DOOR_CLEARANCE = 0.03
#: orientation costs while taking a door's upright handle (the yaw about the bar is held too)
HANDLE_ALIGN = np.array([1.5, 0.8, 2.0])


class DoorSkills(Expert):
    """An :class:`Expert` that opens and closes hinged doors of furniture props."""

    def open_cabinet_door(self, prop: str, key: str, keep_clear: bool = True) -> Script:
        """Open a base cabinet's door to its stop with the hand on its free-edge side (noted
        as the first of the demo's ``hands``), and wait until that hand is back at the body
        before anything else moves; with ``keep_clear`` the body then keeps out of the open
        door (:meth:`keep_clear_of_open_door`)."""
        side = self.door_side(prop, key)
        self.choices["hands"] = [f"{prop}/{key}:{SIDE_NAMES[side]}"]
        yield from self.door(side, prop, key, 1.0, push_past=DOOR_PUSH_PAST)
        if keep_clear:
            self.keep_clear_of_open_door(prop, key)
        end = self.time + HAND_BACK
        while self.hands[side] is not None and self.time < end:
            yield

    def door_side(self, prop: str, key: str) -> int:
        """The hand on the door's free-edge side is the natural one for a base-cabinet door."""
        p = self.env.props[prop]
        hinge = self.data.xanchor[p.joint_ids[p.joint_index(key)]]
        centre = self.data.xpos[p.root_body_id]
        left = np.cross([0.0, 0.0, 1.0], self.module_facing(prop))
        return LEFT if (hinge - centre) @ left > 0.0 else RIGHT

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
        panel = self._door_panel(body)
        centre, half = self.model.geom_pos[panel], self.model.geom_size[panel]
        frame = self.data.xmat[body].reshape(3, 3)
        origin = self.data.xpos[body]
        local = np.array([centre[0], centre[1] + sign * half[1], 0.0])
        point = origin + frame @ local
        # on the panel, a hand's breadth from its top and bottom
        low, high = origin[2] + centre[2] - half[2] + 0.06, origin[2] + centre[2] + half[2] - 0.07
        point[2] = float(np.clip(height, low, high))
        return point, frame[:, 1] * sign, -frame[:, 0]

    def _door_panel(self, body: int) -> int:
        """The door's panel: its door body's largest box geom."""
        boxes = [
            g
            for g in range(self.model.ngeom)
            if self.model.geom_bodyid[g] == body and self.model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX
        ]
        return max(boxes, key=lambda g: float(np.prod(self.model.geom_size[g])))

    def door(
        self,
        side: int,
        prop: str,
        key: str,
        goal: float,
        base: bool = True,
        attempts: int = 3,
        push_past: float = 2.5 * OVERSHOOT,
        margin: float = DONE_MARGIN,
        relax: bool = True,
    ) -> Script:
        """Open or close one hinged door with one hand.

        Opening: pull the handle part of the way, let go, and push the door's inner face
        round to fully open. Closing: push the outer face near the free edge round to
        shut. A door that did not get there gets another push (a correction).
        ``base=False``: the base stays where it is (the other hand may be busy too).
        ``push_past``: how far (normalised) past the goal the push aims; a door that opens
        to its stop needs little (an arm pressing on against a stopped door strains).
        ``margin``: how near the goal (normalised) is near enough (a door that only has to
        be out of the way need not be opened all the way). ``relax``: the arm relaxes
        once the door is there (else the hand stays where it let go, for the caller to
        take it away).
        """
        follow = 0.4 if base else 0.0
        switch = float(np.clip(self.rng.normal(0.5, 0.05), 0.4, 0.6))
        keep_out = self.keep_out_of_sweep(prop, key) if base else None
        try:
            yield from self._door_attempts(
                side, prop, key, goal, base, follow, switch, attempts, push_past, margin, relax
            )
        finally:
            if keep_out is not None:
                planes = self.ik.base_region.planes
                planes[:] = [plane for plane in planes if plane is not keep_out]

    def keep_clear_of_open_door(self, prop: str, key: str, clearance: float = DOOR_CLEARANCE) -> None:
        """The open door stands out from its hinge towards the robot: keep the body on
        the cabinet's side of it (a half-plane ``clearance`` inside the hinge)."""
        p = self.env.props[prop]
        hinge = self.data.xanchor[p.joint_ids[p.joint_index(key)]].copy()
        facing = self.module_facing(prop)
        outward = hinge - self.data.xpos[p.root_body_id]
        outward -= facing * (outward @ facing)
        outward[2] = 0.0
        self.keep_base_behind(hinge, outward / np.linalg.norm(outward), clearance)

    def keep_arms_clear_of_open_door(self, prop: str, key: str, clearance: float = ARM_DOOR_CLEARANCE) -> None:
        """Keep both arms (elbow, forearm, wrist) ``clearance`` off the open door's inner
        face, as it stands now: crouched beside it, the IK swung the elbow out into the
        door, which then held the arm while the hand was carried on."""
        p = self.env.props[prop]
        body = int(self.model.site_bodyid[p.site_id(f"{key}_handle")])
        panel = self._door_panel(body)
        frame = self.data.geom_xmat[panel].reshape(3, 3)
        thin = int(np.argmin(self.model.geom_size[panel]))
        normal = frame[:, thin].copy()
        centre = self.data.geom_xpos[panel]
        if normal @ (self.data.xpos[p.root_body_id] - centre) > 0.0:
            normal = -normal  # away from the cabinet's middle, where the arms work
        b = float(normal @ centre) - float(self.model.geom_size[panel][thin]) - clearance
        for side in (LEFT, RIGHT):
            self.ik.arm_planes.planes.append((side, normal, b))

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

    def _door_attempts(self, side, prop, key, goal, base, follow, switch, attempts, push_past, margin, relax) -> Script:
        for attempt in range(attempts):
            state = self.joint_state(prop, key)
            if abs(state - goal) < margin:
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
                    [side], prop, key, 1.0 + push_past, base_follow=follow, orientation_cost=FIRM * 0.3
                )
            else:
                direction = yield from self.press_door(side, prop, key, inner=False, base=base)
                yield from self.drag([side], prop, key, -push_past, base_follow=follow, orientation_cost=FIRM * 0.3)
            done = abs(self.joint_state(prop, key) - goal) < margin
            yield from self.release(side, back=0.08, away=-direction, relax=done and relax)

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
        standoff = 0.08
        side_now = float(np.sign((hand - edge) @ front))
        if (side_now > 0.0) == inner:  # on the other side: round the free edge, well clear of it
            clear = 0.15 + abs(self.human.jitter(0.02))
            up = np.array([0.0, 0.0, 0.02])
            standoff = ROUND_EDGE_STANDOFF
            behind = side_now * front * (standoff + 0.03)
            via = [edge + out * clear + side_now * front * 0.06 + up, edge + out * clear - behind + up]
        standoff = self.room_in_front(prop, key, point, direction, standoff)
        stance = None
        if base:
            distance = 0.45 if handle[2] < 1.2 else (0.62 if inner else 0.5)
            stance = self.stance(side, point, facing, distance=distance, lateral=0.15)
        yield from self.press(
            side, point, direction, base_goal=stance, via=via, fingers=fingers, contact=0.016, depth=0.012,
            standoff=standoff,
        )  # fmt: skip
        return direction

    def room_in_front(self, prop: str, key: str, point: np.ndarray, direction: np.ndarray, standoff: float) -> float:
        """``standoff``, or less where a fist that far back from ``point`` (pushing along
        ``direction``) would be less than ``FRONT_MARGIN`` in front of the furniture's front:
        behind a door opened only part of the way, there is little room."""
        p = self.env.props[prop]
        hinge = self.data.xanchor[p.joint_ids[p.joint_index(key)]]
        facing = self.module_facing(prop)
        into = float(-direction @ facing)  # how much of a step back from the door goes into the furniture
        if into <= 1e-6:
            return standoff
        room = (-(point - hinge) @ facing - FRONT_MARGIN) / into - PAD_REACH
        return float(np.clip(room, 0.02, standoff))

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


__all__ = ["DoorSkills"]
