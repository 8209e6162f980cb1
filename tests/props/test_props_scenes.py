"""Scenes: every layout compiles, places its modules where the tasks expect them, and
sits still for 10 s."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from propkit import compile_bound, make_world

from bigym.props import BaseCabinet, DishDrainer, Dishwasher, Table, WallCabinet
from bigym.scenes import SCENES, Scene, make_scene, scene_names

PRESETS = [
    "cabinet",
    "cabinet_door",
    "cabinet_hob",
    "counter_base_2",
    "counter_base_2_hob",
    "counter_base_wall_1x1",
    "counter_base_wall_2x2",
    "counter_base_wall_3x1",
    "counter_dishwasher",
    "counter_dishwasher_cutlery_cabinet",
    "counter_dishwasher_wall_cabinet",
    "dishwasher",
    "move_plates",
    "stack_blocks",
]


def _build(name: str, seed: int | None = None):
    spec = make_world()
    scene = make_scene(name)
    props = scene.populate(spec, seed=seed)
    model, data = compile_bound(spec, props.values())
    return model, data, scene


def _top_of(model, data, geom_ids) -> float:
    return max(data.geom_xpos[g][2] + model.geom_size[g][2] for g in geom_ids)


def test_registry():
    assert set(PRESETS) | {"kitchen_full"} == set(scene_names())
    assert set(SCENES) == set(scene_names())
    assert isinstance(SCENES["dishwasher"](), Scene)
    with pytest.raises(KeyError):
        make_scene("garage")


@pytest.mark.parametrize("name", scene_names())
def test_scene_compiles_without_interpenetration(name):
    """Closed and fully open, the fixtures of a layout touch nothing."""
    model, data, scene = _build(name)
    assert data.ncon == 0, [(model.geom(c.geom1).name, model.geom(c.geom2).name) for c in data.contact[: data.ncon]]
    if name == "kitchen_full":
        return  # holds free objects inside drawers and trays
    for p in scene.articulated.values():
        p.set_state(data, 1.0)
    mujoco.mj_forward(model, data)
    assert data.ncon == 0, [(model.geom(c.geom1).name, model.geom(c.geom2).name) for c in data.contact[: data.ncon]]


def test_base_cabinet_geometry_matches_the_reference():
    model, data, scene = _build("cabinet_hob")
    cab: BaseCabinet = scene.props["cabinet"]  # type: ignore[assignment]
    counter = cab.part_geom_ids("counter")[0]
    assert _top_of(model, data, [counter]) == pytest.approx(0.86)
    lo = data.geom_xpos[counter][0] - model.geom_size[counter][0]
    assert lo == pytest.approx(0.58)  # 2 cm overhang over the fronts at x = 0.6
    assert _top_of(model, data, cab.part_geom_ids("hob")) == pytest.approx(0.87)
    assert _top_of(model, data, cab.part_geom_ids("shelf")) == pytest.approx(0.48)
    assert _top_of(model, data, cab.part_geom_ids("shelf_bottom")) == pytest.approx(0.13)
    for k in range(1, 5):
        p = cab.site_pos(data, f"hob_site_{k}")
        assert p[2] == pytest.approx(0.87) and 0.6 < p[0] < 1.2 and abs(p[1]) < 0.3
    handle = cab.site_pos(data, "door_left_handle")
    assert handle[0] < 0.6 and handle[1] > 0.0  # door_left hinges on -y: handle on +y
    assert model.body_pos[cab.root_body_id] == pytest.approx((1.2, 0.0, 0.0))


def test_counter_base_wall_3x1_layout():
    model, data, scene = _build("counter_base_wall_3x1")
    states = {k: p.joint_keys for k, p in scene.articulated.items()}
    assert states == {
        "cabinet_drawers": ["drawer_big_1", "drawer_small_3", "drawer_small_4"],
        "cabinet_right": ["door_left"],
        "cabinet_left": ["door_right"],
        "wall_cabinet": ["door_right", "door_left"],
    }
    assert sum(len(v) for v in states.values()) == 7
    # the side doors hinge on their outer edges: their handles are next to the middle
    assert abs(scene.props["cabinet_right"].site_pos(data, "door_left_handle")[1]) < 0.4
    assert abs(scene.props["cabinet_left"].site_pos(data, "door_right_handle")[1]) < 0.4
    wall: WallCabinet = scene.props["wall_cabinet"]  # type: ignore[assignment]
    assert _top_of(model, data, wall.part_geom_ids("shelf_bottom")) == pytest.approx(1.47)
    assert "vent" in wall.part_names
    top = scene.props["cabinet_drawers"].site_pos(data, "drawer_small_4_handle")
    assert 0.7 < top[2] < 0.8 and top[0] < 0.6


def test_dishwasher_layout_and_cutlery_tray_in_drawer():
    model, data, scene = _build("counter_dishwasher_cutlery_cabinet")
    dw: Dishwasher = scene.props["dishwasher"]  # type: ignore[assignment]
    cab: BaseCabinet = scene.props["cutlery_cabinet"]  # type: ignore[assignment]
    tray = scene.props["cutlery_tray"]
    counter = scene.props["dishwasher_counter"].part_geom_ids("counter")
    assert _top_of(model, data, counter) == pytest.approx(0.86)
    assert dw.site_pos(data, "door_handle")[0] < 0.4
    # the tray rides in the top drawer, below the counter, and comes out with it
    assert model.body_parentid[tray.root_body_id] == model.body("cutlery_cabinet/drawer_small_4").id
    z_tray = tray.get_pose(data)[0][2]
    assert 0.65 < z_tray and z_tray + 0.056 < 0.83
    x0 = tray.get_pose(data)[0][0]
    cab.set_joint_state(data, "drawer_small_4", 1.0)
    mujoco.mj_forward(model, data)
    assert tray.get_pose(data)[0][0] == pytest.approx(x0 - 0.38)
    # opened, the dishwasher's trays come out over the open door
    dw.set_state(data, [1.0, 1.0, 1.0])
    mujoco.mj_forward(model, data)
    assert dw.site_pos(data, "plate_slot_1_1")[0] < 0.2
    assert data.ncon == 0


def test_move_plates_and_stack_blocks_layout():
    model, data, scene = _build("move_plates")
    table: Table = scene.props["table"]  # type: ignore[assignment]
    assert _top_of(model, data, table.part_geom_ids("top")) == pytest.approx(0.95)
    for name, y in (("drainer_start", 0.3), ("drainer_target", -0.3)):
        rack: DishDrainer = scene.props[name]  # type: ignore[assignment]
        np.testing.assert_allclose(rack.get_pose(data)[0], (0.7, y, 0.95))
        assert rack.site_pos(data, "plate_slot_1")[2] == pytest.approx(1.10)
    model, data, scene = _build("stack_blocks")
    tops = [_top_of(model, data, scene.props[t].part_geom_ids("top")) for t in ("table_1", "table_2")]
    assert tops == pytest.approx([0.95, 0.95])


def test_populate_seed_is_reproducible():
    m1, _, _ = _build("counter_base_wall_2x2", seed=3)
    m2, _, _ = _build("counter_base_wall_2x2", seed=3)
    m3, _, _ = _build("counter_base_wall_2x2", seed=4)
    m0, _, _ = _build("counter_base_wall_2x2")
    np.testing.assert_array_equal(m1.geom_rgba, m2.geom_rgba)
    np.testing.assert_array_equal(m1.geom_size, m2.geom_size)
    assert not np.array_equal(m1.geom_rgba, m3.geom_rgba)
    assert not np.array_equal(m0.geom_rgba, m1.geom_rgba)
    np.testing.assert_array_equal(m0.body_pos, m1.body_pos)  # layout never moves


def _dishwasher_safe(prop, state: np.ndarray) -> np.ndarray:
    if isinstance(prop, Dishwasher) and state[0] < 0.999:
        state[1:] = 0.0  # trays only come out with the door fully open
    return state


@pytest.mark.parametrize("name", scene_names())
def test_scene_idles_for_ten_seconds(name):
    """Articulations set to random states (kitchen_full: closed, since it holds free
    objects inside drawers and trays) and left alone for 10 s: nothing drifts more than
    1 mm, nothing jitters."""
    model, data, scene = _build(name)
    rng = np.random.default_rng(1)
    if name != "kitchen_full":
        for p in scene.articulated.values():
            state = rng.uniform(0.0, 1.0, len(p.joint_keys))
            if isinstance(p, Dishwasher) and rng.uniform() < 0.5:
                state[0] = 1.0
            p.set_state(data, _dishwasher_safe(p, state))
    mujoco.mj_forward(model, data)
    free = scene.free_props
    for _ in range(500):  # 1 s to settle objects spawned a hair above their supports
        mujoco.mj_step(model, data)
    xpos0 = data.xpos.copy()
    max_speed = 0.0
    for i in range(4500):
        mujoco.mj_step(model, data)
        if i % 5 == 0:
            max_speed = max(max_speed, float(np.abs(data.cvel[:, 3:]).max()))
    assert not data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number
    drift = np.linalg.norm(data.xpos - xpos0, axis=1)
    worst = int(np.argmax(drift))
    assert drift.max() < 1e-3, f"{model.body(worst).name} drifted {drift.max() * 1000:.2f} mm"
    assert max_speed < 5e-3, f"max body speed {max_speed:.4f} m/s"
    for p in free.values():
        assert data.xpos[p.root_body_id][2] > 0.05, f"{p.name} fell to the floor"
