"""Dishwasher cup tasks: load mugs onto the upper tray, unload them onto the counter or
into the wall cabinet.

Scenes ``counter_dishwasher`` and ``counter_dishwasher_wall_cabinet`` (see
:mod:`bigym.envs.dishwasher_plates`). Mugs stand upside down on the upper tray
(``tray_mid``), their handles towards the robot. The robot starts at (0, -0.6).

Success (paper, appendix; "not held": no gripper geom touches the mug):

* ``DishwasherUnloadCups``: every mug touches the counter (the ``counter`` of the base
  cabinet beside the dishwasher or of the ``dishwasher_counter`` over it) and is not
  held.
* ``DishwasherLoadCups``: every mug touches the upper tray (``tray_mid``) and is not held.
* ``DishwasherUnloadCupsLong``: the mug touches the wall cabinet's ``shelf_bottom`` and is
  not held, the dishwasher is closed (door and both trays within 0.1 of 0, normalised)
  and both wall-cabinet doors are within 0.1 of closed.

Failure: a mug touches the floor.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.dishwasher_plates import CLOSED, COUNTER_TOP, DISHWASHER, OPEN, DishwasherItemsTask
from bigym.props import Mug, Prop
from bigym.props.base import quat_axis_angle, quat_mul, quat_yaw

#: upside down (local +z -> world -z); the handle (local +x) stays along world +x
UPSIDE_DOWN = quat_axis_angle((1.0, 0.0, 0.0), np.pi)
#: mug cells on the upper tray: (row, slot); rows 1 (front) and 2, slots 12 cm apart
TRAY_CELLS = tuple((row, k) for row in (1, 2) for k in (1, 5, 9))
#: the cells are shifted together by 0..3 slots (3 cm each)
TRAY_SHIFTS = 4


class _CupsTask(DishwasherItemsTask):
    items = ("mug_1", "mug_2")
    dishwasher_start = (OPEN, CLOSED, OPEN)
    #: yaw of the handle on the tray (pi: towards the robot) and its +- random range
    tray_yaw: ClassVar[tuple[float, float]] = (np.pi, np.deg2rad(10.0))

    def _task_props(self) -> dict[str, Prop]:
        return {name: Mug(name) for name in self.items}

    def _place_upside_down(self, cup: str, floor_point: np.ndarray, yaw: float) -> None:
        """Stand ``cup`` upside down with its rim on the point ``floor_point``."""
        mug = self.props[cup]
        pos = np.asarray(floor_point, float) + (0.0, 0.0, mug.height + 0.0005)
        mug.set_pose(self.data, pos, quat_mul(quat_yaw(yaw), UPSIDE_DOWN))

    def _cups_on_tray(self, rng: np.random.Generator) -> None:
        dishwasher = self.props[DISHWASHER]
        shift = int(rng.integers(TRAY_SHIFTS))
        cells = rng.choice(len(TRAY_CELLS), len(self.items), replace=False)
        yaw, spread = self.tray_yaw
        for cup, c in zip(self.items, cells, strict=True):
            row, k = TRAY_CELLS[c]
            site = dishwasher.site_pos(self.data, f"cup_slot_{row}_{k + shift}")
            self._place_upside_down(cup, site, yaw + rng.uniform(-spread, spread))


class DishwasherUnloadCups(_CupsTask):
    """Move the two mugs from the dishwasher's upper tray onto the counter."""

    time_limit = 24.0

    def _setup(self) -> None:
        super()._setup()
        self.target_mask = self.mask("cabinet", "counter") | self.mask("dishwasher_counter", "counter")

    def _place(self, rng: np.random.Generator) -> None:
        self._cups_on_tray(rng)


class DishwasherLoadCups(_CupsTask):
    """Move the two mugs from the counter onto the dishwasher's upper tray."""

    time_limit = 18.0
    #: nominal position of the first mug; the second stands 0.15 m further along +y
    counter_pos: ClassVar[tuple[float, float]] = (0.6, -0.6)
    counter_noise: ClassVar[tuple[float, float]] = (0.05, 0.02)
    counter_pitch: ClassVar[float] = 0.15
    counter_yaw: ClassVar[tuple[float, float]] = (np.pi, np.deg2rad(30.0))

    def _setup(self) -> None:
        super()._setup()
        self.target_mask = self.mask(DISHWASHER, "tray_mid")

    def _place(self, rng: np.random.Generator) -> None:
        yaw, spread = self.counter_yaw
        for i, cup in enumerate(self.items):
            dx, dy = rng.uniform(-1.0, 1.0, 2) * self.counter_noise
            point = (self.counter_pos[0] + dx, self.counter_pos[1] + i * self.counter_pitch + dy, COUNTER_TOP)
            self._place_upside_down(cup, point, yaw + rng.uniform(-spread, spread))


class DishwasherUnloadCupsLong(_CupsTask):
    """Move the mug from the dishwasher into the closed wall cabinet, then close the
    dishwasher and the cabinet."""

    scene_name = "counter_dishwasher_wall_cabinet"
    time_limit = 44.0
    items = ("mug_1",)
    closed_props = ("wall_cabinet",)
    close_at_end = True

    def _setup(self) -> None:
        super()._setup()
        self.target_mask = self.mask("wall_cabinet", "shelf_bottom")

    def _place(self, rng: np.random.Generator) -> None:
        self._cups_on_tray(rng)


__all__ = ["DishwasherLoadCups", "DishwasherUnloadCups", "DishwasherUnloadCupsLong"]
