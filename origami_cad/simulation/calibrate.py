"""Calibrate the model on measured force-against-pull curves (a tensile test of a structure).

The measured runs (PyGamiX's bench files, or a CSV with a header) are resampled on one
grid of pulls and averaged; the test-machine pull (:func:`~origami_cad.simulation.pull.
simulate_pull`) is fitted to their mean by bounded least squares
(``scipy.optimize.least_squares``) over the parameters named: the crease's bending
stiffness per length (N mm/rad per mm, fitted on a log scale) and the strings' hole
friction (capstan law). The error reported is the RMSE against the runs' mean over the
pull divided by the measured peak (the normalised RMSE), per run and for the mean.

Measurement files:

- PyGamiX's format: no header, 4 columns ``t - 0.1 (s), t (s), pull (mm), force (N)``,
  values quoted or not;
- a CSV with a header naming ``pull_mm`` and ``tension_N`` (or ``force_N``) columns;
- ``drive``'s CSV log (``t_s,id,target_turns,measured_turns,current_mA``): the servo's
  current becomes its torque (``(I - I_idle) stall_torque / stall_current``, N mm), the
  turns its TSA's twist, and eq. 8 (the ring TSA, :func:`~origami_cad.strings.tsa.
  ring_length`) turns both into pull (the string taken up, mm) and tension
  (torque / (dl/dtheta), N): :func:`drive_log_curve`.

A missing or non-numeric column, a pull that decreases, or too few rows is a
:class:`SimulationError` naming the file and the row.
"""

from __future__ import annotations

import csv
import dataclasses
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad._args import Arg, brief_value, checked
from origami_cad._toml import input_file
from origami_cad.errors import SimulationError
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.materials import Materials
from origami_cad.simulation.pull import simulate_pull
from origami_cad.strings.route import RouteSpec
from origami_cad.strings.tsa import TSAParams, ring_length, ring_length_derivatives

__all__ = [
    "FITTED",
    "Calibration",
    "ServoModel",
    "calibrate",
    "compare_materials",
    "design_tendons",
    "drive_log_curve",
    "load_runs",
    "nrmse",
    "read_force_curve",
    "select_tendons",
    "tendons_x_dis",
]

#: The parameters :func:`calibrate` fits, with their bounds (stiffness N mm/rad per mm;
#: softening: the crease's stiffness factor from :data:`SOFTENING_ANGLE` deg on).
FITTED = {
    "crease_stiffness": (1e-5, 10.0),
    "hole_friction": (0.0, 1.0),
    "crease_softening": (0.0, 1.0),
}

#: deg: a fitted softening law falls linearly from the stiffness at 0 deg to its
#: factor here, and holds it past (PyGamiX's crease: 0.58 at 60 deg).
SOFTENING_ANGLE = 60.0


def _softening_of(m: Materials) -> float:
    """The factor ``m``'s law reaches at :data:`SOFTENING_ANGLE` (1: linear)."""
    return float(np.interp(SOFTENING_ANGLE, m.law_angles, m.law_factors))


def _number(text: str, where: str, row: int, col: str) -> float:
    try:
        value = float(text.strip().strip('"').strip("'"))
    except ValueError:
        raise SimulationError(f"{where}: row {row}, {col}: {text!r} is not a number") from None
    if not math.isfinite(value):
        raise SimulationError(f"{where}: row {row}, {col}: {text!r} is not a finite number")
    return value


