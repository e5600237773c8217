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
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from origami_cad._names import one_line, toml_string
from origami_cad.errors import StringsError
from origami_cad.fabrication.panels import panel_outlines
from origami_cad.fabrication.params import FabricationParams
from origami_cad.fabrication.plan import plan_panels
from origami_cad.kinematics.folding import fold_coords, fold_design, fold_sequence
from origami_cad.parallel import local_pool
from origami_cad.pattern.design import Design
from origami_cad.strings.dcqc import fold_limit
from origami_cad.strings.route import (
    BOTTOM,
    TOP,
    RouteSpec,
    StringRoute,
    mean_pose,
    panel_frame,
    rigid_fit,
    side_rule,
)
from origami_cad.strings.tsa import TSAParams, ring_length

__all__ = [
    "DEFAULT_CREASE_STIFFNESS",
    "PlanGeometry",
    "PlanSettings",
    "PlannedRoute",
    "RouteScores",
    "TSAPlacement",
    "evaluate_routes",
    "plan_geometry",
    "plan_routes",
    "route_toml",
    "string_curves",
    "target_ratio",
]

#: N mm / rad / mm: the default printed sheet's crease stiffness (TPU 95A, E = 26 MPa,
#: t = 0.4 mm over a 7 mm hinge zone: E t^3 / (12 w)), ``SimulationParams().crease_stiffness``.
DEFAULT_CREASE_STIFFNESS = 26.0 * 0.4**3 / (12.0 * 7.0)
TASKS = 8  # the beam search is split into this many tasks, whatever the executor
STALL = 60  # a CMA-ES refinement stops after this many generations without a better route
SET_BEAM = 64  # string sets kept per size at least (a narrow beam may find no compatible set)


@dataclass(frozen=True)
class TSAPlacement:
    """Where the TSA is: a ring rail around the sheet, or onboard on a panel (mm).

    ``kind`` is ``"ring"`` or ``"onboard"``. Ring: string guides on a circle of
    ``radius`` mm around the sheet's centre (the middle of its bounding box),
    ``height`` mm above the sheet's mid-surface, one every ``360 / guides``
    degrees. Onboard: the TSA rides on panel ``panel`` (a label), its string exit
    ``height`` mm above the panel's top face over the panel's automatic hole; the
    panel is held. ``tsa`` is the actuator (eq. 8 for the ring).
    """

    kind: str = "ring"
    panel: str | None = None
    radius: float = 126.0
    height: float = 10.0
    guides: int = 72
    tsa: TSAParams = field(default_factory=TSAParams)

    def __post_init__(self) -> None:
        if self.kind not in ("ring", "onboard"):
            raise StringsError(f"a TSA is placed 'ring' or 'onboard', got {self.kind!r}")
        if self.kind == "onboard" and not self.panel:
            raise StringsError("an onboard TSA needs the label of the panel it rides on")
        if self.kind == "ring" and not (self.radius > 0 and self.guides >= 4):
            raise StringsError("a ring TSA needs a radius > 0 mm and at least 4 guides")


@dataclass(frozen=True)
class PlanSettings:
    """How hard and by what the search looks (mm, N mm, turns).

    ``candidates``: beam width of the hole-sequence search (partial strings kept
    per task and depth) and of the string-set search; ``max_holes`` per string;
    ``grid`` fold ratios from flat to the target (``p_end u^1.5`` for ``u`` evenly
    spaced in [0, 1]: denser near flat, where the torque peaks); ``refine`` routes refined by
    CMA-ES for ``generations`` generations; ``max_turns`` / ``max_torque``
    budgets; ``crease_stiffness`` N mm/rad/mm for the torque; ``share_weight`` and
    ``share_tolerance`` (mm) of the load-share term; ``positions``: fractions of
    the way from a panel's automatic hole to its region's corners where
    candidate holes go; ``keep`` routes returned.
    """

    candidates: int = 128
    max_holes: int = 4
    grid: int = 33
    refine: int = 4
    generations: int = 200
    max_turns: float = 40.0
    max_torque: float = math.inf
    crease_stiffness: float = DEFAULT_CREASE_STIFFNESS
    share_weight: float = 0.5
    share_tolerance: float = 0.2
    positions: tuple[float, ...] = (0.5, 0.9)
    hole_diameter: float = 2.0
    keep: int = 20


@dataclass(frozen=True)
class PlanGeometry:
    """What every candidate is scored on: the placed sheet on a grid of fold ratios.

    Arrays (mm): ``ratios`` (G,); per panel frame ``v0, e1, e2, normal`` (G, F, 3)
    (a point with affine coordinates ``(a, b)`` is ``v0 + a e1 + b e2``) and
    ``flat_v0`` (F, 2), ``flat_inv`` (F, 2, 2) to get ``(a, b)`` from ``(x, y)``;
    candidate holes ``hole_face`` (H,), ``hole_xy`` (H, 2); ``anchors`` (A, G, 3)
    with ``anchor_angle`` (A,) deg on the ring; ``rule`` (F, F) the DCQC side
    between adjacent panels (0: none); ``energy`` (G,) the creases' energy, N mm;
    ``regions`` per panel the rings of its operation region shrunk by the hole's
    radius (empty: no holes there).
    """

    ratios: np.ndarray
    v0: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    normal: np.ndarray
    flat_v0: np.ndarray
    flat_inv: np.ndarray
    hole_face: np.ndarray
    hole_xy: np.ndarray
    anchors: np.ndarray
    anchor_angle: np.ndarray
    rule: np.ndarray
    energy: np.ndarray
    regions: tuple[tuple[np.ndarray, ...], ...]
    labels: tuple[str, ...]
    placement: TSAPlacement
    thickness: float
    centre: tuple[float, float]
    anchor_face: int = -1
    target_p: float = 1.0
    limit_p: float = 1.0
    anchor_xy: tuple[float, float] = (math.nan, math.nan)
    fabrication: FabricationParams = field(default_factory=FabricationParams)


