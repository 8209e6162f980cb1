"""Handles, slots, shelves and work surfaces of every preset layout are within reach of
the floating-base H1 (x, y, z, yaw base + 5-DOF arm): a damped least-squares IK brings a
gripper's pinch point within 2 cm of each target without the torso, head or arms
sinking into the furniture."""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np
import pytest

from bigym.props import (
    ArticulatedProp,
    BaseCabinet,
    CutleryTray,
    DishDrainer,
    Dishwasher,
    OpenShelf,
    Table,
    WallCabinet,
)
from bigym.scenes import Scene, make_scene, scene_names

os.environ.setdefault(
    "MENAGERIE_ROOT", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "menagerie")
)
import bigym.robot.h1 as h1  # noqa: E402
import bigym.robot.robot as robot_mod  # noqa: E402
import bigym.world as world_mod  # noqa: E402

PRESETS = [n for n in scene_names() if n != "kitchen_full"]
TOLERANCE = 0.02  # m, pinch point to target
PENETRATION = 0.005  # m, robot body into furniture


@dataclass
class Target:
    label: str
    states: dict[str, np.ndarray]  # articulated prop name -> normalised state
    point: Callable[[mujoco.MjData], np.ndarray]


def _zero(p: ArticulatedProp) -> np.ndarray:
    s = np.zeros(len(p.joint_keys))
    return s


def _with(p: ArticulatedProp, key: str, value: float) -> np.ndarray:
    s = _zero(p)
    if isinstance(p, Dishwasher) and key != "door":
        s[p.joint_index("door")] = 1.0
    s[p.joint_index(key)] = value
    return s


def _surface(model, data, geom_ids, inset: float, lift: float) -> np.ndarray:
    """A point ``inset`` behind the front (-x) edge, centred in y, ``lift`` above the top."""
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for g in geom_ids:
        c, h = data.geom_xpos[g], model.geom_size[g]
        lo, hi = np.minimum(lo, c - h), np.maximum(hi, c + h)
    return np.array([lo[0] + inset, 0.5 * (lo[1] + hi[1]), hi[2] + lift])


