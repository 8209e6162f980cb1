"""The robot inside a compiled model: ids and index arrays resolved once, cheap accessors."""

from __future__ import annotations

import mujoco
import numpy as np

from bigym.robot.h1 import (
    FLOATING_DOFS,
    LEG_SEGMENT,
    SIDES,
    STANCE,
    STANCE_HEIGHT,
    STANDING_HEIGHT,
    RobotDescription,
)

GRIPPER_DRIVER_MAX = 0.8  # driver joint range (rad) from open to closed


class Robot:
    """Accessors over a compiled model; no name look-ups after construction."""

    def __init__(self, model: mujoco.MjModel, description: RobotDescription) -> None:
        self.description = description
        self.config = description.config
        self.floating_base = self.config.floating_base
        self.actuator_ids = np.array(
            [model.actuator(e.name).id for e in description.actuators]
            + [model.actuator(name).id for name in description.gripper_actuators]
        )
        if not np.array_equal(self.actuator_ids, np.arange(len(self.actuator_ids))):
            raise RuntimeError("robot actuators must come first in the model, in action order")
        self.num_actuators = len(self.actuator_ids)
        joints = [model.joint(name) for name in description.proprio_joints]
        self.proprio_names = tuple(description.proprio_joints)
        self.proprio_qpos = np.array([j.qposadr[0] for j in joints])
        self.proprio_qvel = np.array([j.dofadr[0] for j in joints])
        self.driver_qpos = np.array(
            [[model.joint(name).qposadr[0] for name in pair] for pair in description.gripper_driver_joints]
        )
        self.wrist_site_ids = np.array([model.site(name).id for name in description.wrist_sites])
        self.pinch_site_ids = np.array([model.site(name).id for name in description.pinch_sites])
        self.pelvis_id = model.body(description.pelvis_body).id
        # Base pose addresses: floating servos, or the whole-body free joint.
        if self.floating_base:
            self.base_qpos = {dof: model.joint(f"pelvis_{dof}").qposadr[0] for dof in self.config.floating_dofs}
            self.base_ctrl = {dof: model.actuator(f"pelvis_{dof}").id for dof in self.config.floating_dofs}
            self.fixed_height = model.body_pos[self.pelvis_id, 2]
        else:
            self.root_qpos = model.joint("root").qposadr[0]
            self.stance = {
                model.joint(f"{side}_{part}").qposadr[0]: angle
                for side in SIDES
                for part, angle in STANCE.items()
            }
        self._qpos_of_actuator = np.array([model.joint(e.joint).qposadr[0] for e in description.actuators])
        self.home_qpos = self._home_qpos(model)
        # Floating mode: leg bodies re-posed for rendering when the pelvis crouches.
        self._leg_pose = None
        if self.floating_base and "z" in self.base_qpos:
            self._leg_pose = {
                part: np.array([model.body(f"{side}_{part}_link").id for side in SIDES])
                for part in ("hip_pitch", "knee", "ankle")
            }
            self._leg_quat0 = {part: model.body_quat[ids].copy() for part, ids in self._leg_pose.items()}
            self._leg_height = None
        # Colliding geoms of each gripper ("is the object still held?").
        self.gripper_geom_ids_by_side = tuple(
            np.array(
                [
                    g
                    for g in range(model.ngeom)
                    if model.body(model.geom_bodyid[g]).name.startswith(f"{side}_gripper/")
                    and (model.geom_contype[g] or model.geom_conaffinity[g])
                ]
            )
            for side in SIDES
        )
        self.gripper_geom_ids = np.concatenate(self.gripper_geom_ids_by_side)
        # qpos addresses of the grippers' linkage joints (driver, couplers, spring links, followers).
        self.gripper_qpos = np.array(
            [
                model.jnt_qposadr[j]
                for j in range(model.njnt)
                if model.body(model.jnt_bodyid[j]).name.startswith(tuple(f"{side}_gripper/" for side in SIDES))
            ],
            dtype=int,
        )
        # What an inexact demo replay compares: the robot's own joints, not the gripper linkages.
        checked = np.setdiff1d(self.proprio_qpos, self.gripper_qpos)
        if not self.floating_base:
            checked = np.concatenate([np.arange(self.root_qpos, self.root_qpos + 7), checked])
        self.replay_checked_qpos = checked
        # Bodies of the robot (for "robot left the kitchen" and contact filtering).
        root = self.pelvis_id
        self.body_ids = np.array([b for b in range(model.nbody) if _is_descendant(model, b, root)])

    def _home_qpos(self, model: mujoco.MjModel) -> np.ndarray:
        qpos = model.qpos0.copy()
        if self.floating_base:
            if "z" in self.base_qpos:
                qpos[self.base_qpos["z"]] = STANDING_HEIGHT
        else:
            qpos[self.root_qpos : self.root_qpos + 7] = [0.0, 0.0, STANCE_HEIGHT, 1.0, 0.0, 0.0, 0.0]
            for adr, angle in self.stance.items():
                qpos[adr] = angle
        return qpos

    def reset(self, model: mujoco.MjModel, data: mujoco.MjData, position: np.ndarray, yaw: float) -> None:
        """Home pose at ``position`` (x, y; z ignored) facing ``yaw``; servo targets match."""
        self._write_home(data)
        if self.floating_base:
            target = {"x": position[0], "y": position[1], "rz": yaw}
            for dof, value in target.items():
                if dof in self.base_qpos:
                    data.qpos[self.base_qpos[dof]] = value
        else:
            half = 0.5 * yaw
            data.qpos[self.root_qpos : self.root_qpos + 7] = [
                position[0], position[1], STANCE_HEIGHT, np.cos(half), 0.0, 0.0, np.sin(half)
            ]
        self.hold_current_pose(data)

    def _write_home(self, data: mujoco.MjData) -> None:
        data.qpos[self.proprio_qpos] = self.home_qpos[self.proprio_qpos]
        if not self.floating_base:
            data.qpos[self.root_qpos : self.root_qpos + 7] = self.home_qpos[self.root_qpos : self.root_qpos + 7]

    def hold_current_pose(self, data: mujoco.MjData) -> None:
        """Set every position servo's target to the joint's current position."""
        for index, entry in enumerate(self.description.actuators):
            if self.config.torque_control and entry.kind != "base":
                data.ctrl[index] = 0.0
            else:
                data.ctrl[index] = data.qpos[self._qpos_of_actuator[index]]
        data.ctrl[self.num_actuators - 2 : self.num_actuators] = 0.0

    def pose_legs(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Bend the shown (massless, welded) legs so the feet stay on the floor, for rendering.

        Only visual: the leg bodies have no mass and no colliders, so their pose never
        changes the physics. Two-link inverse kinematics in the sagittal plane.
        """
        if self._leg_pose is None:
            return
        height = data.qpos[self.base_qpos["z"]]
        if height == self._leg_height:
            return
        self._leg_height = height
        reach = np.clip((height - STANDING_HEIGHT + 2 * LEG_SEGMENT) / (2 * LEG_SEGMENT), 0.0, 1.0)
        knee = 2.0 * np.arccos(reach)
        angles = {"hip_pitch": -0.5 * knee, "knee": knee, "ankle": -0.5 * knee}
        turn = np.zeros(4)
        for part, ids in self._leg_pose.items():
            half = 0.5 * angles[part]
            rotation = np.array([np.cos(half), 0.0, np.sin(half), 0.0])  # about the joint's y axis
            for row, body in enumerate(ids):
                mujoco.mju_mulQuat(turn, self._leg_quat0[part][row], rotation)
                model.body_quat[body] = turn
        mujoco.mj_kinematics(model, data)

    def base_xy(self, data: mujoco.MjData) -> tuple[float, float]:
        """World (x, y) of the pelvis, cheaply (two scalar reads)."""
        xpos = data.xpos
        return xpos[self.pelvis_id, 0], xpos[self.pelvis_id, 1]

    def base_pose(self, data: mujoco.MjData) -> np.ndarray:
        """World (x, y, z, yaw) of the pelvis."""
        xpos = data.xpos[self.pelvis_id]
        xmat = data.xmat[self.pelvis_id]
        return np.array([xpos[0], xpos[1], xpos[2], np.arctan2(xmat[3], xmat[0])])

    def gripper_state(self, data: mujoco.MjData) -> np.ndarray:
        """Opening of each gripper in [0, 1]: 0 open, 1 closed (mean driver angle)."""
        return np.clip(data.qpos[self.driver_qpos].mean(axis=1) / GRIPPER_DRIVER_MAX, 0.0, 1.0)

    def wrist_positions(self, data: mujoco.MjData) -> np.ndarray:
        """(2, 3) world positions of the left and right wrist sites."""
        return data.site_xpos[self.wrist_site_ids]


def _is_descendant(model: mujoco.MjModel, body: int, root: int) -> bool:
    while body > 0:
        if body == root:
            return True
        body = model.body_parentid[body]
    return root == 0


__all__ = ["Robot", "FLOATING_DOFS"]