@dataclass
class RouteScores:
    """The DCQC figures of a batch of R candidate routes (arrays over routes).

    ``valid`` (R,); ``turns`` (R,) TSA turns to the target; ``peak_torque`` (R,)
    N mm; ``share`` (R,) load share in [0, 1]; ``cost`` (R,); ``theta`` (R, G)
    TSA rotation at each fold ratio, rad; ``torque`` (R, G - 1) N mm between
    grid ratios; ``why`` (R,) 0 valid, 1 a segment cuts a panel, 2 a string
    would lengthen, 3 the TSA cannot take it up (helix limit).
    """

    valid: np.ndarray
    turns: np.ndarray
    peak_torque: np.ndarray
    share: np.ndarray
    cost: np.ndarray
    theta: np.ndarray
    torque: np.ndarray
    why: np.ndarray


@dataclass(frozen=True)
class PlannedRoute:
    """One ranked route: its strings (as the route file has them) and DCQC figures.

    ``strings`` are :class:`StringRoute` records (holes as points, sides by the
    DCQC rule); ``turns`` to the target, ``peak_torque`` N mm, ``share`` the load
    share; ``p`` (G,) and ``curve_turns`` (G,) the DCQC curve, ``torque`` (G - 1,)
    N mm; ``stage`` where it was found ("beam" or "cma").
    """

    rank: int
    strings: tuple[StringRoute, ...]
    turns: float
    peak_torque: float
    share: float
    cost: float
    p: np.ndarray
    curve_turns: np.ndarray
    torque: np.ndarray
    stage: str
    anchor_angles: tuple[float, ...] = ()
    checks: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """The JSON form (one entry of ``routes.json``)."""
        return {
            "rank": self.rank,
            "turns": self.turns,
            "peak_torque_Nmm": self.peak_torque,
            "load_share": self.share,
            "cost": self.cost,
            "stage": self.stage,
            "strings": [
                {
                    "anchor_mm": list(s.anchor),
                    "holes": [
                        {"panel": n, "x_mm": x, "y_mm": y}
                        for n, (x, y) in zip(s.names, s.points, strict=True)
                    ],
                    "sides": ["top" if v == TOP else "bottom" for v in s.sides],
                }
                for s in self.strings
            ],
            "dcqc_curve": {
                "p": self.p.tolist(),
                "turns": self.curve_turns.tolist(),
                "torque_Nmm": self.torque.tolist(),
            },
            "checks": self.checks,
        }


# --------------------------------------------------------------------------- geometry


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


def _hole_candidates(cp, fab: FabricationParams, settings: PlanSettings, free, existing):
    """Candidate holes (faces, xy) and each panel's shrunk operation region (rings)."""
    import shapely

    fab = replace(fab, hole_diameter=settings.hole_diameter, holes="auto")
    outlines = panel_outlines(cp, fab)
    try:
        auto = {lab: (h[0].x, h[0].y) for lab, h in plan_panels(cp, fab).holes_by_label().items()}
    except Exception:  # a panel too small for a hole: no automatic holes there
        auto = {}
    faces, points, regions = [], [], []
    for o in outlines:
        region = o.region_polygon().buffer(-settings.hole_diameter / 2.0)
        if o.label in free or region.is_empty or o.label not in auto:
            regions.append(())
            continue
        region = max(shapely.get_parts(region), key=lambda g: g.area)
        regions.append((shapely.get_coordinates(region.exterior),))
        pole = np.array(auto[o.label])
        pts = [pole] + [
            pole + t * (v - pole)
            for v in shapely.get_coordinates(region.exterior)[:-1]
            for t in settings.positions
        ]
        for pt in pts:
            faces.append(o.index)
            points.append(pt)
    for x, y in existing:
        fi = cp.face_of_point(float(x), float(y))
        if fi < 0:
            raise StringsError(f"existing hole ({x:g}, {y:g}) mm is not on any panel")
        faces.append(fi)
        points.append(np.array([x, y], dtype=float))
    if not faces:
        raise StringsError("no panel has room for a hole (all free, or regions too small)")
    return np.array(faces, dtype=np.int64), np.array(points, dtype=float), tuple(regions)


def _anchors(geom_parts: dict, placement: TSAPlacement, cp, auto_xy, thickness: float):
    """The anchor candidates (A, G, 3) and their ring angles (A,) deg (NaN onboard)."""
    g = len(geom_parts["ratios"])
    if placement.kind == "ring":
        x0, y0, x1, y1 = cp.bounds
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        angles = np.arange(placement.guides) * 360.0 / placement.guides
        pts = _ring_points((cx, cy), placement, angles)
        return np.broadcast_to(pts[:, None, :], (len(angles), g, 3)).copy(), angles, (cx, cy)
    face = cp.face_index(placement.panel)
    a, b = geom_parts["flat_inv"][face] @ (np.asarray(auto_xy) - geom_parts["flat_v0"][face])
    v0, e1, e2, n = (geom_parts[k][:, face] for k in ("v0", "e1", "e2", "normal"))
    pos = v0 + a * e1 + b * e2 + (placement.height + thickness / 2.0) * n
    return pos[None], np.array([math.nan]), (math.nan, math.nan)


