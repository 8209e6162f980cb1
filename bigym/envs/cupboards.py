"""Kitchen-counter articulation tasks: drawers, wall cupboard doors, and all of them.

Scene ``counter_base_wall_3x1``: a drawer cabinet (big drawer, two small drawers, hob)
between two door cabinets, and a wall cabinet with two doors above. Success (paper,
appendix): every named joint within 0.1 of open (1) or closed (0), normalised.
"""

from __future__ import annotations

from typing import ClassVar

from bigym.envs.task import KitchenTask

TOLERANCE = 0.1
DRAWERS = ("cabinet_drawers", ("drawer_big_1", "drawer_small_3", "drawer_small_4"))
TOP_DRAWER = ("cabinet_drawers", ("drawer_small_4",))
WALL_DOORS = ("wall_cabinet", ("door_right", "door_left"))
BASE_DOORS = (("cabinet_right", ("door_left",)), ("cabinet_left", ("door_right",)))


class _CupboardTask(KitchenTask):
    """Drive some joints to ``goal``; the others start closed (with small random gaps)."""

    scene_name = "counter_base_wall_3x1"
    robot_start: ClassVar[tuple[float, float, float]] = (0.0, 0.0, 0.0)
    robot_start_noise: ClassVar[tuple[float, float, float]] = (0.05, 0.05, 0.08)
    goal: ClassVar[float] = 1.0
    # (prop, joint keys) that must reach the goal
    targets: ClassVar[tuple[tuple[str, tuple[str, ...]], ...]] = ()
    # (prop, joint keys) that start open in the closing tasks although they are not targets
    start_open: ClassVar[tuple[tuple[str, tuple[str, ...]], ...]] = ()

    def _on_reset(self) -> None:
        rng = self.np_random
        for prop in self._articulated.values():
            prop.set_state(self.data, rng.uniform(0.0, 0.03, len(prop.joint_keys)))
        opened = self.targets if self.goal == 0.0 else ()
        for name, keys in (*opened, *self.start_open):
            for key in keys:
                self.props[name].set_joint_state(self.data, key, rng.uniform(0.75, 1.0))

    def _success(self) -> bool:
        return all(self.joints_near(name, self.goal, TOLERANCE, keys) for name, keys in self.targets)


class DrawerTopOpen(_CupboardTask):
    """Open the top drawer."""

    time_limit = 12.0
    targets = (TOP_DRAWER,)


class DrawerTopClose(_CupboardTask):
    """Close the open top drawer."""

    time_limit = 8.0
    goal = 0.0
    targets = (TOP_DRAWER,)


class DrawersOpenAll(_CupboardTask):
    """Open all three drawers."""

    time_limit = 30.0
    targets = (DRAWERS,)


class DrawersCloseAll(_CupboardTask):
    """Close all three open drawers."""

    time_limit = 12.0
    goal = 0.0
    targets = (DRAWERS,)


class WallCupboardOpen(_CupboardTask):
    """Open both doors of the wall cupboard."""

    time_limit = 15.0
    targets = (WALL_DOORS,)


class WallCupboardClose(_CupboardTask):
    """Close both open doors of the wall cupboard."""

    time_limit = 8.0
    goal = 0.0
    targets = (WALL_DOORS,)


class CupboardsOpenAll(_CupboardTask):
    """Open every drawer and door: three drawers, two base-cabinet doors, two wall doors."""

    time_limit = 55.0
    targets = (DRAWERS, *BASE_DOORS, WALL_DOORS)


class CupboardsCloseAll(_CupboardTask):
    """Close every open drawer and door."""

    time_limit = 40.0
    goal = 0.0
    targets = (DRAWERS, *BASE_DOORS, WALL_DOORS)


__all__ = [
    "CupboardsCloseAll",
    "CupboardsOpenAll",
    "DrawerTopClose",
    "DrawerTopOpen",
    "DrawersCloseAll",
    "DrawersOpenAll",
    "WallCupboardClose",
    "WallCupboardOpen",
]
