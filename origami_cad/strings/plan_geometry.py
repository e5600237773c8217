"""The route planner's geometry: the sheet folded and placed once, candidate holes and anchors.

Lengths mm, fold ratios in [0, 1] (see :mod:`origami_cad.strings.plan`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from origami_cad.errors import PatternError, StringsError
from origami_cad.fabrication.fitting import MIN_BIAS
from origami_cad.fabrication.params import FabricationParams
from origami_cad.fabrication.plan import plan_panels
from origami_cad.kinematics.folding import PathDesign, fold_coords, fold_design, fold_sequence
from origami_cad.pattern.design import Design
from origami_cad.strings.dcqc import fold_limit
from origami_cad.strings.plan_model import PlanGeometry, PlanSettings, TSAPlacement
from origami_cad.strings.route import RouteSpec, mean_pose, panel_frame, rigid_fit, side_rule

__all__ = [
    "FACET_CLEARANCE",
    "FACET_SLACK",
    "HOLE_LADDER",
    "MIN_HOLE_DIAMETER",
    "plan_geometry",
    "ring_points",
    "target_ratio",
    "truncated_geometry",
]


def target_ratio(
    design: Design, limit: float, target_p=None, target_angles=None, p0: float = 0.0
) -> float:
    """The fold ratio to plan for: ``target_p``, or where every crease of ``target_angles``
    (``{edge: degrees}``) first reaches its angle, else the fold limit ``limit``.
    """
    if target_p is not None:
        if not p0 < target_p <= limit + 1e-12:
            raise StringsError(
                f"--target-p {target_p:g} must lie in ({p0:g}, {limit:.4f}] (the fold limit)"
            )
        return float(target_p)
    if not target_angles:
        return float(limit)
    cp = design.pattern
    edges = np.array([int(e) for e in target_angles], dtype=int)
    want = np.radians(np.abs([float(v) for v in target_angles.values()]))
    if np.any((edges < 0) | (edges >= cp.n_edges)):
        raise StringsError(f"target angles: no crease {edges.tolist()} in the pattern")

    def short(p: float) -> bool:
        got = np.abs(np.radians(fold_design(design, p).fold_angles[edges]))
        return bool(np.any(got < want - 1e-9))

    ratios = np.linspace(p0, limit, 101)
    reached = [k for k, p in enumerate(ratios) if not short(float(p))]
    if not reached:
        worst = int(edges[0])
        raise StringsError(
            f"target angles: crease {worst} does not reach its angle before the fold "
            f"limit p = {limit:.4f}"
        )
    k = reached[0]
    if k == 0:
        return float(ratios[1])
    lo, hi = float(ratios[k - 1]), float(ratios[k])
    while hi - lo > 1e-6:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if not short(mid) else (mid, hi)
    return hi


def _fold_table(design: Design, ratios: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rigid folding on ``ratios``: coordinates (G, n, 3) mm and fold angles (G, m) rad."""
    from origami_cad.kinematics.fold3d import fold_angles_from_coords

    cp = design.pattern
    if design.tg is not None:
        raw = fold_coords(design, ratios)
        return raw, np.stack([fold_angles_from_coords(cp, c) for c in raw])
    states = fold_sequence(design, ratios)
    return np.stack([s.coords for s in states]), np.radians(
        np.stack([s.fold_angles for s in states])
    )


def _placed_coords(design: Design, raw: np.ndarray, held: int) -> np.ndarray:
    """The folded sheet ``raw`` (G, n, 3) placed as the string models place it (mean pose,
    or panel ``held`` held)."""
    cp = design.pattern
    flat = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    if held < 0:
        return mean_pose(raw, flat)
    ring = cp.faces[held]
    out = np.empty_like(raw)
    for k, c in enumerate(raw):
        rot, shift = rigid_fit(c[ring], flat[ring])
        out[k] = c @ rot.T + shift
    return out


def _energy(cp, angles: np.ndarray, stiffness: float) -> np.ndarray:
    """The creases' elastic energy at each state, N mm (``0.5 k L angle^2`` summed)."""
    k = stiffness * cp.edge_lengths() * cp.edge_mask("M", "V")
    return 0.5 * (angles**2 * k).sum(axis=1)


