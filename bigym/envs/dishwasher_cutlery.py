"""Dishwasher cutlery tasks: load a knife and a fork into the cutlery basket, unload
them into a cutlery tray on the counter or in a drawer.

Scenes ``counter_dishwasher`` and ``counter_dishwasher_cutlery_cabinet`` (a four-drawer
cabinet at y = -1.2 whose top drawer holds a cutlery tray). The basket rides on the
bottom tray; cutlery stands in its compartments head up. The robot starts at (0, -0.6).

Success (paper, appendix; "not held": no gripper geom touches the item):

* ``DishwasherUnloadCutlery``: the knife and the fork both touch the cutlery tray on the
  counter and neither is held.
* ``DishwasherLoadCutlery``: the knife and the fork both touch the dishwasher's cutlery
  basket (``basket``) and neither is held.
* ``DishwasherUnloadCutleryLong``: the fork touches the cutlery tray in the top drawer and
  is not held, the dishwasher is closed (door and both trays within 0.1 of 0,
  normalised) and all four drawers of the cabinet are within 0.1 of closed.

Failure: the knife or the fork touches the floor.

``DishwasherUnloadCutlery`` adds the randomised pose of its tray (``cutlery_tray_pose``)
to the privileged information. The mug of ``DishwasherLoadCutlery`` is free: the
cutlery leans in it against the rim.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.dishwasher_plates import CLOSED, COUNTER_TOP, DISHWASHER, OPEN, DishwasherItemsTask
from bigym.props import CutleryTray, Fork, Knife, Mug, Prop
from bigym.props.base import quat_axis_angle, quat_mul, quat_yaw

#: cutlery (along local +y, head at +y) standing head up
HEAD_UP = quat_axis_angle((1.0, 0.0, 0.0), np.pi / 2)
ITEM_CLASSES: dict[str, type[Prop]] = {"knife": Knife, "fork": Fork}


def standing_pose(bottom, length: float, azimuth: float, lean: float, spin: float) -> tuple[np.ndarray, np.ndarray]:
    """Pose of a piece of cutlery standing head up on the point ``bottom`` (its handle
    end), turned by ``spin`` about the vertical, then leaning by ``lean`` (rad) with its
    head towards the horizontal direction ``azimuth``."""
    q = quat_mul(quat_yaw(spin), HEAD_UP)
    q = quat_mul(quat_axis_angle((-np.sin(azimuth), np.cos(azimuth), 0.0), lean), q)
    axis = np.array([np.sin(lean) * np.cos(azimuth), np.sin(lean) * np.sin(azimuth), np.cos(lean)])
    return np.asarray(bottom, float) + 0.5 * length * axis, q


class _CutleryTask(DishwasherItemsTask):
    dishwasher_start = (OPEN, OPEN, CLOSED)
    items = ("knife", "fork")
    #: +- random spin of an item about its long axis in the basket
    basket_spin: ClassVar[float] = np.deg2rad(30.0)

    def _task_props(self) -> dict[str, Prop]:
        return {name: ITEM_CLASSES[name](name) for name in self.items}

    def _items_in_basket(self, rng: np.random.Generator) -> None:
        """Stand the items in random compartments of the basket (0.08 m along x, 0.045 m
        along y), each leaning forwards or backwards against a compartment wall: the
        handle end 12 mm off the compartment's centre, the head towards the far wall."""
        dishwasher = self.props[DISHWASHER]
        slots = rng.choice(6, len(self.items), replace=False) + 1
        for item, k in zip(self.items, slots, strict=True):
            prop = self.props[item]
            sign = 1.0 if rng.random() < 0.5 else -1.0
            azimuth = (0.0 if sign > 0 else np.pi) + rng.uniform(-0.1, 0.1)
            bottom = dishwasher.site_pos(self.data, f"basket_slot_{k}") + (-0.012 * sign, 0.0, 0.004)
            pos, quat = standing_pose(
                bottom,
                prop.length,
                azimuth=azimuth,
                lean=rng.uniform(*np.deg2rad((12.0, 16.0))),
                spin=rng.uniform(-self.basket_spin, self.basket_spin),
            )
            prop.set_pose(self.data, pos, quat)


class DishwasherUnloadCutlery(_CutleryTask):
    """Move the knife and the fork from the dishwasher's basket into the cutlery tray."""

    time_limit = 38.0
    observed_static = ("cutlery_tray",)
    tray_pos: ClassVar[tuple[float, float, float]] = (0.66, -0.6, COUNTER_TOP)
    tray_noise: ClassVar[tuple[float, float]] = (0.04, 0.03)

    def _task_props(self) -> dict[str, Prop]:
        props = super()._task_props()
        props["cutlery_tray"] = CutleryTray("cutlery_tray", free=False)
        return props

    def _setup(self) -> None:
        super()._setup()
        self.target_mask = self.mask("cutlery_tray")

    def _place(self, rng: np.random.Generator) -> None:
        dx, dy = rng.uniform(-1.0, 1.0, 2) * self.tray_noise
        x, y, z = self.tray_pos
        self._place_static("cutlery_tray", (x + dx, y + dy, z + 0.0005))
        self._items_in_basket(rng)


class DishwasherLoadCutlery(_CutleryTask):
    """Move the knife and the fork from the mug on the counter into the dishwasher's
    cutlery basket."""

    time_limit = 17.0
    mug_pos: ClassVar[tuple[float, float, float]] = (0.65, -0.6, COUNTER_TOP)
    mug_noise: ClassVar[tuple[float, float]] = (0.05, 0.05)

    def _task_props(self) -> dict[str, Prop]:
        props = super()._task_props()
        props["mug"] = Mug("mug")
        return props

    def _setup(self) -> None:
        super()._setup()
        self.target_mask = self.mask(DISHWASHER, "basket")

    def _place(self, rng: np.random.Generator) -> None:
        mug = self.props["mug"]
        dx, dy = rng.uniform(-1.0, 1.0, 2) * self.mug_noise
        x, y, z = self.mug_pos
        yaw = rng.uniform(-np.pi / 2, np.pi / 2)
        centre = np.array([x + dx, y + dy, z + 0.0005])
        mug.set_pose(self.data, centre, quat_yaw(yaw))
        # the two items lean apart, across the handle's direction, each against the rim
        floor = centre + (0.0, 0.0, 0.008 + 0.004)
        inner, height = mug.radius - 0.005, mug.height - 0.008
        first = yaw + np.pi / 2 + rng.uniform(-0.15, 0.15)
        for item, azimuth in zip(self.items, (first, first + np.pi), strict=True):
            prop = self.props[item]
            offset = 0.012
            lean = np.arctan2(inner - offset - 0.004, height)
            bottom = floor + offset * np.array([np.cos(azimuth), np.sin(azimuth), 0.0])
            pos, quat = standing_pose(bottom, prop.length, azimuth, lean, spin=azimuth + np.pi / 2)
            prop.set_pose(self.data, pos, quat)


class DishwasherUnloadCutleryLong(_CutleryTask):
    """Move the fork from the dishwasher into the cutlery tray in the closed top drawer,
    then close the drawer and the dishwasher."""

    scene_name = "counter_dishwasher_cutlery_cabinet"
    time_limit = 44.0
    items = ("fork",)
    closed_props = ("cutlery_cabinet",)
    close_at_end = True

    def _setup(self) -> None:
        super()._setup()
        self.target_mask = self.mask("cutlery_tray")

    def _place(self, rng: np.random.Generator) -> None:
        self._items_in_basket(rng)


__all__ = ["DishwasherLoadCutlery", "DishwasherUnloadCutlery", "DishwasherUnloadCutleryLong"]
