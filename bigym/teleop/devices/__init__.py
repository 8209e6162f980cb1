"""Input devices for teleoperation: each a small class behind :class:`Device`.

Adding a device means one new module here and one line in :data:`DEVICES`.
"""

from __future__ import annotations

from bigym.teleop.devices.base import Device, DeviceEventError
from bigym.teleop.devices.gamepad import GamepadDevice
from bigym.teleop.devices.keyboard import KeyboardDevice
from bigym.teleop.devices.spacemouse import SpaceMouseDevice
from bigym.teleop.devices.vr import VRDevice

#: device name (``--device``) -> class
DEVICES: dict[str, type[Device]] = {
    cls.name: cls for cls in (KeyboardDevice, GamepadDevice, SpaceMouseDevice, VRDevice)
}


def make_devices(names: str | list[str]) -> list[Device]:
    """Devices by name (``"keyboard,gamepad"`` or a list); a clear error for unknown ones."""
    if isinstance(names, str):
        names = [n.strip() for n in names.split(",") if n.strip()]
    if not names:
        raise ValueError(f"name at least one device: {', '.join(DEVICES)}")
    unknown = [n for n in names if n not in DEVICES]
    if unknown:
        raise ValueError(f"unknown device(s) {', '.join(unknown)}; bigym knows {', '.join(DEVICES)}")
    if len(set(names)) != len(names):
        raise ValueError(f"a device is named twice: {', '.join(names)}")
    return [DEVICES[n]() for n in names]


__all__ = [
    "DEVICES",
    "Device",
    "DeviceEventError",
    "GamepadDevice",
    "KeyboardDevice",
    "SpaceMouseDevice",
    "VRDevice",
    "make_devices",
]