def read_force_curve(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """A measured run: ``(pull (N,) mm, force (N,) N)``, the pull never decreasing.

    PyGamiX's 4-column files (no header) and CSV files with ``pull_mm`` and
    ``tension_N`` (or ``force_N``) columns; errors name the file, the row and the column.
    """
    p, where = input_file(path, SimulationError)  # a device or a FIFO never ends
    try:
        rows = [r for r in csv.reader(p.read_text(encoding="utf-8-sig").splitlines()) if r]
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise SimulationError(f"{where}: cannot read: {exc}") from None
    if not rows:
        raise SimulationError(f"{where}: no rows")
    head = [c.strip().strip('"').lower() for c in rows[0]]
    if any(c[:1].isalpha() for c in head):  # a header
        force_col = next((n for n in ("tension_n", "force_n") if n in head), None)
        if "pull_mm" not in head or force_col is None:
            raise SimulationError(f"{where}: the header needs pull_mm and tension_N (or force_N)")
        cols, names = (head.index("pull_mm"), head.index(force_col)), ("pull_mm", force_col)
        body, first = rows[1:], 2
    else:  # PyGamiX's four columns
        cols, names = (2, 3), ("column 3 (pull, mm)", "column 4 (force, N)")
        body, first = rows, 1
    pull, force = [], []
    for i, row in enumerate(body, start=first):
        if len(row) <= max(cols):
            missing = names[0] if len(row) <= cols[0] else names[1]
            raise SimulationError(f"{where}: row {i}: no {missing}")
        pull.append(_number(row[cols[0]], where, i, names[0]))
        force.append(_number(row[cols[1]], where, i, names[1]))
        if len(pull) > 1 and pull[-1] < pull[-2]:
            raise SimulationError(
                f"{where}: row {i}: the pull decreases ({pull[-2]:g} -> {pull[-1]:g} mm)"
            )
    if len(pull) < 2 or pull[-1] <= pull[0]:
        raise SimulationError(f"{where}: fewer than two rows of increasing pull")
    return np.array(pull), np.array(force)


@dataclass(frozen=True)
class ServoModel:
    """A servo as a torque source: ``stall_torque`` N mm at ``stall_current`` mA, drawing
    ``idle_current`` mA unloaded (the default: a Dynamixel XL330-M288, ROBOTIS e-manual)."""

    stall_torque: float = 520.0
    stall_current: float = 1500.0
    idle_current: float = 5.0

    def torque(self, current_ma: np.ndarray) -> np.ndarray:
        """Shaft torque at ``current_ma`` mA, N mm (linear torque-current, >= 0)."""
        held = np.asarray(current_ma, dtype=float) - self.idle_current
        return np.clip(held, 0.0, None) * self.stall_torque / self.stall_current


def drive_log_curve(
    path: str | os.PathLike[str],
    tsa: TSAParams,
    x_dis: float,
    servo: ServoModel | None = None,
    *,
    servo_id: int | None = None,
    min_rate: float = 0.05,
) -> tuple[np.ndarray, np.ndarray]:
    """A ``drive`` log as a force-against-pull curve: ``(pull (N,) mm, tension (N,) N)``.

    The twist is ``2 pi (measured_turns - first)`` rad; the pull is eq. 8's string taken
    up, ``l(theta) - l(0)`` mm at ``x_dis`` mm (the TSA to its first hole); the tension
    is the servo's torque over ``dl/dtheta`` (mm/rad), N. Rows where ``dl/dtheta`` is
    below ``min_rate`` of its largest value (the first few degrees, where the torque
    says nothing of the tension) are left out. ``servo_id`` picks one servo of the log
    (default: the only one). Errors name the file and the row.
    """
    p, where = input_file(path, SimulationError)
    try:
        rows = list(csv.reader(p.read_text(encoding="utf-8-sig").splitlines()))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise SimulationError(f"{where}: cannot read: {exc}") from None
    rows = [r for r in rows if r and not r[0].lstrip().startswith("#")]
    need = ("id", "measured_turns", "current_mA")
    head = [c.strip() for c in rows[0]] if rows else []
    for name in need:
        if name not in head:
            raise SimulationError(f"{where}: the drive log's header has no {name} column")
    col = {n: head.index(n) for n in need}
    turns, current, ids = [], [], []
    for i, row in enumerate(rows[1:], start=2):
        if len(row) <= max(col.values()):
            raise SimulationError(f"{where}: row {i}: fewer columns than the header")
        ids.append(int(_number(row[col["id"]], where, i, "id")))
        turns.append(_number(row[col["measured_turns"]], where, i, "measured_turns"))
        current.append(_number(row[col["current_mA"]], where, i, "current_mA"))
    known = sorted(set(ids))
    if servo_id is None and len(known) > 1:
        raise SimulationError(f"{where}: servos {known} in the log; name one (servo_id)")
    pick = known[0] if servo_id is None and known else servo_id
    keep = [k for k, i in enumerate(ids) if i == pick]
    if len(keep) < 2:
        raise SimulationError(f"{where}: fewer than two rows of servo {pick}")
    t = np.array(turns)[keep]
    if np.any(np.diff(t) < -1e-9):
        k = int(np.argmax(np.diff(t) < -1e-9))
        raise SimulationError(f"{where}: servo {pick}'s turns decrease after its row {k + 2}")
    theta = 2.0 * math.pi * (t - t[0])
    length, rate, _, _ = ring_length_derivatives(theta, x_dis, tsa.d1, tsa.d2, tsa.string_width)
    pull = length - float(ring_length(0.0, x_dis, tsa.d1, tsa.d2, tsa.string_width))
    good = rate >= min_rate * float(np.max(rate, initial=0.0))
    if np.count_nonzero(good) < 2:
        raise SimulationError(f"{where}: the TSA turned too little to measure a tension")
    torque = (servo or ServoModel()).torque(np.array(current)[keep])
    return pull[good], torque[good] / rate[good]


def design_tendons(cp: CreasePattern, where: str = "calibrate") -> RouteSpec:
    """The tendons a design carries (a PyGamiX description's) as the route pulled; a
    :class:`SimulationError` naming ``where`` when it carries none."""
    from origami_cad.strings.route import route_from_pattern

    route = route_from_pattern(cp)
    if route is None:
        raise SimulationError(f"{where}: the design carries no tendons to pull")
    return route


def tendons_x_dis(route: RouteSpec) -> float:
    """The first tendon's anchor to its first hole in the flat sheet, mm (a drive log's
    default ``x_dis``)."""
    s = route.strings[0]
    return float(np.hypot(s.points[0][0] - s.anchor[0], s.points[0][1] - s.anchor[1]))


@checked(
    SimulationError,
    tsa=Arg("object", types=(TSAParams,)),
    x_dis=Arg(min=0.0, open_min=True, max=1e5),
    servo=Arg("object", types=(ServoModel,)),
    route=Arg("object", types=(RouteSpec,)),
)
def load_runs(
    paths: list[str | os.PathLike[str]],
    *,
    tsa: TSAParams | None = None,
    x_dis: float | None = None,
    servo: ServoModel | None = None,
    route: RouteSpec | None = None,
) -> list[tuple[np.ndarray, np.ndarray]]:
    """Measured runs from files: force-against-pull curves (:func:`read_force_curve`), or
    ``drive`` logs (a header with ``current_mA``) through ``tsa`` and ``x_dis`` mm
    (:func:`drive_log_curve`). Given the ``route`` pulled, ``tsa`` defaults to its TSA
    and ``x_dis`` to its first tendon's anchor to first hole (:func:`tendons_x_dis`)."""
    if route is not None:
        tsa = route.tsa if tsa is None else tsa
        x_dis = tendons_x_dis(route) if x_dis is None else x_dis
    if isinstance(paths, str | bytes | os.PathLike) or not isinstance(paths, list | tuple):
        raise SimulationError(
            f"load_runs: paths: expected a list of files, got {brief_value(paths)}"
        )
    for path in paths:
        Arg("path", optional=False).check("load_runs: paths", path, SimulationError)
        input_file(path, SimulationError)
    runs = []
    for path in paths:
        try:
            with Path(path).open(encoding="utf-8-sig") as fh:
                first = fh.readline()
        except (OSError, UnicodeDecodeError) as exc:
            raise SimulationError(f"{path}: cannot read: {exc}") from None
        if "current_mA" in first:
            if tsa is None or x_dis is None:
                raise SimulationError(f"{path}: a drive log needs the TSA and its x_dis")
            runs.append(drive_log_curve(path, tsa, x_dis, servo))
        else:
            runs.append(read_force_curve(path))
    return runs


def nrmse(simulated: np.ndarray, measured: np.ndarray) -> float:
    """RMSE between two curves on one grid, over the measured peak (dimensionless)."""
    peak = float(np.max(np.abs(measured)))
    return float(np.sqrt(np.mean((simulated - measured) ** 2)) / peak) if peak > 0 else math.inf


@dataclass
class Calibration:
    """The fit: ``values`` (name -> fitted value), ``sigma`` (name -> one standard error),
    ``materials`` (the file's values with them), ``grid`` (G,) mm, ``runs`` (R, G) N,
    ``simulated`` (G,) N, ``before`` (G,) N (the starting materials), the normalised
    RMSE against the mean (``error``, ``error_before``) and per run (``run_errors``)."""

    values: dict[str, float]
    sigma: dict[str, float]
    materials: Materials
    grid: np.ndarray
    runs: np.ndarray
    simulated: np.ndarray
    before: np.ndarray
    error: float
    error_before: float
    run_errors: list[float]
    evaluations: int
    names: list[str] = field(default_factory=list)

    def summary(self) -> str:
        """One line: the values fitted with their standard errors, the normalised RMSE
        before and after, the simulations run."""
        values = ", ".join(f"{k} = {v:.4g} +- {self.sigma[k]:.2g}" for k, v in self.values.items())
        return (
            f"fitted {values}; NRMSE {self.error:.3f} (start {self.error_before:.3f}) after "
            f"{self.evaluations} simulations"
        )

    def to_dict(self) -> dict[str, Any]:
        """``calibration.json``."""
        return {
            "parameters": {
                # null: a parameter these runs do not determine (no finite standard error)
                k: {
                    "value": v,
                    "standard_error": self.sigma[k] if math.isfinite(self.sigma[k]) else None,
                }
                for k, v in self.values.items()
            },
            "units": {
                "crease_stiffness": "N mm/rad per mm",
                "hole_friction": "1",
                "crease_softening": f"1 (the stiffness factor at {SOFTENING_ANGLE:g} deg)",
            },
            "nrmse_mean": self.error,
            "nrmse_mean_before": self.error_before,
            "nrmse_per_run": dict(zip(self.names, self.run_errors, strict=True)),
            "simulations": self.evaluations,
            "pull_mm": self.grid.tolist(),
            "measured_mean_N": self.runs.mean(axis=0).tolist(),
            "simulated_N": self.simulated.tolist(),
            "simulated_before_N": self.before.tolist(),
        }


def _curve(cp, route, materials: Materials, grid: np.ndarray, step: float) -> np.ndarray:
    run = simulate_pull(cp, route, float(grid[-1]), materials.simulation_params(), step=step)
    return np.interp(grid, run.pull, run.tension)


def _run_arrays(run: Any, i: int) -> tuple[np.ndarray, np.ndarray]:
    """A run given as a file (read by :func:`read_force_curve`) or as ``(pull mm, force N)``
    arrays, checked: 1-D, finite, as long, at least two, the pull never decreasing."""
    if isinstance(run, str | os.PathLike):
        return read_force_curve(run)
    try:
        pull, force = (np.asarray(a, dtype=float) for a in run)
    except (TypeError, ValueError, OverflowError):
        raise SimulationError(
            f"calibrate: run {i + 1}: expected a file or (pull, force) arrays"
        ) from None
    if pull.ndim != 1 or pull.shape != force.shape or len(pull) < 2:
        raise SimulationError(f"calibrate: run {i + 1}: pull and force must be 1-D, as long, >= 2")
    if not (np.all(np.isfinite(pull)) and np.all(np.isfinite(force))):
        raise SimulationError(f"calibrate: run {i + 1}: a pull or force is not finite")
    if np.any(np.diff(pull) < 0) or pull[-1] <= pull[0]:
        raise SimulationError(f"calibrate: run {i + 1}: the pull must increase")
    return pull, force


def _checked_call(cp, route, runs, materials, fit, step, max_evaluations):
    """The arguments of :func:`calibrate`, checked (a :class:`SimulationError` naming the one
    that is wrong): the route (default: the design's tendons) and the runs as arrays."""
    if not isinstance(cp, CreasePattern):
        raise SimulationError(f"calibrate: cp must be a CreasePattern, got {type(cp).__name__}")
    if route is None:
        route = design_tendons(cp)
    if not isinstance(route, RouteSpec):
        raise SimulationError(f"calibrate: route must be a RouteSpec, got {type(route).__name__}")
    if materials is not None and not isinstance(materials, Materials):
        raise SimulationError("calibrate: materials must be Materials or None")
    if isinstance(fit, str) or not isinstance(fit, tuple | list) or not fit:
        raise SimulationError(f"calibrate: fit must name parameters of {', '.join(FITTED)}")
    unknown = [n for n in fit if not isinstance(n, str) or n not in FITTED]
    if unknown:
        raise SimulationError(f"calibrate: cannot fit {unknown} (known: {', '.join(FITTED)})")
    if isinstance(step, bool) or not isinstance(step, int | float) or not 0.1 <= step < 1e4:
        raise SimulationError(
            f"calibrate: step must be a number of mm in [0.1, 1e4), got {brief_value(step)}"
        )
    if (
        isinstance(max_evaluations, bool)
        or not isinstance(max_evaluations, int)
        or not (1 <= max_evaluations <= 10_000)
    ):
        raise SimulationError("calibrate: max_evaluations must be an integer in [1, 10000]")
    if isinstance(runs, str | os.PathLike) or not isinstance(runs, list | tuple) or not runs:
        raise SimulationError("calibrate: runs must be a non-empty list of files or curves")
    return route, [_run_arrays(r, i) for i, r in enumerate(runs)]


def select_tendons(route: RouteSpec, tendons: tuple[int, ...] | None) -> RouteSpec:
    """``route`` with only its strings ``tendons`` (1-based; None: all of them), or a
    :class:`SimulationError` naming the tendon that does not exist."""
    if tendons is None:
        return route
    k = len(route.strings)
    if isinstance(tendons, str | bytes) or not isinstance(tendons, tuple | list) or not tendons:
        raise SimulationError(f"calibrate: tendons must be numbers in 1..{k}")
    for t in tendons:
        if isinstance(t, bool) or not isinstance(t, int) or not 1 <= t <= k:
            raise SimulationError(
                f"calibrate: tendon {brief_value(t)}: the route has tendons 1..{k}"
            )
    picked = tuple(route.strings[t - 1] for t in dict.fromkeys(tendons))
    return dataclasses.replace(route, strings=picked)


def _run_names(runs: list, names: list[str] | None) -> list[str]:
    """Each run's name in the results: ``names`` (checked: one string per run), else a
    file's name, or ``run i`` for curves given as arrays."""
    if names is None:
        return [Path(r).name if isinstance(r, str | os.PathLike) else f"run {i + 1}"
                for i, r in enumerate(runs)]  # fmt: skip
    if not (isinstance(names, list | tuple) and len(names) == len(runs)
            and all(isinstance(n, str) for n in names)):  # fmt: skip
        raise SimulationError("calibrate: names must be one string per run")
    return list(names)


def _on_grid(curves: list, step: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The runs on one grid: ``(grid (G,) mm, every step mm up to the shortest run's end;
    runs (R, G) N; their mean (G,) N)``."""
    end = min(float(p[-1]) for p, _ in curves)
    grid = np.linspace(0.0, end, max(2, int(end / step) + 1))
    measured = np.array([np.interp(grid, p, f) for p, f in curves])
    return grid, measured, measured.mean(axis=0)


@dataclass(frozen=True)
class _Variables:
    """The parameters ``fit`` as least squares' variables, from ``start``: log10 of the
    crease stiffness (N mm/rad per mm), the hole friction and the softening factor as
    they are."""

    fit: tuple[str, ...]
    start: Materials

    def materials(self, x: np.ndarray) -> Materials:
        """``start`` with the variables ``x``."""
        values: dict[str, Any] = {}
        for name, v in zip(self.fit, x, strict=True):
            if name == "crease_stiffness":
                values["crease_stiffness_given"] = float(10.0**v)
            elif name == "crease_softening":
                values["law_angles"] = (0.0, SOFTENING_ANGLE)
                values["law_factors"] = (1.0, float(v))
            else:
                values[name] = float(v)
        return self.start.replace(**values)

    def start_point(self) -> np.ndarray:
        """``start``'s variables."""
        m = self.start
        return np.array([
            math.log10(m.crease_stiffness()) if n == "crease_stiffness"
            else _softening_of(m) if n == "crease_softening" else m.hole_friction
            for n in self.fit
        ])  # fmt: skip

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The variables' bounds (:data:`FITTED`'s, the stiffness's on its log scale)."""
        scale = [math.log10 if n == "crease_stiffness" else float for n in self.fit]
        lo = np.array([f(FITTED[n][0]) for f, n in zip(scale, self.fit, strict=True)])
        hi = np.array([f(FITTED[n][1]) for f, n in zip(scale, self.fit, strict=True)])
        return lo, hi

    def values(self, x: np.ndarray, sigma_x: np.ndarray) -> tuple[dict, dict]:
        """``(values, standard errors)`` by name, in the parameters' units."""
        values, sigma = {}, {}
        for name, v, s in zip(self.fit, x, sigma_x, strict=True):
            if name == "crease_stiffness":
                values[name] = float(10.0**v)
                sigma[name] = float(10.0**v * math.log(10.0) * s)
            else:
                values[name], sigma[name] = float(v), float(s)
        return values, sigma


def _forward_differences(residual, hi: np.ndarray):
    """The Jacobian of ``residual`` by forward differences with a step of 0.03 in each
    variable (log10 of the stiffness, the friction): large beside the solver's tolerance,
    small beside the bounds; backwards within 0.03 of an upper bound ``hi``."""

    def jacobian(x: np.ndarray) -> np.ndarray:
        r0, cols = residual(x), []
        for i in range(len(x)):
            h = 0.03 if x[i] + 0.03 <= hi[i] else -0.03
            cols.append((residual(x + h * np.eye(len(x))[i]) - r0) / h)
        return np.array(cols).T

    return jacobian


def calibrate(
    cp: CreasePattern,
    route: RouteSpec | None,
    runs: list,
    materials: Materials | None = None,
    *,
    fit: tuple[str, ...] = ("crease_stiffness", "hole_friction"),
    step: float = 2.0,
    max_evaluations: int = 40,
    names: list[str] | None = None,
    tendons: tuple[int, ...] | None = None,
) -> Calibration:
    """Fit ``fit`` (names of :data:`FITTED`) so the pull simulation matches the runs' mean.

    ``route`` is the tendons pulled (None: the design's, a PyGamiX description's). ``runs``
    are measurement files (:func:`read_force_curve`) or ``(pull mm, force N)`` curves;
    the grid is every ``step`` mm up to the
    shortest run's end. ``materials`` are the starting values (default :class:`Materials`),
    ``max_evaluations`` bounds the least-squares evaluations (each forward-difference
    Jacobian costs one more simulation per fitted parameter, and a coarse start a few
    before them: ``Calibration.evaluations`` counts them all). Bounded least squares on the residual
    (simulated - mean) / peak; the standard errors from the Jacobian at the optimum.
    ``tendons`` (1-based) pulls only those of the route's strings (default: every one,
    on one crosshead).
    """
    from scipy.optimize import least_squares

    given = runs
    route, runs = _checked_call(cp, route, runs, materials, fit, step, max_evaluations)
    route = select_tendons(route, tendons)
    names = _run_names(given, names)
    variables = _Variables(tuple(fit), materials or Materials())
    grid, measured, mean = _on_grid(runs, step)
    peak = float(np.max(np.abs(mean)))
    seen: dict[bytes, np.ndarray] = {}

    def residual(x: np.ndarray) -> np.ndarray:
        """(simulated - mean) / peak at the variables ``x``, each point simulated once."""
        key = np.asarray(x, dtype=float).tobytes()
        if key not in seen:
            seen[key] = (_curve(cp, route, variables.materials(x), grid, step) - mean) / peak
        return seen[key]

    lo, hi = variables.bounds()
    x0 = np.clip(variables.start_point(), lo, hi)
    before = residual(x0) * peak + mean
    best, _ = _coarse_start(
        residual, x0, lo, hi, variables.fit, float(np.sum((before - mean) ** 2)) / peak**2
    )
    out = least_squares(
        residual, best, jac=_forward_differences(residual, hi), bounds=(lo, hi),
        max_nfev=max_evaluations, x_scale=np.full(len(variables.fit), 0.1),
    )  # fmt: skip
    evaluations = len(seen)
    simulated = out.fun * peak + mean
    values, sigma = variables.values(out.x, _standard_errors(out))
    return Calibration(
        values, sigma, variables.materials(out.x), grid, measured, simulated, before,
        nrmse(simulated, mean), nrmse(before, mean),
        [nrmse(simulated, m) for m in measured], evaluations,
        list(names),
    )  # fmt: skip


def compare_materials(
    design: CreasePattern | str | os.PathLike[str],
    runs: list,
    before: Materials,
    after: Materials,
    *,
    step: float = 2.0,
    tendons: tuple[int, ...] | None = None,
) -> Calibration:
    """Two materials' pulls against measured runs, no fit: a :class:`Calibration` whose
    ``before`` and ``simulated`` curves (N, on the runs' grid every ``step`` mm) are
    ``before``'s and ``after``'s, and ``values`` empty. ``design`` is a pattern carrying
    its tendons or its file; ``runs`` files or ``(pull mm, force N)`` curves."""
    from origami_cad.pattern import read_pattern

    cp = design if isinstance(design, CreasePattern) else read_pattern(design)
    route, curves = _checked_call(cp, None, runs, after, ("hole_friction",), step, 1)
    route = select_tendons(route, tendons)
    grid, measured, mean = _on_grid(curves, step)
    first = _curve(cp, route, before, grid, step)
    second = _curve(cp, route, after, grid, step)
    names = _run_names(runs, None)
    return Calibration(
        {}, {}, after, grid, measured, second, first, nrmse(second, mean), nrmse(first, mean),
        [nrmse(second, m) for m in measured], 2, names,
    )  # fmt: skip


def _coarse_start(residual, x0, lo, hi, fit, cost0: float) -> np.ndarray:
    """The best start of a grid around ``x0`` (crease stiffness / 4, x 1, x 4 on its log
    scale; hole friction 0, 0.1, 0.25 and 0.5; softening 0.3 and 1): least squares then
    starts in the right valley, not in the one the starting materials happen to lie in."""
    axes = [
        x + np.log10([0.25, 1.0, 4.0])
        if n == "crease_stiffness"
        else np.array([0.3, 1.0])
        if n == "crease_softening"
        else np.array([0.0, 0.1, 0.25, 0.5])
        for n, x in zip(fit, x0, strict=True)
    ]
    best, cost, tried = x0, cost0, 1
    for point in np.array(np.meshgrid(*axes, indexing="ij")).reshape(len(fit), -1).T:
        point = np.clip(point, lo, hi)
        if np.allclose(point, x0):
            continue
        c = float(np.sum(residual(point) ** 2))
        tried += 1
        if c < cost:
            best, cost = point, c
    return best, tried


def _standard_errors(out) -> np.ndarray:
    """One standard error of each fitted variable from the Jacobian at the optimum."""
    j = np.asarray(out.jac, dtype=float)
    dof = max(len(out.fun) - len(out.x), 1)
    s2 = float(np.sum(out.fun**2)) / dof
    try:
        cov = np.linalg.pinv(j.T @ j) * s2
    except np.linalg.LinAlgError:
        return np.full(len(out.x), math.inf)
    return np.sqrt(np.clip(np.diag(cov), 0.0, None))
