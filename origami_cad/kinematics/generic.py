"""Rigid folding of imported patterns whose interior vertices are flat-foldable degree-4.

At such a vertex the fold angles obey two relations (Huffman; Tachi 2009; Evans et
al. 2015): opposite creases fold by equal magnitudes, and the two pairs are tied by
``tan(rho_b / 2) = c tan(rho_a / 2)`` with ``c`` fixed by the sector angles. Here
``c`` is computed from the vertex's spherical closure condition (the product of
the rotations about its creases is the identity), and the signs come from the
crease assignments (Maekawa: one opposite pair folds the same way, the other
opposite ways). :func:`fold_degree4` propagates the fold angles from one driving
crease over the crease graph, checks that every crease gets one value from all
its vertices (loop consistency), then places each panel by composing rotations
about the creases from a root panel and checks that every vertex lands in one
place.
"""

from __future__ import annotations

import math
import weakref
from collections import deque
from dataclasses import dataclass, field

import numpy as np

from origami_cad.errors import PatternError
from origami_cad.pattern.check import interior_vertices, kawasaki_residuals, kawasaki_tolerances
from origami_cad.pattern.model import CreasePattern

__all__ = ["FLAT_FOLD_TOLERANCE", "degree4_ratio", "fold_degree4", "vertex_closure"]

_FOLD = ("M", "V")

#: How far a vertex may be from flat-foldable (Kawasaki's alternating sum), and a crease
#: pair from straight, radians: about what coordinates written to 6 significant digits
#: (as other tools write FOLD and SVG files) leave of an exact pattern.
FLAT_FOLD_TOLERANCE = 1e-5


def _mm(point: np.ndarray) -> tuple[float, ...]:
    """A point's coordinates as messages show them, mm."""
    return tuple(round(float(c), 4) for c in point)


