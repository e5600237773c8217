"""CMA-ES search for a legged robot's gait: forward per cycle over frictions.

Genome
------
A wave gait of four strokes in one cycle (the hand gait's order, docs/crawler.md): the
front legs fold from ``p_low`` to ``p_high``, then the rear legs, then the front legs
unfold, then the rear legs; each stroke is followed by a dwell. Every variable is
normalised to [0, 1] (``cma`` bounds, :class:`~origami_cad.design.search.UnitBox`):

====  =====================================================================
 0-1  front legs: ``p_low`` in [``P_FLOOR``, ``LOW_TOP``], ``p_high`` in
      [``p_low + MIN_STROKE``, blocker / 180]
 2-3  rear legs: the same
 4-5  left-right trim of the front and of the rear strokes' top, +-``TRIM``
      (a left leg folds ``trim`` more, its right twin ``trim`` less: it steers)
 6-9  the four dwells, each 0 .. ``MAX_DWELL`` of the cycle
====  =====================================================================

The strokes share what the dwells leave of the cycle in proportion to the TSA turns
they need, so every servo turns at the same rate; a stroke's start time is its phase
offset in the cycle. The simulator is quasi-static: a dwell changes no pose, so dwells
and stroke times matter through the servo's speed limit (and the time a real robot
has to settle), not through the simulated stride.

Every gait the genome decodes to is within the blockers (``p_high`` <= blocker / 180)
and the legs' floor (``P_FLOOR``: the strings need a bent leg to pick the mountain
branch, docs/crawler.md); the servo's speed, its stall torque and the strings' tension
limit are checked on each simulated candidate and a candidate past any of them is
penalised (:class:`GaitLimits`), so the search ends inside them.

Objective
---------
For every friction of ``settings.frictions`` the gait is simulated as ``crawl`` does
(:func:`origami_cad.crawler.walk.simulate_gait`, free on the ground), and scored

``score = forward - w_drift |drift| - w_yaw |yaw| - w_slip slip - w_limit hits - w_jam jam``

(mm per cycle; drift sideways, mm; yaw of the body, deg; slip: the feet's backward
travel, mm; hits: limits passed; jam: deg by which the legs that jammed, more than
``STUCK_DEG`` past their command, stayed past it). The candidate's score combines its
scores over the frictions: their mean (``mix = "mean"``, the default), their worst
(``"worst"``), the average of the two (``"worst+mean"``), or the worst shortfall against
per-friction targets (``"shortfall"``: the smallest ``score - target`` over the
frictions, ``GaitSettings.targets``; by default 45 / 63 / 45 mm per cycle at
0.4 / 0.6 / 0.8, ``DEFAULT_TARGETS``). Scores are rounded
to ``SCORE_RESOLUTION`` before CMA-ES ranks them, and the eigen-decomposition is
``canonical_eigh``, so a search is the same on any CPU up to its simulations' last bits.

The robot file's own gait is scored first and kept as a candidate, and run 0 starts
CMA-ES from its nearest genome (:func:`encode_gait`): the best returned never scores
below it (when it is within the limits).

Units: mm, deg, s, N, N mm at the edges; fold ratios ``p = fold angle / 180 deg``.
"""

from __future__ import annotations

import concurrent.futures as cf
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import cma
import numpy as np

from origami_cad._libm import canonical_eigh
from origami_cad.crawler.robot import Robot, with_gait
from origami_cad.crawler.walk import (
    SERVO_SPEED_RPM,
    STUCK_DEG,
    GaitResult,
    gait_turns,
    simulate_gait,
    turn_rates,
)
from origami_cad.design.search import UnitBox
from origami_cad.errors import DesignError, SimulationError
from origami_cad.parallel import local_pool

__all__ = [
    "DEFAULT_TARGETS",
    "DIMENSION",
    "FAILED",
    "MIXES",
    "P_FLOOR",
    "SCORE_RESOLUTION",
    "GaitCandidate",
    "GaitDesign",
    "GaitLimits",
    "GaitSettings",
    "GaitTerms",
    "cma_strategy",
    "combine_terms",
    "decode_gait",
    "design_gait",
    "encode_gait",
    "evaluate_gait",
    "gait_terms",
    "hard_hits",
    "settings_score",
    "stride_limits",
]

