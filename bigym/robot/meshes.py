"""Mesh loading with an on-disk cache of decimated (low-poly) render meshes.

The menagerie H1 and 2F-85 ship ~350k triangles of STL. Rendering those on a
CPU dominates an observation step, and parsing them dominates model build time.
So every mesh is read once, decimated for rendering, and stored as a small
``.npz`` under ``$BIGYM_HOME/meshes``; later builds load the arrays directly and
hand them to ``MjSpec`` as user vertices and faces (no file I/O in the compiler).
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bigym.paths import bigym_home

# Bump when the decimation or the file layout changes: old cache entries are then ignored.
_CACHE_VERSION = 2
# Fraction of triangles kept in render meshes (render cost grows with the face count).
RENDER_FACE_FRACTION = 0.05
# Meshes smaller than this are kept as they are: decimating them saves nothing.
_MIN_FACES_TO_DECIMATE = 1000

_STL_TRIANGLE = np.dtype(
    [("normal", "<f4", (3,)), ("vertices", "<f4", (3, 3)), ("attr", "<u2")]
)


@dataclass(frozen=True)
class MeshData:
    """Vertices (N, 3) float32 and triangle indices (M, 3) int32, already scaled."""

    vertices: np.ndarray
    faces: np.ndarray


def read_stl(path: Path) -> MeshData:
    """Parse a binary STL file into an indexed triangle mesh (shared vertices merged)."""
    raw = path.read_bytes()
    if raw[:5] == b"solid" and b"facet" in raw[:512]:
        raise ValueError(f"{path}: ASCII STL is not supported, convert it to binary")
    count = int(np.frombuffer(raw, dtype="<u4", count=1, offset=80)[0])
    expected = 84 + count * _STL_TRIANGLE.itemsize
    if len(raw) < expected:
        raise ValueError(f"{path}: truncated STL ({len(raw)} bytes, {expected} expected)")
    triangles = np.frombuffer(raw, dtype=_STL_TRIANGLE, count=count, offset=84)
    corners = triangles["vertices"].reshape(-1, 3)
    vertices, inverse = np.unique(corners, axis=0, return_inverse=True)
    faces = inverse.reshape(-1, 3).astype(np.int32)
    # Drop triangles that collapsed when duplicate corners were merged.
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    return MeshData(vertices.astype(np.float32), faces[keep])


def decimate(mesh: MeshData, face_fraction: float) -> MeshData:
    """Decimate to about ``face_fraction`` of the triangles.

    Quadric-error decimation first (it keeps the shape best); on meshes where it stalls
    far above the target (thin shells with many borders, as in the 2F-85 mount), vertex
    clustering finishes the job: at 84x84 pixels the difference does not show.
    """
    if face_fraction >= 1.0 or len(mesh.faces) < _MIN_FACES_TO_DECIMATE:
        return mesh
    import fast_simplification  # imported lazily: only needed on a cache miss

    target = max(int(len(mesh.faces) * face_fraction), _MIN_FACES_TO_DECIMATE // 4)
    vertices, faces = fast_simplification.simplify(
        mesh.vertices, mesh.faces, target_reduction=1.0 - face_fraction
    )
    result = MeshData(np.asarray(vertices, np.float32), np.asarray(faces, np.int32))
    if len(result.faces) > 1.5 * target:
        result = _cluster_to(result, target)
    return result


def _cluster_once(mesh: MeshData, cell: float) -> MeshData:
    """Merge the vertices in each cubic cell of size ``cell`` into their mean."""
    keys = np.floor((mesh.vertices - mesh.vertices.min(axis=0)) / cell).astype(np.int64)
    _, cluster = np.unique(keys, axis=0, return_inverse=True)
    cluster = cluster.ravel()
    count = np.bincount(cluster).astype(np.float64)
    vertices = np.stack([np.bincount(cluster, mesh.vertices[:, k]) / count for k in range(3)], axis=1)
    faces = cluster[mesh.faces]
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    faces = faces[keep]
    _, first = np.unique(np.sort(faces, axis=1), axis=0, return_index=True)
    return MeshData(vertices.astype(np.float32), faces[np.sort(first)].astype(np.int32))


def _cluster_to(mesh: MeshData, target_faces: int) -> MeshData:
    """Vertex clustering with the finest cell size that reaches ``target_faces``."""
    extent = float(np.ptp(mesh.vertices, axis=0).max())
    fine, coarse = extent / 1000.0, extent / 4.0
    best = _cluster_once(mesh, coarse)
    for _ in range(14):  # bisect the cell size on a log scale
        cell = float(np.sqrt(fine * coarse))
        candidate = _cluster_once(mesh, cell)
        if len(candidate.faces) > target_faces:
            fine = cell
        else:
            coarse, best = cell, candidate
    return best


def _cache_path(source: Path, scale: np.ndarray, face_fraction: float) -> Path:
    digest = hashlib.sha256()
    digest.update(source.read_bytes())
    digest.update(np.asarray(scale, np.float64).tobytes())
    digest.update(f"{face_fraction:.6f}:{_CACHE_VERSION}".encode())
    return bigym_home() / "meshes" / f"{source.stem}-{digest.hexdigest()[:16]}.npz"


def _atomic_save(path: Path, mesh: MeshData) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as handle:
            np.savez(handle, vertices=mesh.vertices, faces=mesh.faces)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def load_mesh(source: Path, scale: np.ndarray, face_fraction: float = 1.0) -> MeshData:
    """The mesh at ``source`` scaled by ``scale``, decimated to ``face_fraction``, cached."""
    cached = _cache_path(source, scale, face_fraction)
    if cached.exists():
        try:
            with np.load(cached) as arrays:
                return MeshData(arrays["vertices"], arrays["faces"])
        except (OSError, ValueError, KeyError):
            cached.unlink(missing_ok=True)  # a damaged entry is rebuilt below
    mesh = read_stl(source)
    mesh = MeshData(mesh.vertices * np.asarray(scale, np.float32), mesh.faces)
    mesh = decimate(mesh, face_fraction)
    _atomic_save(cached, mesh)
    return mesh
