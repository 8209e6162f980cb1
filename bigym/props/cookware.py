"""Cookware: frying pan, saucepan, spatula, sandwich, chopping board.

Origins at the centre of the base, up along ``+z`` (the sandwich: at its centre).
Pan and saucepan handles point along local ``+x``; the spatula lies along ``+y``
(blade at ``+y``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .base import Colors, Prop, quat_axis_angle

__all__ = ["ChoppingBoard", "FryingPan", "Sandwich", "Saucepan", "Spatula"]

_PAN = (0.18, 0.18, 0.19, 1.0)


class _Pot(Prop):
    """A round pot: lathe visual, bottom disc + 12 wall boxes + handle box colliders."""

    FREE = True
    RADIUS = 0.1
    DEPTH = 0.05
    HANDLE = 0.2
    #: the wall's thickness (m), and how far (m) it flares out from the bottom to the rim
    WALL = 0.004
    FLARE = 0.0
    COLOR: tuple[float, float, float, float] = _PAN

    def __init__(
        self, name: str, seed: int | None = None, *, free: bool | None = None, rgba: Sequence[float] | None = None
    ):
        super().__init__(name, seed, free=free)
        self.radius = self._vary(self.RADIUS, 0.03)
        self.rgba = rgba or self._color(self.COLOR, 0.03)

    def _pot(self, spec, root, part: str, handle_z: float, handle_rgba) -> None:
        R, D, t, flare = self.radius, self.DEPTH, self.WALL, self.FLARE
        Rt = R + flare
        self._lathe(
            spec, root, [(0, 0), (R, 0), (Rt, D), (Rt - t, D), (R - t, 0.005), (0, 0.005)], self.rgba, segments=32
        )
        self._cyl(root, part, R - 0.004, 0.0025, (0, 0, 0.0025), kind="collision")
        self._ring(root, part, R - t / 2, t, 0.0, D, n=12, flare=flare, kind="collision")
        x0 = Rt - 0.004
        x1 = Rt + self.HANDLE
        tilt = 0.18
        L = x1 - x0
        c = (x0 + 0.5 * L * np.cos(tilt), 0.0, handle_z + 0.5 * L * np.sin(tilt))
        self._box(root, part, (0.5 * L, 0.012, 0.008), c, quat=quat_axis_angle((0, 1, 0), -tilt), rgba=handle_rgba)
        self._site(root, "handle", (x0 + 0.7 * L * np.cos(tilt), 0.0, handle_z + 0.7 * L * np.sin(tilt)))
        self._site(root, "center", (0, 0, 0.005))


class FryingPan(_Pot):
    """Frying pan: 0.228 m across (collider r 0.112), 0.045 m deep, handle out to
    ~0.33 m along +x; 0.5 kg (free). Part ``pan``; sites ``handle``, ``center``."""

    MASS = 0.5
    RADIUS = 0.1
    DEPTH = 0.045
    HANDLE = 0.2
    FLARE = 0.012

    def _build(self, spec, root) -> None:
        self._pot(spec, root, "pan", self.DEPTH - 0.01, Colors.BLACK)


class Saucepan(_Pot):
    """Saucepan: 0.134 m across, 0.077 m deep, handle out to ~0.23 m along +x; 0.3 kg
    (free). Part ``saucepan``; sites ``handle``, ``center``."""

    MASS = 0.3
    RADIUS = 0.067
    DEPTH = 0.077
    HANDLE = 0.16
    COLOR = Colors.STEEL

    def _build(self, spec, root) -> None:
        self._pot(spec, root, "saucepan", self.DEPTH - 0.012, Colors.BLACK)


class Spatula(Prop):
    """Turner 0.265 m along +y (blade 0.05 wide at +y, flat at z = 0), 0.1 kg,
    friction 0.8 with priority 1 (free). Part ``spatula``; sites ``handle``, ``blade``."""

    FREE = True
    MASS = 0.1

    def __init__(
        self, name: str, seed: int | None = None, *, free: bool | None = None, rgba: Sequence[float] | None = None
    ):
        super().__init__(name, seed, free=free)
        self.rgba = rgba or self._color(Colors.BLACK, 0.05)

    def _build(self, spec, root) -> None:
        fr = (0.8, 0.005, 0.0001)
        kw = {"friction": fr, "priority": 1}
        L = 0.265
        yb0, yb1 = L / 2 - 0.09, L / 2
        self._box(root, "spatula", (0.025, 0.045, 0.0015), (0, 0.5 * (yb0 + yb1), 0.0015), rgba=Colors.STEEL, **kw)
        # neck rising from the blade to the handle
        ang = 0.5
        nl = 0.05
        c = (0, yb0 - 0.5 * nl * np.cos(ang), 0.0015 + 0.5 * nl * np.sin(ang))
        self._box(
            root, "spatula", (0.006, 0.5 * nl, 0.002), c, quat=quat_axis_angle((1, 0, 0), -ang), rgba=Colors.STEEL, **kw
        )
        yh1 = yb0 - nl * np.cos(ang)
        zh = 0.0015 + nl * np.sin(ang)
        self._box(
            root, "spatula", (0.011, 0.5 * (yh1 + L / 2), 0.008), (0, 0.5 * (yh1 - L / 2), zh), rgba=self.rgba, **kw
        )
        self._site(root, "handle", (0, 0.5 * (yh1 - L / 2), zh))
        self._site(root, "blade", (0, 0.5 * (yb0 + yb1), 0.003))


class Sandwich(Prop):
    """Sandwich 0.123 x 0.127 x 0.038 m, 0.1 kg, friction 0.3 with priority 1 (free).
    Origin at its centre. ``toasted`` browns the bread; ``rounded`` replaces the box
    collider by a box with capsule edges (easier to flip). Part ``sandwich``."""

    FREE = True
    MASS = 0.1
    SIZE = (0.123, 0.127, 0.038)

    def __init__(
        self,
        name: str,
        seed: int | None = None,
        *,
        free: bool | None = None,
        toasted: bool = False,
        rounded: bool = False,
    ):
        super().__init__(name, seed, free=free)
        self.toasted = toasted
        self.rounded = rounded
        self.bread = self._color((0.72, 0.45, 0.20, 1.0) if toasted else (0.93, 0.84, 0.62, 1.0), 0.03)
        self.crust = self._color((0.45, 0.25, 0.10, 1.0) if toasted else (0.70, 0.48, 0.25, 1.0), 0.03)

    def _build(self, spec, root) -> None:
        sx, sy, sz = (s / 2 for s in self.SIZE)
        kw = {"friction": (0.3, 0.005, 0.0001), "priority": 1}
        layers = [
            (0.012, self.bread, 0.0),
            (0.004, (0.30, 0.65, 0.20, 1.0), 0.004),
            (0.006, (0.90, 0.55, 0.55, 1.0), -0.004),
            (0.004, (0.98, 0.80, 0.25, 1.0), 0.002),
            (0.012, self.bread, 0.0),
        ]
        z = -sz
        for h, c, grow in layers:
            self._box(
                root, None, (sx - 0.003 + grow, sy - 0.003 + grow, h / 2), (0, 0, z + h / 2), rgba=c, kind="visual"
            )
            if c is self.bread:
                self._box(root, None, (sx, sy, h / 2 - 0.001), (0, 0, z + h / 2), rgba=self.crust, kind="visual")
            z += h
        if self.rounded:
            r = sz
            self._box(root, "sandwich", (sx - r, sy - r, sz), kind="collision", **kw)
            for sgn in (-1, 1):
                self._capsule_between(
                    root,
                    "sandwich",
                    (-(sx - r), sgn * (sy - r), 0),
                    (sx - r, sgn * (sy - r), 0),
                    r,
                    kind="collision",
                    **kw,
                )
                self._capsule_between(
                    root,
                    "sandwich",
                    (sgn * (sx - r), -(sy - r), 0),
                    (sgn * (sx - r), sy - r, 0),
                    r,
                    kind="collision",
                    **kw,
                )
        else:
            self._box(root, "sandwich", (sx, sy, sz), kind="collision", **kw)
        self._site(root, "center", (0, 0, 0))


class ChoppingBoard(Prop):
    """Wooden board 0.29 (x) x 0.372 (y) x 0.028 m on two feet, 1 kg (free). Part
    ``board``; site ``top`` (centre of the top face)."""

    FREE = True
    MASS = 1.0

    def __init__(
        self, name: str, seed: int | None = None, *, free: bool | None = None, rgba: Sequence[float] | None = None
    ):
        super().__init__(name, seed, free=free)
        self.rgba = rgba or self._color(Colors.LIGHT_WOOD, 0.05)

    def _build(self, spec, root) -> None:
        hx, hy = 0.145, 0.186
        self._box(root, "board", (hx, hy, 0.01), (0, 0, 0.018), rgba=self.rgba)
        for y in (-hy + 0.04, hy - 0.04):
            self._box(root, "board", (hx - 0.02, 0.015, 0.004), (0, y, 0.004), rgba=Colors.DARK_WOOD)
        self._box(root, None, (0.012, 0.04, 0.0005), (hx - 0.03, 0, 0.028), rgba=Colors.DARK_WOOD, kind="visual")
        self._site(root, "top", (0, 0, 0.028))
