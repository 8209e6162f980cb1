"""Cookware demonstrators: the saucepan from the cabinet onto the hob (scene cabinet_hob).

What a person does: opens the cabinet door, crouches in front of the open cabinet, reaches
in under the counter and takes the saucepan by its handle (fingers closing above and
below it, the hand coming in from the front), lifts it off the shelf a little, draws it
straight out, stands up with it, holds it level over a burner, lowers it until it is
felt to rest, lets go and draws the hand back.

Choices drawn per demo: the burner, where along the handle the fingers close, where the
base stands, how far the door is pulled before the hand changes grip (door skill).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.experts.doors import DoorSkills
from bigym.experts.expert import ALIGN_BAR, FREE, LEFT, HandReference, Script
from bigym.experts.geometry import yaw_matrix
from bigym.experts.grasping import (
    EMPTY_GRIP,
    HOLD,
    MAX_SETTLE,
    SETTLE_DISTANCE,
    GraspingExpert,
    from_base,
    to_base,
)

CABINET = "cabinet"
DOOR = "door_left"
#: x of the cabinet's front (its door's outer face, closed) and of the counter's underside
CABINET_FRONT = 0.6
COUNTER_UNDERSIDE = 0.83
#: how far (m) the pelvis keeps from the cabinet's front while working at it
FRONT_CLEARANCE = 0.14
#: how low (m) the pelvis goes to reach into the cabinet: the shoulders below the counter
CROUCH = 0.47
#: the fingers close this far (m) out along the handle from the pot's rim
HANDLE_GRIP = 0.05
#: a pot's handle rises this much (rad) from the rim outwards (``bigym/props/cookware.py``)
HANDLE_RISE = 0.18
#: how steeply (rad below the horizontal) the hand comes down onto a handle in the cabinet
HANDLE_TILT = 0.4
#: a pan is lifted this far (m) off the shelf before it is drawn out
SHELF_LIFT = 0.03
#: the door opens to its stop: the push aims only this far (normalised) past it
DOOR_PUSH_PAST = 0.03
#: how far (m) the pelvis keeps inside an open door's plane (the torso and the other arm)
DOOR_CLEARANCE = 0.36
#: a pot's rim juts out past its base's radius by up to this (m)
POT_RIM = 0.015
#: where a free hand waits beside the hip (base frame, the left hand's; the right one
#: mirrored), out of the way of the furniture when crouching close to it
HAND_AT_HIP = np.array([0.0, 0.24, 0.15])
#: the burners the saucepan is put on: the front two (the arm reaches the back ones, but
#: only the front ones have been tried)
FRONT_BURNERS = ("hob_site_1", "hob_site_2")


class CookwareExpert(GraspingExpert, DoorSkills):
    """Takes the saucepan of ``SaucepanToHob`` out of the cabinet and puts it on the hob."""

    tasks = ("SaucepanToHob",)
    pace: ClassVar[dict[str, float]] = {"SaucepanToHob": 1.2}

    def plan(self) -> Script:
        yield from self.wait(self.human.reaction())
        door_side = self.door_side(CABINET, DOOR)
        self.choices["hands"] = [f"{CABINET}/{DOOR}:{_name(door_side)}"]
        yield from self.door(door_side, CABINET, DOOR, 1.0, push_past=DOOR_PUSH_PAST)
        self.keep_clear_of_open_door(CABINET, DOOR)
        # the door hand comes back to the body before anything else moves
        end = self.time + 2.0
        while self.hands[door_side] is not None and self.time < end:
            yield
        yield from self.saucepan_to_hob()
        while True:
            yield

    def saucepan_to_hob(self) -> Script:
        side = LEFT  # the handle points to the robot's left
        self.choices["hands"].append(f"saucepan:{_name(side)}")
        burner = FRONT_BURNERS[int(self.rng.integers(len(FRONT_BURNERS)))]
        self.choices["burner"] = burner
        yield from self.take_from_cabinet(side, "saucepan")
        yield from self.draw_out(side, "saucepan")
        yield from self.put_on_burner(side, "saucepan", burner)
        self.relax_arm(side)
        self.relax_arm(1 - side)

    # ------------------------------------------------------------------ steps
    def keep_clear_of_open_door(self, prop: str, key: str) -> None:
        """The open door stands out from its hinge towards the robot: keep the body on
        the cabinet's side of it (a half-plane ``DOOR_CLEARANCE`` inside the hinge)."""
        p = self.env.props[prop]
        hinge = self.data.xanchor[p.joint_ids[p.joint_index(key)]].copy()
        facing = self.module_facing(prop)
        outward = hinge - self.data.xpos[p.root_body_id]
        outward -= facing * (outward @ facing)
        outward[2] = 0.0
        self.keep_base_behind(hinge, outward / np.linalg.norm(outward), DOOR_CLEARANCE)

    def take_from_cabinet(self, side: int, pot: str) -> Script:
        """Crouch in front of the open cabinet and take the pot by its handle."""
        prop = self.env.props[pot]
        body = prop.root_body_id
        frame = self.data.xmat[body].reshape(3, 3)
        along = frame[:, 0].copy()  # the handle points along the pot's +x
        handle = self.handle_grip(pot, along)
        bar = along
        approach = np.array([1.0, 0.0, 0.0])
        lateral = 0.2 if side == LEFT else -0.2
        stance = np.array(
            [
                CABINET_FRONT - FRONT_CLEARANCE - abs(self.human.jitter(0.02)),
                handle[1] - lateral + self.human.jitter(0.03),
                CROUCH + self.human.jitter(0.02),
                self.human.jitter(0.05),
            ]
        )
        entry = np.array([CABINET_FRONT - 0.08, handle[1], min(handle[2] + 0.06, COUNTER_UNDERSIDE - 0.12)])
        # crouch, the hand coming to the opening on the way, then in under the counter
        self.note("crouch")
        # the free hand out of the way first: it would catch on the cabinet's front
        yield from self.until(self.hand_to_hip(1 - side) - 0.2)
        ends = [
            self.move_base(stance),
            self.move_hand(
                side, entry, self.bar_grasp_rotation(side, bar, approach), ALIGN_BAR * 0.5, precision=0.05, spread=0.4
            ),
        ]
        yield from self.until(max(ends))
        # the hand has no wrist pitch: it points along the forearm, which comes down from
        # the elbow (under the counter) onto the handle
        yield from self.take_handle(side, pot, handle, bar, approach, SHELF_LIFT)

    def handle_grip(self, pot: str, along: np.ndarray) -> np.ndarray:
        """Where the fingers close on a pot's handle: ``HANDLE_GRIP`` out from the rim, near
        the pot, whose weight then twists the handle less between the fingers; on the
        handle's axis, which rises as it goes out."""
        prop = self.env.props[pot]
        origin = self.data.xpos[prop.root_body_id]
        site = self.site(pot, "handle")
        horizontal = np.array([along[0], along[1], 0.0]) / np.linalg.norm(along[:2])
        out = prop.radius + POT_RIM + HANDLE_GRIP + self.human.jitter(0.01)
        rise = np.tan(HANDLE_RISE) * float(np.linalg.norm(along[:2]))  # per metre out, with the pot's tilt
        step = out - float((site - origin) @ horizontal)
        return site + horizontal * step + np.array([0.0, 0.0, rise * step])

    def take_handle(
        self,
        side: int,
        pot: str,
        handle: np.ndarray,
        bar: np.ndarray,
        approach: np.ndarray,
        lift: float,
        tilt: float = HANDLE_TILT,
    ) -> Script:
        """Take a pot's handle (the fingers closing across its flat sides, the hand coming
        down onto it ``tilt`` rad below the horizontal), trying again if the fingers closed
        on nothing, and lift it ``lift`` metres."""
        tilt = tilt + self.human.jitter(0.08)
        if np.cross(bar, approach)[2] > 0.0:  # the tilt turns the approach about the bar: downwards
            bar = -bar
        for attempt in range(3):
            if attempt:  # closed on nothing: open, back off a little, and go in again
                self.note(f"take the handle again ({attempt})")
                yield from self.release(side, back=0.04, up=0.0)
            yield from self.grasp_bar(side, handle, bar, approach, tilt=tilt, depth=0.0, close=False)
            # the hand may be at the end of its reach: let it get there before closing
            yield from self.settle(side, handle, SETTLE_DISTANCE, MAX_SETTLE)
            yield from self.set_grip(side, 1.0)
            if float(self.env.robot.gripper_state(self.data)[side]) < EMPTY_GRIP and self.env.held(pot):
                break
        else:
            self.note(f"gave up on {pot}")
            while True:  # the demo fails and is not kept
                yield
        pinch = self.data.site_xpos[self.env.robot.pinch_site_ids[side]].copy()
        rotation = self.data.site_xmat[self.env.robot.pinch_site_ids[side]].reshape(3, 3).copy()
        self.grasp_pose[side] = to_base(self.commanded_base(), pinch, rotation)
        lifted = pinch + np.array([0.0, 0.0, lift])
        yield from self.until(self.move_hand(side, lifted, rotation, HOLD, spread=0.0, tremor=0.3, precision=0.01))

    def hand_to_hip(self, side: int) -> float:
        """Bring a free hand beside the hip, where it stays as the body moves; returns the
        end time."""
        base = self.commanded_base()
        p, r = self.hand_pose(side)
        local_p, local_r = to_base(base, p, r)
        goal = HAND_AT_HIP * np.array([1.0, 1.0 if side == LEFT else -1.0, 1.0]) + self.human.jitter(0.02, 3)
        duration = self.human.duration(float(np.linalg.norm(goal - local_p)), 0.05)
        path = self.human.path([local_p, goal], duration)
        t0 = self.time
        self.hands[side] = HandReference(
            (lambda t: from_base(self.base_ref(t), path(min(max(t - t0, 0.0), duration)), None)[0]),
            (lambda t: from_base(self.base_ref(t), None, local_r)[1]),
            FREE,
            tremor=0.5,
        )
        return t0 + duration

    def draw_out(self, side: int, pot: str) -> Script:
        """Draw the pot straight out of the cabinet, stepping back, until it is clear of the
        counter's front edge (it rises only then)."""
        prop = self.env.props[pot]
        base = self.commanded_base()
        back = base.copy()
        clear = (self.data.xpos[prop.root_body_id][0] + prop.radius + 0.08) - (CABINET_FRONT - 0.02)
        back[0] -= clear + abs(self.human.jitter(0.02))
        self.note("draw out")
        yield from self.walk([back], carrying=[side])

    def put_on_burner(self, side: int, pot: str, burner: str) -> Script:
        """Stand up with the pot, step to where the hand reaches over the burner as it
        reached the handle, and put the pot down level."""
        prop = self.env.props[pot]
        body = prop.root_body_id
        spot = self.site(CABINET, burner) + self.human.jitter(0.01, 3) * np.array([1.0, 1.0, 0.0])
        frame = self.data.xmat[body].reshape(3, 3)
        yaw = float(np.arctan2(frame[1, 0], frame[0, 0]))
        level = yaw_matrix(yaw)
        offset = self.held_offset(side, body)
        base = self.commanded_base()
        stance = self.stance_for(side, spot + np.array([0.0, 0.0, 0.03]) + offset, base[3])
        stance[0] = min(stance[0], CABINET_FRONT - FRONT_CLEARANCE)
        up = base.copy()
        up[2] = stance[2]
        self.note("stand up")
        yield from self.walk([up, stance], carrying=[side])
        yield from self.place(side, spot, prop=pot, level=False, orientation=level)


def _name(side: int) -> str:
    return "left" if side == LEFT else "right"


__all__ = ["CookwareExpert"]
