"""A panel's solids built face by face with OCP, no boolean.

The solids of :func:`origami_cad.fabrication.solids.panel_solids` are bounded by planes
(the footprint rings of :mod:`origami_cad.fabrication.panels` at their heights: outer
faces, chamfers of eq. 6, free sides, the crease layer) and by the vertical cylinders
of the string holes. When every hole lies well inside every footprint it crosses (a
convex panel, discs apart), those faces are known without any boolean: each solid is
assembled here from its faces, with shared vertices and edges (``BRep_Builder``), the
same faces a boolean chain leaves (planes, one cylinder per hole with its seam).
:func:`fast_panel_solids` returns ``None`` when that does not hold, and the caller
builds with booleans. Each solid's faces are kept as plain data too (:class:`Facets`,
from :func:`fast_panel_build`): the exports mesh the solid from them
(:func:`origami_cad.fabrication.polymesh.facets_mesh`), not through OCC.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from build123d import Solid
from OCP.BRep import BRep_Builder, BRep_Tool
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeVertex
from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder
from OCP.Geom import Geom_Plane
from OCP.gp import gp_Ax2, gp_Dir, gp_Pln, gp_Pnt
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FORWARD, TopAbs_REVERSED
from OCP.TopExp import TopExp, TopExp_Explorer
from OCP.TopoDS import TopoDS, TopoDS_Face, TopoDS_Shell, TopoDS_Solid, TopoDS_Wire

from origami_cad.fabrication.panels import PanelOutline, shell_of
from origami_cad.fabrication.params import FabricationParams
from origami_cad.pattern.model import Hole

__all__ = [
    "HOLE_CLEARANCE",
    "Cap",
    "Facets",
    "cup",
    "fast_panel_build",
    "fast_panel_solids",
    "frustum",
    "holes_clear",
    "newell_normal",
]

#: Least distance (mm) between a hole's wall and any footprint ring or other hole for
#: :func:`fast_panel_solids` to build without booleans.
HOLE_CLEARANCE = 1e-3
#: Vertex tolerance, mm (OCC's ``Precision::Confusion``)
_TOL = 1e-7


#: A hole's circle in a horizontal face: centre x, y and radius, mm.
Disc = tuple[float, float, float]


@dataclass(frozen=True)
class Cap:
    """A horizontal face of a :class:`Facets` solid, mm.

    ``outer`` runs counter-clockwise seen from above, ``inner`` rings clockwise (all
    corners at height ``z``, no corner repeated); ``discs`` are the holes' circles
    through it; the face's normal points up (``up``) or down.
    """

    z: float
    up: bool
    outer: list[tuple[float, float, float]]
    inner: list[list[tuple[float, float, float]]]
    discs: list[Disc]


@dataclass
class Facets:
    """The faces of a solid assembled here, as plain data (mm): what its mesh is made of.

    ``polygons``: planar faces, corners counter-clockwise seen from outside (the same
    point tuples as the B-rep's vertices); ``caps``: the horizontal faces, which may hold
    rings and the holes' circles; ``walls``: the holes' cylinders, ``(x, y, radius, z0,
    z1)``, whose faces look into the hole.
    """

    polygons: list[list[tuple[float, float, float]]] = field(default_factory=list)
    caps: list[Cap] = field(default_factory=list)
    walls: list[tuple[float, float, float, float, float]] = field(default_factory=list)

    def volume(self) -> float:
        """The solid's volume, mm^3, exactly: the flux of the field ``(0, 0, z)`` through
        its faces (vertical faces, the holes' walls among them, carry none)."""
        total = 0.0
        for cap in self.caps:
            area = abs(_area(cap.outer)) - sum(abs(_area(r)) for r in cap.inner)
            area -= sum(math.pi * r * r for _, _, r in cap.discs)
            total += cap.z * area if cap.up else -cap.z * area
        for points in self.polygons:  # a fan: each triangle's z-area times its mean z
            x0, y0, z0 = points[0]
            for (x1, y1, z1), (x2, y2, z2) in itertools.pairwise(points[1:]):
                up = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0)
                total += up * (z0 + z1 + z2) / 6.0
        return total


def newell_normal(points: list[tuple]) -> tuple[float, float, float]:
    """Newell's normal of a polygon of ``(x, y, z)`` corners (mm): twice its area vector,
    mm^2, pointing where the corners turn anticlockwise."""
    nx = ny = nz = 0.0
    for (x0, y0, z0), (x1, y1, z1) in zip(points, points[1:] + points[:1], strict=True):
        nx += (y0 - y1) * (z0 + z1)
        ny += (z0 - z1) * (x0 + x1)
        nz += (x0 - x1) * (y0 + y1)
    return nx, ny, nz


def _area(ring: list[tuple]) -> float:
    """The signed area (mm^2, anticlockwise positive) of a ring seen from above."""
    return 0.5 * sum(
        x0 * y1 - x1 * y0
        for (x0, y0, *_), (x1, y1, *_) in zip(ring, ring[1:] + ring[:1], strict=True)
    )


class _Builder:
    """One solid's faces, sharing vertices and edges keyed by their points; the faces
    recorded as plain data too (``facets``)."""

    def __init__(self) -> None:
        self.brep = BRep_Builder()
        self.vertices: dict[tuple, object] = {}
        self.edges: dict[tuple, object] = {}
        self.faces: list = []
        self.facets = Facets()

    def _edge(self, a: tuple, b: tuple):
        key = (a, b) if a < b else (b, a)
        edge = self.edges.get(key)
        if edge is None:
            v = [self.vertices.get(p) for p in key]
            for i, p in enumerate(key):
                if v[i] is None:
                    v[i] = self.vertices[p] = BRepBuilderAPI_MakeVertex(gp_Pnt(*p)).Vertex()
            edge = self.edges[key] = BRepBuilderAPI_MakeEdge(v[0], v[1]).Edge()
        return edge.Oriented(TopAbs_FORWARD if key[0] == a else TopAbs_REVERSED)

    def _wire(self, points: list[tuple]) -> TopoDS_Wire:
        wire = TopoDS_Wire()
        self.brep.MakeWire(wire)
        for i, p in enumerate(points):
            self.brep.Add(wire, self._edge(p, points[(i + 1) % len(points)]))
        wire.Closed(True)
        return wire

    def face(self, plane: gp_Pln, outer: list[tuple], inner=(), circles=()) -> None:
        """A planar face: ``outer`` counter-clockwise about the plane's normal, ``inner``
        polygons clockwise, ``circles`` closed edges oriented clockwise."""
        face = TopoDS_Face()
        self.brep.MakeFace(face, Geom_Plane(plane), _TOL)
        self.brep.Add(face, self._wire(outer))
        for ring in inner:
            self.brep.Add(face, self._wire(ring))
        for edge in circles:
            wire = TopoDS_Wire()
            self.brep.MakeWire(wire)
            self.brep.Add(wire, edge)
            wire.Closed(True)
            self.brep.Add(face, wire)
        self.faces.append(face)

    def polygon(self, points: list[tuple]) -> None:
        """The planar face through ``points`` (counter-clockwise seen from outside);
        nothing when they collapse to a segment. Raises ``ValueError`` if not planar."""
        points = [p for i, p in enumerate(points) if p != points[i - 1]]
        if len(points) < 3:
            return
        m = len(points)
        c = [sum(p[i] for p in points) / m for i in range(3)]
        n = newell_normal(points)
        norm = math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
        n = [x / norm for x in n]
        if max(abs(sum((p[i] - c[i]) * n[i] for i in range(3))) for p in points) > _TOL / 10:
            raise ValueError("not planar")
        self.face(gp_Pln(gp_Pnt(*c), gp_Dir(*n)), points)
        self.facets.polygons.append(points)

    def solid(self) -> Solid:
        shell = TopoDS_Shell()
        self.brep.MakeShell(shell)
        for face in self.faces:
            self.brep.Add(shell, face)
        shell.Closed(True)
        solid = TopoDS_Solid()
        self.brep.MakeSolid(solid)
        self.brep.Add(solid, shell)
        return Solid(solid)


def _ring(ring: np.ndarray, z: float) -> list[tuple]:
    """A footprint ring at height ``z`` as point tuples, one per corner; corners within
    1e-9 mm of the one before (a vanished edge) are that same point."""
    pts = [(float(x), float(y), float(z)) for x, y in np.asarray(ring, dtype=float)]
    for i in range(1, len(pts)):
        if math.dist(pts[i], pts[i - 1]) <= 1e-9:
            pts[i] = pts[i - 1]
    i = len(pts) - 1
    while i > 0 and math.dist(pts[i], pts[0]) <= 1e-9:
        pts[i] = pts[0]
        i -= 1
    return pts


def _distinct(points: list[tuple]) -> list[tuple]:
    return [p for i, p in enumerate(points) if p != points[i - 1]]


def _cap(b: _Builder, ring: list[tuple], up: bool, inner=(), circles=()) -> None:
    """The horizontal face of ``ring`` (counter-clockwise seen from above), its normal up
    or down, less ``inner`` rings (counter-clockwise) and the holes' ``circles``
    (``(edge, disc)`` pairs of :func:`_cylinders`)."""
    z = ring[0][2]
    plane = gp_Pln(gp_Pnt(0.0, 0.0, z), gp_Dir(0.0, 0.0, 1.0 if up else -1.0))
    outer = _distinct(ring if up else ring[::-1])
    holes = [_distinct(r[::-1] if up else r) for r in inner]
    turn = TopAbs_REVERSED if up else TopAbs_FORWARD  # circles run anticlockwise from above
    b.face(plane, outer, holes, [c.Oriented(turn) for c, _ in circles])
    b.facets.caps.append(
        Cap(z, up, _distinct(ring), [_distinct(r[::-1]) for r in inner], [d for _, d in circles])
    )


def _band(b: _Builder, lo: list[tuple], hi: list[tuple], outward: bool = True) -> None:
    """The side faces between rings ``lo`` (below) and ``hi`` of corresponding corners;
    their normals out of the ring (``outward``) or into it."""
    k = len(lo)
    for i in range(k):
        j = (i + 1) % k
        quad = [lo[i], lo[j], hi[j], hi[i]]
        b.polygon(quad if outward else quad[::-1])


def _cylinders(b: _Builder, holes: Sequence[Hole], z0: float, z1: float) -> tuple[list, list]:
    """The holes' walls from ``z0`` to ``z1`` (normals into the hole); their bottom and
    top circles, as ``(edge, disc)``: the edge run anticlockwise seen from above."""
    bottom, top = [], []
    for h in holes:
        disc = (float(h.x), float(h.y), h.diameter / 2.0)
        b.facets.walls.append((*disc, z0, z1))
        axes = gp_Ax2(gp_Pnt(h.x, h.y, z0), gp_Dir(0.0, 0.0, 1.0), gp_Dir(1.0, 0.0, 0.0))
        wall = BRepPrimAPI_MakeCylinder(axes, h.diameter / 2.0, z1 - z0).Face()
        explorer = TopExp_Explorer(wall, TopAbs_EDGE)
        while explorer.More():
            edge = TopoDS.Edge(explorer.Current())
            first, last = TopExp.FirstVertex_s(edge), TopExp.LastVertex_s(edge)
            if first.IsSame(last):
                z = BRep_Tool.Pnt_s(first).Z()
                circle = (edge.Oriented(TopAbs_FORWARD), disc)
                (bottom if abs(z - z0) < abs(z - z1) else top).append(circle)
            explorer.Next()
        b.faces.append(TopoDS.Face(wall.Reversed()))
    return bottom, top


def frustum(
    lo: np.ndarray, z_lo: float, hi: np.ndarray, z_hi: float, holes: Sequence[Hole] = ()
) -> tuple[Solid, Facets]:
    """The polyhedron between two rings of corresponding corners (counter-clockwise),
    ``lo`` at ``z_lo`` below ``hi`` at ``z_hi``, less the holes' vertical cylinders; and
    its faces as data."""
    b = _Builder()
    bottom, top = _cylinders(b, holes, z_lo, z_hi)
    ring_lo, ring_hi = _ring(lo, z_lo), _ring(hi, z_hi)
    _cap(b, ring_lo, False, circles=bottom)
    _cap(b, ring_hi, True, circles=top)
    _band(b, ring_lo, ring_hi)
    return b.solid(), b.facets


def cup(whole: tuple, core: tuple, holes: Sequence[Hole], open_up: bool) -> tuple[Solid, Facets]:
    """``whole`` less ``core`` and the holes: each ``(lo ring, z_lo, hi ring, z_hi)``,
    the core inside the whole and flush with its top (``open_up``) or bottom; and its
    faces as data."""
    a, za, bb, zb = whole
    c, zc, d, zd = core
    b = _Builder()
    ring_a, ring_b, ring_c, ring_d = _ring(a, za), _ring(bb, zb), _ring(c, zc), _ring(d, zd)
    if open_up:  # the floor: za .. zc
        bottom, top = _cylinders(b, holes, za, zc)
        _cap(b, ring_a, False, circles=bottom)
        _cap(b, ring_b, True, inner=[ring_d])
        _cap(b, ring_c, True, circles=top)
    else:  # the roof: zd .. zb
        bottom, top = _cylinders(b, holes, zd, zb)
        _cap(b, ring_a, False, inner=[ring_c])
        _cap(b, ring_b, True, circles=top)
        _cap(b, ring_d, False, circles=bottom)
    _band(b, ring_a, ring_b)
    _band(b, ring_c, ring_d, outward=False)
    return b.solid(), b.facets


def _convex(ring: np.ndarray) -> bool:
    poly = shapely.Polygon(ring)
    return poly.is_valid and poly.area > 0 and abs(poly.convex_hull.area - poly.area) < 1e-9


def holes_clear(o: PanelOutline, holes: Sequence[Hole]) -> bool:
    """Whether every hole of the panel lies at least :data:`HOLE_CLEARANCE` inside every
    footprint of the panel (all convex) and apart from the others."""
    rings = [r for r in (o.outer, o.inner, o.infill_outer, o.infill_inner, o.midlayer) if len(r)]
    if not all(_convex(r) for r in rings):
        return False
    discs = [shapely.Point(h.x, h.y).buffer(h.diameter / 2.0 + HOLE_CLEARANCE) for h in holes]
    for ring in rings:
        poly = shapely.Polygon(ring)
        if not all(poly.contains(d) for d in discs):
            return False
    return all(not discs[i].intersects(discs[j]) for i in range(len(discs)) for j in range(i))


def fast_panel_solids(
    o: PanelOutline, holes: Sequence[Hole], params: FabricationParams
) -> dict[str, list[Solid]] | None:
    """The solids of :func:`~origami_cad.fabrication.solids.panel_solids`, assembled
    from their faces; ``None`` when the holes are not clear (:func:`holes_clear`) or a
    side face is not planar."""
    built = fast_panel_build(o, holes, params)
    return None if built is None else built[0]


def fast_panel_build(
    o: PanelOutline, holes: Sequence[Hole], params: FabricationParams
) -> tuple[dict[str, list[Solid]], dict[str, list[Facets]]] | None:
    """:func:`fast_panel_solids` and each solid's :class:`Facets` (the same keys and
    order); ``None`` when the solids are not built here."""
    if not holes_clear(o, holes):
        return None
    h, half, s = params.height, params.half_height, shell_of(o, params)
    lo_z, hi_z = half, half + params.thickness
    lower = (o.outer, 0.0, o.inner, lo_z)
    upper = (o.inner, hi_z, o.outer, h)
    lower_in = (o.infill_outer, s, o.infill_inner, lo_z)
    upper_in = (o.infill_inner, hi_z, o.infill_outer, h - s)
    try:
        built = {"halves": [frustum(*lower), frustum(*upper)]}
        if o.has_infill:
            built["infills"] = [frustum(*lower_in, holes), frustum(*upper_in, holes)]
            built["shells"] = [
                cup(lower, lower_in, holes, True),
                cup(upper, upper_in, holes, False),
            ]
        else:  # TPU alone: each half is its shell
            built["infills"] = []
            built["shells"] = [frustum(*lower, holes), frustum(*upper, holes)]
        built["midlayers"] = (
            [frustum(o.midlayer, lo_z, o.midlayer, hi_z, holes)] if o.has_midlayer else []
        )
    except ValueError:
        return None
    solids = {name: [solid for solid, _ in pairs] for name, pairs in built.items()}
    return solids, {name: [faces for _, faces in pairs] for name, pairs in built.items()}
