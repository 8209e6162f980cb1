"""Demo metadata, action-mode descriptions and the physics fingerprint of a compiled model."""

from __future__ import annotations

import dataclasses
import datetime as _dt
import hashlib
import json
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np

import bigym
from bigym.action_modes import ActionMode, action_mode_from_dict
from bigym.demonstrations.errors import DemoCorruptError

FORMAT = "bigym-demo"
FORMAT_VERSION = 2  # 2: lightweight demos store packed actions and checkpoints (1 stays readable)
PHYSICS_FREQUENCY = 500.0
# What a state checkpoint holds: enough to prove a replay is in sync, far less than the
# full integration state (which also carries applied forces and the warm start).
CHECKPOINT_SPEC = int(
    mujoco.mjtState.mjSTATE_FULLPHYSICS
    | mujoco.mjtState.mjSTATE_CTRL
    | mujoco.mjtState.mjSTATE_EQ_ACTIVE
    | mujoco.mjtState.mjSTATE_MOCAP_POS
    | mujoco.mjtState.mjSTATE_MOCAP_QUAT
)
INITIAL_STATE_SPEC = int(mujoco.mjtState.mjSTATE_INTEGRATION)
SOURCES = ("expert", "human", "teleoperation", "policy", "random", "converted", "unknown")


