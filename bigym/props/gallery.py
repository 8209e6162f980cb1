"""Render every prop and every scene to PNG, plus a labelled contact sheet.

Uses :class:`mujoco.Renderer` (set ``MUJOCO_GL=egl`` for headless rendering) and Pillow
(a dependency of imageio) to write the PNGs.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import mujoco
import numpy as np
from PIL import Image, ImageDraw

from .base import ArticulatedProp, Prop
from .dishwasher import Dishwasher

__all__ = ["render_gallery", "render_prop", "render_scene"]

WIDTH, HEIGHT = 320, 240


def _world() -> mujoco.MjSpec:
    spec = mujoco.MjSpec()
    spec.compiler.degree = False
    spec.option.timestep = 0.002
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    spec.option.impratio = 10
    spec.visual.headlight.ambient = [0.35, 0.35, 0.35]
    spec.visual.headlight.diffuse = [0.45, 0.45, 0.45]
    spec.visual.map.znear = 0.005
    spec.worldbody.add_geom(
        name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 0.05], rgba=[0.62, 0.60, 0.57, 1]
    )
    spec.worldbody.add_light(
        name="sun", pos=[0.5, -1.0, 4.0], dir=[0.0, 0.25, -1.0], diffuse=[0.6, 0.6, 0.6], castshadow=False
    )
    return spec


def _bounds(
    model: mujoco.MjModel, data: mujoco.MjData, geom_ids: Iterable[int], max_group: int = 2
) -> tuple[np.ndarray, np.ndarray]:
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    for g in geom_ids:
        if model.geom_group[g] > max_group or model.geom_type[g] == mujoco.mjtGeom.mjGEOM_PLANE:
            continue
        R = data.geom_xmat[g].reshape(3, 3)
        c = data.geom_xpos[g] + R @ model.geom_aabb[g][:3]
        h = np.abs(R) @ model.geom_aabb[g][3:]
        lo = np.minimum(lo, c - h)
        hi = np.maximum(hi, c + h)
    return lo, hi


def _shoot(
    model: mujoco.MjModel, data: mujoco.MjData, lo, hi, azimuth: float, elevation: float, fill: float
) -> np.ndarray:
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    cam.lookat[:] = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo))
    fovy = np.deg2rad(model.vis.global_.fovy)
    cam.distance = max(radius / np.tan(fovy / 2) * fill, 0.15)
    cam.azimuth = azimuth
    cam.elevation = elevation
    renderer = mujoco.Renderer(model, HEIGHT, WIDTH)
    try:
        renderer.update_scene(data, cam)
        return renderer.render().copy()
    finally:
        renderer.close()


def render_prop(prop: Prop) -> np.ndarray:
    """A 320x240 RGB image of ``prop`` alone on a floor (articulated props part-open)."""
    spec = _world()
    prop.attach_to(spec.worldbody, (0.0, 0.0, 0.0))
    model = spec.compile()
    data = mujoco.MjData(model)
    prop.bind(model, data)
    mujoco.mj_forward(model, data)
    if prop.free:
        lo, _ = _bounds(model, data, prop.collision_geom_ids, max_group=3)
        data.qpos[prop._qadr + 2] -= lo[2]
    if isinstance(prop, ArticulatedProp):
        state = np.full(len(prop.joint_keys), 0.6)
        if isinstance(prop, Dishwasher):
            state = np.array([1.0, 0.7, 0.45])
        prop.set_state(data, state)
    mujoco.mj_forward(model, data)
    lo, hi = _bounds(model, data, prop.geom_ids)
    return _shoot(model, data, lo, hi, azimuth=-35.0, elevation=-28.0, fill=1.05)


def render_scene(name: str) -> np.ndarray:
    """A 320x240 RGB image of layout ``name`` seen from behind the robot's start."""
    from bigym.scenes import make_scene

    spec = _world()
    scene = make_scene(name)
    scene.populate(spec)
    model = spec.compile()
    data = mujoco.MjData(model)
    scene.bind(model, data)
    mujoco.mj_forward(model, data)
    ids = np.concatenate([p.geom_ids for p in scene.props.values()])
    lo, hi = _bounds(model, data, ids)
    lo = np.minimum(lo, [0.0, lo[1], 0.0])  # keep the robot's start in view
    return _shoot(model, data, lo, hi, azimuth=-25.0, elevation=-25.0, fill=0.85)


def _contact_sheet(images: list[tuple[str, np.ndarray]], cols: int = 6) -> Image.Image:
    label_h = 16
    rows = (len(images) + cols - 1) // cols
    sheet = Image.new("RGB", (cols * WIDTH, rows * (HEIGHT + label_h)), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    for k, (label, img) in enumerate(images):
        x, y = (k % cols) * WIDTH, (k // cols) * (HEIGHT + label_h)
        sheet.paste(Image.fromarray(img), (x, y + label_h))
        draw.text((x + 4, y + 2), label, fill=(0, 0, 0))
    return sheet


def render_gallery(out_dir: Path) -> list[Path]:
    """Render every prop class (nominal sizes) and every registered scene to
    ``out_dir/prop_<Class>.png`` and ``out_dir/scene_<name>.png``, plus
    ``out_dir/contact_sheet.png`` tiling them all. Returns the written paths, the contact
    sheet last."""
    from bigym.props import PROP_CLASSES
    from bigym.scenes import scene_names

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    tiles: list[tuple[str, np.ndarray]] = []
    for cls_name, cls in PROP_CLASSES.items():
        img = render_prop(cls(cls_name.lower()))
        path = out / f"prop_{cls_name}.png"
        Image.fromarray(img).save(path)
        written.append(path)
        tiles.append((cls_name, img))
    for name in scene_names():
        img = render_scene(name)
        path = out / f"scene_{name}.png"
        Image.fromarray(img).save(path)
        written.append(path)
        tiles.append((name, img))
    sheet = out / "contact_sheet.png"
    _contact_sheet(tiles).save(sheet)
    written.append(sheet)
    return written
