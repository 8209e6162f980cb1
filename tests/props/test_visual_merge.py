"""The build-time visual merge (bigym.visual_merge): fewer draw calls, the same
physics bit for bit, the same pictures, the prop APIs untouched."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from propkit import make_world

import bigym.env
from bigym.demonstrations import model_fingerprint
from bigym.env import BiGymEnv
from bigym.envs.dishwasher_plates import DishwasherLoadPlates
from bigym.envs.task import KitchenTask
from bigym.observations import CameraConfig, ObservationConfig
from bigym.props import PROP_CLASSES, ArticulatedProp
from bigym.props.base import GROUP_BOTH, GROUP_COLLISION, GROUP_VISUAL, lathe_mesh
from bigym.visual_merge import (
    GROUP_MERGED,
    _box_template,
    _cylinder_template,
    _mesh_normals,
    _sphere_template,
    merge_visual_geoms,
)
from bigym.scenes import make_scene, scene_names

KitchenFull = type("KitchenFull", (KitchenTask,), {"scene_name": "kitchen_full"})
# Physics fields of colliding geoms: all must be identical with and without the merge.
COLLIDER_FIELDS = (
    "geom_type", "geom_size", "geom_pos", "geom_quat", "geom_contype", "geom_conaffinity", "geom_condim",
    "geom_priority", "geom_friction", "geom_solmix", "geom_solref", "geom_solimp", "geom_margin", "geom_gap",
    "geom_rbound", "geom_aabb",
)  # fmt: skip
BODY_FIELDS = ("body_mass", "body_inertia", "body_ipos", "body_iquat", "body_subtreemass", "body_pos", "body_quat")


def _env_pair(monkeypatch, cls, **kwargs) -> tuple[BiGymEnv, BiGymEnv]:
    """The same env built without and with the merge."""
    with monkeypatch.context() as patch:
        patch.setattr(bigym.env, "merge_visual_geoms", lambda *args, **kw: None)
        plain = cls(**kwargs)
    return plain, cls(**kwargs)


def _colliders(model: mujoco.MjModel) -> np.ndarray:
    return np.flatnonzero((model.geom_contype | model.geom_conaffinity) != 0)


def _visible(model: mujoco.MjModel) -> int:
    return int(np.sum(model.geom_group <= GROUP_VISUAL))


def _assert_same_physics_model(plain: mujoco.MjModel, merged: mujoco.MjModel) -> None:
    assert model_fingerprint(plain) == model_fingerprint(merged)
    for name in BODY_FIELDS:
        assert np.array_equal(getattr(plain, name), getattr(merged, name)), name
    a, b = _colliders(plain), _colliders(merged)
    assert [plain.geom(g).name for g in a] == [merged.geom(g).name for g in b]
    assert np.array_equal(plain.geom_bodyid[a], merged.geom_bodyid[b])
    for name in COLLIDER_FIELDS:
        assert np.array_equal(getattr(plain, name)[a], getattr(merged, name)[b]), name
    assert plain.stat.meaninertia == merged.stat.meaninertia  # the solver scales by it


@pytest.mark.parametrize("cls", [KitchenFull, DishwasherLoadPlates], ids=lambda c: c.__name__)
def test_trajectories_are_bit_identical(monkeypatch, cls):
    """Same model physics, and the same random actions give the same states bit for bit
    (free props resting on shelves and in racks keep dozens of contacts active)."""
    plain, merged = _env_pair(monkeypatch, cls, control_frequency=50)
    assert _visible(merged.model) < 0.6 * _visible(plain.model)
    _assert_same_physics_model(plain.model, merged.model)
    plain.reset(seed=3)
    merged.reset(seed=3)
    rng = np.random.default_rng(0)
    contacts = 0
    for step in range(100):
        action = rng.uniform(plain.action_space.low, plain.action_space.high).astype(np.float32)
        plain.step(action)
        merged.step(action)
        for name in ("qpos", "qvel", "act", "qacc_warmstart", "qfrc_constraint", "sensordata"):
            assert np.array_equal(getattr(plain.data, name), getattr(merged.data, name)), (step, name)
        n = plain.data.ncon
        assert merged.data.ncon == n and merged.data.nefc == plain.data.nefc
        first, second = plain.data.contact, merged.data.contact
        for name in ("pos", "frame", "dist"):
            assert np.array_equal(getattr(first, name)[:n], getattr(second, name)[:n]), (step, name)
        # geom ids shift (merged meshes are added to the bodies), the geoms do not
        for side in ("geom1", "geom2"):
            names = [plain.model.geom(g).name for g in getattr(first, side)[:n]]
            assert names == [merged.model.geom(g).name for g in getattr(second, side)[:n]], step
        contacts += n
    assert contacts > 100 * 10


@pytest.mark.parametrize("scene", scene_names())
def test_every_scene_keeps_its_physics(scene):
    def build(merge: bool) -> mujoco.MjModel:
        spec = make_world()
        make_scene(scene).populate(spec)
        if merge:
            merge_visual_geoms(spec)
        return spec.compile()

    plain, merged = build(False), build(True)
    _assert_same_physics_model(plain, merged)
    assert _visible(merged) < _visible(plain)


def test_prop_apis_and_robot_untouched(monkeypatch):
    plain, merged = _env_pair(monkeypatch, KitchenFull)
    model = merged.model
    # the robot is left alone (its geoms are first in the model, before any prop's)
    robot = np.flatnonzero(np.isin(model.geom_bodyid, merged.robot.body_ids))
    assert np.array_equal(robot, np.flatnonzero(np.isin(plain.model.geom_bodyid, plain.robot.body_ids)))
    for name in ("geom_bodyid", "geom_type", "geom_group", "geom_dataid", "geom_rgba", "geom_matid"):
        assert np.array_equal(getattr(model, name)[robot], getattr(plain.model, name)[robot]), name
    # part ids resolve to colliding geoms, hidden or drawn as before
    for prop in merged.props.values():
        ids = prop.collision_geom_ids
        assert len(ids) and np.all((model.geom_contype[ids] | model.geom_conaffinity[ids]) != 0)
        assert set(model.geom_group[ids]) <= {GROUP_BOTH, GROUP_COLLISION}
        for part in prop.part_names:
            names = [model.geom(g).name for g in prop.part_geom_ids(part)]
            assert names == [plain.model.geom(g).name for g in plain.props[prop.name].part_geom_ids(part)]
        prop.set_collisions_enabled(False)
        assert not model.geom_contype[ids].any()
        prop.set_collisions_enabled(True)
    # merged geoms only draw: no contact, no mass (body masses are compared bit for bit above)
    merged_ids = [g for g in range(model.ngeom) if "/merged_visual_" in model.geom(g).name]
    assert len(merged_ids) > 50
    assert np.all(model.geom_group[merged_ids] == GROUP_VISUAL)
    assert not (model.geom_contype[merged_ids] | model.geom_conaffinity[merged_ids]).any()
    assert np.all(model.geom_type[merged_ids] == mujoco.mjtGeom.mjGEOM_MESH)
    hidden = np.flatnonzero(model.geom_group == GROUP_MERGED)
    assert len(hidden) and not (model.geom_contype[hidden] | model.geom_conaffinity[hidden]).any()


def test_images_look_the_same(monkeypatch):
    config = ObservationConfig(
        cameras=[CameraConfig(name, rgb=True, depth=True, resolution=(64, 64)) for name in ("head", "left_wrist")]
    )
    plain, merged = _env_pair(monkeypatch, KitchenFull, observation_config=config)
    first, _ = plain.reset(seed=0)
    second, _ = merged.reset(seed=0)
    for key in first:
        if key.startswith("rgb_"):
            difference = np.abs(first[key].astype(int) - second[key].astype(int))
            assert difference.mean() < 0.5, key  # of 255; it measures ~0.01
            assert np.mean(difference.max(axis=0) > 30) < 0.002, key
        elif key.startswith("depth_"):
            assert np.mean(np.abs(first[key] - second[key]) > 1e-3) < 0.002, key
    plain.close()
    merged.close()


@pytest.mark.parametrize("name", ["Table", "Dishwasher", "Mug", "Crisps", "SoupCan", "Hob"])
def test_merged_mesh_covers_its_geoms(name):
    """Each merged mesh spans the same box in the world as the primitives it replaces."""
    prop = PROP_CLASSES[name](name.lower())
    spec = make_world()
    prop.attach_to(spec.worldbody)
    report = merge_visual_geoms(spec)
    assert report.meshes_added > 0
    model = spec.compile()
    data = mujoco.MjData(model)
    prop.bind(model, data)
    if isinstance(prop, ArticulatedProp) and prop.joint_keys:
        prop.set_state(data, 0.5)
    mujoco.mj_forward(model, data)
    for g in range(model.ngeom):
        gname = model.geom(g).name
        if "/merged_visual_" not in gname:
            continue
        mesh = model.geom_dataid[g]
        start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
        verts = data.geom_xpos[g] + model.mesh_vert[start : start + count] @ data.geom_xmat[g].reshape(3, 3).T
        members = [
            m
            for m in range(model.ngeom)
            if model.geom_bodyid[m] == model.geom_bodyid[g]
            and model.geom_group[m] in (GROUP_COLLISION, GROUP_MERGED)
            and np.array_equal(model.geom_rgba[m], model.geom_rgba[g])
        ]
        lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
        for m in members:
            if model.geom_type[m] == mujoco.mjtGeom.mjGEOM_MESH:
                sub = model.geom_dataid[m]
                s, c = model.mesh_vertadr[sub], model.mesh_vertnum[sub]
                pts = data.geom_xpos[m] + model.mesh_vert[s : s + c] @ data.geom_xmat[m].reshape(3, 3).T
                lo, hi = np.minimum(lo, pts.min(0)), np.maximum(hi, pts.max(0))
                continue
            rot = data.geom_xmat[m].reshape(3, 3)
            centre = data.geom_xpos[m] + rot @ model.geom_aabb[m, :3]
            half = np.abs(rot) @ model.geom_aabb[m, 3:]
            lo, hi = np.minimum(lo, centre - half), np.maximum(hi, centre + half)
        # boxes are exact; round shapes are inscribed polygons (<= 1 - cos(pi / 28) of a radius)
        assert np.all(verts.min(0) >= lo - 1e-5) and np.all(verts.max(0) <= hi + 1e-5), gname
        assert np.allclose(verts.min(0), lo, atol=2e-3) and np.allclose(verts.max(0), hi, atol=2e-3), gname


def _volume_and_orientation(verts: np.ndarray, normals: np.ndarray, faces: np.ndarray) -> tuple[float, float]:
    tri = verts[faces]
    volume = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = np.linalg.norm(cross, axis=1)
    agree = np.einsum("ij,ij->i", cross, normals[faces].mean(axis=1))
    return float(volume), float(agree[area > 1e-12].min())


@pytest.mark.parametrize(
    ("template", "volume", "tolerance"),
    [
        (_box_template((1, 1, 1)), 8.0, 1e-12),
        (_box_template((4, 1, 3)), 8.0, 1e-12),
        (_cylinder_template(28, 4), 2.0 * np.pi, 0.03),
        (_sphere_template(28, 16), 4.0 / 3.0 * np.pi, 0.05),
    ],
)
def test_templates_are_closed_and_face_outwards(template, volume, tolerance):
    measured, agreement = _volume_and_orientation(template.verts, template.normals, template.faces)
    assert measured == pytest.approx(volume, rel=tolerance)
    assert agreement > 0.0  # every triangle winds the way its normals point
    assert np.allclose(np.linalg.norm(template.normals, axis=1), 1.0)


def test_user_mesh_normals_match_mujoco():
    """A merged lathe mesh carries the normals MuJoCo makes for it on its own."""
    verts, faces = lathe_mesh([(0, 0), (0.04, 0), (0.045, 0.1), (0.04, 0.1), (0.035, 0.01), (0, 0.01)])
    spec = mujoco.MjSpec()
    mesh = spec.add_mesh(name="cup")
    mesh.uservert = verts.ravel().tolist()
    mesh.userface = faces.ravel().tolist()
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname="cup", contype=0, conaffinity=0)
    model = spec.compile()
    assert model.mesh_vertnum[0] == model.mesh_normalnum[0] == len(verts)
    assert np.array_equal(model.mesh_facenormal[: len(faces)], faces)
    # MuJoCo moves the mesh to its centroid and principal axes: undo that rotation
    compiled = model.mesh_vert[: len(verts)].astype(float)
    centred = compiled - compiled.mean(axis=0)
    u, _, vt = np.linalg.svd((verts - verts.mean(axis=0)).T @ centred)
    rotation = u @ vt
    assert np.allclose(centred @ rotation.T, verts - verts.mean(axis=0), atol=1e-6)
    theirs = model.mesh_normal[: len(verts)] @ rotation.T
    assert np.allclose(_mesh_normals(verts, faces), theirs, atol=1e-5)
