"""Dishwasher plate tasks: load plates from a dish drainer, unload them into it.

Scenes ``counter_dishwasher`` (a dishwasher under a counter, front at x = 0.4, and a
panel cabinet beside it at y = -0.6) and ``counter_dishwasher_wall_cabinet`` (plus a
glass wall cabinet above that cabinet). The robot starts at (0, -0.6), beside the sweep
of the dishwasher door. Plates stand in slots with their face normal along world y.

Success (paper, appendix; "not held": no gripper geom touches the plate):

* ``DishwasherUnloadPlates``: every plate touches the dish drainer on the counter and is
  not held.
* ``DishwasherLoadPlates``: every plate touches the bottom tray (``tray_bottom``), stands
  upright in it (its face normal within 20 deg of world +y or -y, the orientation of the
  tray's slots) and is not held.
* ``DishwasherUnloadPlatesLong``: the plate touches the dish drainer inside the wall
  cabinet and is not held, the dishwasher is closed (door and both trays within 0.1 of
  0, normalised) and both wall-cabinet doors are within 0.1 of closed.

Failure: a plate touches the floor.

The drainer's randomised pose is privileged information (``drainer_pose``), beside the
poses of the plates and the joint states of the furniture.

This module also holds :class:`DishwasherItemsTask`, the base of the plate, cup and
cutlery tasks: it opens the dishwasher as the task asks, places the task's objects and
lets them settle for a moment on a scratch copy of the state, so that every episode
starts with the objects at rest.
"""

from __future__ import annotations

from typing import ClassVar

import gymnasium as gym
import mujoco
import numpy as np

from bigym.envs.task import POSE_NAMES, KitchenTask
from bigym.props import DishDrainer, Plate, Prop
from bigym.props.base import quat_axis_angle

DISHWASHER = "dishwasher"
TOLERANCE = 0.1
COUNTER_TOP = 0.86
WALL_SHELF_TOP = 1.47
#: normalised start ranges of a joint that is open / closed at the start
OPEN = (0.95, 1.0)
CLOSED = (0.0, 0.02)
#: plate face normal (local +z) -> world +y
PLATE_QUAT = quat_axis_angle((1.0, 0.0, 0.0), -np.pi / 2)
#: plate origin relative to a slot site (the site marks the plate's centre)
PLATE_IN_SLOT = np.array([0.0, -0.0095, 0.002])
UPRIGHT_DEG = 20.0
#: the bottom tray's front row, every other slot: plates in it stand 6 cm apart
FRONT_ROW = tuple(f"plate_slot_1_{k}" for k in range(1, 12, 2))
#: settling on reset: every joint speed of the objects (m/s, rad/s) below this is "still"
SETTLED_SPEED = 0.005
SETTLE_CHUNK = 50
MAX_SETTLE_TIME = 2.0


