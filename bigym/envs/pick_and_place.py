"""Pick-and-place tasks: cups, a box and cookware between counter, cabinets and hob.

Every object starts at rest (placed on its support, no drop). "Touches" means an
active contact between a collision geom of the object and a geom of the named part;
"not held" means no gripper geom touches the object. Exact success criteria:

* ``PutCups`` (scene ``counter_base_wall_1x1``): each of the 2 mugs touches the wall
  cabinet's ``shelf_bottom`` or its middle ``shelf``, and is not held.
* ``TakeCups`` (same scene): each of the 2 mugs touches the base cabinet's ``counter``,
  and is not held.
* ``PickBox`` (scene ``cabinet_door``): the box touches the cabinet's ``counter`` and is
  not held.
* ``StoreBox`` (scene ``cabinet_door``): the box touches the cabinet's middle ``shelf``
  and is not held.
* ``SaucepanToHob`` (scene ``cabinet_hob``): the saucepan touches the ``hob`` and is not
  held.
* ``StoreKitchenware`` (scene ``cabinet_hob``): the saucepan and the frying pan both
  touch the cabinet's middle ``shelf``, and neither is held.

No orientation is required (the paper's detectors check none for these tasks).
Failure: a task object (mug, box, saucepan, pan) touches the floor, except in
``PickBox`` whose box starts on the floor; and, as for every task, the robot leaving
its workspace.

Doors: every door starts closed, up to a random gap of 0.03 (normalised, about 3
degrees), as in the reference, so opening the door is part of the tasks whose objects
start or end behind one (the glass wall cabinet in ``PutCups``/``TakeCups``, the base
cabinet's door in ``StoreBox``, ``SaucepanToHob`` and ``StoreKitchenware``).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.task import KitchenTask
from bigym.props import FryingPan, LargeBox, Mug, Prop, Saucepan
from bigym.props.base import quat_euler, quat_yaw

#: top surfaces (world z) of the supports in the scenes used here
COUNTER_TOP = 0.86
HOB_TOP = 0.87
BASE_SHELF_TOP = 0.48
WALL_SHELF_BOTTOM_TOP = 1.47
#: clearance left under an object placed on a support (it settles by this much)
CLEARANCE = 0.0005
#: closed doors start with a random gap of up to this (normalised)
DOOR_GAP = 0.03


def grid_points(
    rng: np.random.Generator,
    amount: int,
    center: tuple[float, float],
    shape: tuple[int, int],
    step: float,
    jitter: tuple[float, float],
) -> np.ndarray:
    """``amount`` distinct points of a centred ``shape`` (nx, ny) grid of pitch ``step``
    around ``center`` (x, y), each moved by a uniform offset within ``±jitter``."""
    nx, ny = shape
    xs = (np.arange(nx) - (nx - 1) / 2.0) * step + center[0]
    ys = (np.arange(ny) - (ny - 1) / 2.0) * step + center[1]
    grid = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1).reshape(-1, 2)
    chosen = grid[rng.choice(len(grid), size=amount, replace=False)]
    return chosen + rng.uniform(-1.0, 1.0, (amount, 2)) * np.asarray(jitter)


class _PickPlaceTask(KitchenTask):
    """Move every prop of ``objects`` until it touches one of ``targets`` and let go."""

    robot_start: ClassVar[tuple[float, float, float]] = (0.0, 0.0, 0.0)
    robot_start_noise: ClassVar[tuple[float, float, float]] = (0.05, 0.05, 0.08)
    #: the free props to move
    objects: ClassVar[tuple[str, ...]] = ()
    #: (prop, part) pairs any of which an object must touch
    targets: ClassVar[tuple[tuple[str, str], ...]] = ()
    #: (prop, joint keys) of doors that start closed (with a small random gap)
    doors: ClassVar[tuple[tuple[str, tuple[str, ...]], ...]] = ()

    def _setup(self) -> None:
        self.target_mask = self.union(*(self.mask(prop, part) for prop, part in self.targets))
        self._object_masks = [self.mask(name) for name in self.objects]

    def _on_reset(self) -> None:
        for prop, keys in self.doors:
            for key in keys:
                self.props[prop].set_joint_state(self.data, key, self.np_random.uniform(0.0, DOOR_GAP))
        self._place_objects()

    def _place_objects(self) -> None:
        raise NotImplementedError

    def object_placed(self, name: str) -> bool:
        """``name`` touches a target part and no gripper touches it."""
        return self.touching(self.mask(name), self.target_mask) and not self.held(name)

    def _success(self) -> bool:
        # object_placed for every object, on the geom sets resolved in _setup (run every step)
        touching, target, grippers = self.contacts.touching, self.target_mask, self.gripper_mask
        for mask in self._object_masks:
            if not touching(mask, target) or touching(mask, grippers):
                return False
        return True


# --------------------------------------------------------------------------- cups
class _CupsTask(_PickPlaceTask):
    scene_name = "counter_base_wall_1x1"
    objects = ("mug_1", "mug_2")
    fail_on_floor = ("mug_1", "mug_2")
    doors = (("wall_cabinet", ("door_right", "door_left")),)
    # Spawn: a 1 x 3 grid (y pitch 0.15) around (x, 0) on the surface at z, +-3 cm xy;
    # upright, handle towards the robot (yaw 180 deg) +-30 deg.
    spawn: ClassVar[tuple[float, float, float]] = (0.8, 0.0, COUNTER_TOP)
    GRID_STEP = 0.15
    GRID_JITTER = (0.03, 0.03)
    YAW = np.pi
    YAW_RANGE = np.deg2rad(30.0)

    def _task_props(self) -> dict[str, Prop]:
        return {"mug_1": Mug("mug_1", seed=1), "mug_2": Mug("mug_2", seed=2)}

    def _place_objects(self) -> None:
        rng = self.np_random
        x, y, z = self.spawn
        points = grid_points(rng, len(self.objects), (x, y), (1, 3), self.GRID_STEP, self.GRID_JITTER)
        for name, (px, py) in zip(self.objects, points):
            yaw = self.YAW + rng.uniform(-self.YAW_RANGE, self.YAW_RANGE)
            self.props[name].set_pose(self.data, (px, py, z + CLEARANCE), quat_yaw(yaw))


class PutCups(_CupsTask):
    """Open the glass wall cabinet and put both mugs from the counter on its shelf."""

    time_limit = 21.0
    targets = (("wall_cabinet", "shelf_bottom"), ("wall_cabinet", "shelf"))


class TakeCups(_CupsTask):
    """Open the glass wall cabinet and take both mugs out onto the counter."""

    time_limit = 26.0
    targets = (("cabinet", "counter"),)
    spawn = (1.05, 0.0, WALL_SHELF_BOTTOM_TOP)


# --------------------------------------------------------------------------- box
class _BoxTask(_PickPlaceTask):
    scene_name = "cabinet_door"
    objects = ("box",)
    doors = (("cabinet", ("door_left",)),)

    def _task_props(self) -> dict[str, Prop]:
        return {"box": LargeBox("box")}


class PickBox(_BoxTask):
    """Lift the box standing on the floor beside the cabinet onto the counter."""

    time_limit = 33.0
    targets = (("cabinet", "counter"),)
    # the box starts on the floor: touching it is no failure here
    fail_on_floor = ()
    # On its 0.20 x 0.12 end (long axis vertical, as the reference's Ry(90 deg) * Rx(a)),
    # at (0.8, -1) +-3 cm, spun about the vertical by U(+-180 deg).
    SPAWN_XY = (0.8, -1.0)
    JITTER = 0.03

    def _place_objects(self) -> None:
        rng = self.np_random
        xy = np.asarray(self.SPAWN_XY) + rng.uniform(-self.JITTER, self.JITTER, 2)
        roll = rng.uniform(-np.pi, np.pi)
        # Rx(roll) first (about the long axis), then Ry(90 deg): the long axis points down.
        quat = quat_euler(roll=roll, pitch=np.pi / 2)
        half_long = LargeBox.SIZE[0] / 2.0
        self.props["box"].set_pose(self.data, (xy[0], xy[1], half_long + CLEARANCE), quat)


class StoreBox(_BoxTask):
    """Open the cabinet door and put the box from the counter on the shelf inside."""

    time_limit = 36.0
    targets = (("cabinet", "shelf"),)
    fail_on_floor = ("box",)
    # Flat on the counter at (0.8, 0) +-3 cm, yaw U(+-180 deg).
    SPAWN_XY = (0.8, 0.0)
    JITTER = 0.03

    def _place_objects(self) -> None:
        rng = self.np_random
        xy = np.asarray(self.SPAWN_XY) + rng.uniform(-self.JITTER, self.JITTER, 2)
        yaw = rng.uniform(-np.pi, np.pi)
        half_height = LargeBox.SIZE[2] / 2.0
        self.props["box"].set_pose(self.data, (xy[0], xy[1], COUNTER_TOP + half_height + CLEARANCE), quat_yaw(yaw))


# --------------------------------------------------------------------------- cookware
class _CookwareTask(_PickPlaceTask):
    scene_name = "cabinet_hob"
    doors = (("cabinet", ("door_left",)),)


class SaucepanToHob(_CookwareTask):
    """Open the cabinet door, take the saucepan off the shelf and put it on the hob."""

    time_limit = 27.0
    objects = ("saucepan",)
    targets = (("cabinet", "hob"),)
    fail_on_floor = ("saucepan",)
    # On the shelf at (0.85, 0) + (+-4 cm, +-3 cm), handle to the robot's left (yaw
    # 90 deg) +-20 deg: the handle tip stays >= 1 cm clear of the side wall.
    SPAWN_XY = (0.85, 0.0)
    JITTER = (0.04, 0.03)
    YAW = np.pi / 2
    YAW_RANGE = np.deg2rad(20.0)

    def _task_props(self) -> dict[str, Prop]:
        return {"saucepan": Saucepan("saucepan")}

    def _place_objects(self) -> None:
        rng = self.np_random
        xy = np.asarray(self.SPAWN_XY) + rng.uniform(-1.0, 1.0, 2) * np.asarray(self.JITTER)
        yaw = self.YAW + rng.uniform(-self.YAW_RANGE, self.YAW_RANGE)
        self.props["saucepan"].set_pose(self.data, (xy[0], xy[1], BASE_SHELF_TOP + CLEARANCE), quat_yaw(yaw))


class StoreKitchenware(_CookwareTask):
    """Open the cabinet door and put the saucepan and the frying pan from the hob on the shelf."""

    time_limit = 48.0
    objects = ("saucepan", "pan")
    targets = (("cabinet", "shelf"),)
    fail_on_floor = ("saucepan", "pan")
    # On the two +y burners (hob sites 1 front and 3 back) in random order, +-2 cm xy,
    # handles across the free half of the hob (yaw -90 deg) +-30 deg.
    SITES = ("hob_site_1", "hob_site_3")
    JITTER = 0.02
    YAW = -np.pi / 2
    YAW_RANGE = np.deg2rad(30.0)

    def _task_props(self) -> dict[str, Prop]:
        return {"saucepan": Saucepan("saucepan"), "pan": FryingPan("pan")}

    def _place_objects(self) -> None:
        rng = self.np_random
        cabinet = self.props["cabinet"]
        order = rng.permutation(len(self.SITES))
        for name, k in zip(self.objects, order):
            site = cabinet.site_pos(self.data, self.SITES[k])
            xy = site[:2] + rng.uniform(-self.JITTER, self.JITTER, 2)
            yaw = self.YAW + rng.uniform(-self.YAW_RANGE, self.YAW_RANGE)
            self.props[name].set_pose(self.data, (xy[0], xy[1], HOB_TOP + CLEARANCE), quat_yaw(yaw))


__all__ = ["PickBox", "PutCups", "SaucepanToHob", "StoreBox", "StoreKitchenware", "TakeCups"]
