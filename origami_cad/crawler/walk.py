"""Legged robots driven by onboard TSAs: their gait, and walking in simulation.

The robot itself (its file, legs, point masses and parts) is :mod:`origami_cad.crawler.robot`'s.
:func:`gait_turns` turns fold ratios into TSA turns through the model (the strings'
lengths of the rigidly folded leg, eq. 7, and the onboard TSA's contraction);
:func:`simulate_gait` runs the gait in the bar-and-hinge simulator with the robot lying
free on the ground (gravity, penalty contact, Coulomb friction), each TSA twisted
independently, and records the body's path, tensions and torques.

The robot model's names (``Robot``, ``Leg``, ``PointMass``, ``load_robot``,
``dump_robot``, ``leg_key``, ``leg_heading``, ``robot_placements``, ``SERVO``,
``MOUNT_THICKNESS``, ``MOUNT_MARGIN``) are still found here for one release, with a
``DeprecationWarning``: import them from :mod:`origami_cad.crawler.robot`.

Units: mm, N, N mm, grams, seconds; degrees at the edges, radians inside. A leg's fold
ratio is ``p = |fold angle| / 180 deg`` of its hinge crease.
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from origami_cad._args import Arg, brief_value, checked
from origami_cad._names import one_line
from origami_cad.errors import SimulationError
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.cables import SimString, StringSet, string_length
from origami_cad.simulation.mechanics import fold_angles
from origami_cad.simulation.model import SimulationParams, build_structure
from origami_cad.simulation.solver import Ground, solve_equilibrium
from origami_cad.strings.dcqc_result import StopReason
from origami_cad.strings.route import (
    RouteSpec,
    frame_orientation,
    hole_frames,
    panel_frame,
)
from origami_cad.strings.tsa import (
    onboard_angle,
    onboard_contraction,
    onboard_transmission,
)

if TYPE_CHECKING:
    from origami_cad.crawler.robot import Leg, PointMass, Robot
    from origami_cad.drive.sequence import Sequence as DriveSequence

__all__ = [
    "SERVO_SPEED_RPM",
    "STUCK_DEG",
    "GaitResult",
    "check_servo_speed",
    "gait_loads",
    "gait_sequence",
    "gait_sequence_header",
    "gait_turns",
    "leg_contraction",
    "robot_params",
    "simulate_gait",
    "turn_rates",
    "walking_robot",
]

# ----------------------------------------------------------------------------- strings


def _sim_strings(cp: CreasePattern, route: RouteSpec) -> list[SimString]:
    """The route's strings in the simulator's form (as ``simulate`` builds them)."""
    out = []
    for s in route.strings:
        tri, ab = hole_frames(cp, s)
        sides = np.asarray(s.sides, dtype=float)
        sim = SimString(
            np.asarray(s.anchor, float),
            tri,
            ab,
            frame_orientation(cp, tri),
            sides,
            route.thickness * float(np.sum(np.diff(sides) != 0)),
        )
        if s.anchor_face >= 0:
            sim.anchor_tri, sim.anchor_ab = panel_frame(cp, s.anchor_face, *s.anchor[:2])
            sim.anchor_orient = float(frame_orientation(cp, sim.anchor_tri))
            sim.anchor = np.array([*s.anchor[:2], s.anchor[2] + route.thickness / 2.0])
        out.append(sim)
    return out


def _folded_leg(cp: CreasePattern, leg: Leg, angle: float) -> np.ndarray:
    """Vertices (n, 3) with the leg turned rigidly about its crease by ``angle`` (rad).

    Positive ``angle`` folds the crease in the sense of its assignment (a mountain's leg
    goes below the body's plane).
    """
    x = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    i, j = cp.edges[leg.crease]
    a, b = x[i], x[j]
    axis = (b - a) / np.linalg.norm(b - a)
    ring = cp.faces[leg.face]
    centre = cp.vertices[ring].mean(axis=0)
    # orient the axis so that turning by +angle about it lifts the leg (+z), then flip
    # for a mountain
    side = np.cross(axis, np.r_[centre, 0.0] - a)[2]
    sign = 1.0 if side > 0 else -1.0
    if cp.assignments[leg.crease] == "M":
        sign = -sign
    t = sign * angle
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rot = np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * k @ k
    moved = np.setdiff1d(ring, cp.edges[leg.crease])
    x[moved] = (x[moved] - a) @ rot.T + a
    return x


def leg_contraction(cp: CreasePattern, leg: Leg, ratios: np.ndarray) -> np.ndarray:
    """String the leg's TSA must take up to fold it to fold ratios ``ratios`` (mm).

    The leg turns rigidly about its crease by ``p * 180`` deg; each string's path length
    (eq. 7: holes on the panel faces, half the thickness off the mid-surface) is measured
    as the simulator measures it; the TSA takes up the largest shortening among its
    strings (the others go slack a little), from the flat sheet.
    """
    strings = StringSet(_sim_strings(cp, leg.route), leg.route.thickness / 2.0, leg.route.tsa)
    flat = _folded_leg(cp, leg, 0.0)
    base = np.array([string_length(flat, s, strings)[0] for s in strings.strings])
    out = []
    for p in np.atleast_1d(np.asarray(ratios, dtype=float)):
        x = _folded_leg(cp, leg, p * math.pi)
        now = np.array([string_length(x, s, strings)[0] for s in strings.strings])
        out.append(float(np.max(base - now)))
    return np.asarray(out)


def gait_turns(robot: Robot, ratios: np.ndarray | None = None) -> np.ndarray:
    """TSA turns (K, legs) for fold ratios (K, legs) (default: the gait's keyframes).

    Through :func:`leg_contraction` and the inverse of the onboard TSA model
    (``onboard_angle``); raises :class:`SimulationError` beyond what the strands give.
    """
    ratios = robot.gait_p if ratios is None else np.atleast_2d(ratios)
    out = np.zeros(ratios.shape)
    for k, leg in enumerate(robot.legs):
        tsa = leg.route.tsa
        c = leg_contraction(robot.pattern, leg, ratios[:, k])
        out[:, k] = onboard_angle(
            np.clip(c, 0, None), tsa.length, tsa.radius, math.radians(tsa.max_helix_angle)
        ) / (2 * math.pi)
    return out


#: The most quasi-static states :func:`simulate_gait` solves in one call (cycles x steps x
#: keyframe gaps): each is one equilibrium, about 0.1 s, so this is a day's run at most.
MAX_GAIT_STATES = 1_000_000

#: No-load speed of a leg's servo, rev/min: the XL330-M288 at 5 V (ROBOTIS e-manual).
SERVO_SPEED_RPM = 103.0


def turn_rates(robot: Robot) -> np.ndarray:
    """Each TSA's twist rate between consecutive keyframes, turns/s ``(K - 1, legs)``."""
    turns = gait_turns(robot)
    return np.abs(np.diff(turns, axis=0)) / np.diff(robot.gait_t)[:, None]


def check_servo_speed(robot: Robot, rpm: float = SERVO_SPEED_RPM, where: str = "") -> None:
    """Refuse a gait whose TSA must twist faster than its servo turns (``rpm``, rev/min).

    Raises :class:`SimulationError` naming the leg, its servo, the keyframes and the
    limit; nothing is slowed down or clipped.
    """
    rates = turn_rates(robot) * 60.0
    k, leg = np.unravel_index(int(np.argmax(rates)), rates.shape)
    if rates[k, leg] > rpm * (1 + 1e-9):
        name, t = robot.legs[leg], robot.gait_t
        raise SimulationError(
            f"{where or 'the gait'}: {name.name} (servo {name.servo}) must twist at "
            f"{rates[k, leg]:.1f} rev/min between keyframes t = {t[k]:g} s and {t[k + 1]:g} s, "
            f"over its servo's {rpm:g} rev/min"
        )


def walking_robot(
    robot: str | os.PathLike[str], gait: str | os.PathLike[str] | None = None
) -> Robot:
    """The robot file ``robot``, walking the gait file ``gait``'s keyframes if given.

    A gait past the servo's speed is refused (:class:`SimulationError` naming the gait
    file), as ``drive`` would refuse it.
    """
    from origami_cad.crawler.robot import load_gait, load_robot

    spec = load_robot(robot)
    if gait is not None:
        spec = load_gait(gait, spec)
        check_servo_speed(spec, where=str(gait))
    return spec


def gait_loads(robot: Robot, result: GaitResult) -> tuple[np.ndarray, np.ndarray]:
    """Each TSA's torque over one gait cycle: times (k,) s and torques (k, legs) N mm.

    The simulated states are folded onto one cycle (time modulo the cycle) and, where
    several cycles give a state at the same time of the cycle, the largest torque is kept
    (an envelope: a servo must give the most any cycle asks). The curve is closed: its
    value at the cycle's end is its value at 0.
    """
    cycle = robot.cycle
    local = np.round(np.mod(result.t, cycle), 6)
    local[np.isclose(local, cycle)] = 0.0
    times = np.unique(local)
    torque = np.array([result.torque[local == t].max(axis=0) for t in times])
    return np.r_[times, cycle], np.vstack([torque, torque[:1]])


def gait_sequence_header(robot: Robot, command: str | None = None) -> str:
    """The comment lines of a gait's sequence file: what its mappings and loads are, and
    ``command``, the command line that wrote it, quoted and named by its first two words
    (without it, by ``origami_cad``: a script wrote it)."""
    source = robot.source.name if robot.source else "the robot file"
    writer = " ".join(command.split()[:2]) if command else "origami_cad"
    lines = [
        f"# The gait of {one_line(source)} as TSA commands, written by {one_line(writer)}: each",
        "# mapping is the model's string take-up (the leg folded rigidly about its crease,",
        "# strings measured through their holes), so fold ratios become motor turns;",
        "# each load is the TSA's torque in the simulated crawl (N mm, one cycle, the most",
        "# any simulated cycle needed), carried by the emulated servos of a dry run.",
        *([f"#   {one_line(command)}"] if command else []),
    ]
    return "\n".join(lines) + "\n"


def gait_sequence(
    robot: Robot,
    *,
    repeat: int = 1,
    rate: float = 10.0,
    current_limit: float | None = 1200.0,
    result: GaitResult | None = None,
    reverse: bool = False,
) -> DriveSequence:
    """The gait as the sequence ``origami-cad drive`` runs (write it with
    ``dump_sequence(seq, header=gait_sequence_header(robot), layout="gait")``).

    Each TSA's ``mapping`` (fold ratio to contraction, mm) is :func:`leg_contraction`
    sampled every 0.02 up to the blockers' fold ratio, so ``drive`` turns the gait's
    fold-ratio keyframes into the same turns as :func:`gait_turns` (between samples,
    linearly). With a simulated ``result``, each TSA also gets its ``load``: the torque
    the simulation needs of its servo over one cycle, N mm (:func:`gait_loads`), which a
    dry run's emulated servo carries. ``reverse`` gives the keyframes backwards (as
    ``simulate_gait(reverse=True)`` plays them). ``rate`` in Hz; ``current_limit`` (mA)
    stops a stalling servo.
    """
    from origami_cad.drive.sequence import Keyframe, SequenceTSA
    from origami_cad.drive.sequence import Sequence as DriveSequence

    p_max = robot.blocker_angle / 180.0
    # the samples as written (4 decimals), each once (drive needs them increasing), the
    # last rounded up so that the mapping covers every keyframe's fold ratio
    ceiling = math.ceil(float(robot.gait_p.max()) * 1e4 - 1e-6) / 1e4
    top = p_max if round(p_max, 4) >= ceiling else ceiling
    given = np.round(np.r_[np.arange(0.0, p_max, 0.02), robot.gait_p.ravel()], 4)
    samples = np.unique(np.r_[given[given < top], top])
    loads = gait_loads(robot, result) if result is not None else None
    tsas = tuple(
        SequenceTSA(
            dxl_id=leg.servo,
            name=leg.name,
            tsa=leg.route.tsa,
            mapping=np.column_stack([samples, leg_contraction(robot.pattern, leg, samples)]),
            load=None if loads is None else np.column_stack([loads[0], loads[1][:, k]]),
        )
        for k, leg in enumerate(robot.legs)
    )
    t, ratios = robot.gait_t - robot.gait_t[0], robot.gait_p
    if reverse:
        t, ratios = t[-1] - t[::-1], ratios[::-1]
    frames = tuple(
        Keyframe(float(when), "p", tuple(float(v) for v in p))
        for when, p in zip(t, ratios, strict=True)
    )
    return DriveSequence(tsas, frames, repeat=repeat, rate=rate, current_limit=current_limit)


# ----------------------------------------------------------------------------- walking


@dataclass
class GaitResult:
    """A simulated gait, columnar: one row per equilibrium state.

    Attributes
    ----------
    t : ndarray (N,)
        Gait time, s.
    states : ndarray (N, n, 3)
        Node positions, mm.
    body : ndarray (N, 3)
        The body panel's centroid (mean of its vertices), mm.
    turns : ndarray (N, legs)
        Each TSA's twist, turns.
    tensions : ndarray (N, legs, strings)
        String tensions, N.
    torque : ndarray (N, legs)
        Each TSA's torque (sum of tension x the onboard transmission ratio), N mm.
    fold : ndarray (N, legs)
        Each leg crease's fold angle (magnitude), deg.
    blocked : ndarray (N,)
        Largest fold angle over every blocked crease, deg.
    converged : ndarray (N,) bool
    commanded : ndarray (N, legs)
        The gait's fold ratios at each state (the keyframes, linearly between).
    cycle_starts : list of int
        Row index where each cycle starts (the last one: the final state).
    notes : list of str
    stop, reason : StopReason or None, str
        Why the gait ended early (a leg's route ``max_tension`` or ``max_torque``
        passed, naming the leg), else None.
    """

    t: np.ndarray
    states: np.ndarray
    body: np.ndarray
    turns: np.ndarray
    tensions: np.ndarray
    torque: np.ndarray
    fold: np.ndarray
    blocked: np.ndarray
    converged: np.ndarray
    commanded: np.ndarray | None = None
    cycle_starts: list[int] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    friction: float = 0.0
    mass_g: float = 0.0
    stop: StopReason | None = None
    reason: str = "the gait ran to its end"

    def displacement_per_cycle(self, axis: int = 0) -> np.ndarray:
        """Body displacement over each cycle along ``axis`` (0: x, the heading), mm."""
        idx = self.cycle_starts
        return np.array(
            [self.body[b, axis] - self.body[a, axis] for a, b in itertools.pairwise(idx)]
        )

    def numbers(self, seconds: float) -> list[tuple[str, str]]:
        """The key numbers of the walk: displacement per cycle and in total, drift (mm),
        the largest TSA torque (N mm), string tension (N) and blocked fold (deg), the
        simulated mass (g), ``seconds`` (the simulation's time, s) and how it ended."""
        per = self.displacement_per_cycle()
        mean = float(per.mean()) if per.size else math.nan
        return [
            ("displacement per cycle", ", ".join(f"{d:.1f} mm" for d in per) or "none complete"),
            ("mean per cycle (paper: 63 mm)", f"{mean:.1f} mm"),
            ("total displacement", f"{self.body[-1, 0] - self.body[0, 0]:.1f} mm"),
            ("lateral drift", f"{self.body[-1, 1] - self.body[0, 1]:.1f} mm"),
            ("largest TSA torque", f"{self.torque.max():.1f} N mm"),
            ("largest string tension", f"{self.tensions.max():.1f} N"),
            ("largest blocked fold", f"{self.blocked.max():.1f} deg"),
            ("simulated mass", f"{self.mass_g:.0f} g"),
            ("simulation time", f"{seconds:.1f} s"),
            ("how the gait ended", self.reason),
        ]

    def to_dict(self) -> dict:
        per = self.displacement_per_cycle()
        return {
            "friction": self.friction,
            "mass_g": self.mass_g,
            "displacement_per_cycle_mm": per.tolist(),
            "displacement_total_mm": float(self.body[-1, 0] - self.body[0, 0]),
            "lateral_drift_mm": float(self.body[-1, 1] - self.body[0, 1]),
            "max_blocked_fold_deg": float(self.blocked.max()),
            "max_tension_N": float(self.tensions.max()),
            "max_torque_Nmm": self.torque.max(axis=0).tolist(),
            "all_converged": bool(self.converged.all()),
            "stop": None if self.stop is None else str(self.stop),
            "reason": self.reason,
            "notes": self.notes,
            "t_s": self.t.tolist(),
            "body_mm": self.body.tolist(),
            "turns": self.turns.tolist(),
            "torque_Nmm": self.torque.tolist(),
            "tension_N": self.tensions.tolist(),
            "leg_fold_deg": self.fold.tolist(),
        }


def _point_weights(cp: CreasePattern, st, masses: tuple[PointMass, ...], g: float) -> np.ndarray:
    """Node weights (n,), N, carrying each point mass by barycentric shares of its triangle."""
    w = np.zeros(cp.n_vertices)
    xy = cp.vertices
    for m in masses:
        p = np.asarray(m.at, float)
        for tri in st.triangles:
            a, b, c = xy[tri]
            den = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1])
            l1 = ((b[1] - c[1]) * (p[0] - c[0]) + (c[0] - b[0]) * (p[1] - c[1])) / den
            l2 = ((c[1] - a[1]) * (p[0] - c[0]) + (a[0] - c[0]) * (p[1] - c[1])) / den
            lam = np.array([l1, l2, 1 - l1 - l2])
            if np.all(lam >= -1e-9):
                w[tri] += lam * m.grams * 1e-6 * g  # g -> kg, mm/s^2 -> N (kg mm/s^2 / 1000)
                break
        else:
            raise SimulationError(f"mass {m.name!r} at {m.at} lies on no panel")
    return w


