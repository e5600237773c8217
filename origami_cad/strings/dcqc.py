"""Quasi-static folding under the DCQC principle (the paper's section IV-B, eqs. 7-8).

What it returns (:class:`~origami_cad.strings.dcqc_result.DCQCResult`, why it stopped,
a jam, the fold limit) is :mod:`origami_cad.strings.dcqc_result`'s.

In the initial state ``S_0`` (fold ratio ``p0``, strings tight) each string's
length is ``L_0 = l_AB(0) + routed length`` (eq. 7). As the TSA turns by
``theta_s``, its share ``l_AB(theta_s)`` grows (eq. 8, or the onboard model),
so each string demands ``g_i(p) = l_AB,i(theta_s, p) + rest_i(p) - L_0,i <= 0``.

Each quasi-static state is the *continuous successor* of the previous one: the
TSA turns by a small step (at most ``route.take_up`` mm of string and
``route.step`` of rotation), and the sheet folds from the previous fold ratio
up to where every string fits again. Folding is only possible while the
binding string's demand falls as the sheet folds (the DCQC rule): if it would
rise, the string would have to stretch, and the folding *jams*; the jam names
the string, the segment that lengthens, the fold ratio and the stretch it would
need. A state never jumps over fold ratios the strings forbid.

Panels are rigid. Strings are inextensible, or, given their ``EA`` and the creases'
stiffness, elastic: each state is then the nearest equilibrium of the creases' and the
strings' energy along the rigid folding (the bar-and-hinge simulation's energy with rigid
panels), and the tensions are the strings' stretch times ``EA / L_0``. The sheet
keeps its mean pose
(:func:`~origami_cad.strings.route.mean_pose`: the vertex centroid stays and it
does not rotate on average, a sheet free in the middle of the ring and pulled
evenly) unless the route holds a panel. The fold limit is the route's
``p_max``, else the printed sheet's (eq. 6 on the first crease, legs included,
:func:`fold_limit`), else the largest fold ratio the folder takes.

With a crease stiffness alone (inextensible strings), the tension follows by
virtual work: the binding strings' tension times the string that folding saves
per unit ``p`` equals the creases' elastic energy per unit ``p``. The TSA torque
is the tension times the string taken up per radian
(:meth:`TSAParams.consumed_derivatives`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from origami_cad._args import Arg, checked
from origami_cad.errors import SimulationError
from origami_cad.kinematics.folding import fold_coords, fold_design, fold_sequence
from origami_cad.pattern.design import Design
from origami_cad.strings.dcqc_result import DCQCResult, FoldLimit, Jam, StopReason
from origami_cad.strings.friction import capstan_rate
from origami_cad.strings.route import (
    RouteSpec,
    StringRoute,
    anchor_points,
    cutting_segments,
    hole_exits,
    hole_frames,
    mean_pose,
    rigid_fit,
    string_path,
)

__all__ = [
    "MAX_STRING_STRAIN",
    "MIN_DP",
    "fold_limit",
    "segment_lengths",
    "segment_names",
    "simulate_dcqc",
    "time_limit_stop",
    "torque_limit_reason",
    "tsa_step",
    "turn_limit_stop",
]

#: The smallest ``max_dp`` of :func:`simulate_dcqc`: a step of the fold ratio below it would
#: need over 10,000 states to cross the fold (the halving of a step is bounded by it).
MIN_DP = 1e-4


MAX_STRING_STRAIN = 0.02  #: an elastic string strained beyond this jams (both models)


def tsa_step(tsa, theta: float, x_dis: np.ndarray, take_up: float, cap: float) -> float:
    """The TSA rotation (rad) from ``theta`` that takes up ``take_up`` mm of string.

    For the string that takes most (``x_dis`` (k,) mm each), at most ``cap`` rad:
    the slow start of eq. 8 costs few steps and its fast end stays accurate.
    """
    x_dis = np.atleast_1d(np.asarray(x_dis, dtype=float))
    if not len(x_dis):
        return cap
    now = tsa.consumed(theta, x_dis)

    def taken(d: float) -> float:
        return float(np.max(tsa.consumed(theta + d, x_dis) - now))

    at_cap = taken(cap)
    if at_cap <= take_up:
        return cap
    return _root(lambda d: taken(d) - take_up, 0.0, cap, -take_up, at_cap - take_up, 1e-9 * cap)


def segment_names(string: StringRoute) -> list[str]:
    """Names of a string's segments: ``anchor -> hole 1``, then hole to hole."""
    return [f"anchor -> {string.names[0]}"] + [
        f"{a} -> {b}" for a, b in zip(string.names[:-1], string.names[1:], strict=True)
    ]