def _frames(cp, coords: np.ndarray):
    """Each panel's frame in every state: v0, e1, e2, top normal (G, F, 3), flat v0, inverse."""
    from origami_cad.strings.route import frame_orientation

    tri = np.array(
        [
            panel_frame(cp, f, *cp.vertices[cp.faces[f]].mean(axis=0))[0]
            for f in range(len(cp.faces))
        ]
    )
    v0, v1, v2 = coords[:, tri[:, 0]], coords[:, tri[:, 1]], coords[:, tri[:, 2]]
    e1, e2 = v1 - v0, v2 - v0
    normal = np.cross(e1, e2) * frame_orientation(cp, tri)[None, :, None]
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    flat = cp.vertices[tri]
    mats = np.stack([flat[:, 1] - flat[:, 0], flat[:, 2] - flat[:, 0]], axis=-1)  # (F, 2, 2)
    return v0, e1, e2, normal, flat[:, 0], np.linalg.inv(mats)


#: The smallest string hole the planner falls back to, mm: twice the default string's
#: width (``TSAParams().string_width``, 0.5 mm), so the string passes freely.
MIN_HOLE_DIAMETER = 1.0
#: How far a hole's centre keeps from a facet crease inside its printed panel, mm: the
#: printed panel has no crease there, but the bar-and-hinge simulator needs the hole on one
#: facet (it refuses one within 1e-6 of the sheet's size of a crease line).
FACET_CLEARANCE = 0.01
#: How far such a hole may then overlap its panel's operation region, mm (a panel fitted
#: to its hole leaves the hole no room to move off the facet crease its centre is on;
#: 0.03 mm is a tenth of a print layer, which no print resolves).
FACET_SLACK = 3 * FACET_CLEARANCE
#: The hole diameters (mm) tried, largest first, below the asked one when no panel has room
#: for it.
HOLE_LADDER = (1.5, 1.2, MIN_HOLE_DIAMETER)


def _auto_holes(cp, fab: FabricationParams):
    """Each face's operation region (a polygon, ``None`` where it has none) and automatic
    hole (mm), by face, as ``fabricate`` plans them (each panel at its own bias).

    On a pattern with facet creases, whose printed panels merge several faces, the hole
    goes into one face of its printed panel (:func:`_face_of_hole`): the face under
    ``fabricate``'s hole when that hole is at least :data:`FACET_CLEARANCE` inside it, else
    the face with the most room; that face's region is the panel's region within the face,
    so no hole the search places there comes nearer a facet crease than that (the
    bar-and-hinge simulator refuses a hole on a crease line; the printed panel has no
    crease there, so the hole itself may overlap the line).
    """
    plan = plan_panels(cp, fab)
    auto, regions, spread = {}, [None] * len(cp.faces), {}
    merged = None
    if plan.pattern is not cp:
        centres = np.array([cp.vertices[list(f)].mean(axis=0) for f in cp.faces])
        merged = plan.pattern.faces_of_points(centres)
    for h, panel in zip(plan.holes, plan.hole_panels.tolist(), strict=True):
        region = plan.outlines[panel].region_polygon()
        if merged is None:
            fi, xy = cp.face_of_point(h.x, h.y), (h.x, h.y)
        else:
            faces = np.flatnonzero(merged == panel).tolist()
            fi, xy, part = _face_of_hole(cp, faces, region, (h.x, h.y), h.diameter / 2.0)
            for f in faces:  # every face's part: a hole there keeps to its face
                regions[f] = _face_part(cp, f, region, h.diameter / 2.0)
            spread[fi], region = region, part
        if fi < 0 or fi in auto:
            continue
        auto[fi], regions[fi] = xy, region
    return regions, auto, spread


def _face_part(cp, f: int, region, radius: float):
    """The part of ``region`` (a printed panel's operation region) where a hole of
    ``radius`` mm on face ``f`` may go, before the search shrinks it by ``radius``
    (:func:`_face_of_hole`)."""
    import shapely

    grown = cp.face_polygons()[f].buffer(radius - FACET_CLEARANCE, join_style="mitre")
    return shapely.intersection(region.buffer(FACET_SLACK, join_style="mitre"), grown)


def _face_of_hole(cp, faces: list[int], region, xy: tuple[float, float], radius: float):
    """The face of ``faces`` (a printed panel's) a hole of ``radius`` mm goes into, its
    centre (mm) and the part of ``region`` (the panel's operation region) that keeps the
    hole inside the region (to :data:`FACET_SLACK`) and its centre :data:`FACET_CLEARANCE`
    inside the face (the face grown by ``radius - FACET_CLEARANCE``: shrunk by ``radius``,
    as the search shrinks regions, it is the face shrunk by the clearance): the face
    holding ``xy`` so, else the face whose part has the most room (the hole at the centre
    of its largest inscribed circle); face -1 when no part has room."""
    import shapely
    from shapely.ops import polylabel

    best = (-1, xy, None, 0.0)
    for f in faces:
        part = _face_part(cp, f, region, radius)
        room = part.buffer(-radius)
        if room.is_empty:
            continue
        if room.contains(shapely.Point(xy)):
            return f, xy, part
        core = max(shapely.get_parts(room), key=lambda g: g.area)
        if core.area > best[3]:
            centre = polylabel(core, tolerance=radius / 10.0)
            best = (f, (float(centre.x), float(centre.y)), part, core.area)
    return best[:3]


