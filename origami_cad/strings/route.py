"""String routing through panel holes by the DCQC principle.

Route file (TOML)::

    [tsa]
    model = "ring"            # or "onboard" (length, radius, max_helix_angle)
    d1 = 10.0                 # mm, rotation diameter
    d2 = 8.0                  # mm, distance of the two first-entry holes
    string_width = 0.5        # mm
    [fabrication]             # optional: the printed sheet (eq. 6 gives its fold limit)
    bias = 3.0                # mm, b
    height = 2.2              # mm, h (also the default route thickness)
    thickness = 0.4           # mm, t (crease layer)
    shell = 0.8               # mm, s: the TPU shell, s < (h - t) / 2
    midlayer_bias = 0.5       # mm, m
    hole_diameter = 2.0       # mm, the printed string holes (written when not 2 mm)
    [route]
    thickness = 2.2           # mm, panel thickness: hole exits sit half of it off the sheet
    hole_diameter = 2.0       # mm, for holes placed automatically (panel labels)
    take_up = 0.1             # mm of string the TSA takes up per quasi-static step
    step = 180.0              # deg: the TSA turns at most this much per step
    max_turns = 20.0          # TSA turns at most
    max_tension = 50.0        # N, optional: stop when a string pulls harder
    max_torque = 20.0         # N mm, optional: stop when the TSA needs more (e.g. stall torque)
    p0 = 0.0                  # initial fold ratio
    p_max = 0.5               # optional fold limit; default: the printed sheet's limit when
                              # [fabrication] is given (first crease at eq. 6, legs
                              # included), else the largest ratio the pattern's folder takes
    fixed_panel = "c0r0s0"    # optional: this panel is held (default: the sheet keeps its
                              # mean pose, as a sheet free on the ring and pulled evenly)
    [[route.strings]]
    anchor = [60.0, -10.0, 20.0]          # A: where the string leaves the TSA, mm
    # anchor_panel = "c0r0s0"             # optional: the TSA rides on this panel (onboard);
                                          # anchor = [x, y, height above its top face]
    holes = ["c0r0s2", "c0r1s2"]          # panel labels (auto hole) or [x, y] points
    sides = "auto"                        # or ["top", "bottom", ...], one per hole

``sides[k]`` is the face of the sheet along which the string reaches hole
``k`` (from the anchor for ``k = 0``). The DCQC rule: between holes in two
panels sharing a mountain (valley) crease the string runs below (above) the
crease, on the side where the fold closes, so shortening the string folds it.
``"auto"`` applies the rule (and keeps the previous side between panels that
share no crease; the first segment takes the anchor's side); given sides that
break it are reported per segment.
"""

from __future__ import annotations

import functools
import math
import os
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from origami_cad._args import Arg, checked
from origami_cad._toml import MAX_MAGNITUDE, Table, finite_toml, load_toml, toml_table
from origami_cad.errors import StringsError
from origami_cad.fabrication.params import FabricationParams
from origami_cad.pattern.model import CreasePattern
from origami_cad.strings.tsa import TSAParams

__all__ = [
    "RouteSpec",
    "StringRoute",
    "anchor_points",
    "auto_holes",
    "cutting_segments",
    "dump_route",
    "frame_orientation",
    "hole_exits",
    "hole_frames",
    "load_route",
    "mean_pose",
    "panel_frame",
    "parse_route",
    "rigid_fit",
    "route_from_pattern",
    "route_from_tables",
    "route_sheet",
    "side_rule",
    "string_lengths",
    "string_path",
]

TOP, BOTTOM = 1, -1
_SIDE_NAMES = {"top": TOP, "bottom": BOTTOM}


@dataclass(frozen=True)
class StringRoute:
    """One string: anchor (mm, 3D), holes on panels, and the side of each segment."""

    anchor: tuple[float, float, float]
    faces: tuple[int, ...]
    points: tuple[tuple[float, float], ...]
    sides: tuple[int, ...]
    names: tuple[str, ...]
    violations: tuple[str, ...] = ()
    anchor_face: int = -1  # >= 0: the anchor rides on this panel, anchor = (x, y, height)
    bad_segments: tuple[int, ...] = ()  # segments k (hole k-1 -> hole k) breaking the DCQC rule