def segment_lengths(
    cp, coords: np.ndarray, string: StringRoute, thickness: float, frames=None
) -> np.ndarray:
    """Length of each segment (:func:`segment_names`) in folded states ``coords`` (P, n, 3).

    Returns (P, k) mm: the anchor's free stretch, then each hole-to-hole segment.
    """
    arrive, leave, _ = hole_exits(cp, coords, string, thickness, frames)
    first = np.linalg.norm(arrive[:, 0] - anchor_points(cp, coords, string, thickness), axis=-1)
    seg = np.linalg.norm(arrive[:, 1:] - leave[:, :-1], axis=-1)
    return np.column_stack([first, seg])


def _angle_table(design: Design, ratios: np.ndarray, coords: np.ndarray | None) -> np.ndarray:
    """Fold angles (G, m) in radians of every edge at fold ratios ``ratios``."""
    from origami_cad.kinematics.fold3d import fold_angles_from_coords

    if coords is not None:
        return np.stack([fold_angles_from_coords(design.pattern, c) for c in coords])
    return np.radians(np.stack([s.fold_angles for s in fold_sequence(design, ratios)]))


def fold_limit(design: Design, route: RouteSpec, samples: int = 81) -> FoldLimit:
    """The fold limit of a routed sheet: the largest fold ratio either model may reach.

    The route's ``p_max`` if given; with ``[fabrication]`` the printed sheet's
    limit, the fold ratio at which the *first* crease (legs included) reaches
    eq. 6's ``theta_max`` (:func:`~origami_cad.fabrication.params.theta_max`),
    refined by bisection to 1e-6; both given: the smaller. Otherwise the largest
    fold ratio the folder takes, 1 (flat-folded).
    """
    limits = []
    if route.p_max is not None:
        limits.append(FoldLimit(float(route.p_max), "route"))
    fab = route.fabrication
    if fab is not None:
        cp = design.pattern
        creases = np.flatnonzero(cp.edge_mask("M", "V"))
        top = fab.theta_max

        def excess(p: float) -> float:
            return float(np.max(np.abs(np.radians(fold_design(design, p).fold_angles[creases]))))

        ratios = np.linspace(route.p0, 1.0, samples)
        worst = np.abs(_angle_table(design, ratios, None)[:, creases]).max(axis=1)
        over = np.flatnonzero(worst >= top)
        if len(over) and over[0] > 0:
            lo, hi = float(ratios[over[0] - 1]), float(ratios[over[0]])
            while hi - lo > 1e-6:
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if excess(mid) < top else (lo, mid)
            angles = np.abs(fold_design(design, hi).fold_angles[creases])
            edges = tuple(int(e) for e in creases[angles >= math.degrees(top) - 1e-3])
            limits.append(FoldLimit(lo, "eq6", edges))
    if not limits:
        return FoldLimit(1.0, "folder")
    return min(limits, key=lambda lim: lim.p)


def _place(route: RouteSpec, cp, coords: np.ndarray) -> tuple[np.ndarray, str]:
    flat = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    if route.fixed_panel is None:
        return mean_pose(coords, flat), "the sheet keeps its mean pose (free on the ring)"
    ring = cp.faces[cp.face_index(route.fixed_panel)]
    out = np.empty_like(coords)
    for k, c in enumerate(coords):
        rot, shift = rigid_fit(c[ring], flat[ring])
        out[k] = c @ rot.T + shift
    return out, f"panel {route.fixed_panel} is held"


