"""Every prop builds, compiles alone and inside a scene; the Prop API behaves."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from propkit import compile_bound, make_world

from bigym.props import (
    PROP_CLASSES,
    ArticulatedProp,
    BaseCabinet,
    CutleryTray,
    DishDrainer,
    Dishwasher,
    Mug,
    Plate,
    Table,
    TargetMarker,
    WallCabinet,
    geom_mask,
    geoms_in_contact,
)
from bigym.props.base import lathe_mesh
from bigym.scenes import make_scene

ALL = sorted(PROP_CLASSES)


@pytest.mark.parametrize("name", ALL)
@pytest.mark.parametrize("seed", [None, 7])
def test_prop_compiles_alone(name, seed):
    cls = PROP_CLASSES[name]
    prop = cls("thing", seed)
    spec = prop.build_spec()
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert model.body(1).name == "root"
    assert model.ngeom > 0
    if prop.free:
        assert model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
        assert model.body_subtreemass[1] == pytest.approx(cls.MASS, rel=1e-6)
    # every collision part has geoms that actually collide; visual-only geoms never collide
    if not isinstance(prop, TargetMarker):
        assert prop.part_names, "a prop needs at least one collision part"
    for part in prop.part_names:
        for full in prop.part_geom_names(part):
            gid = model.geom(full.removeprefix("thing/")).id
            assert model.geom_contype[gid] or model.geom_conaffinity[gid]
    vis = model.geom_group == 2
    assert np.all(model.geom_contype[vis] == 0) and np.all(model.geom_conaffinity[vis] == 0)
    assert np.all(np.isfinite(data.xpos))


def test_all_props_compile_inside_a_scene():
    """One instance of every class, attached into the full kitchen, compiles and binds."""
    spec = make_world()
    scene = make_scene("kitchen_full")
    props = list(scene.populate(spec).values())
    for k, name in enumerate(ALL):
        prop = PROP_CLASSES[name](f"extra_{k}", seed=k)
        pos = (-3.0 - 1.5 * (k % 5), -3.0 + 1.5 * (k // 5), 0.3 if prop.free else 0.0)
        prop.attach_to(spec.worldbody, pos)
        props.append(prop)
    model, data = compile_bound(spec, props)
    for p in props:
        assert p.root_body_id > 0
        assert len(p.collision_geom_ids) > 0 or isinstance(p, TargetMarker)
        for key, full in p.site_names.items():
            assert model.site(full).id == p.site_id(key)
    mujoco.mj_step(model, data)
    assert np.all(np.isfinite(data.qacc))


def test_names_are_prefixed_and_sites_listed():
    spec = make_world()
    plate = Plate("plate_7")
    assert plate.site_names == {"center": "plate_7/center", "rim": "plate_7/rim"}  # known before attaching
    assert Dishwasher("dw").joint_names == ["dw/door", "dw/tray_bottom", "dw/tray_mid"]
    plate.attach_to(spec.worldbody, (0, 0, 0.5))
    model, _ = compile_bound(spec, [plate])
    assert model.body(plate.root_body_id).name == "plate_7/root"
    assert plate.site_names == {"center": "plate_7/center", "rim": "plate_7/rim"}
    assert model.joint("plate_7/freejoint").type == mujoco.mjtJoint.mjJNT_FREE
    names = [model.geom(g).name for g in plate.collision_geom_ids]
    assert all(n.startswith("plate_7/plate_") for n in names)


def test_free_and_mocap_props_must_go_on_the_world():
    spec = make_world()
    cab = BaseCabinet("cab", small_drawers=(True, True, True, True))
    cab.attach_to(spec.worldbody, (1.2, 0, 0))
    with pytest.raises(ValueError, match="world"):
        Mug("mug").attach_to(cab.spec_site("drawer_small_4"))
    with pytest.raises(ValueError, match="world"):
        TargetMarker("t").attach_to(cab.spec_site("drawer_small_4"))
    # static props may ride on a site of a moving body
    tray = CutleryTray("tray", size=(0.42, 0.5, 0.056))
    tray.attach_to(cab.spec_site("drawer_small_4"))
    model, data = compile_bound(spec, [cab, tray])
    assert model.body_parentid[tray.root_body_id] == model.body("cab/drawer_small_4").id
    x0 = data.xpos[tray.root_body_id].copy()
    cab.set_joint_state(data, "drawer_small_4", 1.0)
    mujoco.mj_forward(model, data)
    assert data.xpos[tray.root_body_id][0] == pytest.approx(x0[0] - 0.38)


def test_invalid_construction():
    with pytest.raises(ValueError):
        BaseCabinet("c", door_left=True, small_drawers=(True, False, False, False))
    with pytest.raises(ValueError):
        BaseCabinet("c", big_drawers=(True, False), small_drawers=(True, False, False, False))
    with pytest.raises(ValueError):
        BaseCabinet("c", door_left=True, panel=True)
    with pytest.raises(ValueError):
        BaseCabinet("c", big_drawers=(True,), small_drawers=(False,) * 4)
    with pytest.raises(ValueError):
        Plate("bad/name")
    with pytest.raises(TypeError):
        Plate("p", colour="red")  # type: ignore[call-arg]
    with pytest.raises(ValueError):
        TargetMarker("t", shape="cone")
    # legal: a shelf with the top drawer only
    BaseCabinet("c", shelf=True, small_drawers=(False, False, False, True)).build_spec().compile()


def test_seed_varies_and_is_reproducible():
    a, b, c = Mug("m", seed=1), Mug("m", seed=1), Mug("m", seed=2)
    assert (a.radius, a.height, a.rgba) == (b.radius, b.height, b.rgba)
    assert (a.radius, a.height) != (c.radius, c.height)
    nominal = Mug("m")
    assert nominal.radius == 0.045 and nominal.height == 0.105
    for seed in range(20):
        m = Mug("m", seed=seed)
        assert 0.04 < m.radius < 0.05 and 0.095 < m.height < 0.115
        assert all(0.0 <= ch <= 1.0 for ch in m.rgba)


@pytest.mark.parametrize(
    "prop, keys",
    [
        (
            BaseCabinet("c", big_drawers=(True, False), small_drawers=(False, False, True, True), hob=True),
            ["drawer_big_1", "drawer_small_3", "drawer_small_4"],
        ),
        (BaseCabinet("c", door_left=True, shelf=True), ["door_left"]),
        (WallCabinet("w", glass=True), ["door_right", "door_left"]),
        (Dishwasher("d"), ["door", "tray_bottom", "tray_mid"]),
    ],
)
def test_state_roundtrip(prop: ArticulatedProp, keys):
    spec = make_world()
    prop.attach_to(spec.worldbody, (1.2, 0, 0))
    model, data = compile_bound(spec, [prop])
    assert prop.joint_keys == keys
    assert prop.joint_names == [f"{prop.name}/{k}" for k in keys]
    np.testing.assert_allclose(prop.get_state(data), 0.0)
    want = np.linspace(0.2, 0.8, len(keys))
    data.qvel[:] = 1.0
    prop.set_state(data, want)
    np.testing.assert_allclose(prop.get_state(data), want)
    assert np.all(data.qvel[prop._jd] == 0.0)
    prop.set_state(data, 7.0)  # clipped
    np.testing.assert_allclose(prop.get_state(data), 1.0)
    np.testing.assert_allclose(data.qpos[prop._jq], model.jnt_range[prop.joint_ids, 1])
    prop.set_joint_state(data, keys[-1], -3.0)
    assert prop.get_state(data)[prop.joint_index(keys[-1])] == 0.0


def test_part_geoms_belong_to_their_bodies():
    spec = make_world()
    cab = BaseCabinet("cab", door_right=True, shelf=True, hob=True)
    dw = Dishwasher("dw")
    cab.attach_to(spec.worldbody, (1.2, 0, 0))
    dw.attach_to(spec.worldbody, (1.2, -0.6, 0))
    model, _ = compile_bound(spec, [cab, dw])
    root = cab.root_body_id
    for part in ("counter", "shelf", "shelf_bottom", "hob", "walls"):
        assert np.all(model.geom_bodyid[cab.part_geom_ids(part)] == root)
    assert np.all(model.geom_bodyid[cab.part_geom_ids("door_right")] == model.body("cab/door_right").id)
    tray = model.body("dw/tray_bottom").id
    assert np.all(model.geom_bodyid[dw.part_geom_ids("tray_bottom")] == tray)
    assert np.all(model.geom_bodyid[dw.part_geom_ids("basket")] == tray)
    both = dw.part_geom_ids("tray_bottom", "basket")
    assert len(both) == len(dw.part_geom_ids("tray_bottom")) + len(dw.part_geom_ids("basket"))
    with pytest.raises(KeyError):
        cab.part_geom_ids("basket")


def test_contact_helper_and_collision_switch():
    spec = make_world()
    table = Table("table")
    table.attach_to(spec.worldbody, (0.7, 0, 0))
    plate = Plate("plate")
    plate.attach_to(spec.worldbody, (0.7, 0, 0.9505))
    model, data = compile_bound(spec, [table, plate])
    for _ in range(50):
        mujoco.mj_step(model, data)
    assert geoms_in_contact(data, plate.collision_geom_ids, table.part_geom_ids("top"))
    assert not geoms_in_contact(data, plate.collision_geom_ids, table.part_geom_ids("shelf"))
    mask_plate, mask_top = geom_mask(model, plate.collision_geom_ids), geom_mask(model, table.part_geom_ids("top"))
    assert geoms_in_contact(data, mask_plate, mask_top)
    assert not geoms_in_contact(data, mask_plate, geom_mask(model, table.part_geom_ids("legs")))
    assert np.linalg.norm(plate.get_velocity(data)) < 0.05
    plate.set_collisions_enabled(False)
    mujoco.mj_forward(model, data)
    assert not geoms_in_contact(data, plate.collision_geom_ids, table.part_geom_ids("top"))
    plate.set_collisions_enabled(True)
    mujoco.mj_forward(model, data)
    assert geoms_in_contact(data, plate.collision_geom_ids, table.part_geom_ids("top"))


def test_set_pose_free_mocap_static():
    spec = make_world()
    plate, marker, rack = Plate("plate"), TargetMarker("target"), DishDrainer("rack")
    plate.attach_to(spec.worldbody, (0, 0, 1))
    marker.attach_to(spec.worldbody, (0.5, 0, 1))
    rack.attach_to(spec.worldbody, (1, 0, 0))
    model, data = compile_bound(spec, [plate, marker, rack])
    q = np.array([0.0, 1.0, 0.0, 0.0])
    plate.set_pose(data, (0.3, 0.2, 1.1), q)
    marker.set_pose(data, (0.4, -0.1, 1.2))
    rack.set_pose(data, (1.5, 0.5, 0.0))
    mujoco.mj_forward(model, data)
    pos, quat = plate.get_pose(data)
    np.testing.assert_allclose(pos, (0.3, 0.2, 1.1))
    np.testing.assert_allclose(quat, q)
    np.testing.assert_allclose(marker.get_pose(data)[0], (0.4, -0.1, 1.2))
    np.testing.assert_allclose(rack.get_pose(data)[0], (1.5, 0.5, 0.0))
    # the marker never collides
    assert len(marker.collision_geom_ids) == 0


@pytest.mark.parametrize(
    "profile",
    [[(0, 0), (0.1, 0), (0.1, 0.2), (0, 0.2)], [(0, 0), (0.05, 0), (0.05, 0.1), (0.04, 0.1), (0.04, 0.01), (0, 0.01)]],
)
def test_lathe_mesh_is_closed_and_outward(profile):
    v, f = lathe_mesh(profile, 16)
    tri = v[f]
    vol = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6
    assert vol > 0
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert np.all(counts == 2), "every edge is shared by exactly two faces"
    with pytest.raises(ValueError):
        lathe_mesh([(0.1, 0), (0.1, 1), (0, 1)])
