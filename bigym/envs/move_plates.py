"""Move plates from one dish drainer to the other on the same table.

Scene ``move_plates``: a table at x = 0.7 with a dish drainer at y = +0.3
(``drainer_start``) and one at y = -0.3 (``drainer_target``). At reset both drainers are
moved by up to 5 cm in x and y and the plates stand, leaning at rest, in distinct random
slots of ``drainer_start``.

Success (paper, appendix), for every plate:

* its centre is within 5 cm of one of the ``plate_slot_*`` sites of ``drainer_target``
  (the sites mark the centre of a plate standing in a slot);
* it is upright in the rack: its face normal (local ``+z``) is within 20 deg of the
  drainer's slot axis (the drainer's local ``y``, either sign);
* it touches ``drainer_target``;
* it does not touch the table;
* no gripper touches it (released).

Failure: a plate touches the floor. Privileged information adds the drainer poses
(``drainer_start_pose``, ``drainer_target_pose``) to the plate poses.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bigym.envs.manipulation import TableTopTask
from bigym.props import Plate, Prop
from bigym.props.base import quat_axis_angle

__all__ = ["MovePlate", "MoveTwoPlates"]

#: top of the table (scene ``move_plates``)
TABLE_TOP = 0.95
#: success tolerances
SLOT_DISTANCE = 0.05
UPRIGHT_DEG = 20.0
#: a plate at rest in a slot of an unrotated drainer: its origin (the centre of its
#: back face) relative to the slot site, and its orientation: face normal along +y,
#: leaning 6 deg (top towards -y) against the holders. Measured by letting a plate
#: settle in the rack.
PLATE_IN_SLOT_OFFSET = np.array([0.0, -0.0213, -0.0048])
PLATE_IN_SLOT_QUAT = quat_axis_angle((1.0, 0.0, 0.0), np.deg2rad(-90.0 + 6.03))


class _MovePlates(TableTopTask):
    scene_name = "move_plates"
    posed_statics = ("drainer_start", "drainer_target")
    robot_start: ClassVar[tuple[float, float, float]] = (0.0, 0.0, 0.0)
    robot_start_noise: ClassVar[tuple[float, float, float]] = (0.05, 0.05, 0.08)
    plates: ClassVar[tuple[str, ...]] = ("plate",)
    #: nominal drainer positions (x, y) and their random shift +- per axis
    DRAINERS: ClassVar[dict[str, tuple[float, float]]] = {"drainer_start": (0.7, 0.3), "drainer_target": (0.7, -0.3)}
    DRAINER_JITTER = 0.05

    def _task_props(self) -> dict[str, Prop]:
        return {name: Plate(name) for name in self.plates}

    def _setup(self) -> None:
        self._plate_masks = [self.mask(name) for name in self.plates]
        self._plate_ids = [self.props[name].root_body_id for name in self.plates]
        self._plate_half = [self.props[name].height / 2 for name in self.plates]
        self._table_mask = self.mask("table")
        self._target_mask = self.mask("drainer_target")
        target = self.props["drainer_target"]
        self._target_id = target.root_body_id
        self._target_slot_ids = np.array([target.site_id(k) for k in target.slot_keys])
        self._min_upright_cosine = float(np.cos(np.deg2rad(UPRIGHT_DEG)))

    def _on_reset(self) -> None:
        rng = self.np_random
        for name, (x, y) in self.DRAINERS.items():
            dx, dy = rng.uniform(-self.DRAINER_JITTER, self.DRAINER_JITTER, 2)
            self.props[name].set_pose(self.data, (x + dx, y + dy, TABLE_TOP))
        start = self.props["drainer_start"]
        slots = rng.choice(len(start.slot_keys), size=len(self.plates), replace=False)
        # the drainers are not rotated: slot positions follow from the new drainer origin
        origin = np.asarray(self.model.body_pos[start.root_body_id])
        slot_local = {k: np.asarray(self.model.site_pos[start.site_id(k)]) for k in start.slot_keys}
        for name, slot in zip(self.plates, slots, strict=True):
            pos = origin + slot_local[start.slot_keys[slot]] + PLATE_IN_SLOT_OFFSET
            self.props[name].set_pose(self.data, pos, PLATE_IN_SLOT_QUAT)

    # ------------------------------------------------------------------ success
    def plate_in_target(self, index: int) -> bool:
        """Plate ``index`` is placed in the target drainer and released."""
        mask = self._plate_masks[index]
        # The contact conditions first: they are cheap and, most of the time, already false.
        if not (
            self.touching(mask, self._target_mask)
            and not self.touching(mask, self._table_mask)
            and not self.touching(mask, self.gripper_mask)
        ):
            return False
        data = self.data
        body = self._plate_ids[index]
        rotation = data.xmat[body].reshape(3, 3)
        normal = rotation[:, 2]
        centre = data.xpos[body] + normal * self._plate_half[index]
        slots = data.site_xpos[self._target_slot_ids]
        if np.min(np.linalg.norm(slots - centre, axis=1)) > SLOT_DISTANCE:
            return False
        slot_axis = data.xmat[self._target_id].reshape(3, 3)[:, 1]
        return abs(float(normal @ slot_axis)) >= self._min_upright_cosine

    def _success(self) -> bool:
        return all(self.plate_in_target(i) for i in range(len(self.plates)))


class MovePlate(_MovePlates):
    """Move the plate from the left dish drainer to the right one."""

    time_limit = 8.0
    fail_on_floor = ("plate",)


class MoveTwoPlates(_MovePlates):
    """Move both plates from the left dish drainer to the right one."""

    time_limit = 14.0
    plates = ("plate_1", "plate_2")
    fail_on_floor = ("plate_1", "plate_2")
