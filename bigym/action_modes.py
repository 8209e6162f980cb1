"""Action modes: how a flat action vector becomes actuator controls.

Layout (see ``env.unwrapped.action_layout``):

* floating base (bi-manual): ``[base dx, dy, dz, dyaw] + left arm (5) + right arm (5) + grippers (2)``
  (only the configured base DOFs appear);
* whole body: ``legs (10) + torso + left arm (5) + right arm (5) + grippers (2)``.

Base actions are always deltas of the base servo targets in the world frame, bounded per
control step (the per-physics-step limit times the number of physics steps per control step).
Grippers are 0 (open) .. 1 (closed). Actions outside the bounds raise ``ValueError``; nothing
is clipped silently.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from bigym.layout import Layout, LayoutEntry
from bigym.robot.h1 import FLOATING_DOFS, RobotConfig
from bigym.robot.robot import Robot

# Largest base change per 500 Hz physics step (m and rad); scaled by substeps per action.
BASE_STEP_LIMITS = {"x": 0.01, "y": 0.01, "z": 0.01, "rz": 0.05}
# Largest delta joint-target change per 500 Hz physics step (rad); scaled by substeps.
DELTA_JOINT_STEP_LIMIT = 0.1


def _normalise_dofs(dofs: Sequence[str] | None) -> tuple[str, ...]:
    if dofs is None:
        return FLOATING_DOFS
    return tuple(str(d).removeprefix("pelvis_") for d in dofs)


@dataclass
class ActionMode:
    """Common settings of every action mode."""

    floating_base: bool = True
    floating_dofs: Sequence[str] | None = None

    @property
    def absolute(self) -> bool | None:
        return None

    @property
    def torque(self) -> bool:
        return False

    def robot_config(self) -> RobotConfig:
        dofs = _normalise_dofs(self.floating_dofs) if self.floating_base else ()
        return RobotConfig(
            floating_base=self.floating_base,
            floating_dofs=dofs if self.floating_base else FLOATING_DOFS,
            torque_control=self.torque,
        )

    def to_dict(self) -> dict:
        """A JSON-able description (demo metadata, caches)."""
        return {
            "name": type(self).__name__,
            "floating_base": self.floating_base,
            "floating_dofs": list(self.robot_config().floating_dofs) if self.floating_base else [],
            "absolute": self.absolute,
        }

    def controller(self, robot: Robot, substeps: int) -> ActionController:
        """Bind this mode to a compiled robot at a control rate."""
        return ActionController(self, robot, substeps)


@dataclass
class JointPositionActionMode(ActionMode):
    """Position servos on every joint; ``absolute`` targets or per-step ``delta`` targets."""

    floating_base: bool = True
    absolute: bool = False  # type: ignore[assignment]
    floating_dofs: Sequence[str] | None = None


@dataclass
class TorqueActionMode(ActionMode):
    """Motor torques on the limbs; the floating base and grippers stay position-controlled."""

    floating_base: bool = True
    floating_dofs: Sequence[str] | None = field(default=None)

    @property
    def torque(self) -> bool:
        return True


def action_mode_from_dict(data: dict) -> ActionMode:
    """Inverse of :meth:`ActionMode.to_dict`."""
    name = data["name"]
    dofs = data.get("floating_dofs") or None
    if name == "JointPositionActionMode":
        return JointPositionActionMode(
            floating_base=data["floating_base"], absolute=bool(data["absolute"]), floating_dofs=dofs
        )
    if name == "TorqueActionMode":
        return TorqueActionMode(floating_base=data["floating_base"], floating_dofs=dofs)
    raise ValueError(f"unknown action mode {name!r}")


_GROUP_OF_KIND = {"base": "base", "leg": "legs", "torso": "torso"}
_FLOAT32 = np.dtype(np.float32)

try:  # the ufunc behind np.clip, minus np.clip's Python-level argument handling: half the cost of max + min
    from numpy._core.umath import clip as _clip
except ImportError:  # pragma: no cover - a numpy that moved it

    def _clip(x: np.ndarray, low: np.ndarray, high: np.ndarray, out: np.ndarray) -> np.ndarray:
        return np.minimum(np.maximum(x, low, out=out), high, out=out)


class ActionController:
    """Validates actions and writes them to ``data.ctrl`` with one vectorised update.

    ``ctrl = clip(keep * ctrl + action, ctrl_low, ctrl_high)``: ``keep`` is 1 for delta
    entries and 0 for absolute ones (the gripper actuators take 0..1 directly).
    """

    def __init__(self, mode: ActionMode, robot: Robot, substeps: int) -> None:
        entries: list[LayoutEntry] = []
        keep, ctrl_low, ctrl_high, torque = [], [], [], []
        absolute = bool(mode.absolute)
        for index, act in enumerate(robot.description.actuators):
            group = _GROUP_OF_KIND.get(act.kind) or ("left_arm" if act.name.startswith("left") else "right_arm")
            if act.kind == "base":
                dof = act.name.removeprefix("pelvis_")
                limit = BASE_STEP_LIMITS[dof] * substeps
                low, high, unit, k = -limit, limit, "rad" if dof == "rz" else "m", 1.0
                name = f"base_d{dof.replace('rz', 'yaw')}"
                c_low, c_high = act.joint_range
            elif mode.torque:
                low, high, unit, k = -act.torque_limit, act.torque_limit, "Nm", 0.0
                name = act.name
                c_low, c_high = low, high
            elif absolute:
                low, high, unit, k = act.joint_range[0], act.joint_range[1], "rad", 0.0
                name = act.name
                c_low, c_high = act.joint_range
            else:
                limit = DELTA_JOINT_STEP_LIMIT * substeps
                low, high, unit, k = -limit, limit, "rad", 1.0
                name = f"{act.name}_delta"
                c_low, c_high = act.joint_range  # targets never wind up past the joint range
            entries.append(LayoutEntry(name, index, low, high, unit, group))
            torque.append(unit == "Nm")
            keep.append(k)
            ctrl_low.append(c_low)
            ctrl_high.append(c_high)
        for side in ("left", "right"):
            entries.append(LayoutEntry(f"{side}_gripper", len(entries), 0.0, 1.0, "0 open .. 1 closed", "grippers"))
            keep.append(0.0)
            torque.append(False)
            ctrl_low.append(0.0)
            ctrl_high.append(1.0)
        self.layout = Layout(entries)
        # Which entries are forces: the env holds them over a control step and ramps the rest.
        self.torque = np.array(torque, bool)
        self.low = np.array([e.low for e in entries], np.float32)
        self.high = np.array([e.high for e in entries], np.float32)
        # Compare in float64 against the float32 bounds widened by one float32 ulp, so a bound
        # written in float64 (2.87) is not rejected for exceeding its float32 rounding.
        self._check_low = np.nextafter(self.low, np.float32(-np.inf)).astype(np.float64)
        self._check_high = np.nextafter(self.high, np.float32(np.inf)).astype(np.float64)
        self._keep = np.array(keep)
        self._ctrl_low = np.array(ctrl_low)
        self._ctrl_high = np.array(ctrl_high)
        self.shape = (len(entries),)
        self._all_absolute = not self._keep.any()
        # The same test in float32 for float32 actions (exact: float32 values compare alike in
        # either precision), so the common case converts nothing.
        self._check_low32 = self._check_low.astype(np.float32)
        self._check_high32 = self._check_high.astype(np.float32)
        self._all_true = np.ones(self.shape, bool).tobytes()  # what both comparisons give for a valid action

    def validate(self, action: np.ndarray) -> np.ndarray:
        """The action as a float32 or float64 array, or ``ValueError`` naming every offending entry.

        NaN fails every comparison, so the bounds test also rejects non-finite entries. Each
        comparison's verdicts are checked as raw bytes: no ``ndarray.all()`` (a Python-level
        wrapper, the slowest part of this check).
        """
        if type(action) is np.ndarray and action.dtype is _FLOAT32:  # what action_space.sample() gives
            if action.shape == self.shape:
                if (
                    np.greater_equal(action, self._check_low32).tobytes() == self._all_true
                    and np.less_equal(action, self._check_high32).tobytes() == self._all_true
                ):
                    return action
                raise ValueError(self._describe_invalid(action))
        action = np.asarray(action, dtype=np.float64)
        if action.shape != self.shape:
            raise ValueError(f"action has shape {action.shape}, expected {self.shape}")
        if (
            np.greater_equal(action, self._check_low).tobytes() != self._all_true
            or np.less_equal(action, self._check_high).tobytes() != self._all_true
        ):
            raise ValueError(self._describe_invalid(action))
        return action

    def _describe_invalid(self, action: np.ndarray) -> str:
        problems = []
        for entry, value in zip(self.layout.entries, action):
            if not np.isfinite(value):
                problems.append(f"{entry.name}[{entry.index}]={value} is not finite")
            elif not self._check_low[entry.index] <= value <= self._check_high[entry.index]:
                problems.append(f"{entry.name}[{entry.index}]={value:.6g} outside [{entry.low:g}, {entry.high:g}]")
        return "invalid action: " + "; ".join(problems)

    def apply(self, ctrl: np.ndarray, action: np.ndarray) -> None:
        """Write a validated action into ``ctrl``, the robot's slice of ``data.ctrl``, in place."""
        if self._all_absolute:
            ctrl[:] = action
        else:
            np.multiply(ctrl, self._keep, out=ctrl)
            np.add(ctrl, action, out=ctrl)  # a float32 action widens exactly
        _clip(ctrl, self._ctrl_low, self._ctrl_high, out=ctrl)  # = np.minimum(np.maximum(...)), bit for bit
