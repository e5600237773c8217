"""The meshes behind every export: each printed solid as vertices (mm) and triangles.

The meshes are OCC's tessellation of each solid (:func:`solid_mesh`), welded within the
solid only, or the same surface made straight from what the solid was built from: a
polygon's prism (:func:`prism_mesh`), a solid assembled from its faces
(:func:`~origami_cad.fabrication.polymesh.facets_mesh`). Each part's meshes are made once
(:func:`part_meshes`) and shared by the STL, 3MF and glb files, the renders and the
printed mass; the exporters only serialise them.
"""

from __future__ import annotations

import numpy as np
from build123d import Solid
from OCP.BRep import BRep_Tool
from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.BRepTools import BRepTools
from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED
from OCP.TopExp import TopExp_Explorer
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS

from origami_cad.fabrication.polymesh import (
    circle_segments,
    facets_mesh,
    polygon_triangles,
    ring_area,
)
from origami_cad.fabrication.solids import PART_NAMES, Parts, prism_rings

__all__ = [
    "ANGULAR_TOLERANCE",
    "TOLERANCE",
    "built_mesh",
    "moved_mesh",
    "part_meshes",
    "parts_tessellation",
    "prism_mesh",
    "solid_mesh",
    "stack_meshes",
    "weld",
    "weld_float32",
]

#: Tessellation of the exports: chordal tolerance (relative) and angular tolerance (rad).
TOLERANCE, ANGULAR_TOLERANCE = 0.01, 0.1


def stack_meshes(meshes) -> tuple[np.ndarray, np.ndarray]:
    """Meshes in one: vertices (mm) stacked, triangles renumbered; no vertex shared."""
    verts, tris, offset = [np.zeros((0, 3))], [np.zeros((0, 3), dtype=np.int64)], 0
    for v, t in meshes:
        verts.append(v)
        tris.append(t + offset)
        offset += len(v)
    return np.vstack(verts), np.vstack(tris)


def weld_float32(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`weld` of float32 points (the same result, as float64), about twice as fast.

    Each coordinate's bits are mapped to an unsigned integer in the order of the floats
    (``-0.0`` is ``0.0``); x and y make one 64-bit key, z another: a sort of two integer
    keys rather than three float ones.
    """
    points = np.asarray(points, dtype=np.float32).reshape(-1, 3)
    bits = (points + np.float32(0.0)).view(np.uint32).astype(np.uint64)
    key = np.where(bits >> np.uint64(31), bits ^ np.uint64(0xFFFFFFFF), bits | np.uint64(1 << 31))
    xy = (key[:, 0] << np.uint64(32)) | key[:, 1]
    order = np.lexsort((key[:, 2], xy))
    ranked_xy, ranked_z = xy[order], key[order, 2]
    new = np.ones(len(points), dtype=bool)
    new[1:] = (ranked_xy[1:] != ranked_xy[:-1]) | (ranked_z[1:] != ranked_z[:-1])
    inverse = np.empty(len(points), dtype=np.int64)
    inverse[order] = np.cumsum(new) - 1
    return points[order[new]].astype(float), inverse


def weld(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Equal points merged: the distinct points (sorted by x, y, z) and each point's index.

    ``np.unique(points, axis=0, return_inverse=True)``, by a lexicographic sort of
    the columns (many times faster on millions of points).
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    if not len(points):
        return points.copy(), np.zeros(0, dtype=np.int64)
    order = np.lexsort((points[:, 2], points[:, 1], points[:, 0]))
    ranked = points[order]
    new = np.ones(len(points), dtype=bool)
    new[1:] = np.any(ranked[1:] != ranked[:-1], axis=1)
    inverse = np.empty(len(points), dtype=np.int64)
    inverse[order] = np.cumsum(new) - 1
    return ranked[new], inverse


def _face_mesh(face) -> tuple[np.ndarray, np.ndarray]:
    """One meshed face's nodes (mm, placed) and triangles (0-based, outward)."""
    loc = TopLoc_Location()
    tri = BRep_Tool.Triangulation_s(face, loc)
    if tri is None:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    node, triangle = tri.Node, tri.Triangle  # bound once: a call per node and triangle
    v = np.array([node(i).Coord() for i in range(1, tri.NbNodes() + 1)], dtype=float)
    t = [triangle(i).Get() for i in range(1, tri.NbTriangles() + 1)]
    t = np.array(t, dtype=np.int64).reshape(-1, 3) - 1
    if not loc.IsIdentity():
        tr = loc.Transformation()
        m = np.array([[tr.Value(r, c) for c in range(1, 5)] for r in range(1, 4)])
        v = v @ m[:, :3].T + m[:, 3]
    if face.Orientation() == TopAbs_REVERSED:
        t = t[:, [0, 2, 1]]
    return v.reshape(-1, 3), t


def solid_mesh(solid: Solid) -> tuple[np.ndarray, np.ndarray]:
    """One solid meshed by OCC: vertices (mm) welded within the solid, triangles.

    OCC's incremental mesher at :data:`TOLERANCE` (relative chordal) and
    :data:`ANGULAR_TOLERANCE` (rad), read face by face (a reversed face's triangles
    turned over). Vertices are welded only inside one solid, never across solids:
    neighbouring shell chamfers meet on a line, and welding them would join four
    triangles on one edge. Triangles that collapse in the weld are dropped.
    """
    shape = solid.wrapped
    if not BRepTools.Triangulation_s(shape, TOLERANCE):
        BRepMesh_IncrementalMesh(shape, TOLERANCE, True, ANGULAR_TOLERANCE, True)
    verts, tris, offset = [np.zeros((0, 3))], [np.zeros((0, 3), dtype=np.int64)], 0
    explorer = TopExp_Explorer(shape, TopAbs_FACE)
    while explorer.More():
        v, t = _face_mesh(TopoDS.Face(explorer.Current()))
        verts.append(v)
        tris.append(t + offset)
        offset += len(v)
        explorer.Next()
    v, t = np.vstack(verts), np.vstack(tris)
    key = np.round(v / 1e-6).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    t = inverse.reshape(-1)[t]
    t = t[(t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 2] != t[:, 0])]
    return v[first], t


