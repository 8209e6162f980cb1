"""Cookware demonstrators (scene cabinet_hob): the saucepan from the cabinet onto the hob,
and the saucepan and the frying pan from the hob into the cabinet.

What a person does: opens the cabinet door (pulls the handle, pushes the door round) and
keeps clear of it. To take a pot out, they crouch in front of the open cabinet with the
free hand at the hip, reach in under the counter and take the pot by its handle (the
fingers close above and below it; the hand has no wrist pitch, so it comes down onto the
handle along the forearm), lift it off the shelf a little, draw it straight out, stand
up, hold it level over a burner, lower it until it is felt to rest, let go and draw the
hand back. To put pots away, they take each from the hob by its handle (fingers
half-closed, the handle being close above the hob), back away until it is clear of the
counter, crouch until it hangs just above the shelf's height, carry it in, and put it
down: the first at the back of the shelf, the second in front of it. A pot held by its
handle hangs tilted in the fingers and comes to rest on its low edge first: the hand goes
on down until it lies flat before letting go.

Choices drawn per demo: the burner (saucepan_to_hob), which pot first (mostly the one on
the front burner; store_kitchenware), where along the handle the fingers close, where the
base stands, how far the door is pulled before the hand changes grip (door skill). The
hands follow the handles: the left for a handle pointing left, the right for ones
pointing right.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.experts.doors import DoorSkills
from bigym.experts.expert import ALIGN_BAR, FREE, LEFT, RIGHT, SIDE_NAMES, Script
from bigym.experts.geometry import yaw_matrix
from bigym.experts.grasping import (
    EMPTY_GRIP,
    HOLD,
    MAX_SETTLE,
    SETTLE_DISTANCE,
    GraspingExpert,
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
#: on the hob, further out, where the handle is higher above the hob: the fingers' links
#: reach below the pinch
HOB_GRIP = 0.09
#: a pot's handle rises this much (rad) from the rim outwards (``bigym/props/cookware.py``)
HANDLE_RISE = 0.18
#: how steeply (rad below the horizontal) the hand comes down onto a handle in the cabinet,
#: and onto one on the hob (less: the open fingers would touch the hob)
HANDLE_TILT = 0.4
HOB_TILT = 0.15
#: how far the fingers are pre-closed for a handle on the hob: wide open, the lower finger
#: would touch the hob under it
HOB_OPENING = 0.45
#: a pan is lifted this far (m) off the shelf before it is drawn out
SHELF_LIFT = 0.03
#: how often the pot on the front burner is taken first
FRONT_FIRST = 0.8
#: how high (m) a pot is lifted off the hob
HOB_LIFT = 0.06
#: the shelf inside the cabinet: its front and back edges (x) and its top
SHELF_FRONT = 0.64
SHELF_BACK = 1.18
SHELF_TOP = 0.48
#: how far (m) a pot is kept from the shelf's edges and from the other pot
SHELF_MARGIN = 0.03
#: how far (m) the pelvis stands behind a handle on the hob, and how high
HOB_REACH = 0.4
HOB_STANCE_HEIGHT = 0.88
#: how far (m) the pelvis stays behind the pinch point when reaching into the cabinet
CABINET_REACH = 0.5
#: how far (m) above the shelf a pot's bottom is carried in
ENTRY_HEIGHT = 0.05
#: a pot's rim juts out past its base's radius by up to this (m)
POT_RIM = 0.015
#: the shelf's half width (m, inside the walls), and the least y of a pot's centre
SHELF_HALF_WIDTH = 0.28
SHELF_SIDE_GAP = 0.0
#: the least y (m) of the right hand's pinch in the cabinet: the body keeps clear of the open door
HAND_MIN_Y = -0.12
#: how far (m) the hand goes on down after a pot rests on its low edge, to lay it flat
TIP_DOWN = 0.1
#: the burners the saucepan is put on: the front two (the arm reaches the back ones, but
#: only the front ones have been tried)
FRONT_BURNERS = ("hob_site_1", "hob_site_2")


class PotHandles(GraspingExpert):
    """Taking a pot by its handle and keeping what it holds level: shared by the experts that
    carry pots (``CookwareExpert``, ``SandwichToastExpert``)."""

    def hob_handle(self, pot: str, side: int, front: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """How to take a pot standing on the hob by its handle with hand ``side``: where the
        fingers close, the handle's direction, the hand's approach (across the handle, away
        from the robot), and where the pelvis stands for it (x, y, height, yaw): about
        ``HOB_REACH`` behind the handle but no nearer the counter than ``front`` (x), beside
        it on the hand's side."""
        frame = self.data.xmat[self.env.props[pot].root_body_id].reshape(3, 3)
        along = frame[:, 0].copy()  # the handle points along the pot's +x
        handle = self.handle_grip(pot, along, HOB_GRIP)
        approach = np.cross([0.0, 0.0, 1.0], along)
        approach[2] = 0.0
        approach *= np.sign(approach[0]) / np.linalg.norm(approach)  # away from the robot
        lateral = 0.2 if side == LEFT else -0.2
        stance = np.array(
            [
                min(front, handle[0] - HOB_REACH) - abs(self.human.jitter(0.02)),
                handle[1] - lateral + self.human.jitter(0.03),
                HOB_STANCE_HEIGHT + self.human.jitter(0.02),
                self.human.jitter(0.05),
            ]
        )
        return handle, along, approach, stance

    def handle_grip(self, pot: str, along: np.ndarray, out: float = HANDLE_GRIP) -> np.ndarray:
        """Where the fingers close on a pot's handle: ``out`` metres out from the rim (near
        the pot, its weight twists the handle less between the fingers); on the handle's
        axis, which rises as it goes out."""
        prop = self.env.props[pot]
        origin = self.data.xpos[prop.root_body_id]
        site = self.site(pot, "handle")
        horizontal = np.array([along[0], along[1], 0.0]) / np.linalg.norm(along[:2])
        out = prop.radius + POT_RIM + out + self.human.jitter(0.01)
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
        opening: float = 0.0,
    ) -> Script:
        """Take a pot's handle (the fingers closing across its flat sides, the hand coming
        down onto it ``tilt`` rad below the horizontal), trying again if the fingers closed
        on nothing, and lift it ``lift`` metres. ``opening``: how far the fingers are
        pre-closed (a handle close above a surface)."""
        tilt = tilt + self.human.jitter(0.08)
        if np.cross(bar, approach)[2] > 0.0:  # the tilt turns the approach about the bar: downwards
            bar = -bar
        for attempt in range(3):
            if attempt:  # closed on nothing: open, back off a little, and go in again
                self.note(f"take the handle again ({attempt})")
                yield from self.release(side, back=0.04, up=0.0)
            yield from self.grasp_bar(side, handle, bar, approach, tilt=tilt, depth=0.0, close=False, opening=opening)
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

    def flat(self, body: int) -> np.ndarray:
        """A body's orientation turned level, keeping its heading."""
        frame = self.data.xmat[body].reshape(3, 3)
        return yaw_matrix(float(np.arctan2(frame[1, 0], frame[0, 0])))


