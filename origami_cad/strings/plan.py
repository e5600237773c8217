"""Automatic string routing: search hole sequences, hole positions and sides by the DCQC model.

The paper routes its strings by hand, following the DCQC principle ("a proper
string routing method should enable the origami folding process to satisfy the
DCQC continuously"). :func:`plan_routes` searches for such routes:

1. **Geometry, once.** The sheet is folded rigidly on a grid of fold ratios from
   flat to the target and placed as both string models place it (the mean pose
   on a ring, the TSA's panel held onboard). Candidate holes lie in each
   panel's operation region (:func:`~origami_cad.fabrication.plan_panels`): its
   automatic hole and points towards the region's corners.
2. **Beam search over hole sequences.** From each TSA anchor (ring guides every
   few degrees, or the onboard TSA's mount) a string threads holes along the
   panel adjacency; between panels sharing a mountain (valley) crease it runs
   below (above) it, the DCQC side rule (:func:`~origami_cad.strings.route.side_rule`).
   The beam keeps the best partial strings at each depth.
3. **Beam search over string sets**: routes of ``n_strings`` strings (on a ring
   no two share a panel or a guide), scored as a whole.
4. **CMA-ES over hole positions** (and ring guide angles) of the best routes,
   holes kept inside their operation regions.

Every candidate is scored on the fast DCQC model, vectorised over candidates and
fold ratios: for each string the TSA rotation ``theta_i(p)`` at which it binds at
fold ratio ``p`` (eq. 8 inverted in closed form, or the onboard model); the TSA
reaches ``p`` at ``theta(p) = min_i theta_i(p)``. A route is **valid** when from
flat to the target no string lengthens (at the TSA's rotation of each state, as
the sheet folds on) and ``theta(p)`` never falls, and no segment cuts through its
panels in any state. Valid routes are ranked by

``cost = ln(turns) + ln(peak torque) + share_weight * (1 - load share)``

where the peak torque follows by virtual work, ``tau = dE/dtheta`` with ``E`` the
creases' elastic energy, and the load share is the fraction of string states
within ``share_tolerance`` mm of taut (1: every string pulls all the way).
``max_turns`` and ``max_torque`` are budgets; routes over them are penalised.

Results do not depend on the executor: the work is split into a fixed number of
tasks, task ``k`` is seeded ``seed + k``, and results are gathered in task order.
"""

from __future__ import annotations

import concurrent.futures as cf
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from origami_cad._args import Arg, brief_value, check_number, check_numbers, checked
from origami_cad.errors import PatternError, StringsError
from origami_cad.fabrication.params import FabricationParams
from origami_cad.kinematics.folding import PathDesign, fold_design
from origami_cad.pattern.design import Design
from origami_cad.strings.plan_geometry import plan_geometry, target_ratio, truncated_geometry
from origami_cad.strings.plan_model import (
    DEFAULT_CREASE_STIFFNESS,
    PlanGeometry,
    PlannedRoute,
    PlanSettings,
    RouteScores,
    TSAPlacement,
)
from origami_cad.strings.plan_scoring import evaluate_routes, string_curves
from origami_cad.strings.plan_search import (
    progress_tick,
    ranked_routes,
    run_tasks,
    search_routes,
    string_pool,
    string_sets,
)
from origami_cad.strings.route import RouteSpec

__all__ = [
    "DEFAULT_CREASE_STIFFNESS",
    "MAX_STRINGS",
    "PlanGeometry",
    "PlanSettings",
    "PlannedRoute",
    "RouteScores",
    "TSAPlacement",
    "evaluate_routes",
    "fewest_strings",
    "plan_data",
    "plan_geometry",
    "plan_messages",
    "plan_numbers",
    "plan_routes",
    "route_spec",
    "run_tasks",
    "string_curves",
    "target_ratio",
    "truncated_geometry",
]


#: The most strings :func:`fewest_strings` tries (the ``--strings`` option's maximum).
MAX_STRINGS = 16


