"""Plot of a calibration: measured force against pull (the runs' mean and spread) and the
simulated curve before and after the fit."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad.viz.figure import png_subplots

__all__ = ["save_fit_png"]


def save_fit_png(fit: Any, path: str | os.PathLike[str], title: str = "") -> Path:
    """Force (N) against pull (mm): the runs' mean, their spread (min to max), and the
    simulation with the starting and the fitted parameters.

    ``fit`` has ``grid`` (G,) mm, ``runs`` (R, G) N, ``simulated`` and ``before`` (G,) N,
    ``error`` and ``error_before`` (normalised RMSE), as
    :class:`origami_cad.simulation.calibrate.Calibration` does.
    """
    runs = np.asarray(fit.runs, dtype=float)
    with png_subplots(path, 1, 1, figsize=(7.5, 4.2), dpi=140) as (_, ax):
        ax.fill_between(fit.grid, runs.min(axis=0), runs.max(axis=0), color="#9bb7e8",
                        alpha=0.5, lw=0, label=f"measured: {len(runs)} runs, spread")  # fmt: skip
        ax.plot(fit.grid, runs.mean(axis=0), "-", color="#1f4fd6", lw=2, label="measured mean")
        ax.plot(fit.grid, fit.before, ":", color="#777777",
                label=f"simulated before (NRMSE {fit.error_before:.2f})")  # fmt: skip
        ax.plot(fit.grid, fit.simulated, "--", color="#d62728", lw=2,
                label=f"simulated, calibrated (NRMSE {fit.error:.2f})")  # fmt: skip
        peak = float(runs.max())  # a curve far above the runs is cut at 3 times their peak
        shown = [peak, float(np.max(fit.simulated)), float(np.max(fit.before))]
        ax.set_ylim(0.0, 1.1 * min(max(shown), 3.0 * peak))
        ax.set_xlabel("pull (mm)")
        ax.set_ylabel("force at the tendon's end (N)")
        if title:
            ax.set_title(title, fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    return Path(path)
