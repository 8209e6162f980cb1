"""Procedural prop library (kitchen modules, dishwasher, tableware, cookware, groceries,
furniture), built in code with :class:`mujoco.MjSpec`.

Typical use::

    spec = world_spec()                      # any MjSpec
    plate = Plate("plate")
    plate.attach_to(spec.worldbody, pos=(0.7, 0.0, 1.0))
    model = spec.compile(); data = mujoco.MjData(model)
    plate.bind(model, data)
    plate.set_pose(data, (0.7, 0.1, 1.0))
"""

from __future__ import annotations

from .base import (
    ArticulatedProp,
    Colors,
    Prop,
    geom_mask,
    geoms_in_contact,
    quat_axis_angle,
    quat_euler,
    quat_mul,
    quat_yaw,
)
from .cookware import ChoppingBoard, FryingPan, Sandwich, Saucepan, Spatula
from .dishwasher import Dishwasher
from .furniture import Block, LargeBox, SmallTable, Table, TargetMarker
from .groceries import (
    GROCERY_CLASSES,
    Beer,
    Cereals,
    Crisps,
    Detergent,
    Jar,
    Ketchup,
    Mustard,
    Soap,
    Soda,
    SoupCan,
    Wine,
)
from .kitchen import BaseCabinet, CounterTop, Hob, OpenShelf, WallCabinet
from .tableware import CutleryHolder, CutleryTray, DishDrainer, Fork, Knife, Mug, Plate, Spoon

#: every prop class by name
PROP_CLASSES: dict[str, type[Prop]] = {
    cls.__name__: cls
    for cls in (
        BaseCabinet,
        WallCabinet,
        OpenShelf,
        CounterTop,
        Hob,
        Dishwasher,
        Plate,
        Mug,
        Fork,
        Knife,
        Spoon,
        DishDrainer,
        CutleryHolder,
        CutleryTray,
        FryingPan,
        Saucepan,
        Spatula,
        Sandwich,
        ChoppingBoard,
        *GROCERY_CLASSES,
        Table,
        SmallTable,
        Block,
        LargeBox,
        TargetMarker,
    )
}

__all__ = [
    "GROCERY_CLASSES",
    "PROP_CLASSES",
    "ArticulatedProp",
    "BaseCabinet",
    "Beer",
    "Block",
    "Cereals",
    "ChoppingBoard",
    "Colors",
    "CounterTop",
    "Crisps",
    "CutleryHolder",
    "CutleryTray",
    "Detergent",
    "DishDrainer",
    "Dishwasher",
    "Fork",
    "FryingPan",
    "Hob",
    "Jar",
    "Ketchup",
    "Knife",
    "LargeBox",
    "Mug",
    "Mustard",
    "OpenShelf",
    "Plate",
    "Prop",
    "Sandwich",
    "Saucepan",
    "SmallTable",
    "Soap",
    "Soda",
    "SoupCan",
    "Spatula",
    "Spoon",
    "Table",
    "TargetMarker",
    "WallCabinet",
    "Wine",
    "geom_mask",
    "geoms_in_contact",
    "quat_axis_angle",
    "quat_euler",
    "quat_mul",
    "quat_yaw",
]
