"""Plots of planned string routes: the best routes on the pattern and their p(turns) curves."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from origami_cad.pattern.model import CreasePattern
from origami_cad.strings.plan import PlannedRoute
from origami_cad.viz.figure import png_subplots
from origami_cad.viz.pattern_plot import plot_pattern
from origami_cad.viz.strings_plots import draw_strings

__all__ = ["save_planned_routes_png", "save_planned_turns_png"]


def save_planned_routes_png(
    cp: CreasePattern, routes: Sequence[PlannedRoute], path: str | os.PathLike[str]
) -> Path:
    """The best (at most four) routes drawn on the flat pattern, one panel each."""
    shown = list(routes[:4]) or []
    cols = 2 if len(shown) > 1 else 1
    rows = (len(shown) + cols - 1) // cols or 1
    with png_subplots(path, rows, cols, figsize=(6.5 * cols, 6.0 * rows), squeeze=False) as (
        _,
        axes,
    ):
        for ax in axes.ravel():
            ax.set_axis_off()
        for ax, r in zip(axes.ravel(), shown, strict=False):
            ax.set_axis_on()
            plot_pattern(cp, ax, legend=False, title="")
            draw_strings(ax, r.strings)
            ax.set_title(
                f"#{r.rank}: {r.turns:.1f} turns, peak {r.peak_torque:.3g} N mm, "
                f"share {r.share:.2f}",
                fontsize=10,
            )
            ax.autoscale()
            ax.set_aspect("equal")
    return Path(path)


def save_planned_turns_png(
    routes: Sequence[PlannedRoute], path: str | os.PathLike[str], count: int = 6
) -> Path:
    """Fold ratio p against TSA turns (DCQC model) of the best ``count`` routes."""
    with png_subplots(path, figsize=(7.5, 4.8)) as (_, ax):
        for r in routes[:count]:
            ax.plot(r.curve_turns, r.p, lw=2 if r.rank == 1 else 1.2, label=f"#{r.rank}")
        ax.set_xlabel("TSA rotation (turns)")
        ax.set_ylabel("fold ratio p")
        ax.set_ylim(
            0, max(1e-3, float(np.max([r.p[-1] for r in routes[:count]], initial=0.0))) * 1.05
        )
        ax.grid(True, alpha=0.3)
        ax.legend(frameon=False, fontsize=8)
        ax.set_title("Planned routes: p against TSA turns (DCQC model)", fontsize=11)
    return Path(path)