def _check_plan_lists(free_panels: Any, existing_holes: Any, target_angles: Any) -> None:
    """plan_routes' list arguments: panel labels, [x, y] mm holes, {edge: degrees}."""
    if isinstance(free_panels, str) or not isinstance(free_panels, list | tuple):
        raise StringsError(
            "plan_routes: free_panels: expected a list of panel labels, got "
            f"{brief_value(free_panels)}"
        )
    if not all(isinstance(label, str) for label in free_panels):
        raise StringsError(
            "plan_routes: free_panels: expected panel labels (text), got "
            f"{brief_value(free_panels)}"
        )
    if not isinstance(existing_holes, list | tuple | np.ndarray):
        raise StringsError(
            "plan_routes: existing_holes: expected a list of [x, y] mm, got "
            f"{brief_value(existing_holes)}"
        )
    for hole in existing_holes:
        check_numbers("plan_routes: existing_holes", hole, length=2, error=StringsError)
    if target_angles is None:
        return
    if not isinstance(target_angles, Mapping):
        raise StringsError(
            "plan_routes: target_angles: expected {edge: degrees}, got "
            f"{brief_value(target_angles)}"
        )
    for edge, angle in target_angles.items():
        check_number("plan_routes: target_angles edge", edge, kind="int", low=0,
                     error=StringsError)  # fmt: skip
        check_number("plan_routes: target_angles degrees", angle, low=-180.0, high=180.0,
                     error=StringsError)  # fmt: skip


@checked(
    StringsError,
    design=Arg("object", types=(Design,), optional=False),
    tsa=Arg("object", types=(TSAPlacement,), optional=False),
    n_strings=Arg("int", min=1, max=MAX_STRINGS),
    target_p=Arg(min=0.0, open_min=True, max=1.0),
    candidates=Arg("int", min=1, max=100_000, optional=False),
    seed=Arg("int", min=0, max=2**32 - 1, optional=False),
    progress=Arg("callable", length=2),
    fabrication=Arg("object", types=(FabricationParams,)),
    settings=Arg("object", types=(PlanSettings,)),
    check=Arg("int", min=0, max=1000, optional=False),
    geometry=Arg("object", types=(PlanGeometry,)),
)
def plan_routes(
    design: Design,
    tsa: TSAPlacement,
    n_strings: int | None = None,
    target_p: float | None = None,
    target_angles: dict[int, float] | None = None,
    free_panels: Sequence[str] = (),
    existing_holes: Sequence[tuple[float, float]] = (),
    candidates: int = 128,
    seed: int = 0,
    executor: cf.Executor | None = None,
    progress: Callable[[int, int | None], None] | None = None,
    *,
    fabrication: FabricationParams | None = None,
    settings: PlanSettings | None = None,
    check: int = 3,
    geometry: PlanGeometry | None = None,
) -> list[PlannedRoute]:
    """Search string routes that fold ``design`` to the target under the DCQC principle.

    Parameters
    ----------
    design : Design
        A pattern the kinematics folds (a TG tessellation or degree-4 vertices).
    tsa : TSAPlacement
        Ring rail (radius, height mm) or onboard on a panel, and the actuator.
    n_strings : int, optional
        Strings the TSA twists; default the fewest (1, 2, ... up to :data:`MAX_STRINGS`)
        whose best route reaches the target within the budgets (:func:`fewest_strings`).
    target_p : float, optional
        Fold ratio to reach; or ``target_angles`` ``{edge: degrees}``; default the fold
        limit (eq. 6 for ``fabrication``, the printed sheet, default ``FabricationParams()``).
    free_panels, existing_holes
        Panel labels that take no hole; holes ([x, y] mm) already there.
    candidates : int
        Beam width of the searches (partial strings per task and depth, string sets).
    seed : int
        Seed of the CMA-ES refinement (task ``k`` uses ``seed + k``).
    executor : concurrent.futures.Executor, optional
        Where the tasks run (default: a process pool on this machine).
    progress : callable, optional
        ``progress(candidates evaluated so far, None)``.
    settings : PlanSettings, optional
        The rest of the search (its ``candidates`` is replaced by ``candidates``).
    check : int
        The best ``check`` routes are re-run by :func:`~origami_cad.strings.simulate_dcqc`
        on the fine grid (``PlannedRoute.checks["dcqc"]``); those that fail are dropped.
    geometry : PlanGeometry, optional
        :func:`plan_geometry` of these arguments, if already made (it is not checked).

    Returns
    -------
    list of PlannedRoute
        Valid routes, best first (at most ``settings.keep``).
    """
    _check_plan_lists(free_panels, existing_holes, target_angles)
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise StringsError(
            "plan_routes: executor: expected a concurrent.futures.Executor, got "
            f"{brief_value(executor)}"
        )
    settings = settings or PlanSettings()
    deadline = min(settings.deadline, time.time() + settings.time_limit)
    settings = replace(settings, candidates=int(candidates), deadline=deadline)
    search = _search(design, settings, seed, executor, progress, check, n_strings)
    search["elsewhere"] = lambda placement: plan_geometry(
        design, placement, fabrication, settings, target_p=target_p,
        target_angles=target_angles, free_panels=free_panels, existing_holes=existing_holes,
    )  # fmt: skip
    geom = geometry or search["elsewhere"](tsa)
    search["lower"] = n_strings is None and target_p is None and not target_angles
    return _within_reach(design, geom, settings, search)


