"""Every device maps its raw events to the same commands, and refuses malformed ones."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bigym.teleop import DeviceEventError, TeleopCommand, make_devices
from bigym.teleop.devices import GamepadDevice, KeyboardDevice, SpaceMouseDevice, VRDevice
from bigym.teleop.devices.base import HAND_SPEED, HAND_TURN_SPEED
from bigym.teleop.devices.vr import XR_TO_ROBOT
from bigym.teleop.window import key_event

DT = 1.0 / 500.0
LEFT, RIGHT = 0, 1


def run(device, steps: int) -> TeleopCommand:
    """The sum of ``steps`` commands (motions add up; last gripper; all events)."""
    return TeleopCommand.combine([device.command(DT) for _ in range(steps)])


def gamepad(axes=(0, 0, 0, 0), pressed=()) -> dict:
    buttons = [0.0] * 17
    for index, value in pressed:
        buttons[index] = value
    return {"type": "gamepad", "axes": list(axes), "buttons": buttons}


def xr_controller(hand, position, yaw=0.0, squeeze=1.0, trigger=0.0, buttons=(), axes=(0, 0, 0, 0)) -> dict:
    """A controller at ``position`` (WebXR frame) turned by ``yaw`` about the vertical (y) axis."""
    values = [trigger, squeeze, 0.0, 0.0, 0.0, 0.0]
    for index in buttons:
        values[index] = 1.0
    orientation = [0.0, math.sin(yaw / 2), 0.0, math.cos(yaw / 2)]
    return {"hand": hand, "position": list(position), "orientation": orientation, "buttons": values,
            "axes": list(axes)}  # fmt: skip


# ---------------------------------------------------------------------- the same targets
def test_a_full_push_forward_moves_the_right_hand_alike_on_every_device():
    seconds, steps = 0.4, 200
    expected = np.array([HAND_SPEED * seconds, 0.0, 0.0])

    keyboard = KeyboardDevice()
    keyboard.handle({"type": "keydown", "code": "KeyW"})
    pad = GamepadDevice()
    pad.handle(gamepad(axes=(0.0, -1.0, 0.0, 0.0)))
    puck = SpaceMouseDevice()
    puck.handle({"type": "spacemouse", "axes": [0, 1, 0, 0, 0, 0], "buttons": [0, 0]})
    for device in (keyboard, pad, puck):
        command = run(device, steps)
        np.testing.assert_allclose(command.hands[RIGHT].translation, expected, atol=1e-12, err_msg=device.name)
        np.testing.assert_allclose(command.hands[LEFT].translation, 0.0, err_msg=device.name)

    vr = VRDevice()  # moves both hands with their own controllers: the right one 0.1 m ahead (-z)
    vr.handle({"type": "xr", "controllers": [xr_controller("right", [0.2, 1.0, -0.3])]})
    vr.handle({"type": "xr", "controllers": [xr_controller("right", [0.2, 1.0, -0.4])]})
    command = run(vr, steps)
    np.testing.assert_allclose(command.hands[RIGHT].translation, expected, atol=1e-12)
    np.testing.assert_allclose(command.hands[LEFT].translation, 0.0)


def test_turning_left_about_the_vertical_is_the_same_yaw_on_every_device():
    seconds, steps = 0.5, 250
    expected = np.array([0.0, 0.0, HAND_TURN_SPEED * seconds])
    keyboard = KeyboardDevice()
    keyboard.handle({"type": "keydown", "code": "KeyJ"})
    pad = GamepadDevice()
    pad.handle(gamepad(axes=(0.0, 0.0, -1.0, 0.0)))
    puck = SpaceMouseDevice()
    puck.handle({"type": "spacemouse", "axes": [0, 0, 0, 0, 0, 1], "buttons": [0, 0]})
    for device in (keyboard, pad, puck):
        np.testing.assert_allclose(run(device, steps).hands[RIGHT].rotation, expected, atol=1e-12, err_msg=device.name)
    vr = VRDevice()
    vr.handle({"type": "xr", "controllers": [xr_controller("right", [0, 1, 0], yaw=0.0)]})
    vr.handle({"type": "xr", "controllers": [xr_controller("right", [0, 1, 0], yaw=0.5)]})
    np.testing.assert_allclose(run(vr, steps).hands[RIGHT].rotation, expected, atol=1e-9)


def test_closing_the_right_gripper_and_keeping_the_demo_on_every_device():
    keyboard = KeyboardDevice()
    for code in ("Space", "Enter"):
        keyboard.handle({"type": "keydown", "code": code})
        keyboard.handle({"type": "keyup", "code": code})
    pad = GamepadDevice()
    pad.handle(gamepad(pressed=[(7, 1.0), (0, 1.0)]))  # right trigger fully, A
    vr = VRDevice()
    vr.handle(
        {"type": "xr", "controllers": [xr_controller("right", [0, 1, 0], squeeze=0.0, trigger=1.0, buttons=(4,))]}
    )
    for device in (keyboard, pad, vr):
        command = run(device, 3)
        assert command.hands[RIGHT].gripper == 1.0, device.name
        assert command.hands[LEFT].gripper is None, device.name
        assert command.events == ("keep",), device.name
    puck = SpaceMouseDevice()
    puck.handle({"type": "spacemouse", "axes": [0] * 6, "buttons": [1, 0]})
    assert run(puck, 3).hands[RIGHT].gripper == 1.0
    # a gripper command is sent once, not every step
    assert keyboard.command(DT).hands[RIGHT].gripper is None


def test_walking_forward_is_the_same_on_every_device_that_walks():
    steps = 250
    keyboard = KeyboardDevice()
    keyboard.handle({"type": "keydown", "code": "ArrowUp"})
    pad = GamepadDevice()
    pad.handle(gamepad(pressed=[(12, 1.0)]))
    vr = VRDevice()
    vr.handle({"type": "xr", "controllers": [xr_controller("left", [0, 1, 0], squeeze=0.0, axes=(0, 0, 0, -1.0))]})
    results = [run(device, steps).base for device in (keyboard, pad, vr)]
    assert results[0][0] > 0.1
    for result in results[1:]:
        np.testing.assert_allclose(result, results[0], atol=1e-12)


# ---------------------------------------------------------------------- device details
def test_a_key_held_for_a_while_moves_for_exactly_that_long():
    keyboard = KeyboardDevice()
    keyboard.handle({"type": "keydown", "code": "KeyR", "hold": 0.1})  # what the window sends
    moved = run(keyboard, 500).hands[RIGHT].translation
    np.testing.assert_allclose(moved, [0.0, 0.0, HAND_SPEED * 0.1], atol=1e-12)


def test_shift_slows_the_keyboard_and_tab_switches_hands():
    keyboard = KeyboardDevice()
    keyboard.handle({"type": "keydown", "code": "Tab"})
    keyboard.handle({"type": "keyup", "code": "Tab"})
    keyboard.handle({"type": "keydown", "code": "ShiftLeft"})
    keyboard.handle({"type": "keydown", "code": "KeyA"})
    command = run(keyboard, 100)
    np.testing.assert_allclose(command.hands[LEFT].translation, [0.0, 0.3 * HAND_SPEED * 0.2, 0.0], atol=1e-12)
    np.testing.assert_allclose(command.hands[RIGHT].translation, 0.0)


def test_the_gamepad_dead_zone_ignores_a_resting_stick():
    pad = GamepadDevice()
    pad.handle(gamepad(axes=(0.08, -0.1, 0.05, 0.11)))
    command = run(pad, 100)
    assert not command.hands[RIGHT].translation.any() and not command.hands[RIGHT].rotation.any()


def test_the_vr_hand_moves_only_while_its_grip_is_held():
    vr = VRDevice()
    vr.handle({"type": "xr", "controllers": [xr_controller("left", [0, 1, 0], squeeze=0.0)]})
    vr.handle({"type": "xr", "controllers": [xr_controller("left", [0.3, 1, 0], squeeze=0.0)]})
    assert not run(vr, 2).hands[LEFT].translation.any()
    vr.handle({"type": "xr", "controllers": [xr_controller("left", [0.3, 1, 0])]})  # grip: clutch in
    vr.handle({"type": "xr", "controllers": [xr_controller("left", [0.3, 1.2, 0])]})  # up 0.2 m
    np.testing.assert_allclose(run(vr, 2).hands[LEFT].translation, [0.0, 0.0, 0.2], atol=1e-12)


def test_the_xr_frame_maps_onto_the_robot_heading_frame():
    # WebXR: x right, y up, z towards the person; the robot: x forward, y left, z up
    np.testing.assert_allclose(XR_TO_ROBOT @ [0, 0, -1], [1, 0, 0])
    np.testing.assert_allclose(XR_TO_ROBOT @ [-1, 0, 0], [0, 1, 0])
    np.testing.assert_allclose(XR_TO_ROBOT @ [0, 1, 0], [0, 0, 1])
    assert np.isclose(np.linalg.det(XR_TO_ROBOT), 1.0)


def test_window_keys_become_keyboard_events():
    assert key_event(ord("W")) == {"type": "keydown", "code": "KeyW", "hold": 0.2}
    assert key_event(265)["code"] == "ArrowUp"
    assert key_event(ord("2"))["code"] == "Digit2"
    assert key_event(999) is None


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "device, event, words",
    [
        (KeyboardDevice(), {"type": "gamepad", "axes": [0] * 4}, "reads keydown"),
        (KeyboardDevice(), {"type": "keydown"}, "'code'"),
        (KeyboardDevice(), {"type": "keydown", "code": "KeyW", "hold": "long"}, "'hold' must be a number"),
        (GamepadDevice(), {"type": "gamepad", "axes": [0, float("nan"), 0, 0], "buttons": [0] * 17}, "finite"),
        (GamepadDevice(), {"type": "gamepad", "axes": [0, 0], "buttons": [0] * 17}, "at least 4"),
        (SpaceMouseDevice(), {"type": "spacemouse", "axes": [0, 0, 0], "buttons": [0, 0]}, "6 finite"),
        (VRDevice(), {"type": "xr", "controllers": {"hand": "left"}}, "must be a list"),
        (VRDevice(), {"type": "xr", "controllers": [{"hand": "middle"}]}, "'left' or 'right'"),
        (VRDevice(), {"type": "xr", "controllers": [xr_controller("left", [0, 1])]}, "3 finite"),
    ],
)
def test_malformed_events_are_refused_clearly(device, event, words):
    with pytest.raises(DeviceEventError, match=words):
        device.handle(event)


def test_devices_by_name():
    assert [d.name for d in make_devices("keyboard, vr")] == ["keyboard", "vr"]
    with pytest.raises(ValueError, match="unknown device.*joystick.*keyboard"):
        make_devices("joystick")
    with pytest.raises(ValueError, match="named twice"):
        make_devices("keyboard,keyboard")
    with pytest.raises(ValueError, match="at least one"):
        make_devices("")