def _regions_and_diameter(cp, fab: FabricationParams, settings: PlanSettings, free):
    """The faces' regions and holes (:func:`_auto_holes`) at the asked hole diameter or,
    when no panel but ``free`` ones has room for it, at the largest of :data:`HOLE_LADDER`
    that gives at least half as many panels a hole as the smallest does; and that
    diameter, mm. A diameter ``fabricate`` refuses (a hole its fitting let through but its
    placing finds a hair too big) counts as no room; when every one is refused, the first
    refusal is raised (a defect of the pattern)."""
    refused: list[PatternError] = []

    def holes_at(d: float):
        try:
            regions, auto, spread = _auto_holes(cp, replace(fab, hole_diameter=d, holes="auto"))
        except PatternError as exc:
            refused.append(exc)
            return [None] * len(cp.faces), {}, d, 0, {}
        return regions, auto, d, sum(cp.face_labels[fi] not in free for fi in auto), spread

    asked = holes_at(settings.hole_diameter)
    if asked[3]:  # the asked diameter fits: the ladder is never planned
        return (*asked[:3], asked[4])
    ladder = [holes_at(d) for d in HOLE_LADDER if d < settings.hole_diameter]
    if not ladder or not max(t[3] for t in ladder):
        if refused and len(refused) == 1 + len(ladder):
            raise refused[0]
        return (*asked[:3], asked[4])
    most = max(t[3] for t in ladder)
    chosen = next(t for t in ladder if 2 * t[3] >= most)
    return (*chosen[:3], chosen[4])


def _hole_candidates(cp, fab: FabricationParams, settings: PlanSettings, free, existing):
    """Candidate holes (faces, xy), each panel's shrunk operation region (rings) and the
    hole diameter, mm."""
    import shapely
    from shapely.ops import polylabel

    regions, auto, diameter, spread = _regions_and_diameter(cp, fab, settings, free)
    faces, points, rings = [], [], []
    for fi, region in enumerate(regions):
        if region is not None:
            region = region.buffer(-diameter / 2.0)
        if region is None or cp.face_labels[fi] in free or region.is_empty:
            rings.append(())
            continue
        region = max(shapely.get_parts(region), key=lambda g: g.area)
        rings.append((shapely.get_coordinates(region.exterior),))
        if fi not in auto:  # another face of a printed panel: its pole, a neighbour's
            faces.append(fi)  # hole across a crease on it
            points.append(np.array(shapely.get_coordinates(polylabel(region, 1e-3))[0]))
            continue
        pole = np.array(auto[fi])
        corners = region if fi not in spread else _largest(spread[fi].buffer(-diameter / 2.0))
        pts = [pole] + [
            pole + t * (v - pole)
            for v in shapely.get_coordinates(corners.exterior)[:-1]
            for t in settings.positions
        ]
        on = cp.faces_of_points(np.array(pts))
        if fi in spread:  # a merged panel: no candidate on (or by) a facet crease
            off = shapely.distance(shapely.boundary(cp.face_polygons()[np.maximum(on, 0)]),
                                   shapely.points(np.array(pts)))  # fmt: skip
            on = np.where(off >= FACET_CLEARANCE, on, -1)
        faces += [int(f) for f in on if f >= 0]
        points += [pt for pt, f in zip(pts, on, strict=True) if f >= 0]
    for x, y in existing:
        fi = cp.face_of_point(float(x), float(y))
        if fi < 0:
            raise StringsError(f"existing hole ({x:g}, {y:g}) mm is not on any panel")
        faces.append(fi)
        points.append(np.array([x, y], dtype=float))
    if not faces:
        raise StringsError(_no_room(cp, fab, free))
    return np.array(faces, dtype=np.int64), np.array(points, dtype=float), tuple(rings), diameter


def _largest(geometry):
    """The largest polygon of ``geometry`` (by area)."""
    import shapely

    return max(shapely.get_parts(geometry), key=lambda g: g.area)


