"""The compiled step path: env.step's per-step bookkeeping in C, the same bits as in Python.

Why: at 500 Hz the physics of the lighter tasks takes 25-50 us, and validating and
applying the action, calling ``mj_step2``/``mj_step1``, gathering the proprioception and
reducing the contacts cost about as many Python calls as there are parts, 5-12 us in all;
below 500 Hz each physics step of the servo-target ramp cost three more calls. The
extension ``bigym._hotloop`` (``bigym/_hotloop.c``, built when bigym is installed, if a C
compiler is there) does that work in one call each, with the very floating-point
operations of the Python code, so demos replay bit for bit on either path.

The Python code stays the reference and the fallback: the extension is optional, and
``BIGYM_PURE_PYTHON=1`` in the environment turns it off. :data:`AVAILABLE` says which
path this process runs.
"""

from __future__ import annotations

import ctypes
import functools
import glob
import os
from types import ModuleType

import mujoco
import numpy as np

#: control_step's return codes (see bigym/_hotloop.c)
STEP_OK, STEP_INVALID, STEP_UNSUPPORTED, STEP_UNSTABLE = 0, 1, 2, 3


def _mujoco_library() -> ctypes.CDLL | None:
    """The MuJoCo library the bindings loaded (opening the same file again gives its handle)."""
    folder = os.path.dirname(mujoco.__file__)
    for pattern in ("libmujoco.so*", "libmujoco*.dylib", "mujoco.dll"):
        for path in sorted(glob.glob(os.path.join(folder, pattern))):
            try:
                return ctypes.CDLL(path)
            except OSError:
                continue
    return None


def _load() -> tuple[ModuleType | None, int, int]:
    if os.environ.get("BIGYM_PURE_PYTHON", "") not in ("", "0"):
        return None, 0, 0
    try:
        from bigym import _hotloop
    except ImportError:
        return None, 0, 0
    library = _mujoco_library()
    if library is None:
        return None, 0, 0
    try:
        step1 = ctypes.cast(library.mj_step1, ctypes.c_void_p).value
        step2 = ctypes.cast(library.mj_step2, ctypes.c_void_p).value
    except AttributeError:
        return None, 0, 0
    if not (step1 and step2) or not hasattr(mujoco.MjData, "_address"):
        return None, 0, 0
    return _hotloop, int(step1), int(step2)


_module, _STEP1, _STEP2 = _load()
#: whether env.step runs the compiled path in this process
AVAILABLE = _module is not None


def _address(array: np.ndarray) -> int:
    if not array.flags.c_contiguous:
        raise ValueError("the compiled step path needs contiguous arrays")
    return int(array.ctypes.data)


class CompiledControlStep:
    """One env's control step in C: validate the action, write it into ``ctrl`` (ramped
    over the physics steps below 500 Hz), step the physics, report instability.

    ``step(action)`` returns one of the ``STEP_*`` codes; on ``STEP_INVALID`` and
    ``STEP_UNSUPPORTED`` nothing has changed, and the caller's Python code explains or
    converts the action. The arrays the C side points into are kept here.
    """

    def __init__(
        self,
        controller,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        ctrl: np.ndarray,
        substeps: int,
        held: np.ndarray | None,
        fractions: np.ndarray,
        warning_counts: np.ndarray,
    ) -> None:
        if _module is None:
            raise RuntimeError("the compiled step path is not available")
        if ctrl.dtype != np.float64 or not ctrl.flags.c_contiguous:
            raise ValueError("ctrl must be a contiguous float64 view")
        if warning_counts.dtype != np.int32 or warning_counts.ndim != 1:
            raise ValueError("warning_counts must be data.warning.number")
        self._model, self._data = model, data
        self._keep = np.ascontiguousarray(controller._keep, dtype=np.float64)
        self._ctrl_low = np.ascontiguousarray(controller._ctrl_low, dtype=np.float64)
        self._ctrl_high = np.ascontiguousarray(controller._ctrl_high, dtype=np.float64)
        self._check_low = np.ascontiguousarray(controller._check_low, dtype=np.float64)
        self._check_high = np.ascontiguousarray(controller._check_high, dtype=np.float64)
        self._check_low32 = np.ascontiguousarray(controller._check_low32, dtype=np.float32)
        self._check_high32 = np.ascontiguousarray(controller._check_high32, dtype=np.float32)
        self._held = None if held is None else np.ascontiguousarray(held, dtype=np.uint8)
        self._fractions = np.ascontiguousarray(np.asarray(fractions, dtype=np.float64).ravel())
        self._warnings = warning_counts
        self._scratch = np.zeros(2 * ctrl.size)
        self._ctrl = ctrl
        arrays = (self._keep, self._ctrl_low, self._ctrl_high, self._check_low, self._check_high)
        if any(a.size != ctrl.size for a in (*arrays, self._check_low32, self._check_high32)):
            raise ValueError("the controller's bounds do not match ctrl")
        self._plan = _module.make_control_plan(
            _STEP1, _STEP2, int(model._address), int(data._address), _address(ctrl), ctrl.size, int(substeps),
            bool(not controller._keep.any()), *(_address(a) for a in arrays),
            _address(self._check_low32), _address(self._check_high32),
            0 if self._held is None else _address(self._held),
            _address(self._fractions) if self._fractions.size else _address(self._scratch),
            int(warning_counts.ctypes.data), int(warning_counts.strides[0]), int(warning_counts.size),
            _address(self._scratch),
        )  # fmt: skip
        #: ``step(action) -> code``: a C-level partial, no Python frame per call
        self.step = functools.partial(_module.control_step, self._plan)


class CompiledGather:
    """The proprioception gather in C: rows read from the state, the two gripper openings
    computed and clipped, the constant rows written, all as float32 (see
    :class:`bigym.observations.ProprioceptionReader`)."""

    def __init__(
        self,
        span: np.ndarray,
        index: np.ndarray,
        rows: int,
        left_row: int,
        right_row: int,
        scale: float,
        constant_rows: np.ndarray | None,
        constant_values: np.ndarray,
    ) -> None:
        if _module is None:
            raise RuntimeError("the compiled step path is not available")
        if span.dtype != np.float64 or span.strides != (8,):
            raise ValueError("span must be a float64 run")
        self._span = span
        self._index = np.ascontiguousarray(index, dtype=np.int64)
        if self._index.size != rows + 4 or self._index.min() < 0 or self._index.max() >= span.size:
            raise ValueError("the gather index must give every row and four driver angles inside the span")
        self._constant_rows = np.ascontiguousarray(
            constant_rows if constant_rows is not None else np.zeros(0), dtype=np.int64
        )
        self._constant_values = np.ascontiguousarray(constant_values, dtype=np.float64)
        if self._constant_rows.size != self._constant_values.size:
            raise ValueError("one constant per constant row")
        constants = self._constant_rows.size
        self.rows = rows
        self._plan = _module.make_gather_plan(
            int(span.ctypes.data), _address(self._index), rows, left_row, right_row, float(scale),
            _address(self._constant_rows) if constants else _address(self._index),
            _address(self._constant_values) if constants else int(span.ctypes.data), constants,
        )  # fmt: skip
        self._gather = _module.gather

    def read(self) -> np.ndarray:
        values = np.empty(self.rows, np.float32)
        self._gather(self._plan, values)
        return values


def label_pairs_function():
    """``label_pairs(labels_address, geoms, dists or None)`` of the extension, or ``None``."""
    return None if _module is None else _module.label_pairs


__all__ = ["AVAILABLE", "CompiledControlStep", "CompiledGather", "label_pairs_function"]
