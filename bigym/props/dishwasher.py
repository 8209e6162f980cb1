"""Dishwasher: carcass, bottom-hinged door, two sliding trays, cutlery basket."""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

from .base import ArticulatedProp, Colors

__all__ = ["Dishwasher"]

_HINGE = mujoco.mjtJoint.mjJNT_HINGE
_SLIDE = mujoco.mjtJoint.mjJNT_SLIDE


class Dishwasher(ArticulatedProp):
    """Built-in dishwasher 0.6 wide x 0.58 deep x 0.82 high (local frame: origin at
    the back-centre on the floor, front towards -x; put a :class:`CounterTop` over it).

    State (joint order): ``door`` (hinge at the bottom front edge, 0.22 m above the floor
    over a kick plate; 0 closed .. 1 open = horizontal, its top face then at 0.26 m),
    ``tray_bottom`` (slide 0..0.5 m, floor at 0.33 m), ``tray_mid`` (slide 0..0.45 m,
    floor at 0.60 m).
    The door carries a (cubic) spring that balances its weight over the whole range plus
    1.2 N m of hinge friction, so it holds any position when released.

    Parts: ``body``, ``door``, ``tray_bottom``, ``basket`` (cutlery basket, rides on the
    bottom tray), ``tray_mid``.

    Sites:
      * ``door_handle``, ``tray_bottom_handle``, ``tray_mid_handle``; ``door_edge`` (middle
        of the door's free edge: the open door is easiest to lift there, its handle then
        hangs under it at ~0.19 m);
      * ``plate_slot_{r}_{k}`` (r = 1 front row, 2 back row; k = 1..12 from -y to +y):
        centre of a plate (0.228 m) standing upright in the slot, face normal along y;
      * ``cup_slot_{r}_{k}`` (r = 1, 2; k = 1..12 from +y to -y, 3 cm pitch): on the
        upper tray's floor;
      * ``basket_slot_{k}`` (k = 1..6): floor centres of the basket compartments.
    """

    WIDTH = 0.6
    DEPTH = 0.58
    HEIGHT = 0.82
    DOOR_MASS = 2.5
    DOOR_FRICTION = 1.2
    TRAY_BOTTOM_TRAVEL = 0.5
    TRAY_MID_TRAVEL = 0.45
    #: height of the door hinge (bottom front edge of the door) above the floor
    DOOR_HINGE_Z = 0.22
    #: top surfaces of the tray floors (closed position, local frame)
    TRAY_BOTTOM_Z = 0.33
    TRAY_MID_Z = 0.60
    PLATE_ROWS_X = (-0.405, -0.165)
    CUP_ROWS_X = (-0.41, -0.17)
    N_SLOTS = 12

    def __init__(self, name: str, seed: int | None = None, *, front_rgba: Sequence[float] | None = None):
        super().__init__(name, seed)
        self.front_rgba = front_rgba or self._color(Colors.STEEL, 0.04)
        self._door_joint: mujoco.MjsJoint | None = None
        self._door_body: mujoco.MjsBody | None = None

    def build_spec(self) -> mujoco.MjSpec:
        spec = super().build_spec()
        self._balance_door()
        return spec

    def _balance_door(self) -> None:
        """Give the door hinge a cubic spring that cancels its gravity torque.

        About the hinge the gravity torque is exactly ``G sin(q - phi)`` (``G = m g r``,
        ``phi`` the angle of the centre of mass behind the hinge line); MuJoCo's joint
        spring is ``-(k1 x + k2 x^2 + k3 x^3)`` with ``x = q - springref``, so with
        ``springref = phi`` a least-squares cubic fit of ``sin`` over the range leaves
        a residual of a few mN m, far below the hinge friction.
        """
        recs = [r for r in self._records if r.body is self._door_body and r.geom.mass > 0]
        m = np.array([r.geom.mass for r in recs])
        p = np.array([r.geom.pos for r in recs])
        com = (m[:, None] * p).sum(0) / m.sum()
        r = float(np.hypot(com[0], com[2]))
        G = 9.81 * float(m.sum()) * r
        phi = float(np.arctan2(com[0], com[2]))
        x = np.linspace(0.0, np.pi / 2, 128) - phi
        A = np.stack([x, x**2, x**3], axis=1)
        coef, *_ = np.linalg.lstsq(A, np.sin(x), rcond=None)
        assert self._door_joint is not None
        self._door_joint.stiffness = G * coef
        # a hair of closing preload (0.03 N m) so the shut door rests on its limit
        self._door_joint.springref = phi - 0.03 / (G * coef[0])
        self.door_residual_torque = float(G * np.abs(np.sin(x) - A @ coef).max()) + 0.03

    def _build(self, spec: mujoco.MjSpec, root: mujoco.MjsBody) -> None:
        hw = self.WIDTH / 2
        t = 0.018
        inner = Colors.STEEL
        for y0, y1 in ((hw - t, hw), (-hw, -hw + t)):
            self._box_span(root, "body", (-0.56, y0, 0), (0, y1, self.HEIGHT), rgba=inner)
        self._box_span(root, "body", (-t, -hw + t, 0.1), (0, hw - t, self.HEIGHT), rgba=inner)
        self._box_span(root, "body", (-0.56, -hw + t, self.HEIGHT - 0.02), (-t, hw - t, self.HEIGHT), rgba=inner)
        hz = self.DOOR_HINGE_Z
        self._box_span(root, "body", (-0.56, -hw + t, hz - 0.02), (-t, hw - t, hz), rgba=inner)
        # kick plate under the door, flush with it
        self._box_span(root, "body", (-0.60, -hw + 0.002, 0.0), (-0.56, hw - 0.002, hz - 0.003), rgba=self.front_rgba)
        # rails and sprinkler arms (visual)
        for z in (self.TRAY_BOTTOM_Z - 0.02, self.TRAY_MID_Z - 0.02):
            for y in (hw - t - 0.004, -hw + t + 0.004):
                self._box(root, None, (0.25, 0.004, 0.006), (-0.29, y, z), rgba=Colors.DARK_STEEL, kind="visual")
        self._box(root, None, (0.02, 0.2, 0.006), (-0.29, 0, hz + 0.015), rgba=Colors.DARK_STEEL, kind="visual")
        self._box(
            root, None, (0.02, 0.2, 0.004), (-0.29, 0, self.TRAY_MID_Z - 0.05), rgba=Colors.DARK_STEEL, kind="visual"
        )
        self._add_door(spec, root)
        self._add_tray_bottom(spec, root)
        self._add_tray_mid(spec, root)

    def _add_door(self, spec, root) -> None:
        b = root.add_body(name="door", pos=[-0.60, 0.0, self.DOOR_HINGE_Z])
        self._door_body = b
        self._door_joint = self._joint(
            b, "door", _HINGE, (0, -1, 0), (0.0, np.pi / 2), damping=1.0, frictionloss=self.DOOR_FRICTION, armature=0.02
        )
        hw = self.WIDTH / 2 - 0.002
        top = self.HEIGHT - 0.005 - self.DOOR_HINGE_Z
        self._box_span(b, "door", (0.0, -hw, 0.002), (0.04, hw, top), rgba=self.front_rgba)
        self._box_span(
            b, None, (0.04, -hw + 0.02, 0.02), (0.041, hw - 0.02, top - 0.015), rgba=Colors.STEEL, kind="visual"
        )
        self._box_span(b, None, (-0.001, -hw, top - 0.035), (0.0, hw, top - 0.002), rgba=Colors.BLACK, kind="visual")
        self._handle_bar(b, "door", "door_handle", (-0.035, 0.0, top - 0.08), "y", 0.30, standoff=0.035)
        # the door's free edge: a grasp point to lift the open door (its handle then hangs low)
        self._site(b, "door_edge", (0.02, 0.0, top))
        self._set_mass(b, self.DOOR_MASS)
        spec.add_exclude(bodyname1="root", bodyname2="door")

    def _tray_frame(self, b, part: str, z: float, wall: float) -> None:
        x0, x1, yi = -0.53, -0.04, 0.272
        self._box_span(b, part, (x0, -yi, z - 0.008), (x1, yi, z), rgba=Colors.WIRE)
        self._box_span(b, part, (x0, -yi, z), (x0 + 0.006, yi, z + wall), rgba=Colors.WIRE)
        self._box_span(b, part, (x1 - 0.006, -yi, z), (x1, yi, z + wall), rgba=Colors.WIRE)
        for y0, y1 in ((yi - 0.006, yi), (-yi, -yi + 0.006)):
            self._box_span(b, part, (x0 + 0.006, y0, z), (x1 - 0.006, y1, z + wall), rgba=Colors.WIRE)
        # handle: a bar 2 cm in front of the front rail (clear of the closed door)
        self._handle_bar(
            b,
            part,
            f"{part}_handle",
            (x0 - 0.018, 0.0, z + wall - 0.012),
            "y",
            0.2,
            standoff=0.018,
            bar=0.006,
            rgba=Colors.DARK_STEEL,
        )

    def _add_tray_bottom(self, spec, root) -> None:
        b = root.add_body(name="tray_bottom")
        self._joint(
            b,
            "tray_bottom",
            _SLIDE,
            (-1, 0, 0),
            (0.0, self.TRAY_BOTTOM_TRAVEL),
            damping=5.0,
            frictionloss=1.0,
            armature=0.01,
        )
        z = self.TRAY_BOTTOM_Z
        self._tray_frame(b, "tray_bottom", z, 0.06)
        pitch = 0.03
        ys = -0.255 + pitch * np.arange(self.N_SLOTS)
        for r, x in enumerate(self.PLATE_ROWS_X, start=1):
            for j in range(1, self.N_SLOTS + 1):
                y = -0.27 + pitch * j
                self._box(b, "tray_bottom", (0.05, 0.002, 0.035), (x, y, z + 0.035), rgba=Colors.WIRE)
            for k, y in enumerate(ys, start=1):
                self._site(b, f"plate_slot_{r}_{k}", (x, y, z + 0.116))
        # cutlery basket (2 x 3 compartments) in the front +y corner
        bx0, bx1, by0, by1 = -0.52, -0.36, 0.125, 0.26
        zb, zt = z + 0.01, z + 0.13
        wt = 0.004
        self._box_span(b, "basket", (bx0, by0, z), (bx1, by1, zb), rgba=Colors.DARK_STEEL)
        self._box_span(b, "basket", (bx0, by0, zb), (bx0 + wt, by1, zt), rgba=Colors.DARK_STEEL)
        self._box_span(b, "basket", (bx1 - wt, by0, zb), (bx1, by1, zt), rgba=Colors.DARK_STEEL)
        self._box_span(b, "basket", (bx0 + wt, by0, zb), (bx1 - wt, by0 + wt, zt), rgba=Colors.DARK_STEEL)
        self._box_span(b, "basket", (bx0 + wt, by1 - wt, zb), (bx1 - wt, by1, zt), rgba=Colors.DARK_STEEL)
        xm = 0.5 * (bx0 + bx1)
        self._box_span(
            b, "basket", (xm - wt / 2, by0 + wt, zb), (xm + wt / 2, by1 - wt, zt - 0.02), rgba=Colors.DARK_STEEL
        )
        dy = (by1 - by0) / 3
        for j in (1, 2):
            y = by0 + j * dy
            self._box_span(
                b, "basket", (bx0 + wt, y - wt / 2, zb), (bx1 - wt, y + wt / 2, zt - 0.02), rgba=Colors.DARK_STEEL
            )
        k = 1
        for x in (0.5 * (bx0 + xm), 0.5 * (xm + bx1)):
            for j in range(3):
                self._site(b, f"basket_slot_{k}", (x, by1 - (j + 0.5) * dy, zb))
                k += 1
        self._set_mass(b, 2.5)
        spec.add_exclude(bodyname1="root", bodyname2="tray_bottom")

    def _add_tray_mid(self, spec, root) -> None:
        b = root.add_body(name="tray_mid")
        self._joint(
            b, "tray_mid", _SLIDE, (-1, 0, 0), (0.0, self.TRAY_MID_TRAVEL), damping=5.0, frictionloss=1.0, armature=0.01
        )
        z = self.TRAY_MID_Z
        self._tray_frame(b, "tray_mid", z, 0.045)
        self._box(b, "tray_mid", (0.003, 0.266, 0.012), (-0.29, 0.0, z + 0.012), rgba=Colors.WIRE)
        for r, x in enumerate(self.CUP_ROWS_X, start=1):
            for k in range(1, self.N_SLOTS + 1):
                self._site(b, f"cup_slot_{r}_{k}", (x, 0.165 - 0.03 * (k - 1), z))
        self._set_mass(b, 1.5)
        spec.add_exclude(bodyname1="root", bodyname2="tray_mid")

    # convenience lists of site keys
    @property
    def plate_slot_keys(self) -> list[str]:
        return [f"plate_slot_{r}_{k}" for r in (1, 2) for k in range(1, self.N_SLOTS + 1)]

    @property
    def cup_slot_keys(self) -> list[str]:
        return [f"cup_slot_{r}_{k}" for r in (1, 2) for k in range(1, self.N_SLOTS + 1)]

    @property
    def basket_slot_keys(self) -> list[str]:
        return [f"basket_slot_{k}" for k in range(1, 7)]
