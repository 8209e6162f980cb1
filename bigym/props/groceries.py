"""Groceries: bottles, cans, jars, boxes and a bag (all free, origin at the centre of
the base, up along ``+z``). Each has one collision part named ``item`` and a site
``grasp`` at a good grasp height."""

from __future__ import annotations

from collections.abc import Sequence

from .base import Colors, Prop

__all__ = [
    "GROCERY_CLASSES",
    "Beer",
    "Cereals",
    "Crisps",
    "Detergent",
    "Jar",
    "Ketchup",
    "Mustard",
    "Soap",
    "Soda",
    "SoupCan",
    "Wine",
]


class _Grocery(Prop):
    FREE = True
    COLOR: tuple[float, float, float, float] = Colors.RED

    def __init__(
        self, name: str, seed: int | None = None, *, free: bool | None = None, rgba: Sequence[float] | None = None
    ):
        super().__init__(name, seed, free=free)
        self.scale = self._vary(1.0, 0.04)
        self.rgba = rgba or self._color(self.COLOR, 0.05)


class _Bottle(_Grocery):
    """Round bottle: body radius ``R`` up to ``H1``, shoulder to ``H2`` and a neck of
    radius ``r`` up to ``H``; visual lathe, two collision cylinders, ballast."""

    R, H1, H2, r, H = 0.035, 0.2, 0.23, 0.013, 0.3
    LABEL: tuple[float, float, float, float] | None = (0.95, 0.92, 0.82, 1.0)
    CAP: tuple[float, float, float, float] = (0.5, 0.05, 0.1, 1.0)
    BALLAST = 0.3

    def _build(self, spec, root) -> None:
        s = self.scale
        R, H1, H2, r, H = self.R, self.H1 * s, self.H2 * s, self.r, self.H * s
        self._lathe(
            spec, root, [(0, 0), (R - 0.003, 0), (R, 0.004), (R, H1), (r, H2), (r, H - 0.02), (0, H - 0.02)], self.rgba
        )
        self._cyl(root, None, r + 0.0012, 0.01, (0, 0, H - 0.01), rgba=self.CAP, kind="visual")
        if self.LABEL is not None:
            self._cyl(root, None, R + 0.0008, 0.3 * H1, (0, 0, 0.5 * H1), rgba=self.LABEL, kind="visual")
        self._cyl(root, "item", R, 0.5 * H1, (0, 0, 0.5 * H1), kind="collision")
        zc = 0.5 * (H1 + H)
        self._cyl(root, "item", r + 0.002, 0.5 * (H - H1), (0, 0, zc), kind="collision")
        self._ballast(root, (0, 0, 0.02), self.BALLAST * self.MASS)
        self._site(root, "grasp", (0, 0, 0.6 * H1))


class Wine(_Bottle):
    """Wine bottle, 0.30 m, 0.9 kg."""

    MASS = 0.9
    COLOR = (0.10, 0.25, 0.12, 1.0)


class Beer(_Bottle):
    """Beer bottle, 0.23 m, 0.45 kg."""

    MASS = 0.45
    COLOR = (0.40, 0.20, 0.06, 1.0)
    R, H1, H2, r, H = 0.031, 0.13, 0.17, 0.012, 0.23
    CAP = (0.85, 0.75, 0.2, 1.0)


class Ketchup(_Bottle):
    """Ketchup squeeze bottle, 0.151 m, 0.35 kg."""

    MASS = 0.35
    COLOR = (0.75, 0.08, 0.05, 1.0)
    R, H1, H2, r, H = 0.03, 0.115, 0.125, 0.018, 0.151
    CAP = (0.95, 0.95, 0.95, 1.0)
    BALLAST = 0.2


class Mustard(_Bottle):
    """Mustard squeeze bottle, 0.152 m, 0.3 kg."""

    MASS = 0.3
    COLOR = (0.93, 0.78, 0.10, 1.0)
    R, H1, H2, r, H = 0.028, 0.11, 0.13, 0.012, 0.152
    CAP = (0.9, 0.2, 0.1, 1.0)
    BALLAST = 0.2


class Soap(_Bottle):
    """Liquid soap pump bottle, 0.162 m, 0.3 kg."""

    MASS = 0.3
    COLOR = (0.55, 0.80, 0.85, 1.0)
    R, H1, H2, r, H = 0.033, 0.11, 0.125, 0.011, 0.162
    CAP = (0.95, 0.95, 0.95, 1.0)
    LABEL = None
    BALLAST = 0.2


class _Can(_Grocery):
    R, H = 0.033, 0.115
    LABEL: tuple[float, float, float, float] | None = None
    LID: tuple[float, float, float, float] = Colors.STEEL

    def _build(self, spec, root) -> None:
        R, H = self.R, self.H * self.scale
        self._lathe(
            spec,
            root,
            [(0, 0.002), (R - 0.004, 0), (R, 0.006), (R, H - 0.006), (R - 0.004, H), (0, H - 0.002)],
            self.rgba,
        )
        self._cyl(root, None, R - 0.004, 0.0006, (0, 0, H - 0.0016), rgba=self.LID, kind="visual")
        if self.LABEL is not None:
            self._cyl(root, None, R + 0.0008, 0.3 * H, (0, 0, 0.5 * H), rgba=self.LABEL, kind="visual")
        self._cyl(root, "item", R, 0.5 * H, (0, 0, 0.5 * H), kind="collision")
        self._site(root, "grasp", (0, 0, 0.5 * H))


