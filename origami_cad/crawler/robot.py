"""The legged robot: the robot file, its legs, point masses, gait keyframes and parts.

A robot file (TOML, see ``examples/crawler/crawler.toml``) names a crease pattern, one
route file per leg (an onboard TSA on that leg, ``anchor_panel``), blockers on the leg
creases, point masses (servos, the driver module) and a gait: keyframes of fold ratios,
one per leg. :func:`load_robot` reads it into a :class:`Robot` (errors name the file,
table and key), :func:`dump_robot` writes it back, and :func:`robot_placements` gives the
parts the printed robot carries (``origami_cad.parts.robot.robot_assembly``). Walking it
in simulation is ``origami_cad.crawler.walk``'s.

Units: mm, grams, seconds; degrees at the edges. A leg's fold ratio is
``p = |fold angle| / 180 deg`` of its hinge crease.
"""

from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad._args import Arg, checked
from origami_cad._names import path_component
from origami_cad._toml import Table, finite_toml, load_toml, toml_table
from origami_cad.errors import PatternError, SimulationError, StringsError
from origami_cad.pattern.io import read_pattern
from origami_cad.pattern.model import CreasePattern
from origami_cad.strings.route import RouteSpec, load_route, route_sheet

__all__ = [
    "MOUNT_MARGIN",
    "MOUNT_THICKNESS",
    "PAPER_CRAWL_MM",
    "SERVO",
    "Leg",
    "PointMass",
    "Robot",
    "dump_robot",
    "is_robot_file",
    "leg_heading",
    "leg_key",
    "load_gait",
    "load_robot",
    "make_leg",
    "robot_placements",
    "with_gait",
]

#: The paper's crawler: mm forward per 32 s gait cycle on a PVC mat.
PAPER_CRAWL_MM = 63.0


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

    def sheet(self, **fields):
        """The printed sheet (``FabricationParams``): the first leg's route's
        ``[fabrication]`` (crease thickness, shell), else the paper's; ``fields`` replaced."""
        return route_sheet(self.legs[0].route, **fields)

    @property
    def cycle(self) -> float:
        """Duration of one gait cycle, s."""
        return float(self.gait_t[-1] - self.gait_t[0])


def _shared_crease(cp: CreasePattern, a: int, b: int) -> int | None:
    ef = cp.edge_faces()
    hit = np.flatnonzero(((ef[:, 0] == a) & (ef[:, 1] == b)) | ((ef[:, 0] == b) & (ef[:, 1] == a)))
    hit = [int(e) for e in hit if cp.assignments[e] in ("M", "V")]
    return hit[0] if len(hit) == 1 else None


def make_leg(
    cp: CreasePattern,
    body: str,
    panel: str,
    route: RouteSpec,
    servo: int,
    name: str | None = None,
    route_path: str | os.PathLike[str] | None = None,
) -> Leg:
    """The :class:`Leg` on panel ``panel`` of ``cp``, hinged to panel ``body`` by the one
    crease they share, folded by ``route`` (an onboard TSA) on servo ID ``servo``;
    ``name`` defaults to the panel label, ``route_path`` is the route file
    :func:`dump_robot` names (a relative path is written as it is). Raises
    :class:`SimulationError` naming the panel that is not a leg of ``body``."""
    labels = cp.face_labels
    for label in (panel, body):
        if label not in labels:
            raise SimulationError(f"leg {panel!r}: no panel labelled {label!r}")
    face = cp.face_index(panel)
    crease = _shared_crease(cp, face, cp.face_index(body))
    if crease is None:
        raise SimulationError(f"leg {panel!r}: it does not share one crease with {body!r}")
    if route.tsa.model != "onboard":
        raise SimulationError(f"leg {panel!r}: a leg's TSA must be onboard")
    where = None if route_path is None else Path(route_path)
    return Leg(panel, face, crease, route, int(servo), name or panel, where)


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
        path_component(name)  # as given: leading or trailing spaces are refused too
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


@checked(SimulationError, path=Arg("path", optional=False))
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


