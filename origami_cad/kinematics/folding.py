"""Fold any design to a fold ratio: closed form for TG tessellations, else degree-4 propagation."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from origami_cad._display import View3DDisplay
from origami_cad.errors import PatternError
from origami_cad.kinematics.fold3d import fold_tessellation, fold_tessellation_many
from origami_cad.pattern.design import Design
from origami_cad.pattern.model import CreasePattern

__all__ = ["FoldedState", "fold_coords", "fold_design", "fold_sequence"]


@dataclass(frozen=True)
class FoldedState(View3DDisplay):
    """One rigidly folded state.

    Attributes
    ----------
    p : float
        Fold ratio ``theta / pi`` of the driving (main) crease.
    coords : ndarray, shape (n, 3)
        Vertex coordinates, mm, in the pattern's vertex order.
    fold_angles : ndarray, shape (m,)
        Signed fold angle of every edge, degrees (valley positive).
    method : str
        How it was folded: ``"closed form"`` (exact, rigid) or ``"general"`` (the
        bar-and-hinge solver of :mod:`origami_cad.simulation.folder`).
    strain : float
        Largest change of an edge's length (the panels' triangulation's too), percent
        of its flat length: 0 for the closed form.
    pattern : CreasePattern or None
        The crease pattern folded (set by :func:`fold_design`, :func:`fold_sequence` and
        ``oc.fold``), so that ``oc.show(state)`` and a notebook draw the state alone.
    """

    p: float
    coords: np.ndarray
    fold_angles: np.ndarray
    method: str = "closed form"
    strain: float = 0.0
    pattern: CreasePattern | None = field(default=None, repr=False, compare=False)

    def __repr__(self) -> str:
        """One line: the fold ratio, the method, the vertices, the fold angles' range
        (degrees) and the largest strain (percent)."""
        angles = np.asarray(self.fold_angles, float)
        span = f"{angles.min():.1f} to {angles.max():.1f} deg" if angles.size else "none"
        return (
            f"<FoldedState p={self.p:g} ({self.method}): {len(self.coords)} vertices, "
            f"fold angles {span}, strain {self.strain:.2g} %>"
        )


def fold_design(design: Design, p: float) -> FoldedState:
    """Fold ``design`` rigidly to fold ratio ``p`` in [0, 1].

    TG tessellations (``design.tg``) fold in closed form
    (:func:`~origami_cad.kinematics.fold3d.fold_tessellation`); any other pattern
    whose interior vertices are flat-foldable degree-4 vertices folds by
    propagating the degree-4 relations from one driving crease
    (:func:`~origami_cad.kinematics.generic.fold_degree4`).
    """
    if not 0.0 <= p <= 1.0:
        raise PatternError(f"fold ratio must lie in [0, 1], got {p}")
    if design.tg is not None:
        coords, angles = fold_tessellation(design.tg, design.pattern, p)
    else:
        from origami_cad.kinematics.generic import fold_degree4

        coords, angles = fold_degree4(design.pattern, p)
    return FoldedState(float(p), coords, angles, pattern=design.pattern)


def fold_sequence(design: Design, ratios: Sequence[float]) -> list[FoldedState]:
    """Fold ``design`` to each fold ratio of ``ratios`` (a TG tessellation: all at once)."""
    if design.tg is None or not len(ratios):
        return [fold_design(design, float(p)) for p in ratios]
    values = [float(p) for p in ratios]
    for p in values:
        if not 0.0 <= p <= 1.0:
            raise PatternError(f"fold ratio must lie in [0, 1], got {p}")
    coords, angles = fold_tessellation_many(design.tg, design.pattern, np.array(values))
    return [
        FoldedState(p, c, a, pattern=design.pattern)
        for p, c, a in zip(values, coords, angles, strict=True)
    ]


def fold_coords(design: Design, ratios: Sequence[float]) -> np.ndarray:
    """Vertex coordinates at many fold ratios at once, shape ``(len(ratios), n, 3)``, mm.

    Vectorised over ``ratios`` for TG tessellations; one fold per ratio otherwise.
    """
    from origami_cad.kinematics.fold3d import tessellation_vertices

    ratios = np.asarray(ratios, dtype=float)
    if design.tg is not None:
        grid = tessellation_vertices(design.tg, ratios)
        return grid.reshape(len(ratios), -1, 3)
    return np.stack([fold_design(design, float(p)).coords for p in ratios])
