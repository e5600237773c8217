"""Plots of fabricated panels (the paper's Fig. 4a) and renders of the printed parts."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from matplotlib.collections import LineCollection, PatchCollection
from matplotlib.patches import Circle, Polygon

from origami_cad.fabrication.build import Fabrication
from origami_cad.fabrication.plan import PanelPlan
from origami_cad.viz.figure import png_subplots
from origami_cad.viz.pattern_plot import plot_pattern

__all__ = ["save_panels_png"]


def save_panels_png(
    plan: PanelPlan | Fabrication, path: str | os.PathLike[str], *, dpi: int = 150
) -> Path:
    """The flat pattern with inset outlines, operation regions (dash-dotted) and holes.

    Parameters
    ----------
    plan : PanelPlan or Fabrication
        The planned panels (no solid is needed).
    path : path-like
        Output PNG (atomic write).
    dpi : int
        Resolution, dots per inch.
    """
    x0, y0, x1, y1 = plan.pattern.bounds
    aspect = float(np.clip((y1 - y0) / max(x1 - x0, 1e-9), 0.3, 1.5))
    with png_subplots(path, figsize=(9, 9 * aspect), dpi=dpi) as (_, ax):
        plot_pattern(plan.pattern, ax, legend=False, title="")
        # one collection per kind (not an artist per panel): a 20 x 20 sheet draws fast
        outers = [Polygon(o.outer, closed=True) for o in plan.outlines]
        ax.add_collection(PatchCollection(outers, fc="#f6efe0", ec="#555555", lw=0.8))
        regions = [rings[0] for o in plan.outlines for rings in o.region]
        ax.add_collection(LineCollection(regions, colors="#ff7f0e", lw=0.9, linestyles="-."))
        circles = [Circle((h.x, h.y), h.diameter / 2) for h in plan.holes]
        ax.add_collection(PatchCollection(circles, fc="none", ec="#2ca02c", lw=1.2))
        p = plan.params
        ax.set_title(
            f"Panels: b = {p.bias:g} mm, h = {p.height:g} mm, t = {p.thickness:g} mm; "
            f"theta_max = {np.degrees(p.theta_max):.1f} deg; operation regions dash-dotted"
        )
    return Path(path)