#: Smallest fold ratio of a leg (20 deg): below it the strings under a flat hinge cannot
#: tell a mountain from a valley (docs/crawler.md, "Never flat").
P_FLOOR = 0.111
#: Largest ``p_low`` (45 deg) and the smallest stroke ``p_high - p_low`` (5.4 deg).
LOW_TOP, MIN_STROKE = 0.25, 0.03
#: Left-right trim of a stroke's top, fold ratio (+-5.4 deg).
TRIM = 0.03
#: Largest dwell after a stroke, share of the cycle.
MAX_DWELL = 0.15
#: Variables of the genome.
DIMENSION = 10
#: Scores are rounded to this (mm) before CMA-ES ranks them.
SCORE_RESOLUTION = 1e-3
#: Score of a candidate whose simulation failed, mm.
FAILED = -1e3
#: The default targets, mm per cycle by friction: the paper's 63 mm at 0.6 (PVC mat), and
#: 45 mm on a slipperier (0.4) and a grippier (0.8) ground; the ``"shortfall"`` mix's
#: default.
DEFAULT_TARGETS = {0.4: 45.0, 0.6: 63.0, 0.8: 45.0}


@dataclass(frozen=True)
class GaitLimits:
    """The limits a gait must stay within (every one named when passed).

    Attributes
    ----------
    servo_rpm : float
        The servo's no-load speed, rev/min (XL330-M288 at 5 V: 103).
    stall_torque : float
        The servo's stall torque, N mm (XL330-M288 at 5 V: 520).
    max_tension : float
        The strings' tension limit, N (the routes' ``max_tension`` when they set one).
    """

    servo_rpm: float = SERVO_SPEED_RPM
    stall_torque: float = 520.0
    max_tension: float = 50.0

    @classmethod
    def of(cls, robot: Robot, **given: float) -> GaitLimits:
        """The limits of ``robot``: its routes' ``max_tension``/``max_torque`` when finite."""
        tension = min(leg.route.max_tension for leg in robot.legs)
        torque = min(leg.route.max_torque for leg in robot.legs)
        base = {"max_tension": tension, "stall_torque": torque}
        base = {k: v for k, v in base.items() if math.isfinite(v)}
        return cls(**{**base, **given})


@dataclass(frozen=True)
class GaitSettings:
    """How the gait is searched and scored.

    Attributes
    ----------
    frictions : tuple of float
        Coulomb coefficients each candidate is simulated at.
    mix : {"mean", "worst", "worst+mean", "shortfall"}
        How the frictions' scores combine (``MIXES``): their mean (the default: the
        worst case trades most of the stride at 0.4-0.6 for the friction the robot walks
        worst at, docs/crawler.md), the worst, the average of the two, or the worst
        shortfall ``min(score - target)`` against ``targets``.
    targets : tuple of float or None
        The ``"shortfall"`` mix's target per friction, mm per cycle, one per friction;
        ``None``: ``DEFAULT_TARGETS``' value at each friction (45 / 63 / 45 mm at 0.4 / 0.6
        / 0.8). Raises :class:`DesignError` (one line) when its count differs from the
        frictions', when given with another mix (it would be ignored), or when ``None``
        and a friction has no default target.
    cycle : float
        Gait cycle, s.
    runs, popsize, generations, seed : int
        Independent CMA-ES runs (run ``k`` seeded ``seed + k``), population, generations.
    sigma0 : float
        CMA-ES's first step (genome units).
    steps, cycles : int
        Quasi-static steps between keyframes, cycles simulated per candidate.
    w_drift, w_yaw, w_slip, w_limit, w_jam : float
        Penalty weights (mm of score): per mm of drift, deg of yaw, mm of foot slip,
        limit passed (servo speed, stall torque, string tension), and deg a jammed leg
        stays past its command.
    """

    frictions: tuple[float, ...] = (0.4, 0.6, 0.8)
    mix: str = "mean"
    targets: tuple[float, ...] | None = None
    cycle: float = 32.0
    runs: int = 1
    popsize: int = 8
    generations: int = 6
    seed: int = 0
    sigma0: float = 0.2
    steps: int = 3
    cycles: int = 1
    w_drift: float = 2.0
    w_yaw: float = 1.0
    w_slip: float = 0.05
    w_limit: float = 100.0
    w_jam: float = 0.2
    limits: GaitLimits = field(default_factory=GaitLimits)

    def __post_init__(self) -> None:
        if self.mix not in MIXES:
            raise DesignError(f"mix {self.mix!r} is not one of {', '.join(MIXES)}")
        if self.targets is not None and len(self.targets) != len(self.frictions):
            raise DesignError(
                f"{len(self.targets)} targets for {len(self.frictions)} frictions: "
                "give one target (mm per cycle) per friction"
            )
        if self.targets is not None and self.mix != "shortfall":
            raise DesignError(
                f"targets are scored by the 'shortfall' mix only, and the mix is {self.mix!r}:"
                " give mix 'shortfall' with them, or no targets"
            )
        if self.mix == "shortfall":
            self.target_values()  # refuse a friction without a target now, not mid-search

    def target_values(self) -> tuple[float, ...]:
        """The target per friction, mm per cycle: ``targets``, or ``DEFAULT_TARGETS``'."""
        if self.targets is not None:
            return tuple(float(t) for t in self.targets)
        missing = [f for f in self.frictions if round(f, 6) not in DEFAULT_TARGETS]
        if missing:
            raise DesignError(
                f"no target at friction {missing[0]:g} (the default targets are at "
                f"{', '.join(f'{f:g}' for f in DEFAULT_TARGETS)}): give targets"
            )
        return tuple(DEFAULT_TARGETS[round(f, 6)] for f in self.frictions)


