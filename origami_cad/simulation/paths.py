"""A design's folding path, for the stages that fold a design without importing the simulation.

The string models and the route planner (:mod:`origami_cad.strings`) fold a design through
:func:`~origami_cad.kinematics.folding.fold_design`: the closed form where it applies. For
any other pattern, :func:`with_fold_path` folds it once with the general folder
(:func:`~origami_cad.simulation.folder.fold_general`, every crease driven toward its
target) on :data:`PATH_SAMPLES` fold ratios from flat to 1 and returns the design with
that path (:class:`~origami_cad.kinematics.folding.PathDesign`), which they then
interpolate. Units: mm, degrees.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from origami_cad._args import Arg, checked
from origami_cad.errors import PatternError, SimulationError
from origami_cad.kinematics.folding import FoldPath, PathDesign
from origami_cad.pattern.design import Design
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.folder import StrainWarning, closed_form_applies, fold_general
from origami_cad.simulation.model import SimulationParams

__all__ = ["PATH_SAMPLES", "fold_path", "fold_ratio_fit", "rigid_table", "with_fold_path"]

#: Fold ratios, evenly spaced from 0 to 1, at which the general folder's path is sampled
#: (4.5 deg apart on a crease driven toward 180 deg).
PATH_SAMPLES = 41


@checked(
    SimulationError,
    design=Arg("object", types=(Design, CreasePattern), optional=False),
    params=Arg("object", types=(SimulationParams,)),
    samples=Arg("int", min=2, max=100_000, optional=False),
    deadline=Arg(inf_ok=True, optional=False),
)
def fold_path(
    design: Design | CreasePattern,
    *,
    params: SimulationParams | None = None,
    samples: int = PATH_SAMPLES,
    deadline: float = math.inf,
) -> FoldPath:
    """The general folder's path of ``design``: states at ``samples`` ratios from 0 to 1.

    ``params``: the panels' and creases' materials (default: the printed sheet's). The
    strain warnings of the general folder are not repeated here: the path's ``strain``
    (percent, per sample) says how far each state stretches its panels. ``deadline``: a
    :func:`time.monotonic` time, s, past which the folding stops with a
    :class:`~origami_cad.errors.SimulationError` (default: none).
    """
    cp = design if isinstance(design, CreasePattern) else design.pattern
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", StrainWarning)
        # the string models and the simulation hold the pattern's vertices: a cut's two
        # sides stay joined on the path too
        ratios = np.linspace(0.0, 1.0, samples)
        states = fold_general(cp, ratios, params=params, cuts_open=False, deadline=deadline)
    return FoldPath.from_states(states)


@checked(
    SimulationError,
    design=Arg("object", types=(Design, CreasePattern), optional=False),
    params=Arg("object", types=(SimulationParams,)),
    samples=Arg("int", min=2, max=100_000, optional=False),
    deadline=Arg(inf_ok=True, optional=False),
)
def with_fold_path(
    design: Design | CreasePattern,
    *,
    params: SimulationParams | None = None,
    samples: int = PATH_SAMPLES,
    deadline: float = math.inf,
) -> Design:
    """``design`` as every stage can fold it: itself where the closed form applies
    (:func:`~origami_cad.simulation.folder.closed_form_applies`) or it already carries a
    path, else a :class:`~origami_cad.kinematics.folding.PathDesign` with the general
    folder's path (:func:`fold_path`). A pattern with no mountain or valley crease is
    returned as it is. ``deadline``: a :func:`time.monotonic` time, s, past which the
    general folder stops with a :class:`~origami_cad.errors.SimulationError` (default: none).

    Pass the result to :func:`~origami_cad.strings.plan.plan_routes`,
    :func:`~origami_cad.strings.simulate_dcqc` or
    :func:`~origami_cad.simulation.simulate` (``design=``) to route and fold a pattern
    with vertices of any degree or several degrees of freedom.

    A waterbomb base (one vertex of six creases), which the closed form does not fold:

    >>> import origami_cad as oc
    >>> from origami_cad.pattern import CreasePattern
    >>> cp = CreasePattern(
    ...     [[0, 0], [100, 0], [100, 100], [0, 100], [50, 50], [0, 50], [100, 50]],
    ...     [[0, 1], [1, 6], [6, 2], [2, 3], [3, 5], [5, 0],
    ...      [0, 4], [1, 4], [2, 4], [3, 4], [5, 4], [6, 4]],
    ...     ["B"] * 6 + ["M"] * 4 + ["V"] * 2,
    ... )
    >>> folded = oc.with_fold_path(cp)
    >>> state = oc.fold_design(folded, 0.5)  # degrees, valley positive
    >>> state.method, bool(state.fold_angles[6] < -45 and state.fold_angles[10] > 45)
    ('general', True)
    """
    if isinstance(design, CreasePattern):
        design = Design(design, None, "file")
    if isinstance(design, PathDesign) or not design.pattern.edge_mask("M", "V").any():
        return design  # a path already, or nothing to fold
    if closed_form_applies(design):
        return design
    path = fold_path(design, params=params, samples=samples, deadline=deadline)
    return PathDesign(design.pattern, design.tg, design.kind, design.source, path=path)


def rigid_table(design: Design) -> tuple[np.ndarray, np.ndarray] | None:
    """Fold ratios and the rigid folding's crease angles (G, m), radians; None if unfoldable."""
    from origami_cad.kinematics.fold3d import fold_angles_from_coords
    from origami_cad.kinematics.folding import fold_coords, fold_sequence

    try:
        if design.tg is not None:
            ratios = np.linspace(0.0, 1.0, 201)
            coords = fold_coords(design, ratios)
            table = np.stack([fold_angles_from_coords(design.pattern, c) for c in coords])
        else:
            ratios = np.linspace(0.0, 1.0, 101)
            table = np.radians(np.stack([s.fold_angles for s in fold_sequence(design, ratios)]))
    except (PatternError, ValueError):
        return None
    return ratios, table


def fold_ratio_fit(angles: np.ndarray, table: tuple[np.ndarray, np.ndarray], mask) -> float:
    """The fold ratio whose rigid folding best matches crease angles ``angles`` (m,), radians.

    Least squares over the creases ``mask`` against the rigid folding's table
    (from the same folder as the DCQC model), refined between samples by a parabola.
    """
    ratios, rigid = table
    err = ((rigid[:, mask] - angles[mask]) ** 2).sum(axis=1)
    k = int(np.clip(np.argmin(err), 1, len(ratios) - 2))
    a, b, c = err[k - 1], err[k], err[k + 1]
    denom = a - 2 * b + c
    shift = 0.5 * (a - c) / denom if denom > 0 else 0.0
    return float(ratios[k] + np.clip(shift, -1.0, 1.0) * (ratios[1] - ratios[0]))
