"""The official evaluation protocol: which seeds, how many episodes, at what rate, with what.

A result is comparable with other people's only when it was measured the same way. The
protocol fixes what changes the problem a policy faces, per task:

* the seed block: seeds ``FIRST_SEED, FIRST_SEED + 1, ...`` (:data:`EPISODES` of them),
  far from the seeds the demos were recorded on (the datasets count up from 0), so a
  policy is never evaluated on a scene it was shown;
* the task's own time limit and its default variant (no ``task_kwargs``);
* the control rate, :data:`CONTROL_FREQUENCY` Hz;
* the action mode: position servos with the floating base on x, y, z and yaw (the demos'
  robot), absolute or delta targets as the method prefers;
* the observations: proprioception, the task's privileged state and the three robot
  cameras at 84x84 (RGB and/or depth) in any combination: which inputs a method uses is
  its choice, recorded as its *track*; other cameras, moved cameras or other
  resolutions are not the protocol.

Anything else is still evaluated and reported, marked unofficial with the reasons.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, field
from typing import Any

import mujoco

import bigym
from bigym.action_modes import ActionMode, JointPositionActionMode
from bigym.observations import ObservationConfig
from bigym.robot.h1 import CAMERAS

PROTOCOL = "bigym-eval-1"
#: the first seed of every task's block; the shipped demos use seeds from 0 upward
FIRST_SEED = 1_000_000
#: episodes per official evaluation (as BiGym 2.0; the paper evaluated 50)
EPISODES = 100
CONTROL_FREQUENCY = 50.0
CAMERA_RESOLUTION = (84, 84)  # the paper's default image size


def official_seeds(episodes: int = EPISODES) -> list[int]:
    """The first ``episodes`` seeds of the official block (the same block for every task)."""
    if episodes < 1:
        raise ValueError(f"episodes must be at least 1, got {episodes}")
    return list(range(FIRST_SEED, FIRST_SEED + episodes))


def official_action_mode() -> JointPositionActionMode:
    """The demos' action mode: absolute joint targets, floating base on x, y, z, yaw."""
    return JointPositionActionMode(floating_base=True, absolute=True)


@dataclass(frozen=True)
class Settings:
    """Everything about an evaluation that can change its result, except the policy."""

    task: str
    seeds: tuple[int, ...]
    control_frequency: float = CONTROL_FREQUENCY
    action_mode: ActionMode = field(default_factory=official_action_mode)
    observation_config: ObservationConfig = field(default_factory=ObservationConfig)
    time_limit: float | None = None  # None: the task's own
    task_kwargs: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        seeds = tuple(int(s) for s in self.seeds)
        if not seeds:
            raise ValueError("an evaluation needs at least one seed")
        if len(set(seeds)) != len(seeds):
            raise ValueError("seeds listed twice: every episode must be a different scene")
        if any(s < 0 for s in seeds):
            raise ValueError("seeds must be non-negative integers")
        object.__setattr__(self, "seeds", seeds)
        if self.time_limit is not None and not (math.isfinite(self.time_limit) and self.time_limit > 0):
            raise ValueError(f"time_limit must be a positive number of seconds, got {self.time_limit!r}")


def track(config: ObservationConfig) -> str:
    """The inputs a policy sees, in a word: ``state``, ``pixels``, ``state+pixels`` or
    ``proprioception`` (``state`` = the task's privileged object state)."""
    parts = []
    if config.privileged_information:
        parts.append("state")
    if config.cameras:
        parts.append("pixels")
    return "+".join(parts) or "proprioception"


def unofficial_reasons(settings: Settings, task_time_limit: float) -> list[str]:
    """Why a result measured with ``settings`` is not an official one (empty: it is)."""
    reasons = []
    n = len(settings.seeds)
    if settings.seeds != tuple(official_seeds(n)):
        reasons.append("seeds are not the official block")
    if n != EPISODES:
        reasons.append(f"{n} episodes instead of {EPISODES}")
    if settings.control_frequency != CONTROL_FREQUENCY:
        reasons.append(f"control rate {settings.control_frequency:g} Hz instead of {CONTROL_FREQUENCY:g} Hz")
    if settings.time_limit is not None and settings.time_limit != task_time_limit:
        reasons.append(f"time limit {settings.time_limit:g} s instead of the task's {task_time_limit:g} s")
    if settings.task_kwargs:
        reasons.append(f"task variant {settings.task_kwargs} instead of the default")
    mode = settings.action_mode.to_dict()
    if mode["name"] != "JointPositionActionMode" or not mode["floating_base"]:
        reasons.append(
            f"action mode {mode['name']} (floating base: {mode['floating_base']}) "
            "instead of joint positions with the floating base"
        )
    elif sorted(mode["floating_dofs"]) != sorted(official_action_mode().to_dict()["floating_dofs"]):
        reasons.append(f"floating base on {mode['floating_dofs']} instead of x, y, z and yaw")
    for camera in settings.observation_config.cameras:
        if camera.name not in CAMERAS:
            reasons.append(f"camera {camera.name!r} is not one of the robot's ({', '.join(CAMERAS)})")
        if camera.pos is not None or camera.quat is not None:
            reasons.append(f"camera {camera.name!r} is moved from its mount")
        if tuple(camera.resolution) != CAMERA_RESOLUTION:
            reasons.append(f"camera {camera.name!r} at {camera.resolution[0]}x{camera.resolution[1]} instead of 84x84")
    return reasons


def fingerprint(settings: Settings, env) -> dict[str, Any]:
    """What was evaluated, as JSON: versions, physics, action mode, observations, rate,
    time limit and seeds. Two results are comparable when their fingerprints match."""
    from bigym.demonstrations.metadata import model_fingerprint

    base = env.unwrapped
    return {
        "protocol": PROTOCOL,
        "bigym_version": bigym.__version__,
        "mujoco_version": mujoco.__version__,
        "task": base.task_name,
        "task_kwargs": dict(settings.task_kwargs),
        "model_fingerprint": model_fingerprint(base.model),
        "action_mode": base.action_mode.to_dict(),
        "observation_config": base.observation_config.to_dict(),
        "track": track(base.observation_config),
        "control_frequency": float(base.control_frequency),
        "time_limit": base.max_episode_steps / base.control_frequency,
        "max_episode_steps": int(base.max_episode_steps),
        "episodes": len(settings.seeds),
        "first_seed": settings.seeds[0],
        "seeds_sha256": hashlib.sha256(json.dumps(list(settings.seeds)).encode()).hexdigest(),
    }
