"""Dishwasher articulation tasks: open or close the door and both trays, or just the trays.

Scene ``dishwasher``: a free-standing dishwasher with its front at x = 0.6; the robot
starts beside the door's sweep. Success (paper, appendix): the listed joints within 0.1
of open (1) or closed (0), normalised. State order: door, bottom tray, middle tray.
"""

from __future__ import annotations

from typing import ClassVar

from bigym.envs.task import KitchenTask

TOLERANCE = 0.1
DISHWASHER = "dishwasher"


class _DishwasherTask(KitchenTask):
    scene_name = "dishwasher"
    robot_start: ClassVar[tuple[float, float, float]] = (0.0, -0.7, 0.0)
    robot_start_noise: ClassVar[tuple[float, float, float]] = (0.05, 0.05, 0.08)
    goal: ClassVar[float] = 1.0
    targets: ClassVar[tuple[str, ...]] = ("door", "tray_bottom", "tray_mid")
    # Start ranges of (door, tray_bottom, tray_mid), normalised. A closed door holds the
    # trays fully in, so trays only start ajar when the door is open.
    start: ClassVar[tuple[tuple[float, float], ...]] = ((0.0, 0.03), (0.0, 0.0), (0.0, 0.0))

    def _on_reset(self) -> None:
        low, high = zip(*self.start)
        self.props[DISHWASHER].set_state(self.data, self.np_random.uniform(low, high))

    def _success(self) -> bool:
        return self.joints_near(DISHWASHER, self.goal, TOLERANCE, self.targets)


class DishwasherOpen(_DishwasherTask):
    """Open the door, then pull out both trays."""

    time_limit = 18.0


class DishwasherClose(_DishwasherTask):
    """Push in both trays, then close the door."""

    time_limit = 18.0
    goal = 0.0
    start = ((0.9, 1.0), (0.8, 1.0), (0.8, 1.0))


class DishwasherOpenTrays(_DishwasherTask):
    """Pull out both trays of the open dishwasher."""

    time_limit = 23.0
    targets = ("tray_bottom", "tray_mid")
    start = ((0.97, 1.0), (0.0, 0.03), (0.0, 0.03))


class DishwasherCloseTrays(_DishwasherTask):
    """Push in both trays of the open dishwasher (the door may stay open)."""

    time_limit = 20.0
    goal = 0.0
    targets = ("tray_bottom", "tray_mid")
    start = ((0.97, 1.0), (0.8, 1.0), (0.8, 1.0))
