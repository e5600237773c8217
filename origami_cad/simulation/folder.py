"""Fold any crease pattern: the exact closed form where it applies, else the bar-and-hinge solver.

The closed form (:func:`~origami_cad.kinematics.folding.fold_design`) folds TG
tessellations and patterns whose interior vertices are flat-foldable degree-4 vertices
moving with one degree of freedom: one driving crease sets every other. Where it does
not apply (other vertices, or several degrees of freedom, which the closed form would
leave partly flat), :func:`fold_general` folds the pattern as Origami Simulator does
(Ghassaei et al. 2018): every crease is a torsional spring driven toward its target
angle, on the bar-and-hinge model of :mod:`origami_cad.simulation.model` (panels as
stiff as the printed ones, triangulated, with stiff facet hinges on their diagonals),
in equilibrium by :func:`~origami_cad.simulation.solver.solve_equilibrium`:

- mountain and valley creases: the file's fold angle where it has one (FOLD's
  ``edges_foldAngle``, an SVG's stroke opacity), else -180 / +180 deg, times the fold
  ratio ``p`` (at most :data:`MAX_TARGET_DEG` in magnitude). Each is driven by its
  printed crease's spring first, so a pattern that folds rigidly folds rigidly. Where
  the panels hold the creases back (they reach on average less than
  :data:`DRIVE_REACH` of their targets: bases, pop-ups, twists, whose panels must bend
  to fold), the drive is stiffened :data:`DRIVE_STEP` times at a time, up to a strip of panel
  :data:`DRIVE_LENGTH` times the pattern's size long bending (``E h^3 / 12`` over that
  length, per mm of crease): the role of the actuators or hands that fold a sheet, as
  Origami Simulator's creases are as stiff as its facets. Where the drive then
  stretches the panels by more than :data:`DRIVE_STRAIN` percent, it is relaxed (a
  third each time, at most :data:`DRIVE_RELAXATIONS` times), so that the creases go as
  far as the panels allow without stretching;
- facet (``F``) and join (``J``) creases: 0, as stiff as the panels' facet hinges;
- cuts (``C``) with a panel on both sides part (Origami Simulator splits them): each
  side has its own vertices (:meth:`~origami_cad.pattern.model.CreasePattern.with_cuts_opened`),
  so a kirigami pattern's cuts open as it folds;
- unassigned (``U``) creases and black (``B``) lines with a panel on both sides (Origami
  Simulator gives them no crease spring): free hinges with no target (a spring of
  :data:`FREE_HINGE_STIFFNESS` times a crease's, toward the angle they had at the start
  of each step, only keeps the equations well posed).

The targets ramp from 0 in steps of at most :data:`STEP_DEG` (continuation), each
solve starting from the last one extrapolated, so the solver follows the folding path.
Panels stretch where the creases cannot reach their targets together (a pattern that
does not fold rigidly): the largest change of an edge's length is reported (percent),
and a :class:`StrainWarning` is issued above :data:`STRAIN_LIMIT`. Units: mm, degrees
at the edges, radians inside.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time
from collections.abc import Sequence

import numpy as np

from origami_cad._args import Arg, checked
from origami_cad.errors import OrigamiCadWarning, PatternError, SimulationError, warn
from origami_cad.kinematics.folding import FoldedState, fold_design, fold_sequence
from origami_cad.pattern.design import Design
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.mechanics import bar_lengths, fold_angles
from origami_cad.simulation.model import SimulationParams, Structure, build_structure
from origami_cad.simulation.solver import HessianAssembly, solve_equilibrium

__all__ = [
    "DRIVE_LENGTH",
    "DRIVE_REACH",
    "DRIVE_RELAXATIONS",
    "DRIVE_STEP",
    "DRIVE_STRAIN",
    "FREE_HINGE_STIFFNESS",
    "MAX_TARGET_DEG",
    "METHODS",
    "STEP_DEG",
    "STRAIN_LIMIT",
    "StrainWarning",
    "closed_form_applies",
    "fold",
    "fold_general",
    "fold_notes",
    "fold_states",
    "placed_fold_states",
]

#: Above this largest edge strain (percent) a fold warns: the panels stretch visibly, the
#: pattern does not fold this far without bending or stretching its panels.
STRAIN_LIMIT = 5.0
#: Largest change of any crease's target between two solves of the continuation, degrees.
STEP_DEG = 10.0
#: Largest target fold angle, degrees: at 180 a crease's angle would wrap around.
MAX_TARGET_DEG = 179.0
#: A free (``U``) hinge's spring, as a fraction of a crease's stiffness.
FREE_HINGE_STIFFNESS = 1e-3
#: The length (a fraction of the pattern's size, the diagonal of its bounding box) of
#: the strip of panel whose bending stiffness drives each crease toward its target.
DRIVE_LENGTH = 0.3
#: The drive is stiffened while the creases reach on average less than this fraction of
#: their targets.
DRIVE_REACH = 0.5
#: The factor by which the drive is stiffened each time (from the printed creases' to
#: the strongest, about 2,500 times, in two steps).
DRIVE_STEP = 100.0
#: Largest stretch of a panel's edge (percent) the drive may cause before it is relaxed.
DRIVE_STRAIN = 3.0
#: How many times the drive is relaxed (each time to a third) at most.
DRIVE_RELAXATIONS = 4
#: The methods :func:`fold` and :func:`fold_states` take.
METHODS = ("auto", "closed form", "general")

_FOLDING = ("M", "V")
_FACET = ("F", "J")
# residual force (N) at which a solve counts as converged: between steps, at the end
_TOL_STEP, _TOL_END = 1e-4, 1e-5
_MAX_ITER = 200
# Newton iterations at most of a solve between steps: a point on the path need not be
# exact (the next solve starts from it); from flat, the slowest converge in 100 and more
_MAX_ITER_STEP = 30


class StrainWarning(OrigamiCadWarning):
    """A general fold stretched an edge by more than :data:`STRAIN_LIMIT` percent."""


def closed_form_applies(design: Design) -> bool:
    """Whether ``design`` folds in closed form, with one degree of freedom.

    True for a TG tessellation, and for a pattern the degree-4 folder folds with every
    mountain and valley crease moving (a pattern with more degrees of freedom, such as a
    map, would keep some crease lines flat there).
    """
    if design.tg is not None:
        return True
    creases = design.pattern.edge_mask(*_FOLDING)
    try:
        probe = fold_design(design, 0.1).fold_angles
    except PatternError:
        return False
    return bool(creases.any() and np.all(np.abs(probe[creases]) > 1e-6))


@checked(
    PatternError,
    design=Arg("object", types=(Design, CreasePattern), optional=False),
    p=Arg(min=0.0, max=1.0, optional=False),
    method=Arg("str", optional=False),
    params=Arg("object", types=(SimulationParams,)),
)
def fold(
    design: Design | CreasePattern,
    p: float,
    *,
    method: str = "auto",
    params: SimulationParams | None = None,
) -> FoldedState:
    """Fold ``design`` (or a bare pattern) to fold ratio ``p`` in [0, 1].

    ``method`` ``"auto"`` takes the closed form where it applies
    (:func:`closed_form_applies`), else the general solver (:func:`fold_general`, with
    the materials of ``params``). The state says which (``method``) and its largest
    edge strain, percent (``strain``); a :class:`StrainWarning` names a strain over
    :data:`STRAIN_LIMIT`.
    """
    return fold_states(design, [p], method=method, params=params)[-1]


@checked(
    PatternError,
    design=Arg("object", types=(Design, CreasePattern), optional=False),
    ratios=Arg("floats", min=0.0, max=1.0, optional=False),
    method=Arg("str", optional=False),
    params=Arg("object", types=(SimulationParams,)),
)
def fold_states(
    design: Design | CreasePattern,
    ratios: Sequence[float],
    *,
    method: str = "auto",
    params: SimulationParams | None = None,
) -> list[FoldedState]:
    """Fold ``design`` to each fold ratio of ``ratios`` (each in [0, 1]), one method for all.

    See :func:`fold`; the general solver folds through the ratios in increasing order
    in one continuation, so a sequence costs about as much as its largest ratio.
    """
    if isinstance(design, CreasePattern):
        design = Design(design, None, "file")
    if method not in METHODS:
        raise PatternError(f"fold method must be one of {', '.join(METHODS)}, got {method!r}")
    values = [_ratio(p) for p in ratios]
    if method == "auto":
        method = "closed form" if closed_form_applies(design) else "general"
    if method == "closed form":
        return fold_sequence(design, values)
    return fold_general(design.pattern, values, params=params)


def placed_fold_states(
    design: Design | CreasePattern, ratio: float, frames: int = 1, method: str = "auto"
) -> tuple[list[FoldedState], list[str]]:
    """The folding of ``design`` from p = 0 to ``ratio`` in ``frames`` evenly spaced states
    (one: ``ratio`` alone), each placed on the table (mm), and what the fold warns of
    (the messages of :class:`StrainWarning`: the panels stretch past :data:`STRAIN_LIMIT` %),
    as ``fold`` gives them to a user. ``method`` as :func:`fold_states`'."""
    import warnings

    from origami_cad.kinematics.placement import place_sequence

    if isinstance(design, CreasePattern):
        design = Design(design, None, "file")
    ratios = np.linspace(0.0, ratio, frames) if frames > 1 else [ratio]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", StrainWarning)
        states = fold_states(design, ratios, method=method)
    folded = states[-1].pattern or design.pattern  # a cut pattern's folds with its cuts open
    placed = place_sequence(folded, [s.coords for s in states])
    states = [dataclasses.replace(s, coords=c) for s, c in zip(states, placed, strict=True)]
    return states, [str(w.message) for w in caught if w.category is StrainWarning]


