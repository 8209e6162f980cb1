"""A scripted person for the teleoperation tests: looks at the target and presses keys."""

from __future__ import annotations

import numpy as np

from bigym.experts.geometry import yaw_matrix

#: per heading-frame axis: the key that moves the hand along it, and the one that moves it back
AXIS_KEYS = [("KeyW", "KeyS"), ("KeyA", "KeyD"), ("KeyR", "KeyF")]


def wrist_error(session, side: int, target: np.ndarray) -> np.ndarray:
    """Target minus wrist, in the robot's heading frame."""
    env = session.env
    wrist = env.data.site_xpos[env.model.site(env.robot.description.wrist_sites[side]).id]
    return yaw_matrix(session.controller.base[3]).T @ (np.asarray(target) - wrist)


def keys_towards(error: np.ndarray, slack: float = 0.02) -> set[str]:
    """The movement keys a person holds to close ``error``."""
    keys = set()
    for axis, (plus, minus) in enumerate(AXIS_KEYS):
        if abs(error[axis]) > slack:
            keys.add(plus if error[axis] > 0 else minus)
    return keys


def reach_with_keyboard(session, side: int = 0, look_every: int = 50, limit: int = 4000):
    """Press keys until the episode ends (the session keeps it 1 s after success); the
    outcome, or None at ``limit`` steps."""
    session.handle({"type": "keydown", "code": ("Digit1", "Digit2")[side]})
    session.handle({"type": "keyup", "code": ("Digit1", "Digit2")[side]})
    held: set[str] = set()
    ended = len(session.outcomes)
    for _ in range(limit // look_every):
        want = keys_towards(wrist_error(session, side, session.env.target_positions[0]))
        for code in sorted(held - want):
            session.handle({"type": "keyup", "code": code})
        for code in sorted(want - held):
            session.handle({"type": "keydown", "code": code})
        held = want
        session.advance(look_every)
        if len(session.outcomes) > ended:
            for code in sorted(held):
                session.handle({"type": "keyup", "code": code})
            return session.outcomes[ended]
    return None
