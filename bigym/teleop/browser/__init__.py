"""The browser front end of teleoperation (see :mod:`bigym.teleop.browser.server`)."""

from bigym.teleop.browser.server import TeleopServer

__all__ = ["TeleopServer"]
