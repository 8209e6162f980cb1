"""Teleoperation: people drive the robot from an input device and record demos.

Devices (:mod:`bigym.teleop.devices`) turn raw input events into commands; the
:class:`TeleopController` turns commands into the benchmark's actions through the
experts' whole-body IK; a :class:`TeleopSession` records, verifies and stores the demos;
front ends (a MuJoCo window, a browser page, a script) feed it events and show it.
"""

from bigym.teleop.command import HandCommand, TeleopCommand
from bigym.teleop.controller import TeleopController
from bigym.teleop.devices import DEVICES, Device, DeviceEventError, make_devices
from bigym.teleop.script import InputScript, play
from bigym.teleop.session import Outcome, TeleopSession

__all__ = [
    "DEVICES",
    "Device",
    "DeviceEventError",
    "HandCommand",
    "InputScript",
    "Outcome",
    "TeleopCommand",
    "TeleopController",
    "TeleopSession",
    "make_devices",
    "play",
]
