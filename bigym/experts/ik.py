"""Whole-body differential inverse kinematics with mink: floating base and both arms.

The IK works on its own copy of the robot's kinematics (the robot alone, without the
kitchen and without the grippers' equality constraints, which do not move the pinch
sites), integrates a *commanded* configuration, and hands the base and arm joint
targets to the action. Tasks, in decreasing weight:

* a :class:`mink.FrameTask` on each hand's pinch site: position, and orientation where
  a grasp needs it (per-axis costs in the pinch frame, so that e.g. only the axis that
  must lie along a handle bar is constrained);
* a :class:`mink.PostureTask`: the base towards its planned stance (x, y, height, yaw)
  and the arms towards a relaxed posture, weak enough that the hands win;

with joint-range and velocity limits, the arms kept off the torso and each other, and,
where an expert sets them, half-planes the pelvis and the arms keep to (out of the
furniture, out of an open door). Base and arms are one problem, so the base moves
exactly as much as the hands need beyond what the plan already gives them.
"""

from __future__ import annotations

import functools

import mink
import mujoco
import numpy as np

from bigym.robot.h1 import ARM_JOINTS, SIDES, RobotConfig, build_robot

SOLVER = "daqp"
#: actions are rounded to multiples of 1 / ACTION_GRID_STEPS (~8 micro-rad / micro-m)
ACTION_GRID_STEPS = 2.0**17
#: velocity caps (rad/s or m/s) of the commanded motion: brisk but human
ARM_SPEED = 3.0
WRIST_SPEED = 4.0
BASE_SPEED = {"x": 0.8, "y": 0.8, "z": 0.6, "rz": 1.2}


class BaseRegionLimit(mink.Limit):
    """Keeps the pelvis (x, y) inside half-planes ``a . (x, y) <= b``: out of the furniture."""

    def __init__(self, model: mujoco.MjModel) -> None:
        self.x_dof = model.joint("pelvis_x").dofadr[0]
        self.y_dof = model.joint("pelvis_y").dofadr[0]
        self.x_qpos = model.joint("pelvis_x").qposadr[0]
        self.y_qpos = model.joint("pelvis_y").qposadr[0]
        self.nv = model.nv
        self.planes: list[tuple[np.ndarray, float]] = []

    def compute_qp_inequalities(self, configuration: mink.Configuration, dt: float) -> mink.limits.limit.Constraint:
        from mink.limits.limit import Constraint

        if not self.planes:
            return Constraint()
        q = configuration.q
        xy = np.array([q[self.x_qpos], q[self.y_qpos]])
        g = np.zeros((len(self.planes), self.nv))
        h = np.zeros(len(self.planes))
        for row, (a, b) in enumerate(self.planes):
            g[row, self.x_dof], g[row, self.y_dof] = a
            # never demand a jump back in: at worst, stop moving outwards
            h[row] = max(b - float(a @ xy), 0.0)
        return Constraint(g, h)


#: points (link, local position, radius) along each arm that :class:`ArmPlaneLimit`
#: keeps out of obstacles: the elbow, the middle of the forearm and the wrist
ARM_POINTS = (
    ("shoulder_yaw_link", (0.0, 0.0, -0.2), 0.03),
    ("elbow_link", (0.14, 0.0, -0.0075), 0.025),
    ("elbow_link", (0.28, 0.0, -0.015), 0.033),
)


