"""Plots of a driven sequence: commanded and measured turns of every TSA over time."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from origami_cad._names import plot_text
from origami_cad.viz.figure import png_subplots

__all__ = ["save_drive_png"]


def save_drive_png(
    log: Any,
    path: str | os.PathLike[str],
    names: dict[int, str] | None = None,
) -> Path:
    """One panel per TSA: commanded (dashed) and measured (solid) motor turns, and current.

    ``log`` is a columnar drive log (:class:`origami_cad.drive.sequence.DriveLog`:
    ``ids``, ``t`` (S,) s, ``target`` and ``measured`` (S, n) turns, ``current`` (S, n) mA).
    """
    ids = list(log.ids)
    with png_subplots(
        path, len(ids), 1, figsize=(9, 1.9 * len(ids) + 0.8), sharex=True, squeeze=False, dpi=140
    ) as (_, axes):
        for j, (ax, i) in enumerate(zip(axes[:, 0], ids, strict=True)):
            ax.plot(log.t, log.target[:, j], "--", color="#555555", label="commanded")
            ax.plot(log.t, log.measured[:, j], "-", color="#1f4fd6", label="measured")
            ax.set_ylabel("turns")
            label = plot_text((names or {}).get(i, ""))
            ax.set_title(f"servo {i} {label}".strip(), fontsize=9, loc="left")
            ax.grid(True, alpha=0.3)
            twin = ax.twinx()
            twin.plot(log.t, log.current[:, j], ":", color="#d62728", lw=1)
            twin.set_ylabel("mA", color="#d62728", fontsize=8)
        axes[0, 0].legend(fontsize=8, loc="upper right")
        axes[-1, 0].set_xlabel("time (s)")
    return Path(path)