def _stroke_top(low: float, u: float, p_max: float) -> float:
    return low + MIN_STROKE + u * max(0.0, p_max - low - MIN_STROKE)


def decode_gait(robot: Robot, x, cycle: float = 32.0) -> tuple[np.ndarray, np.ndarray]:
    """A genome ``x (DIMENSION,)`` in [0, 1] as keyframes: times (K,) s, fold ratios (K, legs).

    Legs are the robot's, front and rear, left and right of the body panel's centre by
    their panel's centre; the keyframes start and end with every leg at its ``p_low``
    and span ``cycle`` s. Times are rounded to 0.01 s and fold ratios to 1e-5, as
    ``gait.toml`` writes them.
    """
    x = np.clip(np.asarray(x, dtype=float), 0.0, 1.0)
    p_max = robot.blocker_angle / 180.0
    low = [P_FLOOR + x[i] * (LOW_TOP - P_FLOOR) for i in (0, 2)]
    top = [_stroke_top(low[g], x[1 + 2 * g], p_max) for g in (0, 1)]
    trim = [(x[4 + g] - 0.5) * 2 * TRIM for g in (0, 1)]
    group, side = _leg_groups(robot)
    lows = np.array([low[g] for g in group])
    highs = np.array([top[g] + s * trim[g] for g, s in zip(group, side, strict=True)])
    highs = np.clip(highs, lows + MIN_STROKE / 2, p_max)  # the genome's range, not a limit
    poses = [lows.copy()]
    for stroke in range(4):  # front folds, rear folds, front unfolds, rear unfolds
        now = poses[-1].copy()
        mine = np.asarray(group) == stroke % 2
        now[mine] = (highs if stroke < 2 else lows)[mine]
        poses.append(now)
    return _keyframes(robot, np.array(poses), x[6:10] * MAX_DWELL * cycle, cycle)


def _leg_groups(robot: Robot) -> tuple[list[int], list[float]]:
    """Each leg's group (0 front, 1 rear) and side (+1 left, -1 right), by its panel centre."""
    cp = robot.pattern
    centres = [cp.vertices[cp.faces[leg.face]].mean(axis=0) for leg in robot.legs]
    body = cp.vertices[cp.faces[cp.face_index(robot.body)]].mean(axis=0)
    group = [0 if c[0] >= body[0] else 1 for c in centres]
    side = [1.0 if c[1] >= body[1] else -1.0 for c in centres]
    return group, side


def _held_range(moving: np.ndarray, p: np.ndarray, others: np.ndarray) -> tuple[float, float]:
    """The lowest and highest fold ratio a leg pair holds still while the other pair
    strokes (its ``p_low`` and ``p_high`` in a wave gait); its whole range if it never does."""
    held = p[~moving & others]
    held = held if held.size else p
    return float(held.min()), float(held.max())