class CookwareExpert(PotHandles, DoorSkills):
    """Moves the pots of ``SaucepanToHob`` and ``StoreKitchenware`` between cabinet and hob."""

    tasks = ("SaucepanToHob", "StoreKitchenware")
    pace: ClassVar[dict[str, float]] = {"SaucepanToHob": 1.2}

    def plan(self) -> Script:
        yield from self.wait(self.human.reaction())
        yield from self.open_cabinet_door(CABINET, DOOR)
        if self.env.task_name == "SaucepanToHob":
            yield from self.saucepan_to_hob()
        else:
            yield from self.store_kitchenware()
        while True:
            yield

    def saucepan_to_hob(self) -> Script:
        side = LEFT  # the handle points to the robot's left
        self.choices["hands"].append(f"saucepan:{SIDE_NAMES[side]}")
        burner = FRONT_BURNERS[int(self.rng.integers(len(FRONT_BURNERS)))]
        self.choices["burner"] = burner
        yield from self.take_from_cabinet(side, "saucepan")
        yield from self.draw_out(side, "saucepan")
        yield from self.put_on_burner(side, "saucepan", burner)
        self.relax_arm(side)
        self.relax_arm(1 - side)

    def store_kitchenware(self) -> Script:
        side = RIGHT  # the handles point to the robot's right
        pots = list(self.env.objects)
        front = min(pots, key=lambda pot: self.data.xpos[self.env.props[pot].root_body_id][0])
        order = [front] + [p for p in pots if p != front]
        if self.rng.random() > FRONT_FIRST:
            order.reverse()
        self.choices["order"] = order
        self.choices["hands"] += [f"{pot}:{SIDE_NAMES[side]}" for pot in order]
        for index, pot in enumerate(order):
            yield from self.take_from_hob(side, pot)
            # the first pot goes to the back of the shelf, the second in front of it
            yield from self.put_in_cabinet(side, pot, deep=index == 0)
        self.relax_arm(side)
        self.relax_arm(1 - side)

    # ------------------------------------------------------------------ steps
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

    def take_from_hob(self, side: int, pot: str) -> Script:
        """Step up to the hob and take the pot by its handle, lifting it off the burner."""
        handle, along, approach, stance = self.hob_handle(pot, side, CABINET_FRONT - FRONT_CLEARANCE)
        self.note(f"to the hob for {pot}")
        yield from self.until(self.move_base(stance))
        lift = HOB_LIFT + abs(self.human.jitter(0.01))
        # a draw the shipped demos were made with (for a via point over the counter's edge
        # that never reached the hand): kept so that they regenerate byte for byte
        self.human.jitter(0.02)
        yield from self.take_handle(side, pot, handle, along, approach, lift, tilt=HOB_TILT, opening=HOB_OPENING)

    def put_in_cabinet(self, side: int, pot: str, deep: bool) -> Script:
        """Back away from the hob with the pot, crouch until it hangs just above the shelf's
        height, carry it in under the counter, and put it down level on the shelf: at the
        back (``deep``) or in front of the pot already there."""
        prop = self.env.props[pot]
        body = prop.root_body_id
        radius = prop.radius + POT_RIM
        offset = self.held_offset(side, body)  # the pinch from the pot's origin
        if deep:
            x = SHELF_BACK - radius - SHELF_MARGIN - abs(self.human.jitter(0.01))
        else:
            placed = [p for p in self.env.objects if p != pot]
            other = self.env.props[placed[0]]
            x = self.data.xpos[other.root_body_id][0] - other.radius - POT_RIM - radius - SHELF_MARGIN
            x = max(x - abs(self.human.jitter(0.01)), SHELF_FRONT + radius + 0.01)
        # the pinch far enough left that the body stays clear of the open door
        y = max(SHELF_SIDE_GAP, HAND_MIN_Y - offset[1]) + abs(self.human.jitter(0.01))
        y = min(y, SHELF_HALF_WIDTH - radius - 0.01)
        spot = np.array([x, y, SHELF_TOP])
        self.choices.setdefault("shelf", []).append(f"{pot}:{'back' if deep else 'front'}")
        base = self.commanded_base()
        # back off until the pot is clear of the counter's front edge
        pot_x = self.data.xpos[body][0]
        back = base.copy()
        back[0] -= max(0.0, pot_x + radius + 0.05 - (CABINET_FRONT - 0.03)) + abs(self.human.jitter(0.02))
        self.note(f"back off with {pot}")
        yield from self.walk([back], carrying=[side])
        # the free hand to the hip, then down until the pot hangs just above the shelf's height
        self.hand_to_hip(1 - side)
        down = back.copy()
        # the pot hangs tilted from its handle: its low edge must clear the shelf's front
        frame = self.data.xmat[body].reshape(3, 3)
        lowest = self.data.xpos[body][2] - radius * float(np.linalg.norm(frame[2, :2]))
        down[2] = float(np.clip(back[2] - (lowest - (SHELF_TOP + ENTRY_HEIGHT)), 0.42, back[2]))
        self.note("crouch")
        yield from self.walk([down], carrying=[side])
        # in under the counter: the arm reaches, the body follows as far as the cabinet lets it
        pinch_goal = spot + offset
        inside = down.copy()
        inside[0] = min(CABINET_FRONT - FRONT_CLEARANCE, pinch_goal[0] - CABINET_REACH) - abs(self.human.jitter(0.02))
        inside[1] = pinch_goal[1] - (0.2 if side == LEFT else -0.2) + self.human.jitter(0.02)
        inside[3] = self.human.jitter(0.05)  # square to the cabinet
        self.note("in")
        yield from self.walk([inside], carrying=[side])
        yield from self.place(side, spot, prop=pot, level=False, orientation=self.flat(body), tip_down=TIP_DOWN)
        # the open hand out of the cabinet, under the counter's edge
        p, r = self.hand_pose(side)
        out = np.array([CABINET_FRONT - 0.12, p[1], min(p[2], COUNTER_UNDERSIDE - 0.15)])
        yield from self.until(self.move_hand(side, out, r, FREE, spread=0.2, precision=0.05))
        up = self.commanded_base()
        up[0] = min(up[0], CABINET_FRONT - FRONT_CLEARANCE - 0.05)
        up[2] = HOB_STANCE_HEIGHT
        self.note("stand up")
        yield from self.walk([up], carrying=[side])

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
        level = self.flat(body)
        offset = self.held_offset(side, body)
        base = self.commanded_base()
        stance = self.stance_for(side, spot + np.array([0.0, 0.0, 0.03]) + offset, base[3])
        stance[0] = min(stance[0], CABINET_FRONT - FRONT_CLEARANCE)
        up = base.copy()
        up[2] = stance[2]
        self.note("stand up")
        yield from self.walk([up, stance], carrying=[side])
        yield from self.place(side, spot, prop=pot, level=False, orientation=level, tip_down=TIP_DOWN)


__all__ = ["CookwareExpert", "PotHandles"]
