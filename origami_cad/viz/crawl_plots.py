"""Plots of a simulated gait: the body's path against time, TSA torques and string tensions."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from origami_cad._names import plot_text
from origami_cad.viz.figure import png_subplots

__all__ = [
    "save_crawl_gait_png",
    "save_crawl_loads_png",
    "save_crawl_position_png",
    "save_gait_convergence_png",
    "save_gait_keyframes_png",
    "save_gait_vs_hand_png",
]


def _label(top, bottom, top_label: str, bottom_label: str, legend: dict) -> None:
    """Y labels of two stacked panels over time (s), the top one's legend, light grids."""
    top.set_ylabel(top_label)
    bottom.set_ylabel(bottom_label)
    bottom.set_xlabel("time (s)")
    top.legend(fontsize=8, **legend)
    top.grid(alpha=0.3)
    bottom.grid(alpha=0.3)


def save_crawl_position_png(
    t: np.ndarray,
    body: np.ndarray,
    cycle_starts: Sequence[int],
    path: str | os.PathLike[str],
    *,
    reference: float | None = None,
    cycle: float | None = None,
) -> Path:
    """The body's x (heading), y (drift) and z (height) against time, mm vs s.

    ``reference`` (mm per cycle, e.g. the paper's 63) draws the line a robot moving
    that much per ``cycle`` seconds would follow.
    """
    with png_subplots(path, 2, 1, figsize=(7.0, 5.5), sharex=True) as (_, (ax, az)):
        x0 = body[0]
        ax.plot(t, body[:, 0] - x0[0], label="x (forward)", color="C0")
        ax.plot(t, body[:, 1] - x0[1], label="y (drift)", color="C2", lw=1)
        if reference is not None and cycle:
            ax.plot(t, reference * t / cycle, "k--", lw=0.8, label=f"{reference:g} mm per cycle")
        for k in cycle_starts[1:-1]:
            ax.axvline(t[k], color="0.8", lw=0.8)
            az.axvline(t[k], color="0.8", lw=0.8)
        az.plot(t, body[:, 2], color="C1")
        _label(ax, az, "body displacement (mm)", "body height (mm)", {"loc": "upper left"})
    return Path(path)


def save_crawl_loads_png(
    t: np.ndarray,
    torque: np.ndarray,
    tensions: np.ndarray,
    names: Sequence[str],
    path: str | os.PathLike[str],
) -> Path:
    """Each TSA's torque (N mm) and its largest string tension (N) against time (s)."""
    with png_subplots(path, 2, 1, figsize=(7.0, 5.5), sharex=True) as (_, (at, af)):
        for k, name in enumerate(names):
            at.plot(t, torque[:, k], label=plot_text(name))
            af.plot(t, tensions[:, k, :].max(axis=1), label=plot_text(name))
        _label(at, af, "TSA torque (N mm)", "largest string tension (N)", {"ncol": 2})
    return Path(path)


def save_crawl_gait_png(
    t: np.ndarray,
    fold: np.ndarray,
    turns: np.ndarray,
    names: Sequence[str],
    path: str | os.PathLike[str],
    *,
    commanded: np.ndarray | None = None,
) -> Path:
    """The gait: each leg's fold angle (deg) and its TSA's twist (turns) against time (s).

    ``fold`` (N, legs) is the simulated leg crease's fold angle; ``commanded`` (N, legs),
    if given, the gait's fold ratios at the same times, drawn dashed as angles (p x 180).
    """
    with png_subplots(path, 2, 1, figsize=(7.0, 5.5), sharex=True) as (_, (af, at)):
        for k, name in enumerate(names):
            (line,) = af.plot(t, fold[:, k], label=plot_text(name))
            if commanded is not None:
                af.plot(t, 180.0 * commanded[:, k], "--", color=line.get_color(), lw=0.8)
            at.plot(t, turns[:, k], label=plot_text(name))
        af.set_title("solid: simulated, dashed: the gait's keyframes", fontsize=8, loc="left")
        _label(af, at, "leg fold angle (deg)", "TSA twist (turns)", {"ncol": 2})
    return Path(path)


def save_gait_convergence_png(
    generations: np.ndarray,
    scores: np.ndarray,
    history: Sequence[Sequence[float]],
    path: str | os.PathLike[str],
    *,
    hand: float | None = None,
) -> Path:
    """A gait search's convergence: every candidate's score (mm) by generation, the best
    so far per run, and the hand gait's score."""
    with png_subplots(path, 1, 1, figsize=(7.0, 4.0)) as (_, ax):
        shown = np.maximum(scores, -300.0)
        ax.plot(generations, shown, ".", color="0.6", ms=4, label="candidates (below -300: -300)")
        for run, best in enumerate(history):
            ax.plot(np.arange(1, len(best) + 1), best, "-o", ms=3, label=f"best, run {run}")
        if hand is not None:
            ax.axhline(hand, color="C3", ls="--", lw=0.8, label="the hand gait")
        ax.set_xlabel("generation")
        ax.set_ylabel("score (mm per cycle, penalised)")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    return Path(path)


def save_gait_keyframes_png(
    best: tuple[np.ndarray, np.ndarray],
    hand: tuple[np.ndarray, np.ndarray],
    legs: Sequence[str],
    path: str | os.PathLike[str],
) -> Path:
    """Each leg's commanded fold angle (deg) over one cycle (s): the designed gait
    (``best``: times, fold ratios) against the hand gait (``hand``)."""
    n = len(legs)
    with png_subplots(path, n, 1, figsize=(7.0, 1.6 * n + 1), sharex=True) as (_, axes):
        for k, ax in enumerate(np.atleast_1d(axes)):
            ax.plot(best[0], 180.0 * best[1][:, k], "-o", ms=3, color="C0", label="designed")
            ax.plot(hand[0], 180.0 * hand[1][:, k], "--", color="C3", lw=1, label="hand")
            ax.set_ylabel(plot_text(legs[k]) + " (deg)", fontsize=8)
            ax.grid(alpha=0.3)
        np.atleast_1d(axes)[0].legend(fontsize=8, ncol=2)
        np.atleast_1d(axes)[-1].set_xlabel("time in the cycle (s)")
    return Path(path)


def save_gait_vs_hand_png(
    frictions: Sequence[float],
    designed: Sequence[float],
    hand: Sequence[float],
    path: str | os.PathLike[str],
    *,
    reference: float = 63.0,
    drift: Sequence[float] | None = None,
) -> Path:
    """Forward displacement per cycle (mm) against friction: the designed gait, the hand
    gait and the paper's ``reference``; with ``drift``, the designed gait's drift (mm)."""
    with png_subplots(path, 1, 1, figsize=(6.5, 4.0)) as (_, ax):
        ax.plot(frictions, designed, "-o", color="C0", label="designed gait")
        ax.plot(frictions, hand, "-s", color="C3", label="hand gait")
        ax.axhline(reference, color="k", ls="--", lw=0.8, label=f"paper: {reference:g} mm")
        if drift is not None:
            ax.plot(frictions, np.abs(drift), ":^", color="C2", label="designed: |drift|")
        ax.set_xlabel("friction coefficient")
        ax.set_ylabel("mm per 32 s cycle")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    return Path(path)
