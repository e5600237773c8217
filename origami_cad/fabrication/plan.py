"""The first step of fabrication: plan the panels as plain data, before any solid is built.

A :class:`PanelPlan` holds what the solids will be made from and what the
plots, the parts library and the string routing need: each panel's footprints
(:class:`~origami_cad.fabrication.panels.PanelOutline`), the holes
(:class:`~origami_cad.pattern.model.Hole` records and the panel of each), the
crease limits of the rigid folding (:class:`CreaseLimits`) and the warnings.
It is cheap (no B-rep); :func:`origami_cad.fabrication.build_fabrication` turns it
into solids.

>>> from origami_cad.fabrication import plan_panels
>>> from origami_cad.pattern.design import miura_design
>>> plan = plan_panels(miura_design(2, 3, 30.0, 30.0, 65.0))
>>> len(plan.outlines), len(plan.holes), plan.limits.status.value
(6, 6, 'foldable')
"""

from __future__ import annotations

import dataclasses
import enum
import math
import time
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from origami_cad._args import Arg, checked
from origami_cad.errors import FabricationError, PatternError
from origami_cad.fabrication.fitting import (
    MIN_BIAS,
    MIN_MIDLAYER_BIAS,
    MIN_SHELL,
    PanelBiases,
    panel_biases,
)
from origami_cad.fabrication.panels import (
    PanelOutline,
    check_panels,
    panel_outline,
    panel_outlines,
    plan_holes,
    printed_pattern,
    ring_joins,
)
from origami_cad.fabrication.params import FabricationParams
from origami_cad.kinematics.limits import crease_fold_limit
from origami_cad.pattern.design import Design
from origami_cad.pattern.model import CreasePattern, Hole

__all__ = [
    "DEFAULT_BED",
    "FABRICATION_BUDGET_S",
    "MAX_FABRICATED_PANELS",
    "MIN_BIAS",
    "MIN_MIDLAYER_BIAS",
    "MIN_SHELL",
    "SECONDS_PER_PANEL",
    "CreaseLimits",
    "LimitStatus",
    "PanelBiases",
    "PanelPlan",
    "check_bed",
    "check_panel_count",
    "crease_limits",
    "largest_bias",
    "panel_biases",
    "plan_panels",
]


#: The print bed a sheet is checked against by default, mm: PrusaSlicer's default printer
#: profile (what its command line slices on without a printer profile), and common 220 mm beds.
DEFAULT_BED = (200.0, 200.0)


class LimitStatus(enum.Enum):
    """Whether the crease limits of a pattern were found."""

    #: The rigid folding ran: the limits are known.
    FOLDABLE = "foldable"
    #: The kinematics could not fold the pattern rigidly (``reason`` says why).
    NOT_FOLDABLE = "not foldable"
    #: Not checked: the pattern has no transition graph to fold it by.
    NOT_CHECKED = "not checked"


@dataclass(frozen=True)
class CreaseLimits:
    """Where the rigid folding brings creases to ``theta_max`` (eq. 6), one schema for all cases.

    Attributes
    ----------
    status : LimitStatus
        Whether the limits were found.
    reason : str
        Why they were not (empty when ``FOLDABLE``).
    p_max_kinematic : float or None
        Fold ratio at which the first crease reaches ``theta_max`` (1.0 if none
        does before the pattern is flat-folded); ``None`` unless ``FOLDABLE``.
    limiting_edges : ndarray of int, shape (k,)
        The creases that reach ``theta_max`` at ``p_max_kinematic`` (at most 50).
    limiting_midpoints : ndarray, shape (k, 2)
        Their midpoints, mm (rounded to 1 um).
    limiting_assignments : tuple of str
        Their assignments (``"M"`` or ``"V"``).
    creases_before_p_max : int
        Number of creases reaching ``theta_max`` before eq. 6's ``p_max``.
    """

    status: LimitStatus
    reason: str = ""
    p_max_kinematic: float | None = None
    limiting_edges: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    limiting_midpoints: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    limiting_assignments: tuple[str, ...] = ()
    creases_before_p_max: int = 0

    @property
    def foldable(self) -> bool:
        """Whether the rigid folding found the limits."""
        return self.status is LimitStatus.FOLDABLE

    def to_dict(self) -> dict[str, Any]:
        """The limits for ``fabrication.json`` (the same keys whatever the status)."""
        return {
            "status": self.status.value,
            "reason": self.reason,
            "p_max_kinematic": self.p_max_kinematic,
            "limiting_creases": [
                {"edge": int(e), "midpoint_mm": m.tolist(), "assignment": a}
                for e, m, a in zip(
                    self.limiting_edges,
                    self.limiting_midpoints,
                    self.limiting_assignments,
                    strict=True,
                )
            ],
            "creases_before_p_max": self.creases_before_p_max,
        }


