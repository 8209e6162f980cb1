"""Helpers for the prop-library tests: a bare world (floor + light) with the physics
options of the bigym world, and small simulation utilities. Imported by the test
modules of this folder (pytest puts the folder on ``sys.path``)."""

from __future__ import annotations

from collections.abc import Iterable

import mujoco
import numpy as np

from bigym.props import Prop, Table


def make_world() -> mujoco.MjSpec:
    """Floor plane + light; timestep 2 ms, implicitfast, elliptic cones, impratio 10."""
    spec = mujoco.MjSpec()
    spec.compiler.degree = False
    spec.option.timestep = 0.002
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.impratio = 10
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[10, 10, 0.1], rgba=[0.5, 0.5, 0.5, 1])
    spec.worldbody.add_light(pos=[0, 0, 4], dir=[0, 0, -1], type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL, castshadow=0)
    return spec


def compile_bound(spec: mujoco.MjSpec, props: Iterable[Prop]) -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = spec.compile()
    data = mujoco.MjData(model)
    for p in props:
        p.bind(model, data)
    mujoco.mj_forward(model, data)
    return model, data


def lowest_z(model: mujoco.MjModel, data: mujoco.MjData, geom_ids: Iterable[int]) -> float:
    """Lowest world z of the bounding boxes of ``geom_ids``."""
    zs = []
    for g in geom_ids:
        R = data.geom_xmat[g].reshape(3, 3)
        c, h = model.geom_aabb[g][:3], model.geom_aabb[g][3:]
        zs.append(data.geom_xpos[g][2] + (R @ c)[2] - np.abs(R[2]) @ h)
    return float(min(zs))


def free_speed(data: mujoco.MjData, prop: Prop, radius: float = 0.15) -> float:
    """Upper bound of the speed of any point of a free prop within ``radius`` of its
    origin: |v| + |w| r."""
    v = data.qvel[prop._dadr : prop._dadr + 6]
    return float(np.linalg.norm(v[:3]) + radius * np.linalg.norm(v[3:]))


def body_axis(data: mujoco.MjData, prop: Prop, axis: int) -> np.ndarray:
    """World direction of local axis ``axis`` (0 x, 1 y, 2 z) of the prop's root."""
    return data.xmat[prop.root_body_id].reshape(3, 3)[:, axis].copy()


def min_contact_dist(data: mujoco.MjData) -> float:
    return float(data.contact.dist[: data.ncon].min()) if data.ncon else 0.0


def table_world(extra: Iterable[tuple[Prop, tuple, tuple]] = ()) -> tuple[mujoco.MjSpec, Table, list[Prop]]:
    """A world with a Table at (0.7, 0, 0) (top at 0.95) and optional extra props."""
    spec = make_world()
    table = Table("table")
    table.attach_to(spec.worldbody, (0.7, 0.0, 0.0))
    props: list[Prop] = [table]
    for p, pos, quat in extra:
        p.attach_to(spec.worldbody, pos, quat)
        props.append(p)
    return spec, table, props
