"""The crawler of the paper's Fig. 7, parametric: its crease pattern, routes and robot file.

:func:`crawler_files` draws the crawler of ``examples/crawler`` (docs/crawler.md) for the
design numbers of a :class:`CrawlerDesign` and returns data: the crease pattern, one
:class:`~origami_cad.strings.route.RouteSpec` per leg and the
:class:`~origami_cad.crawler.robot.Robot`. :func:`write_crawler` writes them through the
formats' one writers (``dump_route``, ``dump_robot``), with the comments of
:mod:`~origami_cad.crawler.design_notes`.
``examples/crawler/make_crawler.py`` is a thin caller: with the default numbers it
writes the committed ``crawler.fold``, ``route_*.toml`` and ``crawler.toml``.

The robot heads along +x. It is one printed sheet:

* a body panel, ``body_length`` x ``body_width`` mm, with a 6 mm notch in the middle of
  its front and rear edges so that no three vertices of its outline are collinear (the
  simulator triangulates panels as fans and the notch keeps every triangle proper);
* four legs, trapezoids ``leg_length`` mm long hinged to the body's front and rear edges
  by MOUNTAIN creases (a leg folds down under the body and lifts it), 85 mm wide at the
  hinge and flaring to ``foot_out`` mm (|y|) at the foot.

Each leg carries its own onboard TSA module (``tsa-module`` of the parts library) on its
top face, twist axis pointing at the body. The module's four strings leave the exit
guide, go down through four holes of the leg ``leg_hole`` mm from the hinge, run under
the mountain crease (DCQC: below a mountain) to four holes of the body ``body_hole`` mm
from the hinge, come up through them and are tied on top.

**Envelope.** The paper's robot is 340 x 320 x 122 mm (x, y, z). :func:`crawler_extent`
folds the legs rigidly (all four at one fold, the body level, the feet on the ground)
and measures the sheet and the leg modules (a box ``MODULE_HEIGHT`` tall over the module's
reach along the leg); :func:`check_envelope` refuses a design past the envelope at any
fold between the strings' floor (20 deg) and the blocker. The driver module's height on
the body is not modelled (its geometry is not in the parts library).

Units: mm, degrees, grams.
"""

from __future__ import annotations

import math
import os
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from origami_cad._fileio import atomic_write
from origami_cad.crawler.design_notes import HAND_GAIT, ROBOT_HEADER, robot_notes, route_header
from origami_cad.crawler.robot import PointMass, Robot, dump_robot, make_leg, with_gait
from origami_cad.errors import DesignError
from origami_cad.pattern import CreasePattern
from origami_cad.pattern.formats.fold import write_fold
from origami_cad.strings.route import RouteSpec, dump_route, route_from_tables

__all__ = [
    "ENVELOPE",
    "LEGS",
    "CrawlerDesign",
    "CrawlerFiles",
    "check_envelope",
    "crawler_extent",
    "crawler_files",
    "crawler_pattern",
    "leg_holes",
    "leg_route",
    "module_centre",
    "shell_for",
    "write_crawler",
]

#: The paper's robot: 340 x 320 x 122 mm (length x, width y, height z).
ENVELOPE = (340.0, 320.0, 122.0)
#: Notch depth at the middle of the front and rear edges, mm, and the legs' inner edge (|y|).
NOTCH, LEG_IN = 6.0, 15.0
#: The four strings' |y| across a leg, mm (evenly over the hinge's 85 mm).
STRING_Y = (25.0, 45.0, 65.0, 85.0)
#: TSA: twisted strands from hub to exit guide (the module's guide_distance), mm.
TSA_LENGTH, TSA_RADIUS, TSA_HELIX = 24.0, 0.6, 75.0
#: String exit above the leg's top face: the module's mount (1 mm) plus half the servo's
#: width (XL330: 20 mm), i.e. the twist axis's height, mm.
EXIT_HEIGHT = 11.0
#: The exit guide's distance from the module's centre along its twist axis:
#: 1 + hub 4 + guide_distance 24 + 1.5 (middle of the guide's hole), mm.
EXIT_OFFSET = 30.5
#: A servo's case centre lies this far behind its module's centre, away from the body, mm.
SERVO_BEHIND = 13.0
#: The module over the leg's top face, for the envelope: 1 mm mount + the XL330's 20 mm,
#: from the exit guide's outer edge (EXIT_OFFSET + 1.5) to the servo case's back
#: (SERVO_BEHIND + half its 34 mm), mm.
MODULE_HEIGHT, MODULE_FRONT, MODULE_BACK = 21.0, EXIT_OFFSET + 1.5, SERVO_BEHIND + 17.0
#: The printed panels' outer faces stop this far from a crease (the sheet's bias b), mm:
#: where the parts library centres a module (the inset outer face's centroid).
CREASE_INSET = 3.0
#: The printed sheet's height h (mm) and print layer (mm): the crease layer t and the TPU
#: shell s are whole layers, and eq. 6's sheet needs s < (h - t) / 2.
SHEET_HEIGHT, LAYER = 2.2, 0.1
#: The legs: label, servo ID, name, x sign (+1 front), y sign (+1 left).
LEGS = (
    ("leg_fl", 1, "front left", 1, 1),
    ("leg_fr", 2, "front right", 1, -1),
    ("leg_rl", 3, "rear left", -1, 1),
    ("leg_rr", 4, "rear right", -1, -1),
)
#: Strings' floor: the smallest fold of a leg, deg (docs/crawler.md, "Never flat").
FLOOR_DEG = 20.0


