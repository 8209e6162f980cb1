"""Offscreen camera rendering built for CPU (software OpenGL) speed, and the human viewer.

Rules from DESIGN.md: no shadows, no reflections, no multisampling, low-poly visual
meshes, and one render plus one ``mjr_readPixels`` (RGB and depth together) per camera.
The scene geometry is gathered once per frame and only the camera changes between
the cameras of one observation.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

import mujoco
import numpy as np

from bigym.gl_context import OffscreenGL
from bigym.observations import CameraConfig


class CameraRenderer:
    """Renders a fixed set of model cameras into RGB (3, H, W) uint8 and metric depth (H, W)."""

    def __init__(
        self, model: mujoco.MjModel, cameras: Sequence[CameraConfig], shadows: bool = False, skybox: bool = False
    ) -> None:
        self._model = model
        self._cameras = tuple(cameras)
        width = max(c.resolution[1] for c in self._cameras)
        height = max(c.resolution[0] for c in self._cameras)
        # The offscreen buffer must hold the largest image; this touches only visual settings.
        model.vis.global_.offwidth = max(model.vis.global_.offwidth, width)
        model.vis.global_.offheight = max(model.vis.global_.offheight, height)
        self._gl = OffscreenGL(model, width, height)
        self._scene = mujoco.MjvScene(model, maxgeom=max(1000, 2 * model.ngeom))
        self._scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = shadows
        self._scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = False
        self._scene.flags[mujoco.mjtRndFlag.mjRND_SKYBOX] = skybox
        self._option = mujoco.MjvOption()
        self._option.sitegroup[:] = 0  # sites are markers for code, not for the cameras
        self._perturb = mujoco.MjvPerturb()
        self._mjv_cameras = []
        self._buffers = []
        for config in self._cameras:
            camera = mujoco.MjvCamera()
            camera.type = mujoco.mjtCamera.mjCAMERA_FIXED
            camera.fixedcamid = model.camera(config.name).id
            self._mjv_cameras.append(camera)
            h, w = config.resolution
            rgb = np.empty((h, w, 3), np.uint8) if config.rgb else None
            depth = np.empty((h, w), np.float32) if config.depth else None
            self._buffers.append((mujoco.MjrRect(0, 0, w, h), rgb, depth))
        extent = model.stat.extent
        self._near = model.vis.map.znear * extent
        self._far = model.vis.map.zfar * extent

    def render(self, data: mujoco.MjData, out: dict[str, np.ndarray]) -> None:
        """Render every camera into ``out`` as ``rgb_<name>`` / ``depth_<name>`` (fresh arrays)."""
        context = self._gl.make_current()
        model, scene = self._model, self._scene
        for index, (config, camera, (viewport, rgb, depth)) in enumerate(
            zip(self._cameras, self._mjv_cameras, self._buffers)
        ):
            if index == 0:
                # mjv_updateScene places infinite planes (the floor) around the scene's
                # camera *before* it moves that camera to this one: without this line the
                # floor sits where the previous frame's last camera was, and an image
                # depends on what was rendered before it (a reused env's first frame after
                # reset differed from a fresh env's by up to 6 levels of RGB).
                mujoco.mjv_updateCamera(model, data, camera, scene)
                mujoco.mjv_updateScene(
                    model, data, self._option, self._perturb, camera, mujoco.mjtCatBit.mjCAT_ALL, scene
                )
            else:
                mujoco.mjv_updateCamera(model, data, camera, scene)
            mujoco.mjr_render(viewport, scene, context)
            mujoco.mjr_readPixels(rgb, depth, viewport, context)
            if rgb is not None:
                out[f"rgb_{config.name}"] = np.ascontiguousarray(rgb[::-1].transpose(2, 0, 1))
            if depth is not None:
                out[f"depth_{config.name}"] = self._metric_depth(depth[::-1])

    def _metric_depth(self, zbuffer: np.ndarray) -> np.ndarray:
        """Convert the [0, 1] OpenGL depth buffer to distance along the view axis in metres."""
        near, far = self._near, self._far
        return (near / (1.0 - zbuffer * (1.0 - near / far))).astype(np.float32)

    def close(self) -> None:
        """Release the GL resources now (idempotent); dropping the renderer does the same."""
        self._gl.close()


class ClosedRenderer:
    """Stands in for a closed env's camera renderer: observing after ``close()`` is an error,
    not an observation that silently lacks its images."""

    def render(self, data: mujoco.MjData, out: dict[str, np.ndarray]) -> None:
        raise RuntimeError("this env is closed and its cameras are released; create a new env")

    def close(self) -> None:
        pass


class HumanViewer:
    """MuJoCo's interactive viewer, or a clear error where there is no display."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")) and os.name != "nt":
            raise RuntimeError(
                'render_mode="human" needs a display, and neither DISPLAY nor WAYLAND_DISPLAY is set. '
                'Use render_mode="rgb_array" (e.g. `bigym run TASK --video out.mp4`) on a headless machine.'
            )
        import mujoco.viewer

        self._handle = mujoco.viewer.launch_passive(model, data)

    def sync(self) -> None:
        self._handle.sync()

    def close(self) -> None:
        self._handle.close()