def _now() -> str:
    return _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def _jsonable(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return value


@dataclass
class Metadata:
    """Everything needed to rebuild the env a demo was recorded in, and to trust a replay.

    The same class describes a request (``Metadata.from_env(env)``: task, action mode,
    observation config and control rate of the env you train in) and a recorded demo
    (plus seed, uuid, source, success, versions and the model fingerprint).
    """

    task: str
    action_mode: dict
    frequency: float  # control rate (Hz) of the actions
    observation_config: dict | None = None  # None for lightweight demos
    task_kwargs: dict = field(default_factory=dict)
    robot: dict = field(default_factory=dict)
    seed: int | None = None
    source: str = "unknown"
    success: bool | None = None
    uuid: str | None = None
    date: str | None = None
    num_steps: int | None = None
    checkpoint_interval: int | None = None
    checkpoint_spec: int = CHECKPOINT_SPEC
    initial_state_spec: int = INITIAL_STATE_SPEC
    bigym_version: str = bigym.__version__
    mujoco_version: str = mujoco.__version__
    model_fingerprint: str | None = None
    action_names: list[str] = field(default_factory=list)
    extra: dict = field(default_factory=dict)

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_env(cls, env, **overrides) -> Metadata:
        """Describe ``env`` (a BiGymEnv, wrapped or not): task, action mode, observations, rate."""
        base = getattr(env, "unwrapped", env)
        mode: ActionMode = base.action_mode
        config = mode.robot_config()
        values = dict(
            task=base.task_name,
            action_mode=mode.to_dict(),
            frequency=float(base.control_frequency),
            observation_config=base.observation_config.to_dict(),
            task_kwargs=dict(getattr(base, "task_kwargs", {}) or {}),
            robot={
                "floating_base": config.floating_base,
                "floating_dofs": list(config.floating_dofs) if config.floating_base else [],
                "torque_control": config.torque_control,
            },
            model_fingerprint=model_fingerprint(base.model),
            action_names=list(base.action_layout.names),
            date=_now(),
        )
        values.update(overrides)
        return cls(**values)

    # ------------------------------------------------------------------ derived
    @property
    def substeps(self) -> int:
        """Physics steps (500 Hz) per action."""
        return max(1, round(PHYSICS_FREQUENCY / float(self.frequency)))

    @property
    def env_id(self) -> str:
        return f"bigym/{self.task}-v0"

    @property
    def duration(self) -> float | None:
        return None if self.num_steps is None else self.num_steps / float(self.frequency)

    def make_action_mode(self) -> ActionMode:
        return action_mode_from_dict(self.action_mode)

    def replace(self, **changes) -> Metadata:
        return dataclasses.replace(self, **changes)

    # ------------------------------------------------------------------ serialisation
    def to_dict(self) -> dict:
        return _jsonable(dataclasses.asdict(self))

    @classmethod
    def from_dict(cls, data: dict) -> Metadata:
        known = {f.name for f in dataclasses.fields(cls)}
        missing = [name for name in ("task", "action_mode", "frequency") if name not in data]
        if missing:
            raise DemoCorruptError(f"demo metadata lacks {', '.join(missing)}")
        values = {k: v for k, v in data.items() if k in known}
        extra = dict(values.get("extra") or {})
        extra.update({k: v for k, v in data.items() if k not in known})  # fields from newer versions
        values["extra"] = extra
        return cls(**values)

    def to_header(self) -> dict[str, str]:
        """safetensors metadata: a string-to-string map, each value JSON."""
        header = {"format": FORMAT, "format_version": str(FORMAT_VERSION)}
        header.update({key: json.dumps(value) for key, value in self.to_dict().items()})
        return header

    @classmethod
    def from_header(cls, header: dict[str, str] | None, source: str = "demo") -> Metadata:
        if not header or header.get("format") != FORMAT:
            raise DemoCorruptError(f"{source} is not a bigym demo (no '{FORMAT}' format tag in its metadata)")
        version = int(header.get("format_version", "0"))
        if version > FORMAT_VERSION:
            raise DemoCorruptError(
                f"{source} uses demo format {version}; this bigym reads up to {FORMAT_VERSION}: upgrade bigym"
            )
        try:
            data = {k: json.loads(v) for k, v in header.items() if k not in ("format", "format_version")}
        except json.JSONDecodeError as error:
            raise DemoCorruptError(f"{source} has unreadable metadata: {error}") from error
        return cls.from_dict(data)


# ---------------------------------------------------------------------- action modes
def normalise_action_mode(mode: dict | ActionMode) -> dict:
    """A canonical dict: equal dicts mean the same action layout and semantics."""
    if isinstance(mode, ActionMode):
        mode = mode.to_dict()
    floating = bool(mode.get("floating_base", True))
    dofs = [str(d).removeprefix("pelvis_") for d in (mode.get("floating_dofs") or [])] if floating else []
    if floating and not dofs:
        dofs = ["x", "y", "z", "rz"]
    order = ["x", "y", "z", "rz"]
    dofs = sorted(dofs, key=lambda d: order.index(d) if d in order else len(order))
    absolute = mode.get("absolute")
    return {
        "name": mode["name"],
        "floating_base": floating,
        "floating_dofs": dofs,
        "absolute": None if absolute is None else bool(absolute),
    }


def same_action_mode(a: dict | ActionMode, b: dict | ActionMode) -> bool:
    return normalise_action_mode(a) == normalise_action_mode(b)


def describe_action_mode(mode: dict | ActionMode) -> str:
    """Human-readable, e.g. ``JointPositionActionMode(absolute, floating x,y,z,rz)``."""
    mode = normalise_action_mode(mode)
    parts = []
    if mode["absolute"] is not None:
        parts.append("absolute" if mode["absolute"] else "delta")
    parts.append("floating " + ",".join(mode["floating_dofs"]) if mode["floating_base"] else "whole body")
    return f"{mode['name']}({', '.join(parts)})"


def action_mode_slug(mode: dict | ActionMode) -> str:
    """A folder name, e.g. ``joint_position-absolute-floating_x_y_z_rz``."""
    mode = normalise_action_mode(mode)
    name = mode["name"].removesuffix("ActionMode")
    snake = "".join(f"_{c.lower()}" if c.isupper() else c for c in name).lstrip("_")
    parts = [snake]
    if mode["absolute"] is not None:
        parts.append("absolute" if mode["absolute"] else "delta")
    parts.append("floating_" + "_".join(mode["floating_dofs"]) if mode["floating_base"] else "whole_body")
    return "-".join(parts)


def frequency_slug(frequency: float) -> str:
    return f"{float(frequency):g}hz".replace(".", "_")


# ---------------------------------------------------------------------- fingerprint
_OPTION_FIELDS = (
    "timestep", "gravity", "wind", "magnetic", "density", "viscosity", "impratio", "tolerance",
    "ls_tolerance", "noslip_tolerance", "o_margin", "o_solref", "o_solimp", "o_friction", "integrator",
    "cone", "jacobian", "solver", "iterations", "ls_iterations", "noslip_iterations", "disableflags",
    "enableflags",
)  # fmt: skip
_SIZES = ("nq", "nv", "nu", "na", "nbody", "njnt", "neq", "nmocap", "ntendon", "nsensor", "npair", "nexclude")
_GLOBAL_FIELDS = (
    "qpos0", "qpos_spring",
    "jnt_type", "jnt_qposadr", "jnt_dofadr", "jnt_bodyid", "jnt_pos", "jnt_axis", "jnt_stiffness", "jnt_range",
    "jnt_limited", "jnt_solref", "jnt_solimp", "jnt_margin",
    "dof_bodyid", "dof_damping", "dof_armature", "dof_frictionloss", "dof_solref", "dof_solimp",
    "actuator_trntype", "actuator_dyntype", "actuator_gaintype", "actuator_biastype", "actuator_trnid",
    "actuator_gear", "actuator_dynprm", "actuator_gainprm", "actuator_biasprm", "actuator_ctrlrange",
    "actuator_forcerange", "actuator_ctrllimited", "actuator_forcelimited", "actuator_actlimited",
    "actuator_actrange",
    "eq_type", "eq_obj1id", "eq_obj2id", "eq_data", "eq_solref", "eq_solimp", "eq_active0",
    "tendon_stiffness", "tendon_damping", "tendon_range", "tendon_limited", "wrap_type", "wrap_objid",
    "pair_geom1", "pair_geom2", "pair_friction", "pair_solref", "pair_solimp", "exclude_signature",
    "sensor_type", "sensor_objtype", "sensor_objid", "sensor_reftype", "sensor_refid", "sensor_cutoff",
    "body_mocapid",
)  # fmt: skip
_BODY_FIELDS = (
    "body_parentid", "body_pos", "body_quat", "body_ipos", "body_iquat", "body_mass", "body_inertia",
    "body_gravcomp", "body_jntnum",
)  # fmt: skip
_GEOM_FIELDS = (
    "geom_type", "geom_bodyid", "geom_size", "geom_pos", "geom_quat", "geom_friction", "geom_contype",
    "geom_conaffinity", "geom_condim", "geom_priority", "geom_solmix", "geom_solref", "geom_solimp",
    "geom_margin", "geom_gap", "geom_dataid",
)  # fmt: skip


def _physical_bodies(model: mujoco.MjModel) -> np.ndarray:
    """Bodies that take part in the physics: with mass, joints, colliders or such descendants.

    Massless, joint-less, collider-less bodies are visuals (the posed legs of the floating
    base): their pose may change for rendering and must not change the fingerprint.
    """
    colliding = (model.geom_contype | model.geom_conaffinity) != 0
    own = (model.body_mass > 0) | (model.body_jntnum > 0) | (model.body_mocapid >= 0)
    own = own.copy()
    np.logical_or.at(own, model.geom_bodyid[colliding], True)
    keep = own.copy()
    for body in range(model.nbody - 1, 0, -1):  # children have larger ids than parents
        if keep[body]:
            keep[model.body_parentid[body]] = True
    return keep


def model_fingerprint(model: mujoco.MjModel) -> str:
    """sha256 over every compiled quantity that affects the physics (hex, 64 characters).

    Two models with the same fingerprint step identically; visual-only settings (colours,
    cameras, offscreen buffer, the posed visual legs) do not enter it.
    """
    digest = hashlib.sha256()

    def add(name: str, value) -> None:
        array = np.ascontiguousarray(np.asarray(value))
        digest.update(f"{name}:{array.dtype.str}:{array.shape};".encode())
        digest.update(array.tobytes())

    for name in _SIZES:
        add(name, getattr(model, name))
    for name in _OPTION_FIELDS:
        if hasattr(model.opt, name):
            add(f"opt.{name}", getattr(model.opt, name))
    for name in _GLOBAL_FIELDS:
        if hasattr(model, name):
            add(name, getattr(model, name))
    bodies = _physical_bodies(model)
    for name in _BODY_FIELDS:
        add(name, getattr(model, name)[bodies])
    geoms = (model.geom_contype | model.geom_conaffinity) != 0
    for name in _GEOM_FIELDS:
        add(name, getattr(model, name)[geoms])
    is_mesh = model.geom_type[geoms] == mujoco.mjtGeom.mjGEOM_MESH
    meshes = sorted({int(m) for m in model.geom_dataid[geoms][is_mesh] if m >= 0})
    for mesh in meshes:
        start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
        add(f"mesh{mesh}", model.mesh_vert[start : start + count])
    return digest.hexdigest()


# ---------------------------------------------------------------------- state layout
_STATE_NAMES = {
    int(mujoco.mjtState.mjSTATE_TIME): "time",
    int(mujoco.mjtState.mjSTATE_QPOS): "qpos",
    int(mujoco.mjtState.mjSTATE_QVEL): "qvel",
    int(mujoco.mjtState.mjSTATE_ACT): "act",
    int(mujoco.mjtState.mjSTATE_HISTORY): "history",
    int(mujoco.mjtState.mjSTATE_WARMSTART): "qacc_warmstart",
    int(mujoco.mjtState.mjSTATE_CTRL): "ctrl",
    int(mujoco.mjtState.mjSTATE_QFRC_APPLIED): "qfrc_applied",
    int(mujoco.mjtState.mjSTATE_XFRC_APPLIED): "xfrc_applied",
    int(mujoco.mjtState.mjSTATE_EQ_ACTIVE): "eq_active",
    int(mujoco.mjtState.mjSTATE_MOCAP_POS): "mocap_pos",
    int(mujoco.mjtState.mjSTATE_MOCAP_QUAT): "mocap_quat",
    int(mujoco.mjtState.mjSTATE_USERDATA): "userdata",
    int(mujoco.mjtState.mjSTATE_PLUGIN): "plugin_state",
    int(mujoco.mjtState.mjSTATE_PLASTIC): "plastic",
}


def state_segments(model: mujoco.MjModel, spec: int) -> dict[str, slice]:
    """Where each field lies in a state vector of ``spec`` (fields in MuJoCo's bit order)."""
    segments: dict[str, slice] = {}
    start = 0
    for bit in range(int(mujoco.mjtState.mjNSTATE)):
        flag = 1 << bit
        if spec & flag:
            size = mujoco.mj_stateSize(model, flag)
            segments[_STATE_NAMES.get(flag, f"state_bit{bit}")] = slice(start, start + size)
            start += size
    return segments


def describe_state_index(model: mujoco.MjModel, spec: int, index: int) -> str:
    """Name the state element ``index``, e.g. ``qpos[12] (joint left_elbow)``."""
    for name, part in state_segments(model, spec).items():
        if part.start <= index < part.stop:
            offset = index - part.start
            if name == "qpos":
                joint = int(np.searchsorted(model.jnt_qposadr, offset, side="right") - 1)
                return f"qpos[{offset}] (joint {model.joint(joint).name or joint})"
            if name == "qvel":
                return f"qvel[{offset}] (joint {model.joint(int(model.dof_jntid[offset])).name or offset})"
            if name == "ctrl":
                return f"ctrl[{offset}] (actuator {model.actuator(offset).name or offset})"
            return f"{name}[{offset}]"
    return f"state[{index}]"
