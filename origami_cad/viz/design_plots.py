"""Plots of arm designs: trajectories among obstacles (Fig. 3b-c) and convergence (Fig. 3d)."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path

import matplotlib
import numpy as np
import shapely
from matplotlib.axes import Axes
from matplotlib.patches import PathPatch
from matplotlib.path import Path as MplPath

from origami_cad.design.search import ArmDesign
from origami_cad.design.task import ArmTask
from origami_cad.kinematics.chain import chain_points
from origami_cad.viz.figure import new_axes, png_subplots

__all__ = [
    "plot_arm_scene",
    "plot_trajectories",
    "save_arm_scene_png",
    "save_convergence_png",
    "save_trajectories_png",
]


def _polygon_patch(poly, **kwargs) -> PathPatch:
    verts, codes = [], []
    for ring in [poly.exterior, *poly.interiors]:
        c = shapely.get_coordinates(ring)
        verts += c.tolist()
        codes += [MplPath.MOVETO] + [MplPath.LINETO] * (len(c) - 2) + [MplPath.CLOSEPOLY]
    return PathPatch(MplPath(verts, codes), **kwargs)


def _draw_areas(ax: Axes, task: ArmTask, view) -> None:
    """The warning and prohibited areas of the task, clipped to the view."""
    for poly in task.warning:
        ax.add_patch(
            _polygon_patch(
                poly.intersection(view), fc="#ffe08a", ec="#d4a017", alpha=0.6, label="warning area"
            )
        )
    for poly in task.prohibited:
        ax.add_patch(
            _polygon_patch(
                poly.intersection(view),
                fc="#f4a6a6",
                ec="#c0392b",
                alpha=0.7,
                hatch="//",
                label="prohibited area",
            )
        )


def _draw_points_and_frame(ax, task: ArmTask, view) -> None:
    """The task's points (stars, P_start .. P_end) and the view's frame in mm, equal axes."""
    names = ["$P_{start}$"] + [f"$P_{{{j}}}$" for j in range(1, len(task.points) - 1)]
    for (x, y), name in zip(task.points, [*names, "$P_{end}$"], strict=True):
        ax.plot(x, y, "*", color="#111111", ms=14)
        ax.annotate(name, (x, y), textcoords="offset points", xytext=(6, 6))
    ax.set_xlim(view.bounds[0], view.bounds[2])
    ax.set_ylim(view.bounds[1], view.bounds[3])
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")


def plot_trajectories(
    results: Sequence[ArmDesign],
    task: ArmTask,
    ax: Axes | None = None,
    top: int = 3,
    ratios: Sequence[float] = (0.0, 0.25, 0.5, 0.75, 1.0),
) -> Axes:
    """Obstacles, target points, the chains of the best designs at several p and their T_e paths."""
    if ax is None:
        ax = new_axes((8, 7))
    pts = np.vstack([task.points, [task.start]])
    for r in results[:top]:
        pts = np.vstack([pts, r.tips])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.15 * max(hi - lo)
    view = shapely.box(lo[0] - pad, lo[1] - pad, hi[0] + pad, hi[1] + pad)
    _draw_areas(ax, task, view)
    colors = matplotlib.colormaps.get_cmap("tab10")
    for rank, r in enumerate(results[:top]):
        color = colors(rank)
        ax.plot(
            r.tips[:, 0],
            r.tips[:, 1],
            "--",
            color=color,
            lw=1.5,
            label=f"#{rank + 1} (run {r.run}) f = {r.fitness:.2f}: T_e path",
        )
        chains = chain_points(  # over the fold range the design reaches
            np.asarray(ratios) * math.pi * getattr(r, "fold_ratio_end", 1.0),
            r.lengths,
            np.radians(r.shape_angles),
            r.entry_flag,
            task.hypar_base,
            task.start,
        )[0]
        for k, c in enumerate(chains):
            ax.plot(
                c[:, 0],
                c[:, 1],
                "-",
                color=color,
                lw=2.2 if rank == 0 else 1.0,
                alpha=0.35 + 0.65 * k / max(len(chains) - 1, 1),
                marker="." if rank == 0 else None,
            )
    ax.plot(*task.start, "ks", ms=8, label="$T_s$")
    _draw_points_and_frame(ax, task, view)
    handles, labels = ax.get_legend_handles_labels()
    uniq = dict(zip(labels, handles, strict=True))
    ax.legend(
        uniq.values(),
        uniq.keys(),
        fontsize=8,
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
        frameon=False,
    )
    ax.grid(True, alpha=0.3)
    ax.set_title("Top designs: chains at p = 0 .. 1 and the path of $T_e$")
    return ax


def save_trajectories_png(
    results: Sequence[ArmDesign], task: ArmTask, path: str | os.PathLike[str], top: int = 3
) -> Path:
    """Save :func:`plot_trajectories` (atomic write)."""
    with png_subplots(path, figsize=(11, 7), dpi=140) as (_, ax):
        plot_trajectories(results, task, ax, top=top)
    return Path(path)


def save_convergence_png(results: Sequence[ArmDesign], path: str | os.PathLike[str]) -> Path:
    """Best fitness per generation, one line per run (Fig. 3d), atomic write."""
    with png_subplots(path, figsize=(8, 5), dpi=140) as (_, ax):
        for r in sorted(results, key=lambda r: r.run):
            h = np.array(r.history, dtype=float)
            h[~np.isfinite(h)] = np.nan
            ax.plot(np.arange(1, len(h) + 1), h, lw=1.3, label=f"run {r.run}")
        ax.set_xlabel("generation")
        ax.set_ylabel("best fitness f (eq. 5)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, ncol=2)
        ax.set_title("CMA-ES convergence, independent runs")
    return Path(path)


def plot_arm_scene(
    task: ArmTask,
    designed: np.ndarray,
    simulated: np.ndarray,
    ax: Axes | None = None,
    title: str = "",
) -> Axes:
    """The arm in its working scene (the paper's Fig. 8): designed and simulated tip paths.

    Parameters
    ----------
    task : ArmTask
        Start, target points and areas.
    designed : ndarray, shape (S, n + 2, 2)
        Chains of the design (rigid kinematics) over its fold range, mm.
    simulated : ndarray, shape (S', n + 2, 2)
        Chains of the printed arm folded by its strings (e.g. a bar-and-hinge
        simulation placed by :func:`~origami_cad.design.arm_route.arm_chain_path`), mm.
    """
    if ax is None:
        ax = new_axes((9, 7))
    pts = np.vstack([task.points, [task.start], designed.reshape(-1, 2), simulated.reshape(-1, 2)])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.12 * max(hi - lo)
    view = shapely.box(lo[0] - pad, lo[1] - pad, hi[0] + pad, hi[1] + pad)
    _draw_areas(ax, task, view)
    for k in np.linspace(0, len(simulated) - 1, 5).round().astype(int):
        ax.plot(
            *simulated[k].T, "-", color="#1f77b4", lw=1.0, alpha=0.25 + 0.6 * k / len(simulated)
        )
    ax.plot(*simulated[-1].T, "o-", color="#1f77b4", lw=2.0, ms=3, label="printed arm, final state")
    ax.plot(*designed[:, -1].T, "--", color="#111111", lw=2.0, label="designed tip path (rigid)")
    ax.plot(*simulated[:, -1].T, "-", color="#d62728", lw=1.6, label="simulated tip path (strings)")
    ax.plot(*task.start, "ks", ms=8, label="$T_s$")
    _draw_points_and_frame(ax, task, view)
    handles, labels = ax.get_legend_handles_labels()
    uniq = dict(zip(labels, handles, strict=True))
    ax.legend(uniq.values(), uniq.keys(), fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    if title:
        ax.set_title(title, fontsize=10)
    return ax


def save_arm_scene_png(
    task: ArmTask,
    designed: np.ndarray,
    simulated: np.ndarray,
    path: str | os.PathLike[str],
    title: str = "",
) -> Path:
    """Save :func:`plot_arm_scene` (atomic write)."""
    with png_subplots(path, figsize=(11, 7), dpi=140) as (_, ax):
        plot_arm_scene(task, designed, simulated, ax, title)
    return Path(path)