@dataclass(frozen=True)
class RouteSpec:
    """A routing: the TSA, the strings and the simulation settings (mm, radians inside).

    ``take_up`` is the string (mm) the TSA takes up per quasi-static step (the
    largest over the strings), ``step`` the largest TSA rotation per step
    (radians), ``max_tension`` (N) and ``max_torque`` (N mm) limits that stop
    the folding, ``p_max`` an explicit fold limit (None: see
    :func:`~origami_cad.strings.dcqc.fold_limit`) and ``fabrication`` the
    printed sheet whose eq. 6 limits every crease.
    """

    tsa: TSAParams
    strings: tuple[StringRoute, ...]
    thickness: float = 2.2
    step: float = math.radians(2.0)
    max_turns: float = 20.0
    p0: float = 0.0
    p_max: float | None = None
    notes: tuple[str, ...] = field(default=())
    fixed_panel: str | None = None
    take_up: float = 0.1
    max_tension: float = math.inf
    max_torque: float = math.inf
    fabrication: FabricationParams | None = None

    @property
    def violations(self) -> list[str]:
        return [v for s in self.strings for v in s.violations]


def side_rule(cp: CreasePattern, face_a: int, face_b: int) -> int | None:
    """DCQC side between two panels: top for a shared valley, bottom for a mountain, else None."""
    ef = cp.edge_faces()
    shared = np.flatnonzero(
        ((ef[:, 0] == face_a) & (ef[:, 1] == face_b))
        | ((ef[:, 0] == face_b) & (ef[:, 1] == face_a))
    )
    kinds = {str(cp.assignments[e]) for e in shared}
    if "V" in kinds and "M" not in kinds:
        return TOP
    if "M" in kinds and "V" not in kinds:
        return BOTTOM
    return None


def auto_holes(cp: CreasePattern, hole_diameter: float) -> dict[str, tuple[float, float]]:
    """The automatic hole of every panel, as fabrication places them, by panel label.

    ``hole_diameter`` in mm; the centres ``(x, y)`` in mm, from
    :func:`origami_cad.fabrication.plan_panels` (no solids are built).
    """
    from origami_cad.fabrication import FabricationParams, plan_panels

    plan = plan_panels(cp, FabricationParams(hole_diameter=hole_diameter))
    return {label: (hs[0].x, hs[0].y) for label, hs in plan.holes_by_label().items()}


@checked(
    StringsError,
    path=Arg("path", optional=False),
    cp=Arg("object", types=(CreasePattern,), optional=False),
)
def load_route(path: str | os.PathLike[str], cp: CreasePattern) -> RouteSpec:
    """Read a route file for the pattern ``cp``; errors name the file, key and string."""
    p = Path(path)
    return _route_from_data(load_toml(p, StringsError), str(p), cp)


def parse_route(text: str, cp: CreasePattern, name: str = "route.toml") -> RouteSpec:
    """A route from its TOML text (as :func:`load_route` reads a file); writes nothing.

    Parameters
    ----------
    text : str
        The route file's text (lengths mm, angles deg).
    cp : CreasePattern
        The pattern the route threads.
    name : str
        What errors call the text (a file name).

    Returns
    -------
    RouteSpec
        The route; errors (``StringsError``) name ``name``, the key and the string.

    Examples
    --------
    >>> from pathlib import Path
    >>> from origami_cad.pattern.design import load_design
    >>> cp = load_design("examples/miura_6x4.toml").pattern
    >>> text = Path("examples/miura_route.toml").read_text()
    >>> parse_route(text, cp) == load_route("examples/miura_route.toml", cp)
    True
    """
    import tomllib

    try:
        data = tomllib.loads(text)
    except (tomllib.TOMLDecodeError, RecursionError) as exc:
        raise StringsError(f"{name}: not valid TOML: {exc}") from None
    return _route_from_data(data, name, cp)


