"""Unitree H1 with a wrist hinge and a Robotiq 2F-85 on each arm, built with MjSpec.

Two configurations:

* floating base (bi-manual): the pelvis rides on position servos along world
  x, y, z and yaw; legs and torso are welded, massless and shown only;
* whole body: the menagerie free pelvis, with legs, torso and arms actuated.

The builder only edits the specification. :class:`bigym.robot.robot.Robot`
resolves ids and index arrays once the model is compiled.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np

from bigym.robot.meshes import RENDER_FACE_FRACTION, load_mesh

SIDES = ("left", "right")
ARM_JOINTS = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist")
LEG_JOINTS = ("hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle")
FLOATING_DOFS = ("x", "y", "z", "rz")
CAMERAS = ("head", "left_wrist", "right_wrist")

# Pelvis height with straight legs and flat feet (menagerie geometry: foot capsules touch z = 0).
STANDING_HEIGHT = 1.0442
LEG_SEGMENT = 0.4  # thigh and shank length (m)
# Whole-body stance: a slight knee bend puts the centre of mass over the mid-foot (DESIGN.md).
STANCE = {"hip_pitch": 0.0, "knee": 0.2, "ankle": -0.2}
STANCE_HEIGHT = 1.0362
# Floating-base pelvis height range (m); lower than the stance so the robot can crouch to low
# shelves and, at 0.4 m (the original's limit), take a box off the floor with both hands.
FLOATING_Z_RANGE = (0.4, STANDING_HEIGHT)

GRIPPER_MENAGERIE_CTRL_MAX = 255.0
PAD_TORSIONAL_FRICTION = 0.01  # m: contact patch radius x sliding friction (see _give_pads_torsional_friction)
WRIST_POINT_RADIUS = 0.001
WRIST_RANGE = (-np.pi / 2, np.pi / 2)
# Motor torque limits (Nm) of the real H1 joints, used as torque bounds and servo force limits.
TORQUE_LIMITS = {
    "hip_yaw": 200.0,
    "hip_roll": 200.0,
    "hip_pitch": 200.0,
    "knee": 300.0,
    "ankle": 40.0,
    "torso": 200.0,
    "shoulder_pitch": 40.0,
    "shoulder_roll": 40.0,
    "shoulder_yaw": 18.0,
    "elbow": 18.0,
    "wrist": 18.0,
}
ARM_KP = 300.0
LEG_KP, LEG_KV = 1000.0, 30.0
BASE_KP = {"x": 1.0e5, "y": 1.0e5, "z": 1.0e5, "rz": 1.0e4}


@dataclass(frozen=True)
class RobotConfig:
    """What to build: base type, which base DOFs are driven, and actuator type."""

    floating_base: bool = True
    floating_dofs: tuple[str, ...] = FLOATING_DOFS
    torque_control: bool = False

    def __post_init__(self) -> None:
        unknown = [d for d in self.floating_dofs if d not in FLOATING_DOFS]
        if unknown:
            raise ValueError(f"unknown floating DOFs {unknown}; choose from {FLOATING_DOFS}")
        if len(set(self.floating_dofs)) != len(self.floating_dofs):
            raise ValueError(f"floating DOFs repeat: {self.floating_dofs}")
        # Keep the canonical order x, y, z, rz whatever order was given.
        object.__setattr__(
            self, "floating_dofs", tuple(d for d in FLOATING_DOFS if d in self.floating_dofs)
        )


@dataclass
class ActuatorEntry:
    """One action element: its actuator, the joint it drives and its bounds."""

    name: str
    joint: str
    kind: str  # "base", "leg", "torso", "arm", "gripper"
    joint_range: tuple[float, float]
    torque_limit: float = 0.0


@dataclass
class RobotDescription:
    """Names the compiled model will hold, in action and proprioception order."""

    config: RobotConfig
    actuators: list[ActuatorEntry] = field(default_factory=list)
    proprio_joints: list[str] = field(default_factory=list)
    gripper_actuators: tuple[str, str] = ("left_gripper/fingers_actuator", "right_gripper/fingers_actuator")
    gripper_driver_joints: tuple[tuple[str, str], ...] = (
        ("left_gripper/left_driver_joint", "left_gripper/right_driver_joint"),
        ("right_gripper/left_driver_joint", "right_gripper/right_driver_joint"),
    )
    wrist_sites: tuple[str, str] = ("left_wrist_site", "right_wrist_site")
    wrist_points: tuple[str, str] = ("left_wrist_point", "right_wrist_point")
    pinch_sites: tuple[str, str] = ("left_gripper/pinch", "right_gripper/pinch")
    pelvis_body: str = "pelvis"
    leg_bodies: tuple[str, ...] = ()


def _menagerie_spec(robot: str, entry: str) -> mujoco.MjSpec:
    import mujoco_menagerie

    if "MENAGERIE_ROOT" not in os.environ:
        shared = Path(__file__).resolve().parents[3] / "shared" / "menagerie"
        if shared.is_dir():  # a development checkout beside ../shared: no download needed
            os.environ["MENAGERIE_ROOT"] = str(shared)
    return mujoco_menagerie.get(robot).spec(entry)


def _euler_quat(euler: tuple[float, float, float]) -> np.ndarray:
    quat = np.zeros(4)
    mujoco.mju_euler2Quat(quat, np.asarray(euler, float), "xyz")
    return quat


def _use_cached_meshes(spec: mujoco.MjSpec) -> None:
    """Swap file meshes for cached arrays: low-poly for visual geoms, full for colliders."""
    mesh_dir = Path(spec.modelfiledir) / spec.meshdir
    collision_users: set[str] = set()
    visual_geoms: dict[str, list[mujoco.MjsGeom]] = {}
    for geom in spec.geoms:
        if geom.type != mujoco.mjtGeom.mjGEOM_MESH:
            continue
        if geom.contype == 0 and geom.conaffinity == 0:
            visual_geoms.setdefault(geom.meshname, []).append(geom)
        else:
            collision_users.add(geom.meshname)
    for mesh in list(spec.meshes):
        source = mesh_dir / mesh.file
        scale = np.array(mesh.scale)
        name = mesh.name
        if name in collision_users:
            full = load_mesh(source, scale, 1.0)
            _set_mesh_data(mesh, full.vertices, full.faces)
            if name in visual_geoms:
                low = load_mesh(source, scale, RENDER_FACE_FRACTION)
                low_mesh = spec.add_mesh(name=f"{name}_lowpoly")
                _set_mesh_data(low_mesh, low.vertices, low.faces)
                for geom in visual_geoms[name]:
                    geom.meshname = low_mesh.name
        else:
            low = load_mesh(source, scale, RENDER_FACE_FRACTION)
            _set_mesh_data(mesh, low.vertices, low.faces)


def _set_mesh_data(mesh: mujoco.MjsMesh, vertices: np.ndarray, faces: np.ndarray) -> None:
    mesh.file = ""
    mesh.scale = [1.0, 1.0, 1.0]
    mesh.uservert = vertices.ravel().astype(float)
    mesh.userface = faces.ravel().astype(np.int32)


def _set_physics_options(spec: mujoco.MjSpec) -> None:
    # Every spec gets the same contact options: attaching keeps the parent's, and
    # matching them avoids MuJoCo's conflict warnings.
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.impratio = 10.0


def _gripper_spec() -> mujoco.MjSpec:
    spec = _menagerie_spec("robotiq_2f85", "2f85")
    _use_cached_meshes(spec)
    _set_physics_options(spec)
    _give_pads_torsional_friction(spec)
    return spec


def _give_pads_torsional_friction(spec: mujoco.MjSpec) -> None:
    """Let the finger pads resist twisting about the closing axis, as real silicone pads do.

    The menagerie pads are condim 3 (sliding friction only): an object held off its centre
    of mass (a mug by its handle, a pan by its long handle) pivots about the closing axis,
    5-10 degrees in 2 s. condim 4 adds torsional friction; its coefficient is a length, the
    radius of the contact patch times the sliding friction: ~0.7 x 15 mm for a 22 x 19 mm
    pad pressed flat, so 0.01. The pads have priority 1, so their condim and friction are
    the ones used in every pad contact.
    """
    pads = [geom for geom in spec.geoms if geom.name.endswith(("_pad1", "_pad2"))]
    if len(pads) != 4:
        raise RuntimeError(f"expected four pad geoms in the 2F-85 model, found {[g.name for g in pads]}")
    for geom in pads:
        geom.condim = 4
        geom.friction = [geom.friction[0], PAD_TORSIONAL_FRICTION, geom.friction[2]]


def build_robot(config: RobotConfig) -> tuple[mujoco.MjSpec, RobotDescription]:
    """A new spec holding only the robot (world elements are added by ``bigym.world``)."""
    spec = _menagerie_spec("unitree_h1", "h1")
    spec.modelname = "bigym"
    _use_cached_meshes(spec)
    for element in [*spec.lights, *spec.actuators]:
        spec.delete(element)  # lights come from the world; actuators are rebuilt below
    _set_physics_options(spec)
    description = RobotDescription(config=config)

    pelvis = spec.body("pelvis")
    for joint in list(pelvis.joints):
        spec.delete(joint)
    if config.floating_base:
        _make_floating_base(spec, pelvis, config, description)
    else:
        pelvis.pos = [0.0, 0.0, STANCE_HEIGHT]
        pelvis.add_freejoint(name="root")

    for side in SIDES:
        _add_wrist(spec, side)
    _add_cameras(spec)
    _add_actuators(spec, config, description)
    # Grippers last, so the model's actuator order is exactly the action order.
    for side in SIDES:
        _attach_gripper(spec, side)
    _compensate_arm_gravity(spec)
    description.proprio_joints += [
        joint.name for side in SIDES for joint in spec.joints if joint.name.startswith(f"{side}_gripper/")
    ]

    return spec, description


def _make_floating_base(
    spec: mujoco.MjSpec, pelvis: mujoco.MjsBody, config: RobotConfig, description: RobotDescription
) -> None:
    pelvis.pos = [0.0, 0.0, 0.0 if "z" in config.floating_dofs else STANDING_HEIGHT]
    axes = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1), "rz": (0, 0, 1)}
    for dof in config.floating_dofs:
        joint = pelvis.add_joint(
            name=f"pelvis_{dof}",
            type=mujoco.mjtJoint.mjJNT_HINGE if dof == "rz" else mujoco.mjtJoint.mjJNT_SLIDE,
            axis=axes[dof],
        )
        joint.damping = [0.0, 0.0, 0.0]
        joint.armature = 0.0
        if dof == "z":
            joint.range = FLOATING_Z_RANGE
            joint.limited = mujoco.mjtLimited.mjLIMITED_TRUE
            joint.ref = 0.0
        else:
            joint.limited = mujoco.mjtLimited.mjLIMITED_FALSE
    # The base (pelvis, torso, welded legs) is carried by the servos: gravity is compensated
    # so the servos track without sag; legs are massless visuals that never collide.
    torso = spec.body("torso_link")
    for joint in list(torso.joints):
        spec.delete(joint)
    pelvis.gravcomp = 1.0
    torso.gravcomp = 1.0
    leg_bodies = []
    for side in SIDES:
        for part in LEG_JOINTS:
            body = spec.body(f"{side}_{part}_link")
            leg_bodies.append(body.name)
            for joint in list(body.joints):
                spec.delete(joint)
            for geom in list(body.geoms):
                if geom.contype != 0 or geom.conaffinity != 0:
                    spec.delete(geom)
            body.explicitinertial = True
            body.mass = 0.0
            body.inertia = [0.0, 0.0, 0.0]
    description.leg_bodies = tuple(leg_bodies)


def _add_wrist(spec: mujoco.MjSpec, side: str) -> None:
    elbow = spec.body(f"{side}_elbow_link")
    wrist = elbow.add_body(name=f"{side}_wrist_link", pos=[0.3, 0.0, -0.02])
    wrist.explicitinertial = True
    wrist.mass = 0.05
    wrist.inertia = [1e-5, 1e-5, 1e-5]
    joint = wrist.add_joint(name=f"{side}_wrist", type=mujoco.mjtJoint.mjJNT_HINGE, axis=[1, 0, 0])
    joint.range = WRIST_RANGE
    joint.limited = mujoco.mjtLimited.mjLIMITED_TRUE
    joint.damping = [1.0, 0.0, 0.0]
    joint.armature = 0.1
    wrist.add_site(name=f"{side}_wrist_site", size=[0.01, 0.01, 0.01], group=4)
    # A point-like, never-colliding geom at the wrist: tasks measure distances to it with
    # MuJoCo's geom-distance sensors, computed inside mj_step at no Python cost.
    wrist.add_geom(
        name=f"{side}_wrist_point",
        type=mujoco.mjtGeom.mjGEOM_SPHERE,
        size=[WRIST_POINT_RADIUS, 0, 0],
        contype=0,
        conaffinity=0,
        group=5,
        mass=0.0,
    )


def _attach_gripper(spec: mujoco.MjSpec, side: str) -> None:
    elbow = spec.body(f"{side}_elbow_link")
    wrist = spec.body(f"{side}_wrist_link")
    # The gripper's approach axis (its local z) points along the forearm (elbow link x).
    mount = wrist.add_site(name=f"{side}_gripper_mount", quat=_euler_quat((np.pi / 2, np.pi / 2, 0.0)), group=5)
    spec.attach(_gripper_spec(), site=mount, prefix=f"{side}_gripper/")
    # The menagerie actuator takes 0..255; rescale its gain so the control is 0 (open) .. 1 (closed).
    actuator = spec.actuator(f"{side}_gripper/fingers_actuator")
    gain = np.array(actuator.gainprm)
    gain[0] *= GRIPPER_MENAGERIE_CTRL_MAX
    actuator.gainprm = gain
    actuator.ctrlrange = (0.0, 1.0)
    for gripper_body in ("base_mount", "base"):
        spec.add_exclude(bodyname1=elbow.name, bodyname2=f"{side}_gripper/{gripper_body}")


def _compensate_arm_gravity(spec: mujoco.MjSpec) -> None:
    """Arms and grippers carry their own weight through their actuators, like a real
    controller's gravity feed-forward, so the servos track their targets without sag."""
    for side in SIDES:
        shoulder = spec.body(f"{side}_shoulder_pitch_link")
        shoulder.gravcomp = 1.0
        for body in shoulder.find_all(mujoco.mjtObj.mjOBJ_BODY):
            body.gravcomp = 1.0