def crease_limits(design: Design, params: FabricationParams, samples: int = 101) -> CreaseLimits:
    """Where the rigid folding of ``design`` brings creases to ``theta_max`` (eq. 6).

    Every crease's fold angle grows with the fold ratio ``p`` at its own rate:
    the legs of a Miura fold faster than its main creases. Finds the fold ratio
    at which each crease reaches ``theta_max``, the structure's kinematic
    ``p_max`` (the first such ratio) and the creases that limit it. ``NOT_CHECKED``
    for a pattern without a transition graph, ``NOT_FOLDABLE`` when the
    kinematics cannot fold it.

    This does not model collisions between several thick panels around one
    vertex (the paper's multi-layer caveat): creases that reach ``theta_max``
    first are where such collisions start.

    Parameters
    ----------
    design : Design
        The pattern and its transition graph.
    params : FabricationParams
        Gives ``theta_max`` (eq. 6).
    samples : int
        Fold ratios sampled from 0 to 1 (limits are interpolated between them).
    """
    from origami_cad.kinematics.folding import fold_sequence

    if design.tg is None:
        return CreaseLimits(LimitStatus.NOT_CHECKED, "the pattern has no transition graph")
    ratios = np.linspace(0.0, 1.0, samples)
    try:
        states = fold_sequence(design, ratios)
    except (PatternError, ImportError) as exc:
        return CreaseLimits(LimitStatus.NOT_FOLDABLE, str(exc))
    cp = design.pattern
    creases = np.flatnonzero(cp.edge_mask("M", "V"))
    angles = np.abs(np.array([s.fold_angles[creases] for s in states]))  # (samples, creases)
    p_first = _first_ratio(ratios, angles, math.degrees(params.theta_max))
    if np.all(np.isnan(p_first)):
        return CreaseLimits(LimitStatus.FOLDABLE, p_max_kinematic=1.0)
    p_kin = float(np.nanmin(p_first))
    limiting = creases[np.isclose(p_first, p_kin, atol=1e-3)][:50]
    mids = (cp.vertices[cp.edges[limiting, 0]] + cp.vertices[cp.edges[limiting, 1]]) / 2
    return CreaseLimits(
        LimitStatus.FOLDABLE,
        p_max_kinematic=p_kin,
        limiting_edges=limiting,
        limiting_midpoints=mids.round(3),
        limiting_assignments=tuple(str(a) for a in cp.assignments[limiting]),
        creases_before_p_max=int(np.count_nonzero(p_first < params.p_max - 1e-3)),
    )


def _first_ratio(ratios: np.ndarray, angles: np.ndarray, limit: float) -> np.ndarray:
    """Per crease (column of ``angles``, degrees): the first ratio reaching ``limit``, or NaN.

    Interpolated linearly between the samples that bracket it.
    """
    reached = angles >= limit
    first = np.where(reached.any(axis=0), np.argmax(reached, axis=0), -1)
    p_first = np.where(first >= 0, ratios[np.maximum(first, 0)], np.nan)
    for k in np.flatnonzero(first > 0):
        i = first[k]
        a0, a1 = angles[i - 1, k], angles[i, k]
        p_first[k] = ratios[i - 1] + (limit - a0) / (a1 - a0) * (ratios[i] - ratios[i - 1])
    return p_first


