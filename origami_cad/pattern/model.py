"""The crease-pattern data model.

A :class:`CreasePattern` is a planar straight-line graph in millimetres: vertices,
edges with an M/V/B/F/U/C/J assignment and a target fold angle, and the faces
(panels) bounded by the edges. It normalises its input on construction
(:func:`origami_cad.pattern.planar.normalise`: snaps near-coincident vertices, splits
edges at T-junctions and crossings, drops zero-length and duplicate edges) in
O(n log n), and records what it changed in :attr:`CreasePattern.notes` and
:attr:`CreasePattern.cleanup` (the largest gap it closed), so nothing is repaired behind
the user's back.

Inputs are checked, not coerced: vertex indices must be whole numbers,
coordinates finite numbers within :data:`MAX_COORDINATE` mm, fold angles finite,
within [-180, 180] degrees and of the assignment's sign (a mountain folds to a
negative angle, a valley to a positive one, a border, flat crease or cut not at all);
an edge joins two different vertices; given faces name vertices that exist. A pattern
has at most :data:`MAX_EDGES` edges and :data:`MAX_VERTICES` vertices (checked before
any costly step), and normalisation works within the budgets of
:mod:`origami_cad.pattern.planar`.

Flat (``F``) edges are facet creases: they stay flat (a triangulated panel's
diagonals, as Origami Simulator draws them); :meth:`CreasePattern.panels` groups the
faces they join into the panels a printer makes. Unassigned (``U``) edges are free
hinges.

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
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from origami_cad._args import Arg, brief_value
from origami_cad._display import PatternDisplay
from origami_cad._toml import printable
from origami_cad.errors import PatternError
from origami_cad.pattern.planar import (
    MAX_CANDIDATE_PAIRS,
    MAX_CLOSE_PAIRS,
    MAX_CROSSINGS,
    MAX_VERTICES,
    Cleanup,
    normalise,
    open_cuts,
    planar_faces,
    rings_with_edges,
)
from origami_cad.pattern.problems import CLEANUP_CODES, Problem, Severity, cleanup_notes

__all__ = [
    "DEFAULT_RELATIVE_TOLERANCE",
    "MAX_CANDIDATE_PAIRS",
    "MAX_CLOSE_PAIRS",
    "MAX_COORDINATE",
    "MAX_CROSSINGS",
    "MAX_EDGES",
    "MAX_VERTICES",
    "Assignment",
    "Cleanup",
    "CreasePattern",
    "Hole",
    "Problem",
    "Severity",
    "cleanup_notes",
    "default_fold_angles",
    "printable",
]

#: Vertices closer than this fraction of the pattern's size are merged.
DEFAULT_RELATIVE_TOLERANCE = 1e-6
#: Largest coordinate magnitude accepted, mm (1000 km). Anything larger is a
#: mistake (or a hostile file) and would overflow the geometry in squares and areas.
MAX_COORDINATE = 1e9
#: Most edges a pattern may be given (before normalisation splits them at crossings).
MAX_EDGES = 100_000


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
    if not isinstance(assignments, str) and (
        isinstance(assignments, bytes | Mapping) or not isinstance(assignments, Iterable)
    ):
        raise PatternError(
            f"assignments must be letters (M V B F U C J), one per edge, got {assignments!r:.60}"
        )
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


class CreasePattern(PatternDisplay):
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
        Target fold angle per edge, degrees (valley positive, mountain negative),
        finite, within [-180, 180] and of the letter's sign (``B``, ``F``, ``C``: 0).
        Default: +-180 for V/M and 0 for other edges.
    faces : sequence of index arrays, optional
        Faces as vertex-index rings (at least 3 vertices that exist, or a
        :class:`PatternError` naming the face). Used when normalisation does not
        change the graph and every side is an edge; otherwise faces are computed
        from the planar graph (shapely ``polygonize``), with a warning note when
        they were usable but their sides are not edges.
    holes : iterable of Hole, optional
        Circular holes on panels.
    face_labels : sequence of str, optional
        One label per face (used with ``faces``); default ``f0, f1, ...``.
    metadata : dict, optional
        Free-form metadata; ``title`` and ``creator`` are written to files.
    tolerance : float or callable, optional
        Distance under which vertices merge and points count as on an edge, mm; or
        a function of the vertices in use (an ``(k, 2)`` array, mm) returning it
        (how :func:`~origami_cad.pattern.io.read_pattern` applies a tolerance meant
        for the pattern once scaled to a width). Default:
        :data:`DEFAULT_RELATIVE_TOLERANCE` times the diagonal of the bounding box
        (exact constructions; the file readers default to
        :data:`~origami_cad.pattern.planar.IMPORT_RELATIVE_TOLERANCE`).

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
        "cleanup",
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
        tolerance: float | Callable[[np.ndarray], float] | None = None,
    ) -> None:
        verts = _as_vertices(vertices)
        edge_arr = _as_edges(edges)
        _check_edge_indices(edge_arr, len(verts))
        assign = _as_assignments(assignments, len(edge_arr))
        angles = _as_fold_angles(fold_angles, assign)
        if len(edge_arr) == 0:
            raise PatternError("the pattern has no edges")
        if faces is not None:
            _check_face_indices(faces, len(verts))
        if metadata is not None and not isinstance(metadata, Mapping):
            raise PatternError(f"metadata must be a dict, got {brief_value(metadata)}")
        holes = _as_holes(holes)
        self.tolerance = _resolve_tolerance(tolerance, verts[np.unique(edge_arr)])
        self.metadata = dict(metadata or {})
        self.metadata.setdefault("unit", "mm")
        result = normalise(verts, edge_arr, assign, angles, self.tolerance)
        self.vertices, self.edges, self.assignments, self.fold_angles, self.cleanup = result
        if len(self.edges) == 0:
            raise PatternError(
                "every edge has zero length (its two vertices coincide): no crease is left"
            )
        for arr in (self.vertices, self.edges, self.assignments, self.fold_angles):
            arr.flags.writeable = False
        face_notes: list[Problem] = []
        computed = True
        if faces is not None and not self.cleanup.changed:
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
        self.notes = tuple(cleanup_notes(self.cleanup) + face_notes)
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
        return rings_with_edges(self.vertices, self.edges, list(self._faces))[2]

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

    def face_panels(self) -> np.ndarray:
        """Panel index of every face, shape (f,): faces joined across flat (``F``) facet
        creases share a panel, numbered by their lowest face index.

        A facet crease stays flat, so the faces it joins are one rigid, printed panel
        (Origami Simulator's triangulated panels); every other edge bounds panels.
        """
        nf = len(self._faces)
        if not nf:
            return np.zeros(0, dtype=np.int64)
        ef = self.edge_faces()
        join = self.edge_mask("F") & (ef >= 0).all(axis=1) & (ef[:, 0] != ef[:, 1])
        pairs = ef[join]
        graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(nf, nf))
        _, labels = connected_components(graph, directed=False)
        first = np.full(labels.max() + 1, nf, dtype=np.int64)
        np.minimum.at(first, labels, np.arange(nf))
        order = np.argsort(first)  # panels numbered in the order of their first face
        rank = np.empty_like(order)
        rank[order] = np.arange(len(order))
        return rank[labels]

    def panels(self) -> tuple[np.ndarray, ...]:
        """The panels: the face indices of each, faces joined across flat (``F``) facet
        creases together (see :meth:`face_panels`), in the order of their first face."""
        which = self.face_panels()
        if not len(which):
            return ()
        order = np.argsort(which, kind="stable")
        starts = np.flatnonzero(np.r_[True, np.diff(which[order]) != 0])
        return tuple(np.split(order, starts[1:]))

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
        out.cleanup = self.cleanup.scaled(factor)  # what the reader merged, in the new mm
        kept = [n for n in self.notes if n.code not in CLEANUP_CODES]
        out.notes = (*cleanup_notes(out.cleanup), *kept, *out.notes, note)
        return out

    def with_outline_cuts_as_border(self) -> CreasePattern:
        """A copy whose cut (``C``) edges on the outer boundary of the sheet are border
        (``B``): ORIPA draws its paper's outline as cut lines. Itself when there are none;
        an ``outline-cuts`` note counts them."""
        cut = np.flatnonzero(self.assignments == "C")
        if cut.size == 0 or not self._faces:
            return self
        parts = shapely.get_parts(shapely.union_all(self.face_polygons()))
        polys = parts[shapely.get_type_id(parts) == 3]  # Polygon
        if polys.size == 0:
            return self
        rings = shapely.get_exterior_ring(polys)
        mids = shapely.points(self.vertices[self.edges[cut]].mean(axis=1))
        on = shapely.dwithin(mids[:, None], rings[None, :], 4 * self.tolerance).any(axis=1)
        if not on.any():
            return self
        assign = self.assignments.copy()
        assign[cut[on]] = "B"
        out = CreasePattern(
            self.vertices,
            self.edges,
            assign,
            self.fold_angles,
            metadata=self.metadata,
            holes=self.holes,
            tolerance=self.tolerance,
        )
        note = Problem(
            "outline-cuts",
            f"{int(on.sum())} cut edges on the outer boundary of the sheet taken as border",
            severity=Severity.INFO,
        )
        out.cleanup = self.cleanup
        out.notes = (*self.notes, *out.notes, note)
        return out

    def with_cuts_opened(self) -> CreasePattern:
        """A copy whose cuts between two faces are open (:func:`~.planar.open_cuts`): each
        side has its own copies of the vertices (same coordinates, mm), the vertices and
        edges of ``self`` first, with their indices. Itself when no cut has two faces."""
        n, faces = len(self.vertices), self.faces
        split = open_cuts(n, self.edges, self.assignments, faces, self.face_edges)
        if split is None:
            return self
        out, source = self._copy(), split[2]
        out.edges, out._faces, out._face_edges = split[1], split[3], split[4]
        out.vertices, out.assignments = self.vertices[split[0]], self.assignments[source]
        out.fold_angles = self.fold_angles[source]
        for arr in (out.vertices, out.edges, out.assignments, out.fold_angles):
            arr.flags.writeable = False
        return out

    def _copy(self) -> CreasePattern:
        out = object.__new__(CreasePattern)
        for name in CreasePattern.__slots__:
            if name != "__weakref__":
                setattr(out, name, getattr(self, name))
        out.metadata = dict(self.metadata)
        return out

    # ------------------------------------------------------------- validation
    def check(self, angle_tolerance: float | None = None) -> list[Problem]:
        """Problems of the pattern, each with its location; empty when sound.

        ``angle_tolerance``: the least tolerance of Kawasaki's defect, radians
        (default :data:`~origami_cad.pattern.check.KAWASAKI_TOLERANCE`).

        See :func:`origami_cad.pattern.check.check_pattern` for what is checked.
        """
        from origami_cad.pattern.check import check_pattern

        if angle_tolerance is None:
            return check_pattern(self)
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
    except (TypeError, ValueError, OverflowError):
        raise PatternError("edges must be an array of [v1, v2] vertex indices") from None
    if raw.size == 0:
        return np.zeros((0, 2), dtype=np.int64)
    if raw.ndim != 2 or raw.shape[1] != 2:
        raise PatternError(f"edges must have shape (m, 2), got {raw.shape}")
    if raw.dtype.kind == "f":
        whole = np.isfinite(raw) & (raw == np.round(raw)) & (np.abs(raw) < 2**62)
        if not whole.all():
            bad = np.argwhere(~whole)[0]
            raise PatternError(
                f"edge {bad[0]}: vertex index {raw[tuple(bad)].item()!r} is not a whole number"
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


def _check_edge_indices(edges: np.ndarray, n: int) -> None:
    """PatternError naming the first edge that refers to a missing vertex or joins a
    vertex to itself."""
    if not edges.size:
        return
    if edges.min() < 0 or edges.max() >= n:
        bad = int(np.flatnonzero((edges < 0).any(1) | (edges >= n).any(1))[0])
        raise PatternError(
            f"edge {bad} refers to vertex {edges[bad].tolist()} but there are {n} vertices"
        )
    loops = np.flatnonzero(edges[:, 0] == edges[:, 1])
    if loops.size:
        k = int(loops[0])
        raise PatternError(
            f"edge {k} joins vertex {int(edges[k, 0])} to itself (an edge needs two vertices)"
        )


def _as_fold_angles(fold_angles: Any, assign: np.ndarray) -> np.ndarray:
    """The fold angles (degrees) of the edges: the letters' defaults, or those given,
    checked (finite, within [-180, 180], of the letter's sign)."""
    angles = default_fold_angles(assign)
    if fold_angles is None:
        return angles
    try:
        given = np.asarray(fold_angles, dtype=float).reshape(-1)
    except (TypeError, ValueError, OverflowError):
        raise PatternError("fold angles must be numbers, in degrees") from None
    if given.shape != angles.shape:
        raise PatternError(f"{given.size} fold angles given for {angles.size} edges")
    bad = np.flatnonzero(~np.isfinite(given))
    if bad.size:
        k = int(bad[0])
        raise PatternError(f"edge {k}: fold angle {float(given[k])} is not a finite number")
    bad = np.flatnonzero(np.abs(given) > 180 + 1e-9)
    if bad.size:
        k = int(bad[0])
        raise PatternError(f"edge {k}: fold angle {float(given[k]):g} deg is outside [-180, 180]")
    flat = np.isin(assign, ("B", "F", "C")) & (np.abs(given) > 1e-6)
    wrong = ((assign == "M") & (given > 0)) | ((assign == "V") & (given < 0)) | flat
    if wrong.any():
        k = int(np.flatnonzero(wrong)[0])
        letter = str(assign[k])
        what, sign = {"M": ("a mountain", "negative"), "V": ("a valley", "positive")}.get(
            letter, (f"a {Assignment(letter).name.lower()} edge", "zero")
        )
        raise PatternError(
            f"edge {k}: fold angle {float(given[k]):g} deg contradicts its assignment "
            f"{letter}: {what} folds to a {sign} angle"
        )
    return given.copy()


def _as_holes(holes: Any) -> tuple[Hole, ...]:
    """``holes`` as a tuple of :class:`Hole`; anything else is a PatternError."""
    if isinstance(holes, str | bytes | Mapping) or not isinstance(holes, Iterable):
        raise PatternError(f"holes must be a list of Hole, got {brief_value(holes)}")
    out = tuple(holes)
    bad = next((h for h in out if not isinstance(h, Hole)), None)
    if bad is not None:
        raise PatternError(f"holes must be a list of Hole, got an item {brief_value(bad)}")
    return out


def _check_face_indices(faces: Sequence[Sequence[int]], n: int) -> None:
    """PatternError naming the first given face with fewer than 3 vertices, or with an
    index that is not a whole number naming a vertex."""
    if isinstance(faces, str | bytes | Mapping) or not isinstance(faces, Iterable):
        raise PatternError(f"faces must be a list of vertex index lists, got {faces!r:.60}")
    for fi, face in enumerate(faces):
        try:
            ring = np.asarray(face)
        except (TypeError, ValueError, OverflowError):
            raise PatternError(f"face {fi} is not a list of vertex indices") from None
        ring = ring.reshape(-1)
        if ring.dtype.kind not in "iu" and not (
            ring.dtype.kind == "f" and np.all(np.isfinite(ring) & (ring == np.round(ring)))
        ):
            raise PatternError(f"face {fi} holds something other than whole vertex indices")
        if len(ring) < 3:
            raise PatternError(f"face {fi} has {len(ring)} vertices, fewer than 3")
        out = (ring < 0) | (ring >= n)
        if out.any():
            raise PatternError(
                f"face {fi} refers to vertex {int(ring[out][0])} but there are {n} vertices"
            )


def _resolve_tolerance(
    tolerance: float | Callable[[np.ndarray], float] | None, used: np.ndarray
) -> float:
    """The tolerance in mm: given, computed from the vertices in use, or the default."""
    if callable(tolerance):
        Arg("callable", length=1).check("tolerance", tolerance, PatternError)
        tolerance = tolerance(used)
    if tolerance is None:
        size = float(np.linalg.norm(np.ptp(used, axis=0))) if len(used) else 0.0
        tolerance = DEFAULT_RELATIVE_TOLERANCE * max(size, 1e-9)
    try:
        value = float(tolerance)
    except (TypeError, ValueError, OverflowError):
        raise PatternError(
            f"tolerance must be a length in mm, got {brief_value(tolerance)}"
        ) from None
    if not (math.isfinite(value) and value > 0):
        raise PatternError(f"tolerance must be a finite length > 0 mm, got {value:g}")
    return value


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


def _given_faces(
    cp: CreasePattern, faces: Sequence[Sequence[int]]
) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...]]:
    """The given faces (indices checked already) counter-clockwise with their sides'
    edges; a PatternError naming a face with a side that is not an edge."""
    rings = [np.asarray(face, dtype=np.int64).reshape(-1) for face in faces]
    out, sides, _ = rings_with_edges(cp.vertices, cp.edges, rings)
    for fi, fe in enumerate(sides):
        if (fe < 0).any():
            raise PatternError(f"face {fi} has a side that is not an edge")
    return out, sides


def _compute_faces(
    cp: CreasePattern,
) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...], list[Problem]]:
    """Faces of the planar graph (:func:`~origami_cad.pattern.planar.planar_faces`), and
    an error note at each panel enclosing another part of the pattern."""
    rings, sides, inner = planar_faces(cp.vertices, cp.edges, cp.assignments)
    notes = [
        Problem(
            "face-with-hole",
            "a panel encloses another part of the pattern (its inner outline is "
            "not connected to its outer one)",
            where,
        )
        for where in inner
    ]
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
