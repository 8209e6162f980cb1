"""Sandwich tasks: toast a sandwich in a frying pan, flip it, take it out, with a spatula.

Scene ``counter_base_2_hob``: ``cabinet_1`` (y = 0) carries a hob, ``cabinet_2``
(y = -0.6) a bare counter. The task adds a frying pan on the hob's front +y burner
(``hob_site_1``; handle towards -y, yaw +-30 deg, +-2 cm), a spatula resting in the pan
(on the sandwich when it starts there) with its handle over the rim towards the robot, a
chopping board on the counter of ``cabinet_2`` at (0.7, -0.6) (yaw +-5 deg) and a
sandwich, any yaw: on the board (+-5 cm, raw) for ``SandwichToast``, in the pan (+-1 cm,
rounded collider; toasted for ``SandwichRemove``) for the others. The robot starts at
(0, -0.2). The sandwich may only be moved with the spatula (or the pan): a gripper
touching it ends the episode.

Success (paper, appendix; "flat" = the sandwich's up axis within 10 deg of world +z or
-z, "upside down" = within 10 deg of -z):

* ``SandwichToast``: the sandwich is flat, touches the pan, the pan touches the hob and
  no gripper touches the sandwich;
* ``SandwichFlip``: the sandwich is upside down, touches the pan, the pan touches the
  hob and no gripper touches the sandwich;
* ``SandwichRemove``: the sandwich is flat, touches the chopping board and no gripper
  touches the sandwich.

Failure: a gripper touches the sandwich, or the sandwich or the pan touches the floor.
"""

from __future__ import annotations

import functools
from typing import ClassVar

import mujoco
import numpy as np

from bigym.envs.task import KitchenTask
from bigym.props import ChoppingBoard, FryingPan, Sandwich, Spatula
from bigym.props.base import quat_mul, quat_yaw
from bigym.world import add_world

FLAT_TOLERANCE_DEG = 10.0
# The pan: on hob_site_1 of cabinet_1, +-2 cm, handle towards -y, yaw +-30 deg.
PAN_SITE = "hob_site_1"
PAN_XY_NOISE = 0.02
PAN_YAW = np.deg2rad(-90.0)
PAN_YAW_NOISE = np.deg2rad(30.0)
# The board: on the counter of cabinet_2, yaw +-5 deg.
BOARD_XY = (0.7, -0.6)
BOARD_YAW_NOISE = np.deg2rad(5.0)
BOARD_TOP = 0.028  # board top above its origin (ChoppingBoard)
PAN_FLOOR = 0.005  # top of the pan's bottom collider above its origin (FryingPan)
# The sandwich: +-5 cm on the board, +-1 cm in the pan; any yaw.
SANDWICH_BOARD_NOISE = 0.05
SANDWICH_PAN_NOISE = 0.01
GAP = 0.0003  # spawn clearance above a supporting surface
SETTLE_SECONDS = 3.0


