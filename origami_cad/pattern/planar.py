"""The planar clean-up of a crease pattern's input: its normalisation into a planar graph.

:func:`normalise` snaps vertices closer than the tolerance (mm), drops zero-length
edges, splits edges at T-junctions (a vertex within the tolerance of an edge) and at
crossings, merges the crossing points with vertices as close, and drops duplicate edges,
in O(n log n) within budgets (:data:`MAX_CROSSINGS` crossing points,
:data:`MAX_CANDIDATE_PAIRS` overlapping edge pairs, :data:`MAX_CLOSE_PAIRS`
near-coincident vertex pairs): a pattern that would exceed one is refused instead of
running for minutes into gigabytes. It returns what it changed as a :class:`Cleanup`
(counts, and the largest gap it closed of each kind, mm), which
:class:`~origami_cad.pattern.model.CreasePattern` turns into notes, so nothing is
repaired behind the user's back.

A merged cluster keeps the coordinates of its lowest-index vertex, so exact inputs stay
exact.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from origami_cad.errors import PatternError

__all__ = [
    "CHAIN_REACH",
    "FREE_END_REACH",
    "IMPORT_RELATIVE_TOLERANCE",
    "MAX_CANDIDATE_PAIRS",
    "MAX_CLOSE_PAIRS",
    "MAX_CROSSINGS",
    "MAX_VERTICES",
    "PRIORITY",
    "SNAP_FRACTION",
    "Cleanup",
    "Tolerance",
    "border_holes",
    "import_tolerance",
    "merge_close",
    "normalise",
    "open_cuts",
    "planar_faces",
    "reach_free_ends",
    "rings_with_edges",
]

#: The tolerance of the file readers, as a fraction of the pattern's size (the diagonal
#: of its bounding box): vertices closer than this merge. Real exports leave gaps where
#: lines should meet: Illustrator's SVG of Origami Simulator's ``miura-ori.svg`` 0.0005
#: to 0.0008 mm at 150 mm wide; its ``huffmanWaterbomb.svg``, ``whirlpool.svg``,
#: ``airplane.svg``, ``traditionalCrane.svg`` and ``curvedPleatSimple.svg`` ends of lines
#: 0.1 to 0.2 mm apart at 150 mm wide (up to 8.5e-4 of their size), which left sliver
#: panels and triangles 0.08 mm wide that can be neither printed nor simulated. The
#: vertices of the 40 public patterns of the test corpus lie 2.4e-3 of the size apart or
#: more once merged, and Origami Simulator itself merges within 3 units of its drawing,
#: 1.5e-3 to 5e-3 of these patterns' size: 1e-3 (0.2 mm at 150 mm wide, far less than a
#: printed crease's width) sits between.
IMPORT_RELATIVE_TOLERANCE = 1e-3
#: A vertex closer to an edge than this fraction of the tolerance lies on it (a
#: T-junction drawn with a gap), and edges cross where they pass this close: half, as a
#: TG design's closest feature is a vertex 8.7e-4 of its size off a crease line
#: (``examples/fig2_tg.toml``, 0.22 mm), while the exports' T-junction gaps are under
#: 5e-4 of their size.
SNAP_FRACTION = 0.5
#: A line's free end this many tolerances from another line is put on it: Origami
#: Simulator's curved patterns (``comet.svg``) end creases 1.3 to 1.9 tolerances short.
FREE_END_REACH = 2.5
#: Vertices chained within the tolerance merge while none lies farther than this many
#: tolerances from the first: Origami Simulator's curved patterns chain up to 1.98
#: (``langKnlDragon.svg``), its finely cut ``HexSpiralTess.svg`` into blobs of 12.
CHAIN_REACH = 2.0
#: Most vertices a pattern may have, once coincident ones are merged (about a 223 x 223
#: grid: converting one from FOLD to SVG took 94 s and 450 MB on a busy 2-core machine; a
#: larger one ran out of memory). Checked before the crossing search and
#: the faces, which need the time and memory; the readers check it (or the edge limit)
#: before they convert a file's numbers.
MAX_VERTICES = 50_000
#: Normalisation budget: most crossing points added where edges cross. A drawing
#: needing more is refused instead of being normalised for minutes into gigabytes.
MAX_CROSSINGS = 100_000
#: Normalisation budget: most pairs of edges whose bounding boxes overlap.
MAX_CANDIDATE_PAIRS = 25_000_000
#: Normalisation budget: most pairs of vertices closer than the tolerance.
MAX_CLOSE_PAIRS = 5_000_000
#: Candidate edge pairs examined at once (bounds the memory of normalisation).
_PAIR_CHUNK = 500_000
#: When two edges coincide, the one whose letter comes first here is kept.
PRIORITY = {a: i for i, a in enumerate("BCMVJUF")}


#: A tolerance as the readers take it: mm, a function of the vertices in use (mm) giving
#: it, or None for the default.
Tolerance = float | Callable[[np.ndarray], float] | None


def import_tolerance(tolerance: Tolerance = None) -> float | Callable[[np.ndarray], float]:
    """A file reader's tolerance for ``CreasePattern(tolerance=...)``: ``tolerance`` mm
    when given, else :data:`IMPORT_RELATIVE_TOLERANCE` of the size of the vertices in
    use (the diagonal of their bounding box, mm)."""
    if tolerance is not None:
        return tolerance

    def relative(used: np.ndarray) -> float:
        size = float(np.linalg.norm(np.ptp(used, axis=0))) if len(used) else 0.0
        return IMPORT_RELATIVE_TOLERANCE * max(size, 1e-9)

    return relative


@dataclass(frozen=True)
class Cleanup:
    """What :func:`normalise` changed, and the largest gap it closed of each kind (mm).

    Attributes
    ----------
    tolerance : float
        The tolerance it worked within, mm.
    merged, merged_gap : int, float
        Vertices merged into a neighbour closer than the tolerance but not at the same
        point (a gap closed), and the largest distance from one to the vertex it was
        merged into, mm.
    coincident : int
        Vertices at the very point of another (the shared ends of lines drawn one by
        one), joined.
    snapped, snapped_gap : int, float
        Vertices that lay off an edge by less than :data:`SNAP_FRACTION` of the
        tolerance (not on it) and split
        it there (a T-junction drawn with a gap), and the largest such gap, mm.
    split : int
        Edges split at T-junctions or crossings (exact ones included).
    crossings : int
        Points added where edges cross.
    crossings_merged, crossing_gap : int, float
        Crossing points merged with a vertex or another crossing point closer than the
        tolerance (not at the same point), and the largest distance closed, mm.
    reached, reached_gap : int, float
        Free ends of lines put on another line within :data:`FREE_END_REACH`
        tolerances of them, and the largest distance moved, mm.
    zero_length, duplicates, unused : int
        Zero-length edges (once merged), duplicate edges, unused vertices dropped.
    conflicts : tuple
        ``(midpoint, letter, kept)`` of coincident edges of different crease letters.
    changed : bool
        Whether the graph differs from the input at all.
    """

    tolerance: float
    merged: int = 0
    merged_gap: float = 0.0
    coincident: int = 0
    snapped: int = 0
    snapped_gap: float = 0.0
    split: int = 0
    crossings: int = 0
    crossings_merged: int = 0
    crossing_gap: float = 0.0
    reached: int = 0
    reached_gap: float = 0.0
    zero_length: int = 0
    duplicates: int = 0
    unused: int = 0
    conflicts: tuple = ()
    changed: bool = False

    def scaled(self, factor: float) -> Cleanup:
        """The same record for the pattern scaled by ``factor`` (its lengths, mm)."""
        import dataclasses

        return dataclasses.replace(
            self,
            tolerance=self.tolerance * factor,
            merged_gap=self.merged_gap * factor,
            snapped_gap=self.snapped_gap * factor,
            crossing_gap=self.crossing_gap * factor,
            reached_gap=self.reached_gap * factor,
            conflicts=tuple(((m[0] * factor, m[1] * factor), a, k) for m, a, k in self.conflicts),
        )


def merge_close(verts: np.ndarray, tol: float) -> np.ndarray:
    """Map each vertex to a representative; vertices within ``tol`` (mm) share one: the
    lowest index of each cluster (clusters chain: two vertices each within ``tol`` of a
    third share one), but never one farther than :data:`CHAIN_REACH` times ``tol`` from
    them: a chain longer than that (the points of a finely cut curve) is split, each of
    its vertices in index order going to the first representative within ``tol`` or
    becoming one. A :class:`PatternError` over :data:`MAX_CLOSE_PAIRS` close pairs."""
    n = len(verts)
    # exact duplicates first (cheap), so that many copies of a point cost nothing
    uniq, inverse = np.unique(verts, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    u = len(uniq)
    tree = cKDTree(uniq)
    close = int(tree.query_ball_point(uniq, tol, return_length=True).sum()) - u
    if close // 2 > MAX_CLOSE_PAIRS:
        raise PatternError(
            f"more than {MAX_CLOSE_PAIRS:,} pairs of vertices lie closer than the tolerance "
            f"({tol:.3g} mm); the pattern is too degenerate to normalise"
        )
    pairs = tree.query_pairs(tol, output_type="ndarray")
    if len(pairs) == 0 and u == n:
        return np.arange(n)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(u, u))
    _, labels = connected_components(graph, directed=False)
    labels = labels[inverse]
    # representative: the lowest index of each cluster, so coordinates stay exact
    rep = np.full(labels.max() + 1, n, dtype=np.int64)
    np.minimum.at(rep, labels, np.arange(n))
    out = rep[labels]
    far = np.hypot(*(verts - verts[out]).T) > CHAIN_REACH * tol
    if far.any():
        out = _split_chains(verts, out, np.isin(labels, labels[far]), tol)
    return out


def _split_chains(
    verts: np.ndarray, rep: np.ndarray, chained: np.ndarray, tol: float
) -> np.ndarray:
    """``rep`` with the ``chained`` vertices (clusters reaching farther than ``tol`` mm)
    reassigned greedily in index order: each to the first representative within ``tol``
    of it among those already chosen, else to itself."""
    rep = rep.copy()
    idx = np.flatnonzero(chained)
    tree = cKDTree(verts[idx])
    near = tree.query_ball_point(verts[idx], tol)
    chosen = np.full(len(idx), -1, dtype=np.int64)
    for k in range(len(idx)):
        if chosen[k] >= 0:
            continue
        chosen[k] = k
        for j in near[k]:
            if chosen[j] < 0:
                chosen[j] = k
    rep[idx] = idx[chosen]
    return rep


def _endpoint_splits(
    verts: np.ndarray,
    edges: np.ndarray,
    tol: float,
    a: np.ndarray,
    b: np.ndarray,
) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Endpoints of edges ``b`` lying inside edges ``a`` (pairwise), within ``tol`` mm.

    One ``(edge, t, vertex)`` triple per end (column 0, then 1) of ``b``: edge
    ``a[k]`` is split at parameter ``t`` by that end vertex.
    """
    p0 = verts[edges[a, 0]]
    d = verts[edges[a, 1]] - p0
    la = np.hypot(d[:, 0], d[:, 1])
    out = []
    for col in (0, 1):
        q_idx = edges[b, col]
        q = verts[q_idx]
        rel = q - p0
        t = np.einsum("ij,ij->i", rel, d) / (la * la)
        foot = p0 + t[:, None] * d
        dist = np.hypot(*(foot - q).T)
        inside = (dist <= tol) & (t * la > tol) & ((1.0 - t) * la > tol)
        inside &= (q_idx != edges[a, 0]) & (q_idx != edges[a, 1])
        out.append((a[inside], t[inside], q_idx[inside]))
    return out


