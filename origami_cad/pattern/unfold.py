"""Unfold a folded form (3D faces sharing vertices) back into its flat crease pattern.

A FOLD file may hold only a folded state (``frame_classes: ["foldedForm"]``, as
the FOLD project's own examples do): its faces are planar polygons in space
that share vertices and edges. Since paper does not stretch, laying every face
flat next to its neighbours, across their shared edges, gives the crease
pattern: :func:`unfold_faces` does that over a spanning tree of the faces, each
face put on the far side of the edge from the face already laid, and then
checks that every vertex lands in one place from all its faces (a form that
is not developable, or faces that do not form one sheet, is refused by
name). :func:`fold_angles_of_form` measures the form's fold angles.

>>> import numpy as np
>>> # a square folded 90 degrees along its diagonal-free middle line x = 1
>>> xyz = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
...                 [1, 0, 1], [1, 1, 1]], dtype=float)
>>> flat = unfold_faces(xyz, [[0, 1, 2, 3], [1, 4, 5, 2]])
>>> np.round(flat, 9).tolist()
[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0], [2.0, 1.0]]
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence

import numpy as np

from origami_cad.errors import PatternError

__all__ = ["counter_clockwise", "faces_per_edge", "fold_angles_of_form", "unfold_faces"]


def _normal(points: np.ndarray) -> np.ndarray:
    """Unit normal of a polygon (Newell's method), oriented by its vertex order."""
    nxt = np.roll(points, -1, axis=0)
    n = np.array(
        [
            np.sum((points[:, 1] - nxt[:, 1]) * (points[:, 2] + nxt[:, 2])),
            np.sum((points[:, 2] - nxt[:, 2]) * (points[:, 0] + nxt[:, 0])),
            np.sum((points[:, 0] - nxt[:, 0]) * (points[:, 1] + nxt[:, 1])),
        ]
    )
    length = float(np.linalg.norm(n))
    return n / length if length > 0 else n


def _signed_area(ring: np.ndarray) -> float:
    """Signed area of a 2D ring (n, 2): positive when counter-clockwise."""
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def counter_clockwise(flat: np.ndarray, faces: Sequence[Sequence[int]]) -> list[list[int]]:
    """Each face's vertex list turned, where needed, to run counter-clockwise in ``flat``
    (n, 2): the faces seen from the top of the laid-out sheet."""
    return [list(f) if _signed_area(flat[list(f)]) > 0 else list(f)[::-1] for f in faces]


def faces_per_edge(faces: Sequence[Sequence[int]], edges: np.ndarray) -> np.ndarray:
    """How many of ``faces`` have each edge of ``edges`` (m, 2) on their boundary."""
    on = _face_edges(faces)
    return np.array([len(on.get((min(a, b), max(a, b)), ())) for a, b in edges], dtype=int)


def _face_edges(faces: Sequence[Sequence[int]]) -> dict[tuple[int, int], list[int]]:
    """The faces on each undirected edge ``(low, high)`` of the faces' boundaries."""
    out: dict[tuple[int, int], list[int]] = {}
    for f, face in enumerate(faces):
        for a, b in zip(face, [*face[1:], face[0]], strict=True):
            out.setdefault((min(a, b), max(a, b)), []).append(f)
    return out


def _check_faces(xyz: np.ndarray, faces: Sequence[Sequence[int]], size: float) -> None:
    for f, face in enumerate(faces):
        if len(set(face)) != len(face):
            raise PatternError(f"face {f} of the folded form lists a vertex twice")
        if any(not 0 <= w < len(xyz) for w in face):
            raise PatternError(
                f"face {f} of the folded form refers to a vertex that does not exist"
            )
        pts = xyz[list(face)]
        sides = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)
        if len(face) < 3 or np.any(sides <= 1e-9 * size):
            raise PatternError(
                f"face {f} of the folded form is degenerate (fewer than 3 corners, or a side "
                "of zero length)"
            )
        n = _normal(pts)
        if not np.any(n):
            raise PatternError(f"face {f} of the folded form is degenerate (no area)")
        off = np.abs((pts - pts[0]) @ n)
        if off.max() > 1e-6 * size:
            raise PatternError(
                f"face {f} of the folded form is not planar ({off.max():.3g} out of its plane)"
            )


