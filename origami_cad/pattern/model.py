"""The crease-pattern data model.

A :class:`CreasePattern` is a planar straight-line graph in millimetres: vertices,
edges with an M/V/B/F/U/C/J assignment and a target fold angle, and the faces
(panels) bounded by the edges. It normalises its input on construction (snaps
near-coincident vertices, splits edges at T-junctions and crossings, drops
zero-length and duplicate edges) in O(n log n), and records what it changed in
:attr:`CreasePattern.notes` so nothing is repaired behind the user's back.

Inputs are checked, not coerced: vertex indices must be whole numbers,
coordinates finite numbers within :data:`MAX_COORDINATE` mm, fold angles within
[-180, 180] degrees; a pattern has at most :data:`MAX_EDGES` edges and
:data:`MAX_VERTICES` vertices (checked before any costly step). Normalisation
works within budgets (:data:`MAX_CROSSINGS` crossing points,
:data:`MAX_CANDIDATE_PAIRS` overlapping edge pairs,
:data:`MAX_CLOSE_PAIRS` near-coincident vertex pairs) and refuses a pattern that
would exceed one, instead of running for minutes into gigabytes.

Examples
--------
>>> import numpy as np
>>> from origami_cad.pattern import CreasePattern
>>> square = np.array([[0, 0], [100, 0], [100, 100], [0, 100]], float)
>>> edges = [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]]
>>> cp = CreasePattern(square, edges, ["B", "B", "B", "B", "V"])
>>> len(cp.faces), float(cp.fold_angles[-1])
(2, 180.0)
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from origami_cad._toml import printable
from origami_cad.errors import PatternError

__all__ = [
    "DEFAULT_RELATIVE_TOLERANCE",
    "MAX_COORDINATE",
    "MAX_CROSSINGS",
    "MAX_EDGES",
    "MAX_VERTICES",
    "Assignment",
    "CreasePattern",
    "Hole",
    "Problem",
    "Severity",
    "printable",
]

#: Vertices closer than this fraction of the pattern's size are merged.
DEFAULT_RELATIVE_TOLERANCE = 1e-6
#: Largest coordinate magnitude accepted, mm (1000 km). Anything larger is a
#: mistake (or a hostile file) and would overflow the geometry in squares and areas.
MAX_COORDINATE = 1e9
#: Most vertices a pattern may have, once coincident ones are merged (about a 223 x 223
#: grid: converting one from FOLD to SVG took 94 s and 450 MB on a busy 2-core machine; a
#: larger one ran out of memory). Checked before the crossing search and
#: the faces, which need the time and memory; the readers check it (or :data:`MAX_EDGES`)
#: before they convert a file's numbers.
MAX_VERTICES = 50_000
#: Most edges a pattern may be given (before normalisation splits them at crossings).
MAX_EDGES = 100_000
#: Normalisation budget: most crossing points added where edges cross. A drawing
#: needing more is refused instead of being normalised for minutes into gigabytes.
MAX_CROSSINGS = 100_000
#: Normalisation budget: most pairs of edges whose bounding boxes overlap.
MAX_CANDIDATE_PAIRS = 25_000_000
#: Normalisation budget: most pairs of vertices closer than the tolerance.
MAX_CLOSE_PAIRS = 5_000_000
#: Candidate edge pairs examined at once (bounds the memory of normalisation).
_PAIR_CHUNK = 500_000


class Assignment(StrEnum):
    """Edge assignment letters of the FOLD format."""

    MOUNTAIN = "M"
    VALLEY = "V"
    BORDER = "B"
    FLAT = "F"
    UNASSIGNED = "U"
    CUT = "C"
    JOIN = "J"


_VALID = frozenset(a.value for a in Assignment)
#: When two edges coincide, the one whose letter comes first here is kept.
_PRIORITY = {a: i for i, a in enumerate("BCMVJUF")}


class Severity(StrEnum):
    """How bad a :class:`Problem` is."""

    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


@dataclass(frozen=True)
class Problem:
    """One finding of :meth:`CreasePattern.check` or of normalisation.

    Parameters
    ----------
    code : str
        Short machine-readable kind, e.g. ``"maekawa"``, ``"open-border"``.
    message : str
        What is wrong, naming the vertex, edge or face.
    location : tuple of float or None
        Where, in pattern coordinates (mm).
    severity : Severity
        ``error`` (the pattern cannot be folded or fabricated as is),
        ``warning`` or ``info`` (what normalisation changed).
    """

    code: str
    message: str
    location: tuple[float, float] | None = None
    severity: Severity = Severity.ERROR

    def __str__(self) -> str:
        where = ""
        if self.location is not None:
            where = f" at ({self.location[0]:.4g}, {self.location[1]:.4g}) mm"
        return f"{self.severity.value}: {self.code}{where}: {self.message}"


@dataclass(frozen=True)
class Hole:
    """A circular hole through a panel (for strings).

    Parameters
    ----------
    x, y : float
        Centre in pattern coordinates, mm.
    diameter : float
        Hole diameter, mm.
    """

    x: float
    y: float
    diameter: float = 2.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.x) and math.isfinite(self.y)):
            raise PatternError(f"hole centre ({self.x}, {self.y}) is not a finite point")
        if not self.diameter > 0:
            raise PatternError(f"hole at ({self.x}, {self.y}): diameter must be > 0 mm")


def _as_assignments(assignments: str | Iterable[str], n: int) -> np.ndarray:
    if isinstance(assignments, str) and len(assignments) == 1:  # one letter for every edge
        arr = np.full(n, assignments.upper(), dtype="<U1")
    elif isinstance(assignments, str):  # one letter per edge, "BBBBV"
        arr = np.array(list(assignments.upper()), dtype="<U1")
    else:
        items = [str(a).upper() for a in assignments]
        long = [a for a in items if len(a) != 1]
        if long:
            raise PatternError(f"assignment {long[0]!r} is not one letter (M V B F U C J)")
        arr = np.array(items, dtype="<U1")
    if arr.shape != (n,):
        raise PatternError(f"{arr.shape[0]} assignments given for {n} edges")
    bad = np.flatnonzero(~np.isin(arr, list(_VALID)))
    if bad.size:
        raise PatternError(
            f"edge {bad[0]}: unknown assignment {str(arr[bad[0]])!r} "
            "(expected one of M V B F U C J)"
        )
    return arr


def default_fold_angles(assignments: np.ndarray) -> np.ndarray:
    """Target fold angles in degrees implied by assignments: V +180, M -180, else 0."""
    out = np.zeros(assignments.shape, dtype=float)
    out[assignments == "V"] = 180.0
    out[assignments == "M"] = -180.0
    return out


class CreasePattern:
    """A crease pattern: vertices (mm), assigned edges and the faces they bound.

    Parameters
    ----------
    vertices : array_like, shape (n, 2)
        Vertex coordinates, mm. 3D input is accepted if every z is equal.
    edges : array_like of int, shape (m, 2)
        Vertex indices of each edge.
    assignments : str or sequence of str
        One letter per edge (``M V B F U C J``, see :class:`Assignment`), or one
        letter for all.
    fold_angles : array_like, shape (m,), optional
        Target fold angle per edge, degrees (valley positive, mountain negative).
        Missing values (NaN, or the whole array) default to +-180 for V/M and 0
        for other edges.
    faces : sequence of index arrays, optional
        Faces as vertex-index rings. Used when normalisation does not change the
        graph and every side is an edge; otherwise faces are computed from the
        planar graph (shapely ``polygonize``).
    holes : iterable of Hole, optional
        Circular holes on panels.
    face_labels : sequence of str, optional
        One label per face (used with ``faces``); default ``f0, f1, ...``.
    metadata : dict, optional
        Free-form metadata; ``title`` and ``creator`` are written to files.
    tolerance : float, optional
        Distance under which vertices merge and points count as on an edge, mm.
        Default: ``1e-6`` times the diagonal of the bounding box.

    Notes
    -----
    The arrays are read-only; derive new patterns with the ``with_*`` methods.
    Faces are counter-clockwise seen from +z (the top face of the sheet).
    """

    __slots__ = (
        "__weakref__",  # caches of derived data (the degree-4 folder's) hold patterns weakly
        "_face_edges",
        "_faces",
        "assignments",
        "edges",
        "face_labels",
        "fold_angles",
        "holes",
        "metadata",
        "notes",
        "tolerance",
        "vertices",
    )

    def __init__(
        self,
        vertices: Any,
        edges: Any,
        assignments: str | Iterable[str] = "U",
        fold_angles: Any = None,
        *,
        faces: Sequence[Sequence[int]] | None = None,
        holes: Iterable[Hole] = (),
        face_labels: Sequence[str] | None = None,
        metadata: dict[str, Any] | None = None,
        tolerance: float | None = None,
    ) -> None:
        verts = _as_vertices(vertices)
        edge_arr = _as_edges(edges)
        if edge_arr.size and (edge_arr.min() < 0 or edge_arr.max() >= len(verts)):
            bad = int(np.flatnonzero((edge_arr < 0).any(1) | (edge_arr >= len(verts)).any(1))[0])
            raise PatternError(
                f"edge {bad} refers to vertex {edge_arr[bad].tolist()} but there are "
                f"{len(verts)} vertices"
            )
        assign = _as_assignments(assignments, len(edge_arr))
        angles = default_fold_angles(assign)
        if fold_angles is not None:
            given = np.asarray(fold_angles, dtype=float).reshape(-1)
            if given.shape != (len(edge_arr),):
                raise PatternError(f"{given.size} fold angles given for {len(edge_arr)} edges")
            bad = np.flatnonzero(np.isinf(given) | (np.abs(np.nan_to_num(given)) > 180 + 1e-9))
            if bad.size:
                raise PatternError(
                    f"edge {bad[0]}: fold angle {given[bad[0]]} deg is outside [-180, 180]"
                )
            known = np.isfinite(given)
            angles[known] = given[known]
        if len(edge_arr) == 0:
            raise PatternError("the pattern has no edges")
        size = float(np.linalg.norm(np.ptp(verts[np.unique(edge_arr)], axis=0)))
        if tolerance is None:
            tolerance = DEFAULT_RELATIVE_TOLERANCE * max(size, 1e-9)
        if not tolerance > 0:
            raise PatternError(f"tolerance must be > 0 mm, got {tolerance}")
        self.tolerance = float(tolerance)
        self.metadata = dict(metadata or {})
        self.metadata.setdefault("unit", "mm")
        result = _normalise(verts, edge_arr, assign, angles, self.tolerance)
        self.vertices, self.edges, self.assignments, self.fold_angles, notes, changed = result
        if len(self.edges) == 0:
            raise PatternError(
                "every edge has zero length (its two vertices coincide): no crease is left"
            )
        for arr in (self.vertices, self.edges, self.assignments, self.fold_angles):
            arr.flags.writeable = False
        face_notes: list[Problem] = []
        computed = True
        if faces is not None and not changed:
            try:
                self._faces, self._face_edges = _given_faces(self, faces)
                computed = False
            except PatternError as exc:
                face_notes.append(
                    Problem(
                        "faces-recomputed",
                        f"faces in the input were not used ({exc}); computed from the edges",
                        severity=Severity.WARNING,
                    )
                )
        if computed:
            self._faces, self._face_edges, more = _compute_faces(self)
            face_notes.extend(more)
        nf = len(self._faces)
        if face_labels is not None and not computed:
            if len(face_labels) != nf:
                raise PatternError(f"{len(face_labels)} face labels given for {nf} faces")
            self.face_labels = tuple(str(s) for s in face_labels)
        else:
            self.face_labels = tuple(f"f{i}" for i in range(nf))
        self.notes = tuple(notes + face_notes)
        self.holes = tuple(holes)

    # ------------------------------------------------------------------ basics
    @property
    def faces(self) -> tuple[np.ndarray, ...]:
        """Faces as counter-clockwise vertex-index arrays."""
        return self._faces

    @property
    def face_edges(self) -> tuple[np.ndarray, ...]:
        """Edge index of each side of each face (side k joins vertex k and k+1)."""
        return self._face_edges

    @property
    def n_vertices(self) -> int:
        return len(self.vertices)

    @property
    def n_edges(self) -> int:
        return len(self.edges)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """``(xmin, ymin, xmax, ymax)`` in mm."""
        lo = self.vertices.min(axis=0)
        hi = self.vertices.max(axis=0)
        return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])

    @property
    def size(self) -> float:
        """Diagonal of the bounding box, mm."""
        x0, y0, x1, y1 = self.bounds
        return math.hypot(x1 - x0, y1 - y0)

    @property
    def title(self) -> str:
        return str(self.metadata.get("title", ""))

    def edge_lengths(self) -> np.ndarray:
        """Length of every edge, mm."""
        d = self.vertices[self.edges[:, 1]] - self.vertices[self.edges[:, 0]]
        return np.hypot(d[:, 0], d[:, 1])

    def edge_mask(self, *letters: str) -> np.ndarray:
        """Boolean mask of the edges whose assignment is one of ``letters``."""
        return np.isin(self.assignments, [str(s) for s in letters])

    def face_polygons(self) -> np.ndarray:
        """The faces as an array of shapely polygons (mm)."""
        if not self._faces:
            return np.array([], dtype=object)
        counts = [len(f) for f in self._faces]
        rings = shapely.linearrings(
            self.vertices[np.concatenate(self._faces)],
            indices=np.repeat(np.arange(len(counts)), counts),
        )
        return shapely.polygons(rings)

    def face_centroids(self) -> np.ndarray:
        """Area centroid of every face, shape (f, 2), mm."""
        return shapely.get_coordinates(shapely.centroid(self.face_polygons()))

    def face_areas(self) -> np.ndarray:
        """Area of every face, mm^2."""
        return _rings_with_edges(self, list(self._faces))[2]

    def face_index(self, label: str) -> int:
        """Index of the face with this label; :class:`PatternError` if none."""
        try:
            return self.face_labels.index(label)
        except ValueError:
            raise PatternError(f"no panel labelled {label!r} in the pattern") from None

    def edge_faces(self) -> np.ndarray:
        """Faces on the left and right of each edge, shape (m, 2); -1 where none.

        Column 0 is the face whose counter-clockwise ring runs the edge from
        ``edges[:, 0]`` to ``edges[:, 1]``; column 1 the face running it backwards.
        """
        out = np.full((self.n_edges, 2), -1, dtype=np.int64)
        if not self._faces:
            return out
        ring = np.concatenate(self._faces)
        fedges = np.concatenate(self._face_edges)
        face = np.repeat(np.arange(len(self._faces)), [len(f) for f in self._faces])
        forward = self.edges[fedges, 0] == ring
        out[fedges[forward], 0] = face[forward]  # a face seen twice: the later one, as before
        out[fedges[~forward], 1] = face[~forward]
        return out

    def face_of_point(self, x: float, y: float) -> int:
        """Index of the face containing the point (mm); -1 if none."""
        pt = shapely.Point(x, y)
        polys = self.face_polygons()
        hit = np.flatnonzero(shapely.contains(polys, pt))
        return int(hit[0]) if hit.size else -1

    def faces_of_points(self, points: np.ndarray) -> np.ndarray:
        """:meth:`face_of_point` of many points at once, ``(k, 2)`` mm: face indices, -1 none."""
        pts = shapely.points(np.asarray(points, dtype=float).reshape(-1, 2))
        out = np.full(len(pts), -1, dtype=np.int64)
        if not self._faces or not len(pts):
            return out
        point, face = shapely.STRtree(self.face_polygons()).query(pts, predicate="within")
        order = np.lexsort((-face, point))  # per point, the lowest face index written last
        out[point[order]] = face[order]
        return out

    # ------------------------------------------------------------- derivation
    def with_holes(self, holes: Iterable[Hole]) -> CreasePattern:
        """A copy of the pattern with these holes (replacing the existing ones)."""
        out = self._copy()
        out.holes = tuple(holes)
        return out

    def with_face_labels(self, labels: Sequence[str]) -> CreasePattern:
        """A copy with these face labels (one per face, unique)."""
        if len(labels) != len(self._faces):
            raise PatternError(f"{len(labels)} face labels given for {len(self._faces)} faces")
        if len(set(labels)) != len(labels):
            raise PatternError("face labels must be unique")
        out = self._copy()
        out.face_labels = tuple(str(s) for s in labels)
        return out

    def with_metadata(self, **metadata: Any) -> CreasePattern:
        """A copy with these metadata entries added or replaced."""
        out = self._copy()
        out.metadata = {**self.metadata, **metadata}
        return out

    def scaled(self, factor: float) -> CreasePattern:
        """A copy ``factor`` times as large (vertices, holes and tolerance), about the origin.

        Edges, assignments, fold angles (degrees), faces and their labels are kept;
        a :class:`PatternError` if ``factor`` is not a finite number > 0 or the
        result leaves :data:`MAX_COORDINATE`. What was done is added to ``notes``.
        """
        factor = float(factor)
        if not (math.isfinite(factor) and factor > 0):
            raise PatternError(f"a scale factor must be a finite number > 0, got {factor:g}")
        if factor == 1.0:
            return self
        if float(np.abs(self.vertices).max()) * factor > MAX_COORDINATE:
            raise PatternError(
                f"scaled by {factor:g} the pattern would lie farther than {MAX_COORDINATE:g} mm "
                "from the origin"
            )
        out = CreasePattern(
            self.vertices * factor,
            self.edges,
            self.assignments,
            self.fold_angles,
            faces=self._faces,
            face_labels=self.face_labels,
            holes=[Hole(h.x * factor, h.y * factor, h.diameter * factor) for h in self.holes],
            metadata=self.metadata,
            tolerance=self.tolerance * factor,
        )
        note = Problem("scaled", f"scaled by {factor:.6g}", severity=Severity.INFO)
        out.notes = (*self.notes, *out.notes, note)
        return out

    def _copy(self) -> CreasePattern:
        out = object.__new__(CreasePattern)
        for name in CreasePattern.__slots__:
            if name != "__weakref__":
                setattr(out, name, getattr(self, name))
        out.metadata = dict(self.metadata)
        return out

    # ------------------------------------------------------------- validation
    def check(self, angle_tolerance: float = 1e-6) -> list[Problem]:
        """Problems of the pattern, each with its location; empty when sound.

        See :func:`origami_cad.pattern.check.check_pattern` for what is checked.
        """
        from origami_cad.pattern.check import check_pattern

        return check_pattern(self, angle_tolerance=angle_tolerance)

    def same_graph(self, other: CreasePattern, tolerance: float = 1e-9) -> bool:
        """True if both patterns have the same edges and assignments within ``tolerance`` mm.

        Vertex and edge order may differ; fold angles are compared within 1e-6 deg.
        """
        return _same_graph(self, other, tolerance)

    def __repr__(self) -> str:
        counts = {a: int(np.sum(self.assignments == a)) for a in "MVBFUCJ"}
        kinds = " ".join(f"{k}={v}" for k, v in counts.items() if v)
        title = f" {self.title!r}" if self.title else ""
        return (
            f"<CreasePattern{title} {self.n_vertices} vertices, {self.n_edges} edges "
            f"({kinds}), {len(self._faces)} faces, {len(self.holes)} holes>"
        )


# ---------------------------------------------------------------------------
# helpers


def _as_edges(edges: Any) -> np.ndarray:
    """Edges as an (m, 2) int64 array; fractional or boolean indices, or more than
    :data:`MAX_EDGES` edges, are refused."""
    try:
        raw = np.asarray(edges)
    except (TypeError, ValueError):
        raise PatternError("edges must be an array of [v1, v2] vertex indices") from None
    if raw.size == 0:
        return np.zeros((0, 2), dtype=np.int64)
    if raw.dtype.kind == "f":
        whole = np.isfinite(raw) & (raw == np.round(raw)) & (np.abs(raw) < 2**62)
        if not whole.all():
            bad = np.argwhere(~whole)[0]
            raise PatternError(
                f"edge {bad[0]}: vertex index {raw[tuple(bad)]!r} is not a whole number"
            )
    elif raw.dtype.kind not in "iu":
        raise PatternError(
            f"edges must hold whole vertex indices, not {raw.dtype.kind!r}-kind values "
            "(booleans, text or objects)"
        )
    if raw.ndim != 2 or raw.shape[1] != 2:
        raise PatternError(f"edges must have shape (m, 2), got {raw.shape}")
    if len(raw) > MAX_EDGES:
        raise PatternError(f"{len(raw):,} edges, more than the limit of {MAX_EDGES:,} (MAX_EDGES)")
    return raw.astype(np.int64)


def _as_vertices(vertices: Any) -> np.ndarray:
    try:
        raw = np.asarray(vertices)
        if raw.dtype.kind not in "iuf":
            raise TypeError
        verts = raw.astype(float)
    except (TypeError, ValueError, OverflowError):
        raise PatternError(
            "vertices must be an (n, 2) array of numbers (not booleans, text or ragged lists)"
        ) from None
    if verts.ndim != 2 or verts.shape[1] not in (2, 3):
        raise PatternError(f"vertices must have shape (n, 2) or (n, 3), got {verts.shape}")
    if verts.shape[1] == 3:
        z = verts[:, 2]
        if z.size and np.ptp(z) > 1e-9 * max(1.0, float(np.abs(verts).max())):
            raise PatternError(
                "vertices are 3D and not flat (z varies); a crease pattern must be planar"
            )
        verts = verts[:, :2]
    if not np.all(np.isfinite(verts)):
        bad = int(np.flatnonzero(~np.isfinite(verts).all(axis=1))[0])
        raise PatternError(f"vertex {bad} has a non-finite coordinate {verts[bad].tolist()}")
    if verts.size and np.abs(verts).max() > MAX_COORDINATE:
        bad = int(np.flatnonzero((np.abs(verts) > MAX_COORDINATE).any(axis=1))[0])
        raise PatternError(
            f"vertex {bad} at {verts[bad].tolist()} mm is farther than {MAX_COORDINATE:g} mm "
            "(1000 km) from the origin; coordinates are limited to that magnitude"
        )
    return np.ascontiguousarray(verts)


def _merge_close(verts: np.ndarray, tol: float) -> np.ndarray:
    """Map each vertex to a representative; vertices within ``tol`` share one."""
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
    return rep[labels]


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
    verts: np.ndarray,
    edges: np.ndarray,
    assign: np.ndarray,
    angles: np.ndarray,
    notes: list[Problem],
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Drop edges joining the same two vertices (either direction), keeping the one
    whose assignment comes first in ``BCMVJUF`` (then the first given); conflicts
    between creases are added to ``notes``."""
    key_lo = np.minimum(edges[:, 0], edges[:, 1])
    key_hi = np.maximum(edges[:, 0], edges[:, 1])
    prio = np.vectorize(_PRIORITY.__getitem__, otypes=[int])(assign) if len(assign) else assign
    order = np.lexsort((np.arange(len(edges)), prio, key_hi, key_lo))
    k_lo, k_hi = key_lo[order], key_hi[order]
    first = np.ones(len(order), dtype=bool)
    first[1:] = (k_lo[1:] != k_lo[:-1]) | (k_hi[1:] != k_hi[:-1])
    group = np.cumsum(first) - 1
    kept_assign = assign[order][first][group]
    conflict = (assign[order] != kept_assign) & ~np.isin(assign[order], ["U", "F"])
    for idx in order[conflict][:20]:
        a, b = edges[idx]
        mid = tuple(float(c) for c in (verts[a] + verts[b]) / 2)
        kept = kept_assign[np.flatnonzero(order == idx)[0]]
        notes.append(
            Problem(
                "duplicate-conflict",
                f"two coincident edges are {assign[idx]} and {kept}; kept {kept}",
                mid,
                Severity.WARNING,
            )
        )
    n_dup = int((~first).sum())
    keep = np.sort(order[first])
    edges, assign, angles = edges[keep], assign[keep], angles[keep]
    return edges, assign, angles, n_dup