def encode_gait(robot: Robot) -> np.ndarray:
    """The genome (DIMENSION,) in [0, 1] nearest to ``robot``'s own gait: where a search starts.

    Each leg pair's ``p_low`` and ``p_high`` are the fold ratios it holds still while the
    other pair strokes (the hand gait of examples/crawler/crawler.toml: 30 and 55 deg; its
    rest at 20 deg before and after the strokes is not part of the wave), its trim is half
    the difference of its left and right legs' top, and each dwell is an equal share of
    the time no leg moves. A gait the genome cannot express (another stroke order, more
    strokes) gets the genome of the same fold ranges; values are clipped to [0, 1].
    """
    times = np.linspace(robot.gait_t[0], robot.gait_t[-1], 641)
    p = np.stack([np.interp(times, robot.gait_t, col) for col in robot.gait_p.T], axis=1)
    group, side = _leg_groups(robot)
    group, side = np.asarray(group), np.asarray(side)
    moving = np.abs(np.gradient(p, times, axis=0)) > 1e-6  # (samples, legs)
    pair = [moving[:, group == g].any(axis=1) for g in (0, 1)]
    p_max, x = robot.blocker_angle / 180.0, np.zeros(DIMENSION)
    for g in (0, 1):
        mean = p[:, group == g].mean(axis=1)
        low, high = _held_range(pair[g], mean, pair[1 - g])
        low = min(max(low, P_FLOOR), LOW_TOP)
        x[2 * g] = (low - P_FLOOR) / (LOW_TOP - P_FLOOR)
        x[2 * g + 1] = (high - low - MIN_STROKE) / max(p_max - low - MIN_STROKE, 1e-9)
        tops = [p[:, (group == g) & (side == s)].max(initial=high) for s in (1.0, -1.0)]
        x[4 + g] = 0.5 + (tops[0] - tops[1]) / 2 / (2 * TRIM)
    still = float(np.mean(~moving.any(axis=1))) * (times[-1] - times[0])
    x[6:10] = still / 4 / (MAX_DWELL * (times[-1] - times[0]))
    return np.clip(x, 0.0, 1.0)


#: A dwell shorter than this (s) is no keyframe of its own: its stroke takes its time.
MIN_DWELL_S = 0.5


def _keyframes(robot: Robot, poses: np.ndarray, dwells: np.ndarray, cycle: float):
    """Times (K,) s and fold ratios (K, legs) of five poses joined by strokes and dwells
    (s): the strokes share what the dwells leave of the cycle in proportion to their turns."""
    turns = gait_turns(robot, poses)
    need = np.abs(np.diff(turns, axis=0)).max(axis=1) + 1e-6
    strokes = need / need.sum() * (cycle - dwells.sum())
    times, rows = [0.0], [poses[0]]
    for k in range(4):
        if dwells[k] >= MIN_DWELL_S:
            times += [times[-1] + strokes[k], times[-1] + strokes[k] + dwells[k]]
            rows += [poses[k + 1], poses[k + 1]]
        else:
            times.append(times[-1] + strokes[k] + dwells[k])
            rows.append(poses[k + 1])
    times[-1] = cycle
    # as gait.toml writes them (6 significant digits): crawl --gait walks the same gait
    top = math.floor(robot.blocker_angle / 180.0 * 1e5) / 1e5  # never past the blocker
    return np.round(np.array(times), 2), np.minimum(np.round(np.array(rows), 5), top)


@dataclass(frozen=True)
class GaitTerms:
    """One simulated gait at one friction: the objective's terms, per cycle.

    Attributes
    ----------
    friction : float
        Coulomb coefficient.
    forward, drift, slip : float
        Body's forward displacement, sideways drift (signed) and the feet's backward
        travel, mm per cycle.
    yaw : float
        Body's turn about the vertical, deg per cycle (signed, counter-clockwise +).
    torque, tension : float
        Largest TSA torque (N mm) and string tension (N).
    hits : tuple of str
        Every limit passed and every leg jammed, named with the limit.
    score : float
        ``forward`` less the weighted penalties, mm.
    """

    friction: float
    forward: float
    drift: float
    yaw: float
    slip: float
    torque: float
    tension: float
    hits: tuple[str, ...]
    score: float

    def to_dict(self) -> dict[str, Any]:
        """The terms for a JSON file, with units in the keys."""
        return {
            "friction": self.friction,
            "forward_mm_per_cycle": self.forward,
            "drift_mm_per_cycle": self.drift,
            "yaw_deg_per_cycle": self.yaw,
            "foot_slip_mm_per_cycle": self.slip,
            "max_torque_Nmm": self.torque,
            "max_tension_N": self.tension,
            "limits_hit": list(self.hits),
            "score_mm": self.score,
        }