@dataclass(frozen=True)
class CrawlerDesign:
    """The crawler's design numbers (mm, deg). The defaults are ``examples/crawler``.

    Attributes
    ----------
    body_length, body_width : float
        The body panel along x and y, mm.
    leg_length : float
        A leg from its hinge to its foot, mm.
    foot_out, foot_in : float
        |y| of a foot's outer and inner corner, mm (``2 foot_out`` is the robot's width).
    leg_hole, body_hole : float
        Distance of the leg's and of the body's string holes from the hinge, mm.
    blocker_angle : float
        The blockers on the leg creases, deg (the paper's: up to 60).
    crease_thickness : float
        The printed crease layer t (TPU), mm: the crease's bending stiffness is
        ``E t^3 / (12 w)``. With t = 0.4 and s = 0.8 (the paper's sheet) the routes carry no
        ``[fabrication]`` table; otherwise they do, and the simulation and the printed
        robot take it.
    shell : float
        The TPU shell s on the panels' faces, mm (eq. 6's sheet needs s < (h - t) / 2).
    """

    body_length: float = 180.0
    body_width: float = 200.0
    leg_length: float = 90.0
    foot_out: float = 160.0
    foot_in: float = 20.0
    leg_hole: float = 12.0
    body_hole: float = 30.0
    blocker_angle: float = 60.0
    crease_thickness: float = 0.4
    shell: float = 0.8

    def __post_init__(self) -> None:
        checks = (
            ("body_length", self.body_length, 2 * (self.body_hole + 20.0), 1000.0),
            ("body_width", self.body_width, 2 * (max(STRING_Y) + 5.0), 1000.0),
            ("leg_length", self.leg_length, MODULE_FRONT + MODULE_BACK + 10.0, 1000.0),
            ("foot_out", self.foot_out, self.body_width / 2 + 1.0, 1000.0),
            ("foot_in", self.foot_in, 0.0, LEG_IN + 20.0),
            ("leg_hole", self.leg_hole, 2.0, self.leg_length / 2),
            ("body_hole", self.body_hole, 2.0 * NOTCH, self.body_length / 2 - 20.0),
            ("blocker_angle", self.blocker_angle, FLOOR_DEG + 5.0, 60.0),
            ("crease_thickness", self.crease_thickness, 0.2, SHEET_HEIGHT - 2 * LAYER),
            ("shell", self.shell, LAYER, 2.0),
        )
        for name, value, low, high in checks:
            if not (math.isfinite(value) and low - 1e-9 <= value <= high + 1e-9):
                raise DesignError(
                    f"crawler design: {name} = {value:g} is outside {low:g} .. {high:g}"
                )
        if self.shell >= (SHEET_HEIGHT - self.crease_thickness) / 2 - 1e-9:
            raise DesignError(
                f"crawler design: shell s = {self.shell:g} mm must be thinner than a panel "
                f"half (h - t) / 2 = {(SHEET_HEIGHT - self.crease_thickness) / 2:g} mm"
            )

    @property
    def paper_sheet(self) -> bool:
        """Whether the sheet is the paper's (t = 0.4, s = 0.8 mm): no ``[fabrication]``."""
        return abs(self.crease_thickness - 0.4) < 1e-9 and abs(self.shell - 0.8) < 1e-9

    def to_dict(self) -> dict[str, float]:
        """The design numbers for a JSON file (mm, deg)."""
        out = asdict(self)
        return {f"{k}_deg" if k == "blocker_angle" else f"{k}_mm": v for k, v in out.items()}