class ArmPlaneLimit(mink.Limit):
    """Keeps an arm's elbow, forearm and wrist inside half-planes ``a . p <= b`` (3-D):
    the IK knows no scene, and an arm left to it can swing its elbow out into an open
    door beside the body, which then holds the arm while the hand is carried on."""

    def __init__(self, model: mujoco.MjModel, gain: float = 0.5) -> None:
        self.model = model
        self.gain = gain
        self.points = [
            [(model.body(f"{side}_{link}").id, np.array(local, float), radius) for link, local, radius in ARM_POINTS]
            for side in SIDES
        ]
        self.planes: list[tuple[int, np.ndarray, float]] = []  # (side, a, b)
        self._jac = np.zeros((3, model.nv))

    def compute_qp_inequalities(self, configuration: mink.Configuration, dt: float) -> mink.limits.limit.Constraint:
        from mink.limits.limit import Constraint

        if not self.planes:
            return Constraint()
        data = configuration.data
        rows, bounds = [], []
        for side, a, b in self.planes:
            for body, local, radius in self.points[side]:
                point = data.xpos[body] + data.xmat[body].reshape(3, 3) @ local
                mujoco.mj_jac(self.model, data, self._jac, None, point, body)
                rows.append(a @ self._jac)
                # never demand a jump back out: at worst, stop moving further in
                bounds.append(self.gain * max(b - radius - float(a @ point), 0.0))
        return Constraint(np.array(rows), np.array(bounds))


#: the gripper bodies :func:`self_collision_pairs` keeps off the torso on request: its
#: body and the linkage at its root, which reach furthest back towards the chest
GRIPPER_ROOT_BODIES = ("base_mount", "base", "left_driver", "right_driver", "left_coupler", "right_coupler")


def self_collision_pairs(model: mujoco.MjModel, grippers: bool = False) -> list[tuple[list[int], list[int]]]:
    """Geom groups the IK keeps apart: each arm (upper arm, forearm) from the torso, and
    the two arms from each other; with ``grippers`` also each gripper's root
    (:data:`GRIPPER_ROOT_BODIES`) from the torso."""

    def colliders(*bodies: str) -> list[int]:
        ids = {model.body(b).id for b in bodies}
        return [
            g
            for g in range(model.ngeom)
            if model.geom_bodyid[g] in ids and (model.geom_contype[g] or model.geom_conaffinity[g])
        ]

    torso = colliders("torso_link")
    arms = [colliders(f"{side}_shoulder_yaw_link", f"{side}_elbow_link") for side in SIDES]
    pairs = [(arms[0], torso), (arms[1], torso), (arms[0], arms[1])]
    if grippers:
        pairs += [(colliders(*(f"{side}_gripper/{b}" for b in GRIPPER_ROOT_BODIES)), torso) for side in SIDES]
    return pairs


@functools.lru_cache(maxsize=4)
def ik_model(config: RobotConfig) -> mujoco.MjModel:
    """The robot alone, compiled for kinematics (cached per configuration)."""
    spec, _ = build_robot(config)
    for equality in list(spec.equalities):
        spec.delete(equality)
    return spec.compile()


def _rotation_to_quat(rotation: np.ndarray) -> np.ndarray:
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(rotation, float).reshape(9))
    return quat