@functools.cache
def spatula_rest_in_pan(with_sandwich: bool, rounded: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Pose ``(pos, quat)`` of a spatula at rest in a frying pan, in the pan's frame.

    Found once by simulation in a bare world: the pan on the floor (handle along +x),
    with a sandwich (``rounded`` collider or not) in its centre when ``with_sandwich``;
    the spatula, its blade towards +y, is dropped so that its blade lies in the pan (or
    on the sandwich) and its handle rests on the rim on the -y side, 90 deg from the
    pan's handle. The arrays returned are shared: read-only.
    """
    spec = mujoco.MjSpec()
    add_world(spec)
    pan, spatula = FryingPan("pan"), Spatula("spatula")
    props = [pan, spatula]
    if with_sandwich:
        props.append(Sandwich("sandwich", rounded=rounded))
    for prop in props:
        prop.attach_to(spec.worldbody)
    model = spec.compile()
    data = mujoco.MjData(model)
    for prop in props:
        prop.bind(model, data)
    pan.set_pose(data, (0.0, 0.0, GAP))
    if with_sandwich:
        props[2].set_pose(data, (0.0, 0.0, GAP + PAN_FLOOR + Sandwich.SIZE[2] / 2 + GAP))
    spatula.set_pose(data, (0.0, -0.06, 0.08 if with_sandwich else 0.06))
    mujoco.mj_forward(model, data)
    for _ in range(round(SETTLE_SECONDS / model.opt.timestep)):
        mujoco.mj_step(model, data)
    pan_pos, pan_quat = pan.get_pose(data)
    pos, quat = spatula.get_pose(data)
    # express in the pan's frame (the pan barely moves; be exact anyway)
    inverse = np.zeros(4)
    mujoco.mju_negQuat(inverse, pan_quat)
    local = np.zeros(3)
    mujoco.mju_rotVecQuat(local, pos - pan_pos, inverse)
    rest = (local, quat_mul(inverse, quat))
    for array in rest:
        array.setflags(write=False)
    return rest


def _rotate(vec: np.ndarray, quat: np.ndarray) -> np.ndarray:
    out = np.zeros(3)
    mujoco.mju_rotVecQuat(out, np.asarray(vec, float), np.asarray(quat, float))
    return out


class _SandwichTask(KitchenTask):
    scene_name = "counter_base_2_hob"
    robot_start: ClassVar[tuple[float, float, float]] = (0.0, -0.2, 0.0)
    robot_start_noise: ClassVar[tuple[float, float, float]] = (0.05, 0.05, 0.08)
    fail_on_floor = ("sandwich", "pan")
    toasted: ClassVar[bool] = False
    rounded: ClassVar[bool] = False
    # the sandwich starts in the pan (else on the board)
    start_in_pan: ClassVar[bool] = False

    def _task_props(self):
        return {
            "pan": FryingPan("pan"),
            "spatula": Spatula("spatula"),
            "board": ChoppingBoard("board"),
            "sandwich": Sandwich("sandwich", toasted=self.toasted, rounded=self.rounded),
        }

    def _setup(self) -> None:
        self.sandwich_mask = self.mask("sandwich")
        self.pan_mask = self.mask("pan")
        self.board_mask = self.mask("board")
        self.hob_mask = self.mask("cabinet_1", "hob")
        self.spatula_rest = spatula_rest_in_pan(self.start_in_pan, self.rounded)

    def _on_reset(self) -> None:
        rng = self.np_random
        props, data = self.props, self.data
        site = props["cabinet_1"].site_pos(data, PAN_SITE)
        pan_pos = site + (*rng.uniform(-PAN_XY_NOISE, PAN_XY_NOISE, 2), GAP)
        pan_quat = quat_yaw(PAN_YAW + rng.uniform(-PAN_YAW_NOISE, PAN_YAW_NOISE))
        props["pan"].set_pose(data, pan_pos, pan_quat)
        rest_pos, rest_quat = self.spatula_rest
        props["spatula"].set_pose(data, pan_pos + _rotate(rest_pos, pan_quat), quat_mul(pan_quat, rest_quat))
        board_pos = np.array([*BOARD_XY, self._part_top("cabinet_2", "counter") + GAP])
        props["board"].set_pose(data, board_pos, quat_yaw(rng.uniform(-BOARD_YAW_NOISE, BOARD_YAW_NOISE)))
        half_height = Sandwich.SIZE[2] / 2
        if self.start_in_pan:
            offset = rng.uniform(-SANDWICH_PAN_NOISE, SANDWICH_PAN_NOISE, 2)
            pos = pan_pos + (*offset, PAN_FLOOR + half_height + GAP)
        else:
            offset = rng.uniform(-SANDWICH_BOARD_NOISE, SANDWICH_BOARD_NOISE, 2)
            pos = board_pos + (*offset, BOARD_TOP + half_height + GAP)
        props["sandwich"].set_pose(data, pos, quat_yaw(rng.uniform(-np.pi, np.pi)))

    def _part_top(self, prop: str, part: str) -> float:
        """Highest z of a static part's (axis-aligned box) geoms; kinematics must be current."""
        ids = self.props[prop].part_geom_ids(part)
        return float(np.max(self.data.geom_xpos[ids, 2] + self.model.geom_size[ids, 2]))

    # ------------------------------------------------------------------ conditions
    def _flat(self) -> bool:
        return self.upright("sandwich", FLAT_TOLERANCE_DEG, either_sign=True)

    def _in_pan_on_hob(self) -> bool:
        return self.touching(self.sandwich_mask, self.pan_mask) and self.touching(self.pan_mask, self.hob_mask)

    def _failure(self) -> bool:
        return super()._failure() or self.held("sandwich")


class SandwichToast(_SandwichTask):
    """Move the sandwich from the chopping board into the pan on the hob with the spatula."""

    time_limit = 40.0

    def _success(self) -> bool:
        return self._flat() and self._in_pan_on_hob() and not self.held("sandwich")


class SandwichFlip(_SandwichTask):
    """Flip the sandwich in the pan upside down with the spatula."""

    time_limit = 38.0
    rounded = True
    start_in_pan = True

    def _success(self) -> bool:
        upside_down = self.upright("sandwich", FLAT_TOLERANCE_DEG, world_axis=(0.0, 0.0, -1.0))
        return upside_down and self._in_pan_on_hob() and not self.held("sandwich")


class SandwichRemove(_SandwichTask):
    """Move the toasted sandwich from the pan onto the chopping board with the spatula."""

    time_limit = 33.0
    rounded = True
    toasted = True
    start_in_pan = True

    def _success(self) -> bool:
        return (
            self._flat() and self.touching(self.sandwich_mask, self.board_mask) and not self.held("sandwich")
        )


__all__ = ["SandwichFlip", "SandwichRemove", "SandwichToast", "spatula_rest_in_pan"]
