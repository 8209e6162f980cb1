"""Build-time merge of each prop body's visible primitives into one mesh per colour.

Why: the observation cameras render with software OpenGL on a 2-core CPU, where a frame
costs mostly per draw call (one per visible geom) and much less per vertex. Props are
built from many primitives (a kitchen cabinet is dozens of boxes), so the fullest kitchen
shows ~440 geoms. Drawing each body's geoms of one material and colour as a single mesh
cuts that to ~180, and an 84x84 camera frame there from ~11 to ~8 ms.

Physics is untouched: colliding geoms stay exactly where and what they are (same order,
sizes, masses, contact parameters; later geom ids shift by the meshes added to earlier
bodies, so look ids up by name, as the props do); group-0 geoms (render + collide) only
move to group 3 (collide, hidden). Visual-only group-2 primitives, which have no mass and no
contact, move to the hidden group 4 (:data:`GROUP_MERGED`). The merged mesh is visual
only: group 2, ``contype = conaffinity = 0``, zero density, so it adds no mass and no
inertia.

Shapes are generated with numpy in the body frame, to look as MuJoCo draws them: boxes
exactly (long sides split into quads, since lighting is per vertex); cylinders, capsules,
spheres and ellipsoids as closed meshes with MuJoCo's segment counts and smooth analytic
normals; user meshes given by vertices and faces (the props' lathe meshes) are copied in
with the normals MuJoCo would have made for them.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable
from dataclasses import dataclass, field

import mujoco
import numpy as np

from bigym.geom_groups import GROUP_BOTH, GROUP_COLLISION, GROUP_MERGED, GROUP_VISUAL

__all__ = ["GROUP_MERGED", "MergeReport", "merge_visual_geoms"]

_G = mujoco.mjtGeom
#: box sides longer than this are split into up to ``vis.quality.numquads`` quads (metres)
BOX_QUAD_SIZE = 0.15


@dataclass(frozen=True)
class _Template:
    """A unit shape: vertices, normals (one per vertex) and outward triangles."""

    verts: np.ndarray  # (k, 3)
    normals: np.ndarray  # (k, 3)
    faces: np.ndarray  # (m, 3) int
    hemisphere: np.ndarray | None = None  # (k,) +1/-1: capsule cap each vertex belongs to


@functools.lru_cache(maxsize=64)
def _box_template(quads: tuple[int, int, int] = (1, 1, 1)) -> _Template:
    """Unit cube [-1, 1]^3 whose faces are grids of quads, ``quads[a]`` along axis ``a``."""
    verts: list[np.ndarray] = []
    normals: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    count = 0
    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        nu, nv = quads[u], quads[v]
        gu, gv = (a.ravel() for a in np.meshgrid(np.linspace(-1, 1, nu + 1), np.linspace(-1, 1, nv + 1), indexing="ij"))
        i, j = (a.ravel() for a in np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij"))
        k00, k10, k01, k11 = i * (nv + 1) + j, (i + 1) * (nv + 1) + j, i * (nv + 1) + j + 1, (i + 1) * (nv + 1) + j + 1
        quad = np.concatenate([np.stack([k00, k10, k11], 1), np.stack([k00, k11, k01], 1)])
        for sign in (1.0, -1.0):
            grid = np.zeros((len(gu), 3))
            grid[:, axis], grid[:, u], grid[:, v] = sign, gu, gv
            # (u, v, axis) is right-handed, so this winding faces +axis; flip it for -axis
            faces.append(count + (quad if sign > 0 else quad[:, ::-1]))
            verts.append(grid)
            normals.append(np.tile(np.eye(3)[axis] * sign, (len(grid), 1)))
            count += len(grid)
    return _Template(np.concatenate(verts), np.concatenate(normals), np.concatenate(faces))


def _ring_faces(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Quads between two rings of vertex ids (``b`` above ``a``, counter-clockwise seen from +z)."""
    a1, b1 = np.roll(a, -1), np.roll(b, -1)
    return np.concatenate([np.stack([a, a1, b1], 1), np.stack([a, b1, b], 1)])


def _fan_faces(centre: int, ring: np.ndarray, up: bool) -> np.ndarray:
    ring1 = np.roll(ring, -1)
    c = np.full_like(ring, centre)
    return np.stack([c, ring, ring1], 1) if up else np.stack([c, ring1, ring], 1)


