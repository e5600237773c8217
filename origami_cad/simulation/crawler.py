"""Legged robots driven by onboard TSAs: the robot file, its gait, and walking in simulation.

A robot file (TOML, see ``examples/crawler/crawler.toml``) names a crease pattern, one
route file per leg (an onboard TSA on that leg, ``anchor_panel``), blockers on the leg
creases, point masses (servos, the driver module) and a gait: keyframes of fold ratios,
one per leg. :func:`gait_turns` turns fold ratios into TSA turns through the model (the
strings' lengths of the rigidly folded leg, eq. 7, and the onboard TSA's contraction);
:func:`simulate_gait` runs the gait in the bar-and-hinge simulator with the robot lying
free on the ground (gravity, penalty contact, Coulomb friction), each TSA twisted
independently, and records the body's path, tensions and torques.

Units: mm, N, N mm, grams, seconds; degrees at the edges, radians inside. A leg's fold
ratio is ``p = |fold angle| / 180 deg`` of its hinge crease.
"""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad._names import one_line, path_component, toml_string
from origami_cad._toml import Table, load_toml, toml_table
from origami_cad.errors import PatternError, SimulationError, StringsError
from origami_cad.pattern.io import read_pattern
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.cables import SimString, StringSet, string_length
from origami_cad.simulation.mechanics import fold_angles
from origami_cad.simulation.model import SimulationParams, build_structure
from origami_cad.simulation.solver import Ground, solve_equilibrium
from origami_cad.strings.dcqc import StopReason
from origami_cad.strings.route import (
    RouteSpec,
    frame_orientation,
    hole_frames,
    load_route,
    panel_frame,
)
from origami_cad.strings.tsa import (
    onboard_angle,
    onboard_contraction,
    onboard_transmission,
)

__all__ = [
    "SERVO",
    "STUCK_DEG",
    "GaitResult",
    "Leg",
    "PointMass",
    "Robot",
    "dump_robot",
    "gait_loads",
    "gait_sequence_text",
    "gait_turns",
    "leg_contraction",
    "leg_heading",
    "leg_key",
    "load_robot",
    "robot_placements",
    "simulate_gait",
]


@dataclass(frozen=True)
class Leg:
    """One leg: its panel, the crease joining it to the body, its TSA route and servo."""

    panel: str
    face: int
    crease: int
    route: RouteSpec
    servo: int
    name: str
    route_path: Path | None = None


@dataclass(frozen=True)
class PointMass:
    """Hardware carried by a panel: ``grams`` at pattern point ``at`` (mm) of ``panel``."""

    name: str
    panel: str
    at: tuple[float, float]
    grams: float


@dataclass(frozen=True)
class Robot:
    """A robot file, loaded: the pattern, its legs, blockers, masses, adapter and gait.

    ``gait_t`` (K,) are keyframe times in s, ``gait_p`` (K, legs) fold ratios.
    """

    pattern: CreasePattern
    body: str
    legs: tuple[Leg, ...]
    blocker_angle: float
    friction: float
    holes: tuple[tuple[float, float], ...]
    masses: tuple[PointMass, ...]
    adapter_at: tuple[float, float]
    adapter_heading: float
    gait_t: np.ndarray
    gait_p: np.ndarray
    source: Path | None = None
    pattern_path: Path | None = None

    @property
    def blockers(self) -> dict[int, float]:
        """``{crease edge: degrees}``: a blocker on every leg crease."""
        return {leg.crease: self.blocker_angle for leg in self.legs}

    @property
    def cycle(self) -> float:
        """Duration of one gait cycle, s."""
        return float(self.gait_t[-1] - self.gait_t[0])


def _shared_crease(cp: CreasePattern, a: int, b: int) -> int | None:
    ef = cp.edge_faces()
    hit = np.flatnonzero(((ef[:, 0] == a) & (ef[:, 1] == b)) | ((ef[:, 0] == b) & (ef[:, 1] == a)))
    hit = [int(e) for e in hit if cp.assignments[e] in ("M", "V")]
    return hit[0] if len(hit) == 1 else None