class DishwasherItemsTask(KitchenTask):
    """Objects (``items``) to move into or out of an open dishwasher.

    Subclasses name the dishwasher's start state, add their props, place them on reset
    (:meth:`_place`) and set ``target_mask`` (the geoms every item must touch) in
    :meth:`_setup`. Success: every item touches the target and is not held; with
    ``close_at_end`` also the dishwasher and every prop of ``closed_props`` are closed
    (all joints within 0.1 of 0). Failure: an item touches the floor.

    On reset, after placing, the state is simulated on a scratch copy until the objects
    are still (at least ``settle_time`` seconds) and the settled poses of the objects and
    joint states of the furniture are written back, so episodes start at rest.
    """

    scene_name = "counter_dishwasher"
    robot_start: ClassVar[tuple[float, float, float]] = (0.0, -0.6, 0.0)
    robot_start_noise: ClassVar[tuple[float, float, float]] = (0.05, 0.05, 0.08)
    #: free props that must reach the target
    items: ClassVar[tuple[str, ...]] = ()
    #: start ranges of the normalised (door, tray_bottom, tray_mid)
    dishwasher_start: ClassVar[tuple[tuple[float, float], ...]] = (OPEN, OPEN, CLOSED)
    #: other articulated props that start closed (small random gaps)
    closed_props: ClassVar[tuple[str, ...]] = ()
    #: the long tasks: the dishwasher and ``closed_props`` must end closed
    close_at_end: ClassVar[bool] = False
    #: static props whose randomised pose is privileged information
    observed_static: ClassVar[tuple[str, ...]] = ()
    settle_time: ClassVar[float] = 0.6

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        cls.fail_on_floor = cls.items  # every item on the floor ends the episode

    # ------------------------------------------------------------------ hooks
    def _place(self, rng: np.random.Generator) -> None:
        """Place the task's props (dishwasher and furniture already posed)."""

    # ------------------------------------------------------------------ reset
    def _setup(self) -> None:
        self.target_mask = None  # each task sets its own in _setup
        self._item_masks = [self.mask(item) for item in self.items]
        self._scratch = mujoco.MjData(self.model)
        qpos: list[int] = []
        qvel: list[int] = []
        for prop in self._free_props.values():
            qpos += range(prop.qpos_adr, prop.qpos_adr + 7)
            qvel += range(prop.dof_adr, prop.dof_adr + 6)
        for prop in self._articulated.values():
            qpos += self.model.jnt_qposadr[prop.joint_ids].tolist()
            qvel += self.model.jnt_dofadr[prop.joint_ids].tolist()
        self._settle_qpos = np.array(qpos, dtype=np.int64)
        self._settle_qvel = np.array(qvel, dtype=np.int64)
        self._settle_steps = round(self.settle_time / self.model.opt.timestep)
        extra = max(0.0, MAX_SETTLE_TIME - self.settle_time)
        self._max_settle_chunks = int(np.ceil(extra / (SETTLE_CHUNK * self.model.opt.timestep)))

    def _on_reset(self) -> None:
        rng = self.np_random
        low, high = zip(*self.dishwasher_start, strict=True)
        self.props[DISHWASHER].set_state(self.data, rng.uniform(low, high))
        for name in self.closed_props:
            prop = self.props[name]
            prop.set_state(self.data, rng.uniform(0.0, 0.03, len(prop.joint_keys)))
        mujoco.mj_kinematics(self.model, self.data)
        self._place(rng)
        self._settle()

    def _settle(self) -> None:
        """Let the placed objects come to rest (at least ``settle_time``, then until they
        are still or ``MAX_SETTLE_TIME`` has passed); the robot's state is untouched."""
        model, data, scratch = self.model, self.data, self._scratch
        mujoco.mj_copyData(scratch, model, data)
        for _ in range(self._settle_steps):
            mujoco.mj_step(model, scratch)
        for _ in range(self._max_settle_chunks):
            if np.abs(scratch.qvel[self._settle_qvel]).max(initial=0.0) < SETTLED_SPEED:
                break
            for _ in range(SETTLE_CHUNK):
                mujoco.mj_step(model, scratch)
        data.qpos[self._settle_qpos] = scratch.qpos[self._settle_qpos]
        data.qvel[self._settle_qvel] = 0.0

    def _place_static(self, name: str, pos, quat=None) -> None:
        """Move a static prop (writes the model) and update the kinematics."""
        self.props[name].set_pose(self.data, pos, quat)
        mujoco.mj_kinematics(self.model, self.data)

    # ------------------------------------------------------------------ conditions
    def _success(self) -> bool:
        for item, mask in zip(self.items, self._item_masks, strict=True):
            if not self.touching(mask, self.target_mask) or self.held(item):
                return False
        if self.close_at_end:
            return self.joints_near(DISHWASHER, 0.0, TOLERANCE) and all(
                self.joints_near(name, 0.0, TOLERANCE) for name in self.closed_props
            )
        return True

    # ------------------------------------------------------------------ privileged state
    @property
    def privileged_layout(self) -> dict[str, tuple[str, ...]]:
        layout = super().privileged_layout
        layout.update({f"{name}_pose": POSE_NAMES for name in self.observed_static})
        return layout

    def _privileged_spaces(self) -> dict[str, gym.spaces.Box]:
        spaces = super()._privileged_spaces()
        spaces.update(
            {f"{name}_pose": gym.spaces.Box(-np.inf, np.inf, (7,), np.float32) for name in self.observed_static}
        )
        return spaces

    def _privileged_observation(self, obs: dict[str, np.ndarray]) -> None:
        super()._privileged_observation(obs)
        for name in self.observed_static:
            body = self.props[name].root_body_id
            obs[f"{name}_pose"] = np.concatenate([self.data.xpos[body], self.data.xquat[body]]).astype(np.float32)