def route_from_tables(data: dict, cp: CreasePattern, where: str = "route") -> RouteSpec:
    """A route from its tables as plain data: ``{"tsa": {...}, "fabrication": {...},
    "route": {..., "strings": [...]}}``, the keys and units of a route file (mm, deg).

    Checked as a route file is (automatic holes by panel label, ``sides = "auto"``, ...);
    errors (``StringsError``) name ``where``. :func:`dump_route` writes the result.
    """
    return _route_from_data(data, where, cp)


def _route_from_data(data: dict, where: str, cp: CreasePattern) -> RouteSpec:
    """The route of a parsed route file; ``where`` names it in errors."""
    p = where
    top = Table(data, where, StringsError)
    tsa_t = top.table("tsa", {})
    fab_t = top.table("fabrication") if top.has("fabrication") else None
    route = top.table("route")
    top.finish()
    fabrication = None if fab_t is None else _read_fabrication(fab_t)
    tsa = _read_tsa(tsa_t)
    settings = _read_settings(route, cp, fabrication)
    raw = route.data.get("strings")
    route.used.add("strings")
    if not isinstance(raw, list) or not raw:
        raise route.error("strings", "expected at least one [[route.strings]] table")
    route.finish()
    auto = functools.cache(functools.partial(auto_holes, cp, settings.pop("hole_diameter")))
    strings = tuple(
        _read_string(Table(item, f"{p} [[route.strings]] #{si + 1}", StringsError), si, cp, auto)
        for si, item in enumerate(raw)
    )
    return RouteSpec(tsa, strings, **settings, fabrication=fabrication)


def route_from_pattern(cp: CreasePattern, tsa: dict | None = None, **settings) -> RouteSpec | None:
    """The route a pattern carries (a PyGamiX design's tendons), or None if it has none.

    ``cp.metadata["tendons"]`` (see :mod:`origami_cad.pattern.formats.pygamix`):
    each tendon from its anchor (fixed, or riding on a panel: an onboard TSA) through
    its panels' holes, on the sides the file gives; the first fixed panel is held.
    ``tsa`` is the ``[tsa]`` table (default: ring, or onboard for an anchor on a
    panel), ``settings`` the ``[route]`` keys (``thickness`` mm, ``take_up`` mm...).
    The route is checked as a route file is; errors name the tendon.
    """
    tendons = cp.metadata.get("tendons")
    if not tendons or not tendons.get("strings"):
        return None
    factor = cp.size / tendons["size"] if tendons.get("size") else 1.0
    where = f"{cp.title or 'the design'}'s tendons"
    anchors, strings = tendons["anchors"], []
    for si, stops in enumerate(tendons["strings"]):
        if not stops or stops[0][0] != "anchor" or any(t[0] == "anchor" for t in stops[1:]):
            raise StringsError(
                f"{where}: tendon {si + 1} does not start at its one anchor (an anchor at its "
                "end or in its middle is not supported)"
            )
        if len(stops) < 2:
            raise StringsError(f"{where}: tendon {si + 1} passes through no panel")
        anchor = anchors[stops[0][1]]
        item: dict = {"anchor": [v * factor for v in anchor["point"][:2]] + [anchor["point"][2]]}
        if anchor["face"] >= 0:
            item["anchor_panel"] = cp.face_labels[anchor["face"]]
        item["holes"] = [[v * factor for v in t[3]] for t in stops[1:]]
        item["sides"] = ["top" if t[2] > 0 else "bottom" for t in stops[1:]]
        strings.append(item)
    onboard = any("anchor_panel" in s for s in strings)
    fixed = tendons.get("fixed") or []
    route = {**settings, "strings": strings}
    if fixed and "fixed_panel" not in route:
        route["fixed_panel"] = cp.face_labels[fixed[0]]
    table = tsa if tsa is not None else {"model": "onboard" if onboard else "ring"}
    return _route_from_data({"tsa": table, "route": route}, where, cp)


