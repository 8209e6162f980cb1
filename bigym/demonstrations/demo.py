"""Demo containers and their safetensors files.

* :class:`Demo` is the lightweight demo, one file per episode: the actions at the
  recording rate (float64, exactly what the env applied), the full initial simulator
  state after ``reset(seed)``, and periodic state checkpoints for proving a replay in sync.
* :class:`ReplayedDemo` is a demo replayed into an :class:`~bigym.observations.ObservationConfig`
  at some control rate: observations, actions, rewards, flags and states per step.

File layout (safetensors; metadata is a string map whose values are JSON, see
:meth:`Metadata.to_header`)::

    Demo (format 2)                                  ReplayedDemo
    actions_packed            (bytes)  uint8         actions      (T, A)     float64
    initial_state             (S,)     float64       obs.<key>    (T+1, ...) env dtype
    checkpoint_steps          (K,)     int64         rewards      (T,)       float64
    checkpoint_states_packed  (bytes)  uint8         terminated / truncated / success (T,) bool
                                                     states       (T+1, C)   float64

The packed arrays (``(T, A)`` float64 actions, ``(K, C)`` float64 checkpoint states) are
lossless: see :mod:`bigym.demonstrations.packing`; the ``packing`` metadata entry says how
each was packed. Format 1 files, with plain ``actions`` and ``checkpoint_states`` tensors,
stay readable. ``checkpoint_steps[k]`` counts the actions applied before
``checkpoint_states[k]`` was read; the last action always has a checkpoint.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import uuid as _uuid
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import safetensors.numpy

from bigym.demonstrations.atomic import atomic_write
from bigym.demonstrations.errors import DemoCorruptError
from bigym.demonstrations.metadata import Metadata
from bigym.demonstrations.packing import pack_actions, pack_floats, unpack_actions, unpack_floats

DEMO_SUFFIX = ".safetensors"
_DEMO_KEYS = ("actions", "initial_state", "checkpoint_steps", "checkpoint_states")  # format 1
_PACKED_KEYS = ("actions_packed", "initial_state", "checkpoint_steps", "checkpoint_states_packed")


# ---------------------------------------------------------------------- file writing
def safetensors_bytes(tensors: dict[str, np.ndarray], metadata: dict[str, str]) -> bytes:
    """safetensors bytes that depend only on the content: the header's keys are sorted.

    The safetensors library writes its metadata map in hash order, which changes from one
    process to the next; a dataset whose checksums must match on regeneration needs the
    same bytes for the same demo. Only the header is rewritten (sorted keys, padded with
    spaces to 8 bytes as the format asks); the tensor data and their offsets are kept.
    """
    raw = safetensors.numpy.save(tensors, metadata=metadata)
    size = int.from_bytes(raw[:8], "little")
    header = json.loads(raw[8 : 8 + size])
    if "__metadata__" in header:
        header["__metadata__"] = dict(sorted(header["__metadata__"].items()))
    text = json.dumps(header, sort_keys=True, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 8)
    return len(text).to_bytes(8, "little") + text + raw[8 + size :]


# ---------------------------------------------------------------------- file reading
def read_safetensors(data: bytes, source: str) -> tuple[dict[str, np.ndarray], dict[str, str]]:
    """Tensors and metadata from safetensors bytes, with a precise error for damaged files."""
    if len(data) < 8:
        raise DemoCorruptError(f"{source} is truncated or empty ({len(data)} bytes)", source=source)
    header_size = int.from_bytes(data[:8], "little")
    if header_size <= 0 or 8 + header_size > len(data):
        raise DemoCorruptError(
            f"{source} is truncated or not a safetensors file: its header claims {header_size} bytes, "
            f"the file has {len(data)}",
            source=source,
        )
    try:
        header = json.loads(data[8 : 8 + header_size])
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise DemoCorruptError(f"{source} has a corrupt safetensors header: {error}", source=source) from error
    if not isinstance(header, dict):
        raise DemoCorruptError(f"{source} has a corrupt safetensors header", source=source)
    ends = [v["data_offsets"][1] for k, v in header.items() if k != "__metadata__" and isinstance(v, dict)]
    expected = 8 + header_size + max(ends, default=0)
    if expected != len(data):
        raise DemoCorruptError(
            f"{source} is truncated or corrupt: {len(data)} bytes where its header describes {expected}",
            source=source,
        )
    try:
        tensors = safetensors.numpy.load(data)
    except Exception as error:  # safetensors raises its own SafetensorError
        raise DemoCorruptError(f"{source} is corrupt: {error}", source=source) from error
    return tensors, dict(header.get("__metadata__") or {})


def _read_file(path: Path | str) -> bytes:
    try:
        return Path(path).read_bytes()
    except FileNotFoundError:
        raise
    except OSError as error:
        raise DemoCorruptError(f"cannot read {path}: {error}", source=str(path)) from error


def sha256_bytes(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def sha256_file(path: Path | str, chunk: int = 1 << 20) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        while block := handle.read(chunk):
            digest.update(block)
    return digest.hexdigest()


# ---------------------------------------------------------------------- lightweight demo
@dataclass
class Demo:
    """A lightweight demo: actions + initial state + checkpoints + metadata."""

    metadata: Metadata
    actions: np.ndarray
    initial_state: np.ndarray
    checkpoint_steps: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    checkpoint_states: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))

    def __post_init__(self) -> None:
        self.actions = np.ascontiguousarray(self.actions, dtype=np.float64)
        self.initial_state = np.ascontiguousarray(self.initial_state, dtype=np.float64)
        self.checkpoint_steps = np.ascontiguousarray(self.checkpoint_steps, dtype=np.int64)
        self.checkpoint_states = np.ascontiguousarray(self.checkpoint_states, dtype=np.float64)
        if self.actions.ndim != 2:
            raise DemoCorruptError(f"actions must be (steps, action_size), got shape {self.actions.shape}")
        if len(self.checkpoint_steps) != len(self.checkpoint_states):
            raise DemoCorruptError("checkpoint_steps and checkpoint_states differ in length")
        if self.metadata.num_steps is None:
            self.metadata.num_steps = len(self.actions)
        if self.metadata.uuid is None:
            self.metadata.uuid = _uuid.uuid4().hex

    # ------------------------------------------------------------------ info
    @property
    def uuid(self) -> str:
        return self.metadata.uuid

    @property
    def num_steps(self) -> int:
        return len(self.actions)

    def __len__(self) -> int:
        return len(self.actions)

    @property
    def duration(self) -> float:
        """Simulated seconds."""
        return len(self.actions) / float(self.metadata.frequency)

    @property
    def filename(self) -> str:
        return f"{self.uuid}{DEMO_SUFFIX}"

    def replace(self, **changes) -> Demo:
        return dataclasses.replace(self, **changes)

    # ------------------------------------------------------------------ files
    def to_bytes(self) -> bytes:
        actions, actions_packing = pack_actions(self.actions)
        states, states_packing = pack_floats(self.checkpoint_states)
        tensors = {
            "actions_packed": actions,
            "initial_state": self.initial_state,
            "checkpoint_steps": self.checkpoint_steps,
            "checkpoint_states_packed": states,
        }
        self.metadata.num_steps = len(self.actions)
        header = self.metadata.to_header()
        header["packing"] = json.dumps({"actions": actions_packing, "checkpoint_states": states_packing})
        return safetensors_bytes(tensors, header)

    def save(self, path: Path | str) -> Path:
        """Write atomically; a folder gets ``<uuid>.safetensors`` inside it."""
        path = Path(path)
        if path.is_dir() or (not path.suffix and not path.exists()):
            path = path / self.filename
        return atomic_write(path, self.to_bytes())

    @classmethod
    def from_bytes(cls, data: bytes, source: str = "demo") -> Demo:
        tensors, header = read_safetensors(data, source)
        packing = header.pop("packing", None)
        metadata = Metadata.from_header(header, source)
        if packing is None:  # format 1: plain arrays
            missing = [key for key in _DEMO_KEYS if key not in tensors]
            if missing:
                raise DemoCorruptError(f"{source} lacks the tensors {missing}; is it a replayed demo?", source=source)
            return cls(metadata, *(tensors[key] for key in _DEMO_KEYS))
        missing = [key for key in _PACKED_KEYS if key not in tensors]
        if missing:
            raise DemoCorruptError(f"{source} lacks the tensors {missing}", source=source)
        try:
            packing = json.loads(packing)
            actions = unpack_actions(tensors["actions_packed"], packing["actions"])
            states = unpack_floats(tensors["checkpoint_states_packed"], packing["checkpoint_states"], "checkpoints")
        except (json.JSONDecodeError, KeyError, TypeError, ValueError) as error:
            raise DemoCorruptError(f"{source} has unreadable packing metadata: {error}", source=source) from error
        except DemoCorruptError as error:
            raise DemoCorruptError(f"{source}: {error}", source=source) from error
        return cls(metadata, actions, tensors["initial_state"], tensors["checkpoint_steps"], states)

    @classmethod
    def load(cls, path: Path | str) -> Demo:
        return cls.from_bytes(_read_file(path), str(path))


# ---------------------------------------------------------------------- replayed demo
@dataclass
class ReplayReport:
    """How a replay went: what was checked and how closely it followed the recording."""

    source_uuid: str
    source_frequency: float
    frequency: float
    exact: bool  # same physics as the recording expected (bit-identical checkpoints)
    tolerance: float
    checkpoints_checked: int = 0
    max_divergence: float = 0.0
    max_divergence_step: int | None = None
    first_success_step: int | None = None
    final_success: bool = False
    converted: str | None = None  # e.g. "500hz->50hz" or "absolute->delta"
    replayed_steps: int = 0  # control steps replayed and checked: the whole recording
    episode_steps: int = 0  # of those, the episode returned: up to its first terminal step

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> ReplayReport:
        known = {f.name for f in dataclasses.fields(cls)}
        return cls(**{k: v for k, v in data.items() if k in known})


@dataclass
class ReplayedDemo:
    """A demo replayed into observations: step ``t`` pairs ``observations[t]`` with ``actions[t]``.

    ``observations`` hold ``T + 1`` entries (the reset observation first); ``rewards``,
    ``terminated``, ``truncated`` and ``success`` describe the result of action ``t``.
    The episode ends at its first terminal step: only the last step can be ``terminated``
    or ``truncated``, as in an env rollout (what the recording holds beyond it was replayed
    and checked, see ``report.replayed_steps``, but is not part of the episode).
    """

    metadata: Metadata
    observations: dict[str, np.ndarray]
    actions: np.ndarray
    rewards: np.ndarray
    terminated: np.ndarray
    truncated: np.ndarray
    success: np.ndarray
    states: np.ndarray
    report: ReplayReport

    def __len__(self) -> int:
        return len(self.actions)

    @property
    def uuid(self) -> str:
        return self.metadata.uuid

    def timesteps(self) -> Iterator[tuple[dict, np.ndarray, float, bool, bool, dict, dict]]:
        """``(obs, action, reward, terminated, truncated, info, next_obs)`` per step."""
        for t in range(len(self.actions)):
            obs = {k: v[t] for k, v in self.observations.items()}
            next_obs = {k: v[t + 1] for k, v in self.observations.items()}
            info = {"is_success": bool(self.success[t])}
            yield (
                obs,
                self.actions[t],
                float(self.rewards[t]),
                bool(self.terminated[t]),
                bool(self.truncated[t]),
                info,
                next_obs,
            )

    def to_bytes(self) -> bytes:
        tensors = {f"obs.{key}": np.ascontiguousarray(value) for key, value in self.observations.items()}
        tensors.update(
            actions=np.ascontiguousarray(self.actions, np.float64),
            rewards=np.ascontiguousarray(self.rewards, np.float64),
            terminated=np.ascontiguousarray(self.terminated, bool),
            truncated=np.ascontiguousarray(self.truncated, bool),
            success=np.ascontiguousarray(self.success, bool),
            states=np.ascontiguousarray(self.states, np.float64),
        )
        header = self.metadata.to_header()
        header["replay"] = json.dumps(self.report.to_dict())
        return safetensors_bytes(tensors, header)

    def save(self, path: Path | str) -> Path:
        return atomic_write(Path(path), self.to_bytes())

    @classmethod
    def from_bytes(cls, data: bytes, source: str = "replayed demo") -> ReplayedDemo:
        tensors, header = read_safetensors(data, source)
        if "replay" not in header:
            raise DemoCorruptError(f"{source} is not a replayed demo (no replay report)", source=source)
        report = ReplayReport.from_dict(json.loads(header.pop("replay")))
        metadata = Metadata.from_header(header, source)
        needed = ("actions", "rewards", "terminated", "truncated", "success", "states")
        missing = [key for key in needed if key not in tensors]
        if missing:
            raise DemoCorruptError(f"{source} lacks the tensors {missing}", source=source)
        observations = {key[4:]: value for key, value in tensors.items() if key.startswith("obs.")}
        return cls(metadata, observations, *(tensors[key] for key in needed), report)

    @classmethod
    def load(cls, path: Path | str) -> ReplayedDemo:
        return cls.from_bytes(_read_file(path), str(path))