def _rx(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def vertex_closure(sectors: np.ndarray, rho: np.ndarray) -> float:
    """How far a vertex with these sector and fold angles is from closing (0 = closed).

    ``sectors`` are the sector angles around the vertex and ``rho`` the fold
    angles of the creases between them, radians. The result is the Frobenius
    norm of the product of the rotations minus the identity (dimensionless).
    """
    m = np.eye(3)
    for sector, r in zip(sectors, rho, strict=True):
        m = m @ _rx(r) @ _rz(sector)
    return float(np.linalg.norm(m - np.eye(3)))


def degree4_ratio(
    sectors: np.ndarray, signs: np.ndarray, tol: float = FLAT_FOLD_TOLERANCE
) -> float:
    """``c`` of ``tan(rho_1 / 2) = c tan(rho_0 / 2)`` at a flat-foldable degree-4 vertex.

    Where two opposite creases lie on one straight line (a map's vertex), that line
    folds on its own: ``c = 0`` when it is creases 0 and 2, ``c = inf`` when it is
    creases 1 and 3 (which then fold before creases 0 and 2 can, reaching 180 deg).

    With ``alpha`` the sector between creases 0 and 1 and ``beta`` the one between
    creases 1 and 2 (opposite creases: 0-2 and 1-3)::

        c = |sin((alpha + beta) / 2) / sin((alpha - beta) / 2)|   creases 0, 2 fold opposite ways
        c = |cos((alpha + beta) / 2) / cos((alpha - beta) / 2)|   creases 0, 2 fold the same way

    Parameters
    ----------
    sectors : ndarray (4,)
        Sector angles, radians: sector ``k`` lies between crease ``k`` and ``k + 1``.
    signs : ndarray (4,)
        +1 valley, -1 mountain, for creases 0..3.
    tol : float
        How far from straight two creases may be and still be one line, and from closed
        the folded vertex may be, radians (more than the default for rounded coordinates).

    Raises
    ------
    ValueError
        If the signs break Maekawa's pairing (one opposite pair folds the same way,
        the other opposite ways) or the vertex does not close when folded.
    """
    alpha, beta = float(sectors[0]), float(sectors[1])
    same_02 = signs[0] == signs[2]
    same_13 = signs[1] == signs[3]
    if same_02 == same_13:
        raise ValueError(
            "they break Maekawa's pairing (one opposite pair must fold the same way, the "
            "other opposite ways)"
        )
    if same_02:
        num, den = math.cos((alpha + beta) / 2), math.cos((alpha - beta) / 2)
    else:
        num, den = math.sin((alpha + beta) / 2), math.sin((alpha - beta) / 2)
    probe = 0.3
    if abs(den) < tol:  # creases 1 and 3 are one straight line: it folds
        c = math.inf  # first, alone; creases 0 and 2 only once it is folded flat (a map)
        rho = np.array([0.0, probe] * 2)
    else:  # c = 0: creases 0 and 2 are one straight line, folding alone
        c = 0.0 if abs(num) < tol else abs(num / den)
        rho = np.array([probe, 2 * math.atan(c * math.tan(probe / 2))] * 2)
    if vertex_closure(np.asarray(sectors, dtype=float), rho * np.asarray(signs)) > tol:
        raise ValueError("the vertex does not close when folded with these signs")
    return c


def _vertex_tables(cp: CreasePattern, interior: np.ndarray):
    """Per interior vertex: its 4 creases in angular order and their sector angles."""
    fold_edges = np.flatnonzero(cp.edge_mask("M", "V", "U", "F", "J"))
    around: dict[int, list[tuple[float, int]]] = {int(v): [] for v in interior}
    for e in fold_edges:
        a, b = cp.edges[e]
        for v, w in ((a, b), (b, a)):
            if int(v) in around:
                d = cp.vertices[w] - cp.vertices[v]
                around[int(v)].append((math.atan2(d[1], d[0]), int(e)))
    tables = {}
    for v, items in around.items():
        loc = _mm(cp.vertices[v])
        if len(items) != 4:
            raise PatternError(
                f"vertex {v} at {loc} mm has {len(items)} crease{'s' * (len(items) != 1)}; "
                "this folder needs every interior vertex to have degree 4"
            )
        items.sort()
        angles = np.array([t for t, _ in items])
        edges = [e for _, e in items]
        for e in edges:
            if cp.assignments[e] not in _FOLD:
                raise PatternError(
                    f"crease {e} at vertex {v} {loc} mm is {cp.assignments[e]}: only mountain "
                    "and valley creases can be folded"
                )
        sectors = np.mod(np.roll(angles, -1) - angles, 2 * math.pi)
        tables[v] = (edges, sectors)
    return tables


def fold_degree4(
    cp: CreasePattern,
    p: float,
    driving_edge: int | None = None,
    tol: float = FLAT_FOLD_TOLERANCE,
) -> tuple[np.ndarray, np.ndarray]:
    """Fold ``cp`` rigidly so that the driving crease folds by ``p * 180`` degrees.

    Parameters
    ----------
    cp : CreasePattern
        A pattern whose interior vertices are flat-foldable degree-4 vertices with
        mountain/valley creases.
    p : float
        Fold ratio of the driving crease, in [0, 1] (1: flat-folded, the limit of
        the closed form).
    driving_edge : int, optional
        The driving crease (default: the mountain or valley crease nearest the
        pattern's centroid).
    tol : float
        Loop-consistency tolerance, radians (and ``tol * size`` mm for positions);
        default :data:`FLAT_FOLD_TOLERANCE`, or more for a pattern whose coordinates
        were rounded (the angle its creases may be off by, as its Kawasaki check allows:
        :func:`~origami_cad.pattern.check.kawasaki_tolerances`).

    Returns
    -------
    coords : ndarray (n, 3)
        Folded vertex positions, mm; the panel next to the driving crease stays flat.
    fold_angles : ndarray (m,)
        Fold angle of every edge, degrees (valley positive; 0 on the border).
    """
    if not 0.0 <= p <= 1.0:
        raise PatternError(f"fold ratio p must lie in [0, 1] for the degree-4 folder, got {p}")
    prep = _prepare(cp)
    tol = max(tol, prep.noise)
    if driving_edge is None:
        if tol not in prep.drivers:
            prep.drivers[tol] = _default_driver(cp, prep, tol)
        driving_edge = prep.drivers[tol]
    if not (
        isinstance(driving_edge, int | np.integer)
        and 0 <= driving_edge < cp.n_edges
        and cp.assignments[driving_edge] in _FOLD
    ):
        raise PatternError(f"edge {driving_edge!r} is not a mountain or valley crease")
    magnitude = _propagate(cp, prep, driving_edge, p * math.pi, tol)
    rho = np.where(np.isnan(magnitude), 0.0, magnitude) * prep.sign
    rho[~cp.edge_mask(*_FOLD)] = 0.0
    return _place(cp, rho, driving_edge, tol), np.degrees(rho)


@dataclass
class _Prepared:
    """What folding a pattern needs at every fold ratio, computed once per pattern: each
    interior vertex's creases and sectors, the creases' signs (+1 valley), the vertices on
    each crease, how far its crease directions may be off by rounding (rad), the vertices'
    ratios by (vertex, first crease) and the default drivers."""

    tables: dict
    sign: np.ndarray
    creases: np.ndarray
    by_edge: dict[int, list[int]]
    noise: float = 0.0
    ratios: dict[tuple[int, int], float] = field(default_factory=dict)
    drivers: dict[float, int] = field(default_factory=dict)


_PREPARED: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _prepare(cp: CreasePattern) -> _Prepared:
    """The pattern's :class:`_Prepared` (checked and built at its first fold, then kept
    while the pattern lives; patterns are immutable)."""
    prep = _PREPARED.get(cp)
    if prep is not None:
        return prep
    creases = np.flatnonzero(cp.edge_mask(*_FOLD))
    if not len(creases):
        raise PatternError("the pattern has no mountain or valley crease to fold")
    interior = interior_vertices(cp)
    tables = _vertex_tables(cp, interior)  # degree 4 first: the more basic requirement
    _check_flat_foldable(cp, interior)
    by_edge: dict[int, list[int]] = {}
    for v, (edges, _) in tables.items():
        for e in edges:
            by_edge.setdefault(e, []).append(v)
    sign = np.where(cp.assignments == "V", 1.0, -1.0)
    # how far rounding may turn a crease (rad); the error adds up vertex by vertex along a
    # loop, about as many as the square root of the vertices (a grid's side)
    noise = float(kawasaki_tolerances(cp, interior, 0.0).max(initial=0.0))
    noise *= math.sqrt(max(len(interior), 1))
    prep = _Prepared(tables, sign, creases, by_edge, noise)
    _PREPARED[cp] = prep
    return prep


def _default_driver(cp: CreasePattern, prep: _Prepared, tol: float) -> int:
    """The crease nearest the pattern's centroid that starts a continuous folding.

    On a map (straight crease lines through its vertices) some lines fold only once
    others are folded flat: driven from such a line, those others would jump to 180
    deg as soon as it moves. Creases are tried from the centre outwards; the first from
    which a small fold moves no crease to 180 deg is taken (the nearest, if none does).
    """
    creases = prep.creases
    mids = (cp.vertices[cp.edges[creases, 0]] + cp.vertices[cp.edges[creases, 1]]) / 2
    ranked = creases[np.argsort(np.linalg.norm(mids - cp.vertices.mean(0), axis=1))]
    for e in ranked[:50]:  # (the ratios met on the way are kept for the folds that follow)
        try:
            magnitude = _propagate(cp, prep, int(e), 0.1 * math.pi, tol)
        except PatternError:
            continue
        if not np.nanmax(magnitude) >= math.pi - 1e-9:
            return int(e)
    return int(ranked[0])


def _check_flat_foldable(cp: CreasePattern, interior: np.ndarray) -> None:
    """Raise :class:`PatternError` naming the first interior vertex that breaks Kawasaki
    by more than its tolerance (:func:`~origami_cad.pattern.check.kawasaki_tolerances`)."""
    res = kawasaki_residuals(cp, interior)
    tol = kawasaki_tolerances(cp, interior)
    folding = cp.edge_mask(*_FOLD, "U", "J")
    for v, r, t in zip(interior, res, tol, strict=True):
        if abs(r) / 2 <= t:
            continue
        loc = _mm(cp.vertices[v])
        if not np.isfinite(r):  # an odd number of folding creases
            degree = int(np.sum(folding & (cp.edges == v).any(axis=1)))
            raise PatternError(
                f"vertex {v} at {loc} mm has {degree} folding crease{'s' * (degree != 1)}, "
                "an odd number: it cannot fold flat, and this folder needs flat-foldable "
                "degree-4 vertices"
            )
        raise PatternError(
            f"vertex {v} at {loc} mm is not flat-foldable (Kawasaki defect "
            f"{math.degrees(abs(r)) / 2:.3g} deg)"
        )


def _propagate(cp, prep: _Prepared, driving_edge: int, angle: float, tol: float) -> np.ndarray:
    """Fold magnitudes (m,) rad of every crease reached from ``driving_edge`` folded by
    ``angle`` rad, vertex by vertex (NaN where none reaches). Raises
    :class:`PatternError` where a loop disagrees by more than ``tol``.
    """
    magnitude = np.full(cp.n_edges, np.nan)
    magnitude[driving_edge] = angle
    tables, sign, ratios = prep.tables, prep.sign, prep.ratios
    queue = deque([driving_edge])
    mids = (cp.vertices[cp.edges[:, 0]] + cp.vertices[cp.edges[:, 1]]) / 2

    def settle(e: int, value: float, v: int) -> None:
        if np.isnan(magnitude[e]):
            magnitude[e] = value
            queue.append(e)
        elif abs(magnitude[e] - value) > tol * max(1.0, value):
            raise PatternError(
                f"the folding is not consistent around the loop through crease {e} at "
                f"{_mm(mids[e])} mm (vertex {v}): "
                f"{math.degrees(magnitude[e]):.6g} deg against {math.degrees(value):.6g} deg "
                f"({math.degrees(abs(magnitude[e] - value)):.3g} deg apart)"
            )

    while queue:
        e = queue.popleft()
        for v in prep.by_edge.get(e, []):
            edges, sectors = tables[v]
            k = edges.index(e)
            order = [edges[(k + j) % 4] for j in range(4)]
            if (v, e) not in ratios:
                ratios[v, e] = _vertex_ratio(cp, v, order, np.roll(sectors, -k), sign, tol)
            a, c = magnitude[e], ratios[v, e]
            settle(order[2], a, v)
            # a map's vertex (two straight lines): tan(b/2) = c tan(a/2) with c = inf says the
            # other line is folded flat once e folds at all, and leaves it free while e is
            # flat; with c = 0, the other line stays flat until e is folded flat
            if (math.isinf(c) and a <= 1e-12) or (c == 0.0 and a >= math.pi - 1e-12):
                continue
            b = math.pi if math.isinf(c) else 2 * math.atan(c * math.tan(a / 2))
            settle(order[1], b, v)
            settle(order[3], b, v)
    return magnitude


def _vertex_ratio(
    cp, v: int, order: list[int], sectors: np.ndarray, sign: np.ndarray, tol: float
) -> float:
    """The degree-4 ratio of vertex ``v`` with its creases in ``order`` (the driving one
    first) and ``sectors`` (rad) in the same order; a clear error when it cannot fold.
    """
    try:
        return degree4_ratio(sectors, sign[order], tol)
    except ValueError as exc:
        loc = _mm(cp.vertices[v])
        raise PatternError(
            f"vertex {v} at {loc} mm: creases {order} ({''.join(cp.assignments[order])}) "
            f"cannot fold rigidly: {exc}"
        ) from None


def _rotation(axis_point: np.ndarray, axis_dir: np.ndarray, angle: float) -> np.ndarray:
    k = axis_dir / np.linalg.norm(axis_dir)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    r = np.eye(3) + math.sin(angle) * kx + (1 - math.cos(angle)) * kx @ kx
    t = np.eye(4)
    t[:3, :3] = r
    t[:3, 3] = axis_point - r @ axis_point
    return t


def _place(cp: CreasePattern, rho: np.ndarray, driving_edge: int, tol: float) -> np.ndarray:
    ef = cp.edge_faces()
    flat = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    root = int(ef[driving_edge, 0] if ef[driving_edge, 0] >= 0 else ef[driving_edge, 1])
    transform = {root: np.eye(4)}
    queue = deque([root])
    while queue:
        f = queue.popleft()
        for e in cp.face_edges[f]:
            other = int(ef[e, 1] if ef[e, 0] == f else ef[e, 0])
            if other < 0 or other in transform:
                continue
            a, b = flat[cp.edges[e]]
            # a valley turns the far panel up toward the top face: face ef[e, 1] lies on the
            # right of a -> b, face ef[e, 0] on its left
            angle = -rho[e] if ef[e, 0] == f else rho[e]
            transform[other] = transform[f] @ _rotation(a, b - a, angle)
            queue.append(other)
    coords = np.full((cp.n_vertices, 3), np.nan)
    limit = tol * max(cp.size, 1.0)
    for f, t in transform.items():
        ring = cp.faces[f]
        pts = (t[:3, :3] @ flat[ring].T).T + t[:3, 3]
        known = ~np.isnan(coords[ring, 0])
        if np.any(np.linalg.norm(coords[ring][known] - pts[known], axis=1) > limit):
            v = int(
                ring[known][np.argmax(np.linalg.norm(coords[ring][known] - pts[known], axis=1))]
            )
            raise PatternError(
                f"the panels do not close up around vertex {v} at "
                f"{_mm(cp.vertices[v])} mm: not rigidly "
                "foldable this way"
            )
        coords[ring] = pts
    if np.isnan(coords).any():
        raise PatternError("some panels are not connected to the rest of the pattern by creases")
    return coords
