"""Furniture and misc: tables, blocks, a large box, target markers.

Tables have their origin at the floor below the centre of the top, long side along
local ``y``; their back lip (if any) is on the ``+x`` edge (away from a robot at the
origin facing ``+x``).
"""

from __future__ import annotations

from collections.abc import Sequence

from .base import Colors, Prop

__all__ = ["Block", "LargeBox", "SmallTable", "Table", "TargetMarker"]


class Table(Prop):
    """Table 1.2 (y) x 0.6 (x), top surface at 0.95 m, a 6 cm back lip on the +x edge and
    a lower shelf at 0.20-0.24 m (static). Parts: ``top``, ``lip``, ``shelf``, ``legs``.
    Site ``top_center``."""

    WIDTH = 1.2
    DEPTH = 0.6
    HEIGHT = 0.95

    def __init__(
        self,
        name: str,
        seed: int | None = None,
        *,
        lip: bool = True,
        shelf: bool = True,
        rgba: Sequence[float] | None = None,
    ):
        super().__init__(name, seed)
        self.lip, self.shelf = lip, shelf
        self.rgba = rgba or self._color(Colors.WOOD, 0.05)

    def _build(self, spec, root) -> None:
        hx, hy, H = self.DEPTH / 2, self.WIDTH / 2, self.HEIGHT
        c = self.rgba
        self._box_span(root, "top", (-hx, -hy, H - 0.04), (hx, hy, H), rgba=c)
        if self.lip:
            self._box_span(root, "lip", (hx - 0.02, -hy, H), (hx, hy, H + 0.06), rgba=c)
        if self.shelf:
            self._box_span(root, "shelf", (-hx + 0.03, -hy + 0.03, 0.20), (hx - 0.03, hy - 0.03, 0.24), rgba=c)
        for sx in (-1, 1):
            for sy in (-1, 1):
                x, y = sx * (hx - 0.035), sy * (hy - 0.035)
                self._box(root, "legs", (0.02, 0.02, (H - 0.04) / 2), (x, y, (H - 0.04) / 2), rgba=Colors.DARK_WOOD)
        self._site(root, "top_center", (0, 0, H))


class SmallTable(Table):
    """Table 0.8 (y) x 0.6 (x), top at 0.95 m, no lip, with a lower shelf (static)."""

    WIDTH = 0.8

    def __init__(self, name: str, seed: int | None = None, *, lip: bool = False, shelf: bool = True, rgba=None):
        super().__init__(name, seed, lip=lip, shelf=shelf, rgba=rgba)


class Block(Prop):
    """Cube 5 cm, 0.125 kg (free). Part ``block``. Origin at its centre."""

    FREE = True
    MASS = 0.125

    def __init__(
        self,
        name: str,
        seed: int | None = None,
        *,
        free: bool | None = None,
        size: float = 0.05,
        rgba: Sequence[float] | None = None,
    ):
        super().__init__(name, seed, free=free)
        self.size = size
        self.rgba = rgba or self._color(Colors.RED, 0.08)

    def _build(self, spec, root) -> None:
        h = self.size / 2
        self._box(root, "block", (h, h, h), rgba=self.rgba)


class LargeBox(Prop):
    """Cardboard box 0.25 x 0.20 x 0.12 m, 5 kg, friction 1.5 (free). Part ``box``.
    Origin at its centre."""

    FREE = True
    MASS = 5.0
    SIZE = (0.25, 0.20, 0.12)

    def __init__(
        self, name: str, seed: int | None = None, *, free: bool | None = None, rgba: Sequence[float] | None = None
    ):
        super().__init__(name, seed, free=free)
        self.rgba = rgba or self._color(Colors.CARDBOARD, 0.04)

    def _build(self, spec, root) -> None:
        hx, hy, hz = (s / 2 for s in self.SIZE)
        self._box(root, "box", (hx, hy, hz), rgba=self.rgba, friction=(1.5, 0.005, 0.0001))
        tape = (0.80, 0.70, 0.50, 1.0)
        self._box(root, None, (hx + 0.0005, 0.025, hz + 0.0005), rgba=tape, kind="visual")


class TargetMarker(Prop):
    """A target: ``shape="sphere"`` (radius 0.05, red, never collides) or
    ``shape="pad"`` (0.1 x 0.1 x 0.002 green box; collides when ``collide``, part
    ``pad``). Mocap by default so tasks can move it through ``set_pose``."""

    def __init__(
        self,
        name: str,
        seed: int | None = None,
        *,
        shape: str = "sphere",
        size: float | None = None,
        collide: bool | None = None,
        mocap: bool = True,
        rgba: Sequence[float] | None = None,
    ):
        super().__init__(name, seed, mocap=mocap)
        if shape not in ("sphere", "pad"):
            raise ValueError(f"unknown marker shape {shape!r}")
        self.shape = shape
        self.size = size if size is not None else (0.05 if shape == "sphere" else 0.1)
        self.collide = (shape == "pad") if collide is None else collide
        self.rgba = rgba or ((0.8, 0.1, 0.1, 0.6) if shape == "sphere" else (0.1, 0.7, 0.2, 1.0))

    def _build(self, spec, root) -> None:
        kind = "both" if self.collide else "visual"
        part = self.shape if self.collide else None
        if self.shape == "sphere":
            self._sphere(root, part, self.size, rgba=self.rgba, kind=kind)
        else:
            h = self.size / 2
            self._box(root, part, (h, h, 0.001), (0, 0, 0.001), rgba=self.rgba, kind=kind)
        self._site(root, "target", (0, 0, 0))
