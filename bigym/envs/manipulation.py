"""Table-top manipulation tasks: stack blocks, flip a cup, flip a spoon in a mug.

Success criteria (paper, appendix "Details of Task Success Detectors"):

* ``StackBlocks`` (scene ``stack_blocks``): sort the three blocks by height; the lowest
  touches the green target pad on the far table, the middle one touches the lowest, the
  top one touches the middle one, each block's centre is at least half a block higher
  than the one below (stacked, not side by side), and no gripper touches any block.
  Failure: a block touches the floor.
* ``FlipCup`` (scene ``cabinet``): the mug's up axis (local ``+z``) is within 5 deg of
  world ``+z``, the mug touches the ``counter`` of the cabinet, and no gripper touches
  it. Failure: the mug touches the floor.
* ``FlipCutlery`` (scene ``cabinet``): the spoon, which starts standing head-up in a mug,
  is flipped: its long axis from handle to bowl (local ``+y``) is within 50 deg of world
  ``-z``; the spoon touches the mug; no gripper touches the spoon (released, as the
  paper asks) nor the mug. Failure: the mug or the spoon touches the floor.

Privileged information of ``StackBlocks`` adds the pad's pose (``target_pad_pose``) to
the block poses.
"""

from __future__ import annotations

from typing import ClassVar

import gymnasium as gym
import mujoco
import numpy as np

from bigym.envs.task import POSE_NAMES, KitchenTask
from bigym.props import Block, Mug, Prop, Spoon, TargetMarker
from bigym.props.base import quat_axis_angle, quat_mul, quat_yaw

__all__ = ["FlipCup", "FlipCutlery", "StackBlocks"]

#: top of the base cabinet's counter (scene ``cabinet``)
COUNTER_TOP = 0.86
#: top of the tables (scene ``stack_blocks``)
TABLE_TOP = 0.95
#: gap left under objects placed on a surface at reset (they settle < 1 mm)
DROP = 0.0005
#: the spoon standing bowl-up in the (nominal) mug, at rest: its end on the mug's inner
#: bottom, its flat back leaning 27.8 deg on the rim at the mug's -y side. Origin
#: (mid-length) relative to the mug's origin, orientation in the mug's frame. Measured by
#: letting the spoon settle in the mug.
SPOON_IN_MUG_OFFSET = np.array([0.0, -0.02813, 0.08678])
SPOON_IN_MUG_QUAT = quat_axis_angle((1.0, 0.0, 0.0), np.deg2rad(90.0 + 27.8))