def _ring_points(centre, placement: TSAPlacement, angles) -> np.ndarray:
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
    limit = fold_limit(design, RouteSpec(placement.tsa, (), fabrication=fab)).p
    p_end = target_ratio(design, limit, target_p, target_angles)
    ratios = p_end * np.linspace(0.0, 1.0, settings.grid) ** 1.5  # denser near flat
    held = cp.face_index(placement.panel) if placement.kind == "onboard" else -1
    raw, fold_angles = _fold_table(design, ratios)
    coords = _placed_coords(design, raw, held)
    v0, e1, e2, normal, flat_v0, flat_inv = _frames(cp, coords)
    faces, xy, regions = _hole_candidates(cp, fab, settings, set(free_panels), existing_holes)
    parts = {"ratios": ratios, "v0": v0, "e1": e1, "e2": e2, "normal": normal}
    parts.update(flat_v0=flat_v0, flat_inv=flat_inv)
    auto_xy = None
    if held >= 0:
        auto_xy = plan_panels(cp, replace(fab, hole_diameter=settings.hole_diameter)).holes_of(held)
        auto_xy = (auto_xy[0].x, auto_xy[0].y) if auto_xy else tuple(flat_v0[held])
    anchors, angles, centre = _anchors(parts, placement, cp, auto_xy, fab.height)
    n_faces = len(cp.faces)
    rule = np.zeros((n_faces, n_faces), dtype=np.int8)
    ef = cp.edge_faces()
    for a, b in {tuple(sorted(map(int, pair))) for pair in ef if min(pair) >= 0}:
        side = side_rule(cp, a, b)
        if side is not None:
            rule[a, b] = rule[b, a] = side
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
        rule=rule,
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
    )


# --------------------------------------------------------------------------- scoring