def _runs(face: Sequence[int], a: int, b: int) -> bool:
    """Whether ``face`` runs its edge from ``a`` to ``b`` (else from ``b`` to ``a``)."""
    k = list(face).index(a)
    return face[(k + 1) % len(face)] == b


def _lay(xyz, face, a, b, flat_a, flat_b, away) -> dict[int, np.ndarray]:
    """The face's vertices in the plane, its edge ``a b`` at ``flat_a flat_b`` and its
    interior on the side ``away`` (a unit 2D vector perpendicular to the edge).

    Each vertex keeps its distance along the edge and its signed distance from the
    edge's line, positive towards the face's interior (the left of its own direction
    round its normal), so that concave faces keep their shape.
    """
    pa, pb = xyz[a], xyz[b]
    u = (pb - pa) / np.linalg.norm(pb - pa)
    inward = np.cross(_normal(xyz[list(face)]), u) * (1.0 if _runs(face, a, b) else -1.0)
    u2 = (flat_b - flat_a) / np.linalg.norm(flat_b - flat_a)
    out = {}
    for w in face:
        d = xyz[w] - pa
        out[int(w)] = flat_a + float(d @ u) * u2 + float(d @ inward) * away
    return out


def _interior_side(flat: dict[int, np.ndarray], face: Sequence[int], a: int, b: int) -> np.ndarray:
    """The unit 2D normal of the laid face's edge ``a -> b`` on the face's interior side."""
    ccw = _signed_area(np.array([flat[w] for w in face])) > 0
    edge = (flat[b] - flat[a]) / np.linalg.norm(flat[b] - flat[a])
    left = np.array([-edge[1], edge[0]])
    return left if ccw == _runs(face, a, b) else -left


def unfold_faces(xyz: np.ndarray, faces: Sequence[Sequence[int]], tol: float = 1e-4) -> np.ndarray:
    """The flat crease pattern (n, 2) of a folded form: vertices ``xyz`` (n, 3) and faces.

    Parameters
    ----------
    xyz : ndarray
        (n, 3) vertex positions of the folded form, in any length unit (the result
        is in the same unit).
    faces : sequence of sequences of int
        Each face's vertex indices in order (``faces_vertices``); faces sharing a
        crease share its two vertices.
    tol : float
        How far (relative to the form's size) a vertex may land from itself when
        reached through different faces.

    Returns
    -------
    ndarray
        (n, 2) the unfolded positions; the first face keeps its shape with its first
        edge along +x and its vertices counter-clockwise.

    Raises
    ------
    PatternError
        When a face is degenerate or not planar, the faces do not form one sheet
        (an unconnected face or a vertex in no face), or the form does not unfold
        flat (a vertex reached at two places: the form is stretched or torn).
    """
    xyz = np.asarray(xyz, dtype=float)
    if xyz.shape[1] == 2:  # a form folded flat, in the plane
        xyz = np.column_stack([xyz, np.zeros(len(xyz))])
    faces = [list(map(int, f)) for f in faces]
    if not faces:
        raise PatternError("the folded form has no faces to unfold")
    size = max(float(np.ptp(xyz, axis=0).max()), 1e-300)
    _check_faces(xyz, faces, size)
    by_edge = _face_edges(faces)
    for (a, b), on in by_edge.items():
        if len(on) > 2:
            raise PatternError(
                f"the edge between vertices {a} and {b} borders {len(on)} faces of the "
                f"folded form ({', '.join(map(str, on))}): paper has two sides, not more"
            )
    # the first face in its own plane: first edge along +x, the face on its left (+y)
    f0 = faces[0]
    a, b = f0[0], f0[1]
    length = float(np.linalg.norm(xyz[b] - xyz[a]))
    up = np.array([0.0, 1.0])
    placed = {0: _lay(xyz, f0, a, b, np.zeros(2), np.array([length, 0.0]), up)}
    queue = deque([0])
    while queue:
        f = queue.popleft()
        face = faces[f]
        for a, b in zip(face, [*face[1:], face[0]], strict=True):
            for g in by_edge[(min(a, b), max(a, b))]:
                if g in placed:
                    continue
                away = -_interior_side(placed[f], face, a, b)  # across the crease from f
                placed[g] = _lay(xyz, faces[g], a, b, placed[f][a], placed[f][b], away)
                queue.append(g)
    missing = sorted(set(range(len(faces))) - set(placed))
    if missing:
        raise PatternError(
            f"face {missing[0]} of the folded form shares no edge with face 0: the faces "
            "do not form one sheet"
        )
    flat = _merge(placed, len(xyz), size, tol)
    _check_no_overlap(flat, faces, size, tol)
    return flat