def _yaw(body0: np.ndarray, body1: np.ndarray) -> float:
    """Turn (deg, counter-clockwise +) of a panel's nodes ``(k, 3)`` from one pose to another."""
    a = body0[:, :2] - body0[:, :2].mean(axis=0)
    b = body1[:, :2] - body1[:, :2].mean(axis=0)
    h = a.T @ b
    return math.degrees(math.atan2(h[0, 1] - h[1, 0], h[0, 0] + h[1, 1]))


def _feet(robot: Robot) -> list[np.ndarray]:
    """Each leg's foot nodes: its panel's vertices off its crease."""
    cp = robot.pattern
    return [np.setdiff1d(cp.faces[leg.face], cp.edges[leg.crease]) for leg in robot.legs]


def _hits(robot: Robot, result: GaitResult, limits: GaitLimits) -> tuple[list[str], float]:
    """The limits the simulated gait passed and its jammed legs, each named; and how far,
    in all, the jammed legs stayed past their command, deg."""
    hits = [result.reason] if result.stop is not None else []
    if result.torque.max() > limits.stall_torque:
        hits.append(f"TSA torque {result.torque.max():.3g} N mm over the servo's "
                    f"stall torque {limits.stall_torque:g} N mm")  # fmt: skip
    if result.tensions.max() > limits.max_tension:
        hits.append(f"string tension {result.tensions.max():.3g} N over the limit "
                    f"{limits.max_tension:g} N")  # fmt: skip
    rate = float(turn_rates(robot).max()) * 60.0
    if rate > limits.servo_rpm:
        hits.append(f"TSA twist {rate:.1f} rev/min over the servo's {limits.servo_rpm:g}")
    lag = result.fold - 180.0 * result.commanded[: len(result.fold)]
    jammed = np.flatnonzero(lag.max(axis=0) > STUCK_DEG)
    for k in jammed:
        hits.append(f"{robot.legs[k].name} jammed {lag[:, k].max():.0f} deg past its command")
    return hits, float(sum(lag[:, k].max() for k in jammed))


def gait_terms(robot: Robot, result: GaitResult, settings: GaitSettings) -> GaitTerms:
    """The objective's terms of a simulated gait (``robot`` carries the gait), per cycle."""
    n = max(1, len(result.cycle_starts) - 1)
    body = robot.pattern.faces[robot.pattern.face_index(robot.body)]
    s0, s1 = result.states[0], result.states[-1]
    feet = [result.states[:, f, 0].mean(axis=1) for f in _feet(robot)]
    slip = sum(float(-np.minimum(np.diff(x), 0.0).sum()) for x in feet) / n
    forward = float(result.body[-1, 0] - result.body[0, 0]) / n
    drift = float(result.body[-1, 1] - result.body[0, 1]) / n
    yaw = _yaw(s0[body], s1[body]) / n
    hits, jam = _hits(robot, result, settings.limits)
    score = forward - settings.w_drift * abs(drift) - settings.w_yaw * abs(yaw)
    hard = len(hits) - sum("jammed" in h for h in hits)
    score -= settings.w_slip * slip + settings.w_limit * hard + settings.w_jam * jam
    return GaitTerms(
        result.friction, forward, drift, yaw, slip,
        float(result.torque.max()), float(result.tensions.max()), tuple(hits), score,
    )  # fmt: skip


