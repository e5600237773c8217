"""Validation of crease patterns that explains itself.

:func:`check_pattern` lists every problem with its location and never changes
the pattern. It checks, in this order:

- what normalisation changed on construction (``info``/``warning`` notes);
- the border: every border vertex joins exactly two border edges (an open or
  self-crossing outline is reported), and the outer boundary of the sheet is
  made of border or cut edges;
- dangling creases (a fold line that ends inside the sheet);
- faces that are not simple polygons;
- at every interior vertex (not on the border) whose creases are all assigned,
  Maekawa's theorem ``|M - V| = 2`` and, for every interior vertex, Kawasaki's
  theorem: the alternating sum of sector angles is zero (even sectors sum to
  pi), within ``angle_tolerance`` radians.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import shapely

from origami_cad.pattern.model import Problem, Severity

if TYPE_CHECKING:
    from origami_cad.pattern.model import CreasePattern

__all__ = ["check_pattern", "interior_vertices", "kawasaki_residuals", "maekawa_counts"]

_FOLDS = ("M", "V", "U", "J")


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


def _border_problems(cp: CreasePattern) -> list[Problem]:
    """Problems of the outline: no border, open ends, crossings (border edges ``B``)."""
    problems: list[Problem] = []
    border = cp.edge_mask("B")
    bdeg = _degree(cp, border)
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
    """Maekawa and Kawasaki violations at interior vertices with creases.

    ``angle_tolerance`` is the tolerance of Kawasaki's theorem, radians.
    """
    problems: list[Problem] = []
    inner = interior_vertices(cp)
    if not len(inner):
        return problems
    n_fold = _degree(cp, cp.edge_mask(*_FOLDS))[inner]
    inner = inner[n_fold > 0]
    m, v = maekawa_counts(cp, inner)
    unassigned = _degree(cp, cp.edge_mask("U", "J"))[inner]
    for k in np.flatnonzero((unassigned == 0) & (np.abs(m - v) != 2)):
        vi = inner[k]
        problems.append(
            Problem(
                "maekawa",
                f"vertex {vi}: {m[k]} mountain and {v[k]} valley creases (|M - V| must be 2)",
                _loc(cp, vi),
            )
        )
    res = kawasaki_residuals(cp, inner)
    for k in np.flatnonzero(~(np.abs(res) <= angle_tolerance)):
        vi = inner[k]
        if np.isnan(res[k]):
            msg = f"vertex {vi}: an odd number of creases cannot fold flat"
        else:
            msg = (
                f"vertex {vi}: alternating sector angles differ from 180 deg by "
                f"{math.degrees(abs(res[k])) / 2:.4g} deg"
            )
        problems.append(Problem("kawasaki", msg, _loc(cp, vi)))
    return problems


def check_pattern(cp: CreasePattern, angle_tolerance: float = 1e-6) -> list[Problem]:
    """Every problem of ``cp`` with its location; an empty list when sound.

    Parameters
    ----------
    cp : CreasePattern
        The pattern to check (not modified).
    angle_tolerance : float
        Tolerance of Kawasaki's theorem, radians.

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
