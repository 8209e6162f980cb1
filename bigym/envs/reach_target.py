"""Reach tasks: bring a wrist (or both) within 0.1 m of a target sphere.

Targets are drawn in a region the robot reaches once it moves its base: in front of the
start pose, between knee and head height. The paper's success tolerance is 0.1 m.
"""

from __future__ import annotations

import math
from typing import ClassVar

import gymnasium as gym
import mujoco
import numpy as np

from bigym.env import BiGymEnv
from bigym.robot.h1 import SIDES, WRIST_POINT_RADIUS

SUCCESS_TOLERANCE = 0.1  # metres, wrist site to target centre
TARGET_RADIUS = 0.05
TARGET_COLOURS = {"any": (0.9, 0.15, 0.1, 0.8), "left": (0.15, 0.45, 0.95, 0.8), "right": (0.95, 0.55, 0.1, 0.8)}
# Target regions (x, y, z) low and high, in the frame of the robot's start pose.
REACH_REGION = ((0.35, -0.45, 0.75), (0.8, 0.45, 1.35))
LEFT_REGION = ((0.35, 0.1, 0.75), (0.8, 0.5, 1.35))
RIGHT_REGION = ((0.35, -0.5, 0.75), (0.8, -0.1, 1.35))


class _ReachBase(BiGymEnv):
    """Targets are mocap bodies: their positions are part of the simulation state."""

    time_limit: ClassVar[float] = 10.0
    # Which wrist must reach each target: "left", "right" or "any".
    target_hands: tuple[str, ...] = ("any",)
    target_regions: tuple[tuple[tuple[float, ...], tuple[float, ...]], ...] = (REACH_REGION,)

    def _build_scene(self, spec: mujoco.MjSpec) -> None:
        for index, hand in enumerate(self.target_hands):
            # One distance sensor per wrist allowed to reach this target.
            for side in SIDES if hand == "any" else (hand,):
                spec.add_sensor(
                    name=f"target_{index}_{side}_distance",
                    type=mujoco.mjtSensor.mjSENS_GEOMDIST,
                    objtype=mujoco.mjtObj.mjOBJ_GEOM,
                    objname=f"{side}_wrist_point",
                    reftype=mujoco.mjtObj.mjOBJ_GEOM,
                    refname=f"target_{index}",
                    cutoff=10.0,
                )
            body = spec.worldbody.add_body(name=f"target_{index}", mocap=True, pos=[0.5, 0.0, 1.0])
            body.add_geom(
                name=f"target_{index}",
                type=mujoco.mjtGeom.mjGEOM_SPHERE,
                size=[TARGET_RADIUS, 0, 0],
                rgba=TARGET_COLOURS[hand],
                contype=0,
                conaffinity=0,
                group=1,
            )

    def _bind(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        self._mocap_ids = np.array(
            [model.body_mocapid[model.body(f"target_{i}").id] for i in range(len(self.target_hands))]
        )
        self._regions = np.array(self.target_regions, dtype=float)
        # Sensor readings are surface distances; success compares centre distances.
        sensors = [model.sensor(i) for i in range(model.nsensor) if model.sensor(i).name.startswith("target_")]
        first = sensors[0].adr[0]
        if [s.adr[0] for s in sensors] != list(range(first, first + len(sensors))):
            raise RuntimeError("target distance sensors must be contiguous in sensordata")
        self._distances = slice(first, first + len(sensors))
        # A view: stays valid across resets (MjData's arrays are never reallocated).
        self._distance_values = data.sensordata[self._distances]
        self._reach_threshold = SUCCESS_TOLERANCE - TARGET_RADIUS - WRIST_POINT_RADIUS

    def _on_reset(self) -> None:
        x0, y0, yaw = self.robot_start
        cos, sin = np.cos(yaw), np.sin(yaw)
        for mocap, (low, high) in zip(self._mocap_ids, self._regions):
            local = self.np_random.uniform(low, high)
            self.data.mocap_pos[mocap] = [x0 + cos * local[0] - sin * local[1], y0 + sin * local[0] + cos * local[1], local[2]]

    @property
    def target_positions(self) -> np.ndarray:
        """(n_targets, 3) world positions of the targets."""
        return self.data.mocap_pos[self._mocap_ids]

    def _success(self) -> bool:
        # Either one target that any listed wrist may reach, or one target per wrist.
        # Python floats: min/max of a few values without numpy's reduction overhead; a NaN
        # fails, as it did with ndarray.min/max.
        distances = self._distance_values.tolist()
        if any(map(math.isnan, distances)):
            return False
        if len(self.target_hands) == 1:
            return min(distances) <= self._reach_threshold
        return max(distances) <= self._reach_threshold

    def _privileged_spaces(self) -> dict[str, gym.spaces.Box]:
        return {
            name: gym.spaces.Box(-np.inf, np.inf, (3,), np.float32) for name in self._privileged_names()
        }

    def _privileged_names(self) -> list[str]:
        if len(self.target_hands) == 1:
            return ["target_position"]
        return [f"target_position_{hand}" for hand in self.target_hands]

    def _privileged_observation(self, obs: dict[str, np.ndarray]) -> None:
        for name, position in zip(self._privileged_names(), self.data.mocap_pos[self._mocap_ids]):
            obs[name] = position.astype(np.float32)


class ReachTargetMultiModal(_ReachBase):
    """Reach the target with either wrist."""


class ReachTargetSingle(_ReachBase):
    """Reach the target with one named wrist (``hand``, the left by default as in the paper)."""

    def __init__(self, *args, hand: str = "left", **kwargs) -> None:
        if hand not in ("left", "right"):
            raise ValueError(f"hand must be 'left' or 'right', got {hand!r}")
        self.task_kwargs = {"hand": hand}  # recorded in demo metadata, so replays rebuild this variant
        self.target_hands = (hand,)
        self.target_regions = (LEFT_REGION if hand == "left" else RIGHT_REGION,)
        super().__init__(*args, **kwargs)


class ReachTargetDual(_ReachBase):
    """Reach one target with each wrist at the same time."""

    target_hands = ("left", "right")
    target_regions = (LEFT_REGION, RIGHT_REGION)


ReachTarget = ReachTargetMultiModal