def with_gait(robot: Robot, times, ratios, *, where: str | None = None) -> Robot:
    """``robot`` with another gait: keyframe times ``times (K,)`` s and fold ratios
    ``ratios (K, legs)``, checked as the robot file's gait is (times increasing, every
    ratio in [0, 1) and within the blockers' ``blocker_angle``, deg); raises
    :class:`SimulationError` naming ``where`` (the gait's file) and the limit, never clips."""
    t = np.asarray(times, dtype=float)
    p = np.atleast_2d(np.asarray(ratios, dtype=float))
    where = where or f"gait of {robot.source.name if robot.source else 'the robot'}"
    if t.ndim != 1 or len(t) < 2 or p.shape != (len(t), len(robot.legs)):
        raise SimulationError(
            f"{where}: expected at least two keyframes of {len(robot.legs)} fold ratios, "
            f"got times {t.shape} and ratios {p.shape}"
        )
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(p))):
        raise SimulationError(f"{where}: keyframe times and fold ratios must be finite")
    if np.any(np.diff(t) <= 0) or t[0] < 0:
        raise SimulationError(f"{where}: keyframe times must start at 0 s or later and increase")
    _check_blocker(where, t, p, robot.blocker_angle, [leg.name for leg in robot.legs])
    return dataclasses.replace(robot, gait_t=t, gait_p=p)


def _check_blocker(
    where: str, times: np.ndarray, ratios: np.ndarray, blocker: float, names: list[str]
) -> None:
    """Refuse fold ratios outside [0, 1) or past the blockers' ``blocker`` deg, naming the
    first keyframe (its time, s) and leg that is."""
    if np.any(ratios < 0) or np.any(ratios >= 1):
        raise SimulationError(f"{where}: fold ratios p must lie in [0, 1)")
    limit = blocker / 180.0
    over = np.argwhere(ratios > limit + 1e-9)
    if len(over):
        k, j = (int(i) for i in over[0])
        raise SimulationError(
            f"{where}: keyframe #{k + 1} (t = {float(times[k]):g} s): p = {float(ratios[k, j]):g} "
            f"folds leg {names[j]!r} past its blocker ({blocker:g} deg = p {limit:.3f})"
        )


