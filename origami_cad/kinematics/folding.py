"""Fold any design to a fold ratio: closed form for TG tessellations, else degree-4 propagation.

A design the closed form does not fold can carry its folding path instead
(:class:`PathDesign`, a :class:`FoldPath` of states computed once by the general folder
of :mod:`origami_cad.simulation.folder`, from :func:`origami_cad.simulation.paths.with_fold_path`):
:func:`fold_design`, :func:`fold_sequence` and :func:`fold_coords` then interpolate that
path, so every stage that folds a design (the DCQC model, the route planner) folds any
pattern without importing the simulation.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from origami_cad._args import Arg, checked
from origami_cad._display import View3DDisplay
from origami_cad.errors import PatternError
from origami_cad.kinematics.fold3d import fold_tessellation, fold_tessellation_many
from origami_cad.pattern.design import Design
from origami_cad.pattern.model import CreasePattern

__all__ = ["FoldPath", "FoldedState", "PathDesign", "fold_coords", "fold_design", "fold_sequence"]


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


@dataclass(frozen=True, eq=False)
class FoldPath:
    """A folding path sampled once: states at increasing fold ratios, interpolated between.

    Attributes
    ----------
    ratios : ndarray, shape (G,)
        Fold ratios in [0, 1], increasing, the first 0 (the flat sheet).
    coords : ndarray, shape (G, n, 3)
        Vertex coordinates at each ratio, mm (one panel held in place along the path).
    fold_angles : ndarray, shape (G, m)
        Signed fold angle of every edge at each ratio, degrees (valley positive).
    strain : ndarray, shape (G,)
        Largest change of an edge's length at each ratio, percent.
    method : str
        The folder that made it (``"general"``).

    Between samples each coordinate and angle is interpolated by a monotone cubic
    (PCHIP), exact at the samples; a ratio above the last sample is refused.
    """

    ratios: np.ndarray
    coords: np.ndarray
    fold_angles: np.ndarray
    strain: np.ndarray
    method: str = "general"
    _splines: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        r = np.asarray(self.ratios, dtype=float)
        if r.ndim != 1 or len(r) < 2 or r[0] != 0.0 or np.any(np.diff(r) <= 0):
            raise PatternError("a fold path needs increasing fold ratios from 0, at least two")
        g = len(r)
        if self.coords.shape[0] != g or self.fold_angles.shape[0] != g or len(self.strain) != g:
            raise PatternError("a fold path needs one state per fold ratio")

    @classmethod
    def from_states(cls, states: Sequence[FoldedState]) -> FoldPath:
        """The path through ``states`` (increasing ``p`` from 0)."""
        return cls(
            np.array([s.p for s in states], dtype=float),
            np.stack([s.coords for s in states]),
            np.stack([s.fold_angles for s in states]),
            np.array([s.strain for s in states], dtype=float),
            states[-1].method if states else "general",
        )

    @property
    def top(self) -> float:
        """The largest fold ratio the path reaches."""
        return float(self.ratios[-1])

    def _spline(self, name: str):
        from scipy.interpolate import PchipInterpolator

        if name not in self._splines:
            self._splines[name] = PchipInterpolator(self.ratios, getattr(self, name), axis=0)
        return self._splines[name]

    def _checked(self, ratios) -> np.ndarray:
        values = np.atleast_1d(np.asarray(ratios, dtype=float))
        bad = values[~((values >= 0.0) & (values <= self.top + 1e-12))]
        if len(bad):
            raise PatternError(
                f"fold ratio {bad[0]:g} is outside the folded path's [0, {self.top:g}]"
            )
        return np.minimum(values, self.top)

    def states(self, ratios: Sequence[float]) -> list[FoldedState]:
        """The states at ``ratios`` (each in [0, ``top``])."""
        values = self._checked(ratios)
        coords = self._spline("coords")(values)
        angles = self._spline("fold_angles")(values)
        strain = np.interp(values, self.ratios, self.strain)
        return [
            FoldedState(float(p), c, a, method=self.method, strain=float(e))
            for p, c, a, e in zip(values, coords, angles, strain, strict=True)
        ]

    def coords_at(self, ratios: Sequence[float]) -> np.ndarray:
        """Vertex coordinates at ``ratios``, shape ``(len(ratios), n, 3)``, mm."""
        return self._spline("coords")(self._checked(ratios))


@dataclass(frozen=True, eq=False)
class PathDesign(Design):
    """A design with the folding path of a folder other than the closed form.

    :func:`fold_design`, :func:`fold_sequence` and :func:`fold_coords` interpolate
    ``path`` (a :class:`FoldPath`) for it; made by
    :func:`origami_cad.simulation.paths.with_fold_path`.
    """

    path: FoldPath | None = None


def _path(design: Design) -> FoldPath | None:
    return design.path if isinstance(design, PathDesign) else None


@checked(
    PatternError,
    design=Arg("object", types=(Design,), optional=False),
    p=Arg(min=0.0, max=1.0, optional=False),
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
    if _path(design) is not None:
        return _path(design).states([p])[0]
    if design.tg is not None:
        coords, angles = fold_tessellation(design.tg, design.pattern, p)
    else:
        from origami_cad.kinematics.generic import fold_degree4

        coords, angles = fold_degree4(design.pattern, p)
    return FoldedState(float(p), coords, angles, pattern=design.pattern)


@checked(
    PatternError,
    design=Arg("object", types=(Design,), optional=False),
    ratios=Arg("floats", min=0.0, max=1.0, optional=False),
)
def fold_sequence(design: Design, ratios: Sequence[float]) -> list[FoldedState]:
    """Fold ``design`` to each fold ratio of ``ratios`` (a TG tessellation: all at once)."""
    if _path(design) is not None and len(ratios):
        return _path(design).states(ratios)
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

    Vectorised over ``ratios`` for TG tessellations and folding paths; one fold per ratio
    otherwise.
    """
    from origami_cad.kinematics.fold3d import tessellation_vertices

    ratios = np.asarray(ratios, dtype=float)
    if _path(design) is not None:
        return _path(design).coords_at(ratios)
    if design.tg is not None:
        grid = tessellation_vertices(design.tg, ratios)
        return grid.reshape(len(ratios), -1, 3)
    return np.stack([fold_design(design, float(p)).coords for p in ratios])
