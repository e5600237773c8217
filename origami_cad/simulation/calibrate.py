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
- a CSV with a header naming ``pull_mm`` and ``tension_N`` (or ``force_N``) columns.

A missing or non-numeric column, a pull that decreases, or too few rows is a
:class:`SimulationError` naming the file and the row.
"""

from __future__ import annotations

import csv
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad.errors import SimulationError
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.materials import Materials
from origami_cad.simulation.pull import simulate_pull
from origami_cad.strings.route import RouteSpec

__all__ = ["FITTED", "Calibration", "calibrate", "nrmse", "read_force_curve"]

#: The parameters :func:`calibrate` fits, with their bounds (stiffness N mm/rad per mm).
FITTED = {"crease_stiffness": (1e-5, 10.0), "hole_friction": (0.0, 1.0)}


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
    p = Path(path)
    where = str(p)
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

    def to_dict(self) -> dict[str, Any]:
        """``calibration.json``."""
        return {
            "parameters": {
                k: {"value": v, "standard_error": self.sigma[k]} for k, v in self.values.items()
            },
            "units": {"crease_stiffness": "N mm/rad per mm", "hole_friction": "1"},
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


def calibrate(
    cp: CreasePattern,
    route: RouteSpec,
    runs: list[tuple[np.ndarray, np.ndarray]],
    materials: Materials | None = None,
    *,
    fit: tuple[str, ...] = ("crease_stiffness", "hole_friction"),
    step: float = 2.0,
    max_evaluations: int = 40,
    names: list[str] | None = None,
) -> Calibration:
    """Fit ``fit`` (names of :data:`FITTED`) so the pull simulation matches the runs' mean.

    ``runs`` are ``(pull mm, force N)`` curves; the grid is every ``step`` mm up to the
    shortest run's end. ``materials`` are the starting values (default :class:`Materials`),
    ``max_evaluations`` bounds the simulations. Bounded least squares on the residual
    (simulated - mean) / peak; the standard errors from the Jacobian at the optimum.
    """
    from scipy.optimize import least_squares

    if not runs:
        raise SimulationError("calibrate: no measured run")
    unknown = [n for n in fit if n not in FITTED]
    if unknown or not fit:
        known = ", ".join(FITTED)
        raise SimulationError(f"calibrate: cannot fit {unknown or fit} (known: {known})")
    start = materials or Materials()
    end = min(float(p[-1]) for p, _ in runs)
    grid = np.linspace(0.0, end, max(2, int(end / step) + 1))
    measured = np.array([np.interp(grid, p, f) for p, f in runs])
    mean = measured.mean(axis=0)
    peak = float(np.max(np.abs(mean)))

    def materials_of(x: np.ndarray) -> Materials:
        values = {}
        for name, v in zip(fit, x, strict=True):
            if name == "crease_stiffness":
                values["crease_stiffness_given"] = float(10.0**v)
            else:
                values[name] = float(v)
        return start.replace(**values)

    def residual(x: np.ndarray) -> np.ndarray:
        return (_curve(cp, route, materials_of(x), grid, step) - mean) / peak

    x0 = np.array([
        math.log10(start.crease_stiffness()) if n == "crease_stiffness" else start.hole_friction
        for n in fit
    ])  # fmt: skip
    scale = [math.log10 if n == "crease_stiffness" else float for n in fit]
    lo = np.array([f(FITTED[n][0]) for f, n in zip(scale, fit, strict=True)])
    hi = np.array([f(FITTED[n][1]) for f, n in zip(scale, fit, strict=True)])
    x0 = np.clip(x0, lo, hi)
    before = residual(x0) * peak + mean
    out = least_squares(residual, x0, bounds=(lo, hi), max_nfev=max_evaluations, diff_step=0.05)
    fitted = materials_of(out.x)
    simulated = out.fun * peak + mean
    sigma_x = _standard_errors(out)
    values, sigma = {}, {}
    for name, v, s in zip(fit, out.x, sigma_x, strict=True):
        if name == "crease_stiffness":
            values[name] = float(10.0**v)
            sigma[name] = float(10.0**v * math.log(10.0) * s)
        else:
            values[name], sigma[name] = float(v), float(s)
    return Calibration(
        values, sigma, fitted, grid, measured, simulated, before,
        nrmse(simulated, mean), nrmse(before, mean),
        [nrmse(simulated, m) for m in measured], int(out.nfev),
        names or [f"run {i + 1}" for i in range(len(runs))],
    )  # fmt: skip


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