class WholeBodyIK:
    """Commanded base + arm configuration driven by hand targets and a base plan."""

    def __init__(
        self, env, hand_position_cost: float = 10.0, damping: float = 1e-5, grippers_off_torso: bool = False
    ) -> None:
        robot = env.robot
        if not robot.floating_base:
            raise ValueError("the experts drive the floating base; use JointPositionActionMode(floating_base=True)")
        self.model = ik_model(robot.config)
        model = self.model
        entries = [a for a in robot.description.actuators if a.kind in ("base", "arm")]
        self.joint_names = [a.joint for a in entries]
        self.is_base = np.array([a.kind == "base" for a in entries])
        self.env_qpos = np.array([env.model.joint(n).qposadr[0] for n in self.joint_names])
        self.qpos = np.array([model.joint(n).qposadr[0] for n in self.joint_names])
        self.dofs = np.array([model.joint(n).dofadr[0] for n in self.joint_names])
        self.base_dofs = {a.joint.removeprefix("pelvis_"): i for i, a in enumerate(entries) if a.kind == "base"}
        # arm joint indices (into the IK joint order) of each side, 0 = left, 1 = right
        self.arm_index = [np.array([self.joint_names.index(f"{side}_{part}") for part in ARM_JOINTS]) for side in SIDES]
        self.lower = np.array(
            [
                model.jnt_range[model.joint(n).id, 0] if model.jnt_limited[model.joint(n).id] else -np.inf
                for n in self.joint_names
            ]
        )
        self.upper = np.array(
            [
                model.jnt_range[model.joint(n).id, 1] if model.jnt_limited[model.joint(n).id] else np.inf
                for n in self.joint_names
            ]
        )
        self.damping = damping
        self.hand_position_cost = hand_position_cost

        self.configuration = mink.Configuration(model)
        # The controlled point of each hand: the pinch site between the fingertips, or
        # the wrist site (the reach tasks measure the wrist).
        self.sites = {
            "pinch": [model.site(name).id for name in robot.description.pinch_sites],
            "wrist": [model.site(name).id for name in robot.description.wrist_sites],
        }
        self.hand_tasks = {
            frame: [
                mink.FrameTask(site, "site", position_cost=hand_position_cost, orientation_cost=0.0) for site in sites
            ]
            for frame, sites in self.sites.items()
        }
        self.posture = mink.PostureTask(model, cost=0.0)
        self._posture_cost = np.zeros(model.nv)
        self._posture_target = model.qpos0.copy()
        velocities = {}
        for name, is_base in zip(self.joint_names, self.is_base):
            if is_base:
                velocities[name] = BASE_SPEED[name.removeprefix("pelvis_")]
            else:
                velocities[name] = WRIST_SPEED if name.endswith("wrist") else ARM_SPEED
        self.base_region = BaseRegionLimit(model)
        self.arm_planes = ArmPlaneLimit(model)
        self.limits = [
            mink.ConfigurationLimit(model, gain=0.5),
            mink.VelocityLimit(model, velocities),
            self.base_region,
            self.arm_planes,
            mink.CollisionAvoidanceLimit(
                model,
                self_collision_pairs(model, grippers=grippers_off_torso),
                minimum_distance_from_collisions=0.02,
                collision_detection_distance=0.08,
            ),
        ]
        self.q = np.zeros(len(self.joint_names))
        self.velocity = np.zeros(len(self.joint_names))

    # ------------------------------------------------------------------ state
    def reset(self, env_qpos: np.ndarray) -> None:
        """Start commanding from the env's current configuration."""
        self.q = np.asarray(env_qpos[self.env_qpos], float).copy()
        self.velocity[:] = 0.0
        self._full = self.model.qpos0.copy()
        self._full[self.qpos] = self.q
        self.configuration.update(self._full)

    def pose(self, side: int, frame: str = "pinch") -> tuple[np.ndarray, np.ndarray]:
        """World position and rotation matrix of a hand frame at the commanded configuration."""
        data = self.configuration.data
        site = self.sites[frame][side]
        return data.site_xpos[site].copy(), data.site_xmat[site].reshape(3, 3).copy()

    def pose_at(self, q: np.ndarray, side: int, frame: str = "pinch") -> tuple[np.ndarray, np.ndarray]:
        """Hand frame pose for another configuration ``q`` (IK joint order), without
        touching the commanded one."""
        if not hasattr(self, "_scratch"):
            self._scratch = mujoco.MjData(self.model)
        scratch = self._scratch
        scratch.qpos[:] = self._full
        scratch.qpos[self.qpos] = q
        mujoco.mj_kinematics(self.model, scratch)
        site = self.sites[frame][side]
        return scratch.site_xpos[site].copy(), scratch.site_xmat[site].reshape(3, 3).copy()

    def base(self) -> dict[str, float]:
        return {dof: float(self.q[i]) for dof, i in self.base_dofs.items()}

    # ------------------------------------------------------------------ solving
    def solve(
        self,
        dt: float,
        hands: list[tuple[str, np.ndarray, np.ndarray, np.ndarray | float, float] | None],
        base_target: dict[str, float],
        base_cost: dict[str, float],
        arm_posture: np.ndarray,
        arm_cost: np.ndarray,
    ) -> np.ndarray:
        """One IK step of ``dt`` seconds; returns the new commanded configuration.

        ``hands[side]`` is ``(frame, position, rotation, orientation_cost, position_scale)`` or
        ``None`` (that hand only follows the posture). ``arm_posture``/``arm_cost`` are
        per joint in the IK's joint order (base entries ignored).
        """
        model = self.model
        tasks: list = []
        for side, goal in enumerate(hands):
            if goal is None:
                continue
            frame, position, rotation, orientation_cost, scale = goal
            task = self.hand_tasks[frame][side]
            task.set_position_cost(self.hand_position_cost * scale)
            task.set_orientation_cost(orientation_cost)
            wxyz = _rotation_to_quat(rotation)
            task.set_target(mink.SE3(np.concatenate([wxyz, position])))
            tasks.append(task)
        cost = self._posture_cost
        target = self._posture_target
        cost[:] = 0.0
        for i, name in enumerate(self.joint_names):
            dof = self.dofs[i]
            if self.is_base[i]:
                key = name.removeprefix("pelvis_")
                cost[dof] = base_cost.get(key, 0.0)
                target[self.qpos[i]] = base_target.get(key, self.q[i])
            else:
                cost[dof] = arm_cost[i]
                target[self.qpos[i]] = arm_posture[i]
        self.posture.set_cost(cost)
        self.posture.set_target(target)
        tasks.append(self.posture)
        try:
            velocity = mink.solve_ik(self.configuration, tasks, dt, SOLVER, damping=self.damping, limits=self.limits)
        except mink.NoSolutionFound:
            velocity = np.zeros(model.nv)
        self.velocity = velocity[self.dofs]
        self.q = np.clip(self.q + self.velocity * dt, self.lower, self.upper)
        self._full[self.qpos] = self.q
        self.configuration.update(self._full)
        return self.q