def evaluate_gait(robot: Robot, x, friction: float, settings: GaitSettings) -> GaitTerms:
    """Simulate genome ``x``'s gait (``None``: the robot's own) at ``friction`` as
    ``crawl`` does and score it.

    A module-level function of picklable arguments, mapped over the search's executor.
    A simulation that fails scores ``FAILED`` mm, with why as its hit.
    """
    walker = robot
    if x is not None:
        walker = with_gait(robot, *decode_gait(robot, x, settings.cycle))
        rate = float(turn_rates(walker).max()) * 60.0
        if rate > settings.limits.servo_rpm:  # known before walking: no simulation
            why = f"TSA twist {rate:.1f} rev/min over the servo's {settings.limits.servo_rpm:g}"
            score = FAILED - (rate - settings.limits.servo_rpm)
            return GaitTerms(friction, 0, 0, 0, 0, 0, 0, (why,), score)
    try:
        result = simulate_gait(
            walker, cycles=settings.cycles, steps=settings.steps, friction=friction
        )
    except (SimulationError, ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
        return GaitTerms(friction, 0, 0, 0, 0, 0, 0, (f"simulation failed: {exc}",), FAILED)
    return gait_terms(walker, result, settings)


#: How a candidate's per-friction scores ``s`` combine (``GaitSettings.mix``) against
#: the per-friction targets ``g`` (used by ``"shortfall"`` only), mm.
MIXES: dict[str, Callable[[list[float], list[float]], float]] = {
    "mean": lambda s, g: float(np.mean(s)),
    "worst": lambda s, g: float(min(s)),
    "worst+mean": lambda s, g: 0.5 * (float(min(s)) + float(np.mean(s))),
    "shortfall": lambda s, g: float(min(a - b for a, b in zip(s, g, strict=True))),
}


def combine_terms(terms: list[GaitTerms], mix: str, targets=None) -> float:
    """One score of a candidate's per-friction terms, by ``MIXES[mix]``, rounded (mm).

    ``targets`` (mm per cycle, one per term, in the terms' order) are the
    ``"shortfall"`` mix's; it needs them (``ValueError`` without), the others ignore them.
    """
    if mix not in MIXES:
        raise ValueError(f"mix {mix!r} is not one of {', '.join(MIXES)}")
    if mix == "shortfall" and (targets is None or len(targets) != len(terms)):
        raise ValueError(f"mix 'shortfall' needs one target per friction ({len(terms)})")
    value = MIXES[mix]([t.score for t in terms], list(targets or ()))
    return float(np.round(value / SCORE_RESOLUTION) * SCORE_RESOLUTION)


def settings_score(terms, settings: GaitSettings) -> float:
    """``combine_terms`` of ``terms`` by ``settings``' mix and (for ``"shortfall"``) targets."""
    targets = settings.target_values() if settings.mix == "shortfall" else None
    return combine_terms(list(terms), settings.mix, targets)


@dataclass(frozen=True)
class GaitCandidate:
    """One evaluated gait: run, generation, genome, keyframes, its terms and score.

    ``hand`` marks the robot file's own gait (run 0, generation 0; its genome is the
    nearest one, :func:`encode_gait`, its keyframes are the file's own).
    """

    run: int
    generation: int
    genome: tuple[float, ...]
    times: tuple[float, ...]
    ratios: tuple[tuple[float, ...], ...]
    terms: tuple[GaitTerms, ...]
    score: float
    hand: bool = False

    def to_dict(self) -> dict[str, Any]:
        """The candidate for ``results.json`` (fold angles in deg, times in s)."""
        return {
            "hand_gait": self.hand,
            "run": self.run,
            "generation": self.generation,
            "genome": list(self.genome),
            "keyframe_t_s": list(self.times),
            "keyframe_fold_deg": [[180.0 * p for p in row] for row in self.ratios],
            "score_mm": self.score,
            "per_friction": [t.to_dict() for t in self.terms],
        }


@dataclass
class GaitDesign:
    """A gait search's outcome: the best candidate, every one evaluated, the hand gait's.

    Attributes
    ----------
    best : GaitCandidate
        The best candidate within every limit (jams are scored, not excluded), of the
        hand gait and every run's; at least as good as the hand gait when that is within
        the limits.
    candidates : list of GaitCandidate
        Every evaluated candidate, in order: the hand gait, then (run, generation, index).
    history : list of list of float
        Best score after each generation, per run, mm.
    hand : tuple of GaitTerms
        The robot file's own gait scored the same way, per friction.
    hand_score : float
        Its combined score, mm.
    settings : GaitSettings
    """

    best: GaitCandidate
    candidates: list[GaitCandidate]
    history: list[list[float]]
    hand: tuple[GaitTerms, ...]
    hand_score: float
    settings: GaitSettings

    def robot(self, robot: Robot) -> Robot:
        """``robot`` walking the best gait."""
        return with_gait(robot, self.best.times, self.best.ratios)


def _evaluate_all(executor: cf.Executor, robot: Robot, pop, settings: GaitSettings):
    """Every genome of ``pop`` at every friction, over ``executor``: terms per genome."""
    jobs = [
        executor.submit(evaluate_gait, robot, x, mu, settings)
        for x in pop
        for mu in settings.frictions
    ]
    done = [job.result() for job in jobs]
    f = len(settings.frictions)
    return [tuple(done[i * f : (i + 1) * f]) for i in range(len(pop))]


def _candidate(robot, run, generation, x, terms, settings) -> GaitCandidate:
    times, ratios = decode_gait(robot, x, settings.cycle)
    return GaitCandidate(
        run, generation, tuple(float(v) for v in x), tuple(float(t) for t in times),
        tuple(tuple(float(v) for v in row) for row in ratios), terms,
        settings_score(terms, settings),
    )  # fmt: skip


def cma_strategy(run: int, settings: GaitSettings, start=None) -> cma.CMAEvolutionStrategy:
    """Run ``run``'s CMA-ES, seeded ``settings.seed + run``: run 0 starts at ``start``
    (the robot's own gait, :func:`encode_gait`; default the middle of the box), the others
    at random; the same populations on every call."""
    seed = settings.seed + run
    rng = np.random.default_rng(seed)
    first = np.full(DIMENSION, 0.5) if start is None else np.asarray(start, dtype=float)
    x0 = first if run == 0 else rng.uniform(0.15, 0.85, DIMENSION)
    opts = {
        "maxstd": 1.0 / 3.0,
        "seed": seed + 1,  # cma takes seed 0 as "from the clock"
        "popsize": settings.popsize,
        "verbose": -9,
        "verb_log": 0,
        "verb_disp": 0,
        "maxiter": settings.generations,
        "CMA_eigenmethod": canonical_eigh,
    }
    return cma.CMAEvolutionStrategy(x0, settings.sigma0, opts)


def _run(robot, settings, run, executor, report, hand: GaitCandidate):
    """One CMA-ES run from the hand gait's genome: every candidate it evaluated, and the
    best score so far (the hand gait's included) after each generation."""
    es, box = cma_strategy(run, settings, hand.genome), UnitBox(DIMENSION)
    out: list[GaitCandidate] = [hand]
    history: list[float] = []
    for generation in range(1, settings.generations + 1):
        genotypes = es.ask()
        pop = box(np.asarray(genotypes))
        terms = _evaluate_all(executor, robot, pop, settings)
        found = [
            _candidate(robot, run, generation, x, t, settings)
            for x, t in zip(pop, terms, strict=True)
        ]
        es.tell(genotypes, [-c.score for c in found])
        out += found
        history.append(max(c.score for c in out))
        report(len(found))
    return out[1:], history


def hard_hits(candidate: GaitCandidate) -> list[str]:
    """The limits ``candidate`` passed at any friction (servo speed or torque, string
    tension, a stopped or failed simulation); its jammed legs are scored, not listed."""
    return [h for t in candidate.terms for h in t.hits if "jammed" not in h]


def _best(candidates: list[GaitCandidate]) -> GaitCandidate:
    """The highest score among the candidates within every limit (else among all); the
    first found (the hand gait) wins a tie (scores are rounded: the same on any CPU).

    A leg that jams (friction lock, docs/crawler.md) is no limit of the robot's hardware
    but the model's outcome at that friction: it is penalised in the score, and a gait
    whose legs jam at some friction (the hand gait does at 0.8) may still be the best."""
    clean = [c for c in candidates if not hard_hits(c)] or candidates
    return max(clean, key=lambda c: c.score)


def design_gait(
    robot: Robot,
    settings: GaitSettings | None = None,
    executor: cf.Executor | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> GaitDesign:
    """Search ``robot``'s gait with CMA-ES; returns data, writes no files.

    Parameters
    ----------
    robot : Robot
        The loaded robot file (its own gait is scored too, as the hand gait).
    settings : GaitSettings, optional
        Frictions, mix, cycle (s), budget, weights and limits (default: ``GaitSettings()``
        with the robot's routes' limits).
    executor : concurrent.futures.Executor, optional
        Where the simulations go (a Dask executor spreads them over a cluster); default
        a process pool with one worker per core.
    progress : callable, optional
        ``progress(candidates evaluated, candidates in all)``.

    Returns
    -------
    GaitDesign
    """
    settings = settings or GaitSettings(limits=GaitLimits.of(robot))
    total = settings.runs * settings.popsize * settings.generations + 1
    done = [0]

    def report(n: int) -> None:
        done[0] += n
        if progress is not None:
            progress(done[0], total)

    own = executor is None
    pool = local_pool(settings.popsize * len(settings.frictions)) if own else executor
    try:
        hand = _hand_candidate(robot, _evaluate_all(pool, robot, [None], settings)[0], settings)
        report(1)
        candidates, history = [hand], []
        for run in range(settings.runs):
            found, best = _run(robot, settings, run, pool, report, hand)
            candidates += found
            history.append(best)
    finally:
        if own:
            pool.shutdown(wait=True, cancel_futures=True)
    return GaitDesign(_best(candidates), candidates, history, hand.terms, hand.score, settings)


def _hand_candidate(robot: Robot, terms, settings: GaitSettings) -> GaitCandidate:
    """The robot file's own gait as a candidate: the search never returns a worse one."""
    return GaitCandidate(
        0, 0, tuple(float(v) for v in encode_gait(robot)),
        tuple(float(t) for t in robot.gait_t),
        tuple(tuple(float(v) for v in row) for row in robot.gait_p), tuple(terms),
        settings_score(terms, settings), hand=True,
    )  # fmt: skip


def _leg_length(robot: Robot) -> float:
    """Mean distance from a leg's crease to its foot nodes, mm."""
    cp, out = robot.pattern, []
    for leg, feet in zip(robot.legs, _feet(robot), strict=True):
        a, b = cp.vertices[cp.edges[leg.crease]]
        d = (b - a) / np.linalg.norm(b - a)
        rel = cp.vertices[feet] - a
        out.append(float(np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0]).mean()))
    return float(np.mean(out))


