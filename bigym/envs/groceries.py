"""Grocery tasks: put four groceries from the counter into the lower or the upper cupboards.

Every grocery kind of the pool (:data:`POOL`: wine, beer, soda, ketchup, mustard,
cereals, soap, jar, soup can, detergent; the flat bag of crisps is left out) is built
into the model once. Each reset draws :data:`CHOSEN` kinds with the task's seeded RNG and
stands them upright on the counter, on a 1 x 4 row of slots 0.2 m apart around
(0.7, -0.3) (x +-0.1, y +-0.05 around each slot, any yaw, redrawn until no two footprints
overlap). The other kinds are *parked*: each pool item has a weld to the world that holds
it at its own spot 0.5 km above the kitchen (beyond every camera's far clipping plane,
touching nothing); a reset switches the welds of the chosen items off and those of the
others on (``data.eq_active``, part of the simulation state). The compiled model never
changes, so a reset depends only on its seed and the model's physics fingerprint is the
same in every episode.

Doors: every door starts closed (normalised state 0..0.03): opening the cupboard is part
of the task (the open shelf of the upper task has none); success does not ask to close
them again.

Success ("not held": no gripper geom touches the item):

* ``StoreGroceriesLower`` (scene ``counter_base_2``): every chosen item is not held and
  touches ``cabinet_1``'s middle ``shelf`` (top 0.48 m) or the ``shelf_bottom`` (top
  0.13 m) of ``cabinet_1`` or of ``cabinet_2``, as in the reference. The middle shelf
  is the easy target: its 0.35 m clearance fits every item standing up, and it is well
  within reach. The bottom shelves are at the edge of reach: the crouched robot's gripper
  gets down to about 0.25 m above them (0.38 m high), enough to stand a tall item there
  or to drop a short one in.
* ``StoreGroceriesUpper`` (scene ``counter_base_wall_2x2``): every chosen item is not
  held and touches the glass wall cabinet's ``shelf_bottom`` (1.47 m) or ``shelf``
  (1.82 m), or the open shelf's ``shelf`` (1.47 m).

Failure: a chosen item touches the floor (parked items cannot).

Privileged information: like every kitchen task, the pose of every free prop, so all ten
pool items; the parked ones read their constant parking pose, 500 m up (which also tells
which kinds are in play).
"""

from __future__ import annotations

from typing import ClassVar

import mujoco
import numpy as np

from bigym.envs.task import KitchenTask
from bigym.props import Beer, Cereals, Detergent, Jar, Ketchup, Mustard, Prop, Soap, Soda, SoupCan, Wine
from bigym.props.base import quat_yaw

#: (prop name, class) of every grocery kind that can be drawn
POOL: tuple[tuple[str, type[Prop]], ...] = (
    ("wine", Wine),
    ("beer", Beer),
    ("soda", Soda),
    ("ketchup", Ketchup),
    ("mustard", Mustard),
    ("cereals", Cereals),
    ("soap", Soap),
    ("jar", Jar),
    ("soup_can", SoupCan),
    ("detergent", Detergent),
)
CHOSEN = 4
# Spawn row on the counter: slot centres (x, y), jitter, yaw.
ROW_CENTRE = (0.7, -0.3)
ROW_OFFSETS = (-0.3, -0.1, 0.1, 0.3)  # along y
SLOT_NOISE = (0.1, 0.05)
CLEARANCE = 0.01  # between two footprints (bounding circles)
MAX_DRAWS = 100
GAP = 0.0005  # spawn clearance above the counter
# Parking: 0.5 km above the kitchen, 1 m apart: beyond every camera's far clipping plane
# (MuJoCo's zfar is 50 model extents, under 200 m in these scenes) and touching nothing.
PARK_ORIGIN = (-5.0, 0.0, 500.0)
PARK_STEP = 1.0
WELD_SOLREF = (0.004, 1.0)  # stiff: a parked item sags < 0.1 mm


def footprint_radius(model: mujoco.MjModel, prop: Prop) -> float:
    """Radius of the vertical cylinder around the prop's origin that holds its colliders."""
    radius = 0.0
    for g in prop.collision_geom_ids:
        centre = model.geom_pos[g]
        if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_CYLINDER and np.allclose(model.geom_quat[g], (1, 0, 0, 0)):
            radius = max(radius, float(np.hypot(*centre[:2]) + model.geom_size[g, 0]))
            continue
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, model.geom_quat[g])
        half = np.abs(rotation.reshape(3, 3)) @ model.geom_aabb[g, 3:]  # local aabb -> body axes
        offset = rotation.reshape(3, 3) @ model.geom_aabb[g, :3] + centre
        corner = np.abs(offset[:2]) + half[:2]
        radius = max(radius, float(np.hypot(*corner)))
    return radius