def string_curves(
    geom: PlanGeometry,
    anchors: np.ndarray,
    faces: np.ndarray,
    xy: np.ndarray,
    sides: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Lengths of C strings over the grid: ``(x_dis, rest, cuts)``, vectorised.

    ``anchors`` (C, G, 3) mm; ``faces`` (C, K) panel of each hole, ``xy`` (C, K, 2)
    mm, ``sides`` (C, K) the side (+1 top, -1 bottom) along which the string
    reaches each hole. Shorter strings repeat their last hole and side. Returns
    ``x_dis`` (C, G) anchor to the first hole exit, ``rest`` (C, G) the routed
    length beyond it (as :func:`~origami_cad.strings.route.string_lengths`) and
    ``cuts`` (C,) True where a segment cuts through a panel in some state.
    """
    ab = np.einsum("ckij,ckj->cki", geom.flat_inv[faces], xy - geom.flat_v0[faces])
    v0, e1, e2, n = (arr[:, faces] for arr in (geom.v0, geom.e1, geom.e2, geom.normal))
    centre = v0 + ab[None, ..., :1] * e1 + ab[None, ..., 1:] * e2  # (G, C, K, 3)
    e = geom.thickness / 2.0
    s = sides.astype(float)
    s_leave = np.concatenate([s[:, 1:], s[:, -1:]], axis=1)
    arrive = centre + e * s[None, ..., None] * n
    leave = centre + e * s_leave[None, ..., None] * n
    anchor = np.swapaxes(anchors, 0, 1)  # (G, C, 3)
    first = anchor - arrive[:, :, 0]
    x_dis = np.linalg.norm(first, axis=-1)
    d = arrive[:, :, 1:] - leave[:, :, :-1]
    seg = np.linalg.norm(d, axis=-1).sum(axis=-1)
    through = geom.thickness * (np.diff(s, axis=1) != 0).sum(axis=1)
    rest = seg + through[None]
    tol = -1e-6
    cuts = np.any(np.einsum("gci,gci->gc", first, s[None, :, :1] * n[:, :, 0]) < tol, axis=0)
    sn = s[None, :, 1:, None]
    out_k = np.einsum("gcki,gcki->gck", d, sn * n[:, :, :-1])
    in_k = np.einsum("gcki,gcki->gck", -d, sn * n[:, :, 1:])
    cuts |= np.any((out_k < tol) | (in_k < tol), axis=(0, 2))
    return x_dis.T, rest.T, cuts


def _consumed(tsa: TSAParams, theta: np.ndarray, x: np.ndarray) -> np.ndarray:
    """String between the TSA and the first hole (eq. 8 or onboard), NaN past the strands."""
    if tsa.model == "ring":
        xx = x if tsa.x_dis is None else np.full_like(x, tsa.x_dis)
        return ring_length(
            np.maximum(np.nan_to_num(theta), 0.0), xx, tsa.d1, tsa.d2, tsa.string_width
        )
    twist = (np.clip(np.nan_to_num(theta), 0.0, 1e12) * tsa.radius) ** 2
    with np.errstate(invalid="ignore"):
        return x + tsa.length - np.sqrt(tsa.length**2 - twist)


def _theta_for(tsa: TSAParams, x: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The TSA rotation (rad) at which the TSA's share is ``target`` mm (eq. 8 inverted).

    NaN where the string would have to lengthen (the share falls below its untwisted
    length), +inf past an onboard TSA's largest twist.
    """
    if tsa.model == "ring":
        d1, d2, ds = tsa.d1, tsa.d2, tsa.string_width
        xx = x if tsa.x_dis is None else np.full_like(x, tsa.x_dis)
        q = target**2 - xx**2
        q0, q1 = (d2 - d1) ** 2 / 4.0, (d1 + d2) ** 2 / 4.0
        cos = np.clip((d1**2 + d2**2 - 4.0 * q) / (2.0 * d1 * d2), -1.0, 1.0)
        with np.errstate(invalid="ignore"):
            wound = math.pi + (2.0 * np.sqrt(np.maximum(q, 0.0)) - d1 - d2) / ds
        theta = np.where(q <= q1, np.arccos(cos), wound)
        return np.where(q < q0 - 1e-6 * (1.0 + q0), np.nan, theta)
    c = target - x
    top = tsa.length * (1.0 - math.cos(math.radians(tsa.max_helix_angle)))
    with np.errstate(invalid="ignore"):
        theta = np.sqrt(np.maximum(tsa.length**2 - (tsa.length - c) ** 2, 0.0)) / tsa.radius
    theta = np.where(c >= top, np.inf, theta)
    return np.where(c < -1e-6, np.nan, theta)


def evaluate_routes(
    geom: PlanGeometry,
    settings: PlanSettings,
    x_dis: np.ndarray,
    rest: np.ndarray,
    cuts: np.ndarray,
) -> RouteScores:
    """Score R candidate routes of n strings each on the DCQC model, vectorised.

    ``x_dis``, ``rest`` (R, n, G) mm and ``cuts`` (R, n) from :func:`string_curves`.
    Each string binds at ``theta_i(p)`` (eq. 8 inverted); the TSA reaches ``p`` at
    ``theta(p) = min_i theta_i(p)``. Valid: no segment cuts a panel, no string
    lengthens as the sheet folds from one state to the next (at that state's TSA
    rotation), ``theta(p)`` never falls, and the TSA can take the string up. The
    torque is ``dE / dtheta`` (virtual work), the load share the fraction of
    string states within ``settings.share_tolerance`` mm of taut.
    """
    tsa = geom.placement.tsa
    l0 = _consumed(tsa, np.zeros(x_dis.shape[:2]), x_dis[..., 0]) + rest[..., 0]
    target = l0[..., None] - rest
    theta_i = _theta_for(tsa, x_dis, target)  # (R, n, G)
    shrink_fail = np.isnan(theta_i).any(axis=(1, 2))
    theta = np.nan_to_num(theta_i, nan=np.inf).min(axis=1)  # (R, G)
    helix = ~np.isfinite(theta).all(axis=1)
    th = np.where(np.isfinite(theta), theta, 0.0)
    now = _consumed(tsa, th[:, None, :-1], x_dis[..., :-1]) + rest[..., :-1]
    nxt = _consumed(tsa, th[:, None, :-1], x_dis[..., 1:]) + rest[..., 1:]
    stretch = np.nan_to_num(nxt - now, nan=np.inf).max(axis=(1, 2))
    falls = (np.diff(th, axis=1) < -1e-9).any(axis=1)
    turns = th[:, -1] / (2.0 * math.pi)
    d_theta = np.maximum(np.diff(th, axis=1), 1e-9)
    torque = np.maximum(np.diff(geom.energy), 0.0)[None] / d_theta
    peak = torque.max(axis=1)
    slack = target - _consumed(tsa, th[:, None, :], x_dis)
    share = (np.nan_to_num(slack[..., 1:], nan=np.inf) <= settings.share_tolerance).mean(
        axis=(1, 2)
    )
    why = np.zeros(len(th), dtype=np.int64)
    why[(stretch > 1e-7) | shrink_fail | falls | (turns < 1e-6)] = 2
    why[helix] = 3
    why[cuts.any(axis=1)] = 1
    valid = why == 0
    with np.errstate(divide="ignore", invalid="ignore"):
        cost = np.log(np.maximum(turns, 1e-9)) + np.log(np.maximum(peak, 1e-12))
    cost = cost + settings.share_weight * (1.0 - share)
    over_turns = np.maximum(turns / settings.max_turns - 1.0, 0.0)
    over_torque = np.maximum(np.nan_to_num(peak / settings.max_torque) - 1.0, 0.0)
    cost = cost + np.where(over_turns > 0, 5.0 + 10.0 * over_turns, 0.0)
    cost = cost + np.where(over_torque > 0, 5.0 + 10.0 * over_torque, 0.0)
    bad = 1e3 + 10.0 * why + np.minimum(np.nan_to_num(stretch, posinf=1e3), 1e3)
    cost = np.where(valid, cost, bad)
    return RouteScores(valid, turns, peak, share, cost, th, torque, why)


# --------------------------------------------------------------------------- search


@dataclass
class _Strings:
    """A batch of strings: anchor index (C,), hole candidates (C, K), sides (C, K), cost (C,)."""

    anchor: np.ndarray
    holes: np.ndarray
    sides: np.ndarray
    cost: np.ndarray
    depth: np.ndarray

    def take(self, idx) -> _Strings:
        return _Strings(
            *(getattr(self, k)[idx] for k in ("anchor", "holes", "sides", "cost", "depth"))
        )


def _first_side(geom: PlanGeometry) -> int:
    """The side along which a string leaves its anchor: the anchor's side of the sheet."""
    return TOP if geom.placement.height >= 0 else BOTTOM


def _score_strings(geom, settings, s: _Strings, width: int) -> tuple[np.ndarray, RouteScores]:
    """Each string scored alone as a one-string route; cost (C,) and the scores."""
    faces = geom.hole_face[s.holes]
    xy = geom.hole_xy[s.holes]
    x, rest, cuts = string_curves(geom, geom.anchors[s.anchor], faces, xy, s.sides)
    scores = evaluate_routes(geom, settings, x[:, None], rest[:, None], cuts[:, None])
    return scores.cost, scores


def _expand(geom: PlanGeometry, beam: _Strings, next_holes) -> _Strings:
    """Every string of ``beam`` extended by one hole on an adjacent, unvisited panel."""
    out_a, out_h, out_s = [], [], []
    d = int(beam.depth[0])
    for c in range(len(beam.anchor)):
        seq = beam.holes[c, :d]
        visited = geom.hole_face[seq]
        nxt = next_holes[visited[-1]]
        nxt = nxt[~np.isin(geom.hole_face[nxt], visited)]
        if not len(nxt):
            continue
        k = len(nxt)
        holes = np.repeat(seq[None], k, axis=0)
        out_h.append(np.column_stack([holes, nxt]))
        sides = np.repeat(beam.sides[c, :d][None], k, axis=0)
        out_s.append(np.column_stack([sides, geom.rule[visited[-1], geom.hole_face[nxt]]]))
        out_a.append(np.full(k, beam.anchor[c]))
    if not out_a:
        return _Strings(
            *(np.zeros((0, *sh), dtype=np.int64) for sh in ((), (d + 1,), (d + 1,))),
            np.zeros(0),
            np.zeros(0, dtype=np.int64),
        )
    n = sum(len(a) for a in out_a)
    return _Strings(
        np.concatenate(out_a),
        np.concatenate(out_h),
        np.concatenate(out_s).astype(np.int64),
        np.zeros(n),
        np.full(n, d + 1),
    )


def _prune(geom, s: _Strings, scores: RouteScores, width: int, per_path: int = 2) -> np.ndarray:
    """Indices of the ``width`` best strings that cut no panel, at most ``per_path``
    per (anchor, panel sequence): the beam keeps different paths."""
    order = np.lexsort((np.arange(len(s.cost)), s.cost))
    seen: dict[tuple, int] = {}
    keep = []
    for i in order:
        if scores.why[i] == 1:
            continue
        key = (int(s.anchor[i]), *geom.hole_face[s.holes[i]].tolist())
        if seen.get(key, 0) >= per_path:
            continue
        seen[key] = seen.get(key, 0) + 1
        keep.append(i)
        if len(keep) >= width:
            break
    return np.array(keep, dtype=np.int64)


def _next_holes(geom: PlanGeometry) -> list[np.ndarray]:
    """For each panel, the candidate holes on the panels it shares a DCQC crease with."""
    return [np.flatnonzero(geom.rule[f, geom.hole_face] != 0) for f in range(len(geom.labels))]


def _beam_task(geom: PlanGeometry, settings: PlanSettings, starts: np.ndarray) -> dict:
    """Beam search from ``starts`` (S, 2: anchor, first hole): the valid strings found.

    Returns padded arrays (``holes``, ``sides`` (M, max_holes)), ``anchor``, ``cost``
    and the number of strings evaluated.
    """
    width = settings.candidates
    side0 = _first_side(geom)
    beam = _Strings(
        starts[:, 0].copy(),
        starts[:, 1:2].copy(),
        np.full((len(starts), 1), side0, dtype=np.int64),
        np.zeros(len(starts)),
        np.ones(len(starts), dtype=np.int64),
    )
    nxt = _next_holes(geom)
    found: list[tuple[_Strings, np.ndarray]] = []
    evaluated = 0
    for depth in range(1, settings.max_holes + 1):
        if depth > 1:
            beam = _expand(geom, beam, nxt)
        if not len(beam.anchor):
            break
        beam.cost, scores = _score_strings(geom, settings, beam, width)
        evaluated += len(beam.cost)
        if depth > 1:
            good = np.flatnonzero(scores.valid)
            found.append((beam.take(good), good))
        beam = beam.take(_prune(geom, beam, scores, width))
    pad = settings.max_holes
    out = {"anchor": [], "holes": [], "sides": [], "cost": []}
    for s, _ in found:
        k = s.holes.shape[1]
        out["anchor"].append(s.anchor)
        out["holes"].append(np.pad(s.holes, ((0, 0), (0, pad - k)), mode="edge"))
        out["sides"].append(np.pad(s.sides, ((0, 0), (0, pad - k)), mode="edge"))
        out["cost"].append(s.cost)
    arrays = {
        k: (np.concatenate(v) if v else np.zeros((0, pad) if k in ("holes", "sides") else 0))
        for k, v in out.items()
    }
    order = np.lexsort((np.arange(len(arrays["cost"])), arrays["cost"]))[: 2 * width]
    result = {k: v[order] for k, v in arrays.items()}
    result["evaluated"] = evaluated
    return result


def _pool_curves(geom: PlanGeometry, pool: dict):
    """The pool's strings over the grid: x_dis, rest (P, G), cuts (P,), faces used (P, F)."""
    faces = geom.hole_face[pool["holes"]]
    x, rest, cuts = string_curves(
        geom, geom.anchors[pool["anchor"]], faces, geom.hole_xy[pool["holes"]], pool["sides"]
    )
    used = np.zeros((len(faces), len(geom.labels)), dtype=bool)
    np.put_along_axis(used, faces, True, axis=1)
    if geom.anchor_face >= 0:
        used[:, geom.anchor_face] = False
    return x, rest, cuts, used


def _compatible(geom: PlanGeometry, pool: dict, used, routes: np.ndarray) -> np.ndarray:
    """(B, P) which pool strings may join each route: later in the pool, no panel or ring
    guide shared on a ring, not the same holes onboard."""
    last = routes.max(axis=1)
    ok = np.arange(len(used))[None, :] > last[:, None]
    if geom.placement.kind == "ring":
        route_used = used[routes].any(axis=1)  # (B, F)
        ok &= ~(route_used.astype(np.uint8) @ used.T.astype(np.uint8)).astype(bool)
        anchors = pool["anchor"]
        ok &= ~(anchors[routes][:, :, None] == anchors[None, None, :]).any(axis=1)
    else:
        same = (pool["holes"][routes][:, :, None, :] == pool["holes"][None, None]).all(axis=-1)
        ok &= ~same.any(axis=1)
    return ok


def _combine(geom, settings, pool: dict, n_strings: int, progress=None):
    """Beam search over sets of ``n_strings`` pool strings: the best routes (B, n), scores."""
    x, rest, cuts, used = _pool_curves(geom, pool)
    width = max(settings.candidates, SET_BEAM)
    routes = np.arange(len(x))[:, None]
    scores = evaluate_routes(geom, settings, x[:, None], rest[:, None], cuts[:, None])
    evaluated = len(routes)
    for _size in range(2, n_strings + 1):
        keep = np.lexsort((np.arange(len(routes)), scores.cost))[:width]
        routes = routes[keep]
        ok = _compatible(geom, pool, used, routes)
        b, p = np.nonzero(ok)
        if not len(b):
            raise StringsError(
                f"no {n_strings} strings fit together (on a ring no two may share a panel "
                "or a guide): ask for fewer strings"
            )
        routes = np.column_stack([routes[b], p])
        parts = []
        for lo in range(0, len(routes), 4096):
            r = routes[lo : lo + 4096]
            parts.append(evaluate_routes(geom, settings, x[r], rest[r], cuts[r]))
        scores = RouteScores(
            *(
                np.concatenate([getattr(s, f) for s in parts])
                for f in RouteScores.__dataclass_fields__
            )
        )
        evaluated += len(routes)
        if progress is not None:
            progress(evaluated)
    order = np.lexsort((np.arange(len(routes)), scores.cost))[:width]
    return routes[order], evaluated


def _route_arrays(geom: PlanGeometry, pool: dict, route: np.ndarray) -> dict:
    """A route of pool strings as arrays: ring angles (n,), faces, xy, sides (n, K), counts."""
    holes = pool["holes"][route]
    count = 1 + (np.diff(holes, axis=1) != 0).sum(axis=1)
    return {
        "angle": geom.anchor_angle[pool["anchor"][route]].astype(float),
        "faces": geom.hole_face[holes],
        "xy": geom.hole_xy[holes].astype(float),
        "sides": pool["sides"][route].astype(np.int64),
        "count": count,
    }


def _anchor_positions(geom: PlanGeometry, angles: np.ndarray) -> np.ndarray:
    """Anchors (..., G, 3) for ring angles (...) deg, or the onboard TSA's for each."""
    g = len(geom.ratios)
    if geom.placement.kind == "ring":
        pts = _ring_points(geom.centre, geom.placement, angles)
        return np.broadcast_to(pts[..., None, :], (*pts.shape[:-1], g, 3))
    return np.broadcast_to(geom.anchors[0], (*np.shape(angles), g, 3))


def _score_arrays(geom, settings, angle, xy, route: dict) -> RouteScores:
    """Scores of P variants of one route: guide angles (P, n) deg and holes (P, n, K, 2)."""
    p, n, k = xy.shape[:3]
    faces = np.broadcast_to(route["faces"], (p, n, k)).reshape(p * n, k)
    sides = np.broadcast_to(route["sides"], (p, n, k)).reshape(p * n, k)
    anchors = _anchor_positions(geom, angle.reshape(-1))
    x, rest, cuts = string_curves(geom, anchors, faces, xy.reshape(p * n, k, 2), sides)
    g = x.shape[-1]
    return evaluate_routes(
        geom, settings, x.reshape(p, n, g), rest.reshape(p, n, g), cuts.reshape(p, n)
    )


def _decode(geom: PlanGeometry, route: dict, genomes: np.ndarray):
    """Guide angles (P, n) deg and holes (P, n, K, 2) mm from genomes: 3 deg and 2 mm steps."""
    n, k = route["faces"].shape
    ring = geom.placement.kind == "ring"
    angle = np.broadcast_to(route["angle"], (len(genomes), n)).copy()
    at = 0
    if ring:
        angle += 3.0 * genomes[:, :n]
        at = n
    xy = np.broadcast_to(route["xy"], (len(genomes), n, k, 2)).copy()
    for i in range(n):
        c = int(route["count"][i])
        move = 2.0 * genomes[:, at : at + 2 * c].reshape(-1, c, 2)
        xy[:, i, :c] += move
        xy[:, i, c:] = xy[:, i, c - 1 : c]
        at += 2 * c
    return angle, xy


def _outside(geom: PlanGeometry, route: dict, xy: np.ndarray, polys: dict) -> np.ndarray:
    """(P,) how many holes of each variant leave their panel's operation region."""
    import shapely

    out = np.zeros(len(xy))
    for i, faces in enumerate(route["faces"]):
        for j in range(int(route["count"][i])):
            f = int(faces[j])
            if f not in polys:
                rings = geom.regions[f]
                polys[f] = shapely.Polygon(rings[0]) if rings else None
            if polys[f] is not None:
                out += ~shapely.contains_xy(polys[f], xy[:, i, j, 0], xy[:, i, j, 1])
    return out


def _refine_task(geom: PlanGeometry, settings: PlanSettings, route: dict, seed: int) -> dict:
    """CMA-ES over one route's hole positions (in their regions) and ring guide angles.

    Seeded with ``seed``; returns the best variant (the route itself if none is better),
    its cost and the number of variants evaluated.
    """
    import cma

    from origami_cad._libm import canonical_eigh

    n = len(route["faces"])
    dim = int(route["count"].sum()) * 2 + (n if geom.placement.kind == "ring" else 0)
    polys: dict = {}

    def cost(genomes: np.ndarray) -> np.ndarray:
        angle, xy = _decode(geom, route, genomes)
        return _score_arrays(geom, settings, angle, xy, route).cost + 1e3 * _outside(
            geom, route, xy, polys
        )

    best_g, best_c = np.zeros(dim), float(cost(np.zeros((1, dim)))[0])
    opts = {"seed": seed + 1, "maxiter": settings.generations, "verbose": -9, "verb_log": 0}
    opts.update(verb_disp=0, popsize=max(8, 4 + int(3 * math.log(dim))), tolfun=1e-6)
    opts["CMA_eigenmethod"] = canonical_eigh  # the same samples whatever the CPU (issue 27)
    es = cma.CMAEvolutionStrategy(np.zeros(dim), 0.5, opts)
    evaluated, since = 1, 0
    while not es.stop() and since < STALL:
        pop = np.asarray(es.ask())
        c = cost(pop)
        evaluated += len(pop)
        es.tell(list(pop), c.tolist())
        k = int(np.argmin(c))
        since += 1
        if c[k] < best_c - 1e-9:
            best_g, best_c, since = pop[k].copy(), float(c[k]), 0
    angle, xy = _decode(geom, route, best_g[None])
    return {**route, "angle": angle[0], "xy": xy[0], "cost": best_c, "evaluated": evaluated}


# --------------------------------------------------------------------------- driver


def run_tasks(
    executor: cf.Executor | None,
    fn: Callable,
    tasks: Sequence[tuple],
    progress: Callable[[Any], None] | None = None,
) -> list:
    """``fn(*task)`` for every task on ``executor``; results in task order.

    Default: a process pool on this machine (one worker per core, fork where
    available). Any ``concurrent.futures.Executor`` works, e.g. a Dask cluster's
    ``Client.get_executor()``. ``progress(result)`` is called as tasks finish (in
    whatever order they finish); the results never depend on that order.
    """
    own = executor is None
    if own:
        executor = local_pool(len(tasks))
    try:
        futures = [executor.submit(fn, *task) for task in tasks]
        if progress is not None:
            for f in cf.as_completed(futures):
                progress(f.result())
        return [f.result() for f in futures]
    finally:
        if own:
            executor.shutdown(wait=True, cancel_futures=True)


def _starts(geom: PlanGeometry) -> list[np.ndarray]:
    """The (anchor, first hole) pairs, split into :data:`TASKS` contiguous chunks."""
    a, h = np.meshgrid(np.arange(len(geom.anchors)), np.arange(len(geom.hole_face)), indexing="ij")
    pairs = np.column_stack([a.ravel(), h.ravel()])
    return [c for c in np.array_split(pairs, TASKS) if len(c)]


def _merge(results: list[dict]) -> dict:
    pool = {
        k: np.concatenate([r[k] for r in results]) for k in ("anchor", "holes", "sides", "cost")
    }
    order = np.lexsort((np.arange(len(pool["cost"])), pool["cost"]))
    return {k: v[order].astype(np.int64) if k != "cost" else v[order] for k, v in pool.items()}


def plan_routes(
    design: Design,
    tsa: TSAPlacement,
    n_strings: int,
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
    n_strings : int
        Strings the TSA twists.
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
    if n_strings < 1:
        raise StringsError(f"--strings must be >= 1, got {n_strings}")
    if candidates < 1:
        raise StringsError(f"--candidates must be >= 1, got {candidates}")
    settings = replace(settings or PlanSettings(), candidates=int(candidates))
    geom = geometry or plan_geometry(
        design,
        tsa,
        fabrication,
        settings,
        target_p=target_p,
        target_angles=target_angles,
        free_panels=free_panels,
        existing_holes=existing_holes,
    )
    planned = _search(geom, settings, n_strings, seed, executor, progress)
    return _check_best(design, geom, settings, planned, check)


def _search(geom, settings, n_strings: int, seed: int, executor, progress) -> list[PlannedRoute]:
    """Beam search of strings (tasks on ``executor``), string sets, CMA-ES of the best."""
    counter = [0]

    def tick(result: dict) -> None:
        counter[0] += int(result["evaluated"])
        if progress is not None:
            progress(counter[0], None)

    found = run_tasks(executor, _beam_task, [(geom, settings, s) for s in _starts(geom)], tick)
    pool = _merge(found)
    if not len(pool["cost"]):
        raise StringsError(
            "no string satisfies DCQC from flat to the target: every hole sequence lengthens "
            "or cuts a panel (try another TSA place or a smaller target)"
        )
    pool = {k: v[: max(4 * settings.candidates, 4 * SET_BEAM)] for k, v in pool.items()}
    routes, evaluated = _combine(geom, settings, pool, n_strings)
    tick({"evaluated": evaluated})
    arrays = [_route_arrays(geom, pool, r) for r in routes[: settings.keep]]
    tasks = [
        (geom, settings, arrays[k], seed + k) for k in range(min(settings.refine, len(arrays)))
    ]
    refined = run_tasks(executor, _refine_task, tasks, tick)
    planned = _ranked(geom, settings, refined, arrays[len(refined) :])
    return planned


def _strings_of(geom: PlanGeometry, route: dict) -> tuple[StringRoute, ...]:
    """The route's strings as :class:`StringRoute` records (the route file's view)."""
    anchors = _anchor_positions(geom, route["angle"])[:, 0]
    out = []
    for i, faces in enumerate(route["faces"]):
        c = int(route["count"][i])
        if geom.placement.kind == "ring":
            anchor, anchor_face = tuple(float(v) for v in anchors[i]), -1
        else:
            anchor = (*geom.anchor_xy, float(geom.placement.height))
            anchor_face = geom.anchor_face
        out.append(
            StringRoute(
                anchor=anchor,
                faces=tuple(int(f) for f in faces[:c]),
                points=tuple((float(x), float(y)) for x, y in route["xy"][i, :c]),
                sides=tuple(int(s) for s in route["sides"][i, :c]),
                names=tuple(geom.labels[int(f)] for f in faces[:c]),
                anchor_face=anchor_face,
            )
        )
    return tuple(out)


def _ranked(geom, settings, refined: list[dict], rest: list[dict]) -> list[PlannedRoute]:
    """Rescore the refined and the other routes, drop the invalid, rank by cost."""
    items = [(r, "cma") for r in refined] + [(r, "beam") for r in rest]
    planned = []
    for k, (route, stage) in enumerate(items):
        angle = np.asarray(route["angle"], dtype=float)[None]
        s = _score_arrays(geom, settings, angle, np.asarray(route["xy"])[None], route)
        if not s.valid[0]:
            continue
        planned.append((float(s.cost[0]), k, route, stage, s))
    planned.sort(key=lambda t: (t[0], t[1]))
    out, seen = [], set()
    for cost, _, route, stage, s in planned:
        key = np.round(np.asarray(route["xy"]), 6).tobytes() + np.round(route["angle"], 6).tobytes()
        if key in seen:
            continue
        seen.add(key)
        out.append(
            PlannedRoute(
                rank=len(out) + 1,
                strings=_strings_of(geom, route),
                turns=float(s.turns[0]),
                peak_torque=float(s.peak_torque[0]),
                share=float(s.share[0]),
                cost=cost,
                p=geom.ratios.copy(),
                curve_turns=s.theta[0] / (2.0 * math.pi),
                torque=s.torque[0],
                stage=stage,
                anchor_angles=tuple(float(a) for a in route["angle"]),
            )
        )
    return out[: settings.keep]


def route_spec(geom: PlanGeometry, planned: PlannedRoute) -> RouteSpec:
    """The planned route as a :class:`RouteSpec`, with the settings :func:`route_toml` writes."""
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
    from origami_cad.strings.dcqc import StopReason, simulate_dcqc

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


def route_toml(geom: PlanGeometry, planned: PlannedRoute, header: str = "") -> str:
    """The route file (TOML text, ``docs/strings.md``) of a planned route.

    Holes are written as points (mm) with their panel in a comment, sides explicitly
    (they follow the DCQC rule); ``[fabrication]`` states the printed sheet, so both
    string models stop at its eq. 6 limit, and ``p_max`` the target when it is below.
    """
    spec = route_spec(geom, planned)
    tsa = spec.tsa
    lines = [header.rstrip("\n")] if header else []
    lines += ["[tsa]", f'model = "{tsa.model}"']
    if tsa.model == "ring":
        lines += [f"d1 = {tsa.d1:g}", f"d2 = {tsa.d2:g}", f"string_width = {tsa.string_width:g}"]
    else:
        lines += [f"length = {tsa.length:g}", f"radius = {tsa.radius:g}"]
        lines.append(f"max_helix_angle = {tsa.max_helix_angle:g}")
    fab = geom.fabrication
    lines += ["", "[fabrication]", f"bias = {fab.bias:g}", f"height = {fab.height:g}"]
    lines += [f"thickness = {fab.thickness:g}", f"midlayer_bias = {fab.midlayer_bias:g}", ""]
    lines += ["[route]", f"thickness = {spec.thickness:g}", "take_up = 0.1", "step = 180.0"]
    lines.append(f"max_turns = {spec.max_turns:g}")
    if spec.p_max is not None:
        lines.append(f"p_max = {spec.p_max:.6f}")
    if spec.fixed_panel:
        lines.append(f"fixed_panel = {toml_string(spec.fixed_panel)}")
    for s in spec.strings:
        lines += ["", "[[route.strings]]"]
        if s.anchor_face >= 0:
            lines.append(f"anchor_panel = {toml_string(geom.labels[s.anchor_face])}")
        lines.append("anchor = [" + ", ".join(f"{v:.4f}" for v in s.anchor) + "]")
        holes = ", ".join(f"[{x:.4f}, {y:.4f}]" for x, y in s.points)
        lines.append(f"holes = [{holes}]  # panels {one_line(', '.join(s.names))}")
        sides = ", ".join('"top"' if v == TOP else '"bottom"' for v in s.sides)
        lines.append(f"sides = [{sides}]  # DCQC: above valleys, below mountains")
    return "\n".join(lines) + "\n"
