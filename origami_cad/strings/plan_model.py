"""The route planner's records: where the TSA is, how hard the search looks, what it scores on.

:mod:`origami_cad.strings.plan` describes the search; its geometry is
:mod:`~origami_cad.strings.plan_geometry`, its scoring :mod:`~origami_cad.strings.plan_scoring`
and its beam search and CMA-ES :mod:`~origami_cad.strings.plan_search`. Lengths mm, torques
N mm, angles as each field says.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from origami_cad.errors import StringsError
from origami_cad.fabrication.params import FabricationParams
from origami_cad.strings.route import TOP, StringRoute
from origami_cad.strings.tsa import TSAParams

__all__ = [
    "DEFAULT_CREASE_STIFFNESS",
    "PlanGeometry",
    "PlanSettings",
    "PlannedRoute",
    "RouteScores",
    "TSAPlacement",
]

#: N mm / rad / mm: the default printed sheet's crease stiffness (TPU 95A, E = 26 MPa,
#: t = 0.4 mm over a 7 mm hinge zone: E t^3 / (12 w)), ``SimulationParams().crease_stiffness``.
DEFAULT_CREASE_STIFFNESS = 26.0 * 0.4**3 / (12.0 * 7.0)


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
    candidate holes go; ``keep`` routes returned. ``time_limit``: wall-clock seconds
    :func:`~origami_cad.strings.plan.plan_routes` may take; it sets ``deadline`` (a
    ``time.time()``, s) from it, past which no more string counts are tried and CMA-ES
    stops, keeping the best found (the result then depends on the machine's speed).
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
    time_limit: float = math.inf
    deadline: float = math.inf


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
    radius (empty: no holes there); ``notes`` what the geometry chose for the user (a
    smaller hole than asked).
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
    notes: tuple[str, ...] = ()


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
