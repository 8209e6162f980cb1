"""Scene: a named list of prop placements that populates a world spec."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np

from bigym.props.base import ArticulatedProp, Prop, quat_yaw

__all__ = ["Placement", "Scene"]


@dataclass(frozen=True)
class Placement:
    """Where one prop goes.

    ``pos`` and ``yaw`` (degrees, about z) are in the world frame, or in the frame of
    the parent site when ``parent = (prop_name, site_key)`` names a site of a prop
    placed earlier (the child then rides on that site's body, e.g. a cutlery tray in
    a drawer). ``quat`` (w, x, y, z), when given, replaces ``yaw``.
    """

    name: str
    cls: type[Prop]
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    yaw: float = 0.0
    kwargs: Mapping[str, Any] = field(default_factory=dict)
    parent: tuple[str, str] | None = None
    quat: tuple[float, float, float, float] | None = None

    def orientation(self) -> np.ndarray:
        if self.quat is not None:
            q = np.asarray(self.quat, float)
            return q / np.linalg.norm(q)
        return quat_yaw(np.deg2rad(self.yaw))


class Scene:
    """A kitchen layout.

    ``populate(spec)`` builds every prop and attaches it to ``spec.worldbody`` (or to
    its parent site); ``bind(model, data)`` binds them all after compiling. Props are
    available by name from the dict ``populate`` returns and from ``scene.props``.
    """

    def __init__(self, name: str, placements: Iterable[Placement], description: str = ""):
        self.name = name
        self.placements: tuple[Placement, ...] = tuple(placements)
        self.description = description
        names = [p.name for p in self.placements]
        if len(set(names)) != len(names):
            raise ValueError(f"scene {name!r}: duplicate prop names")
        self.props: dict[str, Prop] = {}

    def populate(self, spec: mujoco.MjSpec, seed: int | None = None) -> dict[str, Prop]:
        """Build the props (``seed`` varies their sizes/colours; ``None`` = nominal) and
        attach them into ``spec``. Returns ``{prop name: Prop}``."""
        seeds: list[int | None]
        if seed is None:
            seeds = [None] * len(self.placements)
        else:
            seeds = [int(s.generate_state(1)[0]) for s in np.random.SeedSequence(seed).spawn(len(self.placements))]
        props: dict[str, Prop] = {}
        for pl, s in zip(self.placements, seeds, strict=True):
            prop = pl.cls(pl.name, s, **dict(pl.kwargs))
            if pl.parent is None:
                parent: Any = spec.worldbody
            else:
                pname, key = pl.parent
                if pname not in props:
                    raise KeyError(f"scene {self.name!r}: parent prop {pname!r} must be placed before {pl.name!r}")
                parent = props[pname].spec_site(key)
            prop.attach_to(parent, pl.pos, pl.orientation())
            props[pl.name] = prop
        self.props = props
        return props

    def bind(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        for p in self.props.values():
            p.bind(model, data)

    @property
    def articulated(self) -> dict[str, ArticulatedProp]:
        return {k: p for k, p in self.props.items() if isinstance(p, ArticulatedProp)}

    @property
    def free_props(self) -> dict[str, Prop]:
        return {k: p for k, p in self.props.items() if p.free}

    def __repr__(self) -> str:
        return f"Scene({self.name!r}, {len(self.placements)} props)"