def _proper_crossings(
    verts: np.ndarray, edges: np.ndarray, tol: float, i: np.ndarray, j: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(ci, cj, t, u)``: the pairs ``(i, j)`` of edges sharing no vertex that cross
    properly (more than ``tol`` mm inside both), at parameter ``t`` along ``ci`` and
    ``u`` along ``cj``."""
    shares = (
        (edges[i, 0] == edges[j, 0])
        | (edges[i, 0] == edges[j, 1])
        | (edges[i, 1] == edges[j, 0])
        | (edges[i, 1] == edges[j, 1])
    )
    ci, cj = i[~shares], j[~shares]
    p0i, p0j = verts[edges[ci, 0]], verts[edges[cj, 0]]
    di, dj = verts[edges[ci, 1]] - p0i, verts[edges[cj, 1]] - p0j
    denom = di[:, 0] * dj[:, 1] - di[:, 1] * dj[:, 0]
    w = p0j - p0i
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[:, 0] * dj[:, 1] - w[:, 1] * dj[:, 0]) / denom
        u = (w[:, 0] * di[:, 1] - w[:, 1] * di[:, 0]) / denom
    li, lj = np.hypot(di[:, 0], di[:, 1]), np.hypot(dj[:, 0], dj[:, 1])
    sin_angle = np.abs(denom) / np.maximum(li * lj, 1e-300)
    cross = (
        (sin_angle > 1e-12)
        & (t * li > tol)
        & ((1 - t) * li > tol)
        & (u * lj > tol)
        & ((1 - u) * lj > tol)
    )
    return ci[cross], cj[cross], t[cross], u[cross]


def _collect_splits(
    parts: list[list[tuple[np.ndarray, np.ndarray, np.ndarray]]],
    new: np.ndarray,
    n_verts: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The ``(edge, t, vertex, new_vertices)`` result of :func:`_split_points`.

    ``parts`` holds the four endpoint kinds, then the crossings (alternately the
    ``ci`` and ``cj`` splits); crossing ``k`` is vertex ``n_verts + k``.
    """
    new_idx = n_verts + np.arange(len(new))
    # crossings: all the "ci" splits first, then the "cj" splits, as one batch each
    cross_ci = [pc for k, pc in enumerate(parts[4]) if k % 2 == 0]
    cross_cj = [pc for k, pc in enumerate(parts[4]) if k % 2 == 1]
    split_e: list[np.ndarray] = []
    split_t: list[np.ndarray] = []
    split_v: list[np.ndarray] = []
    for kind in range(4):
        for e, t, v in parts[kind]:
            split_e.append(e)
            split_t.append(t)
            split_v.append(v)
    for batch in (cross_ci, cross_cj):
        for e, t, _ in batch:
            split_e.append(e)
            split_t.append(t)
        split_v.append(new_idx)
    empty_i, empty_f = np.zeros(0, np.int64), np.zeros(0)
    return (
        np.concatenate([*split_e, empty_i]).astype(np.int64),
        np.concatenate([*split_t, empty_f]),
        np.concatenate([*split_v, empty_i]).astype(np.int64),
        new,
    )


def _split_points(
    verts: np.ndarray, edges: np.ndarray, tol: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Find where edges must be split.

    Returns ``(edge, t, vertex, new_vertices)``: edge ``edge[k]`` is split at
    parameter ``t[k]`` by vertex ``vertex[k]`` (indices >= len(verts) refer to
    ``new_vertices``, the crossing points).

    The candidate pairs (edges whose boxes overlap) are examined in chunks, so the
    memory stays bounded; more than :data:`MAX_CANDIDATE_PAIRS` candidates or
    :data:`MAX_CROSSINGS` crossings is a :class:`PatternError`.
    """
    p0 = verts[edges[:, 0]]
    p1 = verts[edges[:, 1]]
    lo = np.minimum(p0, p1) - tol
    hi = np.maximum(p0, p1) + tol
    boxes = shapely.box(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1])
    tree = shapely.STRtree(boxes)
    d = p1 - p0
    # five kinds of split, each in the order of the candidate pairs
    parts: list[list[tuple[np.ndarray, np.ndarray, np.ndarray]]] = [[], [], [], [], []]
    crossings: list[np.ndarray] = []
    n_pairs = n_cross = 0
    step = max(1, _PAIR_CHUNK // max(len(edges), 1))
    for first in range(0, len(edges), step):
        i, j = tree.query(boxes[first : first + step])
        i = i + first
        keep = i < j
        i, j = i[keep], j[keep]
        n_pairs += len(i)
        if n_pairs > MAX_CANDIDATE_PAIRS:
            raise PatternError(
                f"more than {MAX_CANDIDATE_PAIRS:,} pairs of edges overlap (by bounding box); "
                "the pattern is too dense to normalise"
            )
        for kind, (a, b) in ((0, (i, j)), (2, (j, i))):
            for col, split in enumerate(_endpoint_splits(verts, edges, tol, a, b)):
                parts[kind + col].append(split)
        ci, cj, t, u = _proper_crossings(verts, edges, tol, i, j)
        n_cross += len(ci)
        if n_cross > MAX_CROSSINGS:
            raise PatternError(
                f"more than {MAX_CROSSINGS:,} points where edges cross; the pattern is too "
                "tangled to normalise (are these really creases?)"
            )
        crossings.append(p0[ci] + t[:, None] * d[ci])
        parts[4].append((ci, t, cj))
        parts[4].append((cj, u, ci))
    new = np.concatenate(crossings) if crossings else np.zeros((0, 2))
    return _collect_splits(parts, new, len(verts))


def _drop_duplicates(
    edges: np.ndarray,
    assign: np.ndarray,
    angles: np.ndarray,
    conflicts: list,
    verts: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Drop edges joining the same two vertices (either direction), keeping the one
    whose assignment comes first in ``BCMVJUF`` (then the first given); conflicts
    between creases are added to ``conflicts`` as ``(midpoint mm, letter, kept)``."""
    key_lo = np.minimum(edges[:, 0], edges[:, 1])
    key_hi = np.maximum(edges[:, 0], edges[:, 1])
    prio = np.vectorize(PRIORITY.__getitem__, otypes=[int])(assign) if len(assign) else assign
    order = np.lexsort((np.arange(len(edges)), prio, key_hi, key_lo))
    k_lo, k_hi = key_lo[order], key_hi[order]
    first = np.ones(len(order), dtype=bool)
    first[1:] = (k_lo[1:] != k_lo[:-1]) | (k_hi[1:] != k_hi[:-1])
    group = np.cumsum(first) - 1
    kept_assign = assign[order][first][group]
    conflict = (assign[order] != kept_assign) & ~np.isin(assign[order], ["U", "F"])
    for idx in order[conflict][: 20 - min(len(conflicts), 20)]:
        a, b = edges[idx]
        mid = tuple(float(c) for c in (verts[a] + verts[b]) / 2)
        kept = str(kept_assign[np.flatnonzero(order == idx)[0]])
        conflicts.append((mid, str(assign[idx]), kept))
    n_dup = int((~first).sum())
    keep = np.sort(order[first])
    edges, assign, angles = edges[keep], assign[keep], angles[keep]
    return edges, assign, angles, n_dup


def _gaps(verts: np.ndarray, rep: np.ndarray, which: np.ndarray) -> np.ndarray:
    """The distance (mm) from each vertex of ``which`` to its representative."""
    d = verts[which] - verts[rep[which]]
    return np.hypot(d[:, 0], d[:, 1])


def _snap_gaps(verts: np.ndarray, edges: np.ndarray, se: np.ndarray, sv: np.ndarray) -> np.ndarray:
    """Distances (mm) from each splitting vertex ``sv`` (an input vertex) to the line of
    the edge ``se`` it splits: 0 for an exact T-junction."""
    p0, p1, q = verts[edges[se, 0]], verts[edges[se, 1]], verts[sv]
    d = p1 - p0
    cross = d[:, 0] * (q[:, 1] - p0[:, 1]) - d[:, 1] * (q[:, 0] - p0[:, 0])
    return np.abs(cross) / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-300)


def _split(
    verts: np.ndarray, edges: np.ndarray, assign: np.ndarray, angles: np.ndarray, tol: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple]:
    """Split the edges at T-junctions and crossings, then merge the crossing points
    with what lies within ``tol`` mm. Returns the new arrays and ``(edges split,
    crossings, vertices snapped onto an edge, largest snap mm, crossing points merged,
    largest crossing gap mm)``."""
    se, st, sv, new = _split_points(verts, edges, SNAP_FRACTION * tol)
    n_split = len(np.unique(se))
    n_cross = len(new)
    ends = sv < len(verts)
    gaps = _snap_gaps(verts, edges, se[ends], sv[ends])
    snapped = len(np.unique(sv[ends][gaps > 0]))
    snapped_gap = float(gaps.max()) if len(gaps) else 0.0
    crossings_merged, crossing_gap = 0, 0.0
    if len(se):
        n_before = len(verts)
        verts = np.vstack([verts, new])
        m = len(edges)
        all_e = np.concatenate([np.arange(m), np.arange(m), se])
        all_t = np.concatenate([np.zeros(m), np.ones(m), st])
        all_v = np.concatenate([edges[:, 0], edges[:, 1], sv])
        order = np.lexsort((all_t, all_e))
        all_e, all_v = all_e[order], all_v[order]
        same = all_e[:-1] == all_e[1:]
        src = all_e[:-1][same]
        edges = np.stack([all_v[:-1][same], all_v[1:][same]], axis=1)
        assign, angles = assign[src], angles[src]
        # crossing points may coincide with each other or with vertices
        rep = merge_close(verts, tol)
        moved = np.flatnonzero(rep != np.arange(len(rep)))
        gaps = _gaps(verts, rep, moved)
        crossings_merged = int(np.sum((moved >= n_before) & (gaps > 0)))
        crossing_gap = float(gaps.max(initial=0.0))
        edges = rep[edges]
        zero = edges[:, 0] == edges[:, 1]
        edges, assign, angles = edges[~zero], assign[~zero], angles[~zero]
    stats = (n_split, n_cross, snapped, snapped_gap, crossings_merged, crossing_gap)
    return verts, edges, assign, angles, stats


def _merged(verts: np.ndarray, edges: np.ndarray, tol: float) -> tuple:
    """``edges`` with vertices within ``tol`` mm merged, ``moved, merged, coincident, gap mm``."""
    rep = merge_close(verts, tol)
    moved = np.flatnonzero(rep != np.arange(len(rep)))
    gaps = _gaps(verts, rep, moved)
    merged, coincident = int(np.sum(gaps > 0)), int(np.sum(gaps == 0))
    edges = rep[edges]
    n_used = len(np.unique(edges))
    if n_used > MAX_VERTICES:
        raise PatternError(
            f"{n_used:,} vertices, more than the limit of {MAX_VERTICES:,} (MAX_VERTICES)"
        )
    return edges, moved, merged, coincident, float(gaps.max(initial=0.0))


def _reached(verts, edges, assign, angles, tol: float) -> tuple:
    """:func:`reach_free_ends` (``tol`` mm), joining an end put on another's end."""
    verts, reached, gap = reach_free_ends(verts, edges, tol)
    if reached:
        edges = merge_close(verts, 0.0)[edges]
        keep = edges[:, 0] != edges[:, 1]
        edges, assign, angles = edges[keep], assign[keep], angles[keep]
    return verts, edges, assign, angles, reached, gap


def normalise(
    verts: np.ndarray,
    edges: np.ndarray,
    assign: np.ndarray,
    angles: np.ndarray,
    tol: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Cleanup]:
    """The planar graph of the input, within ``tol`` mm, and what was changed.

    ``verts`` (n, 2) mm, ``edges`` (m, 2) indices, ``assign`` and ``angles`` (degrees)
    per edge, carried along; ``tol`` is the distance under which vertices merge and a
    vertex counts as on an edge, mm. Returns the normalised vertices, edges,
    assignments and fold angles, and the :class:`Cleanup` record.
    """
    conflicts: list = []
    n_in_vertices, n_in_edges = len(verts), len(edges)
    # 1. snap near-coincident vertices
    edges, moved, merged, coincident, merged_gap = _merged(verts, edges, tol)
    # 2. zero-length edges
    zero = edges[:, 0] == edges[:, 1]
    n_zero = int(zero.sum())
    edges, assign, angles = edges[~zero], assign[~zero], angles[~zero]
    verts, edges, assign, angles, reached, reached_gap = _reached(verts, edges, assign, angles, tol)
    # exact duplicates go before the split, so that they cost nothing there
    edges, assign, angles, n_dup = _drop_duplicates(edges, assign, angles, conflicts, verts)
    # 3. split at T-junctions and crossings
    verts, edges, assign, angles, splits = _split(verts, edges, assign, angles, tol)
    n_split, n_cross, snapped, snapped_gap, crossings_merged, crossing_gap = splits
    # 4. duplicates in either direction: keep the highest-priority assignment
    edges, assign, angles, more = _drop_duplicates(edges, assign, angles, conflicts, verts)
    n_dup += more
    # 5. drop unused vertices, keeping order
    used = np.unique(edges)
    if len(used) > MAX_VERTICES:  # the crossings made them (checked before the faces)
        raise PatternError(
            f"{len(used):,} vertices once the edges are split where they cross ({n_cross:,} "
            f"crossings), more than the limit of {MAX_VERTICES:,} (MAX_VERTICES)"
        )
    remap = np.full(len(verts), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    verts = verts[used]
    edges = remap[edges]
    n_unused = max(0, n_in_vertices + n_cross - len(moved) - crossings_merged - len(used))
    changed = bool(len(moved) or n_zero or n_split or n_dup or n_unused or reached)
    changed = changed or len(edges) != n_in_edges
    cleanup = Cleanup(
        tolerance=float(tol),
        merged=merged,
        merged_gap=merged_gap,
        coincident=coincident,
        snapped=snapped,
        snapped_gap=snapped_gap,
        split=n_split,
        crossings=n_cross,
        crossings_merged=crossings_merged,
        crossing_gap=crossing_gap,
        reached=reached,
        reached_gap=reached_gap,
        zero_length=n_zero,
        duplicates=n_dup,
        unused=n_unused,
        conflicts=tuple(conflicts),
        changed=changed,
    )
    return (
        np.ascontiguousarray(verts, dtype=float),
        np.ascontiguousarray(edges, dtype=np.int64),
        assign.astype("<U1"),
        angles.astype(float),
        cleanup,
    )


def reach_free_ends(
    verts: np.ndarray, edges: np.ndarray, tol: float
) -> tuple[np.ndarray, int, float]:
    """Put each free end of a line (a vertex of one edge) within :data:`FREE_END_REACH`
    times ``tol`` mm of another line on it (on its nearer end when that is as close;
    ends within :data:`SNAP_FRACTION` of ``tol`` stay for the split): ``(vertices mm,
    ends moved, largest move mm)``."""
    free = np.flatnonzero(np.bincount(edges.ravel(), minlength=len(verts)) == 1)
    if len(free) == 0 or len(edges) < 2:
        return verts, 0, 0.0
    reach = FREE_END_REACH * tol
    lines = shapely.linestrings(verts[edges])
    pts = shapely.points(verts[free])
    vi, ei = shapely.STRtree(lines).query(pts, predicate="dwithin", distance=reach)
    own = (edges[ei] == free[vi][:, None]).any(axis=1)
    vi, ei = vi[~own], ei[~own]
    dist = shapely.distance(pts[vi], lines[ei])
    order = np.lexsort((dist, vi))
    vi, ei, dist = vi[order], ei[order], dist[order]
    first = np.r_[True, vi[1:] != vi[:-1]] & (dist > SNAP_FRACTION * tol)
    out = verts.copy()
    moved, gap = 0, 0.0
    for k, e in zip(vi[first].tolist(), ei[first].tolist(), strict=True):
        v = free[k]
        a, b = verts[edges[e, 0]], verts[edges[e, 1]]
        d = b - a
        t = float(np.clip(np.dot(verts[v] - a, d) / max(float(np.dot(d, d)), 1e-300), 0, 1))
        target = a + t * d
        ends = np.hypot(*(np.array([a, b]) - verts[v]).T)
        if ends.min() <= reach:  # that end where it is now (it may have moved: no swap)
            target = out[edges[e, int(np.argmin(ends))]]
        gap = max(gap, float(np.hypot(*(target - verts[v]))))
        out[v] = target
        moved += 1
    return out, moved, gap


def _flat_rings(rings: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Concatenate rings: (flat vertex indices, next position in the ring, ring starts)."""
    counts = np.array([len(r) for r in rings], dtype=np.int64)
    flat = np.concatenate(rings) if rings else np.zeros(0, np.int64)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
    nxt = np.arange(len(flat)) + 1
    if len(rings):
        nxt[starts + counts - 1] = starts
    return flat, nxt, starts


def rings_with_edges(
    vertices: np.ndarray, edges: np.ndarray, rings: list[np.ndarray]
) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...], np.ndarray]:
    """Orient rings of ``vertices`` (mm) counter-clockwise, and find the edge of
    ``edges`` along every side (-1 where none).

    Returns ``(rings, sides, areas)`` with areas in mm^2.
    """
    if not rings:
        return (), (), np.zeros(0)
    flat, nxt, starts = _flat_rings(rings)
    p, q = vertices[flat], vertices[flat[nxt]]
    area = 0.5 * np.add.reduceat(p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0], starts)
    rings = [r[::-1].copy() if a < 0 else r for r, a in zip(rings, area, strict=True)]
    flat, nxt, starts = _flat_rings(rings)
    n = len(vertices)
    keys = np.minimum(edges[:, 0], edges[:, 1]) * n + np.maximum(edges[:, 0], edges[:, 1])
    order = np.argsort(keys)
    sk = keys[order]
    a, b = flat, flat[nxt]
    k = np.minimum(a, b) * n + np.maximum(a, b)
    pos = np.minimum(np.searchsorted(sk, k), len(sk) - 1)
    side = np.where(sk[pos] == k, order[pos], -1)
    return tuple(rings), tuple(np.split(side, starts[1:])), np.abs(area)


def planar_faces(
    vertices: np.ndarray, edges: np.ndarray, assignments: np.ndarray | None = None
) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...], list[tuple[float, float]]]:
    """Faces of the planar graph (shapely ``polygonize``), sorted by centroid (y, x).

    With ``assignments``, a face all of whose sides are border (``B``) edges with a face
    on their other side is a hole drawn in black, not a panel, and is left out (as
    Origami Simulator leaves out faces surrounded by border edges).

    Returns ``(rings, sides, inner)``: counter-clockwise vertex rings starting at their
    lowest index, the edge along each side, and a point (mm) on the inner outline of
    every face that encloses another part of the graph. Vertices in mm.
    """
    inner: list[tuple[float, float]] = []
    lines = shapely.linestrings(vertices[edges])
    polys = shapely.get_parts(shapely.polygonize(lines))
    if len(polys) == 0:
        return (), (), inner
    coords, idx = shapely.get_coordinates(shapely.get_exterior_ring(polys), return_index=True)
    last = np.r_[idx[1:] != idx[:-1], True]  # each ring's closing coordinate
    coords, idx = coords[~last], idx[~last]
    dist, vid = cKDTree(vertices).query(coords)
    if np.any(dist > 0):  # pragma: no cover - polygonize keeps input coordinates
        raise PatternError("internal error: a face corner is not a vertex")
    starts = np.flatnonzero(np.r_[True, idx[1:] != idx[:-1]])
    rings = np.split(vid.astype(np.int64), starts[1:])
    for k in np.flatnonzero(shapely.get_num_interior_rings(polys)):
        c = shapely.get_coordinates(shapely.get_interior_ring(polys[k], 0))[0]
        inner.append((float(c[0]), float(c[1])))
    cent = shapely.get_coordinates(shapely.centroid(polys))
    perm = np.lexsort((np.round(cent[:, 0], 6), np.round(cent[:, 1], 6)))
    rings = [rings[k] for k in perm]
    rings, sides, _ = rings_with_edges(vertices, edges, rings)
    # start every ring at its lowest vertex index, so faces are canonical
    shift = [int(np.argmin(r)) for r in rings]
    rings = tuple(np.roll(r, -s) for r, s in zip(rings, shift, strict=True))
    sides = tuple(np.roll(e, -s) for e, s in zip(sides, shift, strict=True))
    if assignments is not None:
        keep = ~border_holes(len(edges), sides, assignments)
        rings = tuple(r for r, k in zip(rings, keep, strict=True) if k)
        sides = tuple(e for e, k in zip(sides, keep, strict=True) if k)
    return rings, sides, inner


def border_holes(m: int, face_edges: tuple[np.ndarray, ...], assignments: np.ndarray) -> np.ndarray:
    """Which faces are holes drawn in black: every side a border (``B``) edge of the
    ``m`` edges, each with another face on its other side (a face on the sheet's
    outline stays a panel). Returns a bool per face."""
    if not face_edges:
        return np.zeros(0, dtype=bool)
    count = np.bincount(np.concatenate(face_edges).clip(0), minlength=m)
    out = np.zeros(len(face_edges), dtype=bool)
    for f, sides in enumerate(face_edges):
        if len(sides) and (sides >= 0).all():
            out[f] = bool(np.all(assignments[sides] == "B") and np.all(count[sides] == 2))
    if out.all():  # a sheet drawn in black only keeps its panels
        out[:] = False
    return out


def _edge_faces(m: int, face_edges: tuple[np.ndarray, ...]) -> tuple[np.ndarray, np.ndarray]:
    """The first and second face along each of ``m`` edges (-1: none)."""
    first = np.full(m, -1, dtype=np.int64)
    second = np.full(m, -1, dtype=np.int64)
    for f, sides in enumerate(face_edges):
        for e in sides[sides >= 0]:
            if first[e] < 0:
                first[e] = f
            else:
                second[e] = f
    return first, second


def open_cuts(
    n_vertices: int,
    edges: np.ndarray,
    assignments: np.ndarray,
    faces: tuple[np.ndarray, ...],
    face_edges: tuple[np.ndarray, ...],
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple, tuple] | None:
    """The graph with its cuts open (Origami Simulator's split of cuts), or None when no
    cut (``C`` edge) has a face on both sides.

    Around each vertex the faces joined across an edge that is not such a cut stay on one
    copy of the vertex; each further group of faces (a cut's other side) gets a copy of its
    own, numbered after the ``n_vertices`` vertices. An edge keeps its index, with the
    copies of its first face; the side of an opened cut that is not its first face's gets
    a new edge, numbered after the others.

    Returns ``(source (n',): the vertex each vertex copies, edges (m', 2), source (m',):
    the edge each edge copies, faces, face_edges)`` with ``faces`` and ``face_edges`` as given,
    renumbered.
    """
    m = len(edges)
    first, second = _edge_faces(m, face_edges)
    cut = (assignments == "C") & (second >= 0)
    if not cut.any():
        return None
    # one node per (face, corner); joined across the sides of two faces that are no cut
    offset = np.cumsum([0, *(len(r) for r in faces)])
    corner = {
        (f, int(v)): offset[f] + k for f, ring in enumerate(faces) for k, v in enumerate(ring)
    }
    rows, cols = [], []
    for e in np.flatnonzero((second >= 0) & ~cut):
        for v in edges[e]:
            rows.append(corner[(int(first[e]), int(v))])
            cols.append(corner[(int(second[e]), int(v))])
    size = int(offset[-1])
    graph = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(size, size))
    _, group = connected_components(graph, directed=False)
    flat = np.concatenate(faces)
    source = list(range(n_vertices))
    copy_of: dict[int, int] = {}  # group -> its copy of the vertex
    used = np.zeros(n_vertices, dtype=bool)
    for g, v in zip(group.tolist(), flat.tolist(), strict=True):
        if g not in copy_of:
            copy_of[g] = len(source) if used[v] else v
            if used[v]:
                source.append(v)
            used[v] = True
    renumbered = np.array([copy_of[g] for g in group.tolist()], dtype=np.int64)
    new_faces = tuple(renumbered[offset[f] : offset[f + 1]] for f in range(len(faces)))

    def ends(f: int, e: int) -> tuple[int, int]:
        at = dict(zip(faces[f].tolist(), new_faces[f].tolist(), strict=True))
        return at[int(edges[e, 0])], at[int(edges[e, 1])]

    out_edges = [
        ends(int(first[e]), e) if first[e] >= 0 else (int(edges[e, 0]), int(edges[e, 1]))
        for e in range(m)
    ]
    edge_source = list(range(m))
    new_sides = [s.copy() for s in face_edges]
    for e in np.flatnonzero(cut):
        other = ends(int(second[e]), e)
        if set(other) == set(out_edges[e]):
            continue  # a slit whose ends stay joined: it cannot open
        sides = new_sides[int(second[e])]
        sides[sides == e] = len(out_edges)
        out_edges.append(other)
        edge_source.append(int(e))
    return (
        np.array(source, dtype=np.int64),
        np.array(out_edges, dtype=np.int64).reshape(-1, 2),
        np.array(edge_source, dtype=np.int64),
        new_faces,
        tuple(new_sides),
    )
