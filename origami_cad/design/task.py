"""Arm design tasks (the paper's Fig. 3a) and search settings, read from TOML.

.. code-block:: toml

    [arm]
    start = [0.0, 0.0]                      # T_s, mm
    points = [[250.0, 0.0], [50.0, 133.3]]  # P_start, (intermediate ...), P_end, mm
    weights = []                            # one per intermediate point (default 0)
    alpha = 120.0                           # eq. 5 weight, 0 <= alpha <= 600
    vectors = 6                             # n + 1 transition vectors
    length_range = [10.0, 120.0]            # mm, bounds of each l_i
    shape_angle_range = [10.0, 80.0]        # deg, bounds of |beta_i| (both leanings)
    entry_flag = "both"                     # or 0 / 1
    hypar_base = true                       # alpha_0 from eq. 3
    samples = 46                            # theta = 0 .. 180 deg
    unit_width = 36.0                       # mm; designs must be buildable at this width
    min_leg_gap = 2.0                       # mm between neighbouring legs (0 width: no check)
    [[arm.warning]]                         # T_e inside counts as improper
    polygon = [[140, 30], [2000, 30], [2000, 2000], [140, 2000]]
    [[arm.prohibited]]                      # the chain may never touch these
    polygon = [[150, 40], [2000, 40], [2000, 2000], [150, 2000]]
    # an obstacle may also be a circle = [x, y, r], and a polygon may have holes = [[...]]
    [search]
    runs = 10
    seed = 1
    popsize = 0           # 0: the CMA-ES default, 4 + 3 ln(dimension)
    max_generations = 400
    sigma0 = 0.25         # initial step, in units of each variable's range
    [fabrication]         # the printed arm folds only as far as its creases allow (eq. 6)
    bias = 3.0            # b, mm: inner bias of every crease
    height = 2.2          # h, mm
    thickness = 0.4       # t, mm
    # fold_limit = 146.6  # deg: the largest fold angle of every crease, instead of b, h, t
    codesign = false      # true: the bias is searched too, in [bias, max_bias] as panels allow
    max_bias = 6.0        # mm, upper bound of the co-designed bias
    min_panel_face = 5.0  # mm, narrowest outer face the chamfers may leave on a panel

Without a ``[fabrication]`` table the paper's b = 3, h = 2.2, t = 0.4 mm apply;
``fold_limit = 180`` gives the unlimited fold range of the paper (0 <= p <= 1).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from origami_cad._args import Arg, brief_value, check_fields, checked
from origami_cad._toml import Table, finite_toml, load_toml, toml_table
from origami_cad.design.predicates import PackedAreas, pack_areas
from origami_cad.errors import DesignError
from origami_cad.kinematics.limits import crease_fold_limit

__all__ = ["ArmTask", "SearchSettings", "dump_task", "load_task", "task_to_dict"]

#: Vertices of the polygon that stands for a circular obstacle.
CIRCLE_SEGMENTS = 128
#: Limits on the counts of a task file (far beyond any useful search).
MAX_SAMPLES = 10_000
MAX_RUNS = 10_000
MAX_POPSIZE = 100_000
MAX_GENERATIONS = 1_000_000
#: Most vertices of all warning and prohibited polygons together.
MAX_AREA_VERTICES = 100_000


#: The types of an :class:`ArmTask`'s fields (its ranges and finer rules follow); mm, deg.
_TASK_FIELDS = {
    "start": Arg("floats", length=2, optional=False),
    "alpha": Arg(optional=False),
    "vectors": Arg("int", max=1000, optional=False),
    "length_range": Arg("floats", length=2, optional=False),
    "shape_angle_range": Arg("floats", length=2, optional=False),
    "entry_flag": Arg("int"),
    "hypar_base": Arg("bool", optional=False),
    "samples": Arg("int", max=100_000, optional=False),
    "unit_width": Arg(optional=False),
    "min_leg_gap": Arg(optional=False),
    "bias": Arg(optional=False),
    "height": Arg(optional=False),
    "thickness": Arg(optional=False),
    "fold_limit": Arg(),
    "codesign": Arg("bool", optional=False),
    "max_bias": Arg(optional=False),
    "min_panel_face": Arg(optional=False),
}


@dataclass(frozen=True)
class ArmTask:
    """A computational design task for an origami robotic arm (all lengths mm).

    Attributes
    ----------
    start : (float, float)
        ``T_s``, the fixed base.
    points : ndarray, shape (n_p, 2)
        ``P_start``, intermediate points, ``P_end``: ``T_e`` must pass them in order.
    weights : ndarray, shape (n_p - 2,)
        Reward weight of each intermediate point.
    alpha : float
        Eq. 5 weight of ``P_start`` (``600 - alpha`` goes to ``P_end``).
    vectors : int
        Number of transition vectors ``n + 1``.
    length_range : (float, float)
        Bounds of every ``l_i``.
    shape_angle_range : (float, float)
        Bounds of ``|beta_i|`` in degrees; ``beta`` may lean either way, so the
        allowed shape angles are ``[lo, hi]`` and ``[180 - hi, 180 - lo]``.
    entry_flag : int or None
        ``EF_0`` fixed to 0 or 1, or ``None`` to search both.
    hypar_base : bool
        ``alpha_0`` follows eq. 3.
    samples : int
        Number of sampled fold angles from 0 to pi (46: every 4 degrees).
    unit_width : float
        Unit width of the crease pattern the design must have (mm); a design
        whose neighbouring legs come closer than ``min_leg_gap`` mm along the
        long edges (or cross) cannot be built and is infeasible. 0: no check.
    min_leg_gap : float
        Smallest distance between neighbouring legs along the long edges, mm.
    warning, prohibited : tuple of shapely Polygon
        Warning areas (``T_e`` inside is an improper state) and prohibited
        areas (the chain touching one makes the design infeasible).
    bias, height, thickness : float
        ``b``, ``h``, ``t`` of eq. 6 of the printed arm, mm: every crease
        stops at ``theta_max`` and the fitness is evaluated over the fold
        range this leaves (:mod:`origami_cad.kinematics.limits`).
    fold_limit : float or None
        The largest fold angle of every crease in degrees, instead of eq. 6
        (180: no limit, the paper's range 0 <= p <= 1).
    codesign : bool
        Search the inner bias too (one more variable), in ``[bias, max_bias]`` mm.
    max_bias : float
        Upper bound of the co-designed bias, mm.
    min_panel_face : float
        Narrowest outer face a panel may keep between its chamfers, mm: a design
        whose panels cannot hold the bias is infeasible (with ``unit_width > 0``).
    """

    start: tuple[float, float] = (0.0, 0.0)
    points: np.ndarray = field(default_factory=lambda: np.array([[250.0, 0.0], [50.0, 133.3]]))
    weights: np.ndarray = field(default_factory=lambda: np.zeros(0))
    alpha: float = 120.0
    vectors: int = 6
    length_range: tuple[float, float] = (10.0, 120.0)
    shape_angle_range: tuple[float, float] = (10.0, 80.0)
    entry_flag: int | None = None
    hypar_base: bool = True
    samples: int = 46
    unit_width: float = 36.0
    min_leg_gap: float = 2.0
    warning: tuple[Any, ...] = ()
    prohibited: tuple[Any, ...] = ()
    bias: float = 3.0
    height: float = 2.2
    thickness: float = 0.4
    fold_limit: float | None = None
    codesign: bool = False
    max_bias: float = 6.0
    min_panel_face: float = 5.0

    def __post_init__(self) -> None:
        check_fields(self, DesignError, _TASK_FIELDS)
        try:
            pts = np.asarray(self.points, dtype=float)
            w = np.asarray(self.weights, dtype=float).reshape(-1)
        except (TypeError, ValueError, OverflowError):
            raise DesignError("an arm task's points and weights must be numbers (mm)") from None
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise DesignError(
                f"an arm task's points must be (x, y) pairs, mm, got {brief_value(self.points)}"
            )
        object.__setattr__(self, "points", pts)
        if w.size == 0:
            w = np.zeros(max(len(pts) - 2, 0))
        object.__setattr__(self, "weights", w)
        if len(pts) < 2:
            raise DesignError("an arm task needs at least two points (P_start and P_end)")
        if not (np.all(np.isfinite(pts)) and np.all(np.isfinite(self.start))):
            raise DesignError("the start and every point of an arm task must be finite (mm)")
        if not np.all(np.isfinite(w)) or np.any(w < 0):
            raise DesignError("the weights of an arm task must be finite and >= 0")
        if len(w) != len(pts) - 2:
            raise DesignError(f"{len(pts) - 2} intermediate points need as many weights")
        if not 0 <= self.alpha <= 600:
            raise DesignError(f"alpha must lie in [0, 600], got {self.alpha}")
        if self.vectors < 2:
            raise DesignError(f"vectors must be >= 2, got {self.vectors}")
        lo, hi = self.length_range
        if not 0 < lo <= hi:
            raise DesignError(f"length_range must satisfy 0 < min <= max, got {self.length_range}")
        blo, bhi = self.shape_angle_range
        if not 0 < blo <= bhi < 90:
            raise DesignError(
                f"shape_angle_range must satisfy 0 < min <= max < 90 deg, got "
                f"{self.shape_angle_range}"
            )
        if self.entry_flag not in (None, 0, 1):
            raise DesignError(f"entry_flag must be 0, 1 or 'both', got {self.entry_flag}")
        if self.samples < 2:
            raise DesignError(f"samples must be >= 2, got {self.samples}")
        if self.unit_width < 0 or self.min_leg_gap < 0:
            raise DesignError("unit_width and min_leg_gap must be >= 0 mm")
        for name in ("bias", "height", "thickness"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise DesignError(f"fabrication {name} must be > 0 mm, got {value}")
        if self.height <= self.thickness:
            raise DesignError(
                f"fabrication height h = {self.height:g} mm must exceed the crease "
                f"thickness t = {self.thickness:g} mm"
            )
        if self.fold_limit is not None and not 0 < self.fold_limit <= 180:
            raise DesignError(f"fold_limit must lie in (0, 180] deg, got {self.fold_limit}")
        if self.codesign and self.fold_limit is not None:
            raise DesignError("codesign searches the bias of eq. 6: give b, h, t, not fold_limit")
        if self.codesign and not self.max_bias > self.bias:
            raise DesignError(
                f"max_bias ({self.max_bias:g} mm) must exceed bias ({self.bias:g} mm) to codesign"
            )
        if self.min_panel_face < 0:
            raise DesignError(f"min_panel_face must be >= 0 mm, got {self.min_panel_face}")

    @property
    def dimension(self) -> int:
        """Search variables: n + 1 lengths, n shape angles (and the bias when co-designing)."""
        return 2 * self.vectors - 1 + int(self.codesign)

    @cached_property
    def packed_areas(self) -> tuple[PackedAreas, PackedAreas]:
        """The warning and prohibited areas packed for the compiled fitness (computed once)."""
        return pack_areas(self.warning), pack_areas(self.prohibited)

    @cached_property
    def fitness_constants(self) -> tuple:
        """The task's numbers as the compiled fitness takes them (computed once).

        ``fixed_limit`` (radians; NaN: eq. 6 at each design's bias), ``h - t`` (mm), the
        samples' fractions of the fold range (S,), ``hypar_base``, ``T_s`` (2,) mm, the
        points (P, 2) mm, their weights, ``alpha``, half the unit width (mm; 0: the build
        is not checked), the smallest leg gap and panel face (mm), then the warning and
        prohibited areas' packed arrays; the arguments of
        :func:`origami_cad.design.kernel.population_fitness` after the designs' own.
        """
        warn, pro = self.packed_areas
        fixed = math.nan if self.fold_limit is None else float(np.radians(self.fold_limit))
        return (
            fixed,
            float(self.height - self.thickness),
            np.linspace(0.0, 1.0, self.samples),
            bool(self.hypar_base),
            np.ascontiguousarray(self.start, dtype=float),
            np.ascontiguousarray(self.points, dtype=float),
            np.ascontiguousarray(self.weights, dtype=float),
            float(self.alpha),
            self.unit_width / 2.0 if self.unit_width > 0 else 0.0,
            float(max(self.min_leg_gap, 1e-9)),
            float(self.min_panel_face),
            warn.edges, warn.offsets, warn.boxes, pro.edges, pro.offsets, pro.boxes,
        )  # fmt: skip

    def crease_limit(self, bias: Any = None) -> Any:
        """The fold limit of every crease, radians: ``fold_limit``, else eq. 6 at ``bias`` (mm).

        ``bias`` defaults to the task's ``b``; an array gives one limit per design.
        """
        if self.fold_limit is not None:
            return np.radians(self.fold_limit)
        return crease_fold_limit(self.bias if bias is None else bias, self.height, self.thickness)


#: The types and finite ranges of a :class:`SearchSettings` (its finer rules follow).
_SEARCH_FIELDS = {
    "runs": Arg("int", optional=False),
    "seed": Arg("int", optional=False),
    "popsize": Arg("int", optional=False),
    "max_generations": Arg("int", max=1e9, optional=False),
    "sigma0": Arg(optional=False),
}


@dataclass(frozen=True)
class SearchSettings:
    """CMA-ES settings: ``runs`` independent runs seeded ``seed + run``."""

    runs: int = 10
    seed: int = 1
    popsize: int = 0
    max_generations: int = 400
    sigma0: float = 0.25

    def __post_init__(self) -> None:
        check_fields(self, DesignError, _SEARCH_FIELDS)
        if self.runs < 1:
            raise DesignError(f"runs must be >= 1, got {self.runs}")
        if not 0 <= self.seed <= 2**32 - 1 - self.runs:
            raise DesignError(
                f"seed must lie in [0, 2**32 - 1 - runs] (run k is seeded seed + k), "
                f"got {self.seed}"
            )
        if self.popsize < 0 or self.popsize == 1:
            raise DesignError(f"popsize must be 0 (default) or >= 2, got {self.popsize}")
        if self.max_generations < 1:
            raise DesignError(f"max_generations must be >= 1, got {self.max_generations}")
        if not 0 < self.sigma0 <= 1:
            raise DesignError(f"sigma0 must lie in (0, 1], got {self.sigma0}")


def _area(item: Table, kind: str) -> Any:
    if item.has("circle"):
        x, y, r = item.numbers("circle", length=3)
        if not r > 0:
            raise item.error("circle", f"radius must be > 0 mm, got {r:g}")
        item.finish()
        return shapely.Point(x, y).buffer(r, quad_segs=CIRCLE_SEGMENTS // 4)
    shell = item.pairs("polygon", min_length=3)
    holes = []
    if item.has("holes"):
        raw = item.data["holes"]
        item.used.add("holes")
        if not isinstance(raw, list):
            raise item.error("holes", "expected a list of polygons")
        for i, h in enumerate(raw):
            sub = Table({"polygon": h}, f"{item.where} holes[{i}]")
            holes.append(sub.pairs("polygon", min_length=3))
    item.finish()
    poly = shapely.Polygon(shell, holes)
    if not poly.is_valid:
        raise DesignError(
            f"{item.where}: the {kind} polygon is not valid ({shapely.is_valid_reason(poly)})"
        )
    return poly


def _fabrication_fields(fab: Table) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if fab.has("fold_limit"):
        for key in ("bias", "height", "thickness"):
            if fab.has(key):
                raise fab.error(key, "give either fold_limit or b, h, t (bias, height, thickness)")
        out["fold_limit"] = fab.number("fold_limit", low=0, high=180, low_open=True)
    else:
        out["bias"] = fab.number("bias", 3.0, low=0, high=100, low_open=True)
        out["height"] = fab.number("height", 2.2, low=0, high=100, low_open=True)
        out["thickness"] = fab.number("thickness", 0.4, low=0, high=100, low_open=True)
    out["codesign"] = fab.boolean("codesign", False)
    out["max_bias"] = fab.number("max_bias", 6.0, low=0, high=100, low_open=True)
    out["min_panel_face"] = fab.number("min_panel_face", 5.0, low=0, high=1000)
    return out


@checked(DesignError, path=Arg("path", optional=False))
def load_task(path: str | os.PathLike[str]) -> tuple[ArmTask, SearchSettings]:
    """Read an arm task file (TOML); errors name the file, table and key."""
    p = Path(path)
    top = Table(load_toml(p), str(p))
    arm = top.table("arm")
    search = top.table("search", {})
    fab = top.table("fabrication", {})
    top.finish()
    points = arm.pairs("points", min_length=2)
    n_mid = len(points) - 2
    weights = arm.numbers(
        "weights", [0.0] * n_mid, length=n_mid, check=lambda v: v >= 0, what="a weight must be >= 0"
    )
    ef = arm.data.get("entry_flag", "both")
    arm.used.add("entry_flag")
    if ef not in ("both", 0, 1) or isinstance(ef, bool):
        raise arm.error("entry_flag", f'expected 0, 1 or "both", got {ef!r}')
    areas = {}
    for kind in ("warning", "prohibited"):
        raw = arm.data.get(kind, [])
        arm.used.add(kind)
        if not isinstance(raw, list):
            raise arm.error(kind, "expected an array of tables [[arm." + kind + "]]")
        areas[kind] = tuple(
            _area(Table(item, f"{p} [[arm.{kind}]] #{i + 1}"), kind) for i, item in enumerate(raw)
        )
    n_area_vertices = sum(len(shapely.get_coordinates(a)) for k in areas for a in areas[k])
    if n_area_vertices > MAX_AREA_VERTICES:
        raise DesignError(
            f"{p} [arm]: the warning and prohibited areas have {n_area_vertices:,} vertices, "
            f"more than the limit of {MAX_AREA_VERTICES:,}"
        )
    lr = arm.numbers("length_range", [10.0, 120.0], length=2)
    sr = arm.numbers("shape_angle_range", [10.0, 80.0], length=2)
    try:
        task = ArmTask(
            start=tuple(arm.point("start", [0.0, 0.0])),
            points=np.array(points),
            weights=np.array(weights),
            alpha=arm.number("alpha", 120.0, low=0, high=600),
            vectors=arm.integer("vectors", 6, low=2, high=64),
            length_range=(lr[0], lr[1]),
            shape_angle_range=(sr[0], sr[1]),
            entry_flag=None if ef == "both" else int(ef),
            hypar_base=arm.boolean("hypar_base", True),
            samples=arm.integer("samples", 46, low=2, high=MAX_SAMPLES),
            unit_width=arm.number("unit_width", 36.0, low=0),
            min_leg_gap=arm.number("min_leg_gap", 2.0, low=0),
            warning=areas["warning"],
            prohibited=areas["prohibited"],
            **_fabrication_fields(fab),
        )
        arm.finish()
        fab.finish()
        runs = search.integer("runs", 10, low=1, high=MAX_RUNS)
        settings = SearchSettings(
            runs=runs,
            # run k is seeded seed + k, and seeds are 32-bit unsigned (NumPy, CMA-ES)
            seed=search.integer("seed", 1, low=0, high=2**32 - 1 - runs),
            popsize=search.integer("popsize", 0, low=0, high=MAX_POPSIZE),
            max_generations=search.integer("max_generations", 400, low=1, high=MAX_GENERATIONS),
            sigma0=search.number("sigma0", 0.25, low=0, high=1, low_open=True),
        )
        search.finish()
    except DesignError as exc:
        msg = str(exc)
        raise DesignError(msg if msg.startswith(str(p)) else f"{p}: {msg}") from None
    return task, settings


def _area_tables(areas: tuple[Any, ...], name: str) -> list[str]:
    """``[[arm.warning]]`` / ``[[arm.prohibited]]`` tables: each polygon and its holes, mm."""
    lines: list[str] = []
    for area in areas:
        ring = shapely.get_coordinates(area.exterior).tolist()
        holes = [shapely.get_coordinates(h).tolist() for h in area.interiors]
        lines += ["", *toml_table(name, {"polygon": ring, "holes": holes or None}, array=True)]
    return lines


def dump_task(task: ArmTask, settings: SearchSettings | None = None, *, header: str = "") -> str:
    """An arm task file (TOML text) that :func:`load_task` reads back (lengths mm, angles deg).

    A circular area is written as the polygon it was read as (:data:`CIRCLE_SEGMENTS`
    vertices); without ``settings`` the file has no ``[search]`` table (the defaults).

    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "task.toml"
    >>> task = ArmTask(points=[[250.0, 0.0], [120.0, 60.0], [50.0, 133.3]], weights=[2.0])
    >>> _ = path.write_text(dump_task(task, SearchSettings(runs=3)))
    >>> back, settings = load_task(path)
    >>> back.weights.tolist(), settings.runs
    ([2.0], 3)
    """
    arm = {
        "start": [float(v) for v in task.start],
        "points": task.points.tolist(),
        "weights": task.weights.tolist() if task.weights.size else None,
        "alpha": float(task.alpha),
        "vectors": int(task.vectors),
        "length_range": [float(v) for v in task.length_range],
        "shape_angle_range": [float(v) for v in task.shape_angle_range],
        "entry_flag": "both" if task.entry_flag is None else int(task.entry_flag),
        "hypar_base": bool(task.hypar_base),
        "samples": int(task.samples),
        "unit_width": float(task.unit_width),
        "min_leg_gap": float(task.min_leg_gap),
    }
    limit = (
        {"fold_limit": float(task.fold_limit)}
        if task.fold_limit is not None
        else {"bias": task.bias, "height": task.height, "thickness": task.thickness}
    )
    fab = {
        **limit,
        "codesign": bool(task.codesign),
        "max_bias": float(task.max_bias),
        "min_panel_face": float(task.min_panel_face),
    }
    lines = [header.rstrip("\n")] if header else []
    lines += toml_table("arm", arm, comments={"start": "T_s, mm", "points": "mm"})
    lines += _area_tables(task.warning, "arm.warning")
    lines += _area_tables(task.prohibited, "arm.prohibited")
    lines += ["", *toml_table("fabrication", {k: v for k, v in fab.items()})]
    if settings is not None:
        search = {
            "runs": settings.runs,
            "seed": settings.seed,
            "popsize": settings.popsize,
            "max_generations": settings.max_generations,
            "sigma0": float(settings.sigma0),
        }
        lines += ["", *toml_table("search", search)]
    return finite_toml("\n".join(lines) + "\n", "the arm task file", DesignError)


def task_to_dict(task: ArmTask, settings: SearchSettings | None = None) -> dict[str, Any]:
    """A JSON-ready description of the task (and settings), as written to results.json."""
    out: dict[str, Any] = {
        "start": list(task.start),
        "points": task.points.tolist(),
        "weights": task.weights.tolist(),
        "alpha": task.alpha,
        "vectors": task.vectors,
        "length_range": list(task.length_range),
        "shape_angle_range": list(task.shape_angle_range),
        "entry_flag": "both" if task.entry_flag is None else task.entry_flag,
        "hypar_base": task.hypar_base,
        "samples": task.samples,
        "unit_width": task.unit_width,
        "min_leg_gap": task.min_leg_gap,
        "warning": [shapely.get_coordinates(a.exterior).tolist() for a in task.warning],
        "prohibited": [shapely.get_coordinates(a.exterior).tolist() for a in task.prohibited],
        "fabrication": {
            "bias_mm": task.bias,
            "height_mm": task.height,
            "thickness_mm": task.thickness,
            "fold_limit_deg": task.fold_limit,
            "crease_limit_deg": float(np.degrees(task.crease_limit())),
            "codesign": task.codesign,
            "max_bias_mm": task.max_bias,
            "min_panel_face_mm": task.min_panel_face,
        },
    }
    if settings is not None:
        out["search"] = {
            "runs": settings.runs,
            "seed": settings.seed,
            "popsize": settings.popsize,
            "max_generations": settings.max_generations,
            "sigma0": settings.sigma0,
        }
    return out