@functools.lru_cache(maxsize=8)
def _cylinder_template(n: int, rings: int) -> _Template:
    """Cylinder of radius 1 from z = -1 to 1 with ``n`` sides; each cap is ``rings``
    concentric rings around a centre vertex (per-vertex lighting needs inner vertices)."""
    ang = 2.0 * np.pi * np.arange(n) / n
    circle = np.stack([np.cos(ang), np.sin(ang), np.zeros(n)], 1)
    up = np.array([0.0, 0.0, 1.0])
    # side (smooth normals), then the caps with their own vertices for sharp rims
    verts = [circle - up, circle + up]
    normals = [circle, circle]
    faces = [_ring_faces(np.arange(n), np.arange(n, 2 * n))]
    count = 2 * n
    for z in (-1.0, 1.0):
        cap = [z * up[None]] + [circle * (k / rings) + z * up for k in range(1, rings + 1)]
        ids = [count + np.arange(1 + k * n - n, 1 + k * n) for k in range(1, rings + 1)]
        faces.append(_fan_faces(count, ids[0], up=z > 0))
        for inner, outer in zip(ids[:-1], ids[1:]):
            ring = _ring_faces(inner, outer)  # (tangent x outward) winding: faces -z
            faces.append(ring[:, ::-1] if z > 0 else ring)
        cap_verts = np.concatenate(cap)
        verts.append(cap_verts)
        normals.append(np.tile(z * up, (len(cap_verts), 1)))
        count += len(cap_verts)
    return _Template(np.concatenate(verts), np.concatenate(normals), np.concatenate(faces))


@functools.lru_cache(maxsize=16)
def _sphere_template(n: int, bands: int, split_equator: bool = False) -> _Template:
    """UV sphere; with ``split_equator`` the equator ring is doubled (one copy per
    hemisphere) so that a capsule stretches the band between them into its cylinder."""
    ang = 2.0 * np.pi * np.arange(n) / n
    lats = np.pi * (np.arange(1, bands) / bands - 0.5)  # interior latitudes, south to north
    rings, hemi = [], []
    for lat in lats:
        ring = np.stack([np.cos(lat) * np.cos(ang), np.cos(lat) * np.sin(ang), np.full(n, np.sin(lat))], 1)
        copies = (-1.0, 1.0) if split_equator and abs(lat) < 1e-12 else (np.sign(lat) or 1.0,)
        for h in copies:
            rings.append(ring)
            hemi.append(np.full(n, h))
    verts = np.concatenate([[[0, 0, -1.0]], *rings, [[0, 0, 1.0]]])
    hemisphere = np.concatenate([[-1.0], *hemi, [1.0]])
    ids = [1 + k * n + np.arange(n) for k in range(len(rings))]
    top = len(verts) - 1
    faces = [_fan_faces(0, ids[0], up=False)]
    faces += [_ring_faces(a, b) for a, b in zip(ids[:-1], ids[1:])]
    faces.append(_fan_faces(top, ids[-1], up=True))
    return _Template(verts, verts.copy(), np.concatenate(faces), hemisphere if split_equator else None)


def _quat_mats(quats: np.ndarray) -> np.ndarray:
    """Rotation matrices (g, 3, 3) of quaternions (g, 4) (w, x, y, z; normalised here)."""
    q = quats / np.linalg.norm(quats, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], 1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], 1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], 1),
        ],
        1,
    )


def _primitive_pieces(
    gtype: int, sizes: np.ndarray, quads: tuple[int, int, int], slices: int, stacks: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Local vertices (g, k, 3), normals (g, k, 3) and faces (m, 3) of ``g`` primitives
    of one type with sizes ``(g, 3)``. Box sides are grids of ``quads`` (see
    :func:`_box_template`); round shapes have ``slices`` around and ``stacks`` pole to pole."""
    if gtype == _G.mjGEOM_BOX:
        t, scale = _box_template(quads), sizes
    elif gtype == _G.mjGEOM_CYLINDER:
        t, scale = _cylinder_template(slices, max(1, stacks // 4)), sizes[:, [0, 0, 1]]
    elif gtype in (_G.mjGEOM_SPHERE, _G.mjGEOM_CAPSULE):
        t, scale = _sphere_template(slices, stacks, split_equator=gtype == _G.mjGEOM_CAPSULE), sizes[:, [0, 0, 0]]
    elif gtype == _G.mjGEOM_ELLIPSOID:
        t, scale = _sphere_template(slices, stacks), sizes
    else:
        raise ValueError(f"no template for geom type {gtype}")
    verts = t.verts[None] * scale[:, None]
    if t.hemisphere is not None:  # capsule: move each hemisphere out by the half-length
        verts[:, :, 2] += t.hemisphere[None] * sizes[:, 1:2]
    if gtype == _G.mjGEOM_ELLIPSOID:  # normals of a scaled sphere scale inversely
        normals = t.normals[None] / sizes[:, None]
        normals /= np.linalg.norm(normals, axis=2, keepdims=True)
    else:
        normals = np.broadcast_to(t.normals, (len(sizes), *t.normals.shape))
    return verts, normals, t.faces


def _mesh_normals(verts: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Vertex normals as MuJoCo makes them for a mesh given without normals (and
    ``smoothnormal`` off): the area-weighted mean of the normals of the vertex's faces,
    leaving out faces more than ~37 degrees (cosine 0.8) from that mean, so that sharp
    edges stay sharp."""
    tri = verts[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])  # unit normal * 2 area
    unit = cross / np.maximum(np.linalg.norm(cross, axis=1, keepdims=True), 1e-300)
    total = np.zeros_like(verts)
    np.add.at(total, faces.ravel(), np.repeat(cross, 3, axis=0))
    mean = total / np.maximum(np.linalg.norm(total, axis=1, keepdims=True), 1e-300)
    far = np.einsum("ij,ij->i", mean[faces.ravel()], np.repeat(unit, 3, axis=0)) < 0.8
    np.subtract.at(total, faces.ravel()[far], np.repeat(cross, 3, axis=0)[far])
    length = np.linalg.norm(total, axis=1, keepdims=True)
    return np.where(length > 1e-12, total / np.maximum(length, 1e-300), (0.0, 0.0, 1.0))