def turn_limit_stop(route: RouteSpec) -> tuple[StopReason, str]:
    """Why the TSA stops at its last angle: its turn limit or, onboard, its strands'
    maximum helix angle (whichever of ``route.max_turns`` and ``tsa.max_theta()`` is
    smaller); the stop and its sentence.
    """
    if route.tsa.max_theta() < route.max_turns * 2 * math.pi:
        return StopReason.HELIX_LIMIT, "the TSA's strands reached their maximum helix angle"
    return StopReason.TURN_LIMIT, f"the TSA reached its turn limit ({route.max_turns:g} turns)"


def time_limit_stop(limit: float, thetas: list[float]) -> tuple[StopReason, str]:
    """The stop when a folding has used its ``limit`` seconds of wall-clock time, after the
    TSA angles ``thetas`` (rad, one per state so far); the stop and its sentence."""
    turns = thetas[-1] / (2.0 * math.pi)
    return StopReason.TIME_LIMIT, (
        f"the time limit of {limit:g} s ran out after {len(thetas)} states and {turns:.2f} "
        "TSA turns (--time-limit: a longer one folds further)"
    )


def torque_limit_reason(route: RouteSpec, torque: float) -> str | None:
    """The sentence of a stop when the TSA's ``torque`` (N mm) passes the route's
    ``max_torque``, else None.
    """
    if torque > route.max_torque:
        return (
            f"the TSA torque {torque:.3g} N mm exceeds the route's max_torque of "
            f"{route.max_torque:g} N mm"
        )
    return None


@checked(
    SimulationError,
    design=Arg("object", types=(Design,), optional=False),
    route=Arg("object", types=(RouteSpec,), optional=False),
    hole_friction=Arg(min=0.0, max=10.0, optional=False),
    grid=Arg("int", min=2, max=100_000),
    crease_stiffness=Arg(min=0.0, max=1e9),
    max_dp=Arg(min=MIN_DP, max=1.0, optional=False),
    string_stiffness=Arg(min=0.0, open_min=True, max=1e12),
)
def simulate_dcqc(
    design: Design,
    route: RouteSpec,
    grid: int | None = None,
    crease_stiffness: float | None = None,
    max_dp: float = 0.01,
    string_stiffness: float | None = None,
    hole_friction: float = 0.0,
) -> DCQCResult:
    """Simulate the folding that the route's strings and TSA produce, state by state.

    Parameters
    ----------
    design : Design
        A pattern the kinematics folds with one parameter.
    route : RouteSpec
        TSA, strings and settings (take-up per step, max turns, ``p0``, fold limit).
    grid : int, optional
        Fold ratios sampled between ``p0`` and the fold limit, where the exact
        geometry is evaluated; lengths in between are interpolated linearly
        (default 801 for TG tessellations, 201 for the degree-4 folder).
    crease_stiffness : float, optional
        Rotational stiffness of the creases per unit length, N mm / rad / mm
        (e.g. ``SimulationParams.crease_stiffness``); gives tensions and torque.
    max_dp : float
        Largest change of the fold ratio between two states, in [:data:`MIN_DP`, 1]; a
        TSA step that folds more is halved.
    string_stiffness : float, optional
        Axial stiffness ``EA`` of the strings, N (e.g.
        ``SimulationParams.string_axial_stiffness``). With ``crease_stiffness`` the
        strings are elastic (:func:`_elastic_successor`): each state is the nearest
        equilibrium of the creases' and the strings' energy along the rigid folding,
        the same energy as the bar-and-hinge simulation's with rigid panels.
        Without it the strings are inextensible.
    hole_friction : float
        Friction coefficient in the holes (capstan law; 0: none); needs elastic strings.
    """
    if not (math.isfinite(hole_friction) and hole_friction >= 0) or (
        hole_friction > 0 and string_stiffness is None
    ):
        raise SimulationError(f"simulate_dcqc: hole_friction {hole_friction} needs >= 0 and EA")
    if string_stiffness is not None and (crease_stiffness is None or not string_stiffness > 0):
        raise SimulationError(
            "simulate_dcqc: elastic strings need a positive string_stiffness (EA, N) and the "
            f"creases' crease_stiffness too (got {string_stiffness!r}, {crease_stiffness!r})"
        )
    t = _tables(design, route, grid, crease_stiffness, string_stiffness, hole_friction)
    rows: dict[str, list] = {k: [] for k in _ROWS}
    _record(t, route, rows, 0.0, route.p0, False)
    theta_end = min(route.max_turns * 2 * math.pi, route.tsa.max_theta())
    theta, p = 0.0, float(route.p0)
    stop, reason, jam = None, "", None
    while stop is None:
        if theta >= theta_end - 1e-12:
            stop, reason = turn_limit_stop(route)
            break
        theta, p, stop, reason, jam = _dcqc_step(design, route, t, rows, theta, p, max_dp)
        if t.energy_rate is not None and stop is None:
            stop, reason = _load_stop(route, rows)
    return _dcqc_result(design, route, t, rows, p, stop, reason, jam)


