"""Shared base of the procedural prop library.

Every prop is built in code with :class:`mujoco.MjSpec` from primitives and from
convex/lathe meshes generated here with numpy: no asset files.

Conventions
-----------
* A prop is one root body (named ``root``) with an optional subtree. Attached into a
  bigger spec every name gets the prefix ``f"{prop.name}/"``: the root body becomes
  ``"<name>/root"``, a free prop's joint ``"<name>/freejoint"``.
* Geom groups: ``0`` geoms both render and collide, ``2`` geoms only render
  (contype = conaffinity = 0, no mass), ``3`` geoms only collide (hidden by default),
  ``5`` invisible ballast (mass only). In an env, :mod:`bigym.visual_merge` then
  draws each body's visible geoms of one colour as one group-2 mesh: group-0 geoms move to
  group 3 and group-2 ones to the hidden group ``4``.
* Every colliding geom belongs to a named *part* ("counter", "shelf", "hob",
  "tray_bottom", "basket", ...). After :meth:`Prop.bind`, ``prop.part_geom_ids(part)``
  returns the geom ids of that part and ``prop.collision_geom_ids`` those of the whole
  prop, for "object X touches part Y" checks (see :func:`geoms_in_contact`).
* Articulated props expose their joints through a normalised state in ``[0, 1]``
  (0 closed, 1 open); all their joint ranges start at 0 = closed.
* Kitchen modules use a local frame whose origin is the back-centre of the module on
  the floor, with the front facing local ``-x``: placed with identity rotation at
  ``(x_back, y, 0)`` their fronts face a robot standing near the origin facing ``+x``.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import mujoco
import numpy as np

from bigym.geom_groups import GROUP_BALLAST, GROUP_BOTH, GROUP_COLLISION, GROUP_VISUAL

__all__ = [
    "ArticulatedProp",
    "Colors",
    "Prop",
    "geom_mask",
    "geoms_in_contact",
    "lathe_mesh",
    "quat_axis_angle",
    "quat_euler",
    "quat_mul",
    "quat_yaw",
]

Vec3 = Sequence[float] | np.ndarray
Quat = Sequence[float] | np.ndarray

#: contact solref of every colliding prop geom: stiffer than MuJoCo's default (0.02, 1)
#: so that objects dropped a few cm sink < 2 mm on impact; >= 4 timesteps of 2 ms.
SOLREF = (0.008, 1.0)
#: contact solimp of every colliding prop geom: harder than the default (0.9, 0.95, ...)
#: which cuts the slow frictional creep of leaning objects (plates in racks, cutlery in
#: holders) about tenfold, to ~3 um/s.
SOLIMP = (0.99, 0.999, 0.001, 0.5, 2.0)


_G = mujoco.mjtGeom


# --------------------------------------------------------------------------- maths
def quat_axis_angle(axis: Vec3, angle: float) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation by ``angle`` radians about ``axis``."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    h = 0.5 * angle
    return np.concatenate([[np.cos(h)], np.sin(h) * a])


def quat_mul(q1: Quat, q2: Quat) -> np.ndarray:
    """Hamilton product ``q1 * q2`` (apply ``q2`` first, then ``q1``)."""
    out = np.zeros(4)
    mujoco.mju_mulQuat(out, np.asarray(q1, float), np.asarray(q2, float))
    return out


def quat_yaw(angle: float) -> np.ndarray:
    """Rotation about world ``z`` by ``angle`` radians."""
    return quat_axis_angle((0.0, 0.0, 1.0), angle)


def quat_euler(roll: float = 0.0, pitch: float = 0.0, yaw: float = 0.0) -> np.ndarray:
    """Quaternion of extrinsic x-y-z rotations (roll about x first, then pitch about y,
    then yaw about z; radians): ``Rz(yaw) @ Ry(pitch) @ Rx(roll)``."""
    q = quat_axis_angle((1.0, 0.0, 0.0), roll)
    q = quat_mul(quat_axis_angle((0.0, 1.0, 0.0), pitch), q)
    return quat_mul(quat_axis_angle((0.0, 0.0, 1.0), yaw), q)


def lathe_mesh(profile: Sequence[tuple[float, float]], segments: int = 24) -> tuple[np.ndarray, np.ndarray]:
    """Closed surface of revolution about ``z``.

    ``profile`` is a polyline of ``(r, z)`` points that starts and ends on the axis
    (``r == 0``), e.g. a solid bottle ``[(0, 0), (R, 0), (R, h), (r, H), (0, H)]`` or a
    hollow cup ``[(0, 0), (R, 0), (R, H), (R - t, H), (R - t, b), (0, b)]``. Interior
    points must have ``r > 0``. Returns ``(vertices (n, 3), faces (m, 3))`` with faces
    oriented outwards (positive volume), ready for ``MjsMesh.uservert/userface``.
    """
    prof = np.asarray(profile, dtype=float)
    if prof.ndim != 2 or prof.shape[1] != 2 or len(prof) < 3:
        raise ValueError("profile must be a (n >= 3, 2) sequence of (r, z)")
    if prof[0, 0] != 0.0 or prof[-1, 0] != 0.0 or np.any(prof[1:-1, 0] <= 0.0):
        raise ValueError("profile must start and end on the axis and stay off it in between")
    ang = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    c, s = np.cos(ang), np.sin(ang)
    verts: list[np.ndarray] = [np.array([[0.0, 0.0, prof[0, 1]]])]
    rings: list[np.ndarray] = []
    idx = 1
    for r, z in prof[1:-1]:
        verts.append(np.stack([r * c, r * s, np.full(segments, z)], axis=1))
        rings.append(np.arange(idx, idx + segments))
        idx += segments
    top = idx
    verts.append(np.array([[0.0, 0.0, prof[-1, 1]]]))
    faces: list[tuple[int, int, int]] = []
    nxt = np.roll(np.arange(segments), -1)
    first = rings[0]
    for k in range(segments):
        faces.append((0, first[nxt[k]], first[k]))
    for ra, rb in itertools.pairwise(rings):
        for k in range(segments):
            a0, a1, b0, b1 = ra[k], ra[nxt[k]], rb[k], rb[nxt[k]]
            faces.append((a0, a1, b1))
            faces.append((a0, b1, b0))
    last = rings[-1]
    for k in range(segments):
        faces.append((top, last[k], last[nxt[k]]))
    v = np.concatenate(verts)
    f = np.asarray(faces, dtype=np.int64)
    tri = v[f]
    vol = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0
    if vol < 0:
        f = f[:, ::-1].copy()
    return v, f


def _geom_volume(gtype: int, size: np.ndarray) -> float:
    if gtype == _G.mjGEOM_BOX:
        return float(8.0 * size[0] * size[1] * size[2])
    if gtype == _G.mjGEOM_SPHERE:
        return float(4.0 / 3.0 * np.pi * size[0] ** 3)
    if gtype == _G.mjGEOM_CYLINDER:
        return float(np.pi * size[0] ** 2 * 2.0 * size[1])
    if gtype == _G.mjGEOM_CAPSULE:
        return float(np.pi * size[0] ** 2 * 2.0 * size[1] + 4.0 / 3.0 * np.pi * size[0] ** 3)
    if gtype == _G.mjGEOM_ELLIPSOID:
        return float(4.0 / 3.0 * np.pi * size[0] * size[1] * size[2])
    raise ValueError(f"no volume rule for geom type {gtype}")


def geom_mask(model: mujoco.MjModel, geom_ids: Iterable[int]) -> np.ndarray:
    """Boolean mask over all geoms of ``model``, true for ``geom_ids``: precompute it once
    and pass it to :func:`geoms_in_contact` in hot loops (no ``np.isin`` per call)."""
    mask = np.zeros(model.ngeom, dtype=bool)
    mask[np.asarray(list(geom_ids), dtype=np.int64)] = True
    return mask


def geoms_in_contact(data: mujoco.MjData, geoms_a: np.ndarray, geoms_b: np.ndarray, max_dist: float = 0.0) -> bool:
    """True if any active contact joins a geom of ``geoms_a`` and one of ``geoms_b``
    (contact distance ``<= max_dist``). Each argument is an array of geom ids or a
    boolean mask over all geoms (see :func:`geom_mask`, the faster form)."""
    n = data.ncon
    if n == 0:
        return False
    con = data.contact
    g1 = con.geom1[:n]
    g2 = con.geom2[:n]
    ok = con.dist[:n] <= max_dist
    a1, a2 = _member(g1, geoms_a), _member(g2, geoms_a)
    b1, b2 = _member(g1, geoms_b), _member(g2, geoms_b)
    return bool(np.any(((a1 & b2) | (a2 & b1)) & ok))


def _member(ids: np.ndarray, group: np.ndarray) -> np.ndarray:
    if group.dtype == np.bool_:
        return group[ids]
    return np.isin(ids, group)


class Colors:
    """A small shared palette (RGBA)."""

    WHITE = (0.93, 0.93, 0.91, 1.0)
    OFF_WHITE = (0.88, 0.86, 0.82, 1.0)
    CARCASS = (0.86, 0.84, 0.80, 1.0)
    FRONT = (0.55, 0.62, 0.58, 1.0)
    WOOD = (0.62, 0.45, 0.30, 1.0)
    LIGHT_WOOD = (0.78, 0.63, 0.45, 1.0)
    DARK_WOOD = (0.36, 0.24, 0.15, 1.0)
    COUNTER = (0.30, 0.30, 0.32, 1.0)
    STEEL = (0.70, 0.71, 0.73, 1.0)
    DARK_STEEL = (0.35, 0.36, 0.38, 1.0)
    BLACK = (0.08, 0.08, 0.09, 1.0)
    GLASS = (0.75, 0.85, 0.90, 0.25)
    WIRE = (0.80, 0.80, 0.82, 1.0)
    RED = (0.80, 0.12, 0.10, 1.0)
    GREEN = (0.15, 0.65, 0.20, 1.0)
    BLUE = (0.15, 0.30, 0.75, 1.0)
    YELLOW = (0.92, 0.78, 0.12, 1.0)
    CARDBOARD = (0.70, 0.55, 0.36, 1.0)


@dataclass
class _GeomRecord:
    body: mujoco.MjsBody
    geom: mujoco.MjsGeom
    volume: float
    massive: bool


# --------------------------------------------------------------------------- Prop
class Prop:
    """A procedurally built prop.

    Parameters
    ----------
    name:
        Instance name; becomes the name prefix ``f"{name}/"`` in a composed spec.
    seed:
        Seed of the :class:`numpy.random.Generator` that varies sizes and colours within
        plausible bounds. ``None`` gives the nominal prop.
    free:
        Give the root body a free joint. Defaults to the class attribute ``FREE``.
    mocap:
        Make the root body a mocap body (only for non-free props attached to the world).

    Lifecycle: ``attach_to`` (or ``build_spec`` for a standalone spec) → compile the
    spec → ``bind(model, data)`` once → hot-path getters (no name look-ups).
    """

    FREE: ClassVar[bool] = False
    #: nominal mass (kg) of the root body (0: leave the default density; only for
    #: props that are never free and never ride on a moving body)
    MASS: ClassVar[float] = 0.0

    def __init__(
        self, name: str, seed: int | None = None, *, free: bool | None = None, mocap: bool = False, **params: Any
    ):
        if not name or "/" in name:
            raise ValueError(f"invalid prop name {name!r}")
        if params:
            raise TypeError(f"{type(self).__name__} got unexpected parameters: {sorted(params)}")
        self.name = name
        self.seed = seed
        self.rng: np.random.Generator | None = None if seed is None else np.random.default_rng(seed)
        self.free = self.FREE if free is None else bool(free)
        self.mocap = bool(mocap)
        if self.free and self.mocap:
            raise ValueError("a prop cannot be both free and mocap")
        self._spec: mujoco.MjSpec | None = None
        self._attached_body: mujoco.MjsBody | None = None
        self._model: mujoco.MjModel | None = None
        self._reset_registry()

    # ---- variation helpers (call in __init__ of subclasses, never in _build)
    def _vary(self, nominal: float, rel: float = 0.05) -> float:
        """``nominal`` scaled by ``1 + U(-rel, rel)`` when seeded, else ``nominal``."""
        if self.rng is None:
            return float(nominal)
        return float(nominal * (1.0 + self.rng.uniform(-rel, rel)))

    def _color(self, rgba: Sequence[float], jitter: float = 0.06) -> tuple[float, float, float, float]:
        """``rgba`` with its RGB jittered by ``U(-jitter, jitter)`` when seeded."""
        c = np.asarray(rgba, dtype=float).copy()
        if self.rng is not None:
            c[:3] = np.clip(c[:3] + self.rng.uniform(-jitter, jitter, 3), 0.0, 1.0)
        return tuple(float(x) for x in c)  # type: ignore[return-value]

    def _choice(self, options: Sequence[Any]) -> Any:
        if self.rng is None:
            return options[0]
        return options[int(self.rng.integers(len(options)))]

    # ---- registry used while building
    def _reset_registry(self) -> None:
        self._records: list[_GeomRecord] = []
        self._part_geoms: dict[str, list[str]] = {}
        self._site_local: list[str] = []
        self._joint_local: list[str] = []
        self._body_masses: list[tuple[mujoco.MjsBody, float]] = []
        self._mesh_count = 0
        self._geom_count: dict[str, int] = {}

    @property
    def prefix(self) -> str:
        return f"{self.name}/"

    # ---- building
    def build_spec(self) -> mujoco.MjSpec:
        """A fresh standalone spec holding this prop as one root body named ``root``."""
        self._reset_registry()
        spec = mujoco.MjSpec()
        spec.modelname = self.name
        spec.compiler.degree = False  # kept per element when attached into another spec
        root = spec.worldbody.add_body(name="root")
        if self.free:
            root.add_freejoint(name="freejoint")
        if self.mocap:
            root.mocap = True
        self._build(spec, root)
        if self.MASS > 0 and not any(b is root for b, _ in self._body_masses):
            self._set_mass(root, self.MASS)
        self._finalize_masses()
        self._spec = spec
        return spec

    def _build(self, spec: mujoco.MjSpec, root: mujoco.MjsBody) -> None:  # pragma: no cover
        raise NotImplementedError

    def attach_to(
        self,
        parent: mujoco.MjsBody | mujoco.MjsFrame | mujoco.MjsSite,
        pos: Vec3 = (0.0, 0.0, 0.0),
        quat: Quat = (1.0, 0.0, 0.0, 0.0),
    ) -> mujoco.MjsBody:
        """Build the prop and attach it under ``parent`` at ``pos``/``quat`` (relative to
        the parent's frame) with the name prefix ``f"{name}/"``. Free and mocap props
        must go on the world body (or a frame of it). Returns the attached root body."""
        if self.free or self.mocap:
            owner = parent.parent if isinstance(parent, (mujoco.MjsFrame, mujoco.MjsSite)) else parent
            if not isinstance(owner, mujoco.MjsBody) or owner.name != "world":
                kind = "free" if self.free else "mocap"
                raise ValueError(f"{kind} prop {self.name!r} must be attached to the world body")
        spec = self.build_spec()
        root = spec.worldbody.first_body()
        root.pos = np.asarray(pos, dtype=float)
        root.quat = np.asarray(quat, dtype=float)
        if isinstance(parent, mujoco.MjsBody):
            frame = parent.add_frame()
            body = frame.attach_body(root, self.prefix, "")
        elif isinstance(parent, (mujoco.MjsFrame, mujoco.MjsSite)):
            body = parent.attach_body(root, self.prefix, "")
        else:
            raise TypeError(f"cannot attach to {type(parent).__name__}")
        self._attached_body = body
        return body

    def spec_site(self, key: str) -> mujoco.MjsSite:
        """The :class:`mujoco.MjsSite` of site ``key`` in the spec this prop was attached
        to (to attach child props on it, e.g. a cutlery tray in a drawer)."""
        if self._attached_body is None:
            raise RuntimeError(f"prop {self.name!r} is not attached")
        full = self.prefix + key
        for s in self._attached_body.find_all(mujoco.mjtObj.mjOBJ_SITE):
            if s.name == full:
                return s
        raise KeyError(f"prop {self.name!r} has no site {key!r}")

    def _set_mass(self, body: mujoco.MjsBody, mass: float) -> None:
        """Give ``body`` a total mass, spread over its massive geoms by volume."""
        self._body_masses = [(b, m) for b, m in self._body_masses if b is not body]
        self._body_masses.append((body, float(mass)))

    def _finalize_masses(self) -> None:
        for body, mass in self._body_masses:
            recs = [r for r in self._records if r.body is body and r.massive]
            ballast = sum(
                r.geom.mass for r in self._records if r.body is body and not r.massive and r.geom.group == GROUP_BALLAST
            )
            total = sum(r.volume for r in recs)
            if total <= 0 or not recs:
                raise ValueError(f"{self.name}: body has no massive geoms to carry mass")
            rest = mass - ballast
            if rest <= 0:
                raise ValueError(f"{self.name}: ballast exceeds body mass")
            for r in recs:
                r.geom.mass = rest * r.volume / total

    # ---- geom helpers
    def _gname(self, part: str) -> str:
        k = self._geom_count.get(part, 0)
        self._geom_count[part] = k + 1
        return f"{part}_{k}"

    def _geom(
        self,
        body: mujoco.MjsBody,
        part: str | None,
        gtype: int,
        size: Vec3,
        pos: Vec3 = (0.0, 0.0, 0.0),
        quat: Quat | None = None,
        rgba: Sequence[float] = Colors.WHITE,
        kind: str = "both",
        friction: Sequence[float] | None = None,
        condim: int | None = None,
        priority: int | None = None,
        solref: Sequence[float] | None = None,
        fromto: Vec3 | None = None,
    ) -> mujoco.MjsGeom:
        """Add a primitive. ``kind``: "both" (renders and collides, group 0), "visual"
        (group 2, no contact, no mass) or "collision" (group 3, hidden). Colliding geoms
        need a ``part`` name."""
        if kind not in ("both", "visual", "collision"):
            raise ValueError(kind)
        collides = kind != "visual"
        if collides and not part:
            raise ValueError("colliding geoms need a part")
        name = self._gname(part or "visual")
        size_arr = np.zeros(3)
        size_arr[: len(size)] = size
        g = body.add_geom(name=name, type=gtype, size=size_arr, pos=np.asarray(pos, float))
        if quat is not None:
            g.quat = np.asarray(quat, float)
        if fromto is not None:
            g.fromto = np.asarray(fromto, float)
        g.rgba = np.asarray(rgba, float)
        if kind == "both":
            g.group = GROUP_BOTH
        elif kind == "visual":
            g.group = GROUP_VISUAL
            g.contype = 0
            g.conaffinity = 0
            g.density = 0.0
        else:
            g.group = GROUP_COLLISION
            g.rgba = np.array([0.5, 0.5, 0.9, 0.3])
        if friction is not None:
            fr = np.array([1.0, 0.005, 0.0001])
            fr[: len(friction)] = friction
            g.friction = fr
        if condim is not None:
            g.condim = condim
        if priority is not None:
            g.priority = priority
        if collides:
            g.solref = np.asarray(SOLREF if solref is None else solref, float)
            g.solimp = np.asarray(SOLIMP, float)
        if collides:
            self._part_geoms.setdefault(part, []).append(name)  # type: ignore[arg-type]
        vol = 0.0
        if fromto is None and gtype != _G.mjGEOM_MESH:
            vol = _geom_volume(gtype, size_arr)
        self._records.append(_GeomRecord(body, g, vol, massive=collides and vol > 0))
        return g

    def _box(self, body, part, half, pos=(0, 0, 0), **kw) -> mujoco.MjsGeom:
        return self._geom(body, part, _G.mjGEOM_BOX, half, pos, **kw)

    def _box_span(self, body, part, lo: Vec3, hi: Vec3, **kw) -> mujoco.MjsGeom:
        """Axis-aligned box from corner ``lo`` to corner ``hi`` (body frame)."""
        lo_a, hi_a = np.asarray(lo, float), np.asarray(hi, float)
        return self._box(body, part, (hi_a - lo_a) / 2.0, (hi_a + lo_a) / 2.0, **kw)

    def _cyl(self, body, part, radius, half_height, pos=(0, 0, 0), **kw) -> mujoco.MjsGeom:
        return self._geom(body, part, _G.mjGEOM_CYLINDER, (radius, half_height), pos, **kw)

    def _capsule(self, body, part, radius, half_length, pos=(0, 0, 0), **kw) -> mujoco.MjsGeom:
        return self._geom(body, part, _G.mjGEOM_CAPSULE, (radius, half_length), pos, **kw)

    def _capsule_between(self, body, part, p0: Vec3, p1: Vec3, radius: float, **kw) -> mujoco.MjsGeom:
        """Capsule of ``radius`` whose segment runs from ``p0`` to ``p1``."""
        a, b = np.asarray(p0, float), np.asarray(p1, float)
        v = b - a
        length = float(np.linalg.norm(v))
        z = np.array([0.0, 0.0, 1.0])
        axis = np.cross(z, v)
        if np.linalg.norm(axis) < 1e-12:
            q = np.array([1.0, 0, 0, 0]) if v[2] >= 0 else np.array([0.0, 1, 0, 0])
        else:
            q = quat_axis_angle(axis, float(np.arccos(np.clip(v[2] / length, -1, 1))))
        return self._capsule(body, part, radius, length / 2.0, (a + b) / 2.0, quat=q, **kw)

    def _sphere(self, body, part, radius, pos=(0, 0, 0), **kw) -> mujoco.MjsGeom:
        return self._geom(body, part, _G.mjGEOM_SPHERE, (radius,), pos, **kw)

    def _ellipsoid(self, body, part, radii, pos=(0, 0, 0), **kw) -> mujoco.MjsGeom:
        return self._geom(body, part, _G.mjGEOM_ELLIPSOID, radii, pos, **kw)

    def _lathe(
        self,
        spec: mujoco.MjSpec,
        body: mujoco.MjsBody,
        profile: Sequence[tuple[float, float]],
        rgba: Sequence[float],
        pos: Vec3 = (0.0, 0.0, 0.0),
        quat: Quat | None = None,
        segments: int = 24,
    ) -> mujoco.MjsGeom:
        """Visual-only surface of revolution (see :func:`lathe_mesh`)."""
        v, f = lathe_mesh(profile, segments)
        mname = f"mesh_{self._mesh_count}"
        self._mesh_count += 1
        mesh = spec.add_mesh(name=mname)
        mesh.uservert = v.ravel().tolist()
        mesh.userface = f.ravel().tolist()
        g = self._geom(body, None, _G.mjGEOM_MESH, (0, 0, 0), pos, quat=quat, rgba=rgba, kind="visual")
        g.meshname = mname
        return g

    def _ring(
        self,
        body,
        part,
        radius: float,
        thickness: float,
        z0: float,
        z1: float,
        n: int = 12,
        flare: float = 0.0,
        center: Vec3 = (0.0, 0.0),
        overlap: float = 1.08,
        **kw,
    ) -> list[mujoco.MjsGeom]:
        """A cylinder wall of ``n`` boxes: mid-radius ``radius`` at the bottom ``z0``,
        ``radius + flare`` at the top ``z1``, wall ``thickness``."""
        out = []
        height = z1 - z0
        tilt = np.arctan2(flare, height)
        slant = np.hypot(height, flare)
        r_mid = radius + flare / 2.0
        half_w = r_mid * np.tan(np.pi / n) * overlap
        for k in range(n):
            a = 2.0 * np.pi * k / n
            q = quat_mul(quat_yaw(a), quat_axis_angle((0, 1, 0), tilt))
            # lift by the dip of the tilted box's inner corner so the ring spans z0..z1
            zc = (z0 + z1) / 2.0 + 0.5 * thickness * np.sin(abs(tilt))
            p = (center[0] + r_mid * np.cos(a), center[1] + r_mid * np.sin(a), zc)
            out.append(self._box(body, part, (thickness / 2.0, half_w, slant / 2.0), p, quat=q, **kw))
        return out

    def _ballast(self, body: mujoco.MjsBody, pos: Vec3, mass: float) -> mujoco.MjsGeom:
        """Invisible, non-colliding mass (lowers the centre of mass)."""
        g = body.add_geom(
            name=self._gname("ballast"), type=_G.mjGEOM_SPHERE, size=[0.01, 0, 0], pos=np.asarray(pos, float)
        )
        g.contype = 0
        g.conaffinity = 0
        g.group = GROUP_BALLAST
        g.rgba = np.array([0, 0, 0, 0])
        g.mass = float(mass)
        self._records.append(_GeomRecord(body, g, 0.0, massive=False))
        return g

    def _site(
        self, body: mujoco.MjsBody, name: str, pos: Vec3 = (0, 0, 0), quat: Quat | None = None, size: float = 0.01
    ):
        s = body.add_site(name=name, pos=np.asarray(pos, float), size=[size, 0, 0])
        if quat is not None:
            s.quat = np.asarray(quat, float)
        s.rgba = np.array([0.2, 0.8, 0.2, 0.5])
        s.group = 4
        self._site_local.append(name)
        return s

    def _handle_bar(
        self,
        body: mujoco.MjsBody,
        part: str,
        site: str,
        center: Vec3,
        axis: str,
        length: float,
        standoff: float = 0.04,
        bar: float = 0.008,
        rgba: Sequence[float] = Colors.DARK_STEEL,
    ) -> None:
        """A bar handle on a front facing ``-x``: bar of ``length`` along ``axis`` ("y" or
        "z") whose centre is ``center`` (already ``standoff`` in front of the face),
        held by two standoffs, plus a site at the bar centre."""
        cx, cy, cz = center
        if axis == "y":
            half = (bar, length / 2.0, bar)
            ends = [(cx, cy - length / 2.0 + bar, cz), (cx, cy + length / 2.0 - bar, cz)]
        elif axis == "z":
            half = (bar, bar, length / 2.0)
            ends = [(cx, cy, cz - length / 2.0 + bar), (cx, cy, cz + length / 2.0 - bar)]
        else:
            raise ValueError(axis)
        self._box(body, part, half, (cx, cy, cz), rgba=rgba)
        for ex, ey, ez in ends:
            self._box(body, part, (standoff / 2.0, bar * 0.75, bar * 0.75), (ex + standoff / 2.0, ey, ez), rgba=rgba)
        self._site(body, site, (cx, cy, cz))

    def _joint(self, body: mujoco.MjsBody, name: str, jtype: int, axis: Vec3, range_: tuple[float, float], **kw):
        j = body.add_joint(name=name, type=jtype, axis=np.asarray(axis, float))
        j.range = np.asarray(range_, float)
        j.limited = mujoco.mjtLimited.mjLIMITED_TRUE
        if "damping" in kw:
            j.damping = np.array([kw.pop("damping"), 0.0, 0.0])
        if "stiffness" in kw:
            j.stiffness = np.array([kw.pop("stiffness"), 0.0, 0.0])
        for k, v in kw.items():
            setattr(j, k, v)
        self._joint_local.append(name)
        return j

    # ---- names available before compile (building the prop if needed)
    def _ensure_built(self) -> None:
        if self._spec is None:
            self.build_spec()

    @property
    def root_body_name(self) -> str:
        return self.prefix + "root"

    @property
    def site_names(self) -> dict[str, str]:
        """Local site key → full site name, e.g. ``{"rim": "plate/rim"}``."""
        self._ensure_built()
        return {k: self.prefix + k for k in self._site_local}

    @property
    def part_names(self) -> list[str]:
        """Names of the collision parts of this prop."""
        self._ensure_built()
        return list(self._part_geoms)

    def part_geom_names(self, *parts: str) -> list[str]:
        """Full names of the geoms of the named collision parts."""
        self._ensure_built()
        out: list[str] = []
        for p in parts:
            if p not in self._part_geoms:
                raise KeyError(f"{self.name}: no part {p!r} (has {sorted(self._part_geoms)})")
            out += [self.prefix + g for g in self._part_geoms[p]]
        return out

    # ---- binding
    def bind(self, model: mujoco.MjModel, data: mujoco.MjData | None = None) -> None:
        """Resolve ids once after compile. ``data`` is accepted for symmetry; getters take
        the data they read explicitly."""
        if self._spec is None:
            raise RuntimeError(f"prop {self.name!r} was never built")
        del data
        self._model = model
        obj = mujoco.mjtObj
        rid = mujoco.mj_name2id(model, obj.mjOBJ_BODY, self.root_body_name)
        if rid < 0:
            raise KeyError(f"prop {self.name!r} is not in this model")
        self.root_body_id: int = rid
        pre = self.prefix
        self.body_ids = np.array([i for i in range(model.nbody) if model.body(i).name.startswith(pre)], dtype=np.int32)
        self.geom_ids = np.flatnonzero(np.isin(model.geom_bodyid, self.body_ids)).astype(np.int32)
        self._part_ids: dict[str, np.ndarray] = {}
        for part, names in self._part_geoms.items():
            ids = [mujoco.mj_name2id(model, obj.mjOBJ_GEOM, pre + n) for n in names]
            if min(ids) < 0:
                raise KeyError(f"{self.name}: geoms of part {part!r} missing from model")
            self._part_ids[part] = np.array(sorted(ids), dtype=np.int32)
        self.collision_geom_ids = (
            np.unique(np.concatenate(list(self._part_ids.values()))).astype(np.int32)
            if self._part_ids
            else np.zeros(0, np.int32)
        )
        self._collision_saved = (
            model.geom_contype[self.collision_geom_ids].copy(),
            model.geom_conaffinity[self.collision_geom_ids].copy(),
        )
        self._site_ids = {k: mujoco.mj_name2id(model, obj.mjOBJ_SITE, pre + k) for k in self._site_local}
        if self.free:
            jid = model.body_jntadr[rid]
            self._qadr = int(model.jnt_qposadr[jid])
            self._dadr = int(model.jnt_dofadr[jid])
        if self.mocap:
            self._mocap_id = int(model.body_mocapid[rid])

    def _require_bound(self) -> mujoco.MjModel:
        if self._model is None:
            raise RuntimeError(f"prop {self.name!r} is not bound; call bind(model, data)")
        return self._model

    def part_geom_ids(self, *parts: str) -> np.ndarray:
        """Geom ids of the named collision parts (union), after :meth:`bind`."""
        self._require_bound()
        if len(parts) == 1:
            try:
                return self._part_ids[parts[0]]
            except KeyError:
                raise KeyError(f"{self.name}: no part {parts[0]!r} (has {sorted(self._part_ids)})") from None
        return np.unique(np.concatenate([self.part_geom_ids(p) for p in parts]))

    def site_id(self, key: str) -> int:
        return self._site_ids[key]

    def site_pos(self, data: mujoco.MjData, key: str) -> np.ndarray:
        """World position of site ``key`` (valid after mj_kinematics/mj_forward)."""
        return data.site_xpos[self._site_ids[key]]

    # ---- pose
    def get_pose(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
        """World ``(pos, quat)`` of the root body (copies). Free props read ``qpos``,
        others the last computed ``xpos``/``xquat``."""
        self._require_bound()
        if self.free:
            q = data.qpos[self._qadr : self._qadr + 7]
            return q[:3].copy(), q[3:].copy()
        return data.xpos[self.root_body_id].copy(), data.xquat[self.root_body_id].copy()

    def get_velocity(self, data: mujoco.MjData) -> np.ndarray:
        """Free props: the free joint's velocity (linear in world frame, angular in the
        body frame), a view of ``data.qvel``."""
        self._require_bound()
        if not self.free:
            raise TypeError(f"prop {self.name!r} is not free")
        return data.qvel[self._dadr : self._dadr + 6]

    @property
    def qpos_adr(self) -> int:
        """Free props: address of the free joint in ``qpos`` (7 entries)."""
        self._require_bound()
        if not self.free:
            raise TypeError(f"prop {self.name!r} is not free")
        return self._qadr

    @property
    def dof_adr(self) -> int:
        """Free props: address of the free joint in ``qvel`` (6 entries)."""
        self._require_bound()
        if not self.free:
            raise TypeError(f"prop {self.name!r} is not free")
        return self._dadr

    def set_pose(self, data: mujoco.MjData, pos: Vec3, quat: Quat | None = None) -> None:
        """Move the prop. Free props: writes the free joint and zeroes its velocity.
        Mocap props: writes ``data.mocap_pos/quat``. Static props: writes the
        **model's** ``body_pos/body_quat`` (relative to the parent body; persists across
        ``mj_resetData``). Call ``mj_forward`` afterwards."""
        model = self._require_bound()
        if quat is None:
            quat = (1.0, 0.0, 0.0, 0.0)
        q = np.asarray(quat, float)
        q = q / np.linalg.norm(q)
        if self.free:
            data.qpos[self._qadr : self._qadr + 3] = pos
            data.qpos[self._qadr + 3 : self._qadr + 7] = q
            data.qvel[self._dadr : self._dadr + 6] = 0.0
            data.qacc[self._dadr : self._dadr + 6] = 0.0
        elif self.mocap:
            data.mocap_pos[self._mocap_id] = pos
            data.mocap_quat[self._mocap_id] = q
        else:
            model.body_pos[self.root_body_id] = pos
            model.body_quat[self.root_body_id] = q

    def set_collisions_enabled(self, enabled: bool) -> None:
        """Switch all collision geoms of the prop off (contype = conaffinity = 0) or back
        to their compiled values. Mutates the bound model."""
        model = self._require_bound()
        if enabled:
            model.geom_contype[self.collision_geom_ids] = self._collision_saved[0]
            model.geom_conaffinity[self.collision_geom_ids] = self._collision_saved[1]
        else:
            model.geom_contype[self.collision_geom_ids] = 0
            model.geom_conaffinity[self.collision_geom_ids] = 0

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r}, seed={self.seed})"


class ArticulatedProp(Prop):
    """A prop with limited joints exposed as a normalised state (0 closed, 1 open)."""

    @property
    def joint_names(self) -> list[str]:
        """Full joint names in state order."""
        self._ensure_built()
        return [self.prefix + j for j in self._joint_order()]

    @property
    def joint_keys(self) -> list[str]:
        """Local joint keys in state order (e.g. ``"drawer_small_4"``, ``"door"``)."""
        self._ensure_built()
        return self._joint_order()

    def _joint_order(self) -> list[str]:
        return list(self._joint_local)

    def bind(self, model: mujoco.MjModel, data: mujoco.MjData | None = None) -> None:
        super().bind(model, data)
        ids = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, n) for n in self.joint_names]
        if ids and min(ids) < 0:
            raise KeyError(f"{self.name}: joints missing from model")
        self.joint_ids = np.array(ids, dtype=np.int32)
        self._jq = model.jnt_qposadr[self.joint_ids].astype(np.int64)
        self._jd = model.jnt_dofadr[self.joint_ids].astype(np.int64)
        rng = model.jnt_range[self.joint_ids]
        self._lo = rng[:, 0].copy()
        self._span = (rng[:, 1] - rng[:, 0]).copy()
        self._key_index = {k: i for i, k in enumerate(self._joint_order())}

    def joint_index(self, key: str) -> int:
        """Index of joint ``key`` in the state vector."""
        return self._key_index[key]

    def state_mapping(self, keys: Iterable[str] | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(qpos addresses, lows, spans)`` of the listed joints (all by default), such that
        the normalised state is ``clip((qpos[addresses] - lows) / spans, 0, 1)``."""
        indices = list(range(len(self._jq))) if keys is None else [self._key_index[k] for k in keys]
        return self._jq[indices].copy(), self._lo[indices].copy(), self._span[indices].copy()

    def get_state(self, data: mujoco.MjData) -> np.ndarray:
        """Normalised joint positions in ``[0, 1]`` (0 closed, 1 open), in joint order."""
        return np.clip((data.qpos[self._jq] - self._lo) / self._span, 0.0, 1.0)

    def set_state(self, data: mujoco.MjData, state: float | Iterable[float]) -> None:
        """Set normalised joint positions (scalar or one per joint; clipped to [0, 1]) and
        zero their velocities and accelerations. Call ``mj_forward`` afterwards."""
        s = np.clip(np.broadcast_to(np.asarray(state, dtype=float), self._jq.shape), 0.0, 1.0)
        data.qpos[self._jq] = self._lo + s * self._span
        data.qvel[self._jd] = 0.0
        data.qacc[self._jd] = 0.0

    def set_joint_state(self, data: mujoco.MjData, key: str, value: float) -> None:
        """Set one joint's normalised position (see :meth:`set_state`)."""
        i = self._key_index[key]
        v = float(np.clip(value, 0.0, 1.0))
        data.qpos[self._jq[i]] = self._lo[i] + v * self._span[i]
        data.qvel[self._jd[i]] = 0.0
        data.qacc[self._jd[i]] = 0.0
