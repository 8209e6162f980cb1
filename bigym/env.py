"""BiGymEnv: the Gymnasium step/reset loop shared by every task.

A task subclasses :class:`BiGymEnv` and fills in a few hooks: build its props into the
spec, bind ids after compiling, randomise on reset, and say when it has succeeded or
failed. The loop itself does no name look-ups and builds no static data per step.
"""

from __future__ import annotations

import hashlib
import math
import numbers
from typing import Any, ClassVar

import gymnasium as gym
import mujoco
import numpy as np

from bigym.action_modes import ActionMode, JointPositionActionMode
from bigym.contacts import ContactState
from bigym.hotloop import AVAILABLE as HOTLOOP_AVAILABLE
from bigym.hotloop import STEP_INVALID, STEP_UNSTABLE, STEP_UNSUPPORTED, CompiledControlStep
from bigym.layout import Layout
from bigym.observations import ObservationConfig, ProprioceptionReader
from bigym.rendering import CameraRenderer, ClosedRenderer, HumanViewer
from bigym.robot.h1 import build_robot
from bigym.robot.robot import Robot
from bigym.visual_merge import merge_visual_geoms
from bigym.world import TIMESTEP, add_world

PHYSICS_FREQUENCY = round(1.0 / TIMESTEP)  # 500 Hz
MIN_CONTROL_FREQUENCY, MAX_CONTROL_FREQUENCY = 20, 500
# MuJoCo's warnings: each means the simulation can no longer be trusted.
_INSTABILITY_WARNINGS = {
    mujoco.mjtWarning.mjWARN_INERTIA: "bad inertia",
    mujoco.mjtWarning.mjWARN_CONTACTFULL: "contact buffer full",
    mujoco.mjtWarning.mjWARN_CNSTRFULL: "constraint buffer full",
    mujoco.mjtWarning.mjWARN_BADQPOS: "bad qpos (NaN, inf or huge)",
    mujoco.mjtWarning.mjWARN_BADQVEL: "bad qvel (NaN, inf or huge)",
    mujoco.mjtWarning.mjWARN_BADQACC: "bad qacc (NaN, inf or huge)",
    mujoco.mjtWarning.mjWARN_BADCTRL: "bad ctrl (NaN or inf)",
}


