"""Flat crease-pattern plots (matplotlib): mountain red solid, valley blue dashed."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.patches import Circle

from origami_cad._names import plot_text
from origami_cad.pattern.model import CreasePattern
from origami_cad.viz.figure import new_axes, png_subplots

__all__ = ["EDGE_STYLES", "plot_pattern", "save_pattern_png"]

#: Line style of each assignment: (colour, linestyle, linewidth).
EDGE_STYLES: dict[str, tuple[str, Any, float]] = {
    "B": ("black", "solid", 1.6),
    "M": ("#d62728", "solid", 1.0),
    "V": ("#1f4fd6", (0, (4, 2)), 1.0),
    "C": ("#2ca02c", "solid", 1.2),
    "F": ("#bbbbbb", "dotted", 0.6),
    "U": ("#cc00cc", "dashdot", 0.8),
    "J": ("#cc00cc", "dashdot", 0.8),
}
_NAMES = {"B": "border", "M": "mountain", "V": "valley", "C": "cut", "F": "flat", "U": "unassigned"}


def plot_pattern(
    cp: CreasePattern,
    ax: Axes | None = None,
    *,
    labels: bool = False,
    legend: bool = True,
    title: str | None = None,
) -> Axes:
    """Draw a crease pattern on matplotlib axes (mm, equal aspect).

    Parameters
    ----------
    cp : CreasePattern
        The pattern.
    ax : matplotlib Axes, optional
        Where to draw; a new figure if omitted.
    labels : bool
        Write each panel's label at its centroid.
    legend : bool
        Show a legend of the edge types present.
    title : str, optional
        Axes title (default: the pattern's title).
    """
    if ax is None:
        ax = new_axes((7, 7 * _aspect(cp)))
    for letter, (color, style, width) in EDGE_STYLES.items():
        mask = cp.assignments == letter
        if not mask.any():
            continue
        segs = cp.vertices[cp.edges[mask]]
        ax.add_collection(
            LineCollection(
                segs, colors=color, linestyles=style, linewidths=width, label=_NAMES.get(letter)
            )
        )
    for hole in cp.holes:
        ax.add_patch(Circle((hole.x, hole.y), hole.diameter / 2, fill=False, color="#2ca02c"))
    if labels:
        for (x, y), text in zip(cp.face_centroids(), cp.face_labels, strict=True):
            ax.text(x, y, plot_text(text), ha="center", va="center", fontsize=6, color="#555555")
    x0, y0, x1, y1 = cp.bounds
    pad = 0.03 * max(x1 - x0, y1 - y0, 1e-9)
    ax.set_xlim(x0 - pad, x1 + pad)
    ax.set_ylim(y0 - pad, y1 + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(plot_text(cp.title) if title is None else title)
    if legend:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    return ax


def _aspect(cp: CreasePattern) -> float:
    x0, y0, x1, y1 = cp.bounds
    return float(np.clip((y1 - y0) / max(x1 - x0, 1e-9), 0.3, 1.5))


def save_pattern_png(
    cp: CreasePattern, path: str | os.PathLike[str], *, dpi: int = 150, labels: bool = False
) -> Path:
    """Save a PNG picture of the flat pattern (atomic write)."""
    with png_subplots(path, figsize=(8, 8 * _aspect(cp)), dpi=dpi) as (_, ax):
        plot_pattern(cp, ax, labels=labels)
    return Path(path)