def shell_for(crease_thickness: float) -> float:
    """The TPU shell (mm) for crease layer ``crease_thickness``: the paper's 0.8 mm, or the
    thickest whole layer that leaves the panel halves ((h - t) / 2) one layer of infill, as
    the paper's sheet does (0.9 - 0.8 = 0.1 mm).

    >>> shell_for(0.4), shell_for(0.5), shell_for(0.7), shell_for(0.8)
    (0.8, 0.7, 0.6, 0.6)
    """
    room = (SHEET_HEIGHT - crease_thickness) / 2.0 - LAYER
    return round(min(0.8, math.floor(room / LAYER + 1e-6) * LAYER), 3)


def crawler_pattern(design: CrawlerDesign | None = None) -> CreasePattern:
    """The crease pattern: one body panel and four legs on mountain creases (mm)."""
    d = design or CrawlerDesign()
    bx, by = d.body_length / 2.0, d.body_width / 2.0
    verts = [
        (-bx, -by),  # 0
        (bx, -by),  # 1
        (bx, -LEG_IN),  # 2
        (bx - NOTCH, 0.0),  # 3 front notch
        (bx, LEG_IN),  # 4
        (bx, by),  # 5
        (-bx, by),  # 6
        (-bx, LEG_IN),  # 7
        (-bx + NOTCH, 0.0),  # 8 rear notch
        (-bx, -LEG_IN),  # 9
    ]
    edges = [(i, (i + 1) % 10) for i in range(10)]
    assign = ["B"] * 10
    # leg creases: front right 1-2, front left 4-5, rear left 6-7, rear right 9-0
    for e in ((1, 2), (4, 5), (6, 7), (9, 0)):
        assign[edges.index(e)] = "M"
    foot = bx + d.leg_length
    for hinge, (sx, sy) in (
        ((4, 5), (1, 1)),
        ((1, 2), (1, -1)),
        ((6, 7), (-1, 1)),
        ((9, 0), (-1, -1)),
    ):
        a, b = hinge
        # the foot's corners next to a and b: the outer one flares to foot_out
        tip = []
        for v in (a, b):
            y = verts[v][1]
            tip.append((sx * foot, sy * (d.foot_out if abs(y) > LEG_IN else d.foot_in)))
        ia = len(verts)
        verts += [tip[0], tip[1]]
        edges += [(a, ia), (ia, ia + 1), (ia + 1, b)]
        assign += ["B", "B", "B"]
    cp = CreasePattern(verts, edges, assign, metadata={"title": "crawler"})
    labels = []
    for fi in range(len(cp.faces)):
        cx, cy = cp.face_centroids()[fi]
        if abs(cx) < bx:
            labels.append("body")
        else:
            labels.append(("leg_f" if cx > 0 else "leg_r") + ("l" if cy > 0 else "r"))
    return cp.with_face_labels(labels)


def leg_holes(
    design: CrawlerDesign, sx: int, sy: int
) -> tuple[list[tuple[float, float]], list[tuple[float, float]]]:
    """The four holes of a leg and the four matching holes of the body, (x, y) mm."""
    hinge = design.body_length / 2.0
    leg = [(sx * (hinge + design.leg_hole), sy * y) for y in STRING_Y]
    body = [(sx * (hinge - design.body_hole), sy * y) for y in STRING_Y]
    return leg, body


def module_centre(cp: CreasePattern, label: str) -> tuple[float, float]:
    """Where the parts library centres a TSA module on a leg: the centroid of the leg's
    outer face (the panel inset ``CREASE_INSET`` from its crease) inset by 1 mm, mm.

    The same point as ``plan_panels(cp).outline(label)`` buffered by -1 mm
    (``tests/test_crawler_design.py`` checks it).
    """
    import shapely

    ring = cp.vertices[cp.faces[cp.face_index(label)]]
    sx = 1.0 if ring[:, 0].mean() > 0 else -1.0
    hinge = float(np.min(sx * ring[:, 0]))  # the crease is the leg's edge nearest the body
    panel = shapely.Polygon(ring)
    keep = shapely.box(hinge + CREASE_INSET, -1e4, 1e4, 1e4)
    outer = panel.intersection(shapely.affinity.scale(keep, xfact=sx, origin=(0, 0)))
    foot = outer.buffer(-1.0, join_style="mitre")
    return float(foot.centroid.x), float(foot.centroid.y)


def _decimals(value: float, digits: int) -> float:
    """``value`` rounded to ``digits`` decimals, as the route files give them (mm)."""
    return float(f"{value:.{digits}f}")