_ROWS = ("theta", "p", "taut", "tension", "torque", "rs", "ta")  # the columns of a DCQC state


@dataclass
class _Tables:
    """What :func:`simulate_dcqc` evaluates once, on a grid of fold ratios.

    ``ratios`` (G,); ``x_dis`` (strings, G) and ``rest`` (strings, G): each string's
    length between the TSA's ends and the rest of its route, mm; ``l0`` (strings,)
    the string lengths, mm; ``angles`` (A, m) rad at ``angle_ratios`` (A,);
    ``energy_rate`` the creases' energy per fold ratio at ``angle_ratios`` (N mm,
    None without a crease stiffness); ``tol`` the slack taken as taut, mm;
    ``k`` (strings,) the strings' stiffness ``EA / L_0``, N/mm (None: inextensible);
    ``dx_dis`` and ``drest`` (strings, G) the derivatives of ``x_dis`` and ``rest``
    by the fold ratio, mm.
    """

    limit: FoldLimit
    ratios: np.ndarray
    x_dis: np.ndarray
    rest: np.ndarray
    l0: np.ndarray
    angles: np.ndarray
    angle_ratios: np.ndarray
    energy_rate: np.ndarray | None
    placement: str
    tol: float
    k: np.ndarray | None = None
    dx_dis: np.ndarray | None = None
    drest: np.ndarray | None = None
    stacked: np.ndarray | None = None  # x_dis, rest, dx_dis, drest stacked (4 k, G)

    def at(self, p: float, table: np.ndarray) -> np.ndarray:
        """Each row of ``table`` (k, G) interpolated at fold ratio ``p``, (k,)."""
        return np.array([np.interp(p, self.ratios, row) for row in table])