def dump_route(spec: RouteSpec, cp: CreasePattern, *, header: str = "") -> str:
    """A route file (TOML text) of ``spec`` on pattern ``cp`` that :func:`load_route` reads back:
    the route format's one writer.

    Every value is written as the spec holds it (lengths mm, angles deg): the holes as
    their points (with their panels in a comment: an automatic hole keeps its place,
    whatever the hole diameter), the sides explicitly, the anchor's panel by its label.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from origami_cad.pattern.design import load_design
    >>> cp = load_design("examples/miura_6x4.toml").pattern
    >>> spec = load_route("examples/miura_route.toml", cp)
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "route.toml"
    >>> _ = path.write_text(dump_route(spec, cp))
    >>> back = load_route(path, cp)
    >>> back.strings[0].points == spec.strings[0].points, back.tsa == spec.tsa
    (True, True)
    """
    tsa = spec.tsa
    keys = ("d1", "d2", "string_width", "x_dis") if tsa.model == "ring" else ("length", "radius")
    lines = [header.rstrip("\n")] if header else []
    lines += toml_table(
        "tsa",
        {"model": tsa.model, **{k: getattr(tsa, k) for k in keys},
         "max_helix_angle": tsa.max_helix_angle},
    )  # fmt: skip
    fab = spec.fabrication
    if fab is not None:
        keys = ("bias", "height", "thickness", "shell", "midlayer_bias")
        keys += ("hole_diameter",) if fab.hole_diameter != FabricationParams.hole_diameter else ()
        lines += ["", *toml_table("fabrication", {k: getattr(fab, k) for k in keys})]
    finite = {k: getattr(spec, k) for k in ("max_tension", "max_torque")}
    settings = {
        "thickness": spec.thickness,
        "take_up": spec.take_up,
        "step": math.degrees(spec.step),
        "max_turns": spec.max_turns,
        **{k: v for k, v in finite.items() if math.isfinite(v)},
        "p0": spec.p0,
        "p_max": spec.p_max,
        "fixed_panel": spec.fixed_panel,
    }
    lines += ["", *toml_table("route", settings, comments={"step": "deg"})]
    for s in spec.strings:
        table = {
            "anchor_panel": cp.face_labels[s.anchor_face] if s.anchor_face >= 0 else None,
            "anchor": list(s.anchor),
            "holes": [list(p) for p in s.points],
            "sides": ["top" if v == TOP else "bottom" for v in s.sides],
        }
        names = [cp.face_labels[f] if f >= 0 else n for f, n in zip(s.faces, s.names, strict=True)]
        panels = f"panels {', '.join(names)}"
        lines += ["", *toml_table("route.strings", table, array=True, comments={"holes": panels})]
    return finite_toml("\n".join(lines) + "\n", "the route file", StringsError)


def route_sheet(route: RouteSpec, **fields) -> FabricationParams:
    """The sheet ``route`` is printed with (its ``[fabrication]``, else the paper's
    ``FabricationParams()``), with ``fields`` replaced (e.g. ``holes``)."""
    return replace(route.fabrication or FabricationParams(), **fields)


def _read_fabrication(fab_t: Table) -> FabricationParams:
    """The route's ``[fabrication]`` table: the printed sheet (mm), defaults for what is missing."""
    defaults = FabricationParams()
    fabrication = FabricationParams(
        bias=fab_t.number("bias", defaults.bias, low=0, low_open=True),
        height=fab_t.number("height", defaults.height, low=0, low_open=True),
        thickness=fab_t.number("thickness", defaults.thickness, low=0, low_open=True),
        shell=fab_t.number("shell", defaults.shell, low=0, low_open=True),
        midlayer_bias=fab_t.number("midlayer_bias", defaults.midlayer_bias, low=0),
        hole_diameter=fab_t.number("hole_diameter", defaults.hole_diameter, low=0, low_open=True),
    )
    fab_t.finish()
    return fabrication


