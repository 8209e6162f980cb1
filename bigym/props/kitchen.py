"""Kitchen modules: base cabinet, wall cabinet, open shelf, counter top, hob.

Local frame of every module: origin at the back-centre on the floor, front facing
``-x``, width along ``y``. Placed at ``(1.2, 0, 0)`` with identity rotation a base
cabinet's front is at ``x = 0.6`` (counter top ``0.86``), like the reference presets
where modules face a robot standing at the origin.

Door naming follows the reference presets, where "left"/"right" are the module's own
sides (it faces the robot): ``door_left`` is hinged on the module's ``-y`` edge (the
robot's right), ``door_right`` on its ``+y`` edge. With this, the presets' neighbouring
doors (e.g. ``counter_base_2``) hinge on their outer edges and open away from each
other instead of clashing.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

from .base import ArticulatedProp, Colors, Prop

__all__ = ["BaseCabinet", "CounterTop", "Hob", "OpenShelf", "WallCabinet"]

_HINGE = mujoco.mjtJoint.mjJNT_HINGE
_SLIDE = mujoco.mjtJoint.mjJNT_SLIDE

#: panel thickness of carcasses
T = 0.018
#: counter top height (top surface) of base modules
COUNTER_TOP = 0.86
COUNTER_THICKNESS = 0.03
#: base cabinet drawer/door slot grid (fronts)
FRONT_Z0 = 0.112
FRONT_Z1 = 0.828
DRAWER_TRAVEL = 0.38
#: wall cabinets
WALL_BOTTOM = 1.45
WALL_SHELF_BOTTOM_TOP = 1.47
WALL_TOP = 2.17
WALL_DEPTH = 0.32


def _build_hob(prop: Prop, body: mujoco.MjsBody, center_x: float, base_z: float, depth: float, width: float) -> None:
    """Black glass slab (part ``hob``) on ``base_z`` with four burners and sites
    ``hob_site_1..4`` (1: front +y, 2: front -y, 3: back +y, 4: back -y)."""
    thick = 0.01
    top = base_z + thick
    prop._box(body, "hob", (depth / 2, width / 2, thick / 2), (center_x, 0.0, base_z + thick / 2), rgba=Colors.BLACK)
    burner = (0.35, 0.12, 0.10, 1.0)
    dx, dy = depth * 0.24, width * 0.24
    spots = [(-dx, dy, 0.085), (-dx, -dy, 0.065), (dx, dy, 0.065), (dx, -dy, 0.085)]
    for k, (ox, oy, r) in enumerate(spots, start=1):
        p = (center_x + ox, oy, top + 0.0005)
        prop._cyl(body, None, r, 0.0005, p, rgba=burner, kind="visual")
        prop._cyl(body, None, r * 0.8, 0.0006, p, rgba=Colors.BLACK, kind="visual")
        prop._site(body, f"hob_site_{k}", (center_x + ox, oy, top))


class BaseCabinet(ArticulatedProp):
    """Floor cabinet 0.6 wide x 0.6 deep with a counter top at 0.86 m.

    Parameters (all keyword):
        walls: carcass (sides, back, plinth, ``shelf_bottom`` whose top is at 0.13).
        counter: the counter top (part ``counter``, top at 0.86, front at x = -0.62).
        shelf: middle shelf (part ``shelf``, top at 0.48).
        hob: glass hob on the counter (part ``hob``, top at 0.87, sites ``hob_site_1..4``).
        panel: a fixed front (part ``panel``).
        door_left / door_right: a full-width hinged door (0..90 deg), hinged on the -y /
            +y edge, vertical bar handle (site ``door_left_handle``/``door_right_handle``)
            at z 0.70 near the free edge.
        big_drawers: 2 flags, drawers spanning two small slots (``drawer_big_1`` bottom).
        small_drawers: 4 flags, ``drawer_small_1`` (bottom) .. ``drawer_small_4`` (top).

    Drawers slide 0..0.38 m towards -x (damping 10, frictionloss 1); each has a site
    named after it at the centre of its inner bottom and a handle site
    ``<drawer>_handle``. Joint (state) order: big drawers, small drawers, door_left,
    door_right (only those enabled). Parts: ``walls``, ``shelf_bottom``, ``counter``,
    ``shelf``, ``hob``, ``panel`` and one per door/drawer (named like its joint).
    """

    WIDTH = 0.6
    DEPTH = 0.6

    def __init__(
        self,
        name: str,
        seed: int | None = None,
        *,
        walls: bool = True,
        counter: bool = True,
        shelf: bool = False,
        hob: bool = False,
        panel: bool = False,
        door_left: bool = False,
        door_right: bool = False,
        big_drawers: Sequence[bool] = (False, False),
        small_drawers: Sequence[bool] = (False, False, False, False),
        front_rgba: Sequence[float] | None = None,
        carcass_rgba: Sequence[float] | None = None,
        counter_rgba: Sequence[float] | None = None,
    ):
        super().__init__(name, seed)
        if len(big_drawers) != 2 or len(small_drawers) != 4:
            raise ValueError("big_drawers needs 2 flags, small_drawers 4")
        self.walls, self.counter, self.shelf, self.hob, self.panel = walls, counter, shelf, hob, panel
        self.door_left, self.door_right = door_left, door_right
        self.big_drawers = tuple(bool(b) for b in big_drawers)
        self.small_drawers = tuple(bool(b) for b in small_drawers)
        self._check_layout()
        self.front_rgba = front_rgba or self._color(Colors.FRONT, 0.05)
        self.carcass_rgba = carcass_rgba or self._color(Colors.CARCASS, 0.03)
        self.counter_rgba = counter_rgba or self._color(Colors.COUNTER, 0.04)

    # slots of the front grid
    @staticmethod
    def _small_slot(k: int) -> tuple[float, float]:
        h = (FRONT_Z1 - FRONT_Z0) / 4.0
        return FRONT_Z0 + k * h, FRONT_Z0 + (k + 1) * h

    @classmethod
    def _big_slot(cls, k: int) -> tuple[float, float]:
        return cls._small_slot(2 * k)[0], cls._small_slot(2 * k + 1)[1]

    def _drawers(self) -> list[tuple[str, float, float]]:
        out = []
        for k, on in enumerate(self.big_drawers):
            if on:
                out.append((f"drawer_big_{k + 1}", *self._big_slot(k)))
        for k, on in enumerate(self.small_drawers):
            if on:
                out.append((f"drawer_small_{k + 1}", *self._small_slot(k)))
        return out

    def _check_layout(self) -> None:
        fronts: list[tuple[str, float, float]] = list(self._drawers())
        for flag, nm in ((self.door_left, "door_left"), (self.door_right, "door_right"), (self.panel, "panel")):
            if flag:
                fronts.append((nm, FRONT_Z0, FRONT_Z1))
        for i, (a, a0, a1) in enumerate(fronts):
            for b, b0, b1 in fronts[i + 1 :]:
                if min(a1, b1) - max(a0, b0) > 1e-6:
                    raise ValueError(f"{self.name}: fronts {a} and {b} overlap")
        if self.shelf:
            for nm, z0, z1 in self._drawers():
                if z0 < 0.48 and z1 - 0.06 > 0.462:
                    raise ValueError(f"{self.name}: shelf collides with {nm}")

    def _build(self, spec: mujoco.MjSpec, root: mujoco.MjsBody) -> None:
        W, D = self.WIDTH, self.DEPTH
        hw = W / 2
        cc = self.carcass_rgba
        ctop = COUNTER_TOP - COUNTER_THICKNESS
        if self.walls:
            for y0, y1 in ((hw - T, hw), (-hw, -hw + T)):
                self._box_span(root, "walls", (-0.58, y0, 0), (0, y1, ctop), rgba=cc)
            self._box_span(root, "walls", (-T, -hw + T, FRONT_Z0), (0, hw - T, ctop), rgba=cc)
            self._box_span(root, "walls", (-0.54, -hw + T, 0), (-T, hw - T, FRONT_Z0), rgba=Colors.DARK_STEEL)
            self._box_span(root, "shelf_bottom", (-0.58, -hw + T, FRONT_Z0), (-T, hw - T, 0.13), rgba=cc)
        if self.counter:
            self._box_span(root, "counter", (-D - 0.02, -hw, ctop), (0, hw, COUNTER_TOP), rgba=self.counter_rgba)
        if self.shelf:
            self._box_span(root, "shelf", (-0.56, -hw + T, 0.462), (-T, hw - T, 0.48), rgba=cc)
        if self.hob:
            _build_hob(self, root, -0.31, COUNTER_TOP, 0.51, 0.58)
        if self.panel:
            self._box_span(
                root,
                "panel",
                (-0.6, -hw + 0.003, FRONT_Z0 + 0.002),
                (-0.58, hw - 0.003, FRONT_Z1 - 0.002),
                rgba=self.front_rgba,
            )
        for nm, z0, z1 in self._drawers():
            self._add_drawer(spec, root, nm, z0, z1, big=nm.startswith("drawer_big"))
        if self.door_left:
            self._add_door(spec, root, "door_left", -1)
        if self.door_right:
            self._add_door(spec, root, "door_right", +1)

    def _add_drawer(self, spec, root, nm: str, z0: float, z1: float, big: bool) -> None:
        hw = self.WIDTH / 2
        b = root.add_body(name=nm)
        self._joint(b, nm, _SLIDE, (-1, 0, 0), (0.0, DRAWER_TRAVEL), damping=10.0, frictionloss=1.0, armature=0.01)
        fr = self.front_rgba
        inner = self.carcass_rgba
        self._box_span(b, nm, (-0.6, -hw + 0.003, z0 + 0.002), (-0.58, hw - 0.003, z1 - 0.002), rgba=fr)
        fz0 = z0 + 0.02
        ftop = z0 + 0.032
        side_top = min(z1 - 0.03, ftop + 0.30)
        x0, x1 = -0.575, -0.06
        yi = 0.27
        self._box_span(b, nm, (x0, -yi, fz0), (x1, yi, ftop), rgba=inner)
        for sgn in (1, -1):
            lo = (x0, yi - 0.012 if sgn > 0 else -yi, ftop)
            hi = (x1, yi if sgn > 0 else -yi + 0.012, side_top)
            self._box_span(b, nm, lo, hi, rgba=inner)
        self._box_span(b, nm, (x1 - 0.012, -yi + 0.012, ftop), (x1, yi - 0.012, side_top), rgba=inner)
        hz = z1 - (0.07 if big else 0.05)  # near the top edge: the lowest stays reachable
        self._handle_bar(b, nm, f"{nm}_handle", (-0.6 - 0.035, 0.0, hz), "y", 0.2, standoff=0.035)
        self._site(b, nm, (0.5 * (x0 + x1), 0.0, ftop))
        self._set_mass(b, 2.5 if big else 1.5)
        spec.add_exclude(bodyname1="root", bodyname2=nm)

    def _add_door(self, spec, root, nm: str, side: int) -> None:
        # side +1: hinge on the +y edge (door_right); -1: on the -y edge (door_left)
        hw = self.WIDTH / 2 - 0.003
        b = root.add_body(name=nm, pos=[-0.6, side * hw, 0.0])
        self._joint(b, nm, _HINGE, (0, 0, -side), (0.0, np.pi / 2), damping=0.2, frictionloss=0.3, armature=0.01)
        w = 2 * hw
        ylo, yhi = (-w, 0.0) if side > 0 else (0.0, w)
        self._box_span(b, nm, (0.0, ylo, FRONT_Z0 + 0.002), (0.02, yhi, FRONT_Z1 - 0.002), rgba=self.front_rgba)
        hy = -side * (w - 0.05)
        self._handle_bar(b, nm, f"{nm}_handle", (-0.035, hy, 0.70), "z", 0.16, standoff=0.035)
        self._set_mass(b, 3.0)
        spec.add_exclude(bodyname1="root", bodyname2=nm)


class WallCabinet(ArticulatedProp):
    """Wall cabinet 0.6 wide x 0.32 deep, hanging between 1.45 and 2.17 m.

    Parts: ``shelf_bottom`` (top surface at 1.47), ``shelf`` (middle, top at 1.822),
    ``walls``, ``vent`` (optional hood slab under the cabinet), ``door_right``,
    ``door_left``. Two half-width doors (``doors`` opaque or ``glass`` with a
    transparent colliding pane) hinged on the outer edges, 0..90 deg: ``door_left``
    covers the -y half, ``door_right`` the +y half (see the module docstring). Vertical
    handles near the bottom inner corners (sites ``door_left_handle``,
    ``door_right_handle``, z 1.54). Joint order: door_right, door_left. The door fronts
    are at x = -0.34.
    """

    WIDTH = 0.6

    def __init__(
        self,
        name: str,
        seed: int | None = None,
        *,
        doors: bool = True,
        glass: bool = False,
        vent: bool = False,
        front_rgba: Sequence[float] | None = None,
        carcass_rgba: Sequence[float] | None = None,
    ):
        super().__init__(name, seed)
        self.doors = doors or glass
        self.glass = glass
        self.vent = vent
        self.front_rgba = front_rgba or self._color(Colors.FRONT, 0.05)
        self.carcass_rgba = carcass_rgba or self._color(Colors.CARCASS, 0.03)

    def _build(self, spec: mujoco.MjSpec, root: mujoco.MjsBody) -> None:
        hw = self.WIDTH / 2
        D = WALL_DEPTH
        cc = self.carcass_rgba
        for y0, y1 in ((hw - T, hw), (-hw, -hw + T)):
            self._box_span(root, "walls", (-D, y0, WALL_BOTTOM), (0, y1, WALL_TOP), rgba=cc)
        self._box_span(root, "walls", (-T, -hw + T, WALL_SHELF_BOTTOM_TOP), (0, hw - T, WALL_TOP - T), rgba=cc)
        self._box_span(root, "walls", (-D, -hw + T, WALL_TOP - T), (0, hw - T, WALL_TOP), rgba=cc)
        self._box_span(root, "shelf_bottom", (-D, -hw + T, WALL_BOTTOM), (-T, hw - T, WALL_SHELF_BOTTOM_TOP), rgba=cc)
        st = WALL_SHELF_BOTTOM_TOP + 0.352
        self._box_span(root, "shelf", (-D + 0.01, -hw + T, st - T), (-T, hw - T, st), rgba=cc)
        if self.vent:
            self._box_span(root, "vent", (-0.40, -hw + 0.01, 1.39), (-0.02, hw - 0.01, WALL_BOTTOM), rgba=Colors.STEEL)
            self._box_span(
                root,
                None,
                (-0.38, -hw + 0.05, 1.3895),
                (-0.06, hw - 0.05, 1.3905),
                rgba=Colors.DARK_STEEL,
                kind="visual",
            )
        if self.doors:
            self._add_door(spec, root, "door_right", +1)
            self._add_door(spec, root, "door_left", -1)

    def _add_door(self, spec, root, nm: str, side: int) -> None:
        hw = self.WIDTH / 2 - 0.0015
        w = hw - 0.0015
        b = root.add_body(name=nm, pos=[-WALL_DEPTH - 0.02, side * hw, 0.0])
        self._joint(b, nm, _HINGE, (0, 0, -side), (0.0, np.pi / 2), damping=0.1, frictionloss=0.15, armature=0.005)
        ylo, yhi = (-w, 0.0) if side > 0 else (0.0, w)
        z0, z1 = WALL_BOTTOM + 0.002, WALL_TOP - 0.002
        if self.glass:
            f = 0.05
            fr = self.front_rgba
            self._box_span(b, nm, (0.0, ylo, z0), (0.02, yhi, z0 + f), rgba=fr)
            self._box_span(b, nm, (0.0, ylo, z1 - f), (0.02, yhi, z1), rgba=fr)
            self._box_span(b, nm, (0.0, ylo, z0 + f), (0.02, ylo + f, z1 - f), rgba=fr)
            self._box_span(b, nm, (0.0, yhi - f, z0 + f), (0.02, yhi, z1 - f), rgba=fr)
            self._box_span(b, nm, (0.007, ylo + f, z0 + f), (0.013, yhi - f, z1 - f), rgba=Colors.GLASS)
        else:
            self._box_span(b, nm, (0.0, ylo, z0), (0.02, yhi, z1), rgba=self.front_rgba)
        hy = -side * (w - 0.04)
        self._handle_bar(b, nm, f"{nm}_handle", (-0.035, hy, WALL_BOTTOM + 0.09), "z", 0.12, standoff=0.035)
        self._set_mass(b, 1.5)
        spec.add_exclude(bodyname1="root", bodyname2=nm)


class OpenShelf(Prop):
    """Open wall shelf 0.6 x 0.32: a board (part ``shelf``, top at 1.47) with a back
    panel (part ``walls``) and two brackets."""

    WIDTH = 0.6

    def __init__(self, name: str, seed: int | None = None, *, rgba: Sequence[float] | None = None):
        super().__init__(name, seed)
        self.rgba = rgba or self._color(Colors.LIGHT_WOOD, 0.05)

    def _build(self, spec: mujoco.MjSpec, root: mujoco.MjsBody) -> None:
        hw = self.WIDTH / 2
        self._box_span(root, "shelf", (-WALL_DEPTH, -hw, WALL_BOTTOM), (0, hw, WALL_SHELF_BOTTOM_TOP), rgba=self.rgba)
        self._box_span(root, "walls", (-0.012, -hw, WALL_SHELF_BOTTOM_TOP), (0, hw, 1.90), rgba=self.rgba)
        for y in (-hw + 0.06, hw - 0.06):
            self._box_span(
                root,
                None,
                (-0.2, y - 0.01, WALL_BOTTOM - 0.12),
                (0, y + 0.01, WALL_BOTTOM),
                rgba=Colors.DARK_STEEL,
                kind="visual",
            )
        self._site(root, "shelf_center", (-WALL_DEPTH / 2, 0, WALL_SHELF_BOTTOM_TOP))


class CounterTop(Prop):
    """A counter slab (part ``counter``, top at 0.86 m, x from -0.62 to 0), e.g. over a
    dishwasher; optional ``hob`` like :class:`BaseCabinet`."""

    def __init__(
        self,
        name: str,
        seed: int | None = None,
        *,
        width: float = 0.6,
        depth: float = 0.6,
        hob: bool = False,
        rgba: Sequence[float] | None = None,
    ):
        super().__init__(name, seed)
        self.width, self.depth, self.hob = width, depth, hob
        self.rgba = rgba or self._color(Colors.COUNTER, 0.04)

    def _build(self, spec: mujoco.MjSpec, root: mujoco.MjsBody) -> None:
        hw = self.width / 2
        self._box_span(
            root,
            "counter",
            (-self.depth - 0.02, -hw, COUNTER_TOP - COUNTER_THICKNESS),
            (0, hw, COUNTER_TOP),
            rgba=self.rgba,
        )
        if self.hob:
            _build_hob(self, root, -self.depth / 2 - 0.01, COUNTER_TOP, 0.51, min(0.58, self.width - 0.02))


class Hob(Prop):
    """Stand-alone glass hob (0.51 deep x 0.58 wide x 0.01) to put on any counter.
    Origin at the centre of its bottom face; part ``hob``; sites ``hob_site_1..4``."""

    def __init__(self, name: str, seed: int | None = None):
        super().__init__(name, seed)

    def _build(self, spec: mujoco.MjSpec, root: mujoco.MjsBody) -> None:
        _build_hob(self, root, 0.0, 0.0, 0.51, 0.58)
