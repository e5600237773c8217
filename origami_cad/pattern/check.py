"""Validation of crease patterns that explains itself.

:func:`check_pattern` lists every problem with its location and never changes
the pattern. It checks, in this order:

- what normalisation changed on construction (``info``/``warning`` notes);
- the border: every border vertex joins exactly two border edges (an open or
  self-crossing outline is reported; black lines with a panel on both sides are
  inside the sheet, not on its outline), and the outer boundary of the sheet is
  made of border or cut edges;
- dangling creases (a fold line that ends inside the sheet);
- faces that are not simple polygons;
- at every interior vertex (not on the border) whose creases are all assigned and
  fold flat (every mountain and valley to 180 degrees), Maekawa's theorem
  ``|M - V| = 2`` and, for every interior vertex, Kawasaki's theorem: the
  alternating sum of sector angles is zero (even sectors sum to pi: the defect,
  how far they miss it, is half the alternating sum), within the vertex's
  tolerance (:func:`kawasaki_tolerances`: :data:`KAWASAKI_TOLERANCE`, or more where
  the file's coordinates were rounded). Flat (``F``) facet creases stay flat and
  count in neither.

A vertex that breaks Maekawa or Kawasaki cannot fold flat, but it still folds in 3D
(as Origami Simulator folds it, with some strain): it is a warning, not an error.
Errors are what no folding can get past: an open or crossing outline, a crease that
ends inside the sheet, a panel that is not a simple polygon.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import shapely

from origami_cad.pattern.problems import Problem, Severity

if TYPE_CHECKING:
    from origami_cad.pattern.model import CreasePattern

__all__ = [
    "KAWASAKI_TOLERANCE",
    "check_pattern",
    "interior_vertices",
    "kawasaki_residuals",
    "kawasaki_tolerances",
    "maekawa_counts",
]

_FOLDS = ("M", "V", "U", "J")

#: Kawasaki's theorem holds within this defect at least, radians (0.01 degrees): the
#: even sectors of flat-foldable patterns exported by other tools sum to pi within
#: 5e-5 rad (Origami Simulator's ``miura_sharpangle.svg``: 1.4e-5 rad, 0.000778 deg),
#: while patterns that are not flat-foldable miss it by 5e-4 rad or more.
KAWASAKI_TOLERANCE = math.radians(0.01)


def _loc(cp: CreasePattern, v: int) -> tuple[float, float]:
    return float(cp.vertices[v, 0]), float(cp.vertices[v, 1])


def _degree(cp: CreasePattern, mask: np.ndarray) -> np.ndarray:
    return np.bincount(cp.edges[mask].ravel(), minlength=cp.n_vertices)


def interior_vertices(cp: CreasePattern) -> np.ndarray:
    """Indices of the vertices inside the sheet (touching no border, cut or outer edge)."""
    nfaces = (cp.edge_faces() >= 0).sum(axis=1)
    outer = (nfaces == 1) | cp.edge_mask("B", "C")
    on_outer = _degree(cp, outer) > 0
    return np.flatnonzero(~on_outer & (_degree(cp, np.ones(cp.n_edges, bool)) > 0))


def maekawa_counts(cp: CreasePattern, vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Number of mountain and valley creases at each of ``vertices``."""
    m = _degree(cp, cp.edge_mask("M"))[vertices]
    v = _degree(cp, cp.edge_mask("V"))[vertices]
    return m, v