def _read_tsa(tsa_t: Table) -> TSAParams:
    """The route's ``[tsa]`` table (mm, degrees), defaults for what is missing."""
    model = tsa_t.string("model", "ring", choices=("ring", "onboard"))
    tsa = TSAParams(
        model=model,
        d1=tsa_t.number("d1", 10.0, low=0, low_open=True),
        d2=tsa_t.number("d2", 8.0, low=0, low_open=True),
        string_width=tsa_t.number("string_width", 0.5, low=0, low_open=True),
        x_dis=tsa_t.number("x_dis", None, low=0) if tsa_t.has("x_dis") else None,
        length=tsa_t.number("length", 100.0, low=0, low_open=True),
        radius=tsa_t.number("radius", 0.5, low=0, low_open=True),
        max_helix_angle=tsa_t.number(
            "max_helix_angle", 80.0, low=0, high=90, low_open=True, high_open=True
        ),
    )
    if not tsa_t.has("x_dis"):
        tsa_t.used.add("x_dis")
    tsa_t.finish()
    return tsa


def _read_settings(route: Table, cp: CreasePattern, fabrication) -> dict:
    """The scalar settings of ``[route]`` as :class:`RouteSpec` keywords (``step`` in
    radians), plus ``hole_diameter`` (mm) for the automatic holes.
    """
    thickness = route.number(
        "thickness", fabrication.height if fabrication is not None else 2.2, low=0
    )
    hole_d = route.number("hole_diameter", 2.0, low=0, low_open=True)
    take_up = route.number("take_up", 0.1, low=0, high=1e3, low_open=True)
    step = route.number("step", 180.0, low=0, high=360, low_open=True)
    max_turns = route.number("max_turns", 20.0, low=0, high=1e4, low_open=True)
    max_tension, max_torque = (
        route.number(key, None, low=0, low_open=True) if route.has(key) else math.inf
        for key in ("max_tension", "max_torque")
    )
    p0 = route.number("p0", 0.0, low=0, high=1, high_open=True)
    p_max = (
        route.number("p_max", None, low=0, high=1, low_open=True) if route.has("p_max") else None
    )
    fixed_panel = route.string("fixed_panel") if route.has("fixed_panel") else None
    if fixed_panel is not None and fixed_panel not in cp.face_labels:
        raise route.error("fixed_panel", f"no panel labelled {fixed_panel!r}")
    if p_max is not None and p_max <= p0:
        raise route.error("p_max", f"must exceed p0 = {p0:g}")
    return {
        "thickness": thickness,
        "step": math.radians(step),
        "max_turns": max_turns,
        "p0": p0,
        "p_max": p_max,
        "fixed_panel": fixed_panel,
        "take_up": take_up,
        "max_tension": max_tension,
        "max_torque": max_torque,
        "hole_diameter": hole_d,
    }


def _read_string(t: Table, si: int, cp: CreasePattern, auto) -> StringRoute:
    """String ``si`` (from 0) of ``[[route.strings]]``; ``auto()`` gives the automatic
    holes ``{panel label: (x, y) mm}``, computed once when a hole names a panel.
    """
    anchor, anchor_face = _read_anchor(t, cp)
    faces, points, names = _read_holes(t, cp, auto)
    raw_sides = t.data.get("sides", "auto")
    t.used.add("sides")
    t.finish()
    rule: list[int | None] = [TOP if anchor[2] >= 0 else BOTTOM]
    rule += [side_rule(cp, faces[k - 1], faces[k]) for k in range(1, len(faces))]
    sides, violations, bad = _read_sides(t, raw_sides, rule, si, names)
    return StringRoute(
        tuple(anchor),
        tuple(faces),
        tuple(points),
        tuple(sides),
        tuple(names),
        tuple(violations),
        anchor_face,
        tuple(bad),
    )


def _read_anchor(t: Table, cp: CreasePattern) -> tuple[list[float], int]:
    """A string's ``anchor`` (mm, 3D) and the panel it rides on (``anchor_panel``; -1: none)."""
    anchor = t.point("anchor", dims=3)
    anchor_face = -1
    if t.has("anchor_panel"):
        label = t.string("anchor_panel")
        if label not in cp.face_labels:
            raise t.error("anchor_panel", f"no panel labelled {label!r}")
        anchor_face = cp.face_index(label)
        if cp.face_of_point(anchor[0], anchor[1]) != anchor_face:
            raise t.error(
                "anchor",
                f"({anchor[0]:g}, {anchor[1]:g}) mm is not on panel {label!r} "
                "(anchor_panel): give the mount's [x, y] on that panel and its height",
            )
        if anchor[2] < 0:
            raise t.error("anchor", "the height above the mounting panel must be >= 0 mm")
    return anchor, anchor_face