def _check_no_overlap(flat: np.ndarray, faces: list[list[int]], size: float, tol: float) -> None:
    """Refuse a layout whose faces overlap: paper lies flat in one layer."""
    import shapely

    polygons = np.array([shapely.Polygon(flat[f]) for f in faces])
    bad = np.flatnonzero(~shapely.is_valid(polygons))
    if bad.size:
        raise PatternError(
            f"face {bad[0]} of the folded form crosses itself when laid flat (is it planar "
            "and listed in order round its boundary?)"
        )
    areas = shapely.area(polygons)
    total = float(np.sum(areas))
    union = float(shapely.area(shapely.union_all(polygons)))
    if total - union > tol * float(np.min(areas)):
        tree = shapely.STRtree(polygons)
        for f, g in np.asarray(tree.query(polygons, predicate="overlaps")).T:
            if f < g and shapely.area(shapely.intersection(polygons[f], polygons[g])) > 0:
                raise PatternError(
                    f"the folded form does not unfold into one layer: faces {f} and {g} "
                    "overlap when laid flat"
                )
        raise PatternError("the folded form does not unfold into one layer: its faces overlap")


def _merge(placed: dict, n: int, size: float, tol: float) -> np.ndarray:
    """One position per vertex from every face's layout; refuse where they disagree."""
    sums = np.zeros((n, 2))
    counts = np.zeros(n)
    first: dict[int, np.ndarray] = {}
    for f in sorted(placed):
        for w, p in placed[f].items():
            if w in first and np.linalg.norm(p - first[w]) > tol * size:
                gap = float(np.linalg.norm(p - first[w]))
                raise PatternError(
                    f"the folded form does not unfold flat: vertex {w} lands at two places "
                    f"{gap:.3g} apart (through face {f}); the form is stretched or torn there"
                )
            first.setdefault(w, p)
            sums[w] += p
            counts[w] += 1
    if np.any(counts == 0):
        w = int(np.flatnonzero(counts == 0)[0])
        raise PatternError(f"vertex {w} of the folded form lies on no face")
    return sums / counts[:, None]


def fold_angles_of_form(
    xyz: np.ndarray, faces: Sequence[Sequence[int]], edges: np.ndarray
) -> np.ndarray:
    """Each edge's fold angle in the folded form, degrees (valley positive; NaN off creases).

    ``edges`` (m, 2) vertex pairs; an edge between two faces gets the angle between
    their normals, positive when the second face lies on the first one's normal side
    (a valley, folding toward the top), NaN where the edge borders fewer than two
    faces (two faces listed the opposite ways round are taken as one sheet). A crease
    folded flat, its faces in one plane, has no sense the geometry can tell: NaN.
    """
    xyz = np.asarray(xyz, dtype=float)
    if xyz.shape[1] == 2:
        xyz = np.column_stack([xyz, np.zeros(len(xyz))])
    by_edge = _face_edges(faces)
    normals = [_normal(xyz[list(f)]) for f in faces]
    out = np.full(len(edges), np.nan)
    for k, (a, b) in enumerate(np.asarray(edges, dtype=int)):
        on = by_edge.get((min(a, b), max(a, b)), [])
        if len(on) != 2:
            continue
        f, g = on
        forward = _runs(faces[f], a, b)
        u = xyz[b] - xyz[a] if forward else xyz[a] - xyz[b]  # the edge as f runs it
        u = u / np.linalg.norm(u)
        n_f = normals[f]
        # g oriented like f: it runs the shared edge the other way round
        n_g = normals[g] if _runs(faces[g], a, b) != forward else -normals[g]
        across, dot = float(np.cross(n_f, n_g) @ u), float(n_f @ n_g)
        if abs(across) <= 1e-6 and dot < 0:
            continue  # folded flat: mountain or valley only the layer order tells
        out[k] = -float(np.degrees(np.arctan2(across, dot)))
    return out
