"""Small rotation and articulation helpers (numpy only)."""

from __future__ import annotations

import mujoco
import numpy as np


def axis_angle_matrix(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix of ``angle`` radians about the unit ``axis``."""
    axis = np.asarray(axis, float)
    axis = axis / np.linalg.norm(axis)
    x, y, z = axis
    c, s = np.cos(angle), np.sin(angle)
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + s * k + (1.0 - c) * (k @ k)


def rotation_log(rotation: np.ndarray) -> np.ndarray:
    """Rotation vector (axis times angle) of a rotation matrix."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(rotation, float).reshape(9))
    if quat[0] < 0.0:
        quat = -quat
    sin_half = np.linalg.norm(quat[1:])
    if sin_half < 1e-12:
        return np.zeros(3)
    angle = 2.0 * np.arctan2(sin_half, quat[0])
    return quat[1:] / sin_half * angle


def interpolate_rotation(r0: np.ndarray, r1: np.ndarray, s: float) -> np.ndarray:
    """Geodesic interpolation from ``r0`` (s = 0) to ``r1`` (s = 1)."""
    delta = rotation_log(r0.T @ r1)
    angle = float(np.linalg.norm(delta))
    if angle < 1e-12:
        return r1.copy() if s >= 1.0 else r0.copy()
    return r0 @ axis_angle_matrix(delta / angle, angle * s)


def frame_from_axes(x_axis: np.ndarray, z_axis: np.ndarray) -> np.ndarray:
    """Right-handed rotation whose z column is ``z_axis`` and whose x column is ``x_axis``
    made orthogonal to it."""
    z = np.asarray(z_axis, float)
    z = z / np.linalg.norm(z)
    x = np.asarray(x_axis, float) - z * (np.asarray(x_axis, float) @ z)
    x = x / np.linalg.norm(x)
    y = np.cross(z, x)
    return np.column_stack([x, y, z])


def aligning_rotation(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation taking unit vector ``a`` to unit vector ``b``."""
    axis = np.cross(a, b)
    sine = float(np.linalg.norm(axis))
    if sine < 1e-9:
        return np.eye(3)
    return axis_angle_matrix(axis / sine, float(np.arctan2(sine, a @ b)))


def yaw_matrix(yaw: float) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def clamp(vector: np.ndarray, most: float) -> np.ndarray:
    """``vector`` shortened to at most ``most`` long (a correction that must stay bounded)."""
    length = float(np.linalg.norm(vector))
    return vector if length <= most else vector * (most / length)


class JointMotion:
    """Where a body attached to one slide or hinge joint goes as that joint moves.

    Built from the current (measured) state: the joint's world axis and anchor, its
    position, and any point/frame rigidly attached to its body; :meth:`transform`
    then gives the rigid motion for another joint position.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, joint_id: int) -> None:
        self.joint_id = joint_id
        self.hinge = model.jnt_type[joint_id] == mujoco.mjtJoint.mjJNT_HINGE
        if not self.hinge and model.jnt_type[joint_id] != mujoco.mjtJoint.mjJNT_SLIDE:
            raise ValueError("only hinge and slide joints are supported")
        self.axis = data.xaxis[joint_id].copy()
        self.anchor = data.xanchor[joint_id].copy()
        self.q0 = float(data.qpos[model.jnt_qposadr[joint_id]])
        self.low, self.high = model.jnt_range[joint_id]

    def value(self, normalised: float) -> float:
        return float(self.low + normalised * (self.high - self.low))

    def normalised(self, value: float) -> float:
        return float((value - self.low) / (self.high - self.low))

    def transform(self, q: float) -> tuple[np.ndarray, np.ndarray]:
        """``(R, p)`` such that a point ``x`` attached to the body maps to ``R x + p``."""
        if self.hinge:
            rotation = axis_angle_matrix(self.axis, q - self.q0)
            return rotation, self.anchor - rotation @ self.anchor
        return np.eye(3), self.axis * (q - self.q0)

    def move_point(self, point: np.ndarray, q: float) -> np.ndarray:
        rotation, offset = self.transform(q)
        return rotation @ point + offset

    def move_frame(self, point: np.ndarray, frame: np.ndarray, q: float) -> tuple[np.ndarray, np.ndarray]:
        rotation, offset = self.transform(q)
        return rotation @ point + offset, rotation @ frame


__all__ = [
    "JointMotion",
    "axis_angle_matrix",
    "clamp",
    "frame_from_axes",
    "interpolate_rotation",
    "rotation_log",
    "yaw_matrix",
]