def _ratio(p) -> float:
    value = float(p)
    if not 0.0 <= value <= 1.0:
        raise PatternError(f"fold ratio must lie in [0, 1], got {p}")
    return value


def fold_general(
    cp: CreasePattern,
    ratios: Sequence[float],
    *,
    params: SimulationParams | None = None,
    step_deg: float = STEP_DEG,
    cuts_open: bool = True,
    deadline: float = math.inf,
) -> list[FoldedState]:
    """Fold ``cp`` by driving every crease toward its target angle times each ratio.

    Parameters
    ----------
    cp : CreasePattern
        Any pattern with panels, mm.
    ratios : sequence of float
        Fold ratios in [0, 1]: each crease's target is its fold angle (or +-180 deg)
        times the ratio.
    params : SimulationParams, optional
        Materials of the panels and creases (default: the printed sheet's); fold
        limits, gravity and ground are not used.
    step_deg : float
        Largest change of a target between two solves, degrees.
    cuts_open : bool
        Part the two sides of every cut with a panel on both (else they stay joined,
        as the string models hold them: the states keep ``cp``'s vertices).
    deadline : float
        A :func:`time.monotonic` time (s) past which a ``SimulationError`` says how far it got.

    Returns
    -------
    list of FoldedState
        One per ratio, in the order given (``method`` ``"general"``, ``strain`` percent),
        the panel nearest the pattern's centre held flat in ``z = 0``. Where a cut has
        a panel on both sides the sides part (as Origami Simulator splits cuts): the
        states' ``pattern`` is ``cp.with_cuts_opened()``, its vertices and edges those of
        ``cp`` first (same indices), then the cuts' other sides.
    """
    values = [_ratio(p) for p in ratios]
    if not step_deg > 0:
        raise PatternError(f"the continuation step must be > 0 deg, got {step_deg}")
    if not values:
        return []
    if not cp.edge_mask(*_FOLDING).any():
        raise PatternError("the pattern has no mountain or valley crease to fold")
    if cuts_open:
        cp = cp.with_cuts_opened()  # a cut's sides part: each has its own vertices
    params = params or SimulationParams()
    st, target, free, driven = _driven_structure(cp, params)
    drive = {"strongest": _strongest_drive(cp, st, params, driven)}
    drive.update(relaxations=DRIVE_RELAXATIONS, deadline=deadline)
    asm = HessianAssembly(st)
    solve = functools.partial(solve_equilibrium, st=st, assembly=asm, deadline=deadline)
    cap = math.radians(MAX_TARGET_DEG)
    largest = float(np.degrees(np.max(np.abs(target)))) if len(target) else 0.0
    x, previous = st.x0.copy(), st.x0.copy()
    q_x = q_previous = done = 0.0  # the ratios of x and of the state before it
    states: dict[float, FoldedState] = {}
    for goal in sorted(set(values)):
        ramp = _ramp(done, goal, largest, step_deg)
        for k, q in enumerate(ramp, start=1):
            # predictor: the last step extrapolated (the path is smooth between solves)
            reach = (q - q_x) / (q_x - q_previous) if q_x > q_previous else 0.0
            guess = x + (x - previous) * min(reach, 1.0)
            previous, q_previous, q_x = x, q_x, q
            st.hinge_rest = np.clip(target * q, -cap, cap)
            st.hinge_rest[free] = fold_angles(x, st.hinges[free])
            tol, most = (_TOL_END, _MAX_ITER) if k == len(ramp) else (_TOL_STEP, _MAX_ITER_STEP)
            x, _ = solve(guess, tol=tol, max_iter=most)
            # the drive is stiffened at the first step where the panels hold the creases back,
            # relaxed at the first where it stretches them: the rest of the path follows it
            x, settled = _settle(st, x, asm, driven, free, drive, tol)
            _in_time(deadline, q, max(values))
            if settled:
                previous, q_previous = x, q_x  # no extrapolation across a change of drive
        done = goal
        states[goal] = _state(cp, st, x, goal)
    out = [states[p] for p in values]
    _warn_strain(max(s.strain for s in out))
    return out