class IkAction:
    """The benchmark's action (floating base, absolute joint positions) for a commanded
    configuration of :class:`WholeBodyIK` and two gripper commands: absolute arm joint
    targets, base *deltas* of the env's base servo targets, and the grippers, on the action
    grid (multiples of ``1 / ACTION_GRID_STEPS``: last-bit differences of the IK's linear
    algebra between CPUs vanish, and the actions pack compactly), within the action space."""

    def __init__(self, env, ik: WholeBodyIK) -> None:
        env = env.unwrapped
        if not getattr(env.action_mode, "absolute", False) or env.action_mode.torque:
            raise ValueError("the IK drives JointPositionActionMode(floating_base=True, absolute=True) actions")
        self.data = env.data
        layout = env.action_layout
        names = [e.name for e in layout.entries]
        self.size = len(layout)
        self.grip_index = np.array([names.index("left_gripper"), names.index("right_gripper")])
        # the base and arm entries lead the action layout, in the IK's joint order
        self.joint_action = np.arange(len(ik.joint_names))
        leading = [e.group for e in layout.entries[: len(ik.joint_names)]]
        if any(group not in ("base", "left_arm", "right_arm") for group in leading):
            raise ValueError("unexpected action layout: base and arm entries must lead")
        self.base_mask = ik.is_base
        self.low = env.action_space.low.astype(np.float64)
        self.high = env.action_space.high.astype(np.float64)

    def __call__(self, q: np.ndarray, grip: np.ndarray) -> np.ndarray:
        action = np.zeros(self.size)
        action[self.joint_action] = np.where(self.base_mask, q - self.data.ctrl[self.joint_action], q)
        action[self.grip_index] = grip
        np.round(action * ACTION_GRID_STEPS, out=action)
        action /= ACTION_GRID_STEPS
        return np.clip(action, self.low, self.high)


__all__ = ["ACTION_GRID_STEPS", "IkAction", "WholeBodyIK", "ik_model"]
