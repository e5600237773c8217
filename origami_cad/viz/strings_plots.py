"""Plots of string routings (Fig. 5e) and of the DCQC folding curve."""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np
from matplotlib.patches import Circle

from origami_cad.pattern.model import CreasePattern
from origami_cad.strings.dcqc import DCQCResult
from origami_cad.strings.route import TOP, RouteSpec
from origami_cad.viz._figure import png_subplots
from origami_cad.viz.pattern_plot import plot_pattern

__all__ = ["save_dcqc_png", "save_route_png"]

_COLORS = ["#8e44ad", "#e67e22", "#16a085", "#c0392b", "#2c3e50", "#d35400"]


def save_route_png(cp: CreasePattern, route: RouteSpec, path: str | os.PathLike[str]) -> Path:
    """The flat pattern with holes and every string: solid above the sheet, dashed below."""
    x0, y0, x1, y1 = cp.bounds
    with png_subplots(
        path, figsize=(9, 9 * float(np.clip((y1 - y0) / (x1 - x0), 0.3, 1.5))), dpi=150
    ) as (_, ax):
        plot_pattern(cp, ax, legend=False, title="")
        for i, s in enumerate(route.strings):
            color = _COLORS[i % len(_COLORS)]
            pts = np.asarray(s.points)
            ax.plot([s.anchor[0], pts[0, 0]], [s.anchor[1], pts[0, 1]], ":", color=color, lw=1.5)
            ax.plot(*s.anchor[:2], "^", color=color, ms=9)
            for k in range(1, len(pts)):
                style = "-" if s.sides[k] == TOP else "--"
                ax.plot(
                    pts[k - 1 : k + 1, 0],
                    pts[k - 1 : k + 1, 1],
                    style,
                    color=color,
                    lw=2.5,
                    label=f"string {i + 1}" if k == 1 else None,
                )
            for x, y in pts:
                ax.add_patch(Circle((x, y), 1.5, fc="white", ec=color, lw=1.5, zorder=5))
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, fontsize=8)
        ax.set_title("String routing: solid above the sheet, dashed below; triangle = TSA anchor")
        ax.autoscale()
        ax.set_aspect("equal")
    return Path(path)


def save_dcqc_png(result: DCQCResult, path: str | os.PathLike[str]) -> Path:
    """Fold ratio p against TSA turns, with the reason the folding stopped."""
    with png_subplots(path, figsize=(7.5, 4.8), dpi=150) as (_, ax):
        ax.plot(result.turns, result.p, lw=2, color="#1f4fd6")
        ax.plot(result.turns[-1], result.p[-1], "o", color="#d62728")
        ax.set_xlabel("TSA rotation (turns)")
        ax.set_ylabel("fold ratio p")
        ax.set_ylim(0, 1)
        ax.grid(True, alpha=0.3)
        ax.set_title(f"DCQC folding: final p = {result.p[-1]:.3f}", fontsize=11)
        ax.text(
            0.02, 0.96, result.reason, transform=ax.transAxes, fontsize=7.5, va="top", wrap=True
        )
    return Path(path)