def _no_room(cp, fab: FabricationParams, free) -> str:
    """Why no panel takes a hole, and what was checked to give some room: the pattern
    printed twice as large (its panels fitted as ``fabricate`` fits them), or fewer
    panels freed."""
    smallest = (
        f"no panel has room for a {MIN_HOLE_DIAMETER:g} mm hole, the smallest a string passes"
    )
    kept = [label for label in cp.face_labels if label not in free]
    if not kept:
        return f"{smallest}: every panel is free (free_panels): free fewer panels"
    which = f"the {len(kept)} not free" if len(kept) < len(cp.faces) else f"all {len(kept)}"
    why = f"{smallest} ({which} are too small even at the narrowest bias fabricate prints, "
    why += f"{MIN_BIAS:g} mm)"
    x0, _, x1, _ = cp.bounds
    width = float(10 * math.ceil(2 * (x1 - x0) / 10))
    big = cp.scaled(width / (x1 - x0))
    try:
        plan = plan_panels(big, replace(fab, hole_diameter=MIN_HOLE_DIAMETER, holes="auto"))
    except PatternError:
        plan = None
    room = 0
    if plan is not None and plan.holes:
        on = big.faces_of_points(np.array([(h.x, h.y) for h in plan.holes]))
        room = sum(int(f) >= 0 and big.face_labels[int(f)] not in free for f in on)
    if not room:
        return f"{why}; printed twice as large (--width {width:g}) they are too small still"
    return (
        f"{why}: print the pattern larger: at --width {width:g}, {room} of its "
        f"{len(plan.outlines)} printed panels have room for one"
    )


def _anchors(geom_parts: dict, placement: TSAPlacement, cp, auto_xy, thickness: float):
    """The anchor candidates (A, G, 3) and their ring angles (A,) deg (NaN onboard)."""
    g = len(geom_parts["ratios"])
    if placement.kind == "ring":
        x0, y0, x1, y1 = cp.bounds
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        angles = np.arange(placement.guides) * 360.0 / placement.guides
        pts = ring_points((cx, cy), placement, angles)
        return np.broadcast_to(pts[:, None, :], (len(angles), g, 3)).copy(), angles, (cx, cy)
    face = cp.face_index(placement.panel)
    a, b = geom_parts["flat_inv"][face] @ (np.asarray(auto_xy) - geom_parts["flat_v0"][face])
    v0, e1, e2, n = (geom_parts[k][:, face] for k in ("v0", "e1", "e2", "normal"))
    pos = v0 + a * e1 + b * e2 + (placement.height + thickness / 2.0) * n
    return pos[None], np.array([math.nan]), (math.nan, math.nan)


def ring_points(centre, placement: TSAPlacement, angles) -> np.ndarray:
    """Guides on the ring at ``angles`` (deg): (k, 3) mm."""
    t = np.radians(np.asarray(angles, dtype=float))
    return np.stack(
        [
            centre[0] + placement.radius * np.cos(t),
            centre[1] + placement.radius * np.sin(t),
            np.full(t.shape, placement.height),
        ],
        axis=-1,
    )


def _hole_notes(asked: float, diameter: float) -> tuple[str, ...]:
    """The warning when the holes had to be smaller than ``asked`` mm (``diameter`` mm)."""
    if diameter >= asked:
        return ()
    return (
        f"no panel has room for a {asked:g} mm hole: the route's holes are {diameter:g} mm "
        f"(the largest of {', '.join(f'{d:g}' for d in HOLE_LADDER)} mm that fits; its "
        f"[fabrication] says so, and fabricate takes --hole-diameter {diameter:g})",
    )


def _side_rules(cp, hole_faces: np.ndarray) -> np.ndarray:
    """(F, F) int8: for each pair of neighbouring panels, the DCQC side a string must run
    on between them (:func:`~origami_cad.strings.route.side_rule`; 0 where free).

    On a pattern with facet creases the printed panels merge faces: two faces with holes
    (``hole_faces``) in two printed panels that meet at creases of one side get that side,
    as neighbours do (a string runs from one printed panel to the next whichever of their
    faces holds the hole)."""
    from origami_cad.fabrication.panels import printed_pattern

    n_faces = len(cp.faces)
    rule = np.zeros((n_faces, n_faces), dtype=np.int8)
    for a, b in {tuple(sorted(map(int, pair))) for pair in cp.edge_faces() if min(pair) >= 0}:
        side = side_rule(cp, a, b)
        if side is not None:
            rule[a, b] = rule[b, a] = side
    printed = printed_pattern(cp)
    if printed is cp:
        return rule
    centres = np.array([cp.vertices[list(f)].mean(axis=0) for f in cp.faces])
    panel = printed.faces_of_points(centres)
    sides: dict[tuple[int, int], set[int]] = {}
    for a, b in zip(*np.nonzero(rule), strict=True):
        if panel[a] != panel[b] and min(panel[a], panel[b]) >= 0:
            sides.setdefault((int(panel[a]), int(panel[b])), set()).add(int(rule[a, b]))
    holes_of: dict[int, list[int]] = {}
    for f in np.unique(hole_faces).tolist():
        holes_of.setdefault(int(panel[f]), []).append(f)
    for (pa, pb), side in sides.items():  # both orders: the rule stays symmetric
        if len(side) == 1:
            for f in holes_of.get(pa, ()):
                rule[f, holes_of.get(pb, [])] = next(iter(side))
    return rule