@dataclass(frozen=True)
class PanelPlan:
    """The panels of a structure to print, as plain data (no solids).

    Attributes
    ----------
    pattern : CreasePattern
        The crease pattern (its own holes, if any, unchanged).
    params : FabricationParams
        The fabrication parameters.
    outlines : tuple of PanelOutline
        Footprints of every panel, in face order.
    holes : tuple of Hole
        The string holes placed following ``params.holes``, mm.
    hole_panels : ndarray of int, shape (len(holes),)
        Index of the panel (face) of each hole.
    limits : CreaseLimits
        Where the rigid folding brings creases to ``theta_max``.
    warnings : tuple of str
        What may print or fold badly.
    timings : dict of str to float
        Seconds spent on each step of the plan.
    biases : ndarray (F,) or None
        Each panel's inner bias, mm, when some panel got less than ``params.bias``
        (:func:`panel_biases`); ``None`` when every panel has ``params.bias``.
    shells : ndarray (F,) or None
        Each panel's shell wall, mm, when some panel got a thinner one than ``params.shell``
        (:func:`panel_biases`; NaN for a panel in TPU alone, which has none); ``None`` when
        every panel has ``params.shell`` and some PLA.
    midlayers : ndarray (F,) or None
        Each panel's mid-layer margin ``m``, mm, when some panel got a narrower one than
        ``params.midlayer_bias`` or none (NaN: a panel in TPU alone); ``None`` otherwise.
    tpu_only : frozenset of int
        The panels (face indices) too small for any PLA, printed in TPU alone: no infill,
        no mid-layer, no hole (:func:`panel_biases`).
    """

    pattern: CreasePattern
    params: FabricationParams
    outlines: tuple[PanelOutline, ...]
    holes: tuple[Hole, ...]
    hole_panels: np.ndarray
    limits: CreaseLimits
    warnings: tuple[str, ...] = ()
    timings: dict[str, float] = field(default_factory=dict)
    biases: np.ndarray | None = None
    shells: np.ndarray | None = None
    midlayers: np.ndarray | None = None
    tpu_only: frozenset[int] = frozenset()

    def __repr__(self) -> str:
        """One line: the pattern, the panels, the holes, the smallest bias (mm), warnings."""
        least = self.params.bias if self.biases is None else float(np.min(self.biases))
        return (
            f"<PanelPlan of {self.pattern!r}: {len(self.outlines)} panels, "
            f"{len(self.holes)} holes, bias {least:g} to {self.params.bias:g} mm, "
            f"{len(self.warnings)} warnings>"
        )

    def bias_of(self, panel: int) -> float:
        """The inner bias of panel (face) index ``panel``, mm (``params.bias`` unless the
        panel was too small for it: :func:`panel_biases`)."""
        return self.params.bias if self.biases is None else float(self.biases[panel])

    def shell_of(self, panel: int) -> float:
        """The shell wall of panel (face) index ``panel``, mm (``params.shell`` unless the
        panel was too small for it even at :data:`MIN_BIAS`: :func:`panel_biases`; NaN for
        a panel printed in TPU alone)."""
        return self.params.shell if self.shells is None else float(self.shells[panel])

    def midlayer_of(self, panel: int) -> float:
        """The mid-layer margin ``m`` of panel (face) index ``panel``, mm
        (``params.midlayer_bias`` unless the panel was too small for it even at
        :data:`MIN_BIAS` and :data:`MIN_SHELL`: :func:`panel_biases`; NaN for a panel
        printed in TPU alone, which has no mid-layer)."""
        if self.midlayers is None:
            return self.params.midlayer_bias
        return float(self.midlayers[panel])

    @property
    def pattern_with_holes(self) -> CreasePattern:
        """The crease pattern carrying the placed holes (for FOLD files and routing)."""
        return self.pattern.with_holes(self.holes)

    def outline(self, label: str) -> PanelOutline:
        """The outline of the panel with this label; :class:`PatternError` if none."""
        return self.outlines[self.pattern.face_index(label)]

    def holes_of(self, panel: int) -> tuple[Hole, ...]:
        """The holes through panel (face) index ``panel``."""
        return tuple(h for h, i in zip(self.holes, self.hole_panels, strict=True) if i == panel)

    def holes_by_label(self) -> dict[str, tuple[Hole, ...]]:
        """The holes of every panel that has some, by panel label."""
        labels = self.pattern.face_labels
        return {labels[i]: self.holes_of(i) for i in dict.fromkeys(self.hole_panels.tolist())}


