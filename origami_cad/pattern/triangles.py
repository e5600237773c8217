"""Panels cut into triangles of their own vertices (mm, the flat pattern's plane).

One triangulation for every stage that needs triangles: the bar-and-hinge model's facets
(``simulation``) and the glTF meshes of a folding (``viz``). A convex panel is a fan from
its first vertex (unless vertices along a side would make slivers); a non-convex one (an
L-shaped border panel) is shapely's constrained Delaunay triangulation, whose corners
are the panel's own vertices, so the triangles follow the vertices into any folded state.
Every triangle is counter-clockwise seen from +z, as the panels are.
"""

from __future__ import annotations

import numpy as np
import shapely

from origami_cad.pattern.model import CreasePattern

__all__ = ["panel_triangles", "triangulate_panel"]


def triangulate_panel(cp: CreasePattern, ring) -> list[tuple[int, int, int]]:
    """The triangles (vertex index triples, counter-clockwise) of one panel of ``cp``.

    ``ring`` is the panel's vertex indices in order (an entry of ``cp.faces``).
    """
    ring = np.asarray(ring)
    if len(ring) == 3:
        return [tuple(int(v) for v in ring)]
    pts = cp.vertices[ring]
    poly = shapely.Polygon(pts)
    if poly.convex_hull.area - poly.area <= 1e-9 * poly.area:  # convex: a fan
        fan = [(int(ring[0]), int(ring[k]), int(ring[k + 1])) for k in range(1, len(ring) - 1)]
        a, b, c = (cp.vertices[list(t)] for t in zip(*fan, strict=True))
        u, w = b - a, c - a
        areas = np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]) / 2
        if np.all(areas > 1e-6 * poly.area):  # (vertices along a side make slivers)
            return fan
    index = {(float(x), float(y)): int(v) for (x, y), v in zip(pts, ring, strict=True)}
    tris = []
    for tri in shapely.get_parts(shapely.constrained_delaunay_triangles(poly)):
        c = shapely.get_coordinates(tri)[:-1]
        t = [index[(float(x), float(y))] for x, y in c]
        a, b, d = cp.vertices[t]
        if (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]) < 0:
            t = [t[0], t[2], t[1]]
        tris.append(tuple(t))
    return tris


def panel_triangles(cp: CreasePattern) -> np.ndarray:
    """Every panel of ``cp`` triangulated, panel by panel: vertex index triples (t, 3)."""
    tris = [t for ring in cp.faces for t in triangulate_panel(cp, ring)]
    return np.array(tris, dtype=np.int64).reshape(-1, 3)