def leg_route(cp: CreasePattern, design: CrawlerDesign, leg: tuple) -> RouteSpec:
    """The route of one leg's TSA (``leg``: a row of ``LEGS``): four strings from the
    module's exit guide (anchor mm, 3 decimals) down through the leg's holes and up
    through the body's (mm, 1 decimal), under the mountain crease; the printed sheet's
    ``[fabrication]`` when it is not the paper's. Checked as a route file is."""
    label, _, _, sx, sy = leg
    cx, cy = module_centre(cp, label)
    ax = cx - sx * EXIT_OFFSET  # the twist axis points at the body (heading 180 deg front)
    anchor = [_decimals(ax, 3), _decimals(cy, 3), EXIT_HEIGHT]
    strings = [
        {"anchor_panel": label, "anchor": anchor, "sides": ["top", "bottom"],
         "holes": [[_decimals(v, 1) for v in hole] for hole in pair]}
        for pair in zip(*leg_holes(design, sx, sy), strict=True)
    ]  # fmt: skip
    tables: dict = {
        "tsa": {"model": "onboard", "length": TSA_LENGTH, "radius": TSA_RADIUS,
                "max_helix_angle": TSA_HELIX},
        "route": {"thickness": SHEET_HEIGHT, "step": 20.0, "max_turns": 8, "strings": strings},
    }  # fmt: skip
    if not design.paper_sheet:
        tables["fabrication"] = {"height": SHEET_HEIGHT, "thickness": design.crease_thickness,
                                 "shell": design.shell}  # fmt: skip
    return route_from_tables(tables, cp, f"the {label} route")


@dataclass(frozen=True)
class CrawlerFiles:
    """A crawler as data: its design, crease pattern, routes and robot.

    ``routes`` maps each route file's name (``route_fl.toml``...) to its
    :class:`~origami_cad.strings.route.RouteSpec`; ``robot`` is the
    :class:`~origami_cad.crawler.robot.Robot` of ``crawler.toml``, which names
    ``crawler.fold`` and the routes; ``notes`` its comments by table and ``headers`` the
    route files' first lines. :meth:`texts` gives the files' texts.
    """

    design: CrawlerDesign
    pattern: CreasePattern
    routes: dict[str, RouteSpec]
    robot: Robot
    notes: dict[str, str]
    headers: dict[str, str]

    def texts(self) -> dict[str, str]:
        """Each TOML file's text by name: the routes (``dump_route``), then ``crawler.toml``
        (``dump_robot``)."""
        out = {
            name: dump_route(spec, self.pattern, header=self.headers[name])
            for name, spec in self.routes.items()
        }
        out["crawler.toml"] = dump_robot(self.robot, header=ROBOT_HEADER, notes=self.notes)
        return out


def crawler_files(
    design: CrawlerDesign | None = None,
    gait: tuple[np.ndarray, np.ndarray] | None = None,
    *,
    envelope: tuple[float, float, float] | None = ENVELOPE,
    header: str | None = None,
) -> CrawlerFiles:
    """The crawler of ``design`` as data (see the module docstring).

    Parameters
    ----------
    design : CrawlerDesign, optional
        The design numbers (default: ``examples/crawler``'s).
    gait : (times (K,) s, fold ratios (K, 4)), optional
        The robot file's gait (default: the hand gait of ``examples/crawler``, 30 -> 55 deg,
        which a blocker below 56 deg refuses).
    envelope : (x, y, z) mm or None
        Refuse a design past it (:func:`check_envelope`, between the strings' floor and
        the blocker); ``None`` checks nothing (``examples/crawler`` as built is 349 mm
        long at its 20 deg rest, over the paper's 340 mm).
    header : str, optional
        The comment lines before the robot file's gait (default: ``examples/crawler``'s).

    Raises
    ------
    DesignError
        The design is past ``envelope``, naming the dimension, the fold and the limit.
    SimulationError
        The gait folds a leg past the blockers, naming the keyframe and the leg.
    """
    d = design or CrawlerDesign()
    if envelope is not None:
        check_envelope(d, FLOOR_DEG, d.blocker_angle, envelope)
    cp = crawler_pattern(d)
    near = module_centre(cp, "leg_fl")[0] - d.body_length / 2.0 - MODULE_FRONT
    if d.leg_hole > near:
        raise DesignError(
            f"crawler design: leg_hole = {d.leg_hole:g} mm is under the leg's TSA module "
            f"(it starts {near:.1f} mm from the hinge)"
        )
    routes, headers, legs = {}, {}, []
    masses = [PointMass("driver module", "body", (0.0, 0.0), 109.71)]
    for leg in LEGS:
        label, servo, name, sx, _ = leg
        file = f"route_{label[4:]}.toml"
        routes[file] = leg_route(cp, d, leg)
        headers[file] = route_header(d, name, servo, label)
        legs.append(make_leg(cp, "body", label, routes[file], servo, name, file))
        cx, cy = module_centre(cp, label)
        at = (float(round(cx + sx * SERVO_BEHIND)), float(round(cy)))
        masses.append(PointMass(f"servo {name}", label, at, 18.0))
    holes = tuple(dict.fromkeys(p for r in routes.values() for s in r.strings for p in s.points))
    times, ratios = HAND_GAIT if gait is None else gait
    robot = Robot(cp, "body", tuple(legs), float(d.blocker_angle), 0.6, holes, tuple(masses),
                  (0.0, 0.0), 0.0, times, ratios, None, Path("crawler.fold"))  # fmt: skip
    robot = with_gait(robot, times, ratios, where="the crawler's gait")
    notes = robot_notes(d, module_centre(cp, "leg_fl"), gait is None, header)
    return CrawlerFiles(d, cp, routes, robot, notes, headers)


