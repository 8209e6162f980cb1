"""Free props come to rest, sit in their racks/slots/holders and do not sink."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from propkit import body_axis, compile_bound, free_speed, lowest_z, make_world, min_contact_dist, table_world

from bigym.props import (
    PROP_CLASSES,
    CutleryHolder,
    CutleryTray,
    DishDrainer,
    Dishwasher,
    Fork,
    FryingPan,
    Knife,
    Mug,
    Plate,
    Sandwich,
    Spoon,
    Table,
    geoms_in_contact,
)
from bigym.props.base import quat_axis_angle, quat_mul, quat_yaw

FREE = sorted(n for n, c in PROP_CLASSES.items() if c.FREE)
TOP = Table.HEIGHT
PLATE_UP_Y = quat_axis_angle((1, 0, 0), -np.pi / 2)  # plate face normal -> world +y
CUTLERY_UP = quat_axis_angle((1, 0, 0), np.pi / 2)  # cutlery head -> world +z
MUG_DOWN = quat_mul(quat_yaw(np.pi), quat_axis_angle((1, 0, 0), np.pi))  # upside down, handle -> -x


def _simulate(model, data, seconds: float, track=()) -> float:
    """Step; return the most negative contact distance seen."""
    worst = 0.0
    for _ in range(round(seconds / model.opt.timestep)):
        mujoco.mj_step(model, data)
        worst = min(worst, min_contact_dist(data))
    return worst


@pytest.mark.parametrize("name", FREE)
def test_free_prop_dropped_on_table_comes_to_rest(name):
    """Dropped from 1 cm above the table top: at rest within 2 s (< 1 cm/s), the impact
    sinks it less than 2 mm and at rest it sits within 0.1 mm of the surface."""
    prop = PROP_CLASSES[name]("obj", seed=11)
    spec, table, props = table_world([(prop, (0.7, 0.0, 1.5), (1, 0, 0, 0))])
    model, data = compile_bound(spec, props)
    data.qpos[prop._qadr + 2] -= lowest_z(model, data, prop.collision_geom_ids) - (TOP + 0.01)
    mujoco.mj_forward(model, data)
    worst = _simulate(model, data, 1.5)
    speeds = []
    for _ in range(250):
        mujoco.mj_step(model, data)
        speeds.append(free_speed(data, prop))
        worst = min(worst, min_contact_dist(data))
    assert max(speeds) < 0.01, f"still moving at {max(speeds):.4f} m/s"
    assert worst > -0.002, f"sank {-worst * 1000:.2f} mm"
    assert min_contact_dist(data) > -1e-4
    assert geoms_in_contact(data, prop.collision_geom_ids, table.part_geom_ids("top"))
    if name not in ("Spatula", "Spoon"):  # those rest on a tilt by design
        assert body_axis(data, prop, 2)[2] > 0.995, "it tipped over"


@pytest.mark.parametrize(
    "name", ["Mug", "Wine", "Beer", "Ketchup", "Soda", "Detergent", "Soap", "Jar", "Cereals", "CutleryHolder"]
)
def test_upright_objects_recover_from_a_small_tilt(name):
    """Stood on the table 8 deg off vertical, tall items settle back upright."""
    prop = PROP_CLASSES[name]("obj")
    q = quat_axis_angle((1, 1, 0), np.deg2rad(8))
    spec, _table, props = table_world([(prop, (0.7, 0.0, 1.5), q)])
    model, data = compile_bound(spec, props)
    data.qpos[prop._qadr + 2] -= lowest_z(model, data, prop.collision_geom_ids) - (TOP + 0.002)
    mujoco.mj_forward(model, data)
    _simulate(model, data, 2.0)
    assert body_axis(data, prop, 2)[2] > np.cos(np.deg2rad(1.0))
    assert free_speed(data, prop) < 0.005


def test_plates_rest_in_drainer_slots():
    spec, table, props = table_world()
    rack = DishDrainer("rack")
    rack.attach_to(spec.worldbody, (0.7, 0.0, TOP))
    plates = [Plate(f"plate_{k}", seed=k) for k in range(6)]
    for p in plates:
        p.attach_to(spec.worldbody, (0, 0, 3.0), PLATE_UP_Y)
    model, data = compile_bound(spec, props + [rack] + plates)
    for k, p in enumerate(plates):
        p.set_pose(data, rack.site_pos(data, f"plate_slot_{k + 1}") + (0.0, -0.0095, 0.002), PLATE_UP_Y)
    mujoco.mj_forward(model, data)
    worst = _simulate(model, data, 2.0)
    assert worst > -0.002
    for k, p in enumerate(plates):
        site = rack.site_pos(data, f"plate_slot_{k + 1}")
        pos = p.get_pose(data)[0]
        normal = body_axis(data, p, 2)
        assert abs(normal[1]) > np.cos(np.deg2rad(15)), "plate leans more than 15 deg"
        centre = pos + normal * 0.0095
        assert abs(centre[1] - site[1]) < 0.021 and abs(centre[0] - site[0]) < 0.005
        assert free_speed(data, p) < 0.005
        assert geoms_in_contact(data, p.collision_geom_ids, rack.collision_geom_ids)
        assert not geoms_in_contact(data, p.collision_geom_ids, table.collision_geom_ids)


def _dishwasher_world(n_plates=0, n_mugs=0, cutlery=()):
    spec = make_world()
    dw = Dishwasher("dw")
    dw.attach_to(spec.worldbody, (1.0, 0, 0))
    plates = [Plate(f"plate_{k}") for k in range(n_plates)]
    mugs = [Mug(f"mug_{k}") for k in range(n_mugs)]
    items = [cls(f"cut_{k}") for k, cls in enumerate(cutlery)]
    for p in plates + mugs + items:
        p.attach_to(spec.worldbody, (0, 0, 3.0))
    model, data = compile_bound(spec, [dw] + plates + mugs + items)
    dw.set_state(data, [1.0, 1.0, 1.0])
    mujoco.mj_forward(model, data)
    return model, data, dw, plates, mugs, items


def test_plates_rest_in_dishwasher_tray_slots():
    slots = ["plate_slot_1_1", "plate_slot_1_6", "plate_slot_1_12", "plate_slot_2_2", "plate_slot_2_9"]
    model, data, dw, plates, _, _ = _dishwasher_world(n_plates=len(slots))
    for p, key in zip(plates, slots, strict=True):
        p.set_pose(data, dw.site_pos(data, key) + (0.0, -0.0095, 0.001), PLATE_UP_Y)
    mujoco.mj_forward(model, data)
    worst = _simulate(model, data, 2.0)
    assert worst > -0.002
    tray = dw.part_geom_ids("tray_bottom")
    for p, key in zip(plates, slots, strict=True):
        site = dw.site_pos(data, key)
        normal = body_axis(data, p, 2)
        centre = p.get_pose(data)[0] + normal * 0.0095
        assert abs(normal[1]) > np.cos(np.deg2rad(15))
        assert np.linalg.norm(centre[:2] - site[:2]) < 0.02
        assert abs(centre[2] - site[2]) < 0.01
        assert geoms_in_contact(data, p.collision_geom_ids, tray)
        assert free_speed(data, p) < 0.005
    np.testing.assert_allclose(dw.get_state(data), 1.0, atol=0.005)
    # closing the tray at a brisk walk (~0.4 m/s) carries the plates in with it
    for _ in range(2000):
        data.qfrc_applied[dw._jd[1]] = -3.0
        mujoco.mj_step(model, data)
    assert dw.get_state(data)[1] < 0.02
    for p, key in zip(plates, slots, strict=True):
        normal = body_axis(data, p, 2)
        centre = p.get_pose(data)[0] + normal * 0.0095
        assert abs(normal[1]) > np.cos(np.deg2rad(15))
        assert np.linalg.norm(centre[:2] - dw.site_pos(data, key)[:2]) < 0.02


def test_mugs_rest_upside_down_on_the_upper_tray():
    slots = ["cup_slot_1_1", "cup_slot_1_4", "cup_slot_2_7", "cup_slot_2_12"]
    model, data, dw, _, mugs, _ = _dishwasher_world(n_mugs=len(slots))
    for m, key in zip(mugs, slots, strict=True):
        m.set_pose(data, dw.site_pos(data, key) + (0.0, 0.0, m.height + 0.002), MUG_DOWN)
    mujoco.mj_forward(model, data)
    assert _simulate(model, data, 2.0) > -0.002
    for m, key in zip(mugs, slots, strict=True):
        assert body_axis(data, m, 2)[2] < -0.995
        assert np.linalg.norm(m.get_pose(data)[0][:2] - dw.site_pos(data, key)[:2]) < 0.005
        assert geoms_in_contact(data, m.collision_geom_ids, dw.part_geom_ids("tray_mid"))
        assert free_speed(data, m) < 0.005


def test_cutlery_stays_in_the_dishwasher_basket():
    model, data, dw, _, _, items = _dishwasher_world(cutlery=(Fork, Knife, Spoon, Fork))
    keys = ["basket_slot_1", "basket_slot_3", "basket_slot_5", "basket_slot_6"]
    for it, key in zip(items, keys, strict=True):
        it.set_pose(data, dw.site_pos(data, key) + (0, 0, it.length / 2 + 0.003), CUTLERY_UP)
    mujoco.mj_forward(model, data)
    assert _simulate(model, data, 2.5) > -0.002
    basket = dw.part_geom_ids("basket")
    for it, key in zip(items, keys, strict=True):
        site = dw.site_pos(data, key)
        low = it.get_pose(data)[0] - body_axis(data, it, 1) * it.length / 2  # handle end
        assert np.linalg.norm(low[:2] - site[:2]) < 0.04, "fell out of its compartment"
        assert site[2] - 0.005 < low[2] < site[2] + 0.03
        assert body_axis(data, it, 1)[2] > 0.85, "no longer standing"
        assert geoms_in_contact(data, it.collision_geom_ids, basket)
        assert free_speed(data, it) < 0.005


def test_cutlery_stays_in_a_holder():
    holder = CutleryHolder("holder")
    items = [Fork("fork"), Knife("knife"), Spoon("spoon")]
    spec, _table, props = table_world(
        [(holder, (0.7, 0.0, TOP + 0.0005), (1, 0, 0, 0))] + [(it, (0, 0, 3.0), (1, 0, 0, 0)) for it in items]
    )
    model, data = compile_bound(spec, props)
    for k, it in enumerate(items):
        a = 2 * np.pi * k / 3
        lean = quat_axis_angle((-np.sin(a), np.cos(a), 0.0), 0.12)  # head outwards
        q = quat_mul(lean, quat_mul(quat_yaw(a + np.pi / 2), CUTLERY_UP))  # flat side to the centre
        pos = holder.site_pos(data, f"slot_{k + 1}") + (0.0, 0.0, it.length / 2 + 0.005)
        it.set_pose(data, pos, q)
    mujoco.mj_forward(model, data)
    assert _simulate(model, data, 3.0) > -0.002
    hpos = holder.get_pose(data)[0]
    for it in items:
        low = it.get_pose(data)[0] - body_axis(data, it, 1) * it.length / 2
        assert np.linalg.norm(low[:2] - hpos[:2]) < 0.046
        assert low[2] < hpos[2] + 0.03
        assert free_speed(data, it) < 0.005
        assert geoms_in_contact(data, it.collision_geom_ids, holder.collision_geom_ids)
    assert body_axis(data, holder, 2)[2] > 0.999
    assert np.linalg.norm(hpos[:2] - (0.7, 0.0)) < 0.002


def test_cutlery_lies_in_tray_compartments():
    tray = CutleryTray("tray")
    items = [Fork("fork"), Knife("knife"), Spoon("spoon")]
    spec, _table, props = table_world(
        [(tray, (0.7, 0.0, TOP), (1, 0, 0, 0))] + [(it, (0, 0, 3.0), (1, 0, 0, 0)) for it in items]
    )
    model, data = compile_bound(spec, props)
    along_x = quat_yaw(-np.pi / 2)  # cutlery length along the compartments
    for k, it in enumerate(items):
        it.set_pose(data, tray.site_pos(data, f"slot_{2 * k + 1}") + (0, 0, 0.02), along_x)
    mujoco.mj_forward(model, data)
    assert _simulate(model, data, 1.5) > -0.002
    for k, it in enumerate(items):
        site = tray.site_pos(data, f"slot_{2 * k + 1}")
        pos = it.get_pose(data)[0]
        assert abs(pos[1] - site[1]) < 0.03 and pos[2] < site[2] + 0.012
        assert geoms_in_contact(data, it.collision_geom_ids, tray.collision_geom_ids)
        assert free_speed(data, it) < 0.005


def test_sandwich_rests_in_pan_and_board():
    """The sandwich tasks: a pan on the table, a sandwich in it; a board with a sandwich."""
    from bigym.props import ChoppingBoard

    pan, board = FryingPan("pan"), ChoppingBoard("board")
    s1, s2 = Sandwich("s1", rounded=True), Sandwich("s2", toasted=True)
    spec, _table, props = table_world(
        [
            (pan, (0.7, 0.25, TOP + 0.0005), (1, 0, 0, 0)),
            (board, (0.7, -0.25, TOP + 0.0005), (1, 0, 0, 0)),
            (s1, (0.7, 0.25, TOP + 0.005 + 0.019 + 0.003), (1, 0, 0, 0)),
            (s2, (0.7, -0.25, TOP + 0.028 + 0.019 + 0.003), quat_yaw(0.3)),
        ]
    )
    model, data = compile_bound(spec, props)
    assert _simulate(model, data, 2.0) > -0.002
    assert geoms_in_contact(data, s1.collision_geom_ids, pan.collision_geom_ids)
    assert geoms_in_contact(data, s2.collision_geom_ids, board.collision_geom_ids)
    for s in (s1, s2):
        assert body_axis(data, s, 2)[2] > 0.995
        assert free_speed(data, s) < 0.005
