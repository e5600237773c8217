"""Meshes of the solids assembled from their faces, made from those faces, not by OCC.

A solid of :mod:`origami_cad.fabrication.polyhedra` is bounded by planar polygons,
horizontal caps (rings, and the circles of the string holes) and vertical hole
cylinders, all known as plain data (:class:`~origami_cad.fabrication.polyhedra.Facets`).
:func:`facets_mesh` triangulates them as OCC's mesher does at the exports' tolerances:
the same vertices (the B-rep's corners, and each circle as the regular polygon of
:func:`circle_segments` corners from the seam at +x), no vertex inside a face, every
edge shared by the faces on either side, normals outward.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import shapely

from origami_cad.fabrication.polyhedra import Cap, Facets, newell_normal

__all__ = ["circle_segments", "facets_mesh", "polygon_triangles", "ring_area"]


def circle_segments(angular_tolerance: float) -> int:
    """Corners of a circle in OCC's mesh at angular tolerance ``angular_tolerance`` (rad).

    ``BRepMesh_IncrementalMesh`` steps along a circle by half that angle, whatever its
    radius, when its chordal tolerance is relative (as the exports' is).
    """
    return math.ceil(2.0 * math.pi / (angular_tolerance / 2.0) - 1e-9)


def _circle(disc: tuple[float, float, float], z: float, n: int) -> list[tuple]:
    """The ``n`` corners of a circle at height ``z``, anticlockwise from the seam (+x)."""
    x, y, r = disc
    angles = np.arange(n) * (2.0 * math.pi / n)
    ring = np.column_stack([x + r * np.cos(angles), y + r * np.sin(angles), np.full(n, z)])
    return [tuple(p) for p in ring.tolist()]


class _Mesh:
    """Vertices keyed by their point (shared by every face through them), triangles."""

    def __init__(self, segments: int) -> None:
        self.segments = segments
        self.index: dict[tuple, int] = {}
        self.triangles: list[np.ndarray] = []
        self.circles: dict[tuple, list[tuple]] = {}

    def circle(self, disc: tuple[float, float, float], z: float) -> list[tuple]:
        """:func:`_circle`, the same points each time (a wall and a cap share them)."""
        key = (*disc, z)
        if key not in self.circles:
            self.circles[key] = _circle(disc, z, self.segments)
        return self.circles[key]

    def ids(self, points: list[tuple]) -> np.ndarray:
        """The vertex index of each point, a new vertex for a point not seen before."""
        index = self.index
        return np.array([index.setdefault(p, len(index)) for p in points], dtype=np.int64)

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """The vertices (mm, in the order first seen) and the triangles."""
        verts = np.array(list(self.index), dtype=float).reshape(-1, 3)
        return verts, np.vstack(self.triangles).astype(np.int64)


def _wall(mesh: _Mesh, wall: tuple) -> None:
    """A hole's cylinder: two triangles per step of the circle, normals into the hole."""
    x, y, r, z0, z1 = wall
    lo, hi = mesh.ids(mesh.circle((x, y, r), z0)), mesh.ids(mesh.circle((x, y, r), z1))
    nxt_lo, nxt_hi = _turned(lo), _turned(hi)
    mesh.triangles += [np.column_stack([lo, nxt_hi, nxt_lo]), np.column_stack([lo, hi, nxt_hi])]


def _cap(mesh: _Mesh, cap: Cap) -> bool:
    """A horizontal face, triangulated on its own corners (a fan when it is convex and
    has no hole, :func:`_annulus` when it has one, else constrained Delaunay); ``False``
    when that needs another point."""
    if not cap.inner and not cap.discs and _polygon(mesh, cap.outer[:: 1 if cap.up else -1]):
        return True
    rings = [cap.outer, *cap.inner, *(mesh.circle(d, cap.z) for d in cap.discs)]
    ids = [mesh.ids(ring) for ring in rings]
    xy = [np.array(ring, dtype=float)[:, :2] for ring in rings]
    tri = _annulus(xy, np.concatenate(ids)) if len(rings) == 2 else None
    if tri is None:
        tri = _delaunay(xy, np.concatenate(ids))
    if tri is None:
        return False
    mesh.triangles.append(tri if cap.up else tri[:, [0, 2, 1]])
    return True


def _turned(a: np.ndarray) -> np.ndarray:
    """``np.roll(a, -1)`` of a 1-d array: each entry's successor, cyclic."""
    return np.concatenate([a[1:], a[:1]])


def ring_area(xy: np.ndarray) -> float:
    """The signed area (mm^2, anticlockwise positive) of a ring of ``(x, y)`` corners."""
    return 0.5 * float(np.dot(xy[:, 0], _turned(xy[:, 1])) - np.dot(_turned(xy[:, 0]), xy[:, 1]))


def _annulus(xy: list[np.ndarray], ids: np.ndarray) -> np.ndarray | None:
    """The region between a convex ring and one convex ring inside it, zipped by their
    edges' outward normals (rotating calipers): each outer edge makes a triangle with
    the inner corner extreme along its normal, each inner edge one with the outer corner
    extreme along its normal; anticlockwise from above. ``None`` unless every triangle
    turns anticlockwise and they cover the region's area.
    """
    pts, index, begin = np.vstack(xy), [], 0
    for ring in xy:
        k = np.arange(begin, begin + len(ring))
        index.append(k if ring_area(ring) > 0 else k[::-1])  # both anticlockwise
        begin += len(ring)
    first = np.concatenate(index)  # each edge's first corner, then its last
    last = np.concatenate([_turned(k) for k in index])
    d = pts[last] - pts[first]
    order = np.argsort(np.arctan2(-d[:, 0], d[:, 1]), kind="stable")
    first, last, outer = first[order], last[order], order < len(index[0])
    tri = np.where(
        outer[:, None],
        np.column_stack([first, last, first[_next(~outer)]]),
        np.column_stack([first, first[_next(outer)], last]),
    )
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    turns = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    want = ring_area(pts[index[0]]) - ring_area(pts[index[1]])
    if np.any(turns <= 0) or abs(0.5 * turns.sum() - want) > 1e-9 * max(want, 1.0):
        return None
    return ids[tri]


def _next(mask: np.ndarray) -> np.ndarray:
    """For each position, the first later position (cyclic) where ``mask`` holds."""
    n = len(mask)
    at = np.where(mask, np.arange(n), n)
    ahead = np.minimum.accumulate(at[::-1])[::-1]  # the first at or after each position
    out = np.append(ahead[1:], n)
    out[out == n] = ahead[0]
    return out


def _delaunay(xy: list[np.ndarray], ids: np.ndarray) -> np.ndarray | None:
    """The constrained Delaunay triangles of the rings (the first the outer one),
    anticlockwise from above; ``None`` if a triangle has a corner of no ring."""
    return polygon_triangles(shapely.Polygon(xy[0], xy[1:]), np.vstack(xy), ids)


def polygon_triangles(
    poly: shapely.Polygon, corners: np.ndarray, ids: np.ndarray
) -> np.ndarray | None:
    """A polygon's constrained Delaunay triangles on its own corners, anticlockwise
    from above.

    Parameters
    ----------
    poly : shapely.Polygon
        The polygon, mm.
    corners : (n, 2) ndarray
        Its corners (every ring's), mm.
    ids : (n,) ndarray
        The vertex index of each corner.

    Returns
    -------
    (m, 3) ndarray of int64, or None
        Vertex indices per triangle; ``None`` if a triangle has a corner that is not
        one of ``corners``.
    """
    keys = {p: i for p, i in zip(map(tuple, corners.tolist()), ids.tolist(), strict=True)}
    triangles = shapely.get_parts(shapely.constrained_delaunay_triangles(poly))
    points = shapely.get_coordinates(shapely.get_exterior_ring(triangles))
    points = points.reshape(len(triangles), 4, 2)[:, :3]
    try:
        tri = np.array([keys[(x, y)] for x, y in points.reshape(-1, 2).tolist()])
    except KeyError:
        return None
    tri = tri.reshape(-1, 3).astype(np.int64)
    a, b = points[:, 1] - points[:, 0], points[:, 2] - points[:, 0]
    clockwise = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] < 0
    return np.where(clockwise[:, None], tri[:, [0, 2, 1]], tri)