def _read_holes(t: Table, cp: CreasePattern, auto) -> tuple[list, list, list]:
    """A string's ``holes``, panel labels or ``[x, y]`` mm: (faces, points, names)."""
    holes = t.data.get("holes")
    t.used.add("holes")
    if not isinstance(holes, list) or not holes:
        raise t.error("holes", "expected a list of panel labels or [x, y] points")
    faces, points, names = [], [], []
    for hi, h in enumerate(holes):
        if isinstance(h, str):
            if h not in cp.face_labels:
                raise t.error("holes", f"item {hi}: no panel labelled {h!r}")
            x, y = auto()[h]
            names.append(h)
        elif (
            isinstance(h, list)
            and len(h) == 2
            and all(
                isinstance(v, int | float)
                and not isinstance(v, bool)
                and math.isfinite(v)
                and abs(v) <= MAX_MAGNITUDE
                for v in h
            )
        ):
            x, y = float(h[0]), float(h[1])
            names.append(f"({x:g}, {y:g})")
        else:
            raise t.error(
                "holes",
                f"item {hi}: expected a panel label or a finite [x, y], got {repr(h)[:60]}",
            )
        fi = cp.face_of_point(x, y)
        if fi < 0:
            raise t.error("holes", f"item {hi}: ({x:g}, {y:g}) mm is not on any panel")
        faces.append(fi)
        points.append((x, y))
    return faces, points, names


def _read_sides(t: Table, raw_sides, rule: list, si: int, names: list[str]):
    """The side (TOP/BOTTOM) of each segment: from ``rule`` (the DCQC side of each, None
    where free) when ``"auto"``, else as given, with the segments that break the rule:
    (sides, violation sentences, bad segment indices).
    """
    if raw_sides == "auto":
        sides = []
        for k, r in enumerate(rule):
            sides.append(r if r is not None else (sides[k - 1] if k else TOP))
        return sides, [], []
    n = len(rule)
    if (
        not isinstance(raw_sides, list)
        or len(raw_sides) != n
        or any(not isinstance(s, str) or s not in _SIDE_NAMES for s in raw_sides)
    ):
        raise t.error("sides", f'expected "auto" or {n} of "top"/"bottom"')
    sides = [_SIDE_NAMES[s] for s in raw_sides]
    violations = []
    bad = []
    for k in range(1, n):
        if rule[k] is not None and sides[k] != rule[k]:
            bad.append(k)
            crease = "valley" if rule[k] == TOP else "mountain"
            violations.append(
                f"string {si + 1}: segment {names[k - 1]} -> {names[k]} runs "
                f"{'above' if sides[k] == TOP else 'below'} a {crease} crease; DCQC "
                f"needs it {'above' if rule[k] == TOP else 'below'}"
            )
    return sides, violations, bad