def _in_time(deadline: float, p: float, last: float) -> None:
    """A :class:`SimulationError` when the :func:`time.monotonic` ``deadline`` (s) has
    passed, the folding at ratio ``p`` of ``last``."""
    if time.monotonic() > deadline:
        raise SimulationError(
            f"the general folder ran out of time at fold ratio {p:.3f} of {last:g} (its path "
            "is unfinished): a longer time limit lets it fold the pattern"
        )


def _warn_strain(worst: float) -> None:
    """A :class:`StrainWarning` when the largest strain ``worst`` (percent) is over
    :data:`STRAIN_LIMIT`."""
    if worst > STRAIN_LIMIT:
        warn(
            f"the general fold stretches an edge by {worst:.3g} %, over the {STRAIN_LIMIT:g} % "
            "limit: the pattern does not fold this far without bending or stretching its panels",
            StrainWarning,
            stacklevel=3,
        )


def _ramp(start: float, goal: float, largest: float, step_deg: float) -> list[float]:
    """The ratios of the solves from ratio ``start`` to ``goal`` (>= ``start``): equal
    steps of at most ``step_deg`` on the ``largest`` target (degrees)."""
    if goal <= start or largest <= 0:
        return [goal]
    n = max(1, math.ceil((goal - start) * largest / step_deg - 1e-9))
    return [start + (goal - start) * k / n for k in range(1, n + 1)]