def _polygon(mesh: _Mesh, points: list[tuple]) -> bool:
    """A planar polygon as a fan from its first corner; ``False`` unless it is convex
    (each triangle of the fan turning as the whole polygon does)."""
    normal = newell_normal(points)
    x0, y0, z0 = points[0]
    for (x1, y1, z1), (x2, y2, z2) in itertools.pairwise(points[1:]):
        ax, ay, az, bx, by, bz = x1 - x0, y1 - y0, z1 - z0, x2 - x0, y2 - y0, z2 - z0
        turn = (ay * bz - az * by) * normal[0] + (az * bx - ax * bz) * normal[1]
        if turn + (ax * by - ay * bx) * normal[2] <= 0.0:
            return False
    ids = mesh.ids(points)
    mesh.triangles.append(np.column_stack([np.full(len(ids) - 2, ids[0]), ids[1:-1], ids[2:]]))
    return True


def facets_mesh(facets: Facets, segments: int) -> tuple[np.ndarray, np.ndarray] | None:
    """A solid's mesh from its faces: vertices (mm, each point once) and triangles
    (outward); ``None`` when a face is not triangulated on its own corners (then mesh
    the solid with OCC).

    Parameters
    ----------
    facets : Facets
        The solid's faces (:mod:`~origami_cad.fabrication.polyhedra`).
    segments : int
        Corners of each hole's circle (:func:`circle_segments`).
    """
    mesh = _Mesh(segments)
    for wall in facets.walls:
        _wall(mesh, wall)
    if not all(_cap(mesh, cap) for cap in facets.caps):
        return None
    if not all(_polygon(mesh, points) for points in facets.polygons):
        return None
    return mesh.arrays()