def _search(design, settings, seed, executor, progress, check: int, n_strings) -> dict:
    """What a plan tries: ``attempt(geometry, n)`` plans ``n`` strings (None: the fewest
    that reach its target), ``counted``: a count was asked for."""

    def attempt(g: PlanGeometry, n: int | None = n_strings) -> list[PlannedRoute]:
        if n is None:
            return fewest_strings(design, g, settings, seed, executor, progress, check)
        planned = search_routes(g, settings, n, seed, executor, progress)
        return _checked(design, g, settings, planned, check, n)

    return {"attempt": attempt, "counted": n_strings is not None}


#: Grid states a default target falls back to when no route reaches the fold limit (of a
#: 33-state grid, ``p = limit (k / 32)^1.5``: about 65 %, 35 % and 20 % of the limit).
LOWER_STATES = (25, 17, 12)


def _within_reach(design, geom, settings, search: dict):
    """``search["attempt"](geom)``: the routes to the target; ``search["lower"]`` (a
    default target): failing that, to the furthest of :data:`LOWER_STATES`' fold ratios
    some route reaches (its routes' ``p`` grid ends there), within the time limit.
    Failing all, a :class:`StringsError` saying what failed and what was seen to work
    instead (:func:`_refusal`)."""
    attempt, start = search["attempt"], time.time()
    try:
        return attempt(geom)
    except StringsError as exc:
        first = str(exc)
    search["cost"] = time.time() - start  # s: what a search of the same sheet may take
    tried = []
    for lowered in _lowered(geom) if search["lower"] else ():
        if time.time() > settings.deadline:
            break
        tried.append(lowered.target_p)
        try:
            return attempt(lowered)
        except StringsError:
            continue
    raise StringsError(_refusal(design, geom, settings, search, first, tried)) from None


def _lowered(geom: PlanGeometry) -> list[PlanGeometry]:
    """``geom`` truncated to each of :data:`LOWER_STATES` its grid has, furthest first."""
    n = len(geom.ratios)
    return [truncated_geometry(geom, round(k * (n - 1) / 32) + 1) for k in LOWER_STATES if k < n]


