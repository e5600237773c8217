"""Plots of fabricated panels (the paper's Fig. 4a) and renders of the printed parts."""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np
import shapely
from matplotlib.patches import Circle, Polygon

from origami_cad.fabrication.build import Fabrication
from origami_cad.viz._figure import png_subplots
from origami_cad.viz.pattern_plot import plot_pattern

__all__ = ["save_panels_png"]


def save_panels_png(fab: Fabrication, path: str | os.PathLike[str], *, dpi: int = 150) -> Path:
    """The flat pattern with inset outlines, operation regions (dash-dotted) and holes."""
    x0, y0, x1, y1 = fab.pattern.bounds
    aspect = float(np.clip((y1 - y0) / max(x1 - x0, 1e-9), 0.3, 1.5))
    with png_subplots(path, figsize=(9, 9 * aspect), dpi=dpi) as (_, ax):
        plot_pattern(fab.pattern, ax, legend=False, title="")
        for o in fab.outlines:
            ax.add_patch(
                Polygon(o.outer, closed=True, fill=True, fc="#f6efe0", ec="#555555", lw=0.8)
            )
            if not o.region.is_empty:
                for part in shapely.get_parts(o.region):
                    c = shapely.get_coordinates(part.exterior)
                    ax.plot(c[:, 0], c[:, 1], color="#ff7f0e", lw=0.9, ls="-.")
        for _, x, y, d in fab.holes:
            ax.add_patch(Circle((x, y), d / 2, fill=False, ec="#2ca02c", lw=1.2))
        p = fab.params
        ax.set_title(
            f"Panels: b = {p.bias:g} mm, h = {p.height:g} mm, t = {p.thickness:g} mm; "
            f"theta_max = {np.degrees(p.theta_max):.1f} deg; operation regions dash-dotted"
        )
    return Path(path)