def _settle(st, x, asm, driven, free, drive: dict, tol) -> tuple[np.ndarray, bool]:
    """Stiffen the drive where the panels hold the creases back, relax it where it
    stretches them: ``(nodes (n, 3) mm, whether the drive changed)``.

    While the driven creases reach on average less than :data:`DRIVE_REACH` of their
    targets, the drive is stiffened :data:`DRIVE_STEP` times (up to ``drive["strongest"]`` (H,)
    N mm/rad) and the state solved again from where it is (to a residual of ``tol``
    N); then, while a bar is stretched by more than :data:`DRIVE_STRAIN` percent, it is
    relaxed to a third (``drive["relaxations"]`` times at most in all), and never
    stiffened again."""
    changed = False

    def solve(x):
        st.hinge_rest[free] = fold_angles(x, st.hinges[free])
        limit = {"tol": tol, "max_iter": _MAX_ITER, "deadline": drive["deadline"]}
        return solve_equilibrium(x, st, assembly=asm, **limit)[0]

    strongest = drive["strongest"]
    while _reach(st, x, driven) < DRIVE_REACH and np.any(st.hinge_k[driven] < strongest):
        st.hinge_k[driven] = np.minimum(st.hinge_k[driven] * DRIVE_STEP, strongest)
        x, changed = solve(x), True
    while drive["relaxations"] > 0 and _bar_strain(st, x) > DRIVE_STRAIN / 100.0:
        st.hinge_k[driven] /= 3.0
        drive["strongest"] = st.hinge_k[driven].copy()
        drive["relaxations"] -= 1
        x, changed = solve(x), True
    return x, changed


