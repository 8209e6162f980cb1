"""From a device's commands to the benchmark's actions, through the experts' whole-body IK.

The controller keeps what the person asks for: a pose target for each hand's pinch point
(between the fingertips) and a stance for the base. Hand targets live in the base's
heading frame, so that when the person walks or turns the robot, the hands go along,
as a person's do. Every control step the command moves the targets; at ``ik_rate`` the
whole-body IK (:class:`bigym.experts.ik.WholeBodyIK`, the one the experts use) solves
for a configuration that puts the hands there, moving the base as well where the hands
need it, and :class:`bigym.experts.ik.IkAction` turns it into the action, exactly as an
expert's: floating base deltas, absolute arm joint targets, grippers, on the action grid.
"""

from __future__ import annotations

import numpy as np

from bigym.experts.expert import ARM_ACTIVE_COST, BASE_COST, IDLE_ARM
from bigym.experts.geometry import axis_angle_matrix, yaw_matrix
from bigym.experts.ik import IkAction, WholeBodyIK
from bigym.robot.h1 import ARM_JOINTS, FLOATING_Z_RANGE, STANDING_HEIGHT
from bigym.teleop.command import TeleopCommand

#: a hand target never leads the hand the IK commands by more than this (m): pushing on
#: against a limit or an obstacle does not wind up a target the hand then races to
MAX_LEAD = 0.08
#: IK weight of each hand's orientation (per pinch-frame axis); the 5-joint arms cannot
#: reach every orientation, so position comes first
ORIENTATION_COST = np.array([0.4, 0.4, 0.4])


class TeleopController:
    """Hand and base targets moved by commands; actions from the whole-body IK."""

    def __init__(self, env, ik_rate: float = 100.0) -> None:
        self.env = env.unwrapped
        self.ik = WholeBodyIK(self.env)
        self.to_action = IkAction(self.env, self.ik)
        self.dt = 1.0 / self.env.control_frequency
        self.ik_every = max(1, round(self.env.control_frequency / ik_rate))
        posture = np.zeros(len(self.ik.joint_names))
        for side, sign in ((0, 1.0), (1, -1.0)):
            relaxed = [IDLE_ARM[p] * (sign if p in ("shoulder_roll", "shoulder_yaw") else 1.0) for p in ARM_JOINTS]
            posture[self.ik.arm_index[side]] = np.array(relaxed) * 0.3  # elbows slightly down
        self.posture = posture
        self.arm_cost = np.where(self.ik.is_base, 0.0, ARM_ACTIVE_COST)
        self.reset()

    def reset(self) -> None:
        """Targets where the robot is now (call after the env's reset)."""
        self.ik.reset(self.env.data.qpos)
        self.base = self._base_of(self.ik.q)
        self.hand_positions, self.hand_rotations = [], []
        for side in (0, 1):
            position, rotation = self.ik.pose(side)
            local_position, local_rotation = self.to_local(position, rotation)
            self.hand_positions.append(local_position)
            self.hand_rotations.append(local_rotation)
        self.grip = np.zeros(2)
        self.steps = 0
        self._q_from = self.ik.q.copy()

    def _base_of(self, q: np.ndarray) -> np.ndarray:
        dofs = self.ik.base_dofs
        z = q[dofs["z"]] if "z" in dofs else STANDING_HEIGHT
        return np.array([q[dofs["x"]], q[dofs["y"]], z, q[dofs["rz"]]], float)

    # ------------------------------------------------------------------ frames
    def to_local(self, position: np.ndarray, rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A world pose in the base target's heading frame."""
        turn = yaw_matrix(self.base[3])
        return turn.T @ (np.asarray(position, float) - self.base[:3]), turn.T @ rotation

    def to_world(self, position: np.ndarray, rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        turn = yaw_matrix(self.base[3])
        return turn @ position + self.base[:3], turn @ rotation

    def hand_target(self, side: int) -> tuple[np.ndarray, np.ndarray]:
        """The hand's target pose in the world."""
        return self.to_world(self.hand_positions[side], self.hand_rotations[side])

    # ------------------------------------------------------------------ one step
    def apply(self, command: TeleopCommand) -> None:
        """Move the targets as ``command`` asks."""
        forward, left, up, yaw = command.base
        turn = yaw_matrix(self.base[3])
        self.base[:2] += turn[:2, :2] @ np.array([forward, left])
        low, high = FLOATING_Z_RANGE if "z" in self.ik.base_dofs else (STANDING_HEIGHT, STANDING_HEIGHT)
        self.base[2] = float(np.clip(self.base[2] + up, low, high))
        self.base[3] += yaw
        for side, hand in enumerate(command.hands):
            if hand.gripper is not None:
                self.grip[side] = float(np.clip(hand.gripper, 0.0, 1.0))
            if not (np.any(hand.translation) or np.any(hand.rotation)):
                continue
            target = self.hand_positions[side] + hand.translation
            commanded, _ = self.to_local(*self.ik.pose(side))
            lead = target - commanded
            distance = float(np.linalg.norm(lead))
            if distance > MAX_LEAD:
                target = commanded + lead * (MAX_LEAD / distance)
            self.hand_positions[side] = target
            angle = float(np.linalg.norm(hand.rotation))
            if angle > 0.0:
                spin = axis_angle_matrix(hand.rotation / angle, angle)
                self.hand_rotations[side] = spin @ self.hand_rotations[side]

    def __call__(self, command: TeleopCommand) -> np.ndarray:
        """The action of the next control step under ``command``."""
        self.apply(command)
        k = self.steps % self.ik_every
        if k == 0:
            self._q_from = self.ik.q.copy()
            goals = []
            for side in (0, 1):
                position, rotation = self.hand_target(side)
                goals.append(("pinch", position, rotation, ORIENTATION_COST, 1.0))
            base_target = dict(zip(("x", "y", "z", "rz"), (float(v) for v in self.base)))
            self.ik.solve(self.ik_every * self.dt, goals, base_target, BASE_COST, self.posture, self.arm_cost)
        q = self._q_from + (k + 1) / self.ik_every * (self.ik.q - self._q_from)
        self.steps += 1
        return self.to_action(q, self.grip)


__all__ = ["MAX_LEAD", "TeleopController"]