def kawasaki_residuals(cp: CreasePattern, vertices: np.ndarray) -> np.ndarray:
    """Alternating sum of sector angles at each vertex, radians (0 when flat-foldable).

    Only folding edges (M, V, U, J) count; a vertex with an odd number of them
    gets ``nan`` (Kawasaki needs an even degree).
    """
    fold = np.flatnonzero(cp.edge_mask(*_FOLDS))
    e = cp.edges[fold]
    src = np.concatenate([e[:, 0], e[:, 1]])
    dst = np.concatenate([e[:, 1], e[:, 0]])
    sel = np.isin(src, vertices)
    src, dst = src[sel], dst[sel]
    d = cp.vertices[dst] - cp.vertices[src]
    ang = np.arctan2(d[:, 1], d[:, 0])
    order = np.lexsort((ang, src))
    src, ang = src[order], ang[order]
    out = np.full(len(vertices), np.nan)
    if len(src) == 0:
        return out
    starts = np.flatnonzero(np.r_[True, src[1:] != src[:-1]])
    counts = np.diff(np.r_[starts, len(src)])
    nxt = np.arange(len(src)) + 1
    ends = starts + counts
    nxt[ends - 1] = starts
    sector = np.mod(ang[nxt] - ang, 2 * math.pi)
    pos = np.arange(len(src)) - np.repeat(starts, counts)
    signed = np.where(pos % 2 == 0, sector, -sector)
    sums = np.add.reduceat(signed, starts)
    sorted_v = np.argsort(vertices)
    where = sorted_v[np.searchsorted(vertices[sorted_v], src[starts])]
    res = np.where(counts % 2 == 0, sums, np.nan)
    out[where] = res
    return out


def kawasaki_tolerances(
    cp: CreasePattern, vertices: np.ndarray, angle_tolerance: float = KAWASAKI_TOLERANCE
) -> np.ndarray:
    """How far each of ``vertices`` may miss Kawasaki's theorem (its defect, half the
    alternating sum of its sector angles), radians.

    ``angle_tolerance`` (radians), or more where the pattern's coordinates were
    rounded: when the import closed gaps of up to ``g`` mm
    (:attr:`~origami_cad.pattern.model.CreasePattern.cleanup`), each crease of
    length ``L`` at the vertex may point ``g / L`` radians off, and each direction
    bounds two sectors: ``sum(g / L)`` over its folding creases.
    """
    c = cp.cleanup
    gap = max(c.merged_gap, c.snapped_gap, c.crossing_gap)
    out = np.full(len(vertices), float(angle_tolerance))
    if gap <= 0 or not len(vertices):
        return out
    fold = cp.edge_mask(*_FOLDS)
    e = cp.edges[fold]
    inv = 1.0 / np.maximum(cp.edge_lengths()[fold], 1e-300)
    per_vertex = np.bincount(e.ravel(), weights=np.repeat(inv, 2), minlength=cp.n_vertices)
    return np.maximum(out, gap * per_vertex[vertices])


def _border_problems(cp: CreasePattern) -> list[Problem]:
    """Problems of the outline: no border, open ends, crossings (border edges ``B``; a
    black line with a panel on both sides is a line inside the sheet, a free hinge as
    Origami Simulator folds it, not its outline)."""
    problems: list[Problem] = []
    border = cp.edge_mask("B")
    bdeg = _degree(cp, border & ((cp.edge_faces() >= 0).sum(axis=1) < 2))
    if not border.any():
        problems.append(
            Problem("open-border", "the pattern has no border edges (no outline of the sheet)")
        )
    for v in np.flatnonzero(bdeg == 1):
        problems.append(
            Problem("open-border", f"vertex {v}: the border ends here (open outline)", _loc(cp, v))
        )
    for v in np.flatnonzero(bdeg > 2):
        problems.append(
            Problem(
                "border-crossing",
                f"vertex {v}: {bdeg[v]} border edges meet (the outline crosses or touches itself)",
                _loc(cp, v),
            )
        )
    return problems


def _loose_crease_problems(cp: CreasePattern) -> list[Problem]:
    """Creases ending at a free vertex, and creases that do not separate two panels."""
    problems: list[Problem] = []
    nfaces = (cp.edge_faces() >= 0).sum(axis=1)
    deg = _degree(cp, np.ones(cp.n_edges, bool))
    free_end = (deg[cp.edges[:, 0]] == 1) | (deg[cp.edges[:, 1]] == 1)
    fold = cp.edge_mask(*_FOLDS, "F")
    for e in np.flatnonzero(fold & free_end):
        v = cp.edges[e, 0] if deg[cp.edges[e, 0]] == 1 else cp.edges[e, 1]
        problems.append(
            Problem("dangling-crease", f"edge {e} ({cp.assignments[e]}) ends here", _loc(cp, v))
        )
    loose = ~cp.edge_mask("B", "C") & ((nfaces == 1) | ((nfaces == 0) & ~free_end))
    for e in np.flatnonzero(loose)[:50]:
        a, b = cp.edges[e]
        mid = tuple(float(c) for c in (cp.vertices[a] + cp.vertices[b]) / 2)
        if nfaces[e] == 1:
            code, what = "open-border", "lies on the outer boundary of the sheet"
        else:
            code, what = "dangling-crease", "does not separate two panels"
        problems.append(Problem(code, f"edge {e} ({cp.assignments[e]}) {what}", mid))
    return problems