def _schedule(
    robot: Robot, cycles: int, steps: int, reverse: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Times (N,) and fold ratios (N, legs) of the simulated states, ``steps`` per keyframe gap."""
    t, p = robot.gait_t - robot.gait_t[0], robot.gait_p
    if reverse:
        t, p = t[-1] - t[::-1], p[::-1]
    times, ratios = [np.array([0.0])], [p[:1]]
    for c in range(cycles):
        for k in range(len(t) - 1):
            s = np.linspace(0, 1, steps + 1)[1:]
            times.append(c * t[-1] + t[k] + s * (t[k + 1] - t[k]))
            ratios.append(p[k] + s[:, None] * (p[k + 1] - p[k]))
    return np.concatenate(times), np.concatenate(ratios)


def _over_limit(robot: Robot, tensions: np.ndarray, torque: np.ndarray):
    """(StopReason, reason) when a leg passes its route's max_tension or max_torque."""
    for k, leg in enumerate(robot.legs):
        if tensions[k].max() > leg.route.max_tension:
            return StopReason.TENSION_LIMIT, (
                f"{leg.name} (servo {leg.servo}): a string pulls {tensions[k].max():.3g} N, "
                f"over its route's max_tension of {leg.route.max_tension:g} N"
            )
        if torque[k] > leg.route.max_torque:
            return StopReason.TORQUE_LIMIT, (
                f"{leg.name} (servo {leg.servo}): the TSA needs {torque[k]:.3g} N mm, over "
                f"its route's max_torque of {leg.route.max_torque:g} N mm"
            )
    return None


def _truncate(out: GaitResult, rows: int) -> None:
    names = ("t", "states", "body", "turns", "tensions", "torque", "fold", "blocked", "commanded")
    for name in names:
        setattr(out, name, getattr(out, name)[:rows])
    out.converged = out.converged[:rows]
    out.cycle_starts = [k for k in out.cycle_starts if k < rows]
    if out.cycle_starts[-1] != rows - 1:
        out.notes.append("the last cycle is incomplete")


def _pose(robot: Robot, params: SimulationParams, prefold: float) -> tuple[np.ndarray, float]:
    """The robot on its legs, each folded rigidly by ``prefold`` deg, feet on the ground:
    node positions (n, 3) mm and the contact height of the mid-surface, mm.

    The strings then hold every leg on its mountain branch from the first step.
    """
    cp = robot.pattern
    posed = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    for leg in robot.legs:
        folded = _folded_leg(cp, leg, math.radians(prefold))
        ring = cp.faces[leg.face]
        posed[ring] = folded[ring]
    contact = params.ground + 0.5 * params.panel_thickness
    posed[:, 2] += contact - posed[:, 2].min()
    return posed, contact


def _gait_strings(
    robot: Robot, params: SimulationParams, contact: float
) -> tuple[StringSet, np.ndarray, np.ndarray]:
    """Every leg's strings in one set at zero twist: (set, owning leg (s,), free lengths (s,) mm).

    An onboard TSA's share is x_dis plus the strands' contraction, so each TSA's twist
    shortens its own strings' free length from the flat sheet's.
    """
    cp = robot.pattern
    sims, owner = [], []
    flat = np.column_stack([cp.vertices, np.full(cp.n_vertices, contact)])
    for k, leg in enumerate(robot.legs):
        for s in _sim_strings(cp, leg.route):
            sims.append(s)
            owner.append(k)
    thickness = robot.legs[0].route.thickness
    strings = StringSet(sims, thickness / 2.0, robot.legs[0].route.tsa)
    for s in strings.strings:
        s.free_length = string_length(flat, s, strings)[0]
        s.stiffness = params.string_axial_stiffness / s.free_length
    base = np.array([s.free_length for s in strings.strings])
    return strings, np.asarray(owner), base


def _tsa_values(robot: Robot, theta: np.ndarray, fn: Callable) -> np.ndarray:
    """``fn(theta, length, radius, max helix)`` of every leg's onboard TSA at twist ``theta``
    (rad, one per leg): its contraction (mm) or transmission ratio (mm)."""
    return np.array(
        [
            float(fn(th, leg.route.tsa.length, leg.route.tsa.radius,
                     math.radians(leg.route.tsa.max_helix_angle)))
            for th, leg in zip(theta, robot.legs, strict=True)
        ]
    )  # fmt: skip


def _equilibrium(x, previous, st, strings, ground):
    """The next equilibrium from ``x``: a linear predictor first, the last state if it fails."""
    start = x if previous is None else 2.0 * x - previous
    try:
        x_new, info = solve_equilibrium(start, st, strings, ground=ground)
    except Exception:  # a poor predictor: start from the last equilibrium
        x_new, info = solve_equilibrium(x, st, strings, ground=ground)
    if not info.converged and start is not x:
        x_new, info = solve_equilibrium(x, st, strings, ground=ground)
    return x_new, info


@dataclass
class _Walk:
    """What one simulated gait needs at every step besides the state."""

    st: Any
    strings: StringSet
    owner: np.ndarray
    base: np.ndarray
    ground: Ground
    body_nodes: np.ndarray
    leg_hinges: list[int]
    blocked_hinges: np.ndarray


def _record(out: GaitResult, r: int, x: np.ndarray, info, walk: _Walk, ratio: np.ndarray):
    """Row ``r`` of ``out``: the state, the body, fold angles, tensions and TSA torques."""
    out.states[r] = x
    out.body[r] = x[walk.body_nodes].mean(axis=0)
    rho = fold_angles(x, walk.st.hinges)
    out.fold[r] = np.degrees(np.abs(rho[walk.leg_hinges]))
    out.blocked[r] = float(np.degrees(np.abs(rho[walk.blocked_hinges])).max())
    out.converged[r] = info.converged
    tens = np.asarray(info.tensions)
    for k in range(len(ratio)):
        mine = tens[walk.owner == k]
        out.tensions[r, k, : len(mine)] = mine
        out.torque[r, k] = float(mine.sum()) * ratio[k]


def _start_walk(robot: Robot, params: SimulationParams, mu: float, prefold: float | None):
    """The structure on the ground with its strings; the start state and the mass, g."""
    cp = robot.pattern
    st = build_structure(cp, params, None, robot.blockers, free=True)
    st.weight = st.weight + _point_weights(cp, st, robot.masses, params.gravity)
    mass_g = float(st.weight.sum() / params.gravity * 1e6) if params.gravity > 0 else 0.0
    if prefold is None:
        prefold = max(2.0, 180.0 * float(robot.gait_p[0].max()))
    st.x0, contact = _pose(robot, params, prefold)
    ground = Ground(contact, params.ground_stiffness, mu, params.slip)
    ground.start(st.x0)
    strings, owner, base = _gait_strings(robot, params, contact)
    walk = _Walk(
        st,
        strings,
        owner,
        base,
        ground,
        cp.faces[cp.face_index(robot.body)],
        [int(np.flatnonzero(st.hinge_edge == leg.crease)[0]) for leg in robot.legs],
        np.flatnonzero(np.isin(st.hinge_edge, list(robot.blockers))),
    )
    return walk, mass_g


#: deg: a leg folded this much past its command is reported as stuck (simulate_gait's notes)
STUCK_DEG = 10.0


def _inclination(x: np.ndarray, ring: np.ndarray) -> float:
    """Angle between a panel (its nodes ``x[ring]``, mm) and the ground plane, deg."""
    p = x[ring] - x[ring].mean(axis=0)
    normal = np.linalg.svd(p)[2][2]
    return math.degrees(math.acos(min(1.0, abs(float(normal[2])))))


def _stuck_legs(robot: Robot, out: GaitResult) -> list[str]:
    """Notes on the legs that stayed folded well past the gait's command.

    The strings only pull: they fold a leg, and its crease (plus the robot's weight,
    pushing the foot outward) unfolds it, which needs the foot to slide. A foot whose leg
    stands at ``alpha`` to the ground self-locks when ``friction >= cot(alpha)`` (the
    leg as a strut; the other feet's grip shifts that bound, docs/crawler.md, "friction").
    """
    notes = []
    lag = out.fold - 180.0 * out.commanded[: len(out.fold)]
    for k, leg in enumerate(robot.legs):
        r = int(np.argmax(lag[:, k]))
        if lag[r, k] <= STUCK_DEG:
            continue
        alpha = _inclination(out.states[r], robot.pattern.faces[leg.face])
        notes.append(
            f"{leg.name} (servo {leg.servo}) stayed folded at {out.fold[r, k]:.0f} deg where "
            f"the gait commands {180.0 * out.commanded[r, k]:.0f} deg (t = {out.t[r]:.1f} s), "
            f"standing at {alpha:.0f} deg to the ground: the strings only pull, and a leg "
            f"unfolds only while the robot's weight can slide its foot outward (a strut at "
            f"alpha to the ground slides while friction < about cot alpha; here friction "
            f"{out.friction:g}, cot {alpha:.0f} deg = {1.0 / math.tan(math.radians(alpha)):.2f})"
        )
    return notes


def _empty_result(
    robot: Robot, walk: _Walk, times: np.ndarray, ratios: np.ndarray, steps: int
) -> GaitResult:
    """The result's arrays for the scheduled states (``times``, ``ratios``), zero-filled."""
    n_legs, rows = len(robot.legs), len(times)
    per_leg = max(int(np.sum(walk.owner == k)) for k in range(n_legs))
    n = robot.pattern.n_vertices
    return GaitResult(
        t=times,
        states=np.zeros((rows, n, 3)),
        body=np.zeros((rows, 3)),
        turns=gait_turns(robot, ratios),
        tensions=np.zeros((rows, n_legs, per_leg)),
        torque=np.zeros((rows, n_legs)),
        fold=np.zeros((rows, n_legs)),
        blocked=np.zeros(rows),
        converged=np.zeros(rows, dtype=bool),
        commanded=ratios,
        cycle_starts=list(range(0, rows, (len(robot.gait_t) - 1) * steps)),
    )


def robot_params(robot: Robot, **overrides) -> SimulationParams:
    """The robot's sheet on the ground: gravity 9810 mm/s^2, the ground at z = 0, the
    robot's friction, and the printed sheet of its routes' ``[fabrication]`` (the first
    leg's; crease thickness t, so the crease stiffness E t^3 / (12 w), and eq. 6's fold
    limit), else the paper's sheet. ``overrides`` set any field."""
    values = {"gravity": 9810.0, "ground": 0.0, "friction": robot.friction, **overrides}
    fab = robot.legs[0].route.fabrication if robot.legs else None
    if fab is None:
        return SimulationParams(**values)
    return SimulationParams.from_fabrication(fab, **values)


@checked(
    SimulationError,
    cycles=Arg("int", min=1, max=10_000, optional=False),
    steps=Arg("int", min=1, max=1000, optional=False),
    reverse=Arg("bool", optional=False),
    params=Arg("object", types=(SimulationParams,)),
    friction=Arg(min=0.0, max=100.0),
    prefold=Arg(min=0.0, max=90.0),
    progress=Arg("callable", length=2),
)
def simulate_gait(
    robot: Robot,
    *,
    cycles: int = 1,
    steps: int = 6,
    reverse: bool = False,
    params: SimulationParams | None = None,
    friction: float | None = None,
    prefold: float | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> GaitResult:
    """Walk the robot through ``cycles`` gait cycles in the bar-and-hinge simulator.

    Parameters
    ----------
    robot : Robot
        The loaded robot file.
    cycles : int
        Gait cycles to run.
    steps : int
        Quasi-static steps between consecutive keyframes.
    reverse : bool
        Play the gait backwards (keyframes in reverse order).
    params : SimulationParams, optional
        Materials and loads (default: :func:`robot_params`, the routes' printed sheet,
        gravity 9810 mm/s^2, the ground at z = 0 and the robot's friction coefficient).
    friction : float, optional
        Override the robot's Coulomb coefficient.
    prefold : float, optional
        Leg creases start pre-folded by this much in their assignment's sense, deg
        (default: the gait's first keyframe, at least 2 deg).
    progress : callable, optional
        ``progress(state, states)`` after each equilibrium.

    Returns
    -------
    GaitResult
        Its ``notes`` name each leg that stayed folded more than ``STUCK_DEG`` past the
        gait's command (a foot that cannot slide: at high friction the gait jams).
    """
    from origami_cad.crawler.robot import Robot

    if not isinstance(robot, Robot):
        raise SimulationError(f"simulate_gait: robot: expected a Robot, got {brief_value(robot)}")
    states = cycles * steps * (len(robot.gait_t) - 1)
    if states > MAX_GAIT_STATES:
        raise SimulationError(
            f"simulate_gait: {cycles} cycles x {steps} steps x {len(robot.gait_t) - 1} keyframe "
            f"gaps make {states} states, more than {MAX_GAIT_STATES}"
        )
    mu = robot.friction if friction is None else friction
    if params is None:
        params = robot_params(robot, friction=mu)
    walk, mass_g = _start_walk(robot, params, mu, prefold)
    times, ratios = _schedule(robot, cycles, steps, reverse)
    out = _empty_result(robot, walk, times, ratios, steps)
    out.friction, out.mass_g = mu, mass_g
    turns, rows = out.turns, len(times)
    x, previous = walk.st.x0.copy(), None
    for r in range(rows):
        theta = turns[r] * 2 * math.pi
        contraction = _tsa_values(robot, theta, onboard_contraction)
        for s, b, k in zip(walk.strings.strings, walk.base, walk.owner, strict=True):
            s.free_length = b - contraction[k]
        x_new, info = _equilibrium(x, previous, walk.st, walk.strings, walk.ground)
        previous, x = x, x_new
        walk.ground.start(x)
        _record(out, r, x, info, walk, _tsa_values(robot, theta, onboard_transmission))
        if progress is not None:
            progress(r, rows)
        stop = _over_limit(robot, out.tensions[r], out.torque[r])
        if stop is not None:
            out.stop, out.reason = stop
            _truncate(out, r + 1)
            break
    if not out.converged.all():
        out.notes.append(f"{int((~out.converged).sum())} of {rows} states did not fully converge")
    out.notes += _stuck_legs(robot, out)
    return out