def _targets(scene: Scene, model: mujoco.MjModel) -> list[Target]:
    out: list[Target] = []
    art = scene.articulated
    for name, p in scene.props.items():
        if isinstance(p, ArticulatedProp):
            for key in p.joint_keys:
                out.append(
                    Target(
                        f"{name}:{key}_handle closed",
                        {name: _with(p, key, 0.0)},
                        lambda d, p=p, k=key: p.site_pos(d, f"{k}_handle"),
                    )
                )
                grip = "door_edge" if isinstance(p, Dishwasher) and key == "door" else f"{key}_handle"
                out.append(
                    Target(f"{name}:{grip} open", {name: _with(p, key, 1.0)}, lambda d, p=p, g=grip: p.site_pos(d, g))
                )
        if isinstance(p, BaseCabinet):
            opened = {name: np.ones(len(p.joint_keys))}
            if p.shelf:
                ids = p.part_geom_ids("shelf")
                out.append(Target(f"{name}:shelf", opened, lambda d, ids=ids: _surface(model, d, ids, 0.12, 0.06)))
            if p.counter:
                ids = p.part_geom_ids("counter")
                out.append(Target(f"{name}:counter", {}, lambda d, ids=ids: _surface(model, d, ids, 0.2, 0.05)))
            if p.hob:
                for k in range(1, 5):
                    out.append(
                        Target(
                            f"{name}:hob_site_{k}",
                            {},
                            lambda d, p=p, k=k: p.site_pos(d, f"hob_site_{k}") + (0, 0, 0.05),
                        )
                    )
            for key in p.joint_keys:
                # inside an open drawer, 10 cm over its floor (the bottom drawer's floor, at
                # 0.14 m, is below the robot's reach and left out)
                if key.startswith("drawer") and key not in ("drawer_small_1", "drawer_big_1"):
                    out.append(
                        Target(
                            f"{name}:{key} inside",
                            {name: _with(p, key, 1.0)},
                            lambda d, p=p, k=key: p.site_pos(d, k) + (0, 0, 0.1),
                        )
                    )
        if isinstance(p, WallCabinet):
            opened = {name: np.ones(len(p.joint_keys))}
            for part in ("shelf_bottom", "shelf"):
                ids = p.part_geom_ids(part)
                out.append(Target(f"{name}:{part}", opened, lambda d, ids=ids: _surface(model, d, ids, 0.1, 0.06)))
        if isinstance(p, OpenShelf):
            ids = p.part_geom_ids("shelf")
            out.append(Target(f"{name}:shelf", {}, lambda d, ids=ids: _surface(model, d, ids, 0.1, 0.06)))
        if isinstance(p, Dishwasher):
            for key, state, lift in (
                ("plate_slot_1_1", [1, 1, 0], 0.115),
                ("plate_slot_1_12", [1, 1, 0], 0.115),
                ("plate_slot_2_1", [1, 1, 0], 0.115),
                ("plate_slot_2_12", [1, 1, 0], 0.115),
                ("basket_slot_1", [1, 1, 0], 0.15),
                ("basket_slot_6", [1, 1, 0], 0.15),
                ("cup_slot_1_1", [1, 0, 1], 0.11),
                ("cup_slot_2_12", [1, 0, 1], 0.11),
            ):
                out.append(
                    Target(
                        f"{name}:{key}",
                        {name: np.array(state, float)},
                        lambda d, p=p, k=key, z=lift: p.site_pos(d, k) + (0, 0, z),
                    )
                )
        if isinstance(p, DishDrainer):
            for key in ("plate_slot_1", "plate_slot_6"):
                out.append(Target(f"{name}:{key}", {}, lambda d, p=p, k=key: p.site_pos(d, k) + (0, 0, 0.115)))
        if isinstance(p, CutleryTray):
            drawers = {n: _with(c, "drawer_small_4", 1.0) for n, c in art.items() if "drawer_small_4" in c.joint_keys}
            for key in ("slot_1", "slot_6"):
                out.append(Target(f"{name}:{key}", drawers, lambda d, p=p, k=key: p.site_pos(d, k) + (0, 0, 0.03)))
        if isinstance(p, Table):
            ids = p.part_geom_ids("top")
            for dy in (-0.45, 0.0, 0.45):
                out.append(
                    Target(
                        f"{name}:top {dy:+.2f}",
                        {},
                        lambda d, ids=ids, dy=dy: _surface(model, d, ids, 0.3, 0.05) + (0, dy, 0),
                    )
                )
    return out


COUNTER_CROUCH = 0.55  # lowest pelvis height tried for targets on furniture