def _split_rings(message: str, design: Design, params, bed) -> PanelPlan:
    """The plan of ``design``, one of whose panels encloses another part of the pattern
    (``message``), with the facet creases of :func:`~origami_cad.fabrication.panels.
    ring_joins` printed as hinges that stay flat (assignment ``J``): each ring split in two,
    and a warning naming them. :class:`PatternError` (``message``, what was tried and what
    stops it) when no such creases split the rings, or the split pattern does not plan."""
    edges, joined = ring_joins(design.pattern)
    if joined is None:
        raise PatternError(
            f"{message}: no two facet creases cross the ring from its inner outline to its "
            "outer one, which fabricate would print as flat hinges to split it; draw them "
            "(assignment F: yellow in Origami Simulator's SVG) on two sides of the enclosed "
            "part, or make the enclosed part a separate pattern"
        )
    cp = design.pattern
    named = ", ".join(
        f"e{e} ({cp.vertices[a][0]:.4g}, {cp.vertices[a][1]:.4g})-({cp.vertices[b][0]:.4g}, "
        f"{cp.vertices[b][1]:.4g}) mm"
        for e, (a, b) in zip(edges, cp.edges[edges], strict=True)
    )
    change = f"printing the facet creases {named} as hinges that stay flat (assignment J)"
    try:
        plan = plan_panels(replace(design, pattern=joined), params, bed)
    except PatternError as exc:
        then = str(exc).removeprefix("cannot fabricate: ")
        raise PatternError(
            f"{message}; {change} splits the rings in two, but then {then}"
        ) from None
    said = message.removeprefix("cannot fabricate: ")
    split = f"{said}: {change}, which splits the rings in two"
    return replace(plan, warnings=(split, *plan.warnings))