def is_robot_file(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is a robot file: a readable TOML file with a ``[robot]`` table."""
    import tomllib

    try:  # a FIFO or a device would block, or never end: its reader refuses it
        if Path(path).suffix.lower() != ".toml" or not Path(path).is_file():
            return False
        data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError):  # ValueError: bad UTF-8, TOML, a NUL
        return False
    return isinstance(data.get("robot"), dict)


@checked(
    SimulationError,
    path=Arg("path", optional=False),
    robot=Arg("object", types=(Robot,), optional=False),
)
def load_gait(path: str | os.PathLike[str], robot: Robot) -> Robot:
    """``robot`` with the gait of a gait file (``design-gait``'s ``gait.toml``, or any
    sequence file for ``drive`` whose ``[[tsa]]`` ids are the robot's servos in leg order).

    Its ``[[keyframe]]`` tables give ``t`` (s) and ``p`` (one fold ratio per leg); a
    gait past the blockers is refused with the limit (:class:`SimulationError`, naming
    the file and keyframe); ``[sequence]`` and the ``[[tsa]]`` mappings are ``drive``'s.
    """
    p = Path(path)
    top = Table(load_toml(p, SimulationError), str(p), SimulationError)
    frames, tsas = top.data.get("keyframe"), top.data.get("tsa", [])
    top.used.update(("keyframe", "tsa", "sequence"))
    top.finish()
    if not isinstance(frames, list) or len(frames) < 2:
        raise SimulationError(f"{p}: a gait needs at least two [[keyframe]] tables")
    ids = [t.get("id") if isinstance(t, dict) else None for t in tsas]
    servos = [leg.servo for leg in robot.legs]
    if tsas and ids != servos:
        raise SimulationError(
            f"{p}: [[tsa]] ids {ids} are not the robot's servos {servos} (leg order)"
        )
    times, ratios = [], []
    for i, item in enumerate(frames):
        t = Table(item, f"{p} [[keyframe]] #{i + 1}", SimulationError)
        times.append(t.number("t", low=0))
        ratios.append(t.numbers("p", length=len(robot.legs)))
        t.finish()
    return with_gait(robot, times, ratios, where=str(p))


def _relative(path: Path | None, folder: Path, what: str) -> str:
    """``path`` relative to ``folder`` (a relative ``path`` is taken as it is)."""
    if path is None:
        raise SimulationError(f"the robot's {what} has no file to name")
    if not Path(path).is_absolute():
        return Path(path).as_posix()
    return Path(os.path.relpath(path, folder)).as_posix()


#: The tables :func:`dump_robot` may put a note before, in the file's order.
NOTE_TABLES = ("robot", "fabrication", "leg", "mass", "adapter", "gait")


def _note(notes: dict[str, str] | None, table: str) -> list[str]:
    """The comment lines before the first ``table``: each line of its note after ``# ``."""
    text = (notes or {}).get(table)
    return [f"# {line}".rstrip() for line in text.splitlines()] if text else []


def dump_robot(
    robot: Robot,
    folder: str | os.PathLike[str] | None = None,
    *,
    header: str = "",
    notes: dict[str, str] | None = None,
) -> str:
    """A robot file (TOML text) of ``robot`` that :func:`load_robot` reads back: the robot
    format's one writer.

    The pattern and route files are named relative to ``folder``, where the robot file
    goes (default: the folder it was read from; a relative path is written as it is);
    lengths mm, angles deg, masses g, times s. The ``[fabrication]`` holes are written
    only when they are not the routes' holes. ``header`` (comment lines, ``#`` and all)
    opens the file; ``notes`` maps a table of :data:`NOTE_TABLES` to the comment put
    before its first table (plain text, each line written after ``# ``).

    >>> robot = load_robot("examples/crawler/crawler.toml")
    >>> text = dump_robot(robot, notes={"gait": "one 32 s cycle"})
    >>> 'pattern = "crawler.fold"' in text and 'route = "route_fl.toml"' in text
    True
    >>> "# one 32 s cycle\\n[gait]" in text
    True
    """
    unknown = set(notes or {}) - set(NOTE_TABLES)
    if unknown:
        raise SimulationError(
            f"robot file notes: no table {sorted(unknown)[0]!r} (one of {', '.join(NOTE_TABLES)})"
        )
    base = Path(folder) if folder is not None else (robot.source or Path("x")).parent
    base = base.resolve()
    lines = [header.rstrip("\n")] if header else []
    head = {
        "pattern": _relative(robot.pattern_path, base, "pattern"),
        "body": robot.body,
        "blocker_angle": float(robot.blocker_angle),
        "friction": float(robot.friction),
    }
    lines += [*_note(notes, "robot"), *toml_table("robot", head, comments={"blocker_angle": "deg"})]
    routed = tuple(
        dict.fromkeys(p for leg in robot.legs for s in leg.route.strings for p in s.points)
    )
    if tuple(robot.holes) != routed:
        holes = {"holes": [list(h) for h in robot.holes]}
        lines += ["", *_note(notes, "fabrication")]
        lines += toml_table("fabrication", holes, comments={"holes": "mm"})
    elif _note(notes, "fabrication"):  # the note alone: why there is no holes list
        lines += ["", *_note(notes, "fabrication")]
    for k, leg in enumerate(robot.legs):
        route = _relative(leg.route_path, base, f"leg {leg.name!r}'s route")
        table = {"panel": leg.panel, "route": route, "servo": leg.servo, "name": leg.name}
        note = _note(notes, "leg") if k == 0 else []
        lines += ["", *note, *toml_table("leg", table, array=True)]
    for k, m in enumerate(robot.masses):
        table = {"name": m.name, "panel": m.panel, "at": list(m.at), "grams": float(m.grams)}
        note = _note(notes, "mass") if k == 0 else []
        lines += ["", *note, *toml_table("mass", table, array=True, comments={"at": "mm"})]
    adapter = {"at": list(robot.adapter_at), "heading": float(robot.adapter_heading)}
    lines += ["", *_note(notes, "adapter"), *toml_table("adapter", adapter,
              comments={"heading": "deg"})]  # fmt: skip
    lines += ["", *_note(notes, "gait"), "[gait]"]
    for t, p in zip(robot.gait_t, robot.gait_p, strict=True):
        frame = {"t": float(t), "p": [float(v) for v in p]}
        lines += toml_table("gait.keyframe", frame, array=True, comments={"t": "s"})
    return finite_toml("\n".join(lines) + "\n", "the robot file", SimulationError)


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
