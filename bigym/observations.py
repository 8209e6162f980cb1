"""Observation configuration and the proprioception reader.

Keys returned by the env (all float32 unless noted):

* ``proprioception``: robot joint positions then velocities, in the order of
  ``env.unwrapped.observation_layout`` (base DOFs, legs and torso in whole-body mode,
  arms with wrists, then the gripper linkage joints);
* ``proprioception_grippers``: opening of (left, right) gripper, 0 open .. 1 closed;
* ``proprioception_floating_base``: pelvis world (x, y, z, yaw);
* ``proprioception_floating_base_actions``: floating mode only, the base servo targets
  (the running sum of base actions, offset by the start pose);
* ``rgb_<camera>``: uint8 (3, H, W); ``depth_<camera>``: float32 (H, W) in metres;
* task keys when ``privileged_information=True``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import gymnasium as gym
import mujoco
import numpy as np

from bigym.hotloop import AVAILABLE as HOTLOOP_AVAILABLE
from bigym.hotloop import CompiledGather
from bigym.layout import Layout, LayoutEntry
from bigym.robot.h1 import CAMERAS
from bigym.robot.robot import GRIPPER_DRIVER_MAX, Robot

CAMERA_NAMES = (*CAMERAS, "external")
#: observation keys of camera images start with these (``rgb_head``, ``depth_left_wrist``)
IMAGE_PREFIXES = ("rgb_", "depth_")


def is_image_key(key: str) -> bool:
    """Whether an observation key holds a camera image (RGB or depth) rather than a vector."""
    return key.startswith(IMAGE_PREFIXES)


@dataclass(frozen=True)
class CameraConfig:
    """One camera's images: ``resolution`` is (height, width).

    ``pos`` (x, y, z in metres) and ``quat`` (w, x, y, z, normalised here) move the camera:
    in its parent's frame, which is the world for ``external`` and the carrying link for
    the robot cameras (the torso for ``head``, the elbow links for the wrists). Either may
    be given alone; the other keeps the built-in value. MuJoCo cameras look along their
    local -z axis with +y up in the image.
    """

    name: str
    rgb: bool = True
    depth: bool = False
    resolution: tuple[int, int] = (84, 84)
    pos: tuple[float, float, float] | None = None
    quat: tuple[float, float, float, float] | None = None

    def __post_init__(self) -> None:
        if self.name not in CAMERA_NAMES:
            raise ValueError(f"unknown camera {self.name!r}; choose from {CAMERA_NAMES}")
        try:
            height, width = self.resolution
        except (TypeError, ValueError):
            raise ValueError(f"camera {self.name!r}: resolution must be (height, width), got {self.resolution!r}") from None
        if not (isinstance(height, int) and isinstance(width, int) and height > 0 and width > 0):
            raise ValueError(f"camera {self.name!r}: resolution must be two positive ints, got {self.resolution}")
        object.__setattr__(self, "resolution", (int(height), int(width)))
        if not (self.rgb or self.depth):
            raise ValueError(f"camera {self.name!r} renders neither rgb nor depth")
        if self.pos is not None:
            object.__setattr__(self, "pos", _finite_vector(self.name, "pos", self.pos, 3))
        if self.quat is not None:
            quat = np.array(_finite_vector(self.name, "quat", self.quat, 4))
            norm = float(np.linalg.norm(quat))
            if norm < 1e-6:
                raise ValueError(f"camera {self.name!r}: quat must not be zero, got {self.quat!r}")
            object.__setattr__(self, "quat", tuple(float(q) for q in quat / norm))

    def to_dict(self) -> dict:
        out = {"name": self.name, "rgb": self.rgb, "depth": self.depth, "resolution": list(self.resolution)}
        # Only when set, so the content keys of replays made with the built-in poses stay as they were.
        if self.pos is not None:
            out["pos"] = list(self.pos)
        if self.quat is not None:
            out["quat"] = list(self.quat)
        return out

    @classmethod
    def from_dict(cls, data: dict) -> CameraConfig:
        return cls(
            data["name"],
            data["rgb"],
            data["depth"],
            tuple(data["resolution"]),
            tuple(data["pos"]) if data.get("pos") is not None else None,
            tuple(data["quat"]) if data.get("quat") is not None else None,
        )


def _finite_vector(camera: str, field_name: str, value, size: int) -> tuple[float, ...]:
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"camera {camera!r}: {field_name} must be {size} numbers, got {value!r}") from None
    if array.shape != (size,) or not np.all(np.isfinite(array)):
        raise ValueError(f"camera {camera!r}: {field_name} must be {size} finite numbers, got {value!r}")
    return tuple(float(v) for v in array)


@dataclass(frozen=True)
class ObservationConfig:
    """Which observations the env returns."""

    cameras: tuple[CameraConfig, ...] = field(default_factory=tuple)
    proprioception: bool = True
    privileged_information: bool = False

    def __post_init__(self) -> None:
        cameras = tuple(self.cameras)
        names = [c.name for c in cameras]
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise ValueError(f"cameras listed twice: {duplicates}")
        object.__setattr__(self, "cameras", cameras)

    @classmethod
    def robot_cameras(cls, resolution: tuple[int, int] = (84, 84), depth: bool = True, **kwargs) -> ObservationConfig:
        """The three robot cameras (head, left and right wrist) with RGB and optional depth."""
        return cls(cameras=tuple(CameraConfig(n, True, depth, resolution) for n in CAMERAS), **kwargs)

    def to_dict(self) -> dict:
        return {
            "cameras": [c.to_dict() for c in self.cameras],
            "proprioception": self.proprioception,
            "privileged_information": self.privileged_information,
        }

    @classmethod
    def from_dict(cls, data: dict) -> ObservationConfig:
        cameras = tuple(CameraConfig.from_dict(c) for c in data.get("cameras", []))
        return cls(cameras, data.get("proprioception", True), data.get("privileged_information", False))


def _box(shape: tuple[int, ...], low: float = -np.inf, high: float = np.inf) -> gym.spaces.Box:
    return gym.spaces.Box(low=low, high=high, shape=shape, dtype=np.float32)


class ProprioceptionReader:
    """Reads every proprioception key with one gather straight from MjData's memory.

    ``data.qpos``, ``data.qvel`` and ``data.ctrl`` lie in one MjData buffer; a read-only
    float64 view spanning from the first to the end of the last lets one ``take`` with a
    fixed index array pick every entry at once (joint positions and velocities, base
    pose, base targets) without copying the state first. Only the two gripper openings
    (the mean of two driver angles) are computed, on Python floats. A handful of calls per
    step whatever the robot size, touching only the entries read.
    """

    def __init__(self, model: mujoco.MjModel, robot: Robot) -> None:
        self.robot = robot
        names = robot.proprio_names
        n = len(names)
        entries = [LayoutEntry(f"{name}_qpos", i, -np.inf, np.inf, "", "qpos") for i, name in enumerate(names)]
        entries += [LayoutEntry(f"{name}_qvel", n + i, -np.inf, np.inf, "", "qvel") for i, name in enumerate(names)]
        self.layout = Layout(entries)
        self._floating = robot.floating_base
        self.spaces: dict[str, gym.spaces.Box] = {
            "proprioception": _box((2 * n,)),
            "proprioception_grippers": _box((2,), 0.0, 1.0),
            "proprioception_floating_base": _box((4,)),
        }
        base_dofs = list(robot.base_ctrl) if self._floating else []
        if self._floating:
            self.spaces["proprioception_floating_base_actions"] = _box((len(base_dofs),))

        # What each entry reads: (field, address in that field), or a constant. Gripper rows
        # and the whole-body base pose are computed after the gather.
        base_row = 2 * n + 2
        rows = base_row + 4 + len(base_dofs)
        sources: list[tuple[str, int]] = [("qpos", 0)] * rows
        constants: dict[int, float] = {}
        for i, (qpos_adr, dof_adr) in enumerate(zip(robot.proprio_qpos, robot.proprio_qvel)):
            sources[i] = ("qpos", int(qpos_adr))
            sources[n + i] = ("qvel", int(dof_adr))
        if self._floating:
            fixed = {"x": 0.0, "y": 0.0, "z": robot.fixed_height, "rz": 0.0}
            for k, dof in enumerate(("x", "y", "z", "rz")):
                if dof in robot.base_qpos:
                    sources[base_row + k] = ("qpos", int(robot.base_qpos[dof]))
                else:
                    constants[base_row + k] = float(fixed[dof])
            for k, dof in enumerate(base_dofs):
                sources[base_row + 4 + k] = ("ctrl", int(robot.base_ctrl[dof]))
        drivers = np.sort(np.asarray(robot.driver_qpos), axis=1)
        if drivers.shape != (2, 2):
            raise RuntimeError(f"expected two driver joints per gripper, got {drivers.tolist()}")
        # The gather reads every row, then the four driver angles (left a, b, right a, b).
        self._sources = sources + [("qpos", int(q)) for q in drivers.ravel()]
        self._constant_rows = np.array(list(constants), dtype=np.int64) if constants else None
        self._constant_values = np.array(list(constants.values()))
        self._rows = rows
        self._gripper_scale = 0.5 / GRIPPER_DRIVER_MAX
        self._slices = {
            "proprioception": slice(0, 2 * n),
            "proprioception_grippers": slice(2 * n, 2 * n + 2),
            "proprioception_floating_base": slice(base_row, base_row + 4),
        }
        if self._floating:
            self._slices["proprioception_floating_base_actions"] = slice(base_row + 4, base_row + 4 + len(base_dofs))
        self._grippers = self._slices["proprioception_grippers"]
        self._left_gripper, self._right_gripper = 2 * n, 2 * n + 1
        self._base = self._slices["proprioception_floating_base"]
        self._slice_items = tuple(self._slices.items())
        self._data: mujoco.MjData | None = None  # the MjData the view below reads
        self._compiled: CompiledGather | None = None  # the gather in C, once bound (bigym.hotloop)

    def _bind(self, data: mujoco.MjData) -> None:
        """The read-only view over ``data``'s qpos .. ctrl and the gather index into it. MjData
        never reallocates these arrays (reset and state copies write in place), so one bind
        lasts as long as ``data``."""
        fields = {name: getattr(data, name) for name in ("qpos", "qvel", "ctrl")}
        first = min(fields, key=lambda name: fields[name].ctypes.data)
        start = fields[first].ctypes.data
        offsets = {}
        for name, array in fields.items():
            offset, rest = divmod(array.ctypes.data - start, 8)
            if rest or array.dtype != np.float64:
                raise RuntimeError(f"data.{name} is not a float64 array aligned with data.{first}")
            offsets[name] = offset
        end = max(offsets[name] + array.size for name, array in fields.items())
        # Only the indexed entries are ever read: each lies inside its own field.
        self._span = np.lib.stride_tricks.as_strided(fields[first], shape=(end,), strides=(8,), writeable=False)
        self._index = np.array([offsets[name] + adr for name, adr in self._sources], dtype=np.int64)
        self._compiled = (
            CompiledGather(
                self._span, self._index, self._rows, self._left_gripper, self._right_gripper, self._gripper_scale,
                self._constant_rows, self._constant_values,
            )
            if HOTLOOP_AVAILABLE
            else None
        )  # fmt: skip
        self._data = data

    def read(self, data: mujoco.MjData, obs: dict[str, np.ndarray]) -> None:
        """Put every proprioception key into ``obs``: views of one freshly allocated float32
        array, so observations handed out earlier are never overwritten."""
        if data is not self._data:
            self._bind(data)
        values = self._compiled.read() if self._compiled is not None else self._gather()  # C: the same values
        if not self._floating:  # free-joint yaw is not linear in the state
            values[self._base] = self.robot.base_pose(data)
        for key, part in self._slice_items:
            obs[key] = values[part]

    def _gather(self) -> np.ndarray:
        """Every row as float32 (the Python reference of the compiled gather)."""
        gathered = self._span.take(self._index)  # a new float64 array: rows, then 4 driver angles
        left_a, left_b, right_a, right_b = gathered[self._rows :].tolist()
        scale = self._gripper_scale
        left, right = scale * left_a + scale * left_b, scale * right_a + scale * right_b
        # Clipped to [0, 1] as np.minimum(np.maximum(x, 0), 1) does it: NaN stays, -0.0 becomes 0.0.
        gathered[self._left_gripper] = 0.0 if left <= 0.0 else 1.0 if left > 1.0 else left
        gathered[self._right_gripper] = 0.0 if right <= 0.0 else 1.0 if right > 1.0 else right
        if self._constant_rows is not None:  # base DOFs that the floating base does not have
            gathered[self._constant_rows] = self._constant_values
        return gathered.astype(np.float32)
