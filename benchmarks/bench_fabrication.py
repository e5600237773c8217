"""Fabrication: all four parts and every export for the 6 x 4 Miura (with holes) and a 20 x 20."""

from __future__ import annotations

import tempfile
import time

from origami_cad.fabrication import fabricate, write_fabrication
from origami_cad.pattern.design import miura_design


def _one(rows: int, columns: int, length: float, width: float) -> tuple[float, dict, int]:
    design = miura_design(rows, columns, length, width, 70.0)
    t0 = time.perf_counter()
    fab = fabricate(design)
    with tempfile.TemporaryDirectory() as tmp:
        write_fabrication(fab, tmp)
    return time.perf_counter() - t0, fab.timings, len(fab.outlines)


def run() -> list[tuple[str, float, str]]:
    out = []
    for rows, cols, length, width, target in (
        (4, 6, 20.0, 30.0, "target < 10 s"),
        (20, 20, 15.0, 15.0, "target < 60 s"),
    ):
        total, timings, panels = _one(rows, cols, length, width)
        out.append(
            (
                f"{rows} x {cols} Miura ({panels} panels, holes): build + all exports, s",
                total,
                target,
            )
        )
        for stage, seconds in timings.items():
            out.append((f"  {stage}, s", seconds, ""))
    return out