def _reach(st: Structure, x: np.ndarray, driven: np.ndarray) -> float:
    """How far the driven creases are folded toward their targets, on average: the sum
    of their fold angles' magnitudes over the sum of their targets' (1: there)."""
    goal = float(np.sum(np.abs(st.hinge_rest[driven])))
    if goal <= 0:
        return 1.0
    angle = fold_angles(x, st.hinges[driven])
    return float(np.sum(np.minimum(np.abs(angle), np.abs(st.hinge_rest[driven])))) / goal


def _strongest_drive(cp, st, params, driven) -> np.ndarray:
    """The stiffest drive of each driven hinge, N mm/rad: a strip of panel
    :data:`DRIVE_LENGTH` times the pattern's size long bending, per mm of crease."""
    i, j = st.hinges[driven, 0], st.hinges[driven, 1]
    length = np.linalg.norm(st.x0[j] - st.x0[i], axis=1)
    return np.maximum(params.panel_bending / (DRIVE_LENGTH * cp.size) * length, st.hinge_k[driven])


def _bar_strain(st: Structure, x: np.ndarray) -> float:
    """The largest relative change of a bar's length at nodes ``x`` (n, 3) mm."""
    length, _ = bar_lengths(x, st.bars)
    return float(np.max(np.abs(length - st.bar_rest) / st.bar_rest))


def _driven_structure(cp: CreasePattern, params: SimulationParams):
    """The bar-and-hinge model with every hinge's stiffness set for folding: ``(structure,
    target (H,) rad at p = 1, free (H,) bool: the unassigned creases and the border lines
    with a panel on both sides, driven (H,) bool: the mountain and valley creases)``."""
    st: Structure = build_structure(cp, params)
    st.hinge_limit = np.full(len(st.hinges), math.inf)
    edge = st.hinge_edge
    assigned = np.full(len(edge), "", dtype="<U1")
    assigned[edge >= 0] = cp.assignments[edge[edge >= 0]]
    driven = np.isin(assigned, _FOLDING)
    target = np.zeros(len(edge))
    target[driven] = np.radians(cp.fold_angles[edge[driven]])
    facet = np.isin(assigned, _FACET)
    st.hinge_k = st.hinge_k.copy()
    st.hinge_k[facet] = _facet_stiffness(st, params)[facet]
    free = np.isin(assigned, ("U", "B"))  # a black line inside the sheet: a free hinge
    st.hinge_k[free] *= FREE_HINGE_STIFFNESS
    return st, target, free, driven