class _Reacher:
    """Damped least-squares IK of one gripper's pinch point over the base and one arm."""

    def __init__(self, model: mujoco.MjModel, robot, desc) -> None:
        self.model, self.robot = model, robot
        self.sides = {}
        for s, side in enumerate(("left", "right")):
            names = [f"pelvis_{dof}" for dof in ("x", "y", "z", "rz")] + [f"{side}_{j}" for j in h1.ARM_JOINTS]
            jids = np.array([model.joint(n).id for n in names])
            lo = np.where(model.jnt_limited[jids], model.jnt_range[jids, 0], -np.inf)
            hi = np.where(model.jnt_limited[jids], model.jnt_range[jids, 1], np.inf)
            # Counter work without a deep squat: this collision-blind IK otherwise sinks the
            # pelvis to the 0.4 m floor-reach limit and pushes the body into the cabinets.
            lo[2] = max(lo[2], COUNTER_CROUCH)
            site = model.site(desc.pinch_sites[s]).id
            self.sides[side] = (
                model.jnt_qposadr[jids],
                model.jnt_dofadr[jids],
                lo,
                hi,
                site,
                1 if side == "left" else -1,
            )
        self.elbow = {side: model.jnt_qposadr[model.joint(f"{side}_elbow").id] for side in ("left", "right")}
        self.weights = np.array([0.0, 0.0, 0.5, 0.2, 1, 1, 1, 1, 1])
        grippers = [b for b in robot.body_ids if "gripper" in model.body(b).name]
        self.body_geoms = np.flatnonzero(
            np.isin(model.geom_bodyid, robot.body_ids) & ~np.isin(model.geom_bodyid, grippers)
        )
        self.jac = np.zeros((3, model.nv))

    def solve(
        self,
        data: mujoco.MjData,
        target: np.ndarray,
        side: str,
        yaw: float,
        idle_elbow: float,
        standoff: float | None,
        iters: int = 250,
    ) -> float:
        """Put the base ``standoff`` behind the target facing ``yaw`` and keep it there in
        x, y (``standoff=None``: start 0.5 m behind and let x, y move too); move its height,
        yaw and the ``side`` arm. The other arm holds its home pose with its elbow at
        ``idle_elbow`` (0 forward, 1.5 hanging, -1.25 raised)."""
        weights = self.weights.copy()
        if standoff is None:
            standoff = 0.5
            weights[:2] = 0.5
        m = self.model
        qa, da, lo, hi, site, sgn = self.sides[side]
        c, s = np.cos(yaw), np.sin(yaw)
        off = np.array([standoff * c + sgn * 0.21 * s, standoff * s - sgn * 0.21 * c])  # base -> target, rotated
        data.qpos[self.robot.proprio_qpos] = self.robot.home_qpos[self.robot.proprio_qpos]
        data.qpos[self.elbow["right" if side == "left" else "left"]] = idle_elbow
        data.qpos[qa[:4]] = [target[0] - off[0], target[1] - off[1], np.clip(target[2] - 0.09, lo[2], hi[2]), yaw]
        for _ in range(iters):
            mujoco.mj_kinematics(m, data)
            mujoco.mj_comPos(m, data)
            err = target - data.site_xpos[site]
            if err @ err < 1e-5:
                break
            mujoco.mj_jacSite(m, data, self.jac, None, site)
            J = self.jac[:, da] * weights
            dq = weights * (J.T @ np.linalg.solve(J @ J.T + 1e-3 * np.eye(3), err))
            data.qpos[qa] = np.clip(data.qpos[qa] + 0.5 * dq, lo, hi)
        mujoco.mj_forward(m, data)
        return float(np.linalg.norm(target - data.site_xpos[site]))

    def worst_penetration(self, data: mujoco.MjData, scene_geoms: np.ndarray) -> float:
        n = data.ncon
        g1, g2, dist = data.contact.geom1[:n], data.contact.geom2[:n], data.contact.dist[:n]
        hit = (np.isin(g1, self.body_geoms) & np.isin(g2, scene_geoms)) | (
            np.isin(g2, self.body_geoms) & np.isin(g1, scene_geoms)
        )
        return float(-dist[hit].min()) if hit.any() else 0.0


@pytest.mark.parametrize("name", PRESETS)
def test_scene_targets_are_reachable(name):
    spec, desc = h1.build_robot(h1.RobotConfig())
    world_mod.add_world(spec)
    scene = make_scene(name)
    scene.populate(spec)
    model = spec.compile()
    data = mujoco.MjData(model)
    scene.bind(model, data)
    robot = robot_mod.Robot(model, desc)
    reacher = _Reacher(model, robot, desc)
    scene_geoms = np.concatenate([p.collision_geom_ids for p in scene.props.values()])
    targets = _targets(scene, model)
    assert targets
    failures = []
    for t in targets:
        for pname, p in scene.articulated.items():
            p.set_state(data, t.states.get(pname, _zero(p)))
        mujoco.mj_forward(model, data)
        point = np.array(t.point(data), float)
        best = (np.inf, np.inf)
        tries = [
            (yaw, side, idle, standoff)
            for standoff in (None, 0.45, 0.6, 0.75, 0.35)
            for yaw in (0.0, np.pi / 2, -np.pi / 2, np.pi)
            for side in ("left", "right")
            for idle in (0.0, 1.5, -1.25)
        ]
        for yaw, side, idle, standoff in tries:
            err = reacher.solve(data, point, side, yaw, idle, standoff)
            pen = reacher.worst_penetration(data, scene_geoms)
            best = min(best, (err, pen), key=lambda e: (e[0] >= TOLERANCE, e[1]))
            if err < TOLERANCE and pen < PENETRATION:
                break
        if not (best[0] < TOLERANCE and best[1] < PENETRATION):
            failures.append(f"{t.label} at {point.round(3)}: err {best[0]:.3f} m, penetration {best[1]:.3f} m")
    assert not failures, "\n".join(failures)
