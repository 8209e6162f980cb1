"""KitchenTask: the shared base of the kitchen tasks.

A task names its scene, adds its own free props (plates, cups, ...), randomises them on
reset, and states success as a combination of the conditions below, all evaluated on
precomputed geom masks (no name look-ups in the hot loop):

* :meth:`touching`: some contact joins two geom sets;
* :meth:`held`: a gripper touches the prop (one pad is enough, as in the original);
* :meth:`upright`: a prop axis is within an angle of a world axis;
* :meth:`joints_near`: normalised joint states within a tolerance of a target.

Privileged information (``ObservationConfig(privileged_information=True)``) adds the pose
(x, y, z, qw, qx, qy, qz) of every free prop as ``<prop>_pose`` and the normalised
joint state of every articulated prop as ``<prop>_state``; ``env.privileged_layout``
names the entries.
"""

from __future__ import annotations

from typing import ClassVar

import gymnasium as gym
import mujoco
import numpy as np

from bigym.env import BiGymEnv
from bigym.contacts import GeomSet
from bigym.props.base import ArticulatedProp, Prop
from bigym.scenes import make_scene

POSE_NAMES = ("x", "y", "z", "qw", "qx", "qy", "qz")


class KitchenTask(BiGymEnv):
    """A BiGym task in a kitchen scene."""

    scene_name: ClassVar[str | None] = None  # a kitchen layout from bigym.scenes, or none
    # Props whose contact with the floor ends the episode as a failure.
    fail_on_floor: ClassVar[tuple[str, ...]] = ()

    # ------------------------------------------------------------------ hooks for tasks
    def _task_props(self) -> dict[str, Prop]:
        """Free props the task adds to the scene (attached to the world at the origin)."""
        return {}

    def _setup(self) -> None:
        """Precompute masks and ids (called once after compiling)."""

    # ------------------------------------------------------------------ building
    def _build_scene(self, spec: mujoco.MjSpec) -> None:
        self.scene = make_scene(self.scene_name) if self.scene_name is not None else None
        if self.scene is not None:
            self.props = self.scene.populate(spec)
        self.task_props = self._task_props()
        for name, prop in self.task_props.items():
            if name in self.props:
                raise ValueError(f"{self.task_name}: prop {name!r} already exists in scene {self.scene_name!r}")
            prop.attach_to(spec.worldbody)
            self.props[name] = prop

    def _bind(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        if self.scene is not None:
            self.scene.bind(model, data)
        for prop in self.task_props.values():
            prop.bind(model, data)
        self._mask_cache: dict[tuple[str, ...], GeomSet] = {}
        self.floor_mask = self.contacts.geom_set([model.geom("floor").id])
        self.gripper_mask = self.contacts.geom_set(self.robot.gripper_geom_ids)
        self._free_props = {name: p for name, p in self.props.items() if p.free}
        self._articulated = {
            name: p for name, p in self.props.items() if isinstance(p, ArticulatedProp) and p.joint_keys
        }
        self._floor_fail_masks = [self.mask(name) for name in self.fail_on_floor]
        # One contact query for all of them: "some prop touches the floor" is "the union of
        # their geoms touches the floor".
        self._floor_fail_mask = self.union(*self._floor_fail_masks) if self._floor_fail_masks else None
        self._joint_indices: dict[tuple[str, tuple[str, ...] | None], tuple[np.ndarray, tuple]] = {}
        self._qpos = data.qpos  # views for the env's life: MjData never reallocates them
        self._xmat = data.xmat
        self._upright_constants: dict[tuple, tuple[tuple[tuple[int, float], ...], float]] = {}
        self._setup()

    # ------------------------------------------------------------------ conditions
    def mask(self, prop: str, *parts: str) -> GeomSet:
        """The geom set of a prop's collision geoms (or of some of its parts); built once."""
        key = (prop, *parts)
        mask = self._mask_cache.get(key)
        if mask is None:
            p = self.props[prop]
            ids = p.part_geom_ids(*parts) if parts else p.collision_geom_ids
            mask = self._mask_cache[key] = self.contacts.geom_set(ids)
        return mask

    def union(self, *sets: GeomSet) -> GeomSet:
        """One geom set holding every geom of ``sets`` (build it once, in ``_setup``)."""
        return self.contacts.geom_set(np.flatnonzero(np.logical_or.reduce([s.mask for s in sets])))

    def touching(self, mask_a: GeomSet | np.ndarray, mask_b: GeomSet | np.ndarray) -> bool:
        """Some touching contact joins a geom of ``mask_a`` and a geom of ``mask_b`` (geom
        sets, or boolean masks over all geoms: slower, for one-off questions)."""
        return self.contacts.touching(mask_a, mask_b)

    def held(self, prop: str) -> bool:
        """A gripper touches the prop: not yet released."""
        return self.contacts.touching(self.mask(prop), self.gripper_mask)

    def upright(
        self,
        prop: str,
        max_angle_deg: float,
        local_axis: tuple[float, float, float] = (0.0, 0.0, 1.0),
        world_axis: tuple[float, float, float] = (0.0, 0.0, 1.0),
        either_sign: bool = False,
    ) -> bool:
        """The prop's ``local_axis`` is within ``max_angle_deg`` of ``world_axis`` (or of
        its opposite too, with ``either_sign``)."""
        key = (local_axis, world_axis, max_angle_deg)
        try:
            constants = self._upright_constants.get(key)
        except TypeError:  # axes given as lists or arrays: nothing to cache them by
            key, constants = None, None
        if constants is None:  # built once per distinct call, not per step
            # cosine = world . (R local) = sum_ij world_i R_ij local_j: the nonzero terms of
            # the outer product, as (index into the row-major xmat, coefficient) pairs.
            outer = np.outer(np.asarray(world_axis, float), np.asarray(local_axis, float)).ravel()
            terms = tuple((int(i), float(outer[i])) for i in np.flatnonzero(outer))
            constants = (terms, float(np.cos(np.deg2rad(max_angle_deg))))
            if key is not None:
                self._upright_constants[key] = constants
        terms, min_cosine = constants
        rotation = self._xmat[self.props[prop].root_body_id].tolist()
        cosine = 0.0
        for index, coefficient in terms:
            cosine += coefficient * rotation[index]
        if either_sign:
            cosine = abs(cosine)
        return cosine >= min_cosine

    def joints_near(self, prop: str, target: float, tolerance: float, keys: tuple[str, ...] | None = None) -> bool:
        """Every (or every listed) normalised joint of ``prop`` is within ``tolerance`` of ``target``.

        The same arithmetic as ``ArticulatedProp.get_state`` (``clip((q - lo) / span, 0, 1)``),
        on Python floats and only for the joints asked about: one gather per call.
        """
        key = (prop, keys if keys is None or type(keys) is tuple else tuple(keys))
        joints = self._joint_indices.get(key)
        if joints is None:  # joint names, addresses and ranges resolved once, not per step
            addresses, lows, spans = self.props[prop].state_mapping(key[1])
            joints = self._joint_indices[key] = (addresses, tuple(zip(lows.tolist(), spans.tolist())))
        addresses, ranges = joints
        for value, (low, span) in zip(self._qpos.take(addresses).tolist(), ranges):
            state = (value - low) / span
            state = 0.0 if state < 0.0 else 1.0 if state > 1.0 else state  # NaN stays NaN: never near
            if not abs(state - target) <= tolerance:
                return False
        return True

    def _failure(self) -> bool:
        if super()._failure():
            return True
        return self._floor_fail_mask is not None and self.touching(self._floor_fail_mask, self.floor_mask)

    # ------------------------------------------------------------------ privileged state
    @property
    def privileged_layout(self) -> dict[str, tuple[str, ...]]:
        """Names of the entries of every privileged observation key."""
        layout = {f"{name}_pose": POSE_NAMES for name in self._free_props}
        layout.update({f"{name}_state": tuple(p.joint_keys) for name, p in self._articulated.items()})
        return layout

    def _privileged_spaces(self) -> dict[str, gym.spaces.Box]:
        spaces = {f"{name}_pose": gym.spaces.Box(-np.inf, np.inf, (7,), np.float32) for name in self._free_props}
        spaces.update(
            {
                f"{name}_state": gym.spaces.Box(0.0, 1.0, (len(p.joint_keys),), np.float32)
                for name, p in self._articulated.items()
            }
        )
        return spaces

    def _privileged_observation(self, obs: dict[str, np.ndarray]) -> None:
        data = self.data
        for name, prop in self._free_props.items():
            adr = prop.qpos_adr
            obs[f"{name}_pose"] = data.qpos[adr : adr + 7].astype(np.float32)
        for name, prop in self._articulated.items():
            obs[f"{name}_state"] = prop.get_state(data).astype(np.float32)