def plan_geometry(
    design: Design,
    placement: TSAPlacement,
    fabrication: FabricationParams | None = None,
    settings: PlanSettings | None = None,
    *,
    target_p: float | None = None,
    target_angles: dict[int, float] | None = None,
    free_panels: Sequence[str] = (),
    existing_holes: Sequence[tuple[float, float]] = (),
) -> PlanGeometry:
    """Fold and place the sheet once, and lay out the candidate holes and anchors.

    ``fabrication`` is the printed sheet (default ``FabricationParams()``): its
    eq. 6 limit bounds the target and its operation regions bound the holes;
    ``free_panels`` (labels) get no holes; ``existing_holes`` ([x, y] mm) are
    candidates too. See :func:`plan_routes` for the rest.
    """
    cp = design.pattern
    fab = fabrication or FabricationParams()
    settings = settings or PlanSettings()
    for label in [*free_panels, *([placement.panel] if placement.panel else [])]:
        if label not in cp.face_labels:
            raise StringsError(f"no panel labelled {label!r} in the pattern")
    try:
        limit = fold_limit(design, RouteSpec(placement.tsa, (), fabrication=fab)).p
    except PatternError as exc:
        if design.tg is not None or isinstance(design, PathDesign):
            raise
        raise PatternError(
            f"{exc}; plan on the general folder's path: origami_cad.with_fold_path(design)"
        ) from exc
    p_end = target_ratio(design, limit, target_p, target_angles)
    ratios = p_end * np.linspace(0.0, 1.0, settings.grid) ** 1.5  # denser near flat
    held = cp.face_index(placement.panel) if placement.kind == "onboard" else -1
    faces, xy, regions, diameter = _hole_candidates(
        cp, fab, settings, set(free_panels), existing_holes
    )  # before the folding: a sheet with no room for a hole is refused at once
    raw, fold_angles = _fold_table(design, ratios)
    coords = _placed_coords(design, raw, held)
    v0, e1, e2, normal, flat_v0, flat_inv = _frames(cp, coords)
    notes = _hole_notes(settings.hole_diameter, diameter)
    fab = replace(fab, hole_diameter=diameter)
    settings = replace(settings, hole_diameter=diameter)
    parts = {"ratios": ratios, "v0": v0, "e1": e1, "e2": e2, "normal": normal}
    parts.update(flat_v0=flat_v0, flat_inv=flat_inv)
    auto_xy = None
    if held >= 0:
        auto = _auto_holes(cp, replace(fab, hole_diameter=settings.hole_diameter))[1]
        auto_xy = auto.get(held, tuple(flat_v0[held]))
    anchors, angles, centre = _anchors(parts, placement, cp, auto_xy, fab.height)
    return PlanGeometry(
        ratios=ratios,
        v0=v0,
        e1=e1,
        e2=e2,
        normal=normal,
        flat_v0=flat_v0,
        flat_inv=flat_inv,
        hole_face=faces,
        hole_xy=xy,
        anchors=anchors,
        anchor_angle=angles,
        rule=_side_rules(cp, faces),
        energy=_energy(cp, fold_angles, settings.crease_stiffness),
        regions=regions,
        labels=tuple(cp.face_labels),
        placement=placement,
        thickness=fab.height,
        centre=centre,
        anchor_face=held,
        target_p=p_end,
        limit_p=limit,
        anchor_xy=tuple(float(v) for v in auto_xy) if auto_xy is not None else (math.nan,) * 2,
        fabrication=fab,
        notes=notes,
    )


def truncated_geometry(geom: PlanGeometry, count: int) -> PlanGeometry:
    """``geom`` planned to its ``count``-th fold ratio instead of its target: the first
    ``count`` states of its grid (at least 2), the target that ratio; nothing refolded."""
    k = max(2, min(int(count), len(geom.ratios)))
    return replace(
        geom,
        ratios=geom.ratios[:k],
        v0=geom.v0[:k],
        e1=geom.e1[:k],
        e2=geom.e2[:k],
        normal=geom.normal[:k],
        anchors=geom.anchors[:, :k],
        energy=geom.energy[:k],
        target_p=float(geom.ratios[k - 1]),
    )