@checked(
    FabricationError,
    source=Arg("object", types=(CreasePattern, Design), optional=False),
    params=Arg("object", types=(FabricationParams,)),
    bed=Arg("floats", length=2, min=0.0, open_min=True, max=1e5, optional=False),
)
def plan_panels(
    source: CreasePattern | Design,
    params: FabricationParams | None = None,
    bed: tuple[float, float] = DEFAULT_BED,
) -> PanelPlan:
    """Plan the printable panels of a crease pattern (or design): footprints, holes, limits.

    A panel too small for ``params.bias`` gets the largest bias that fits it, down to
    :data:`MIN_BIAS`, one too small even then the thickest shell wall that fits, down to
    :data:`MIN_SHELL`, then the widest mid-layer margin, down to :data:`MIN_MIDLAYER_BIAS`,
    and one too small for any PLA is printed in TPU alone (:func:`panel_biases`;
    ``biases``, ``shells``, ``midlayers``, ``tpu_only`` and ``warnings`` say which).

    Parameters
    ----------
    source : CreasePattern or Design
        The pattern; a design with a transition graph also gets its crease limits. Its
        faces are merged across facet creases (``F``): the plan's ``pattern`` is
        :func:`~origami_cad.fabrication.panels.printed_pattern`. A panel that encloses
        another part of the pattern (a ring) is split in two by printing two of its facet
        creases as hinges that stay flat (assignment ``J``,
        :func:`~origami_cad.fabrication.panels.ring_joins`), named in a warning.
    params : FabricationParams, optional
        Default ``FabricationParams()``.
    bed : (float, float)
        The print bed, mm: a sheet larger than it is warned about (``warnings``).

    Raises
    ------
    PatternError
        Naming the panel too small even for TPU alone at :data:`MIN_BIAS`, or the hole
        that does not fit, and the width that prints it, or the pattern's defect.
    """
    params = params or FabricationParams()
    design = source if isinstance(source, Design) else Design(source, None, "file")
    cp, source = printed_pattern(design.pattern), design
    if cp is not design.pattern:
        design = replace(design, pattern=cp)
    t0 = time.perf_counter()
    try:
        check_panels(cp)
    except PatternError as exc:
        return _split_rings(str(exc), source, params, bed)
    biases = panel_biases(cp, params)
    reduced = biases.reduced(params.bias)
    outlines = tuple(
        panel_outline(
            cp,
            fi,
            params,
            b,
            biases.shell_of(fi, params),
            biases.midlayer_of(fi, params),
            fi in biases.tpu_only,
        )
        for fi, b in enumerate(biases.bias)
    )
    holes, hole_panels = plan_holes(cp, list(outlines), params, biases.holeless)
    timings = {"panels_and_holes": time.perf_counter() - t0}
    t0 = time.perf_counter()
    limits = crease_limits(design, params)
    if design.tg is not None:
        timings["crease_limits"] = time.perf_counter() - t0
    warned = (
        *_bias_warnings(cp, params, biases),
        *_warnings(params, limits),
        *_bed_warning(cp, bed),
    )
    plan = PanelPlan(cp, params, outlines, holes, hole_panels, limits, warned, timings)
    if biases.shell is not None:
        plan = replace(plan, shells=biases.shell)
    if biases.midlayer is not None:
        plan = replace(plan, midlayers=biases.midlayer, tpu_only=biases.tpu_only)
    return replace(plan, biases=biases.bias) if len(reduced) else plan


def _named(cp: CreasePattern, faces, what) -> str:
    """Up to eight panels named with ``what(face)``, and how many more."""
    faces = list(faces)
    named = ", ".join(f"{cp.face_labels[f]}{what(f)}" for f in faces[:8])
    return named + (f" and {len(faces) - 8} more" if len(faces) > 8 else "")


def _bias_warnings(
    cp: CreasePattern, params: FabricationParams, biases: PanelBiases
) -> tuple[str, ...]:
    """Which panels got a smaller bias than ``params.bias``, a thinner shell wall, a narrower
    mid-layer, no PLA or no hole, and what it costs."""
    out = []
    reduced = biases.reduced(params.bias)
    if len(reduced):
        least = float(biases.bias[reduced].min())
        limit = math.degrees(float(crease_fold_limit(least, params.height, params.thickness)))
        out.append(
            f"{len(reduced)} of {len(cp.faces)} panels are too small for the inner bias "
            f"{params.bias:g} mm and got the largest that fits (at least {MIN_BIAS:g} mm): "
            f"{_named(cp, reduced, lambda f: f' {biases.bias[f]:.2f} mm')}; a crease "
            f"between two panels of {least:.2f} mm folds to {limit:.1f} deg before their "
            f"chamfers meet (eq. 6; fabrication.json lists every panel's bias)"
        )
    thinned = biases.thinned(params.shell)
    if len(thinned):
        out.append(
            f"{len(thinned)} of {len(cp.faces)} panels are too small for the shell wall "
            f"{params.shell:g} mm even at the inner bias {MIN_BIAS:g} mm and got the thickest "
            f"that fits (at least {min(MIN_SHELL, params.shell):g} mm, whole print layers): "
            f"{_named(cp, thinned, lambda f: f' {biases.shell[f]:.2f} mm')}; their TPU "
            f"wraps the PLA infill more thinly (fabrication.json lists every panel's shell)"
        )
    out += _midlayer_warnings(cp, params, biases)
    if biases.holeless:
        out.append(
            f"{len(biases.holeless)} panels have no room for a {params.hole_diameter:g} mm hole "
            f"and are printed without one: {_named(cp, sorted(biases.holeless), lambda f: '')}"
        )
    return tuple(out)