def _tables(design: Design, route: RouteSpec, grid, crease_stiffness, ks=None, mu=0.0) -> _Tables:
    """The geometry of the route on ``grid`` fold ratios from ``p0`` to the fold limit."""
    cp = design.pattern
    limit = fold_limit(design, route)
    if grid is None:
        grid = 801 if design.tg is not None else 201
    ratios = np.linspace(route.p0, limit.p, grid)
    if design.tg is not None:
        raw = fold_coords(design, ratios)
        sub = np.linspace(0, grid - 1, min(grid, 201)).round().astype(int)
        angles = _angle_table(design, ratios[sub], raw[sub])
        angle_ratios = ratios[sub]
    else:
        states = fold_sequence(design, ratios)
        raw = np.stack([s.coords for s in states])
        angles = np.radians(np.stack([s.fold_angles for s in states]))
        angle_ratios = ratios
    coords, placement = _place(route, cp, raw)
    frames = [hole_frames(cp, s) for s in route.strings]
    segs = [
        segment_lengths(cp, coords, s, route.thickness, f)
        for s, f in zip(route.strings, frames, strict=True)
    ]  # each (G, k_i)
    through = np.array(
        [route.thickness * float(np.sum(np.diff(s.sides) != 0)) for s in route.strings]
    )
    x_dis = np.stack([s[:, 0] for s in segs])  # (strings, G)
    rest = np.stack([s[:, 1:].sum(axis=1) for s in segs]) + through[:, None]
    l0 = route.tsa.consumed(0.0, x_dis[:, 0]) + rest[:, 0]
    energy_rate = None
    if crease_stiffness is not None:
        lengths = np.linalg.norm(np.diff(cp.vertices[cp.edges], axis=1)[:, 0], axis=1)
        k = crease_stiffness * lengths * cp.edge_mask("M", "V")
        energy = 0.5 * (angles**2 * k).sum(axis=1)
        energy_rate = np.gradient(energy, angle_ratios) if len(angle_ratios) > 1 else energy * 0
    tol = 1e-7 * max(cp.size, 1.0)
    t = _Tables(limit, ratios, x_dis, rest, l0, angles, angle_ratios, energy_rate, placement, tol)
    if energy_rate is not None and ks is not None and len(ratios) > 1:
        t.k = float(ks) / l0
        t.dx_dis = np.gradient(x_dis, ratios, axis=1)
        t.drest = np.gradient(rest, ratios, axis=1)
        if mu > 0:  # friction at the holes: the segments pull by their capstan weights
            t.drest = capstan_rate(cp, coords, route, frames, segs, ratios, mu)
    return t


def _record(t: _Tables, route: RouteSpec, rows: dict[str, list], theta, p, moving) -> None:
    """Append the state at TSA angle ``theta`` (rad) and fold ratio ``p`` to ``rows``.

    ``moving``: the sheet folds at this state (its taut strings pull); the tensions
    (N) balance the creases' energy rate against the string the fold saves.
    """
    tsa = route.tsa
    xd, rs = t.at(p, t.x_dis), t.at(p, t.rest)
    length, rate, _, _ = tsa.consumed_derivatives(theta, xd)
    g = length + rs - t.l0
    taut = (g >= -t.tol) & moving
    tension = np.full(len(t.l0), np.nan)
    torque = math.nan
    if t.k is not None:  # elastic strings: the tension is the stiffness times the stretch
        taut = g > t.tol
        tension = t.k * np.maximum(g, 0.0)
        torque = float(np.sum(tension * rate))
    elif t.energy_rate is not None:
        tension[:] = 0.0
        if taut.any():
            dp = 1e-4 * (t.limit.p - route.p0)
            lo, hi = max(p - dp, route.p0), min(p + dp, t.limit.p)
            dg = (
                tsa.consumed(theta, t.at(hi, t.x_dis))
                + t.at(hi, t.rest)
                - tsa.consumed(theta, t.at(lo, t.x_dis))
                - t.at(lo, t.rest)
            ) / (hi - lo)
            saved = -float(np.sum(dg[taut]))
            work = float(np.interp(p, t.angle_ratios, t.energy_rate))
            if saved > 0:
                tension[taut] = max(work, 0.0) / saved
        torque = float(np.sum(tension * rate))
    for key, value in zip(
        rows, (theta, p, taut, tension, torque, rs, np.asarray(length)), strict=True
    ):
        rows[key].append(value)