def _robot_pattern(p: Path, robot: Table) -> tuple[CreasePattern, Path, str]:
    """The ``[robot] pattern`` file, read: (pattern, its path, the name as given)."""
    rel = robot.string("pattern")
    pattern_path = (p.parent / rel).resolve()
    if not pattern_path.is_file():
        raise robot.error("pattern", f"{pattern_path}: no such file")
    try:
        cp = read_pattern(pattern_path)
    except PatternError as exc:
        raise SimulationError(f"{p}: [robot] pattern: {exc}") from None
    return cp, pattern_path, rel


def _read_legs(p: Path, legs_raw: Any, cp: CreasePattern, body: str, rel: str) -> list[Leg]:
    """The ``[[leg]]`` tables: a panel sharing one crease with ``body``, an onboard route."""
    if not isinstance(legs_raw, list) or not legs_raw:
        raise SimulationError(f"{p}: expected at least one [[leg]] table")
    body_face = cp.face_index(body)
    legs = []
    for i, item in enumerate(legs_raw):
        t = Table(item, f"{p} [[leg]] #{i + 1}", SimulationError)
        panel = t.string("panel")
        if panel not in cp.face_labels:
            raise t.error("panel", f"no panel labelled {panel!r} in {rel}")
        face = cp.face_index(panel)
        crease = _shared_crease(cp, face, body_face)
        if crease is None:
            raise t.error("panel", f"panel {panel!r} does not share one crease with {body!r}")
        route_path = (p.parent / t.string("route")).resolve()
        if not route_path.is_file():
            raise t.error("route", f"{route_path}: no such file")
        try:
            route = load_route(route_path, cp)
        except StringsError as exc:
            raise t.error("route", str(exc)) from None
        if route.tsa.model != "onboard":
            raise t.error("route", f"{route_path.name}: a leg's TSA must be onboard")
        servo = t.integer("servo", low=0, high=252)
        name = _leg_name(t, panel)
        t.finish()
        legs.append(Leg(panel, face, crease, route, servo, name, route_path))
    ids = [leg.servo for leg in legs]
    if len(set(ids)) != len(ids):
        raise SimulationError(f"{p}: [[leg]] servo IDs must differ, got {ids}")
    keys = [leg_key(leg.name).casefold() for leg in legs]
    for i, key in enumerate(keys):
        if key in keys[:i]:
            raise SimulationError(
                f"{p} [[leg]] #{i + 1}: key 'name': {legs[i].name!r} names the same files as "
                f"[[leg]] #{keys.index(key) + 1} (names must differ, also in case and spaces)"
            )
    return legs


def _leg_name(t: Table, panel: str) -> str:
    """The ``name`` of a ``[[leg]]`` (default: its panel label), refused unless it can be
    part of a file name (``tsa_module_<name>.stl``: no ``/``, ``..``, control characters)."""
    name = t.string("name", panel)
    try:
        path_component(leg_key(name))
    except ValueError as exc:
        given = "" if t.has("name") else " (the panel label, as no name is given)"
        raise t.error("name", f"{exc}{given}; the leg's name names its part files") from None
    return name


def leg_key(name: str) -> str:
    """A leg name as it appears in file and part names: spaces become ``_``."""
    return name.replace(" ", "_")


def _read_masses(p: Path, masses_raw: Any, cp: CreasePattern, rel: str) -> list[PointMass]:
    """The ``[[mass]]`` tables: grams at a point (mm) of a named panel."""
    masses = []
    for i, item in enumerate(masses_raw if isinstance(masses_raw, list) else [masses_raw]):
        t = Table(item, f"{p} [[mass]] #{i + 1}", SimulationError)
        name = t.string("name")
        panel = t.string("panel")
        if panel not in cp.face_labels:
            raise t.error("panel", f"no panel labelled {panel!r} in {rel}")
        at = t.point("at")
        if cp.face_of_point(*at) != cp.face_index(panel):
            raise t.error("at", f"({at[0]:g}, {at[1]:g}) mm is not on panel {panel!r}")
        grams = t.number("grams", low=0)
        t.finish()
        masses.append(PointMass(name, panel, at, grams))
    return masses


