"""The geometric predicates of the fitness (eq. 5), compiled with numba.

The one implementation of each test, run one sampled state at a time:
segments that touch count as intersecting; points on a polygon's boundary
follow the even-odd rule of a ray cast toward +x. The tests check them
against shapely. The ``state_*`` functions are numba functions (callable from
other compiled code, such as :mod:`origami_cad.design.kernel`); the
array functions below them run them over many states from Python.

An area is given by its boundary segments (:func:`area_edges`); several areas
are packed into one array of segments with offsets and bounding boxes
(:func:`pack_areas`), so compiled code can test a state against all of them.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import shapely
from numba import njit

__all__ = [
    "PackedAreas",
    "area_edges",
    "pack_areas",
    "points_inside",
    "segments_touch",
    "self_intersections",
    "state_inside_area",
    "state_self_touches",
    "state_touches_area",
    "touches_area",
]


def area_edges(areas: tuple[Any, ...]) -> list[np.ndarray]:
    """The boundary segments of each shapely polygon (exterior and holes), shape (E, 2, 2), mm."""
    out = []
    for poly in areas:
        rings = [poly.exterior, *poly.interiors]
        segs = []
        for ring in rings:
            c = shapely.get_coordinates(ring)
            segs.append(np.stack([c[:-1], c[1:]], axis=1))
        out.append(np.concatenate(segs))
    return out


class PackedAreas:
    """Several polygons' boundary segments in one array, for compiled code.

    Attributes
    ----------
    edges : ndarray, shape (E, 2, 2)
        Every area's boundary segments, area after area, mm.
    offsets : ndarray of int, shape (A + 1,)
        Area ``a`` owns ``edges[offsets[a]:offsets[a + 1]]``.
    boxes : ndarray, shape (A, 4)
        ``xmin, ymin, xmax, ymax`` of each area, mm.
    """

    def __init__(self, edges: np.ndarray, offsets: np.ndarray, boxes: np.ndarray) -> None:
        self.edges = edges
        self.offsets = offsets
        self.boxes = boxes

    def __len__(self) -> int:
        return len(self.boxes)


def pack_areas(areas: tuple[Any, ...]) -> PackedAreas:
    """Pack shapely polygons (exterior and holes) for :func:`state_touches_area` and kin."""
    parts = area_edges(areas)
    sizes = [len(p) for p in parts]
    edges = np.ascontiguousarray(
        np.concatenate(parts) if parts else np.zeros((0, 2, 2)), dtype=float
    )
    offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    boxes = np.array(
        [[p[:, :, 0].min(), p[:, :, 1].min(), p[:, :, 0].max(), p[:, :, 1].max()] for p in parts]
        if parts
        else np.zeros((0, 4)),
        dtype=float,
    ).reshape(-1, 4)
    return PackedAreas(edges, offsets, boxes)


@njit(cache=True, inline="always")
def segments_touch(ax, ay, bx, by, cx, cy, dx, dy) -> bool:
    """Do segments ``ab`` and ``cd`` intersect or touch? (numba; coordinates in mm)."""
    if (
        min(ax, bx) > max(cx, dx)
        or min(cx, dx) > max(ax, bx)
        or min(ay, by) > max(cy, dy)
        or min(cy, dy) > max(ay, by)
    ):
        return False
    o1 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    o2 = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax)
    if o1 * o2 > 0:
        return False
    o3 = (dx - cx) * (ay - cy) - (dy - cy) * (ax - cx)
    o4 = (dx - cx) * (by - cy) - (dy - cy) * (bx - cx)
    return o3 * o4 <= 0


@njit(cache=True)
def state_self_touches(x: np.ndarray, y: np.ndarray, r: int) -> bool:
    """Do two non-adjacent segments of chain ``r`` (row of joints ``x, y``, mm) touch?"""
    m = x.shape[1]
    for i in range(m - 3):
        ax, ay, bx, by = x[r, i], y[r, i], x[r, i + 1], y[r, i + 1]
        for j in range(i + 2, m - 1):
            if segments_touch(ax, ay, bx, by, x[r, j], y[r, j], x[r, j + 1], y[r, j + 1]):
                return True
    return False


@njit(cache=True, inline="always")
def _inside_edges(px: float, py: float, edges: np.ndarray, lo: int, hi: int) -> bool:
    parity = False
    for e in range(lo, hi):
        x0, y0, x1, y1 = edges[e, 0, 0], edges[e, 0, 1], edges[e, 1, 0], edges[e, 1, 1]
        if (y0 > py) != (y1 > py):
            x_at = x0 + (py - y0) * (x1 - x0) / (y1 - y0)
            if px < x_at:
                parity = not parity
    return parity


@njit(cache=True)
def state_inside_area(
    px: float, py: float, edges: np.ndarray, offsets: np.ndarray, boxes: np.ndarray, a: int
) -> bool:
    """Is point ``(px, py)`` (mm) inside packed area ``a`` (even-odd rule)?"""
    if px < boxes[a, 0] or px > boxes[a, 2] or py < boxes[a, 1] or py > boxes[a, 3]:
        return False
    return _inside_edges(px, py, edges, offsets[a], offsets[a + 1])


@njit(cache=True)
def state_touches_area(
    x: np.ndarray,
    y: np.ndarray,
    r: int,
    edges: np.ndarray,
    offsets: np.ndarray,
    boxes: np.ndarray,
    a: int,
) -> bool:
    """Does chain ``r`` (a joint inside, or a segment on an edge) touch packed area ``a``?"""
    m = x.shape[1]
    lox, loy, hix, hiy = boxes[a, 0], boxes[a, 1], boxes[a, 2], boxes[a, 3]
    if x[r].max() < lox or x[r].min() > hix or y[r].max() < loy or y[r].min() > hiy:
        return False
    for i in range(m):
        if state_inside_area(x[r, i], y[r, i], edges, offsets, boxes, a):
            return True
    for i in range(m - 1):
        ax, ay, bx, by = x[r, i], y[r, i], x[r, i + 1], y[r, i + 1]
        if max(ax, bx) < lox or min(ax, bx) > hix or max(ay, by) < loy or min(ay, by) > hiy:
            continue
        for e in range(offsets[a], offsets[a + 1]):
            cx, cy, dx, dy = edges[e, 0, 0], edges[e, 0, 1], edges[e, 1, 0], edges[e, 1, 1]
            if segments_touch(ax, ay, bx, by, cx, cy, dx, dy):
                return True
    return False


@njit(cache=True)
def _self_intersections(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    out = np.zeros(x.shape[0], dtype=np.bool_)
    for r in range(x.shape[0]):
        out[r] = state_self_touches(x, y, r)
    return out


@njit(cache=True)
def _touches_area(x, y, edges, offsets, boxes) -> np.ndarray:
    out = np.zeros(x.shape[0], dtype=np.bool_)
    for r in range(x.shape[0]):
        out[r] = state_touches_area(x, y, r, edges, offsets, boxes, 0)
    return out


@njit(cache=True)
def _inside_points(x, y, edges, offsets, boxes) -> np.ndarray:
    out = np.zeros(x.shape[0], dtype=np.bool_)
    for r in range(x.shape[0]):
        out[r] = state_inside_area(x[r], y[r], edges, offsets, boxes, 0)
    return out


def _one_area(edges: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    e = np.ascontiguousarray(edges, dtype=float).reshape(-1, 2, 2)
    box = np.array([[e[:, :, 0].min(), e[:, :, 1].min(), e[:, :, 0].max(), e[:, :, 1].max()]])
    return e, np.array([0, len(e)], dtype=np.int64), box


def self_intersections(z: np.ndarray) -> np.ndarray:
    """Per sample: do two non-adjacent segments of the chain intersect or touch?

    Parameters
    ----------
    z : ndarray of complex, shape (..., m)
        Joints of each sampled chain, ``x + iy`` in mm.

    Returns
    -------
    ndarray of bool, shape (...)
    """
    zf = z.reshape(-1, z.shape[-1])
    out = _self_intersections(np.ascontiguousarray(zf.real), np.ascontiguousarray(zf.imag))
    return out.reshape(z.shape[:-1])


def touches_area(z: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Per sample: does the chain touch the polygon (a joint inside, or a segment on its edges)?

    Parameters
    ----------
    z : ndarray of complex, shape (..., m)
        Joints of each sampled chain, ``x + iy`` in mm.
    edges : ndarray, shape (E, 2, 2)
        Boundary segments of the polygon, mm (see :func:`area_edges`).

    Returns
    -------
    ndarray of bool, shape (...)
    """
    zf = z.reshape(-1, z.shape[-1])
    out = _touches_area(
        np.ascontiguousarray(zf.real), np.ascontiguousarray(zf.imag), *_one_area(edges)
    )
    return out.reshape(z.shape[:-1])


def points_inside(points: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Even-odd inside test of points against a polygon's boundary segments.

    Parameters
    ----------
    points : ndarray, shape (..., 2)
        Points, mm.
    edges : ndarray, shape (E, 2, 2)
        Boundary segments of the polygon, mm.

    Returns
    -------
    ndarray of bool, shape (...)
    """
    flat = points.reshape(-1, 2)
    out = _inside_points(
        np.ascontiguousarray(flat[:, 0]), np.ascontiguousarray(flat[:, 1]), *_one_area(edges)
    )
    return out.reshape(points.shape[:-1])