def _dcqc_step(design, route, t: _Tables, rows, theta: float, p: float, max_dp: float):
    """One TSA step from ``(theta, p)``, halved while it folds by more than ``max_dp``.

    Records the new state; returns ``(theta, p, stop, reason, jam)``, ``stop`` None
    when the folding goes on.
    """
    tsa = route.tsa
    theta_end = min(route.max_turns * 2 * math.pi, tsa.max_theta())
    dtheta = tsa_step(
        tsa, theta, t.at(p, t.x_dis), route.take_up, min(route.step, theta_end - theta)
    )
    for _ in range(30):
        new = theta + dtheta
        if t.k is not None:
            outcome = _elastic_successor(tsa, new, p, t)
        else:
            outcome = _advance(tsa, new, p, t.ratios, t.x_dis, t.rest, t.l0)
        if outcome[0] != "fold" or abs(outcome[1] - p) <= max_dp or dtheta < 1e-9:
            break
        dtheta *= 0.5
    kind, value = outcome[0], outcome[1]
    if kind == "fit":
        _record(t, route, rows, new, p, False)
        return new, p, None, "", None
    if kind == "fold":
        _record(t, route, rows, new, value, True)
        return new, value, None, "", None
    if kind == "limit":
        lo = _limit_angle(tsa, t, theta, new)
        if t.limit.p > p:
            theta, p = lo, float(t.limit.p)
            _record(t, route, rows, theta, p, True)
        return theta, p, StopReason.FOLD_LIMIT, f"fold limit reached: {t.limit.describe()}", None
    string, stretch, p_jam = value  # jam
    if t.k is not None:  # the elastic state where a string stretches instead: recorded
        theta, p = new, p_jam
        _record(t, route, rows, theta, p, True)
    segment = _lengthening_segment(design, route, string, p, t.limit.p)
    jam = Jam(string, segment, p, stretch, elastic=t.k is not None)
    return theta, p, StopReason.JAM, jam.describe(), jam


def _limit_angle(tsa, t: _Tables, theta: float, new: float) -> float:
    """The TSA angle (rad) in ``[theta, new]`` at which the sheet reaches the fold limit.

    Inextensible strings: where they fit exactly at the limit; elastic ones: where the
    equilibrium sits exactly at the limit (:func:`_strings_force` zero there).
    """
    lo, hi = theta, new
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if t.k is not None:
            beyond = _strings_force(tsa, mid, np.array([t.limit.p]), t)[0][0] < 0
        else:
            beyond = np.max(tsa.consumed(mid, t.x_dis[:, -1]) + t.rest[:, -1] - t.l0) > 0
        lo, hi = (lo, mid) if beyond else (mid, hi)
    return hi if t.k is not None else lo


def _load_stop(route: RouteSpec, rows: dict[str, list]) -> tuple[StopReason | None, str]:
    """A string's tension over the route's ``max_tension`` or the torque over its
    ``max_torque`` at the last state: the stop and its sentence, else ``(None, "")``.
    """
    if np.nanmax(rows["tension"][-1], initial=0.0) > route.max_tension:
        return StopReason.TENSION_LIMIT, (
            f"a string's tension {np.nanmax(rows['tension'][-1]):.3g} N exceeds the "
            f"route's max_tension of {route.max_tension:g} N"
        )
    reason = torque_limit_reason(route, rows["torque"][-1])
    return (None, "") if reason is None else (StopReason.TORQUE_LIMIT, reason)


def _dcqc_result(design, route, t: _Tables, rows, p, stop, reason, jam) -> DCQCResult:
    """The states as NumPy columns, the final shape and strings, and the cutting checks."""
    cp = design.pattern
    p_states = np.array(rows["p"])
    result = DCQCResult(
        theta=np.array(rows["theta"]),
        p=p_states,
        taut=np.array(rows["taut"], dtype=bool),
        tensions=np.array(rows["tension"]),
        torque=np.array(rows["torque"]),
        routed_length=np.array(rows["rs"]),
        tsa_length=np.array(rows["ta"]),
        fold_angles=np.degrees(
            np.column_stack([np.interp(p_states, t.angle_ratios, col) for col in t.angles.T])
        ).reshape(len(p_states), -1),
        stop=stop,
        reason=reason,
        limit=t.limit,
        jam=jam,
        valid=not (stop is StopReason.JAM and p <= route.p0),
        initial_length_mm=t.l0.tolist(),
        violations=route.violations,
        placement=t.placement,
    )
    if not result.valid:
        result.reason = "the routing never folds the structure: " + result.reason
    final = _place(route, cp, fold_coords(design, [p]))[0][0]
    result.final_coords = final
    result.final_strings = [string_path(cp, final, s, route.thickness) for s in route.strings]
    seen: set[str] = set()
    checks = np.linspace(route.p0, p, 6)
    for q, c in zip(checks, _place(route, cp, fold_coords(design, checks))[0], strict=True):
        for i, s in enumerate(route.strings):
            for msg in cutting_segments(cp, c, s, route.thickness, i):
                if msg not in seen:
                    seen.add(msg)
                    result.cutting.append(f"{msg} (from p = {q:.3f})")
    return result