def _normalise(
    verts: np.ndarray,
    edges: np.ndarray,
    assign: np.ndarray,
    angles: np.ndarray,
    tol: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[Problem], bool]:
    notes: list[Problem] = []
    n_in_vertices, n_in_edges = len(verts), len(edges)
    # 1. snap near-coincident vertices
    rep = _merge_close(verts, tol)
    merged = int(np.sum(rep != np.arange(len(rep))))
    edges = rep[edges]
    n_used = len(np.unique(edges))
    if n_used > MAX_VERTICES:
        raise PatternError(
            f"{n_used:,} vertices, more than the limit of {MAX_VERTICES:,} (MAX_VERTICES)"
        )
    # 2. zero-length edges
    zero = edges[:, 0] == edges[:, 1]
    n_zero = int(zero.sum())
    edges, assign, angles = edges[~zero], assign[~zero], angles[~zero]
    # exact duplicates go before the split, so that they cost nothing there
    edges, assign, angles, n_dup = _drop_duplicates(verts, edges, assign, angles, notes)
    # 3. split at T-junctions and crossings
    se, st, sv, new = _split_points(verts, edges, tol)
    n_split = len(np.unique(se))
    n_cross = len(new)
    if len(se):
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
        rep = _merge_close(verts, tol)
        edges = rep[edges]
        zero = edges[:, 0] == edges[:, 1]
        edges, assign, angles = edges[~zero], assign[~zero], angles[~zero]
    # 4. duplicates in either direction: keep the highest-priority assignment
    edges, assign, angles, more = _drop_duplicates(verts, edges, assign, angles, notes)
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
    n_unused = n_in_vertices - merged - len(used) + n_cross
    changed = bool(merged or n_zero or n_split or n_dup or n_unused) or len(edges) != n_in_edges
    for count, text in (
        (merged, "vertices merged with a neighbour closer than the tolerance"),
        (n_zero, "zero-length edges dropped"),
        (n_split, "edges split at T-junctions or crossings"),
        (n_cross, "vertices added where edges cross"),
        (n_dup, "duplicate edges dropped"),
        (n_unused, "unused vertices dropped"),
    ):
        if count:
            notes.append(Problem("normalised", f"{count} {text}", severity=Severity.INFO))
    return (
        np.ascontiguousarray(verts, dtype=float),
        np.ascontiguousarray(edges, dtype=np.int64),
        assign.astype("<U1"),
        angles.astype(float),
        notes,
        changed,
    )