def _face_problems(cp: CreasePattern) -> list[Problem]:
    """Panels that are not valid, simple polygons."""
    problems: list[Problem] = []
    polys = cp.face_polygons()
    bad = np.flatnonzero(~shapely.is_valid(polys) | ~shapely.is_simple(polys)) if len(polys) else []
    for f in bad:
        reason = shapely.is_valid_reason(polys[f])
        c = shapely.get_coordinates(polys[f])[0]
        problems.append(
            Problem(
                "face-not-simple",
                f"panel {cp.face_labels[f]} is not a simple polygon ({reason})",
                (float(c[0]), float(c[1])),
            )
        )
    return problems


def _flat_fold_problems(cp: CreasePattern, angle_tolerance: float) -> list[Problem]:
    """Warnings at interior vertices that cannot fold flat (Maekawa, Kawasaki).

    ``angle_tolerance`` is the least tolerance of Kawasaki's defect, radians
    (:func:`kawasaki_tolerances`). Maekawa's theorem is checked where every crease
    is assigned and every mountain and valley folds to 180 degrees (a flat fold).
    """
    problems: list[Problem] = []
    inner = interior_vertices(cp)
    if not len(inner):
        return problems
    n_fold = _degree(cp, cp.edge_mask(*_FOLDS))[inner]
    inner = inner[n_fold > 0]
    m, v = maekawa_counts(cp, inner)
    partial = cp.edge_mask("M", "V") & (np.abs(cp.fold_angles) < 180 - 1e-6)
    skip = _degree(cp, cp.edge_mask("U", "J") | partial)[inner]
    for k in np.flatnonzero((skip == 0) & (np.abs(m - v) != 2)):
        vi = inner[k]
        problems.append(
            Problem(
                "maekawa",
                f"vertex {vi}: {m[k]} mountain and {v[k]} valley creases (|M - V| must be 2 "
                "to fold flat); it folds in 3D only",
                _loc(cp, vi),
                Severity.WARNING,
            )
        )
    res = kawasaki_residuals(cp, inner)
    tol = kawasaki_tolerances(cp, inner, angle_tolerance)
    for k in np.flatnonzero(~(np.abs(res) / 2 <= tol)):
        vi = inner[k]
        if np.isnan(res[k]):
            msg = f"vertex {vi}: an odd number of creases cannot fold flat; it folds in 3D only"
        else:
            msg = (
                f"vertex {vi}: alternating sector angles differ from 180 deg by "
                f"{math.degrees(abs(res[k])) / 2:.4g} deg (tolerance "
                f"{math.degrees(tol[k]):.2g} deg): not flat-foldable, it folds in 3D only"
            )
        problems.append(Problem("kawasaki", msg, _loc(cp, vi), Severity.WARNING))
    return problems


def check_pattern(cp: CreasePattern, angle_tolerance: float = KAWASAKI_TOLERANCE) -> list[Problem]:
    """Every problem of ``cp`` with its location; an empty list when sound.

    Parameters
    ----------
    cp : CreasePattern
        The pattern to check (not modified).
    angle_tolerance : float
        Least tolerance of Kawasaki's defect, radians (default
        :data:`KAWASAKI_TOLERANCE`; see :func:`kawasaki_tolerances`).

    Returns
    -------
    list of Problem
        Notes from normalisation first, then errors and warnings.
    """
    problems: list[Problem] = list(cp.notes)
    problems += _border_problems(cp)
    problems += _loose_crease_problems(cp)
    problems += _face_problems(cp)
    problems += _flat_fold_problems(cp, angle_tolerance)
    order = {Severity.INFO: 0, Severity.WARNING: 1, Severity.ERROR: 2}
    problems.sort(key=lambda p: order[p.severity])
    return problems