def _strings_force(tsa, theta: float, q: np.ndarray, t: _Tables):
    """The generalised force along the rigid folding with elastic strings, at ratios ``q``.

    ``f(q) = dE/dp``: the creases' energy rate plus each string's tension ``k_i
    max(g_i, 0)`` times the rate ``dg_i/dp`` of its demand ``g_i`` (its length with the
    TSA's share at ``theta`` rad, less ``L_0``; mm), N mm per unit fold ratio; negative
    where the strings fold the sheet further. Returns ``(f (Q,), g (k, Q), dg/dp (k, Q))``.
    """
    q = np.atleast_1d(np.asarray(q, dtype=float))
    if t.stacked is None:
        t.stacked = np.vstack([t.x_dis, t.rest, t.dx_dis, t.drest])
    j = np.clip(np.searchsorted(t.ratios, q, side="right"), 1, len(t.ratios) - 1)
    w = np.clip((q - t.ratios[j - 1]) / (t.ratios[j] - t.ratios[j - 1]), 0.0, 1.0)
    rows = t.stacked[:, j - 1] * (1.0 - w) + t.stacked[:, j] * w  # linear, as np.interp
    xd, rs, dxd, drs = np.split(rows, 4)
    length, _, per_x, _ = tsa.consumed_derivatives(theta, xd)
    g = length + rs - t.l0[:, None]
    dg = per_x * dxd + drs
    f = np.interp(q, t.angle_ratios, t.energy_rate) + np.sum(
        t.k[:, None] * np.maximum(g, 0.0) * dg, axis=0
    )
    return f, g, dg


def _elastic_successor(tsa, theta: float, p: float, t: _Tables) -> tuple[str, Any]:
    """Where the sheet goes from fold ratio ``p`` with elastic strings, the TSA at ``theta``.

    The sheet moves along the rigid folding, downhill in the energy (creases plus
    strings, :func:`_strings_force`), to the *first* equilibrium it meets: the
    continuous successor of the previous state. ``("fold", p_new)``;
    ``("limit", None)`` when it would fold past the fold limit; ``("jam", (string,
    stretch mm, p_new))`` when at ``p_new`` a taut string's demand rises as the sheet
    folds (the DCQC rule broken: it stretches instead of folding the sheet) or its
    strain passes :data:`MAX_STRING_STRAIN`.
    """
    f_p = float(_strings_force(tsa, theta, np.array([p]), t)[0][0])
    start = int(np.searchsorted(t.ratios, p, side="right"))
    up = f_p < 0
    nodes = t.ratios[start:] if up else t.ratios[: max(start - 1, 0)][::-1]
    nodes = nodes[nodes != p]
    f_nodes = _strings_force(tsa, theta, nodes, t)[0] if len(nodes) else np.zeros(0)
    crossed = np.flatnonzero(f_nodes >= 0 if up else f_nodes <= 0)
    if not len(crossed):
        if up:
            return "limit", None
        q = float(t.ratios[0])
    else:
        j = int(crossed[0])
        lo, hi = (p if j == 0 else float(nodes[j - 1])), float(nodes[j])
        f_lo = f_p if j == 0 else float(f_nodes[j - 1])
        q = _root(
            lambda v: float(_strings_force(tsa, theta, np.array([v]), t)[0][0]),
            lo,
            hi,
            f_lo,
            float(f_nodes[j]),
        )
    _, g, dg = _strings_force(tsa, theta, np.array([q]), t)
    g, dg = g[:, 0], dg[:, 0]
    taut = g > t.tol
    bad = taut & (
        (dg > 1e-6 * max(1.0, float(np.max(np.abs(dg))))) | (g / t.l0 > MAX_STRING_STRAIN)
    )
    if bad.any():
        string = int(np.argmax(np.where(bad, g, -np.inf)))
        return "jam", (string, float(g[string]), q)
    return "fold", q