def _add_cameras(spec: mujoco.MjSpec) -> None:
    torso = spec.body("torso_link")
    torso.add_camera(name="head", pos=[0.12, 0.0, 0.69], quat=_euler_quat((0.0, -0.52, -1.57)), fovy=60.0)
    for side in SIDES:
        elbow = spec.body(f"{side}_elbow_link")
        elbow.add_camera(
            name=f"{side}_wrist",
            pos=[0.2, 0.0, 0.1],
            quat=_euler_quat((0.0, -0.872665, -1.57)),
            fovy=60.0,
        )


def _joint_range(spec: mujoco.MjSpec, joint: str) -> tuple[float, float]:
    low, high = spec.joint(joint).range
    return float(low), float(high)


def _add_actuators(spec: mujoco.MjSpec, config: RobotConfig, description: RobotDescription) -> None:
    entries: list[ActuatorEntry] = []
    proprio: list[str] = []
    if config.floating_base:
        for dof in config.floating_dofs:
            joint = f"pelvis_{dof}"
            rng = FLOATING_Z_RANGE if dof == "z" else (-np.inf, np.inf)
            entries.append(ActuatorEntry(joint, joint, "base", rng))
            proprio.append(joint)
    else:
        for side in SIDES:
            for part in LEG_JOINTS:
                joint = f"{side}_{part}"
                entries.append(
                    ActuatorEntry(joint, joint, "leg", _joint_range(spec, joint), TORQUE_LIMITS[part])
                )
        entries.append(ActuatorEntry("torso", "torso", "torso", _joint_range(spec, "torso"), TORQUE_LIMITS["torso"]))
    for side in SIDES:
        for part in ARM_JOINTS:
            joint = f"{side}_{part}"
            entries.append(ActuatorEntry(joint, joint, "arm", _joint_range(spec, joint), TORQUE_LIMITS[part]))
    proprio += [e.joint for e in entries if e.kind in ("leg", "torso")]
    proprio += [e.joint for e in entries if e.kind == "arm"]

    for entry in entries:
        actuator = spec.add_actuator(name=entry.name, target=entry.joint)
        actuator.trntype = mujoco.mjtTrn.mjTRN_JOINT
        joint = spec.joint(entry.joint)
        if entry.kind == "base":
            actuator.set_to_position(kp=BASE_KP[entry.name.removeprefix("pelvis_")], dampratio=1.0)
            if np.isfinite(entry.joint_range[0]):
                actuator.ctrlrange = entry.joint_range
                actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
            else:
                actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE
            continue
        if entry.kind == "arm":
            joint.actgravcomp = True
        if config.torque_control:
            actuator.set_to_motor()
            actuator.ctrlrange = (-entry.torque_limit, entry.torque_limit)
            actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
        else:
            if entry.kind == "arm":
                actuator.set_to_position(kp=ARM_KP, dampratio=1.0)
            else:
                actuator.set_to_position(kp=LEG_KP, kv=LEG_KV)
            actuator.ctrlrange = entry.joint_range
            actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
            actuator.forcerange = (-entry.torque_limit, entry.torque_limit)
            actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
    description.actuators = entries
    description.proprio_joints = proprio
