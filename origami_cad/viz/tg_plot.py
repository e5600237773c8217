"""Plots of transition graphs: the chain at several fold ratios and the path of T_e."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.axes import Axes

from origami_cad.kinematics.chain import chain_points
from origami_cad.pattern.tg import TGDesign
from origami_cad.viz.figure import new_axes, png_subplots

__all__ = ["plot_tg", "save_tg_png"]


def plot_tg(
    design: TGDesign,
    ax: Axes | None = None,
    ratios: Sequence[float] = (0.0, 0.25, 0.5, 0.75, 1.0),
    samples: int = 91,
) -> Axes:
    """Draw the TG chain at several fold ratios and the path of ``T_e`` (mm).

    Parameters
    ----------
    design : TGDesign
        The TG.
    ratios : sequence of float
        Fold ratios ``p`` at which to draw the chain.
    samples : int
        Number of ``theta`` samples of the ``T_e`` path from 0 to pi.
    """
    if ax is None:
        ax = new_axes((7, 6))
    args = (
        design.lengths,
        np.radians(design.shape_angles),
        design.entry_flag,
        design.hypar_base,
        design.start,
    )
    path = chain_points(np.linspace(0, math.pi, samples), *args)[0, :, -1]
    ax.plot(path[:, 0], path[:, 1], color="#7f7f7f", lw=1.2, ls="--", label="$T_e$, p = 0 to 1")
    cmap = matplotlib.colormaps.get_cmap("viridis")
    chains = chain_points(np.asarray(ratios, float) * math.pi, *args)[0]
    for k, (p, pts) in enumerate(zip(ratios, chains, strict=True)):
        color = cmap(k / max(len(ratios) - 1, 1))
        ax.plot(pts[:, 0], pts[:, 1], "-o", color=color, ms=3, lw=2, label=f"p = {p:g}")
    ax.plot(*design.start, "ks", ms=7, label="$T_s$")
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    ax.set_title("Transition graph")
    return ax


def save_tg_png(design: TGDesign, path: str | os.PathLike[str], **kwargs) -> Path:
    """Save :func:`plot_tg` as a PNG (atomic write)."""
    with png_subplots(path, figsize=(9, 6), dpi=150) as (_, ax):
        plot_tg(design, ax, **kwargs)
    return Path(path)