def _read_gait(p: Path, gait: Table, legs: int, blocker: float) -> tuple[np.ndarray, np.ndarray]:
    """The ``[[gait.keyframe]]`` tables: times (K,) s and fold ratios (K, legs) within the
    blockers' ``blocker`` deg."""
    frames = gait.data.get("keyframe")
    gait.used.add("keyframe")
    gait.finish()
    if not isinstance(frames, list) or len(frames) < 2:
        raise SimulationError(f"{p}: [gait] needs at least two [[gait.keyframe]] tables")
    times, ratios = [], []
    for i, item in enumerate(frames):
        t = Table(item, f"{p} [[gait.keyframe]] #{i + 1}", SimulationError)
        times.append(t.number("t", low=0))
        ratios.append(
            t.numbers("p", length=legs, check=lambda v: 0 <= v < 1, what="must lie in [0, 1)")
        )
        t.finish()
    if np.any(np.diff(times) <= 0):
        raise SimulationError(f"{p}: [[gait.keyframe]] times must increase, got {times}")
    limit = blocker / 180.0
    worst = max(max(r) for r in ratios)
    if worst > limit + 1e-9:
        raise SimulationError(
            f"{p}: [[gait.keyframe]] p = {worst:g} folds a leg past its blocker "
            f"({blocker:g} deg = p {limit:.3f})"
        )
    return np.asarray(times), np.asarray(ratios)


def load_robot(path: str | os.PathLike[str]) -> Robot:
    """Read a robot file; errors name the file, table and key (:class:`SimulationError`)."""
    p = Path(path)
    top = Table(load_toml(p, SimulationError), str(p), SimulationError)
    robot = top.table("robot")
    fab = top.table("fabrication", {})
    adapter = top.table("adapter", {})
    gait = top.table("gait")
    legs_raw = top.data.get("leg")
    masses_raw = top.data.get("mass", [])
    top.used.update(("leg", "mass"))
    top.finish()
    cp, pattern_path, rel = _robot_pattern(p, robot)
    body = robot.string("body")
    if body not in cp.face_labels:
        raise robot.error("body", f"no panel labelled {body!r} in {rel}")
    blocker = robot.number("blocker_angle", 60.0, low=0, high=180, low_open=True, high_open=True)
    friction = robot.number("friction", 0.6, low=0)
    robot.finish()
    given = fab.pairs("holes", None, min_length=1) if fab.has("holes") else None
    fab.finish()
    legs = _read_legs(p, legs_raw, cp, body, rel)
    if given is None:  # the holes the strings run through, in route order
        routed = [p for leg in legs for s in leg.route.strings for p in s.points]
        holes = tuple(dict.fromkeys(routed))
    else:
        holes = tuple((float(x), float(y)) for x, y in given)
    masses = _read_masses(p, masses_raw, cp, rel)
    adapter_at = adapter.point("at", (0.0, 0.0))
    heading = adapter.number("heading", 0.0)
    adapter.finish()
    times, ratios = _read_gait(p, gait, len(legs), blocker)
    return Robot(
        cp,
        body,
        tuple(legs),
        blocker,
        friction,
        holes,
        tuple(masses),
        adapter_at,
        heading,
        times,
        ratios,
        p,
        pattern_path,
    )


def _relative(path: Path | None, folder: Path, what: str) -> str:
    if path is None:
        raise SimulationError(f"the robot's {what} has no file to name")
    return Path(os.path.relpath(path, folder)).as_posix()