def _refusal(design, geom, settings, search: dict, first: str, tried: list) -> str:
    """Why no route was planned (``first``), and only remedies seen to work: the search
    tries, while its time lasts, the fewest strings (a count was asked for), the TSA
    placed the other way (onboard the largest panel, or on a ring) and, for a target that
    was asked for, the smaller targets of :data:`LOWER_STATES`; what it tried in vain
    (``tried``: the smaller targets already tried) and what the time limit left untried
    are said instead."""
    attempt, elsewhere = search["attempt"], search["elsewhere"]
    at = geom.placement
    if at.kind == "ring":
        panel = _largest_panel(design)
        other = replace(at, kind="onboard", panel=panel, tsa=replace(at.tsa, model="onboard"))
        option = f"the TSA onboard its largest panel (``tsa`` onboard:{panel})"
    else:
        other = replace(at, kind="ring", panel=None, tsa=replace(at.tsa, model="ring"))
        option = "the TSA on a ring (``tsa`` ring)"
    options = [(option, lambda: attempt(elsewhere(other)))]
    if search["counted"]:
        options.insert(0, ("leaving --strings out", lambda: attempt(geom, None)))
    if not tried:
        options += [
            (f"--target-p {g.target_p:.2f}", lambda g=g: attempt(g)) for g in _lowered(geom)
        ]
    failed = [f"p = {p:.2f}" for p in tried]
    for k, (name, plan) in enumerate(options):
        if time.time() + search["cost"] > settings.deadline:  # one more would overrun it
            rest = ", ".join(n for n, _ in options[k:])
            vain = f" ({', '.join(failed)}: no route either)" if failed else ""
            return (
                f"{first}{vain}; the time limit of {settings.time_limit:g} s leaves no time to "
                f"try {rest}: a longer --time-limit tries them"
            )
        try:
            found = plan()
        except (StringsError, PatternError):
            failed.append(name)
            continue
        strings = len(found[0].strings)
        reach = "s reach" if strings != 1 else " reaches"
        return f"{first}; {name} works: {strings} string{reach} p = {found[0].p[-1]:.3f}"
    return f"{first}; tried too, and no route reaches its target: {'; '.join(failed)}"


def _largest_panel(design: Design) -> str:
    """The label of the pattern's largest panel (by area)."""
    cp = design.pattern
    areas = [abs(_area(cp.vertices[list(f)])) for f in cp.faces]
    return cp.face_labels[int(np.argmax(areas))]


def _area(xy: np.ndarray) -> float:
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _checked(design, geom, settings, planned, check: int, n_strings: int) -> list:
    """:func:`_check_best`, refusing when none of ``n_strings`` strings passes."""
    planned = _check_best(design, geom, settings, planned, check)
    if not planned:  # plan_routes says what else works
        raise StringsError(
            f"no route of {n_strings} strings satisfies DCQC to p = {geom.target_p:.3f}"
        )
    return planned


def _reaches(route: PlannedRoute, settings: PlanSettings) -> bool:
    """Whether a checked route reaches the target within the turn and torque budgets."""
    dcqc = route.checks.get("dcqc")
    return bool(
        dcqc is not None
        and route.turns <= settings.max_turns
        and route.peak_torque <= settings.max_torque
    )