class Soda(_Can):
    """Soda can, 0.115 m, 0.35 kg."""

    MASS = 0.35
    COLOR = (0.80, 0.08, 0.10, 1.0)


class SoupCan(_Can):
    """Tin of soup, 0.1 m, 0.4 kg."""

    MASS = 0.4
    R, H = 0.038, 0.1
    COLOR = Colors.STEEL
    LABEL = (0.85, 0.20, 0.15, 1.0)


class Jar(_Can):
    """Glass jar with a lid, 0.11 m, 0.45 kg."""

    MASS = 0.45
    R, H = 0.04, 0.11
    COLOR = (0.55, 0.12, 0.25, 1.0)

    def _build(self, spec, root) -> None:
        R, H = self.R, self.H * self.scale
        self._lathe(
            spec,
            root,
            [(0, 0), (R - 0.004, 0), (R, 0.005), (R, H - 0.025), (R - 0.006, H - 0.018), (0, H - 0.018)],
            self.rgba,
        )
        self._cyl(root, None, R - 0.002, 0.009, (0, 0, H - 0.009), rgba=Colors.YELLOW, kind="visual")
        self._cyl(root, "item", R, 0.5 * H, (0, 0, 0.5 * H), kind="collision")
        self._site(root, "grasp", (0, 0, 0.5 * H))


class Cereals(_Grocery):
    """Cereal box 0.07 (x) x 0.19 (y) x 0.238 m, 0.4 kg."""

    MASS = 0.4
    COLOR = (0.92, 0.65, 0.15, 1.0)

    def _build(self, spec, root) -> None:
        hx, hy, hz = 0.035, 0.095, 0.119 * self.scale
        self._box(root, "item", (hx, hy, hz), (0, 0, hz), rgba=self.rgba)
        self._box(
            root,
            None,
            (0.0005, hy * 0.7, hz * 0.45),
            (-hx - 0.0005, 0, hz * 1.1),
            rgba=(0.95, 0.95, 0.9, 1.0),
            kind="visual",
        )
        self._box(
            root,
            None,
            (0.0005, hy * 0.5, hz * 0.2),
            (-hx - 0.0006, 0, hz * 1.2),
            rgba=(0.8, 0.15, 0.1, 1.0),
            kind="visual",
        )
        self._site(root, "grasp", (0, 0, 1.2 * hz))


class Detergent(_Grocery):
    """Detergent jug 0.1 (x) x 0.065 (y) x 0.259 m, 1.0 kg."""

    MASS = 1.0
    COLOR = (0.20, 0.40, 0.85, 1.0)

    def _build(self, spec, root) -> None:
        s = self.scale
        hx, hy, hz = 0.05, 0.0325, 0.11 * s
        self._box(root, "item", (hx, hy, hz), (0, 0, hz), rgba=self.rgba)
        self._cyl(root, "item", 0.018, 0.0195 * s, (0.02, 0, 2 * hz + 0.0195 * s), rgba=(0.95, 0.95, 0.95, 1.0))
        self._box(
            root,
            None,
            (0.0005, hy * 0.75, hz * 0.4),
            (-hx - 0.0005, 0, hz * 0.9),
            rgba=(0.95, 0.9, 0.3, 1.0),
            kind="visual",
        )
        self._ballast(root, (0, 0, 0.02), 0.3)
        self._site(root, "grasp", (0, 0, 1.2 * hz))


class Crisps(_Grocery):
    """Bag of crisps lying flat, 0.17 (x) x 0.24 (y) x 0.04 m, 0.15 kg (a puffy,
    pillow-shaped bag: ellipsoid look, flat collision box)."""

    MASS = 0.15
    COLOR = (0.85, 0.15, 0.45, 1.0)

    def _build(self, spec, root) -> None:
        s = self.scale
        ax, ay, az = 0.085 * s, 0.11 * s, 0.02
        self._ellipsoid(root, None, (ax, ay, az), (0, 0, az), rgba=self.rgba, kind="visual")
        for y in (-ay, ay):
            self._box(root, None, (ax * 0.85, 0.008, 0.002), (0, y * 0.98, az), rgba=self.rgba, kind="visual")
        self._box(root, "item", (ax * 0.75, ay * 0.8, az), (0, 0, az), kind="collision")
        self._site(root, "grasp", (0, 0, az))


GROCERY_CLASSES: tuple[type[Prop], ...] = (
    Wine,
    Beer,
    Soda,
    Ketchup,
    Mustard,
    Cereals,
    Crisps,
    Detergent,
    Soap,
    Jar,
    SoupCan,
)
