"""The geometric predicates of the fitness (eq. 5), compiled with numba.

The one implementation of each test, run one design-sample at a time:
segments that touch count as intersecting; points on a polygon's boundary
follow the even-odd rule of a ray cast toward +x. The tests check them
against shapely.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["points_inside", "self_intersections", "touches_area"]


@njit(cache=True, inline="always")
def _touch(ax, ay, bx, by, cx, cy, dx, dy) -> bool:
    o1 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    o2 = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax)
    o3 = (dx - cx) * (ay - cy) - (dy - cy) * (ax - cx)
    o4 = (dx - cx) * (by - cy) - (dy - cy) * (bx - cx)
    if o1 * o2 > 0 or o3 * o4 > 0:
        return False
    return (
        min(ax, bx) <= max(cx, dx)
        and min(cx, dx) <= max(ax, bx)
        and min(ay, by) <= max(cy, dy)
        and min(cy, dy) <= max(ay, by)
    )


@njit(cache=True, inline="always")
def _row_self_touches(x: np.ndarray, y: np.ndarray, r: int) -> bool:
    m = x.shape[1]
    for i in range(m - 3):
        ax, ay, bx, by = x[r, i], y[r, i], x[r, i + 1], y[r, i + 1]
        for j in range(i + 2, m - 1):
            if _touch(ax, ay, bx, by, x[r, j], y[r, j], x[r, j + 1], y[r, j + 1]):
                return True
    return False


@njit(cache=True)
def _self_intersections(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    out = np.zeros(x.shape[0], dtype=np.bool_)
    for r in range(x.shape[0]):
        out[r] = _row_self_touches(x, y, r)
    return out


@njit(cache=True)
def _inside_one(px: float, py: float, edges: np.ndarray) -> bool:
    parity = False
    for e in range(edges.shape[0]):
        x0, y0, x1, y1 = edges[e, 0, 0], edges[e, 0, 1], edges[e, 1, 0], edges[e, 1, 1]
        if (y0 > py) != (y1 > py):
            x_at = x0 + (py - y0) * (x1 - x0) / (y1 - y0)
            if px < x_at:
                parity = not parity
    return parity


@njit(cache=True, inline="always")
def _row_touches_edges(x: np.ndarray, y: np.ndarray, r: int, edges: np.ndarray) -> bool:
    m = x.shape[1]
    for i in range(m):
        if _inside_one(x[r, i], y[r, i], edges):
            return True
    for i in range(m - 1):
        ax, ay, bx, by = x[r, i], y[r, i], x[r, i + 1], y[r, i + 1]
        for e in range(edges.shape[0]):
            cx, cy, dx, dy = edges[e, 0, 0], edges[e, 0, 1], edges[e, 1, 0], edges[e, 1, 1]
            if _touch(ax, ay, bx, by, cx, cy, dx, dy):
                return True
    return False


@njit(cache=True)
def _touches_area(x: np.ndarray, y: np.ndarray, edges: np.ndarray) -> np.ndarray:
    out = np.zeros(x.shape[0], dtype=np.bool_)
    lox, loy = edges[:, :, 0].min(), edges[:, :, 1].min()
    hix, hiy = edges[:, :, 0].max(), edges[:, :, 1].max()
    for r in range(x.shape[0]):
        if x[r].max() < lox or x[r].min() > hix or y[r].max() < loy or y[r].min() > hiy:
            continue
        out[r] = _row_touches_edges(x, y, r, edges)
    return out


@njit(cache=True)
def _inside_points(x: np.ndarray, y: np.ndarray, edges: np.ndarray) -> np.ndarray:
    out = np.zeros(x.shape[0], dtype=np.bool_)
    for r in range(x.shape[0]):
        out[r] = _inside_one(x[r], y[r], edges)
    return out


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
        Boundary segments of the polygon, mm (see :func:`~origami_cad.design.fitness.area_edges`).

    Returns
    -------
    ndarray of bool, shape (...)
    """
    zf = z.reshape(-1, z.shape[-1])
    out = _touches_area(
        np.ascontiguousarray(zf.real),
        np.ascontiguousarray(zf.imag),
        np.ascontiguousarray(edges, dtype=float),
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
        np.ascontiguousarray(flat[:, 0]),
        np.ascontiguousarray(flat[:, 1]),
        np.ascontiguousarray(edges, dtype=float),
    )
    return out.reshape(points.shape[:-1])