class _GroceriesTask(KitchenTask):
    robot_start: ClassVar[tuple[float, float, float]] = (0.0, -0.3, 0.0)
    robot_start_noise: ClassVar[tuple[float, float, float]] = (0.05, 0.05, 0.08)
    fail_on_floor = tuple(name for name, _ in POOL)
    # (prop, part) pairs an item may touch to count as stored
    targets: ClassVar[tuple[tuple[str, str], ...]] = ()

    def _task_props(self) -> dict[str, Prop]:
        return {name: cls(name) for name, cls in POOL}

    def _build_scene(self, spec: mujoco.MjSpec) -> None:
        super()._build_scene(spec)
        # One weld to the world per pool item, holding it at its parking spot while active.
        for name, _ in POOL:
            weld = spec.add_equality(name=f"{name}_parked")
            weld.type = mujoco.mjtEq.mjEQ_WELD
            weld.objtype = mujoco.mjtObj.mjOBJ_BODY
            weld.name1 = "world"
            weld.name2 = self.props[name].root_body_name
            # anchor, pose of the item in the world frame, torque scale
            weld.data = np.array([0.0, 0.0, 0.0, *self._park_spot(name), 1.0, 0.0, 0.0, 0.0, 1.0, 0.0])
            weld.solref = WELD_SOLREF
            weld.active = True

    @staticmethod
    def _park_spot(name: str) -> np.ndarray:
        k = [n for n, _ in POOL].index(name)
        return np.array(PARK_ORIGIN) + (k * PARK_STEP, 0.0, 0.0)

    def _setup(self) -> None:
        self.pool = tuple(name for name, _ in POOL)
        self.item_masks = {name: self.mask(name) for name in self.pool}
        self.target_mask = self.union(*(self.mask(prop, part) for prop, part in self.targets))
        self.radii = {name: footprint_radius(self.model, self.props[name]) for name in self.pool}
        self.park = {name: self._park_spot(name) for name in self.pool}
        self.weld_ids = {name: self.model.equality(f"{name}_parked").id for name in self.pool}
        self.counter_ids = np.concatenate(
            [p.part_geom_ids("counter") for p in self.props.values() if "counter" in p.part_names]
        )
        self.chosen: tuple[str, ...] = ()

    def _draw_spots(self, names: tuple[str, ...]) -> np.ndarray:
        """(x, y) per item on the row of slots, redrawn until the footprints are apart."""
        rng = self.np_random
        radii = np.array([self.radii[n] for n in names])
        need = radii[:, None] + radii[None, :] + CLEARANCE
        np.fill_diagonal(need, 0.0)
        for _ in range(MAX_DRAWS):
            slots = rng.permutation(len(ROW_OFFSETS))[: len(names)]
            base = np.array([(ROW_CENTRE[0], ROW_CENTRE[1] + ROW_OFFSETS[s]) for s in slots])
            spots = base + rng.uniform(-1.0, 1.0, (len(names), 2)) * SLOT_NOISE
            dist = np.linalg.norm(spots[:, None] - spots[None, :], axis=-1)
            if np.all(dist >= need):
                return spots
        return base  # the bare slots (0.2 m apart) always fit

    def _on_reset(self) -> None:
        rng = self.np_random
        data = self.data
        for prop in self._articulated.values():
            prop.set_state(data, rng.uniform(0.0, 0.03, len(prop.joint_keys)))
        picks = np.sort(rng.choice(len(self.pool), CHOSEN, replace=False))
        self.chosen = tuple(self.pool[i] for i in picks)
        spots = self._draw_spots(self.chosen)
        yaws = rng.uniform(-np.pi, np.pi, CHOSEN)
        counter = self._counter_top()
        for name in self.pool:
            in_play = name in self.chosen
            data.eq_active[self.weld_ids[name]] = not in_play
            if not in_play:
                self.props[name].set_pose(data, self.park[name])
        for name, (x, y), yaw in zip(self.chosen, spots, yaws, strict=True):
            self.props[name].set_pose(data, (x, y, counter + GAP), quat_yaw(yaw))

    def _counter_top(self) -> float:
        """Top of the counters (kinematics are current during reset)."""
        ids = self.counter_ids
        return float(np.max(self.data.geom_xpos[ids, 2] + self.model.geom_size[ids, 2]))

    def _success(self) -> bool:
        for name in self.chosen:
            mask = self.item_masks[name]
            if not self.touching(mask, self.target_mask) or self.touching(mask, self.gripper_mask):
                return False
        return bool(self.chosen)


class StoreGroceriesLower(_GroceriesTask):
    """Put the four groceries from the counter into the cupboard under the counter."""

    scene_name = "counter_base_2"
    time_limit = 77.0
    targets = (("cabinet_1", "shelf"), ("cabinet_1", "shelf_bottom"), ("cabinet_2", "shelf_bottom"))


class StoreGroceriesUpper(_GroceriesTask):
    """Put the four groceries from the counter into the wall cupboard or onto the open shelf."""

    scene_name = "counter_base_wall_2x2"
    time_limit = 46.0
    targets = (("wall_cabinet", "shelf_bottom"), ("wall_cabinet", "shelf"), ("open_shelf", "shelf"))


__all__ = ["POOL", "StoreGroceriesLower", "StoreGroceriesUpper"]