def _rigid_stride(length: float, low_deg: float, high_deg: float) -> float:
    """Stride of rigid legs whose holding feet never slip: two strokes per cycle, mm."""
    return 2.0 * length * (math.cos(math.radians(low_deg)) - math.cos(math.radians(high_deg)))


def stride_limits(robot: Robot, design: GaitDesign, target: float = 63.0) -> dict[str, Any]:
    """What limits the stride, measured: leg length, blocker, friction lock, slip, stroke.

    Returns a dict (mm, deg, turns): the leg length; the rigid stride of the best gait's
    strokes (feet that never slip) and the most any gait could give between the floor
    (``P_FLOOR``) and the blocker; at each friction the self-locking angle
    ``arccot(friction)`` (a leg folded past it cannot unfold, docs/crawler.md) and the
    rigid stride capped by it; the foot slip as the rigid stride less the simulated
    one; the TSA turns the blocker needs against the route's ``max_turns`` (string
    stroke); and the leg length that would give ``target`` mm at the measured share of
    the rigid stride (the stride taken as proportional to the leg length), at each
    friction and, at the top level, at the friction nearest the robot file's.
    """
    length = _leg_length(robot)
    best = np.asarray(design.best.ratios) * 180.0
    low, high = float(best.min()), float(best.max())
    floor, blocker = P_FLOOR * 180.0, robot.blocker_angle
    per = {}
    for t in design.best.terms:
        lock = math.degrees(math.atan2(1.0, t.friction)) if t.friction > 0 else 90.0
        rigid = _rigid_stride(length, low, high)
        per[f"{t.friction:g}"] = {
            "self_lock_deg": lock,
            "ceiling_mm": _rigid_stride(length, floor, min(blocker, lock)),
            "rigid_stride_of_best_mm": rigid,
            "simulated_mm": t.forward,
            "slip_loss_mm": rigid - t.forward,
            "share_of_rigid": t.forward / rigid if rigid > 0 else 0.0,
            "leg_length_for_target_mm": target * length / t.forward if t.forward > 0 else math.inf,
        }
    own = min(design.best.terms, key=lambda t: abs(t.friction - robot.friction))
    stroke = gait_turns(robot, np.full((1, len(robot.legs)), blocker / 180.0))[0]
    return {
        "leg_length_mm": length,
        "best_fold_range_deg": [low, high],
        "floor_deg": floor,
        "blocker_deg": blocker,
        "ceiling_floor_to_blocker_mm": _rigid_stride(length, floor, blocker),
        "per_friction": per,
        "tsa_turns_at_blocker": float(stroke.max()),
        "route_max_turns": min(leg.route.max_turns for leg in robot.legs),
        "leg_length_for_target_mm": per[f"{own.friction:g}"]["leg_length_for_target_mm"],
        "target_friction": own.friction,
        "target_mm": target,
    }
