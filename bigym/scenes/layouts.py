"""Named kitchen layouts matching the reference presets, plus ``kitchen_full``.

World convention: the robot stands near the origin facing ``+x``; module fronts face
``-x``. A base cabinet placed at ``x = 1.2`` has its front at ``x = 0.6`` and its
counter top at ``z = 0.86``; wall cabinets hang from 1.45 to 2.17 m with their doors at
``x = 0.86``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from bigym.props import (
    BaseCabinet,
    Cereals,
    ChoppingBoard,
    CounterTop,
    CutleryHolder,
    CutleryTray,
    DishDrainer,
    Dishwasher,
    Fork,
    FryingPan,
    Jar,
    Knife,
    Mug,
    OpenShelf,
    Plate,
    Prop,
    Sandwich,
    Saucepan,
    Spoon,
    Table,
    WallCabinet,
    Wine,
)
from bigym.props.base import quat_axis_angle, quat_mul, quat_yaw

from .base import Placement, Scene

__all__ = ["SCENES", "make_scene", "scene_names"]

P = Placement


def _site_local(cls: type[Prop], key: str, **kwargs) -> np.ndarray:
    """Position of a site of the root body of ``cls(**kwargs)`` in the prop frame."""
    spec = cls("tmp", None, **kwargs).build_spec()
    return np.array(spec.site(key).pos)


def _at(
    base: tuple[float, float, float], yaw_deg: float, local: np.ndarray, dz: float = 0.0
) -> tuple[float, float, float]:
    c, s = np.cos(np.deg2rad(yaw_deg)), np.sin(np.deg2rad(yaw_deg))
    x = base[0] + c * local[0] - s * local[1]
    y = base[1] + s * local[0] + c * local[1]
    return (float(x), float(y), float(base[2] + local[2] + dz))


def _q(q: np.ndarray) -> tuple[float, float, float, float]:
    return tuple(float(v) for v in q)  # type: ignore[return-value]


def _cutlery_in_holder_quat(a: float, lean: float = 0.12) -> tuple[float, float, float, float]:
    """Cutlery standing head-up at polar angle ``a`` in a round holder: flat side facing
    the centre, leaning ``lean`` rad outwards."""
    up = quat_axis_angle((1, 0, 0), np.pi / 2)  # local +y (head) -> world +z
    q = quat_mul(quat_yaw(a + np.pi / 2), up)
    q = quat_mul(quat_axis_angle((-np.sin(a), np.cos(a), 0.0), lean), q)
    return _q(q)


# --------------------------------------------------------------------------- presets
def _cabinet() -> list[Placement]:
    return [P("cabinet", BaseCabinet, (1.2, 0, 0), kwargs={"panel": True})]


def _cabinet_door() -> list[Placement]:
    return [P("cabinet", BaseCabinet, (1.2, 0, 0), kwargs={"door_left": True, "shelf": True})]


def _cabinet_hob() -> list[Placement]:
    return [P("cabinet", BaseCabinet, (1.2, 0, 0), kwargs={"door_left": True, "shelf": True, "hob": True})]


def _counter_base_2(hob: bool = False) -> list[Placement]:
    return [
        P("cabinet_1", BaseCabinet, (1.1, 0, 0), kwargs={"shelf": True, "door_right": True, "hob": hob}),
        P("cabinet_2", BaseCabinet, (1.1, -0.6, 0), kwargs={"door_left": True}),
    ]


def _counter_base_wall_1x1() -> list[Placement]:
    return [
        P("cabinet", BaseCabinet, (1.2, 0, 0), kwargs={"door_left": True, "shelf": True}),
        P("wall_cabinet", WallCabinet, (1.2, 0, 0), kwargs={"glass": True}),
    ]


def _counter_base_wall_2x2() -> list[Placement]:
    return _counter_base_2() + [
        P("wall_cabinet", WallCabinet, (1.1, 0, 0), kwargs={"glass": True}),
        P("open_shelf", OpenShelf, (1.1, -0.6, 0)),
    ]


def _counter_base_wall_3x1() -> list[Placement]:
    return [
        P(
            "cabinet_drawers",
            BaseCabinet,
            (1.2, 0, 0),
            kwargs={"big_drawers": (True, False), "small_drawers": (False, False, True, True), "hob": True},
        ),
        P("cabinet_right", BaseCabinet, (1.2, -0.6, 0), kwargs={"door_left": True, "shelf": True}),
        P("cabinet_left", BaseCabinet, (1.2, 0.6, 0), kwargs={"door_right": True, "shelf": True}),
        P("wall_cabinet", WallCabinet, (1.2, 0, 0), kwargs={"doors": True, "vent": True}),
    ]


def _counter_dishwasher() -> list[Placement]:
    return [
        P("dishwasher", Dishwasher, (1.0, 0, 0)),
        P("dishwasher_counter", CounterTop, (1.0, 0, 0)),
        P("cabinet", BaseCabinet, (1.0, -0.6, 0), kwargs={"panel": True}),
    ]


def _counter_dishwasher_cutlery_cabinet() -> list[Placement]:
    return _counter_dishwasher() + [
        P("cutlery_cabinet", BaseCabinet, (1.0, -1.2, 0), kwargs={"small_drawers": (True, True, True, True)}),
        P(
            "cutlery_tray",
            CutleryTray,
            (0.0, 0.0, 0.0005),
            kwargs={"size": (0.42, 0.5, 0.056)},
            parent=("cutlery_cabinet", "drawer_small_4"),
        ),
    ]


def _counter_dishwasher_wall_cabinet() -> list[Placement]:
    return _counter_dishwasher() + [P("wall_cabinet", WallCabinet, (1.0, -0.6, 0), kwargs={"glass": True})]


def _dishwasher() -> list[Placement]:
    return [P("dishwasher", Dishwasher, (1.2, 0, 0))]


def _move_plates() -> list[Placement]:
    return [
        P("table", Table, (0.7, 0, 0)),
        P("drainer_start", DishDrainer, (0.7, 0.3, Table.HEIGHT)),
        P("drainer_target", DishDrainer, (0.7, -0.3, Table.HEIGHT)),
    ]


def _stack_blocks() -> list[Placement]:
    return [P("table_1", Table, (0.7, 0, 0)), P("table_2", Table, (1.4, 0, 0))]


# --------------------------------------------------------------------------- full kitchen
def _kitchen_full() -> list[Placement]:
    xb = 1.2
    out: list[Placement] = [
        P("cabinet_a", BaseCabinet, (xb, 1.2, 0), kwargs={"door_right": True, "shelf": True}),
        P("cabinet_b", BaseCabinet, (xb, 0.6, 0), kwargs={"small_drawers": (True, True, True, True)}),
        P(
            "cabinet_hob",
            BaseCabinet,
            (xb, 0.0, 0),
            kwargs={"big_drawers": (True, False), "small_drawers": (False, False, True, True), "hob": True},
        ),
        P("cabinet_c", BaseCabinet, (xb, -0.6, 0), kwargs={"door_left": True, "shelf": True}),
        P("dishwasher", Dishwasher, (xb, -1.2, 0)),
        P("dishwasher_counter", CounterTop, (xb, -1.2, 0)),
        P("cutlery_cabinet", BaseCabinet, (xb, -1.8, 0), kwargs={"small_drawers": (True, True, True, True)}),
        P(
            "cutlery_tray",
            CutleryTray,
            (0.0, 0.0, 0.0005),
            kwargs={"size": (0.42, 0.5, 0.056)},
            parent=("cutlery_cabinet", "drawer_small_4"),
        ),
        P("wall_cabinet_a", WallCabinet, (xb, 1.2, 0), kwargs={"glass": True}),
        P("wall_cabinet_b", WallCabinet, (xb, 0.6, 0), kwargs={"doors": True}),
        P("wall_cabinet_hob", WallCabinet, (xb, 0.0, 0), kwargs={"doors": True, "vent": True}),
        P("wall_cabinet_c", WallCabinet, (xb, -0.6, 0), kwargs={"glass": True}),
        P("open_shelf_1", OpenShelf, (xb, -1.2, 0)),
        P("open_shelf_2", OpenShelf, (xb, -1.8, 0)),
        P("table", Table, (-1.0, 0.0, 0.0), yaw=180.0),
        P("drainer_table", DishDrainer, (-1.0, 0.3, Table.HEIGHT), yaw=180.0),
        P("drainer_counter", DishDrainer, (0.85, -0.6, 0.86)),
    ]
    # free objects, spawned at rest
    top = Table.HEIGHT + 0.0005
    # plates standing in the table drainer, face normal along world y
    slot2 = _site_local(DishDrainer, "plate_slot_2")
    slot5 = _site_local(DishDrainer, "plate_slot_5")
    q_plate = _q(quat_axis_angle((1, 0, 0), -np.pi / 2))  # plate normal -> +y
    for nm, slot in (("plate_1", slot2), ("plate_2", slot5)):
        x, y, z = _at((-1.0, 0.3, Table.HEIGHT), 180.0, slot)
        out.append(P(nm, Plate, (x, y - 0.0095, z - 0.0005), quat=q_plate))
    out += [
        P("board", ChoppingBoard, (-1.0, -0.3, top), yaw=180.0),
        P("sandwich", Sandwich, (-1.0, -0.3, top + 0.028 + 0.019), yaw=170.0),
        P("cutlery_holder", CutleryHolder, (-0.85, 0.0, top)),
        P("mug_1", Mug, (0.8, 0.5, 0.8605), yaw=180.0),
        P("mug_2", Mug, (0.8, 0.72, 0.8605), yaw=160.0),
    ]
    # cutlery standing in the holder, head up, leaning apart
    for k, (nm, cls) in enumerate((("fork", Fork), ("knife", Knife), ("spoon", Spoon))):
        a = 2 * np.pi * k / 3
        q = _cutlery_in_holder_quat(a)
        half = cls("tmp").length / 2
        pos = (-0.85 + 0.022 * np.cos(a), 0.022 * np.sin(a), top + 0.012 + half * np.cos(0.12) + 0.004)
        out.append(P(nm, cls, pos, quat=q))
    # cookware on the hob
    hob1 = _site_local(BaseCabinet, "hob_site_1", hob=True)
    hob4 = _site_local(BaseCabinet, "hob_site_4", hob=True)
    out += [
        P("pan", FryingPan, _at((xb, 0.0, 0.0), 0.0, hob1, 0.0005), yaw=180.0),
        P("saucepan", Saucepan, _at((xb, 0.0, 0.0), 0.0, hob4, 0.0005), yaw=180.0),
    ]
    # groceries on the shelf behind the door of cabinet_c (shelf top 0.48)
    out += [
        P("cereals", Cereals, (0.95, -0.78, 0.4805)),
        P("wine", Wine, (0.95, -0.6, 0.4805)),
        P("jar", Jar, (0.85, -0.45, 0.4805)),
    ]
    # a plate in the dishwasher's bottom tray and a mug upside down on the upper tray
    dw = (xb, -1.2, 0.0)
    spec = Dishwasher("tmp").build_spec()
    ps = np.array(spec.site("plate_slot_2_4").pos)
    cs = np.array(spec.site("cup_slot_2_6").pos)
    x, y, z = _at(dw, 0.0, ps)
    out.append(P("plate_dishwasher", Plate, (x, y - 0.0095, z - 0.0015), quat=q_plate))
    x, y, z = _at(dw, 0.0, cs)
    mug_q = _q(quat_mul(quat_yaw(np.pi / 2), quat_axis_angle((1, 0, 0), np.pi)))
    out.append(P("mug_dishwasher", Mug, (x, y, z + Mug("tmp").height + 0.0005), quat=mug_q))
    return out


_LAYOUTS: dict[str, tuple[Callable[[], list[Placement]], str]] = {
    "cabinet": (_cabinet, "one base cabinet with a fixed panel front at x = 1.2"),
    "cabinet_door": (_cabinet_door, "base cabinet (x = 1.2) with door_left and a middle shelf"),
    "cabinet_hob": (_cabinet_hob, "base cabinet (x = 1.2) with door_left, a middle shelf and a hob"),
    "counter_base_2": (_counter_base_2, "two base cabinets at x = 1.1: y = 0 door_right + shelf, y = -0.6 door_left"),
    "counter_base_2_hob": (lambda: _counter_base_2(hob=True), "counter_base_2 with a hob on cabinet_1"),
    "counter_base_wall_1x1": (_counter_base_wall_1x1, "cabinet_door + a glass wall cabinet above it"),
    "counter_base_wall_2x2": (
        _counter_base_wall_2x2,
        "counter_base_2 + a glass wall cabinet (y = 0) + an open shelf (y = -0.6)",
    ),
    "counter_base_wall_3x1": (
        _counter_base_wall_3x1,
        "drawer/hob cabinet between two door cabinets + wall cabinet with vent",
    ),
    "counter_dishwasher": (_counter_dishwasher, "dishwasher under a counter + a panel cabinet"),
    "counter_dishwasher_cutlery_cabinet": (
        _counter_dishwasher_cutlery_cabinet,
        "counter_dishwasher + a 4-drawer cabinet with a cutlery tray in its top drawer",
    ),
    "counter_dishwasher_wall_cabinet": (_counter_dishwasher_wall_cabinet, "counter_dishwasher + glass wall cabinet"),
    "dishwasher": (_dishwasher, "a dishwasher alone, back at x = 1.2"),
    "move_plates": (_move_plates, "a table at x = 0.7 with dish drainers at y = +0.3 (start) and -0.3 (target)"),
    "stack_blocks": (_stack_blocks, "two tables, at x = 0.7 and x = 1.4"),
    "kitchen_full": (_kitchen_full, "a full kitchen: counter run, wall cabinets, dishwasher, table, tableware"),
}


def scene_names() -> list[str]:
    """Names of all registered layouts."""
    return list(_LAYOUTS)


def make_scene(name: str) -> Scene:
    """A fresh :class:`Scene` for layout ``name``."""
    try:
        fn, desc = _LAYOUTS[name]
    except KeyError:
        raise KeyError(f"unknown scene {name!r}; known: {scene_names()}") from None
    return Scene(name, fn(), desc)


#: layout name -> factory of a fresh Scene
SCENES: dict[str, Callable[[], Scene]] = {n: (lambda n=n: make_scene(n)) for n in _LAYOUTS}