@dataclass(frozen=True)
class MergeReport:
    """What :func:`merge_visual_geoms` did."""

    bodies: int  # bodies that received a merged mesh
    geoms_merged: int  # visible geoms drawn through a merged mesh now (and hidden themselves)
    meshes_added: int  # merged mesh geoms added (one per body, material and colour)


@dataclass
class _Group:
    """Visible geoms of one body with one material and colour: one merged mesh."""

    body: mujoco.MjsBody
    material: str
    rgba: tuple[float, ...]
    members: list[mujoco.MjsGeom] = field(default_factory=list)


_PRIMITIVES = (_G.mjGEOM_BOX, _G.mjGEOM_CYLINDER, _G.mjGEOM_SPHERE, _G.mjGEOM_ELLIPSOID, _G.mjGEOM_CAPSULE)


def _mergeable(geom: mujoco.MjsGeom, spec: mujoco.MjSpec) -> bool:
    """A visible geom whose shape and pose in its body can be read off the spec."""
    if geom.group not in (GROUP_BOTH, GROUP_VISUAL) or geom.rgba[3] <= 0.0:
        return False
    if geom.alt.type != mujoco.mjtOrientation.mjORIENTATION_QUAT or not np.isnan(geom.fromto[0]):
        return False
    if geom.frame is not None or geom.plugin.active:
        return False
    if geom.material:
        material = spec.material(geom.material)
        if material is None or any(material.textures):
            return False  # textures need texture coordinates: leave those geoms alone
    if geom.type == _G.mjGEOM_MESH:
        mesh = spec.mesh(geom.meshname)
        return (
            mesh is not None
            and not mesh.file
            and len(mesh.uservert) > 0
            and len(mesh.userface) > 0
            and len(mesh.usernormal) in (0, len(mesh.uservert))
            and len(mesh.userfacenormal) == 0
            and np.array_equal(mesh.scale, (1.0, 1.0, 1.0))
            and not np.any(mesh.refpos)
            and np.array_equal(mesh.refquat, (1.0, 0.0, 0.0, 0.0))
        )
    return geom.type in _PRIMITIVES


def _collect_groups(spec: mujoco.MjSpec, skip_subtrees: Iterable[str]) -> list[_Group]:
    skip: set[str] = set()
    for name in skip_subtrees:
        root = spec.body(name)
        if root is None:
            raise KeyError(f"no body {name!r} in the spec")
        skip.add(root.name)
        skip.update(b.name for b in root.find_all(mujoco.mjtObj.mjOBJ_BODY))
    groups: list[_Group] = []
    for body in spec.bodies:
        if body.name in skip:
            continue
        by_look: dict[tuple[str, tuple[float, ...]], _Group] = {}
        for geom in body.geoms:
            if _mergeable(geom, spec):
                rgba = tuple(float(c) for c in geom.rgba)
                by_look.setdefault((geom.material, rgba), _Group(body, geom.material, rgba)).members.append(geom)
        groups += [g for g in by_look.values() if len(g.members) >= 2]  # one geom: nothing to gain
    return groups