def fewest_strings(
    design: Design,
    geom: PlanGeometry,
    settings: PlanSettings,
    seed: int = 0,
    executor: cf.Executor | None = None,
    progress: Callable[[int, int | None], None] | None = None,
    check: int = 3,
) -> list[PlannedRoute]:
    """The routes of the fewest strings that reach the target, as PyGamiX searches its count.

    One beam search of single strings, then for 1, 2, ... :data:`MAX_STRINGS` strings the
    best sets of that many: the first count whose best route, re-run by the full DCQC model
    (:func:`~origami_cad.strings.simulate_dcqc`), reaches ``geom.target_p`` within
    ``settings.max_turns`` and ``settings.max_torque`` is refined by CMA-ES and returned
    (every route has that many strings).

    Raises
    ------
    StringsError
        No count reaches the target, saying how far the search went and what else to try.
    """
    tick = progress_tick(progress)
    pool = string_pool(geom, settings, executor, tick)
    tried, why, best = 0, "", []
    for n in range(1, MAX_STRINGS + 1):
        if n > 1 and time.time() > settings.deadline:
            why = (
                f"; the time limit of {settings.time_limit:g} s ran out before {n} strings were "
                f"tried (--strings {n}, or a longer --time-limit)"
            )
            break
        try:
            routes, evaluated = string_sets(geom, settings, pool, n)
        except StringsError:
            why = f"; no {n} strings fit together on this sheet"
            break
        tick({"evaluated": evaluated})
        tried = n
        quick = ranked_routes(geom, settings, pool, routes, seed, executor, tick, 0)
        best = quick[:1] or best
        within = [r for r in quick if r.turns <= settings.max_turns]
        if not any(_reaches(r, settings) for r in _check_best(design, geom, settings, within, 1)):
            continue
        planned = ranked_routes(geom, settings, pool, routes, seed, executor, tick, settings.refine)
        planned = _check_best(design, geom, settings, planned, check)
        if planned:
            return planned
    remedy = _remedy(design, geom, settings, best)
    raise StringsError(
        f"no route of 1 to {tried} strings reaches p = {geom.target_p:.3f} within "
        f"{settings.max_turns:g} TSA turns{why}{f'; try {remedy}' if remedy else ''}"
    )


def _remedy(design, geom, settings, best: list[PlannedRoute]) -> str:
    """What the full DCQC model shows would let the best route found (``best``: it or
    nothing) reach its end: a larger turn budget, or the fold ratio it does reach as the
    target; empty when it shows neither."""
    if not best:
        return ""
    figures = _full_dcqc(design, geom, settings, best[0])
    if figures["reaches_target"]:
        return f"a larger turn budget (``budget`` {math.ceil(1.1 * figures['turns'])})"
    reached = math.floor(100 * figures["p"]) / 100
    if reached >= 0.01:
        return f"--target-p {reached:.2f} (the best route's DCQC folding stops there)"
    return ""


def route_spec(geom: PlanGeometry, planned: PlannedRoute) -> RouteSpec:
    """The planned route as a :class:`RouteSpec`, with the settings its route file keeps
    (``dump_route`` writes it): the turns a quarter more than planned, ``p_max`` the target
    when it is below the fold limit, an onboard TSA's panel held."""
    return RouteSpec(
        tsa=geom.placement.tsa,
        strings=planned.strings,
        thickness=geom.thickness,
        step=math.pi,
        max_turns=_max_turns(planned),
        p_max=geom.target_p if geom.target_p < geom.limit_p - 1e-9 else None,
        fixed_panel=geom.placement.panel if geom.placement.kind == "onboard" else None,
        take_up=0.1,
        fabrication=geom.fabrication,
    )


def _max_turns(planned: PlannedRoute) -> float:
    """Turns the route file allows: a quarter more than the plan needs, and one turn."""
    return float(math.ceil(1.25 * planned.turns + 1.0))


def _check_best(design, geom, settings, planned: list[PlannedRoute], check: int):
    """Re-run the best routes with the full DCQC model (its fine grid) until ``check`` of
    them pass (at most ``3 check`` tried); those that jam or stop short are dropped."""
    out, passed = [], 0
    for k, route in enumerate(planned):
        if passed >= check or k >= 3 * check:
            out.append(route)
            continue
        figures = _full_dcqc(design, geom, settings, route)
        if figures["reaches_target"] and not figures["segments_cutting_panels"]:
            passed += 1
            out.append(replace(route, checks={**route.checks, "dcqc": figures}))
    return [replace(r, rank=k + 1) for k, r in enumerate(out)]