# ---------------------------------------------------------------------------- plates
class _PlatesTask(DishwasherItemsTask):
    items = ("plate_1", "plate_2")
    observed_static = ("drainer",)
    #: nominal drainer position and the +- range of its random xy offset
    drainer_pos: ClassVar[tuple[float, float, float]] = (0.65, -0.6, COUNTER_TOP)
    drainer_noise: ClassVar[tuple[float, float]] = (0.05, 0.05)

    def _task_props(self) -> dict[str, Prop]:
        props: dict[str, Prop] = {name: Plate(name) for name in self.items}
        props["drainer"] = DishDrainer("drainer", free=False)
        return props

    def _place_drainer(self, rng: np.random.Generator) -> None:
        dx, dy = rng.uniform(-1.0, 1.0, 2) * self.drainer_noise
        x, y, z = self.drainer_pos
        self._place_static("drainer", (x + dx, y + dy, z + 0.0005))

    def _place_plates(self, holder: Prop, slots: list[str], rng: np.random.Generator) -> None:
        chosen = rng.choice(len(slots), len(self.items), replace=False)
        for plate, k in zip(self.items, chosen, strict=True):
            pos = holder.site_pos(self.data, slots[k]) + PLATE_IN_SLOT
            self.props[plate].set_pose(self.data, pos, PLATE_QUAT)

    def _plates_in_dishwasher(self, rng: np.random.Generator) -> None:
        self._place_plates(self.props[DISHWASHER], list(FRONT_ROW), rng)


class DishwasherUnloadPlates(_PlatesTask):
    """Move the two plates from the dishwasher's bottom tray to the dish drainer."""

    time_limit = 48.0

    def _setup(self) -> None:
        super()._setup()
        self.target_mask = self.mask("drainer")

    def _place(self, rng: np.random.Generator) -> None:
        self._place_drainer(rng)
        self._plates_in_dishwasher(rng)


class DishwasherLoadPlates(_PlatesTask):
    """Move the two plates from the dish drainer into the dishwasher's bottom tray."""

    time_limit = 34.0

    def _setup(self) -> None:
        super()._setup()
        self.target_mask = self.mask(DISHWASHER, "tray_bottom")

    def _place(self, rng: np.random.Generator) -> None:
        self._place_drainer(rng)
        drainer = self.props["drainer"]
        self._place_plates(drainer, drainer.slot_keys, rng)

    def _success(self) -> bool:
        return super()._success() and all(
            self.upright(p, UPRIGHT_DEG, world_axis=(0.0, 1.0, 0.0), either_sign=True) for p in self.items
        )


class DishwasherUnloadPlatesLong(DishwasherUnloadPlates):
    """Move the plate from the dishwasher into the drainer in the closed wall cabinet,
    then close the dishwasher and the cabinet."""

    scene_name = "counter_dishwasher_wall_cabinet"
    time_limit = 63.0
    items = ("plate_1",)
    closed_props = ("wall_cabinet",)
    close_at_end = True
    # inside the wall cabinet (interior x 0.68..0.98, y -0.88..-0.32, floor at 1.47)
    drainer_pos = (0.83, -0.6, WALL_SHELF_TOP)
    drainer_noise = (0.01, 0.05)


__all__ = ["DishwasherLoadPlates", "DishwasherUnloadPlates", "DishwasherUnloadPlatesLong"]
