"""Kitchen scenes composed from :mod:`bigym.props`.

>>> scene = make_scene("counter_dishwasher")
>>> props = scene.populate(world_spec)      # attaches into the spec
>>> model = world_spec.compile(); data = mujoco.MjData(model)
>>> scene.bind(model, data)
>>> props["dishwasher"].set_state(data, [1.0, 1.0, 0.0])
"""

from __future__ import annotations

from .base import Placement, Scene
from .layouts import SCENES, make_scene, scene_names

__all__ = ["SCENES", "Placement", "Scene", "make_scene", "scene_names"]