class BiGymEnv(gym.Env):
    """A BiGym task: H1 with two grippers in a scene, sparse reward 1.0 on success."""

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["human", "rgb_array"], "render_fps": 50}

    # Task settings, overridden by subclasses.
    time_limit: ClassVar[float] = 20.0  # seconds of simulated time per episode
    robot_start: ClassVar[tuple[float, float, float]] = (0.0, 0.0, 0.0)  # x, y, yaw
    workspace_radius: ClassVar[float] = 5.0  # leaving this disc around the start is a failure
    robot_start_noise: ClassVar[tuple[float, float, float]] = (0.0, 0.0, 0.0)  # +- x, y, yaw at reset

    def __init__(
        self,
        action_mode: ActionMode | None = None,
        observation_config: ObservationConfig | None = None,
        render_mode: str | None = None,
        control_frequency: float = 50,
        render_resolution: tuple[int, int] = (480, 640),
    ) -> None:
        super().__init__()
        # Constructor arguments that select a task variant (e.g. which hand); subclasses set them.
        self.task_kwargs: dict[str, Any] = getattr(self, "task_kwargs", {})
        self.action_mode = action_mode if action_mode is not None else JointPositionActionMode()
        if not isinstance(self.action_mode, ActionMode):
            raise TypeError(f"action_mode must be an ActionMode, got {type(self.action_mode).__name__}")
        self.observation_config = observation_config if observation_config is not None else ObservationConfig()
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode {render_mode!r} not in {self.metadata['render_modes']}")
        # numbers.Real also admits numpy scalars (np.int64(50) from a config or an array).
        if not (
            isinstance(control_frequency, numbers.Real)
            and MIN_CONTROL_FREQUENCY <= control_frequency <= MAX_CONTROL_FREQUENCY
        ):
            raise ValueError(
                f"control_frequency must be within [{MIN_CONTROL_FREQUENCY}, {MAX_CONTROL_FREQUENCY}] Hz, "
                f"got {control_frequency!r}"
            )
        control_frequency = float(control_frequency)
        self.render_mode = render_mode
        self.substeps = round(PHYSICS_FREQUENCY / control_frequency)
        # The rate actually run: 500 Hz divided by a whole number of physics steps.
        self.control_frequency = PHYSICS_FREQUENCY / self.substeps
        self.metadata = {**self.metadata, "render_fps": self.control_frequency}
        self.max_episode_steps = math.ceil(self.time_limit * self.control_frequency)

        spec, description = build_robot(self.action_mode.robot_config())
        add_world(spec)
        self.props: dict = {}  # named objects of the task (filled by _build_scene)
        self._build_scene(spec)
        self.mj_spec = spec
        merge_visual_geoms(spec, skip_subtrees=(description.pelvis_body,))  # fewer draw calls; physics unchanged
        self.model = spec.compile()
        self._place_cameras(self.model)
        self.data = mujoco.MjData(self.model)
        self.robot = Robot(self.model, description)
        self._controller = self.action_mode.controller(self.robot, self.substeps)
        self.contacts = ContactState(self.model, self.data)  # tasks register their geom sets in _bind
        self._bind(self.model, self.data)

        self.action_space = gym.spaces.Box(self._controller.low, self._controller.high, dtype=np.float32)
        self._proprioception = (
            ProprioceptionReader(self.model, self.robot) if self.observation_config.proprioception else None
        )
        self.observation_space = self._make_observation_space()
        self._renderer: CameraRenderer | ClosedRenderer | None = (
            CameraRenderer(self.model, self.observation_config.cameras) if self.observation_config.cameras else None
        )
        self._render_resolution = render_resolution
        self._external_renderer: CameraRenderer | None = None
        self._viewer: HumanViewer | None = None

        # Hot-loop state: cached views and index arrays. Views of MjData's arrays stay valid for
        # the env's life: reset (mj_resetData) and state copies write into the same memory.
        self._ctrl = self.data.ctrl[: self.robot.num_actuators]
        # Below 500 Hz a servo target moves to its new value in equal parts over the control
        # step's physics steps instead of jumping at its start (see step()); torques are held.
        self._ramp_fractions = (np.arange(1, self.substeps) / self.substeps)[:, None]
        self._held = self._controller.torque if self._controller.torque.any() else None
        self._warning_counts = self.data.warning.number
        # The same control step in C where bigym was built with its extension (bigym.hotloop).
        self._compiled_step = (
            CompiledControlStep(
                self._controller, self.model, self.data, self._ctrl, self.substeps, self._held,
                self._ramp_fractions, self._warning_counts,
            )
            if HOTLOOP_AVAILABLE
            else None
        )  # fmt: skip
        self._pelvis_xy = self.data.xpos[self.robot.pelvis_id, :2]
        self._privileged = self.observation_config.privileged_information
        self._human_view = render_mode == "human"
        self._elapsed_steps = 0
        self._unstable_reason: str | None = None
        self._last_obs: dict[str, np.ndarray] | None = None

    def _place_cameras(self, model: mujoco.MjModel) -> None:
        """Apply the ``pos``/``quat`` of the observation config's cameras (in the parent frame)."""
        for camera in self.observation_config.cameras:
            camera_id = model.camera(camera.name).id
            if camera.pos is not None:
                model.cam_pos[camera_id] = camera.pos
            if camera.quat is not None:
                model.cam_quat[camera_id] = camera.quat

    # ------------------------------------------------------------------ task hooks
    def _build_scene(self, spec: mujoco.MjSpec) -> None:
        """Add the task's props to ``spec`` (before compiling)."""

    def _bind(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Resolve the task's ids and index arrays once, after compiling."""

    def _on_reset(self) -> None:
        """Randomise the task with ``self.np_random`` (robot already at its start pose)."""

    def _success(self) -> bool:
        return False

    def _failure(self) -> bool:
        """The episode can no longer succeed; by default: the robot left the workspace."""
        x, y = self._pelvis_xy.tolist()  # Python floats: scalar arithmetic without numpy overhead
        dx, dy = x - self.robot_start[0], y - self.robot_start[1]
        return dx * dx + dy * dy > self.workspace_radius**2

    def _privileged_spaces(self) -> dict[str, gym.spaces.Box]:
        return {}

    def _privileged_observation(self, obs: dict[str, np.ndarray]) -> None:
        """Add task state (object poses, joint states) to ``obs``."""

    def state_digest(self) -> str:
        """A short sha256 of the full simulator state (positions, velocities, controls,
        mocap, time): after ``reset(seed)`` it names the seed's scene, exactly."""
        spec = mujoco.mjtState.mjSTATE_INTEGRATION
        state = np.empty(mujoco.mj_stateSize(self.model, spec))
        mujoco.mj_getState(self.model, self.data, state, spec)
        return hashlib.sha256(state.tobytes()).hexdigest()[:16]

    # ------------------------------------------------------------------ layouts
    @property
    def action_layout(self) -> Layout:
        """Name, index, bounds and unit of every action entry."""
        return self._controller.layout

    @property
    def observation_layout(self) -> Layout:
        """Name and index of every entry of the ``proprioception`` vector."""
        if self._proprioception is None:
            raise AttributeError("proprioception is disabled in this env's ObservationConfig")
        return self._proprioception.layout

    @property
    def task_name(self) -> str:
        return type(self).__name__

    # ------------------------------------------------------------------ spaces
    def _make_observation_space(self) -> gym.spaces.Dict:
        spaces: dict[str, gym.spaces.Space] = {}
        if self._proprioception is not None:
            spaces.update(self._proprioception.spaces)
        for camera in self.observation_config.cameras:
            h, w = camera.resolution
            if camera.rgb:
                spaces[f"rgb_{camera.name}"] = gym.spaces.Box(0, 255, (3, h, w), np.uint8)
            if camera.depth:
                spaces[f"depth_{camera.name}"] = gym.spaces.Box(0.0, np.inf, (h, w), np.float32)
        if self.observation_config.privileged_information:
            spaces.update(self._privileged_spaces())
        return gym.spaces.Dict(spaces)

    def _observe(self) -> dict[str, np.ndarray]:
        obs: dict[str, np.ndarray] = {}
        if self._proprioception is not None:
            self._proprioception.read(self.data, obs)
        if self._renderer is not None:
            self.robot.pose_legs(self.model, self.data)
            self._renderer.render(self.data, obs)
        if self._privileged:
            self._privileged_observation(obs)
        return obs

    # ------------------------------------------------------------------ gym API
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        model, data = self.model, self.data
        mujoco.mj_resetData(model, data)
        start = np.array(self.robot_start) + self.np_random.uniform(-1.0, 1.0, 3) * self.robot_start_noise
        self.robot.reset(model, data, start[:2], start[2])
        mujoco.mj_kinematics(model, data)
        self._on_reset()
        mujoco.mj_forward(model, data)
        self._elapsed_steps = 0
        self._unstable_reason = None
        obs = self._observe()
        self._last_obs = obs
        self.contacts.hold()
        try:
            success = self._success()
        finally:
            self.contacts.release()
        return obs, {"is_success": success}

    def step(self, action):
        if self._unstable_reason is not None:
            # The physics blew up last step: nothing more happens until reset().
            info = {"is_success": False, "unstable": self._unstable_reason}
            return self._last_obs, 0.0, False, True, info
        controller = self._controller
        compiled = self._compiled_step
        if compiled is not None:
            code = compiled.step(action)
            if code == STEP_UNSUPPORTED:  # not a float32/float64 vector: convert (or explain) in Python
                code = compiled.step(np.ascontiguousarray(controller.validate(action)))
            if code == STEP_INVALID:
                controller.validate(action)  # raises, naming every offending entry
                raise RuntimeError("the compiled step path refused an action that Python accepts")
            self._elapsed_steps += 1
            if code == STEP_UNSTABLE:
                return self._unstable_step()
            return self._finish_step()
        action = controller.validate(action)
        model, data, ctrl = self.model, self.data, self._ctrl
        # mj_step2 then mj_step1 per physics step: the same physics as mj_step, bit for bit,
        # but it ends with positions, contacts and sensors computed for the *new* state, so
        # observations, images and success all describe the state the step returns.
        step1, step2 = mujoco.mj_step1, mujoco.mj_step2
        if self.substeps == 1:
            controller.apply(ctrl, action)
        else:
            # Ramp each servo target from its last value to the new one: step k of n sets
            # start + k/n * (end - start), the last exactly end. A 50 Hz action is then the ten
            # 500 Hz actions it stands for, and the floating base has no step jolt (a held
            # target jumps the base servo's error by the whole step: 20-70 m/s^2 at 50-20 Hz).
            start = ctrl.copy()
            controller.apply(ctrl, action)
            if self._held is not None:
                start[self._held] = ctrl[self._held]
            ramp = start + self._ramp_fractions * (ctrl - start)
            end = ctrl.copy()
            for targets in ramp:
                ctrl[:] = targets
                step2(model, data)
                step1(model, data)
            ctrl[:] = end
        step2(model, data)
        step1(model, data)
        self._elapsed_steps += 1
        if any(self._warning_counts.tolist()):  # ~10x faster than ndarray.any() on these few ints
            return self._unstable_step()
        return self._finish_step()

    def _finish_step(self):
        """Observe, check success and failure, and say what the step returns."""
        obs = self._observe()
        self._last_obs = obs
        contacts = self.contacts
        contacts.hold()  # the checks below share one reading of the contacts
        try:
            success = self._success()
            terminated = success or self._failure()
        finally:
            contacts.release()
        truncated = self._elapsed_steps >= self.max_episode_steps
        info = {"is_success": success}
        if truncated:
            info["time_limit"] = True
        if self._human_view:
            self.render()
        return obs, 1.0 if success else 0.0, terminated, truncated, info

    def _unstable_step(self):
        counts = self.data.warning.number
        reasons = [text for code, text in _INSTABILITY_WARNINGS.items() if counts[code]]
        self._unstable_reason = f"unstable physics at t={self.data.time:.3f}s: " + ", ".join(reasons)
        # MuJoCo may have reset the state itself: report the last good observation.
        info = {"is_success": False, "unstable": self._unstable_reason}
        return self._last_obs, 0.0, False, True, info

    def render(self):
        if self.render_mode == "rgb_array":
            if self._external_renderer is None:
                from bigym.observations import CameraConfig

                h, w = self._render_resolution
                # The viewing camera shows the sky; observation cameras skip it for speed.
                self._external_renderer = CameraRenderer(
                    self.model, [CameraConfig("external", resolution=(h, w))], skybox=True
                )
            frame: dict[str, np.ndarray] = {}
            self.robot.pose_legs(self.model, self.data)
            self._external_renderer.render(self.data, frame)
            return frame["rgb_external"].transpose(1, 2, 0).copy()
        if self.render_mode == "human":
            if self._viewer is None:
                self._viewer = HumanViewer(self.model, self.data)
            self.robot.pose_legs(self.model, self.data)
            self._viewer.sync()
            return None
        return None

    def close(self) -> None:
        for renderer in (self._renderer, self._external_renderer):
            if renderer is not None:
                renderer.close()
        if self._renderer is not None:
            self._renderer = ClosedRenderer()
        self._external_renderer = None
        if self._viewer is not None:
            self._viewer.close()
            self._viewer = None
        super().close()