def _midlayer_warnings(
    cp: CreasePattern, params: FabricationParams, biases: PanelBiases
) -> list[str]:
    """Which panels got a narrower mid-layer margin than ``params.midlayer_bias``, and which
    are printed in TPU alone."""
    out = []
    narrowed = biases.narrowed(params.midlayer_bias)
    least = f"the inner bias {MIN_BIAS:g} mm and shell wall {min(MIN_SHELL, params.shell):g} mm"
    if len(narrowed):
        out.append(
            f"{len(narrowed)} of {len(cp.faces)} panels are too small for the mid-layer margin "
            f"m = {params.midlayer_bias:g} mm even at {least} and got the widest that fits "
            f"(at least {MIN_MIDLAYER_BIAS:g} mm): "
            f"{_named(cp, narrowed, lambda f: f' {biases.midlayer[f]:.2f} mm')}; their PLA "
            f"mid-layer comes nearer their creases (fabrication.json lists every panel's "
            f"mid-layer margin)"
        )
    if biases.tpu_only:
        soft = _named(cp, sorted(biases.tpu_only), lambda f: "")
        out.append(
            f"{len(biases.tpu_only)} of {len(cp.faces)} panels are too small for a PLA infill "
            f"even at {least} and mid-layer margin {MIN_MIDLAYER_BIAS:g} mm, and are printed "
            f"in TPU alone (no infill, no mid-layer, no hole; the crease sheet runs through "
            f"them, so they bend like creases): {soft} "
            f"(fabrication.json: panels_tpu_only)"
        )
    return out


def _bed_excess(cp: CreasePattern, bed: tuple[float, float]) -> str | None:
    """How the flat sheet exceeds ``bed`` (mm, either way round), or ``None`` if it fits."""
    x0, y0, x1, y1 = cp.bounds
    w, h = sorted((x1 - x0, y1 - y0))
    if w <= min(bed) and h <= max(bed):
        return None
    return (
        f"the sheet is printed flat, {x1 - x0:.1f} x {y1 - y0:.1f} mm: larger than the "
        f"{bed[0]:g} x {bed[1]:g} mm print bed"
    )


#: CPU seconds :func:`~origami_cad.fabrication.build.fabricate` may take on a sheet, with
#: every file ``origami-cad fabricate`` writes: a minute, well inside the three minutes no
#: step of the chain may take on a busy machine.
FABRICATION_BUDGET_S = 60.0

#: CPU seconds per panel of the build and every export, measured (``benchmarks/
#: bench_fabrication.py``): 0.5 s for 25 panels, 1.3 s for 100, 5.0 s for 400, 12.4 s for
#: 900 Miura panels; linear in the panels from 100 on (14.8 ms a panel between 400 and 900,
#: rounded up). Memory grows alike: 1.6 GB peak for the 900.
SECONDS_PER_PANEL = 0.015

#: The most panels fabricate builds: those that fit :data:`FABRICATION_BUDGET_S` at
#: :data:`SECONDS_PER_PANEL` (4,000, a 63 x 63 sheet). A larger sheet is refused before
#: any work instead of running past its budget.
MAX_FABRICATED_PANELS = int(FABRICATION_BUDGET_S / SECONDS_PER_PANEL)


def check_panel_count(cp: CreasePattern) -> None:
    """Refuse a pattern of more than :data:`MAX_FABRICATED_PANELS` printed panels (its faces
    merged across facet creases), before any work.

    Raises
    ------
    FabricationError
        Naming the panel count, the time it would take and the budget.

    Examples
    --------
    >>> from origami_cad.pattern.design import miura_design
    >>> check_panel_count(miura_design(60, 60, 5.0, 5.0, 70.0).pattern)  # 3,600: accepted
    >>> check_panel_count(miura_design(70, 70, 5.0, 5.0, 70.0).pattern)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    origami_cad.errors.FabricationError: the sheet has 4,900 panels: fabricate would take ...
    """
    n = len(printed_pattern(cp).faces)
    if n > MAX_FABRICATED_PANELS:
        raise FabricationError(
            f"the sheet has {n:,} panels: fabricate would take about {n * SECONDS_PER_PANEL:.0f} "
            f"s of CPU ({1000 * SECONDS_PER_PANEL:g} ms a panel), more than its budget of "
            f"{FABRICATION_BUDGET_S:g} s (MAX_FABRICATED_PANELS = {MAX_FABRICATED_PANELS:,}): "
            "split it into sheets printed apart"
        )