def _body_frame_pieces(
    spec: mujoco.MjSpec, geoms: list[mujoco.MjsGeom]
) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """``(vertices, normals, faces)`` of each geom in its body's frame, computed in one
    vectorised pass per kind of shape."""
    quality = spec.visual.quality
    # as many segments as MuJoCo draws its own round primitives with; stacks even (capsules)
    slices, stacks = max(3, quality.numslices), max(2, quality.numstacks + quality.numstacks % 2)
    types = np.array([g.type for g in geoms], dtype=int)
    sizes = np.array([g.size for g in geoms], dtype=float)
    pos = np.array([g.pos for g in geoms], dtype=float)
    rot = _quat_mats(np.array([g.quat for g in geoms], dtype=float))
    # MuJoCo lights per vertex and splits each side of its own boxes into numquads
    # quads: split long box sides alike (short ones need no split, which saves vertices)
    quads = np.clip(np.ceil(2.0 * sizes / BOX_QUAD_SIZE), 1, max(1, quality.numquads)).astype(int)
    quads[types != _G.mjGEOM_BOX] = 1
    pieces: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = [None] * len(geoms)  # type: ignore[list-item]
    # (a set, not np.unique(axis=0), which imports numpy.ma on first use: 60 ms)
    kinds = sorted({tuple(row) for row in np.column_stack([types, quads]).tolist()})
    for gtype, *q in kinds:
        idx = np.flatnonzero((types == gtype) & (quads == q).all(axis=1))
        if gtype == _G.mjGEOM_MESH:
            for i in idx:
                mesh = spec.mesh(geoms[i].meshname)
                verts = np.asarray(mesh.uservert, float).reshape(-1, 3)
                faces = np.asarray(mesh.userface, np.int64).reshape(-1, 3)
                normals = np.asarray(mesh.usernormal, float).reshape(-1, 3)
                if len(normals) != len(verts):
                    normals = _mesh_normals(verts, faces)
                pieces[i] = (verts @ rot[i].T + pos[i], normals @ rot[i].T, faces)
            continue
        verts, normals, faces = _primitive_pieces(gtype, sizes[idx], tuple(q), slices, stacks)
        verts = np.einsum("gij,gkj->gki", rot[idx], verts) + pos[idx, None]
        normals = np.einsum("gij,gkj->gki", rot[idx], normals)
        for j, i in enumerate(idx):
            pieces[i] = (verts[j], normals[j], faces)
    return pieces


def merge_visual_geoms(spec: mujoco.MjSpec, skip_subtrees: Iterable[str] = ()) -> MergeReport:
    """Draw each body's visible geoms of one material and colour as one visual mesh.

    Call on a finished spec right before ``spec.compile()``. Bodies in the subtrees of
    the bodies named in ``skip_subtrees`` (the robot) are left alone. In every other body
    the visible (group 0 or 2) primitives and user meshes are grouped by ``(material,
    rgba)``; each group of two or more becomes one mesh geom in group 2 with no contact
    and no mass. Its group-0 members move to group 3 (still colliding, now hidden), its
    group-2 members to the hidden group :data:`GROUP_MERGED` (``spec.delete`` would cost
    ~4 ms per element).
    """
    groups = _collect_groups(spec, skip_subtrees)
    if not groups:
        return MergeReport(0, 0, 0)
    pieces = _body_frame_pieces(spec, [g for group in groups for g in group.members])
    start = 0
    counters: dict[str, int] = {}
    for group in groups:
        own = pieces[start : start + len(group.members)]
        start += len(group.members)
        offsets = np.cumsum([0] + [len(v) for v, _, _ in own[:-1]])
        faces = np.concatenate([f + o for (_, _, f), o in zip(own, offsets)]).ravel().tolist()
        index = counters[group.body.name] = counters.get(group.body.name, -1) + 1
        name = f"{group.body.name}/merged_visual_{index}"
        mesh = spec.add_mesh(name=name)
        mesh.uservert = np.concatenate([v for v, _, _ in own]).ravel().tolist()
        mesh.usernormal = np.concatenate([n for _, n, _ in own]).ravel().tolist()
        mesh.userface = faces
        mesh.userfacenormal = faces  # one normal per vertex
        geom = group.body.add_geom(name=name, type=_G.mjGEOM_MESH, meshname=name)
        geom.group = GROUP_VISUAL
        geom.contype = geom.conaffinity = 0
        geom.density = 0.0
        geom.rgba = np.asarray(group.rgba, float)
        if group.material:
            geom.material = group.material
        for member in group.members:
            member.group = GROUP_COLLISION if member.group == GROUP_BOTH else GROUP_MERGED
    return MergeReport(
        bodies=len({id(g.body) for g in groups}),
        geoms_merged=sum(len(g.members) for g in groups),
        meshes_added=len(groups),
    )
