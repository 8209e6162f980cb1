"""Tableware: plate, mug, cutlery, dish drainer, cutlery holder, cutlery tray.

Free props have their origin at the centre of their base (cutlery: at mid-length),
with the "up" axis along local ``+z``. Cutlery lies along local ``+y`` (handle at
``-y``, head at ``+y``): ``quat_euler(roll=pi/2)`` stands it head-up.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .base import Colors, Prop

__all__ = ["CutleryHolder", "CutleryTray", "DishDrainer", "Fork", "Knife", "Mug", "Plate", "Spoon"]

_MUG_COLORS = [
    Colors.WHITE,
    (0.85, 0.35, 0.25, 1.0),
    (0.25, 0.45, 0.70, 1.0),
    (0.95, 0.80, 0.35, 1.0),
    (0.35, 0.60, 0.45, 1.0),
]


class Plate(Prop):
    """Dinner plate, 0.228 m across, 0.019 m high, 0.4 kg (free).

    Collision: a base disc and a rim of 12 sloped boxes (part ``plate``); visual: one
    lathe mesh. Sites: ``center`` (top of the well), ``rim`` (on the rim at +x, a grasp
    point).
    """

    FREE = True
    MASS = 0.4

    def __init__(
        self, name: str, seed: int | None = None, *, free: bool | None = None, rgba: Sequence[float] | None = None
    ):
        super().__init__(name, seed, free=free)
        self.radius = self._vary(0.114, 0.02)
        self.height = 0.019
        self.rgba = rgba or self._color(Colors.WHITE, 0.04)

    def _build(self, spec, root) -> None:
        R, H = self.radius, self.height
        self._lathe(
            spec,
            root,
            [
                (0, 0.002),
                (0.055, 0.002),
                (0.062, 0.0),
                (0.07, 0.0),
                (0.076, 0.003),
                (R, H - 0.003),
                (R, H),
                (R - 0.006, H),
                (0.072, 0.007),
                (0, 0.007),
            ],
            self.rgba,
            segments=32,
        )
        self._cyl(root, "plate", 0.074, 0.0035, (0, 0, 0.0035), kind="collision")
        self._ring(root, "plate", 0.074, 0.004, 0.004, H - 0.002, n=12, flare=R - 0.002 - 0.074, kind="collision")
        self._site(root, "center", (0, 0, 0.007))
        self._site(root, "rim", (R - 0.01, 0, H - 0.004))


class Mug(Prop):
    """Mug 0.105 m high, 0.09 m across, handle out to x = 0.084, 0.3 kg (free).

    Collision (part ``mug``): 12 wall boxes, a bottom disc, a 3-capsule handle. Sites:
    ``handle`` (middle of the grip), ``rim`` (+y side of the rim), ``inside`` (inner
    bottom centre).
    """

    FREE = True
    MASS = 0.3

    def __init__(
        self, name: str, seed: int | None = None, *, free: bool | None = None, rgba: Sequence[float] | None = None
    ):
        super().__init__(name, seed, free=free)
        self.radius = self._vary(0.045, 0.04)
        self.height = self._vary(0.105, 0.04)
        self.rgba = rgba or self._color(self._choice(_MUG_COLORS), 0.04)

    def _build(self, spec, root) -> None:
        R, H, t = self.radius, self.height, 0.005
        self._lathe(
            spec, root, [(0, 0), (R - 0.003, 0), (R, 0.003), (R, H), (R - t, H), (R - t, 0.008), (0, 0.008)], self.rgba
        )
        self._ring(root, "mug", R - t / 2, t, 0.0, H, n=12, kind="collision")
        self._cyl(root, "mug", R - t, 0.0035, (0, 0, 0.0045), kind="collision")
        x_in, x_out = R - 0.004, 0.078 + (R - 0.045)
        z_top, z_bot = H - 0.022, 0.028
        hr = 0.006
        self._capsule_between(root, "mug", (x_in, 0, z_top), (x_out, 0, z_top - 0.004), hr, rgba=self.rgba)
        self._capsule_between(root, "mug", (x_out, 0, z_top - 0.004), (x_out, 0, z_bot + 0.004), hr, rgba=self.rgba)
        self._capsule_between(root, "mug", (x_out, 0, z_bot + 0.004), (x_in, 0, z_bot), hr, rgba=self.rgba)
        self._site(root, "handle", (x_out, 0, 0.5 * (z_top + z_bot)))
        self._site(root, "rim", (0, R - t / 2, H))
        self._site(root, "inside", (0, 0, 0.008))


class _Cutlery(Prop):
    FREE = True
    MASS = 0.032
    LENGTH = 0.18

    def __init__(
        self, name: str, seed: int | None = None, *, free: bool | None = None, rgba: Sequence[float] | None = None
    ):
        super().__init__(name, seed, free=free)
        self.length = self._vary(self.LENGTH, 0.03)
        self.rgba = rgba or self._color(Colors.STEEL, 0.03)

    def _handle(self, root, y0: float, y1: float, width: float, thick: float) -> None:
        self._box(root, "cutlery", (width / 2, (y1 - y0) / 2, thick / 2), (0, (y0 + y1) / 2, 0), rgba=self.rgba)
        self._site(root, "handle", (0, y0 + 0.3 * (y1 - y0), 0))


class Fork(_Cutlery):
    """Fork 0.185 m along +y (tines at +y), 32 g. Part ``cutlery``; sites ``handle``,
    ``head``."""

    LENGTH = 0.185

    def _build(self, spec, root) -> None:
        L = self.length
        y_head = L / 2 - 0.07
        self._handle(root, -L / 2, y_head, 0.018, 0.004)
        self._box(root, "cutlery", (0.012, 0.035, 0.0015), (0, y_head + 0.035, 0.0005), kind="collision")
        self._box(root, None, (0.011, 0.0175, 0.0015), (0, y_head + 0.0175, 0.0005), rgba=self.rgba, kind="visual")
        for k in range(4):
            x = -0.009 + 0.006 * k
            self._box(root, None, (0.0012, 0.0175, 0.0012), (x, y_head + 0.0525, 0.0005), rgba=self.rgba, kind="visual")
        self._site(root, "head", (0, y_head + 0.035, 0))


class Knife(_Cutlery):
    """Table knife 0.228 m along +y (blade at +y), 32 g. Part ``cutlery``; sites
    ``handle``, ``head``."""

    LENGTH = 0.228

    def _build(self, spec, root) -> None:
        L = self.length
        y_blade = -L / 2 + 0.1
        self._handle(root, -L / 2, y_blade, 0.02, 0.009)
        self._box(
            root, "cutlery", (0.011, (L / 2 - y_blade) / 2, 0.001), (0.0, (L / 2 + y_blade) / 2, 0.0), rgba=self.rgba
        )
        self._site(root, "head", (0, (L / 2 + y_blade) / 2, 0))


class Spoon(_Cutlery):
    """Spoon 0.176 m along +y (bowl at +y), 32 g. Part ``cutlery``; sites ``handle``,
    ``head``."""

    LENGTH = 0.176

    def _build(self, spec, root) -> None:
        L = self.length
        y_bowl = L / 2 - 0.06
        self._handle(root, -L / 2, y_bowl, 0.016, 0.004)
        self._ellipsoid(root, "cutlery", (0.021, 0.03, 0.006), (0, y_bowl + 0.03, 0.002), rgba=self.rgba)
        self._site(root, "head", (0, y_bowl + 0.03, 0))


class DishDrainer(Prop):
    """Plate rack 0.12 (x) x 0.275 (y) x 0.105 m holding six plates upright in slots
    along y (static unless ``free=True``; 0.6 kg).

    Parts: ``base``, ``holders_front`` (x = -0.05), ``holders_back`` (x = +0.05).
    Sites: ``plate_slot_1..6`` at y = 0.105 .. -0.105 (pitch 0.042), z = 0.15: the centre
    of a plate standing in the slot (face normal along y).
    """

    MASS = 0.6
    PITCH = 0.042

    def __init__(
        self, name: str, seed: int | None = None, *, free: bool | None = None, rgba: Sequence[float] | None = None
    ):
        super().__init__(name, seed, free=free)
        self.rgba = rgba or self._color(Colors.WIRE, 0.05)

    def _build(self, spec, root) -> None:
        c = self.rgba
        fr = (0.6, 0.005, 0.0001)
        self._box(root, "base", (0.06, 0.1375, 0.005), (0, 0, 0.03), rgba=c, friction=fr)
        for x in (-0.05, 0.05):
            self._box(root, "base", (0.008, 0.1375, 0.0125), (x, 0, 0.0125), rgba=Colors.DARK_STEEL, friction=fr)
        for y in (-0.1375, 0.1375):
            self._box(root, "base", (0.06, 0.003, 0.03), (0, y, 0.065), rgba=c, friction=fr)
        for part, x in (("holders_front", -0.05), ("holders_back", 0.05)):
            for k in range(7):
                y = (k - 3) * self.PITCH
                self._box(root, part, (0.003, 0.004, 0.035), (x, y, 0.07), rgba=c, friction=fr)
        for k in range(6):
            self._site(root, f"plate_slot_{k + 1}", (0, 0.105 - k * self.PITCH, 0.15))

    @property
    def slot_keys(self) -> list[str]:
        return [f"plate_slot_{k}" for k in range(1, 7)]


class CutleryHolder(Prop):
    """Round utensil holder (0.1 m across, 0.13 m high, 0.35 kg incl. a heavy base) in
    which cutlery stands upright (free). Part ``holder``; sites ``inside`` (inner bottom
    centre) and ``slot_1..3`` (three spots on the inner bottom)."""

    FREE = True
    MASS = 0.35

    def __init__(
        self, name: str, seed: int | None = None, *, free: bool | None = None, rgba: Sequence[float] | None = None
    ):
        super().__init__(name, seed, free=free)
        self.rgba = rgba or self._color(Colors.DARK_STEEL, 0.05)

    def _build(self, spec, root) -> None:
        R, H, t = 0.05, 0.13, 0.004
        self._lathe(spec, root, [(0, 0), (R, 0), (R, H), (R - t, H), (R - t, 0.012), (0, 0.012)], self.rgba)
        self._ring(root, "holder", R - t / 2, t, 0.0, H, n=12, kind="collision")
        self._cyl(root, "holder", R - t, 0.005, (0, 0, 0.007), kind="collision")
        self._ballast(root, (0, 0, 0.006), 0.15)
        self._site(root, "inside", (0, 0, 0.012))
        for k in range(3):
            a = 2 * np.pi * k / 3
            self._site(root, f"slot_{k + 1}", (0.022 * np.cos(a), 0.022 * np.sin(a), 0.012))


class CutleryTray(Prop):
    """Cutlery organiser: 6 long compartments side by side along y (static unless
    ``free=True``; 0.5 kg). Default size 0.422 (x) x 0.514 (y) x 0.056 (z). Part
    ``tray``; sites ``slot_1..6`` on the compartment floors, slot 1 at +y."""

    MASS = 0.5

    def __init__(
        self,
        name: str,
        seed: int | None = None,
        *,
        free: bool | None = None,
        size: tuple[float, float, float] = (0.422, 0.514, 0.056),
        rgba: Sequence[float] | None = None,
    ):
        super().__init__(name, seed, free=free)
        self.size = tuple(float(s) for s in size)
        self.rgba = rgba or self._color(Colors.LIGHT_WOOD, 0.05)

    def _build(self, spec, root) -> None:
        sx, sy, sz = self.size
        hx, hy = sx / 2, sy / 2
        t, fl = 0.006, 0.005
        c = self.rgba
        self._box_span(root, "tray", (-hx, -hy, 0), (hx, hy, fl), rgba=c)
        self._box_span(root, "tray", (-hx, -hy, fl), (-hx + t, hy, sz), rgba=c)
        self._box_span(root, "tray", (hx - t, -hy, fl), (hx, hy, sz), rgba=c)
        self._box_span(root, "tray", (-hx + t, -hy, fl), (hx - t, -hy + t, sz), rgba=c)
        self._box_span(root, "tray", (-hx + t, hy - t, fl), (hx - t, hy, sz), rgba=c)
        w = (sy - 2 * t) / 6
        for k in range(1, 6):
            y = -hy + t + k * w
            self._box_span(root, "tray", (-hx + t, y - 0.002, fl), (hx - t, y + 0.002, sz - 0.01), rgba=c)
        for k in range(6):
            self._site(root, f"slot_{k + 1}", (0, hy - t - (k + 0.5) * w, fl))

    @property
    def slot_keys(self) -> list[str]:
        return [f"slot_{k}" for k in range(1, 7)]