def check_bed(cp: CreasePattern, bed: tuple[float, float] = DEFAULT_BED) -> None:
    """Refuse a sheet that does not lie flat on a ``bed[0] x bed[1]`` mm bed, either way round.

    Raises
    ------
    FabricationError
        Naming the sheet's size and the bed's.
    """
    if len(bed) != 2 or not all(math.isfinite(b) and b > 0 for b in bed):
        raise FabricationError(f"the print bed must be two sizes > 0 mm, got {tuple(bed)!r}")
    excess = _bed_excess(cp, bed)
    if excess:
        raise FabricationError(
            f"{excess}; give the bed it prints on (--bed X Y) or scale the pattern"
        )


def _bed_warning(cp: CreasePattern, bed: tuple[float, float]) -> tuple[str, ...]:
    """A warning when the flat sheet is larger than ``bed`` either way round."""
    excess = _bed_excess(cp, bed)
    if excess is None:
        return ()
    return (
        f"{excess} (PrusaSlicer's default printer, which its command line slices on without "
        "a printer profile: 'Objects could not fit on the bed'); print it on a printer whose "
        "bed holds it, or scale the pattern",
    )


def _fits(cp: CreasePattern, params: FabricationParams) -> bool:
    try:
        plan_holes(cp, panel_outlines(cp, params), params)
    except PatternError:
        return False
    return True


def largest_bias(
    pattern: CreasePattern | Design, params: FabricationParams | None = None, step: float = 0.01
) -> float | None:
    """The largest inner bias ``b`` (mm, a multiple of ``step``) at which every panel fits.

    Every panel must keep its footprints for ``b`` and the mid-layer inset ``b + m``
    and, with ``holes`` set, room for its hole: the other parameters of ``params``
    stay as they are. ``None`` when not even ``step`` fits (the cause is then not
    the bias: the hole diameter, the mid-layer inset or the pattern itself).
    Searched by bisection up to ``params.bias`` (returned as is when it fits).

    >>> from origami_cad.pattern.design import miura_design
    >>> largest_bias(miura_design(2, 3, 20.0, 20.0, 70.0), FabricationParams(bias=8))
    7.59
    """
    cp = pattern.pattern if isinstance(pattern, Design) else pattern
    params = params or FabricationParams()

    def fits(b: float) -> bool:
        return _fits(cp, dataclasses.replace(params, bias=b))

    lo, hi = step, max(params.bias, step)
    if not fits(lo):
        return None
    if fits(hi):
        return hi
    for _ in range(40):  # fits(lo), not fits(hi)
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if fits(mid) else (lo, mid)
        if hi - lo < step / 10:
            break
    best = math.floor(lo / step + 1e-9) * step
    while best > step and not fits(best):
        best -= step
    while best + step < hi and fits(best + step):
        best += step
    return round(best, 10)


def _warnings(params: FabricationParams, limits: CreaseLimits) -> tuple[str, ...]:
    out = []
    infill = params.half_height - params.shell
    if infill < 0.2:
        out.append(
            f"the infill is only {infill:.2g} mm thick between the shell skin and the crease "
            f"layer (half height {(params.half_height):.2g} mm, shell {params.shell:g} mm): "
            "consider a thinner shell or a taller panel"
        )
    if limits.creases_before_p_max:
        out.append(
            f"{limits.creases_before_p_max} creases reach their fold limit (eq. 6) before the "
            f"main crease: the structure folds to p = {limits.p_max_kinematic:.3f}, not eq. 6's "
            f"{params.p_max:.3f}"
        )
    return tuple(out)