def prism_mesh(poly, z0: float, z1: float) -> tuple[np.ndarray, np.ndarray] | None:
    """The mesh of a polygon's :func:`~origami_cad.fabrication.solids.planar_prism`, mm.

    The same surface as OCC's mesh of the prism (every face is planar, every edge
    straight): the polygon's constrained Delaunay triangulation on the top and the bottom,
    two triangles per side, on the prism's own corners; outward. ``None`` when the
    triangulation does not stand on those corners alone (then the solid is meshed by OCC).
    """
    rings = [np.array(r, dtype=float) for r in prism_rings(poly)]
    for k, ring in enumerate(rings):  # exterior counter-clockwise, holes clockwise
        if (ring_area(ring) > 0) != (k == 0):
            rings[k] = ring[::-1]
    flat = np.vstack(rings)
    n = len(flat)
    tri = polygon_triangles(poly, flat, np.arange(n))  # counter-clockwise: +z
    if tri is None:
        return None
    nxt = np.concatenate([np.roll(np.arange(len(r)), -1) for r in rings])
    nxt += np.repeat(np.cumsum([0, *[len(r) for r in rings[:-1]]]), [len(r) for r in rings])
    i = np.arange(n)
    sides = np.vstack([np.column_stack([i, nxt, nxt + n]), np.column_stack([i, nxt + n, i + n])])
    verts = np.vstack(
        [np.column_stack([flat, np.full(n, z0)]), np.column_stack([flat, np.full(n, z1)])]
    )
    return verts, np.vstack([tri[:, [0, 2, 1]], tri + n, sides]).astype(np.int64)


def moved_mesh(mesh: tuple[np.ndarray, np.ndarray], motion: np.ndarray) -> tuple:
    """A mesh moved by a 3 x 3 plane motion (rotation about z, translation in mm)."""
    v, t = mesh
    m = np.asarray(motion, dtype=float)
    out = v.copy()
    out[:, :2] = v[:, :2] @ m[:2, :2].T + m[:2, 2]
    return out, t


def part_meshes(parts: Parts, name: str) -> list[tuple[np.ndarray, np.ndarray]]:
    """The meshes of every solid of a part (see :func:`solid_mesh`), tessellated once.

    A solid that is, as built, a moved copy of an earlier one (``parts.copy_of``) gets
    that solid's mesh, moved; a prism or a solid assembled from its faces, as built, is
    meshed from them (:func:`built_mesh`). The meshes are kept on ``parts`` and shared
    by every export (STL, 3MF, glb, renders) until the part's solids change.
    """
    solids = parts.solids[name]
    cached = parts.mesh_cache.get(name)
    if cached is not None and len(cached[0]) == len(solids):
        if all(a is b for a, b in zip(cached[0], solids, strict=True)):
            return cached[1]
    meshes: list[tuple[np.ndarray, np.ndarray]] = []
    for k, solid in enumerate(solids):
        source, mesh = parts.source(name, k), built_mesh(parts, name, k)
        if mesh is not None:
            meshes.append(mesh)
        elif source is None:
            meshes.append(solid_mesh(solid))
        else:
            meshes.append(moved_mesh(meshes[source[0]], source[1]))
    parts.mesh_cache[name] = (list(solids), meshes)
    return meshes


def built_mesh(parts: Parts, name: str, k: int) -> tuple[np.ndarray, np.ndarray] | None:
    """Solid ``k``'s mesh made from what it was built from (a prism's polygon, the faces
    it was assembled from), the surface OCC's mesh of it has; ``None`` for other solids."""
    prism = parts.prism(name, k)
    if prism is not None:
        return prism_mesh(*prism)
    facets = parts.faces_of(name, k)
    if facets is not None:
        return facets_mesh(facets, circle_segments(ANGULAR_TOLERANCE))
    return None


def parts_tessellation(parts: Parts) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each part as one plain mesh: vertices (mm, assembly position) and triangles.

    The solids of a part are stacked (:func:`part_meshes`, no vertex shared between
    solids); this is what other stages draw, as NumPy arrays rather than build123d
    shapes.
    """
    return {name: stack_meshes(part_meshes(parts, name)) for name in PART_NAMES}