def _facet_stiffness(st: Structure, params: SimulationParams) -> np.ndarray:
    """A stiff facet hinge's rotational stiffness on every hinge, N mm/rad: the panels'
    bending ``E h^3 / 12`` times the hinge's length over its triangles' mean height (as
    :func:`~origami_cad.simulation.model.build_structure` gives a panel's diagonal)."""
    x0 = st.x0
    i, j, k, l = st.hinges.T
    axis = x0[j] - x0[i]
    length = np.linalg.norm(axis, axis=1)
    h1 = np.abs(np.cross(axis, x0[k] - x0[i])[:, 2]) / length
    h2 = np.abs(np.cross(axis, x0[l] - x0[i])[:, 2]) / length
    return params.panel_bending * length / np.maximum(0.5 * (h1 + h2), 1e-6)


def _state(cp: CreasePattern, st: Structure, x: np.ndarray, p: float) -> FoldedState:
    """The folded state of nodes ``x`` (n, 3) mm: the vertices on no panel carried by the
    panel triangle they lie in, fold angles per edge (degrees, 0 on the border) and the
    largest strain of a bar or pattern edge, percent."""
    x = _carry_loose(cp, st, x)
    length, _ = bar_lengths(x, st.bars)
    strain = float(np.max(np.abs(length - st.bar_rest) / st.bar_rest))
    flat = cp.edge_lengths()
    folded = np.linalg.norm(x[cp.edges[:, 1]] - x[cp.edges[:, 0]], axis=1)
    keep = flat > 0
    if keep.any():
        strain = max(strain, float(np.max(np.abs(folded[keep] - flat[keep]) / flat[keep])))
    angles = np.zeros(cp.n_edges)
    folds = st.hinge_edge >= 0
    angles[st.hinge_edge[folds]] = np.degrees(fold_angles(x, st.hinges[folds]))
    return FoldedState(float(p), x, angles, method="general", strain=100.0 * strain, pattern=cp)


def _carry_loose(cp: CreasePattern, st: Structure, x: np.ndarray) -> np.ndarray:
    """``x`` (n, 3) mm with each vertex that no panel triangle has (the far end of a
    dangling crease) moved with the triangle it lies in (or the nearest), flat."""
    x = x.copy()
    loose = np.setdiff1d(np.arange(cp.n_vertices), st.triangles.ravel())
    if not len(loose):
        return x
    tri = st.triangles
    a, b, c = (cp.vertices[tri[:, k]] for k in range(3))
    u, w = b - a, c - a
    det = u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]
    for v in loose:
        d = cp.vertices[v] - a
        s1 = (d[:, 0] * w[:, 1] - d[:, 1] * w[:, 0]) / det
        s2 = (u[:, 0] * d[:, 1] - u[:, 1] * d[:, 0]) / det
        inside = np.minimum(np.minimum(s1, s2), 1.0 - s1 - s2)  # >= 0 inside the triangle
        t = int(np.argmax(inside))
        i, j, k = tri[t]
        x[v] = x[i] + s1[t] * (x[j] - x[i]) + s2[t] * (x[k] - x[i])
    return x


def fold_notes(cp: CreasePattern, fold_angles, method: str = "closed form") -> list[str]:
    """A note when some mountain and valley creases do not fold at all (``fold_angles``
    in degrees), or, folded by the general solver, when most turn by less than 5 deg."""
    if fold_angles is None:
        return []
    creases = cp.edge_mask("M", "V")
    if method != "closed form":
        turned = int(np.sum(np.abs(np.asarray(fold_angles)[creases]) > 5.0))
        if 2 * turned >= creases.sum():
            return []
        return [
            f"note: only {turned} of the {int(creases.sum())} creases turn by more than 5 deg: "
            "even driven hard enough to bend its panels this pattern hardly folds from flat "
            "(a pattern whose panels must stretch stops short)"
        ]
    flat = creases & (np.abs(np.asarray(fold_angles)) < 1e-6)
    if not flat.any():
        return []
    return [
        f"note: {int(flat.sum())} of the {int(creases.sum())} creases stay flat: their straight "
        "crease lines fold independently of the driving crease (as a map's lines fold one at "
        "a time), which a one-parameter rigid folding leaves flat; the general method "
        "folds them together"
    ]
