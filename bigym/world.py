"""The empty world every task starts from: physics options, floor, light, external camera."""

from __future__ import annotations

import mujoco
import numpy as np

TIMESTEP = 0.002  # 500 Hz physics
EXTERNAL_CAMERA_POS = (-1.3, -2.4, 2.3)
EXTERNAL_CAMERA_TARGET = (0.6, 0.0, 1.0)


def look_at_xyaxes(pos: tuple[float, float, float], target: tuple[float, float, float]) -> list[float]:
    """Camera ``xyaxes`` that look from ``pos`` at ``target`` with world z up."""
    forward = np.asarray(target, float) - np.asarray(pos, float)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    return [*right, *up]


def add_world(spec: mujoco.MjSpec) -> mujoco.MjSpec:
    """Give ``spec`` the shared physics options, a floor, lighting and the ``external`` camera."""
    spec.compiler.autolimits = True
    spec.option.timestep = TIMESTEP
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.impratio = 10.0
    # Observation cameras render without multisampling (DESIGN.md: rendering rules).
    spec.visual.quality.offsamples = 0
    spec.visual.headlight.ambient = [0.35, 0.35, 0.35]
    spec.visual.headlight.diffuse = [0.5, 0.5, 0.5]
    spec.visual.map.znear = 0.01

    spec.add_texture(
        name="sky",
        type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT,
        rgb1=[0.85, 0.88, 0.92],
        rgb2=[0.45, 0.5, 0.55],
        width=64,
        height=64,
    )
    floor_texture = spec.add_texture(
        name="floor_tiles",
        type=mujoco.mjtTexture.mjTEXTURE_2D,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
        rgb1=[0.62, 0.6, 0.56],
        rgb2=[0.52, 0.5, 0.46],
        width=256,
        height=256,
    )
    floor_material = spec.add_material(name="floor", texrepeat=[8, 8], reflectance=0.0)
    floor_material.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = floor_texture.name
    spec.worldbody.add_geom(
        name="floor",
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[0.0, 0.0, 0.05],
        material="floor",
    )
    spec.worldbody.add_light(
        name="sun",
        pos=[0.5, -1.0, 4.0],
        dir=[0.0, 0.25, -1.0],
        diffuse=[0.6, 0.6, 0.6],
        castshadow=False,
    )
    spec.worldbody.add_camera(
        name="external",
        pos=list(EXTERNAL_CAMERA_POS),
        xyaxes=look_at_xyaxes(EXTERNAL_CAMERA_POS, EXTERNAL_CAMERA_TARGET),
        fovy=50.0,
    )
    return spec