def rigid_fit(src: np.ndarray, dst: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rotation ``R`` (3, 3) and shift ``t`` (3,) that best map points ``src`` onto ``dst``.

    Least squares over all points (Kabsch): ``R src_i + t ~ dst_i``, both (n, 3), mm.
    """
    sc, dc = src.mean(axis=0), dst.mean(axis=0)
    u, _, vt = np.linalg.svd((src - sc).T @ (dst - dc))
    d = np.sign(np.linalg.det(u @ vt)) or 1.0
    rot = (u @ np.diag([1.0, 1.0, d]) @ vt).T
    return rot, dc - rot @ sc


def mean_pose(coords: np.ndarray, flat: np.ndarray) -> np.ndarray:
    """Place each folded state of ``coords`` (P, n, 3) in the flat sheet's mean pose, mm.

    The state is moved rigidly so that it fits the flat sheet ``flat`` (n, 3) best in
    the least-squares sense: its vertex centroid stays where it was flat and it has
    no mean rotation. This is the placement of a sheet lying free in the middle of
    the ring and pulled evenly by its strings; both string models use it unless
    the route holds a panel.
    """
    out = np.empty_like(coords)
    for k, c in enumerate(coords):
        rot, shift = rigid_fit(c, flat)
        out[k] = c @ rot.T + shift
    return out


def hole_frames(cp: CreasePattern, string: StringRoute) -> tuple[np.ndarray, np.ndarray]:
    """For each hole: three vertices of its panel and the hole's affine coordinates.

    A rigid panel maps its points affinely, so ``hole = v0 + a (v1 - v0) + b (v2 - v0)``
    holds in every folded state with the flat ``a, b``.
    """
    tri = np.empty((len(string.faces), 3), dtype=np.int64)
    ab = np.empty((len(string.faces), 2))
    n = len(cp.faces)
    for k, fi in enumerate(string.faces):
        if not 0 <= fi < n:
            name = string.names[k] if k < len(string.names) else f"#{k + 1}"
            raise StringsError(
                f"route: hole {name} is on panel {fi}, but the pattern has {n} panels "
                "(a route of another pattern?)"
            )
    for k, (fi, (x, y)) in enumerate(zip(string.faces, string.points, strict=True)):
        tri[k], ab[k] = panel_frame(cp, fi, x, y)
    return tri, ab


def panel_frame(cp: CreasePattern, face: int, x: float, y: float) -> tuple[np.ndarray, np.ndarray]:
    """Three vertices of panel ``face`` and the affine coordinates of point (x, y), mm."""
    ring = cp.faces[face]
    xy = cp.vertices[ring]
    # the corner with the largest triangle makes a well-conditioned frame
    best, pick = -1.0, (0, 1, 2)
    for i in range(1, len(ring) - 1):
        for j in range(i + 1, len(ring)):
            e1, e2 = xy[i] - xy[0], xy[j] - xy[0]
            area = abs(e1[0] * e2[1] - e1[1] * e2[0])
            if area > best:
                best, pick = area, (0, i, j)
    e1, e2 = xy[pick[1]] - xy[0], xy[pick[2]] - xy[0]
    ab = np.linalg.solve(np.column_stack([e1, e2]), np.array([x, y]) - xy[0])
    return ring[list(pick)], ab


def frame_orientation(cp: CreasePattern, tri: np.ndarray) -> np.ndarray:
    """+1 or -1 per panel frame ``tri`` (..., 3): the sign that keeps ``e1 x e2`` on the top."""
    flat = cp.vertices[np.asarray(tri)]
    f1, f2 = flat[..., 1, :] - flat[..., 0, :], flat[..., 2, :] - flat[..., 0, :]
    return np.sign(f1[..., 0] * f2[..., 1] - f1[..., 1] * f2[..., 0])


def _frame_points(
    cp: CreasePattern, coords: np.ndarray, tri: np.ndarray, ab: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Points ``ab`` of frames ``tri`` (k, 3) and their top normals in ``coords`` (P, n, 3)."""
    v0, v1, v2 = coords[:, tri[:, 0]], coords[:, tri[:, 1]], coords[:, tri[:, 2]]
    e1, e2 = v1 - v0, v2 - v0
    centre = v0 + ab[None, :, :1] * e1 + ab[None, :, 1:] * e2
    normal = np.cross(e1, e2) * frame_orientation(cp, tri)[None, :, None]
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    return centre, normal


def anchor_points(
    cp: CreasePattern, coords: np.ndarray, string: StringRoute, thickness: float
) -> np.ndarray:
    """Where the string leaves its TSA in folded states ``coords`` (P, n, 3): (P, 3), mm.

    A fixed anchor stays put; one on a panel (``anchor_face``) moves with it, at
    its height above the panel's top face.
    """
    coords = np.asarray(coords, dtype=float)
    if string.anchor_face < 0:
        return np.broadcast_to(np.asarray(string.anchor, dtype=float), (len(coords), 3))
    x, y, height = string.anchor
    tri, ab = panel_frame(cp, string.anchor_face, x, y)
    centre, normal = _frame_points(cp, coords, tri[None], ab[None])
    return (centre + (height + thickness / 2.0) * normal)[:, 0]


def hole_exits(
    cp: CreasePattern,
    coords: np.ndarray,
    string: StringRoute,
    thickness: float,
    frames: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where the string meets each hole in folded states ``coords`` (P, n, 3), mm.

    Returns ``(arrive, leave, normals)``, each (P, k, 3): the exit point on the face
    along which the string reaches hole ``k``, the one along which it leaves
    towards hole ``k + 1`` (half the panel thickness off the mid-surface), and
    each panel's top normal. ``frames`` (from :func:`hole_frames`) saves
    recomputing the holes' panel frames when called many times.
    """
    coords = np.asarray(coords, dtype=float)
    tri, ab = frames if frames is not None else hole_frames(cp, string)
    centre, normal = _frame_points(cp, coords, tri, ab)
    e = thickness / 2.0
    sides = np.asarray(string.sides, dtype=float)
    leave_sides = np.r_[sides[1:], sides[-1]]
    arrive = centre + e * sides[None, :, None] * normal
    leave = centre + e * leave_sides[None, :, None] * normal
    return arrive, leave, normal


def string_lengths(
    cp: CreasePattern,
    coords: np.ndarray,
    string: StringRoute,
    thickness: float,
    frames: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """``(x_dis, rest)`` of a string in folded states ``coords`` (P, n, 3), mm.

    ``x_dis`` is the distance from the anchor to the first hole exit; ``rest`` the
    routed length from there to the last hole (segments plus passes through the
    sheet where the string changes side).
    """
    arrive, leave, _ = hole_exits(cp, coords, string, thickness, frames)
    x_dis = np.linalg.norm(arrive[:, 0] - anchor_points(cp, coords, string, thickness), axis=-1)
    seg = np.linalg.norm(arrive[:, 1:] - leave[:, :-1], axis=-1).sum(axis=-1)
    through = thickness * float(np.sum(np.diff(np.asarray(string.sides)) != 0))
    return x_dis, seg + through


def string_path(
    cp: CreasePattern, coords: np.ndarray, string: StringRoute, thickness: float
) -> np.ndarray:
    """The string as a polyline in one folded state ``coords`` (n, 3): anchor, then holes (mm)."""
    arrive, leave, _ = hole_exits(cp, np.asarray(coords)[None], string, thickness)
    pts = [anchor_points(cp, np.asarray(coords)[None], string, thickness)[0]]
    for k in range(len(string.faces)):
        pts.append(arrive[0, k])
        if not np.allclose(arrive[0, k], leave[0, k]):
            pts.append(leave[0, k])
    return np.array(pts)


def cutting_segments(
    cp: CreasePattern, coords: np.ndarray, string: StringRoute, thickness: float, index: int = 0
) -> list[str]:
    """Segments that would cut through their own panels instead of running over a face.

    A segment leaving hole ``k`` on one side must head away from that side of the
    panel (and likewise arriving at hole ``k + 1``); ``coords`` (n, 3) is one state.
    """
    arrive, leave, normal = hole_exits(cp, np.asarray(coords)[None], string, thickness)
    arrive, leave, normal = arrive[0], leave[0], normal[0]
    sides = np.asarray(string.sides, dtype=float)
    out = []
    tol = 1e-9 * max(cp.size, 1.0)
    first = anchor_points(cp, np.asarray(coords)[None], string, thickness)[0] - arrive[0]
    if np.dot(first, sides[0] * normal[0]) < -tol:
        out.append(
            f"string {index + 1}: the segment from the anchor cuts through panel "
            f"{cp.face_labels[string.faces[0]]}"
        )
    for k in range(len(string.faces) - 1):
        d = arrive[k + 1] - leave[k]
        side = sides[k + 1]
        for hole, dot in (
            (k, np.dot(d, side * normal[k])),
            (k + 1, np.dot(-d, side * normal[k + 1])),
        ):
            if dot < -tol:
                out.append(
                    f"string {index + 1}: segment {string.names[k]} -> {string.names[k + 1]} "
                    f"cuts through panel {cp.face_labels[string.faces[hole]]}"
                )
    return out