def dump_robot(
    robot: Robot, folder: str | os.PathLike[str] | None = None, *, header: str = ""
) -> str:
    """A robot file (TOML text) of ``robot`` that :func:`load_robot` reads back.

    The pattern and route files are named relative to ``folder``, where the robot file
    goes (default: the folder it was read from); lengths mm, angles deg, masses g.
    The ``[fabrication]`` holes are written only when they are not the routes' holes.

    >>> robot = load_robot("examples/crawler/crawler.toml")
    >>> text = dump_robot(robot)
    >>> 'pattern = "crawler.fold"' in text and 'route = "route_fl.toml"' in text
    True
    """
    base = Path(folder) if folder is not None else (robot.source or Path("x")).parent
    base = base.resolve()
    lines = [header.rstrip("\n")] if header else []
    head = {
        "pattern": _relative(robot.pattern_path, base, "pattern"),
        "body": robot.body,
        "blocker_angle": float(robot.blocker_angle),
        "friction": float(robot.friction),
    }
    lines += toml_table("robot", head, comments={"blocker_angle": "deg"})
    routed = tuple(
        dict.fromkeys(p for leg in robot.legs for s in leg.route.strings for p in s.points)
    )
    if tuple(robot.holes) != routed:
        holes = [list(h) for h in robot.holes]
        lines += ["", *toml_table("fabrication", {"holes": holes}, comments={"holes": "mm"})]
    for leg in robot.legs:
        route = _relative(leg.route_path, base, f"leg {leg.name!r}'s route")
        table = {"panel": leg.panel, "route": route, "servo": leg.servo, "name": leg.name}
        lines += ["", *toml_table("leg", table, array=True)]
    for m in robot.masses:
        table = {"name": m.name, "panel": m.panel, "at": list(m.at), "grams": float(m.grams)}
        lines += ["", *toml_table("mass", table, array=True, comments={"at": "mm"})]
    adapter = {"at": list(robot.adapter_at), "heading": float(robot.adapter_heading)}
    lines += ["", *toml_table("adapter", adapter, comments={"heading": "deg"}), "", "[gait]"]
    for t, p in zip(robot.gait_t, robot.gait_p, strict=True):
        frame = {"t": float(t), "p": [float(v) for v in p]}
        lines += toml_table("gait.keyframe", frame, array=True)
    return "\n".join(lines) + "\n"


#: The servo of every leg module (the paper's TSA modules use Dynamixel XL330 servos).
SERVO = "XL330"
#: Thickness of a leg module's mount plate, mm (thin: the leg panel carries the load).
MOUNT_THICKNESS = 1.0
#: How far a leg module's mount plate reaches around its servo, hub and guide, mm: a plate
#: that size holds the module; the rest of the leg needs none (the whole leg face as the
#: mount weighed 11.7 g a leg, docs/crawler.md, mass budget).
MOUNT_MARGIN = 3.0


def leg_heading(robot: Robot, leg: Leg) -> float:
    """Direction (deg from +x) across the leg's crease toward the body: a module's twist axis."""
    cp = robot.pattern
    a, b = cp.vertices[cp.edges[leg.crease]]
    d = (b - a) / np.linalg.norm(b - a)
    normal = np.array([-d[1], d[0]])
    centre = cp.vertices[cp.faces[leg.face]].mean(axis=0)
    if np.dot(centre - a, normal) > 0:
        normal = -normal
    return math.degrees(math.atan2(normal[1], normal[0])) % 360.0


def robot_placements(robot: Robot) -> dict[str, list]:
    """The robot's parts as placements for :func:`origami_cad.parts.robot.robot_assembly`.

    A TSA module (``SERVO``, strands = the route's TSA length as its guide distance, twist
    axis toward the body) on every leg, a blocker on every leg crease and the driver
    adapter (one connector per leg) at ``[adapter] at``. Names have no spaces (STEP
    labels).
    """
    from origami_cad.parts.robot import BlockerPlacement, FreePlacement, ModulePlacement

    modules = [
        ModulePlacement(
            f"tsa_module_{leg_key(leg.name)}",
            leg.panel,
            {
                "servo": SERVO,
                "guide_distance": leg.route.tsa.length,
                "mount_thickness": MOUNT_THICKNESS,
                "mount_margin": MOUNT_MARGIN,
                "heading": leg_heading(robot, leg),
                "tsa": leg.route.tsa,
            },
        )
        for leg in robot.legs
    ]
    blockers = [
        BlockerPlacement(f"blocker_{leg_key(leg.name)}", leg.crease, robot.blocker_angle)
        for leg in robot.legs
    ]
    free = [
        FreePlacement(
            "driver_adapter",
            "driver-adapter",
            robot.adapter_at,
            robot.adapter_heading,
            {"connectors": len(robot.legs)},
        )
    ]
    return {"modules": modules, "blockers": blockers, "free": free}


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