def _full_dcqc(design, geom, settings, route: PlannedRoute) -> dict[str, Any]:
    """The full DCQC model's figures for a planned route (its route file's settings)."""
    from origami_cad.strings.dcqc import simulate_dcqc
    from origami_cad.strings.dcqc_result import StopReason

    res = simulate_dcqc(
        design,
        route_spec(geom, route),
        grid=None if design.tg is not None else 61,
        crease_stiffness=settings.crease_stiffness,
    )
    stops = (StopReason.FOLD_LIMIT,)
    return {
        "p": float(res.p[-1]),
        "turns": float(res.turns[-1]),
        "peak_torque_Nmm": float(np.nanmax(res.torque, initial=0.0)),
        "stop": res.stop.value,
        "reaches_target": bool(res.stop in stops and res.p[-1] >= geom.target_p - 1e-3),
        "segments_cutting_panels": len(res.cutting),
    }


def plan_numbers(planned, geom: PlanGeometry, seconds: float, cpu: float) -> list[tuple[str, str]]:
    """The key numbers of a plan (``planned`` best first; ``seconds`` wall, ``cpu`` CPU s)."""
    best = planned[0]
    sim = best.checks.get("simulation")
    checked = (
        "not run"
        if sim is None
        else f"p = {sim['p']:.3f} after {sim['turns']:.1f} turns ({sim['stop']})"
    )
    return [
        ("valid routes ranked", str(len(planned))),
        ("strings", str(len(best.strings))),
        ("target fold ratio", f"p = {geom.target_p:.4f} (fold limit {geom.limit_p:.4f})"),
        ("best: TSA turns / peak torque", f"{best.turns:.2f} / {best.peak_torque:.3g} N mm"),
        ("best: load share", f"{best.share:.2f}"),
        ("search time", f"{seconds:.1f} s wall, {cpu:.1f} s CPU here"),
        ("bar-and-hinge check of the best", checked),
    ]


def plan_messages(
    planned,
    geom: PlanGeometry,
    fewest: bool = False,
    design: Design | None = None,
    default_target: bool = False,
) -> list[str]:
    """What a plan tells its user: the best route, how many strings (``fewest``: chosen as
    the fewest that reach the target), the routes the simulator stops short, and, for a
    ``design`` folded along a general folder's path, that path's largest strain (percent)
    at the target; ``default_target``: the target was not asked for (a target below the
    fold limit is then one the search fell back to)."""
    best = planned[0]
    n = len(best.strings)
    strings = f"{n} string{'s' if n != 1 else ''}"
    chose = " (the fewest that reach the target)" if fewest else ""
    lines = [
        f"best of {len(planned)} routes: {strings}{chose}, {best.turns:.2f} TSA turns "
        f"to p = {geom.target_p:.4f}, peak torque {best.peak_torque:.3g} N mm"
    ]
    lines += [f"warning: {note}" for note in geom.notes]
    if default_target and geom.target_p < geom.limit_p - 1e-9:
        lines.append(
            f"warning: no route reaches the fold limit p = {geom.limit_p:.3f}; planned to "
            f"p = {geom.target_p:.3f}, the furthest of the fold ratios tried that one reaches "
            "(--target-p sets the target)"
        )
    for r in planned:
        sim = r.checks.get("simulation")
        if sim is not None and not sim["reaches_target"]:
            lines.append(
                f"warning: route {r.rank}: the bar-and-hinge simulation stops at p = "
                f"{sim['p']:.3f} ({sim['reason']})"
            )
    if isinstance(design, PathDesign) and design.path is not None:
        strain = fold_design(design, geom.target_p).strain
        lines.append(
            f"note: the pattern was folded by the general solver (the closed form does not "
            f"fold it); its largest edge strain at p = {geom.target_p:.3f} is {strain:.2g} %"
        )
    return lines


def plan_data(geom: PlanGeometry, planned, seconds: float) -> dict[str, Any]:
    """The content of ``routes.json``: the target, the TSA and every ranked route."""
    return {
        "target_p": geom.target_p,
        "fold_limit_p": geom.limit_p,
        "tsa": geom.placement.kind,
        "search_seconds": seconds,
        "routes": [r.to_dict() for r in planned],
    }
