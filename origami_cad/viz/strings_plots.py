"""Plots of string routings (Fig. 5e) and of the DCQC folding curve."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from matplotlib.patches import Circle

from origami_cad._fileio import atomic_path
from origami_cad.pattern.model import CreasePattern
from origami_cad.strings.dcqc_result import DCQCResult
from origami_cad.strings.route import TOP, RouteSpec
from origami_cad.viz.figure import png_subplots
from origami_cad.viz.pattern_plot import plot_pattern

__all__ = ["draw_strings", "save_dcqc_png", "save_fig5_png", "save_route_png"]

_COLORS = ["#8e44ad", "#e67e22", "#16a085", "#c0392b", "#2c3e50", "#d35400"]


def draw_strings(ax, strings) -> None:
    """Strings (``StringRoute``) on a flat pattern: anchor, holes, solid above, dashed below."""
    for i, s in enumerate(strings):
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


def save_route_png(cp: CreasePattern, route: RouteSpec, path: str | os.PathLike[str]) -> Path:
    """The flat pattern with holes and every string: solid above the sheet, dashed below."""
    x0, y0, x1, y1 = cp.bounds
    with png_subplots(
        path, figsize=(9, 9 * float(np.clip((y1 - y0) / (x1 - x0), 0.3, 1.5))), dpi=150
    ) as (_, ax):
        plot_pattern(cp, ax, legend=False, title="")
        draw_strings(ax, route.strings)
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


def _sheet(ax, cp: CreasePattern, coords: np.ndarray, title: str) -> None:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    polys = [coords[face] for face in cp.faces]
    ax.add_collection3d(
        Poly3DCollection(polys, facecolor="#9ecae1", edgecolor="#08306b", lw=0.4, alpha=0.9)
    )
    lo, hi = coords.min(axis=0), coords.max(axis=0)
    mid, half = (lo + hi) / 2, float(np.max(hi - lo)) / 2
    ax.set(xlim=(mid[0] - half, mid[0] + half), ylim=(mid[1] - half, mid[1] + half))
    ax.set_zlim(mid[2] - half, mid[2] + half)
    ax.view_init(elev=28, azim=-60)
    ax.set_axis_off()
    ax.set_title(title, fontsize=9)


#: how a figure's title names each stop reason (StopReason values)
_STOP_PHRASES = {
    "turn_limit": "the TSA's turn limit",
    "helix_limit": "the strands' helix limit",
    "fold_limit": "the fold limit",
    "tension_limit": "the tension limit",
    "torque_limit": "the torque limit",
    "jam": "a jam",
}


def save_fig5_png(cp: CreasePattern, dcqc: DCQCResult, sim, path: str | os.PathLike[str]) -> Path:
    """The paper's Fig. 5 from both string models, for sizing the hardware.

    Top left: fold ratio p against TSA turns from the DCQC model and the
    bar-and-hinge simulation (``sim``, a
    :class:`~origami_cad.simulation.SimulationResult`), with the fold limit; top
    right: the simulation's string tensions (N) and TSA torque (N mm) against
    turns; bottom: the simulated sheet at four stages (as Fig. 5f-h).
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(12, 8))  # a Figure, not pyplot: no global state
    grid = fig.add_gridspec(2, 4, height_ratios=[1.1, 1.0])
    ax = fig.add_subplot(grid[0, :2])
    ax.plot(dcqc.turns, dcqc.p, lw=2.2, color="#1f4fd6", label="DCQC (rigid panels)")
    ax.plot(sim.turns, sim.p, "o-", ms=2.5, lw=1.2, color="#d62728", label="bar-and-hinge")
    ax.axhline(dcqc.limit.p, color="0.4", ls=":", lw=1, label="fold limit")
    ax.set_xlabel("TSA rotation (turns)")
    ax.set_ylabel("fold ratio p")
    ax.set_ylim(0, max(0.6, float(np.nanmax(sim.p)) + 0.05))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    a, b = _STOP_PHRASES.get(dcqc.stop.value, "?"), _STOP_PHRASES.get(sim.stop.value, "?")
    title = f"both models stop at {a}" if a == b else f"DCQC stops at {a}, the simulation at {b}"
    ax.set_title(title, fontsize=10)
    ax2 = fig.add_subplot(grid[0, 2:])
    for i in range(sim.tensions.shape[1]):
        ax2.plot(
            sim.turns,
            sim.tensions[:, i],
            lw=1.2,
            color=_COLORS[i % len(_COLORS)],
            label=f"string {i + 1} tension",
        )
    ax2.set_xlabel("TSA rotation (turns)")
    ax2.set_ylabel("tension (N)")
    ax2.grid(True, alpha=0.3)
    twin = ax2.twinx()
    twin.plot(sim.turns, sim.torque, "k--", lw=1.5, label="TSA torque")
    twin.set_ylabel("TSA torque (N mm)")
    lines = ax2.get_legend_handles_labels()
    more = twin.get_legend_handles_labels()
    ax2.legend(lines[0] + more[0], lines[1] + more[1], fontsize=7, loc="upper left")
    ax2.set_title("What the TSA and strings must carry (simulation)", fontsize=10)
    stages = np.unique(np.linspace(0, len(sim) - 1, 4).round().astype(int))
    for j, k in enumerate(stages):
        a3 = fig.add_subplot(grid[1, j], projection="3d")
        _sheet(a3, cp, sim.states[k], f"{sim.turns[k]:.1f} turns, p = {sim.p[k]:.2f}")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130, format="png")
    return Path(path)