def gait_sequence_text(
    robot: Robot,
    *,
    repeat: int = 1,
    rate: float = 10.0,
    current_limit: float | None = 1200.0,
    result: GaitResult | None = None,
    reverse: bool = False,
    command: str | None = None,
) -> str:
    """The gait as a sequence file for ``origami-cad drive`` (TOML text).

    Each TSA's ``mapping`` (fold ratio to contraction, mm) is :func:`leg_contraction`
    sampled every 0.02 up to the blockers' fold ratio, so ``drive`` turns the gait's
    fold-ratio keyframes into the same turns as :func:`gait_turns` (between samples,
    linearly). With a simulated ``result``, each TSA also gets its ``load``: the torque
    the simulation needs of its servo over one cycle, N mm (:func:`gait_loads`), which a
    dry run's emulated servo carries. ``reverse`` writes the keyframes backwards (as
    ``simulate_gait(reverse=True)`` plays them); ``command`` is the command line that
    wrote the file, quoted in its header. ``current_limit`` (mA) stops a stalling servo.
    """
    p_max = robot.blocker_angle / 180.0
    samples = np.unique(np.r_[np.arange(0.0, p_max, 0.02), p_max, robot.gait_p.ravel()])
    source = robot.source.name if robot.source else "the robot file"
    lines = [
        f"# The gait of {one_line(source)} as TSA commands, written by origami-cad crawl: each",
        "# mapping is the model's string take-up (the leg folded rigidly about its crease,",
        "# strings measured through their holes), so fold ratios become motor turns;",
        "# each load is the TSA's torque in the simulated crawl (N mm, one cycle, the most",
        "# any simulated cycle needed), carried by the emulated servos of a dry run.",
        *([f"#   {one_line(command)}"] if command else []),
        "[sequence]",
        f"repeat = {repeat}",
        f"rate = {rate:g}              # Hz",
    ]
    if current_limit is not None:
        lines.append(f"current_limit = {current_limit:g}   # mA: a stalling TSA is stopped")
    loads = gait_loads(robot, result) if result is not None else None
    for k, leg in enumerate(robot.legs):
        tsa = leg.route.tsa
        c = leg_contraction(robot.pattern, leg, samples)
        pairs = ", ".join(f"[{p:.4f}, {v:.4f}]" for p, v in zip(samples, c, strict=True))
        lines += [
            "",
            "[[tsa]]",
            f"id = {leg.servo}",
            f"name = {toml_string(leg.name)}",
            f"length = {tsa.length:g}           # mm, twisted strands",
            f"radius = {tsa.radius:g}            # mm",
            f"max_helix_angle = {tsa.max_helix_angle:g}   # deg",
            f"mapping = [{pairs}]  # [p, mm]",
        ]
        if loads is not None:
            curve = ", ".join(
                f"[{t:g}, {v:.3f}]" for t, v in zip(loads[0], loads[1][:, k], strict=True)
            )
            lines.append(f"load = [{curve}]  # [t s, N mm]")
    t, ratios = robot.gait_t - robot.gait_t[0], robot.gait_p
    if reverse:
        t, ratios = t[-1] - t[::-1], ratios[::-1]
    for when, p in zip(t, ratios, strict=True):
        values = ", ".join(f"{v:g}" for v in p)
        lines += ["", "[[keyframe]]", f"t = {when:g}", f"p = [{values}]"]
    return "\n".join(lines) + "\n"


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
        Materials and loads (default: the printed sheet, gravity 9810 mm/s^2, the ground
        at z = 0 and the robot's friction coefficient).
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
    mu = robot.friction if friction is None else friction
    if params is None:
        params = SimulationParams(gravity=9810.0, ground=0.0, friction=mu)
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