def grid_points(
    rng: np.random.Generator,
    center: tuple[float, float],
    extent: tuple[float, float],
    spacing: float,
    amount: int,
    jitter: tuple[float, float] = (0.0, 0.0),
) -> np.ndarray:
    """``amount`` distinct points of a centred grid (pitch ``spacing``) covering
    ``center +- extent`` in x and y, each moved by ``U(+-jitter)``. Shape (amount, 2)."""
    nx = max(1, int(2 * extent[0] // spacing))
    ny = max(1, int(2 * extent[1] // spacing))
    xs = center[0] + (np.arange(nx) - (nx - 1) / 2) * spacing
    ys = center[1] + (np.arange(ny) - (ny - 1) / 2) * spacing
    grid = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1).reshape(-1, 2)
    chosen = grid[rng.choice(len(grid), size=amount, replace=False)]
    return chosen + rng.uniform(-1.0, 1.0, (amount, 2)) * np.asarray(jitter, float)


class TableTopTask(KitchenTask):
    """A kitchen task whose randomly placed static props (``posed_statics``: a target pad,
    dish drainers) also report their pose (x, y, z, qw, qx, qy, qz) as privileged
    information, under ``<prop>_pose`` like the free props."""

    posed_statics: ClassVar[tuple[str, ...]] = ()

    @property
    def privileged_layout(self) -> dict[str, tuple[str, ...]]:
        layout = super().privileged_layout
        layout.update({f"{name}_pose": POSE_NAMES for name in self.posed_statics})
        return layout

    def _privileged_spaces(self) -> dict[str, gym.spaces.Box]:
        spaces = super()._privileged_spaces()
        for name in self.posed_statics:
            spaces[f"{name}_pose"] = gym.spaces.Box(-np.inf, np.inf, (7,), np.float32)
        return spaces

    def _privileged_observation(self, obs: dict[str, np.ndarray]) -> None:
        super()._privileged_observation(obs)
        data = self.data
        for name in self.posed_statics:
            body = self.props[name].root_body_id
            obs[f"{name}_pose"] = np.concatenate([data.xpos[body], data.xquat[body]]).astype(np.float32)


# --------------------------------------------------------------------------- stack blocks
class StackBlocks(TableTopTask):
    """Stack the three blocks on the green pad on the far table."""

    scene_name = "stack_blocks"
    robot_start: ClassVar[tuple[float, float, float]] = (0.0, 0.0, 0.0)
    robot_start_noise: ClassVar[tuple[float, float, float]] = (0.05, 0.05, 0.08)
    time_limit = 69.0
    fail_on_floor = ("block_1", "block_2", "block_3")
    posed_statics = ("target_pad",)

    BLOCKS: ClassVar[tuple[str, ...]] = ("block_1", "block_2", "block_3")
    # blocks: a 2 x 6 grid (pitch 0.15 m) around (0.7, 0) on the near table
    BLOCK_CENTER = (0.7, 0.0)
    BLOCK_EXTENT = (0.15, 0.45)
    BLOCK_SPACING = 0.15
    BLOCK_JITTER = (0.03, 0.03)
    # pad: on the far table
    PAD_CENTER = (1.4, 0.0)
    PAD_JITTER = (0.05, 0.2)

    def _task_props(self) -> dict[str, Prop]:
        props: dict[str, Prop] = {name: Block(name) for name in self.BLOCKS}
        props["target_pad"] = TargetMarker("target_pad", shape="pad")
        return props

    def _setup(self) -> None:
        self._pad_mask = self.mask("target_pad")
        self._block_masks = [self.mask(name) for name in self.BLOCKS]
        self._block_ids = np.array([self.props[name].root_body_id for name in self.BLOCKS])
        self._min_rise = 0.5 * min(self.props[name].size for name in self.BLOCKS)
        self._any_block_mask = self.union(*self._block_masks)

    def _on_reset(self) -> None:
        rng = self.np_random
        points = grid_points(rng, self.BLOCK_CENTER, self.BLOCK_EXTENT, self.BLOCK_SPACING, 3, self.BLOCK_JITTER)
        for name, (x, y) in zip(self.BLOCKS, points, strict=True):
            block = self.props[name]
            z = TABLE_TOP + block.size / 2 + DROP
            block.set_pose(self.data, (x, y, z), quat_yaw(rng.uniform(-np.pi, np.pi)))
        pad_xy = np.asarray(self.PAD_CENTER) + rng.uniform(-1.0, 1.0, 2) * np.asarray(self.PAD_JITTER)
        self.props["target_pad"].set_pose(self.data, (pad_xy[0], pad_xy[1], TABLE_TOP))

    def _success(self) -> bool:
        # Necessary and cheap first: no block held, and some block on the pad.
        if self.touching(self._any_block_mask, self.gripper_mask) or not self.touching(
            self._any_block_mask, self._pad_mask
        ):
            return False
        heights = self.data.xpos[self._block_ids, 2].tolist()
        order = sorted(range(len(heights)), key=heights.__getitem__)  # stable, as np.argsort on 3 values
        # each block sits on the one below (not beside it)
        if any(heights[upper] - heights[lower] < self._min_rise for lower, upper in zip(order, order[1:])):
            return False
        low, mid, top = (self._block_masks[i] for i in order)
        return bool(self.touching(low, self._pad_mask) and self.touching(mid, low) and self.touching(top, mid))


# --------------------------------------------------------------------------- flip cup
class FlipCup(KitchenTask):
    """Turn the upside-down mug on the counter upright."""

    scene_name = "cabinet"
    robot_start: ClassVar[tuple[float, float, float]] = (0.0, 0.0, 0.0)
    robot_start_noise: ClassVar[tuple[float, float, float]] = (0.05, 0.05, 0.08)
    time_limit = 14.0
    fail_on_floor = ("mug",)

    UPRIGHT_DEG = 5.0
    # the mug: a 2 x 4 grid (pitch 0.1 m) around (0.8, 0) on the counter
    GRID_CENTER = (0.8, 0.0)
    GRID_EXTENT = (0.1, 0.2)
    GRID_SPACING = 0.1
    GRID_JITTER = (0.03, 0.03)
    YAW_RANGE = np.deg2rad(30.0)

    def _task_props(self) -> dict[str, Prop]:
        return {"mug": Mug("mug")}

    def _setup(self) -> None:
        self._counter_mask = self.mask("cabinet", "counter")
        self._mug_mask = self.mask("mug")

    def _on_reset(self) -> None:
        rng = self.np_random
        x, y = grid_points(rng, self.GRID_CENTER, self.GRID_EXTENT, self.GRID_SPACING, 1, self.GRID_JITTER)[0]
        mug = self.props["mug"]
        # upside down (rim on the counter), handle towards the robot (yaw 180 deg) +- 30 deg
        yaw = np.pi + rng.uniform(-self.YAW_RANGE, self.YAW_RANGE)
        quat = quat_mul(quat_yaw(yaw), quat_axis_angle((1.0, 0.0, 0.0), np.pi))
        mug.set_pose(self.data, (x, y, COUNTER_TOP + mug.height + DROP), quat)

    def _success(self) -> bool:
        return bool(
            self.upright("mug", self.UPRIGHT_DEG)
            and self.touching(self._mug_mask, self._counter_mask)
            and not self.held("mug")
        )


# --------------------------------------------------------------------------- flip cutlery
class FlipCutlery(KitchenTask):
    """Turn the spoon standing bowl-up in the mug upside down, bowl first into the mug."""

    scene_name = "cabinet"
    robot_start: ClassVar[tuple[float, float, float]] = (0.0, 0.0, 0.0)
    robot_start_noise: ClassVar[tuple[float, float, float]] = (0.05, 0.05, 0.08)
    time_limit = 30.0
    fail_on_floor = ("mug", "spoon")

    FLIPPED_DEG = 50.0
    GRID_CENTER = (0.8, 0.0)
    GRID_EXTENT = (0.1, 0.2)
    GRID_SPACING = 0.1
    GRID_JITTER = (0.03, 0.03)

    def _task_props(self) -> dict[str, Prop]:
        return {"mug": Mug("mug"), "spoon": Spoon("spoon")}

    def _setup(self) -> None:
        self._mug_mask = self.mask("mug")
        self._spoon_mask = self.mask("spoon")

    def _on_reset(self) -> None:
        rng = self.np_random
        x, y = grid_points(rng, self.GRID_CENTER, self.GRID_EXTENT, self.GRID_SPACING, 1, self.GRID_JITTER)[0]
        yaw = np.pi + rng.uniform(-np.pi, np.pi)
        mug_pos = np.array([x, y, COUNTER_TOP + DROP])
        mug_quat = quat_yaw(yaw)
        self.props["mug"].set_pose(self.data, mug_pos, mug_quat)
        # the spoon at rest in the mug, placed in the mug's frame
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, mug_quat)
        pos = mug_pos + rotation.reshape(3, 3) @ SPOON_IN_MUG_OFFSET
        self.props["spoon"].set_pose(self.data, pos, quat_mul(mug_quat, SPOON_IN_MUG_QUAT))

    def _success(self) -> bool:
        return bool(
            self.upright("spoon", self.FLIPPED_DEG, local_axis=(0.0, 1.0, 0.0), world_axis=(0.0, 0.0, -1.0))
            and self.touching(self._spoon_mask, self._mug_mask)
            and not self.held("spoon")
            and not self.held("mug")
        )