def _flat_rings(rings: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Concatenate rings: (flat vertex indices, next position in the ring, ring starts)."""
    counts = np.array([len(r) for r in rings], dtype=np.int64)
    flat = np.concatenate(rings) if rings else np.zeros(0, np.int64)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
    nxt = np.arange(len(flat)) + 1
    if len(rings):
        nxt[starts + counts - 1] = starts
    return flat, nxt, starts


def _rings_with_edges(
    cp: CreasePattern, rings: list[np.ndarray]
) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...], np.ndarray]:
    """Orient rings counter-clockwise, find the edge of every side (-1 where none).

    Returns ``(rings, sides, areas)`` with areas in mm^2.
    """
    if not rings:
        return (), (), np.zeros(0)
    flat, nxt, starts = _flat_rings(rings)
    p, q = cp.vertices[flat], cp.vertices[flat[nxt]]
    area = 0.5 * np.add.reduceat(p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0], starts)
    rings = [r[::-1].copy() if a < 0 else r for r, a in zip(rings, area, strict=True)]
    flat, nxt, starts = _flat_rings(rings)
    n = cp.n_vertices
    keys = np.minimum(cp.edges[:, 0], cp.edges[:, 1]) * n + np.maximum(
        cp.edges[:, 0], cp.edges[:, 1]
    )
    order = np.argsort(keys)
    sk = keys[order]
    a, b = flat, flat[nxt]
    k = np.minimum(a, b) * n + np.maximum(a, b)
    pos = np.minimum(np.searchsorted(sk, k), len(sk) - 1)
    side = np.where(sk[pos] == k, order[pos], -1)
    return tuple(rings), tuple(np.split(side, starts[1:])), np.abs(area)


def _given_faces(
    cp: CreasePattern, faces: Sequence[Sequence[int]]
) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...]]:
    n = cp.n_vertices
    rings = []
    for fi, face in enumerate(faces):
        ring = np.asarray(face, dtype=np.int64).reshape(-1)
        if len(ring) < 3:
            raise PatternError(f"face {fi} has fewer than 3 vertices")
        if ring.min() < 0 or ring.max() >= n:
            raise PatternError(f"face {fi} refers to a vertex that does not exist")
        rings.append(ring)
    out, sides, _ = _rings_with_edges(cp, rings)
    for fi, fe in enumerate(sides):
        if (fe < 0).any():
            raise PatternError(f"face {fi} has a side that is not an edge")
    return out, sides


def _compute_faces(
    cp: CreasePattern,
) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...], list[Problem]]:
    """Faces of the planar graph (shapely ``polygonize``), sorted by centroid (y, x)."""
    notes: list[Problem] = []
    lines = shapely.linestrings(cp.vertices[cp.edges])
    polys = shapely.get_parts(shapely.polygonize(lines))
    if len(polys) == 0:
        return (), (), notes
    coords, idx = shapely.get_coordinates(shapely.get_exterior_ring(polys), return_index=True)
    last = np.r_[idx[1:] != idx[:-1], True]  # each ring's closing coordinate
    coords, idx = coords[~last], idx[~last]
    dist, vid = cKDTree(cp.vertices).query(coords)
    if np.any(dist > 0):  # pragma: no cover - polygonize keeps input coordinates
        raise PatternError("internal error: a face corner is not a vertex")
    starts = np.flatnonzero(np.r_[True, idx[1:] != idx[:-1]])
    rings = np.split(vid.astype(np.int64), starts[1:])
    for k in np.flatnonzero(shapely.get_num_interior_rings(polys)):
        c = shapely.get_coordinates(shapely.get_interior_ring(polys[k], 0))[0]
        notes.append(
            Problem(
                "face-with-hole",
                "a panel encloses another part of the pattern (its inner outline is "
                "not connected to its outer one)",
                (float(c[0]), float(c[1])),
            )
        )
    cent = shapely.get_coordinates(shapely.centroid(polys))
    perm = np.lexsort((np.round(cent[:, 0], 6), np.round(cent[:, 1], 6)))
    rings = [rings[k] for k in perm]
    rings, sides, _ = _rings_with_edges(cp, rings)
    # start every ring at its lowest vertex index, so faces are canonical
    shift = [int(np.argmin(r)) for r in rings]
    rings = tuple(np.roll(r, -s) for r, s in zip(rings, shift, strict=True))
    sides = tuple(np.roll(e, -s) for e, s in zip(sides, shift, strict=True))
    return rings, sides, notes


def _same_graph(a: CreasePattern, b: CreasePattern, tol: float) -> bool:
    if a.n_vertices != b.n_vertices or a.n_edges != b.n_edges:
        return False
    dist, match = cKDTree(b.vertices).query(a.vertices)
    if np.any(dist > tol) or len(np.unique(match)) != a.n_vertices:
        return False
    ea = match[a.edges]
    ka = np.minimum(ea[:, 0], ea[:, 1]) * a.n_vertices + np.maximum(ea[:, 0], ea[:, 1])
    kb = np.minimum(b.edges[:, 0], b.edges[:, 1]) * a.n_vertices + np.maximum(
        b.edges[:, 0], b.edges[:, 1]
    )
    oa, ob = np.argsort(ka), np.argsort(kb)
    return bool(
        np.array_equal(ka[oa], kb[ob])
        and np.array_equal(a.assignments[oa], b.assignments[ob])
        and np.allclose(a.fold_angles[oa], b.fold_angles[ob], atol=1e-6)
    )