def _root(f, a: float, b: float, fa: float, fb: float, tol: float = 1e-12) -> float:
    """A root of ``f`` between ``a`` and ``b``, where it changes sign (``fa``, ``fb``):
    regula falsi with the Illinois rule, falling back to bisection, to ``tol``.
    """
    side = 0
    for _ in range(100):
        if fb == fa:
            c = 0.5 * (a + b)
        else:
            c = b - fb * (b - a) / (fb - fa)
            if not min(a, b) < c < max(a, b):
                c = 0.5 * (a + b)
        fc = f(c)
        if fc == 0 or abs(b - a) < tol:
            return c
        if (fc > 0) == (fb > 0):
            b, fb = c, fc
            if side == -1:
                fa *= 0.5
            side = -1
        else:
            a, fa = c, fc
            if side == 1:
                fb *= 0.5
            side = 1
    return c


def _advance(tsa, theta, p, ratios, x_dis, rest, l0) -> tuple[str, Any]:
    """Where the sheet goes from fold ratio ``p`` when the TSA is at ``theta``.

    ``("fit", p)``: every string still fits; ``("fold", p_new)``: the sheet folds
    continuously to ``p_new``, the worst demand falling all the way; ``("limit",
    None)``: it would fold past the fold limit; ``("jam", (string, stretch))``:
    the binding string's demand rises as the sheet folds.
    """
    start = int(np.searchsorted(ratios, p, side="right"))
    g_p = (
        tsa.consumed(theta, np.array([np.interp(p, ratios, r) for r in x_dis]))
        + np.array([np.interp(p, ratios, r) for r in rest])
        - l0
    )
    w_p = float(np.max(g_p))
    if w_p <= 0:
        return "fit", p
    g = tsa.consumed(theta, x_dis[:, start:]) + rest[:, start:] - l0[:, None]
    worst = np.r_[w_p, g.max(axis=0)]
    below = np.flatnonzero(worst <= 0)
    end = int(below[0]) if len(below) else len(worst) - 1
    rises = np.flatnonzero(np.diff(worst[: end + 1]) > 1e-9 * max(1.0, abs(w_p)))
    if len(rises):
        k = int(rises[0])
        string = int(np.argmax(g[:, k]))  # the string that makes the worst demand rise
        return "jam", (string, float(np.max(worst[k : end + 1])), p)
    if not len(below):
        return "limit", None
    lo = p if end == 1 else float(ratios[start + end - 2])
    w_lo = float(worst[end - 1])
    return "fold", lo + (0.0 - w_lo) / (worst[end] - w_lo) * (ratios[start + end - 1] - lo)


def _lengthening_segment(design: Design, route: RouteSpec, string: int, p: float, p_lim: float):
    """The segment of ``string`` that breaks the DCQC rule, else the one lengthening most.

    Lengthening most as the sheet folds on from ``p`` (rigidly, in the model's placement).
    """
    cp = design.pattern
    s = route.strings[string]
    if s.bad_segments:
        return segment_names(s)[s.bad_segments[0]]
    dp = min(1e-3, max(p_lim - p, 1e-6))
    lo, hi = max(p - dp, 0.0), min(p + dp, p_lim)
    if hi <= lo:
        lo = max(lo - dp, 0.0)
    coords, _ = _place(route, cp, fold_coords(design, [lo, hi]))
    lengths = segment_lengths(cp, coords, s, route.thickness)
    return segment_names(s)[int(np.argmax(lengths[1] - lengths[0]))]