def write_crawler(files: CrawlerFiles, folder: str | os.PathLike[str]) -> Path:
    """Write ``crawler.fold``, the routes and ``crawler.toml`` into ``folder`` (each file
    whole or not at all); the robot file's path."""
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    texts = files.texts()  # every text first: a refused value writes nothing
    write_fold(files.pattern, out / "crawler.fold")
    for name, text in texts.items():
        with atomic_write(out / name, "w", encoding="utf-8") as fh:
            fh.write(text)
    return out / "crawler.toml"


def crawler_extent(design: CrawlerDesign, fold_deg: float) -> tuple[float, float, float]:
    """The robot's extent (x, y, z) mm with every leg folded rigidly by ``fold_deg``.

    The body stays level, the feet on the ground; the sheet is ``SHEET_HEIGHT`` thick and
    each leg module a box ``MODULE_HEIGHT`` tall over its reach along the leg (from
    ``MODULE_FRONT`` before its centre to ``MODULE_BACK`` behind it).
    """
    d, th = design, math.radians(fold_deg)
    cp = crawler_pattern(d)
    cx, _ = module_centre(cp, "leg_fl")
    centre = cx - d.body_length / 2.0  # the module's centre from the hinge, along the leg
    h, c, s = SHEET_HEIGHT, math.cos(th), math.sin(th)
    lift = d.leg_length * s  # the hinge's height over the feet
    # a point at distance u along the leg, v above its top face: x past the hinge, z
    reach = [u * c + v * s for u in (centre - MODULE_FRONT, centre + MODULE_BACK)
             for v in (0.0, h / 2 + MODULE_HEIGHT)]  # fmt: skip
    reach += [d.leg_length * c + h / 2 * s]
    tops = [lift - u * s + v * c for u in (centre - MODULE_FRONT, centre + MODULE_BACK)
            for v in (h / 2 + MODULE_HEIGHT,)]  # fmt: skip
    length = d.body_length + 2.0 * max(reach)
    height = max(max(tops), lift + h / 2) + h / 2  # the mid-surface's feet at h / 2
    return length, 2.0 * d.foot_out, height


def check_envelope(
    design: CrawlerDesign,
    low_deg: float = FLOOR_DEG,
    high_deg: float | None = None,
    envelope: tuple[float, float, float] = ENVELOPE,
) -> tuple[float, float, float]:
    """The largest extent (x, y, z) mm over folds ``low_deg`` .. ``high_deg`` (default the
    blocker); raises :class:`DesignError` naming the dimension and fold past ``envelope``."""
    high = design.blocker_angle if high_deg is None else high_deg
    folds = np.linspace(low_deg, high, 9)
    extents = np.array([crawler_extent(design, f) for f in folds])
    for k, name in enumerate(("length (x)", "width (y)", "height (z)")):
        i = int(np.argmax(extents[:, k]))
        if extents[i, k] > envelope[k] + 1e-6:
            raise DesignError(
                f"crawler design (body {design.body_length:g} mm, legs "
                f"{design.leg_length:g} mm): {name} {extents[i, k]:.1f} mm at legs folded "
                f"{folds[i]:.0f} deg is over the envelope's {envelope[k]:g} mm "
                f"({envelope[0]:g} x {envelope[1]:g} x {envelope[2]:g} mm)"
            )
    return tuple(float(v) for v in extents.max(axis=0))
