"""Panel outlines of the printed structure in 2D (plain data: NumPy arrays).

Every solid of a panel is bounded by planes parallel to its edges, so each
footprint is the panel polygon with every edge moved inward by its own offset:
crease edges by the chamfer's run at that height, border and cut edges by the
border margin. :func:`offset_ring` computes such polygons exactly (each corner
is the intersection of its two offset lines); on a convex panel a short side
that the inset makes vanish stays as a corner of zero length, and a panel too
small for its inset is refused instead of returning a broken polygon.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.ops import nearest_points, polylabel

from origami_cad.errors import PatternError
from origami_cad.fabrication.params import FabricationParams
from origami_cad.pattern.model import CreasePattern, Hole

__all__ = [
    "CUT_GAP",
    "FREE_EDGES",
    "MIN_PLA_WIDTH",
    "PanelOutline",
    "check_panels",
    "jog_corners",
    "offset_ring",
    "panel_fits",
    "panel_outline",
    "panel_outlines",
    "plan_holes",
    "printed_pattern",
    "ring_joins",
    "sheet_outline",
    "shell_of",
]

#: Edges whose sides are free (vertical walls, border margin): border and cut.
FREE_EDGES = ("B", "C")

#: Gap between neighbouring panels' halves on the crease layer, mm: each half stops
#: ``CREASE_GAP / 2`` short of its creases, so no two solids of the shells touch (they
#: would meet on the crease line, an edge of four triangles in ``shells.stl``). Far below
#: a slicer's resolution (PrusaSlicer closes gaps up to 0.049 mm), so it prints as before.
CREASE_GAP = 0.01

#: Kerf of a cut (assignment ``C``), mm: each side's solids stop ``CUT_GAP / 2`` short of
#: the cut line (beyond the border margin), and the crease sheet is cut along it
#: (:func:`sheet_outline`), so the two sides are apart in the model (each part's STL one
#: watertight mesh). As narrow as :data:`CREASE_GAP`, below a slicer's resolution, so the
#: two sides still print joined along the cut, to be parted with a blade after printing: a
#: kerf the slicer keeps (a nozzle line, 0.4 mm) would be wider than the crease layer's
#: inset, and the jog where a hinge and a cut meet on one line would turn over between the
#: panel's crease layer and outer face (no planar-faced solid).
CUT_GAP = CREASE_GAP

#: The narrowest PLA mid-layer patch a panel is printed with, mm: two lines of a 0.4 mm
#: nozzle, the least that is a patch rather than a lone line. A panel whose mid-layer would
#: hold no disc this wide does not fit its parameters (:func:`panel_outline`): the bias
#: search gives it a smaller inset, else prints it in TPU alone. PrusaSlicer does not drop
#: such slivers for us: 2.5.0, sliced at 0.45 mm lines and 0.1 mm layers, drops a strip
#: 0.1 mm wide but prints one 0.15 mm wide (Arachne widens it to a bead extruding as much
#: as a 0.3 mm strip, into the TPU around it; the classic generator gap-fills it).
MIN_PLA_WIDTH = 0.8

#: The sine of the largest turn (1 deg) at which :func:`offset_ring` joins two edges of
#: different kinds (a hinge and a border or cut) by a jog instead of the meeting of their
#: offset lines: there, lines 3 mm apart (the default bias against a border) would meet
#: 172 mm along the edge, so an edge an imported pattern draws in two nearly straight
#: pieces (a vertex 1 um off the line, as SVG's rounding leaves) keeps its jog.
_JOG_TURN = math.sin(math.radians(1.0))


def offset_ring(
    ring: np.ndarray,
    offsets: np.ndarray,
    label: str = "",
    what: str = "",
    kinds: np.ndarray | None = None,
) -> np.ndarray:
    """Move every edge of a counter-clockwise ring inward by its own offset (mm).

    Edge ``k`` joins ``ring[k]`` and ``ring[k + 1]``. Corners between collinear
    edges with equal offsets are dropped. Two collinear edges of different kinds
    (``kinds``, one per edge, default the offsets themselves: a hinge and a border on one
    line) are joined by a jog, as a CAD offset with per-edge distances draws them: a
    step across the corner, perpendicular to the line, from one offset line to the other
    (two points, equal when the two offsets are), so every ring made with the same
    ``kinds`` has the same points. On a convex panel without jogs, an edge that the
    offset makes vanish (a short edge between two converging creases, such as the
    0.734 mm border edge of the paper's Fig. 2 pattern) is kept as a corner of zero
    length: the ring keeps one point per edge, two of them equal, so the solids built
    between rings stay planar-faced. Raises :class:`PatternError` naming the panel
    when the panel is too small for its inset (fewer than three edges would remain),
    when two collinear edges of one kind have different offsets, or when an edge of a
    non-convex panel (or of one with a jog) would vanish or turn over.
    """
    pts = np.asarray(ring, dtype=float)
    off = np.asarray(offsets, dtype=float)
    kind = off if kinds is None else np.asarray(kinds)
    d = np.roll(pts, -1, axis=0) - pts
    length = np.hypot(d[:, 0], d[:, 1])
    u = d / length[:, None]
    n = np.column_stack([-u[:, 1], u[:, 0]])  # inward normal of a CCW ring
    base = pts + n * off[:, None]  # a point on each offset line
    a = np.roll(np.arange(len(pts)), 1)  # corner k joins edge a[k] to edge k
    cross = u[a, 0] * u[:, 1] - u[a, 1] * u[:, 0]
    collinear = np.abs(cross) < 1e-12
    jog = jog_corners(pts, kind)
    uneven = np.flatnonzero(collinear & ~jog & (np.abs(off[a] - off) > 1e-9))
    if uneven.size:
        k = uneven[0]
        raise PatternError(
            f"panel {label}: collinear edges with different insets at corner "
            f"({pts[k, 0]:.4g}, {pts[k, 1]:.4g}) mm"
        )
    if jog.any():
        return _offset_jogged(pts, u, n, base, off, a, cross, jog, label, what)
    keep_edges = np.flatnonzero(~collinear)
    a, b = a[keep_edges], keep_edges
    # base[a] + s u[a] = base[b] + r u[b]
    w = base[b] - base[a]
    s = (w[:, 0] * u[b, 1] - w[:, 1] * u[b, 0]) / cross[b]
    out = base[a] + s[:, None] * u[a]
    res = out.reshape(-1, 2)
    if len(res) < 3:
        raise PatternError(f"panel {label} is too small for the {what or 'inset'}")
    # every kept edge must keep its direction and a positive length
    e = np.roll(res, -1, axis=0) - res
    dots = np.einsum("ij,ij->i", e, u[keep_edges])
    poly = shapely.Polygon(res)
    if np.any(dots <= 1e-9) or not poly.is_valid or poly.area <= 0:
        convex = _is_convex(pts)
        if convex:
            return _offset_convex(
                pts[keep_edges], u[keep_edges], n[keep_edges], base[keep_edges], label, what
            )
        raise PatternError(
            f"panel {label} is too small for the {what or 'inset'} (an edge would vanish)"
        )
    return res


def jog_corners(ring: np.ndarray, kinds) -> np.ndarray:
    """Which corners of a ring (mm; corner ``k`` starts edge ``k``) :func:`offset_ring` joins
    by a jog: straight or nearly (a turn under 1 deg) between edges of different ``kinds``."""
    pts = np.asarray(ring, dtype=float)
    kind = np.asarray(kinds)
    d = np.roll(pts, -1, axis=0) - pts
    u = d / np.hypot(d[:, 0], d[:, 1])[:, None]
    a = np.roll(np.arange(len(pts)), 1)
    cross = u[a, 0] * u[:, 1] - u[a, 1] * u[:, 0]
    dot = np.einsum("ij,ij->i", u[a], u)
    return (np.abs(cross) < _JOG_TURN) & (dot > 0) & (kind[a] != kind)


def _offset_jogged(pts, u, n, base, off, a, cross, jog, label: str, what: str) -> np.ndarray:
    """:func:`offset_ring` of a ring with jogs (``jog``: the corners, straight or nearly,
    between edges of different kinds; mm). Every other turning corner is the meeting of its
    two offset lines; a jog corner ``k`` gives two points, where the line through it along
    the mean of its two edges' inward normals meets the offset line of the edge before it,
    then that of edge ``k`` (so the jogs of every ring of a panel lie on one line, and the
    solids' faces between them are planar). Straight corners between edges of one kind
    (equal offsets) are dropped. :class:`PatternError` when an edge vanishes or turns over,
    or the ring is no longer simple."""
    points: list[np.ndarray] = []
    along: list[np.ndarray | None] = []  # the direction each edge of the result keeps
    for k in range(len(pts)):
        j = a[k]
        if jog[k]:
            m = n[j] + n[k]
            m /= np.hypot(m[0], m[1])
            for e in (j, k):  # base[e] + s u[e] on the line pts[k] + t m
                w = pts[k] - base[e]
                s = (w[0] * m[1] - w[1] * m[0]) / (u[e, 0] * m[1] - u[e, 1] * m[0])
                points.append(base[e] + s * u[e])
            along += [None, u[k]]
        elif abs(cross[k]) >= 1e-12:
            w = base[k] - base[j]
            s = (w[0] * u[k, 1] - w[1] * u[k, 0]) / cross[k]
            points.append(base[j] + s * u[j])
            along.append(u[k])
    res = np.array(points)
    too_small = PatternError(
        f"panel {label} is too small for the {what or 'inset'} (an edge would vanish)"
    )
    if len(res) < 3:
        raise too_small
    e = np.roll(res, -1, axis=0) - res
    poly = shapely.Polygon(res)
    turned = any(v is not None and float(e[i] @ v) <= 1e-9 for i, v in enumerate(along))
    if turned or not poly.is_valid or poly.area <= 0:
        raise too_small
    return res


def _is_convex(pts: np.ndarray) -> bool:
    d = np.roll(pts, -1, axis=0) - pts
    cross = d[:, 0] * np.roll(d, -1, axis=0)[:, 1] - d[:, 1] * np.roll(d, -1, axis=0)[:, 0]
    return bool(np.all(cross >= -1e-9 * np.max(np.abs(d)) ** 2))


def _offset_convex(
    pts: np.ndarray, u: np.ndarray, n: np.ndarray, base: np.ndarray, label: str, what: str
) -> np.ndarray:
    """The offset of a convex ring as the intersection of its edges' inner half-planes.

    ``pts[k]`` starts edge ``k`` (unit direction ``u[k]``, inward normal ``n[k]``, offset
    line through ``base[k]``). Returns one point per edge: the start of the edge's side
    of the result, or, for an edge that vanished, the start of the next edge that did not.
    """
    size = float(np.ptp(pts, axis=0).max()) * 4.0 + 1.0
    region = shapely.Polygon(pts)
    for k in range(len(pts)):
        b, uk, nk = base[k], u[k], n[k]
        half = shapely.Polygon(
            [b - uk * size, b + uk * size, b + uk * size + nk * size, b - uk * size + nk * size]
        )
        region = region.intersection(half)
    too_small = PatternError(f"panel {label} is too small for the {what or 'inset'}")
    if region.is_empty or region.geom_type != "Polygon" or region.area <= 1e-9:
        raise too_small
    corners = shapely.get_coordinates(shapely.geometry.polygon.orient(region, 1).exterior)[:-1]
    starts: list[np.ndarray | None] = []
    for k in range(len(pts)):
        dist = np.abs((corners - base[k]) @ n[k])
        on = corners[dist < 1e-7]
        along = (on - base[k]) @ u[k] if len(on) else np.zeros(0)
        if len(on) >= 2 and np.ptp(along) > 1e-9:
            starts.append(on[np.argmin(along)])
        else:
            starts.append(None)
    alive = [k for k, p in enumerate(starts) if p is not None]
    if len(alive) < 3:
        raise too_small
    out = np.empty_like(pts)
    for k in range(len(pts)):
        j = k
        while starts[j % len(pts)] is None:
            j += 1
        out[k] = starts[j % len(pts)]
    return out


@dataclass(frozen=True)
class PanelOutline:
    """The footprints of one panel's solids (mm, counter-clockwise rings).

    Attributes
    ----------
    index, label : int, str
        The face of the pattern.
    polygon : ndarray (k, 2)
        The panel as drawn in the crease pattern.
    crease_edge : ndarray of bool (k,)
        Which sides are creases (chamfered) rather than free edges.
    inner : ndarray (k, 2)
        Footprint of each half on the crease layer (creases at offset ``CREASE_GAP / 2``).
    outer : ndarray (k, 2)
        Outer face of each half (creases at offset ``b``).
    infill_inner, infill_outer : ndarray (k, 2)
        Footprints of the infill on the crease layer and at ``s`` below the outer face;
        ``(0, 2)`` for a panel printed in TPU alone (too small for any PLA infill).
    midlayer : ndarray (k, 2)
        The mid-layer patch (creases at offset ``b + m``); ``(0, 2)`` for a panel printed
        without one (in TPU alone: the crease sheet runs through it).
    region : tuple of tuple of ndarray (k, 2)
        Maximum operation region, where holes may go: for each of its polygons,
        the exterior ring then any interior rings, closed (first point repeated).
        Empty when nothing is left. :meth:`region_polygon` gives it as shapely.
    shell : float or None
        The shell wall ``s`` the footprints were made for, mm (``None``: ``params.shell``
        of the solids built from them). :func:`shell_of` gives the one to build with.
    midlayer_bias : float or None
        The mid-layer's margin ``m`` the footprints were made for, mm (``None``:
        ``params.midlayer_bias``).
    """

    index: int
    label: str
    polygon: np.ndarray
    crease_edge: np.ndarray
    inner: np.ndarray
    outer: np.ndarray
    infill_inner: np.ndarray
    infill_outer: np.ndarray
    midlayer: np.ndarray
    region: tuple[tuple[np.ndarray, ...], ...]
    shell: float | None = None
    midlayer_bias: float | None = None

    @property
    def has_infill(self) -> bool:
        """Whether the panel has PLA infills (``False``: its halves are TPU alone)."""
        return len(self.infill_inner) > 0

    @property
    def has_midlayer(self) -> bool:
        """Whether the panel has a PLA mid-layer (``False``: the crease sheet runs through)."""
        return len(self.midlayer) > 0

    def region_polygon(self) -> shapely.Polygon | shapely.MultiPolygon:
        """The operation region as a shapely geometry (empty if nothing is left)."""
        polys = [shapely.Polygon(rings[0], rings[1:]) for rings in self.region]
        if len(polys) == 1:
            return polys[0]
        return shapely.MultiPolygon(polys) if polys else shapely.Polygon()


def _rings(region: shapely.Polygon | shapely.MultiPolygon) -> tuple[tuple[np.ndarray, ...], ...]:
    """Every polygon of ``region`` as closed coordinate rings, exterior first."""
    if region.is_empty:
        return ()
    return tuple(
        tuple(shapely.get_coordinates(r) for r in (poly.exterior, *poly.interiors))
        for poly in shapely.get_parts(region)
    )


def panel_outlines(
    cp: CreasePattern, params: FabricationParams, biases: np.ndarray | None = None
) -> list[PanelOutline]:
    """The footprints of every panel of ``cp`` (see :class:`PanelOutline`).

    ``biases`` (one per panel, mm) replaces ``params.bias`` panel by panel (default: every
    panel at ``params.bias``).
    """
    check_panels(cp)
    if biases is None:
        return [panel_outline(cp, fi, params) for fi in range(len(cp.faces))]
    return [panel_outline(cp, fi, params, float(b)) for fi, b in enumerate(biases)]


def printed_pattern(cp: CreasePattern) -> CreasePattern:
    """The pattern whose faces are the printed panels: the faces of ``cp`` merged across its
    facet creases (assignment ``F``: kept flat, never printed as hinges). ``cp`` itself when
    it has none. The vertices stay as they are (same indices, mm), so a folded state of
    ``cp`` places the merged panels too; the merged faces get the default labels."""
    flat = cp.assignments == "F"
    if not flat.any():
        return cp
    keep = ~flat
    return CreasePattern(
        cp.vertices,
        cp.edges[keep],
        cp.assignments[keep],
        cp.fold_angles[keep],
        holes=cp.holes,
        metadata=cp.metadata,
        tolerance=cp.tolerance,
    )


def check_panels(cp: CreasePattern) -> None:
    """Refuse a pattern without panels, or with a panel that is not a simple polygon
    (:class:`PatternError` naming it, and where)."""
    problems = [p for p in cp.check() if p.code in ("face-not-simple", "face-with-hole")]
    if problems:
        where = problems[0].location
        at = f" around ({where[0]:.4g}, {where[1]:.4g}) mm" if where is not None else ""
        raise PatternError(f"cannot fabricate: {problems[0].message}{at}")
    if not cp.faces:
        raise PatternError("cannot fabricate: the pattern has no panels")


def ring_joins(source: CreasePattern) -> tuple[list[int], CreasePattern | None]:
    """Facet creases (``F`` edges) of ``source`` that, printed as hinges that stay flat
    (assignment ``J``), leave no printed panel enclosing another part of the pattern, and
    ``source`` with them so: for each panel (faces joined across facet creases) that is a
    ring, two of its facet creases from its inner outline to its outer one (the shortest,
    and the one farthest from it), which split it in two. ``([], None)`` when a ring has
    no two such creases, or the pattern with them still has a ring."""
    polys, chosen = source.face_polygons(), []
    near = 2.0 * source.tolerance
    for faces in source.panels():
        shape = shapely.union_all(polys[list(faces)])
        if shape.geom_type != "Polygon" or not shape.interiors:
            continue
        inner = shapely.MultiLineString([ring.coords for ring in shape.interiors])
        sides = np.unique(np.concatenate([source.face_edges[f] for f in faces]))
        flat = sides[(sides >= 0) & (source.assignments[sides] == "F")]
        ends = shapely.points(source.vertices[source.edges[flat]])  # (k, 2)
        on_inner = shapely.dwithin(ends, inner, near).any(axis=1)
        spans = flat[on_inner & shapely.dwithin(ends, shape.exterior, near).any(axis=1)]
        if len(spans) < 2:
            return [], None
        mids = source.vertices[source.edges[spans]].mean(axis=1)
        first = int(np.argmin(source.edge_lengths()[spans]))
        far = int(np.argmax(np.linalg.norm(mids - mids[first], axis=1)))
        chosen += [int(spans[first]), int(spans[far])]
    if not chosen:
        return [], None
    assign = source.assignments.copy()
    assign[chosen] = "J"
    joined = CreasePattern(
        source.vertices,
        source.edges,
        assign,
        source.fold_angles,
        holes=source.holes,
        metadata=source.metadata,
        tolerance=source.tolerance,
    )
    left = [p for p in printed_pattern(joined).check() if p.code == "face-with-hole"]
    return ([], None) if left else (sorted(chosen), joined)


def panel_outline(
    cp: CreasePattern,
    fi: int,
    params: FabricationParams,
    bias: float | None = None,
    shell: float | None = None,
    midlayer_bias: float | None = None,
    tpu_only: bool = False,
) -> PanelOutline:
    """The footprints of panel (face) ``fi`` of ``cp`` at inner bias ``bias`` (mm, default
    ``params.bias``), shell wall ``shell`` (mm, default ``params.shell``) and mid-layer margin
    ``midlayer_bias`` (mm, default ``params.midlayer_bias``); ``tpu_only``: the halves alone,
    printed in TPU (no infill, no mid-layer, no operation region). :class:`PatternError`
    naming the panel when it is too small for them. The pattern itself is not checked
    (:func:`panel_outlines` does)."""
    b = params.bias if bias is None else bias
    s = params.shell if shell is None else shell
    m = params.midlayer_bias if midlayer_bias is None else midlayer_bias
    half = params.half_height
    margin = params.border_margin
    slope = b / half  # horizontal run of a chamfer per mm of height
    wall = s * math.hypot(half, b) / half  # horizontal width of a wall s thick along a chamfer
    ring, sides = cp.faces[fi], cp.face_edges[fi]
    label = cp.face_labels[fi]
    poly = cp.vertices[ring]
    crease = ~np.isin(cp.assignments[sides], FREE_EDGES)

    cut = cp.assignments[sides] == "C"
    kinds = np.where(crease, 0, np.where(cut, 2, 1))  # a jog where a hinge meets a cut
    jogs = np.flatnonzero(jog_corners(poly, kinds))
    if margin > 0 and jogs.size:  # the jog would turn over between the crease layer and face
        x, y = poly[jogs[0]]
        raise PatternError(
            f"panel {label}: a hinge and a free edge on one line at corner ({x:.4g}, {y:.4g}) "
            f"mm take no border margin (border_margin = {margin:g} mm; use 0)"
        )

    def inset(crease_off: float, free_off: float, what: str) -> np.ndarray:
        free = free_off + np.where(cut, CUT_GAP / 2.0, 0.0)
        return offset_ring(poly, np.where(crease, crease_off, free), label, what, kinds)

    inner = inset(CREASE_GAP / 2, margin, "crease layer")
    outer = inset(b, margin, f"inner bias b = {b:g} mm")
    if tpu_only:
        none = np.zeros((0, 2))
        return PanelOutline(fi, label, poly, crease, inner, outer, none, none, none, (), s, m)
    infill_inner = inset(wall, margin + s, "shell wall")
    infill_outer = inset((half - s) * slope + wall, margin + s, "shell wall")
    mid = inset(b + m, margin + m, f"mid-layer bias b + m = {b + m:g} mm")
    if shapely.Polygon(mid).buffer(-MIN_PLA_WIDTH / 2.0).is_empty:
        raise PatternError(
            f"panel {label} is too small for the mid-layer bias b + m = {b + m:g} mm: its "
            f"PLA mid-layer would be narrower than {MIN_PLA_WIDTH:g} mm"
        )
    region = (
        shapely.Polygon(outer).buffer(-s, join_style="mitre").intersection(shapely.Polygon(mid))
    )
    return PanelOutline(
        fi,
        label,
        poly,
        crease,
        inner,
        outer,
        infill_inner,
        infill_outer,
        mid,
        _rings(region),
        s,
        None if midlayer_bias is None else m,
    )


def sheet_outline(cp: CreasePattern) -> shapely.Polygon | shapely.MultiPolygon:
    """The printed sheet's outline, mm: the union of the panels of ``cp`` less a kerf
    :data:`CUT_GAP` wide along every cut (the cuts merged into chains first, so a cut
    running straight through a vertex leaves no step), its corners snapped to 0.1 um so that
    no sliver of an edge is left where kerfs meet. The union itself when ``cp`` has no cut."""
    sheet = shapely.union_all(cp.face_polygons())
    cuts = cp.edges[cp.assignments == "C"]
    if not len(cuts):
        return sheet
    chains = shapely.line_merge(shapely.multilinestrings(cp.vertices[cuts]))
    kerf = shapely.buffer(chains, CUT_GAP / 2.0, cap_style="flat", join_style="mitre")
    return shapely.set_precision(shapely.difference(sheet, kerf), 1e-4)


def shell_of(o: PanelOutline, params: FabricationParams) -> float:
    """The shell wall the solids of panel ``o`` are built with, mm: the one its footprints
    were made for (``o.shell``), else ``params.shell``."""
    return params.shell if o.shell is None else float(o.shell)


def _centred_pole(region) -> shapely.Point:
    """The pole of inaccessibility, ties broken toward the centroid.

    Points whose clearance is within 1 % of the best form a segment in a
    parallelogram; the one nearest the centroid keeps holes centred.
    """
    pole = polylabel(region, tolerance=0.001)
    best = region.exterior.distance(pole)
    core = region.buffer(-0.99 * best)
    if core.is_empty:
        return pole
    centroid = region.centroid
    if core.contains(centroid):
        return centroid
    return nearest_points(core, centroid)[0]


def plan_holes(
    cp: CreasePattern,
    outlines: list[PanelOutline],
    params: FabricationParams,
    without: frozenset[int] = frozenset(),
) -> tuple[tuple[Hole, ...], np.ndarray]:
    """The holes following ``params.holes`` and the panel each one goes through.

    ``without``: panels (face indices) that get no automatic hole (too small for one).

    ``auto`` puts one hole per panel at the pole of inaccessibility of its
    operation region (the centre of its largest inscribed circle; among nearly
    equal candidates, the one nearest the centroid); a panel whose region
    cannot hold the hole is an error naming it (never a silently shifted or
    dropped hole).

    Returns
    -------
    holes : tuple of Hole
        Centres and diameters, mm.
    panels : ndarray of int, shape (len(holes),)
        Index of the panel (face of ``cp``) of each hole.
    """
    spec = params.holes
    diameter = params.hole_diameter
    if spec == "none":
        return (), np.zeros(0, dtype=np.int64)
    if spec == "auto":
        placed = [(o.index, _auto_hole(o, diameter)) for o in outlines if o.index not in without]
    else:
        points = (
            [(h.x, h.y, h.diameter) for h in cp.holes]
            if spec == "pattern"
            else [(x, y, diameter) for x, y in spec]
        )
        by_index = {o.index: o for o in outlines}
        faces = cp.faces_of_points(np.array([(x, y) for x, y, _ in points]).reshape(-1, 2))
        placed = [
            _given_hole(int(fi), by_index, k, x, y, d)
            for k, ((x, y, d), fi) in enumerate(zip(points, faces.tolist(), strict=True))
        ]
    return tuple(h for _, h in placed), np.array([i for i, _ in placed], dtype=np.int64)


def _auto_hole(o: PanelOutline, diameter: float) -> Hole:
    region = o.region_polygon()
    if region.is_empty:
        raise PatternError(f"panel {o.label}: no operation region left for a hole")
    centre = _centred_pole(region)
    room = region.exterior.distance(centre)
    if room < diameter / 2.0:
        raise PatternError(
            f"panel {o.label}: a {diameter:g} mm hole does not fit its operation region "
            f"(room for {2 * room:.3g} mm); use a smaller hole_diameter or holes = 'none'"
        )
    return Hole(float(centre.x), float(centre.y), diameter)


def panel_fits(
    cp: CreasePattern,
    fi: int,
    params: FabricationParams,
    bias: float,
    holes: tuple[tuple[float, float, float], ...] = (),
    auto_hole: bool = True,
    shell: float | None = None,
    midlayer_bias: float | None = None,
    tpu_only: bool = False,
) -> bool:
    """Whether panel (face) ``fi`` keeps its footprints at inner bias ``bias`` (mm), shell
    wall ``shell`` (mm, default ``params.shell``) and mid-layer margin ``midlayer_bias`` (mm,
    default ``params.midlayer_bias``), or as TPU alone (``tpu_only``: no hole fits then), and
    room for its hole: the automatic one (``params.holes == "auto"`` and ``auto_hole``) or
    ``holes`` ((x, y, diameter) mm, the given holes on this panel)."""
    try:
        o = panel_outline(cp, fi, params, bias, shell, midlayer_bias, tpu_only)
        if params.holes == "auto" and auto_hole:
            _auto_hole(o, params.hole_diameter)
    except PatternError:
        return False
    region = o.region_polygon()
    return all(
        region.contains(shapely.Point(x, y).buffer(d / 2.0, quad_segs=32)) for x, y, d in holes
    )


def _given_hole(
    fi: int, by_index: dict[int, PanelOutline], k: int, x: float, y: float, d: float
) -> tuple[int, Hole]:
    """The hole ``k`` at ``(x, y)`` (diameter ``d``) on face ``fi`` (-1: none), checked."""
    if fi < 0:
        raise PatternError(f"hole {k} at ({x:g}, {y:g}) mm is not on any panel")
    o = by_index[fi]
    disc = shapely.Point(x, y).buffer(d / 2.0, quad_segs=32)
    if not o.region_polygon().contains(disc):
        raise PatternError(
            f"hole {k} at ({x:g}, {y:g}) mm (diameter {d:g} mm) does not fit the operation "
            f"region of panel {o.label}"
        )
    return fi, Hole(float(x), float(y), float(d))
