"""Fabrication: the Miura with holes built and every export fabricate writes, against its size.

Each sheet is built (``fabricate``) and written as ``origami-cad fabricate`` writes it:
the four STLs, ``assembly.step``, ``print.3mf``, the FOLD and JSON
(``write_fabrication``), ``parts.glb`` and ``panels.png``. Times are wall-clock and
CPU (``time.process_time``: this process and its threads; on a shared machine the CPU
time is the steadier figure). The cost against the panel count is fitted as
``t = c * panels ** k`` over 5 x 5 ... 32 x 32 (CPU times; the 32 x 32, 1,024 panels, is the
issue's 1,000-panel sheet). Peak memory is the process's
peak RSS (``resource``), reached on the 32 x 32, the last and largest: it counts OCC's
C++ allocations, which ``tracemalloc`` does not see (and tracing would slow the run
being timed). Benchmarks, never tests.
"""

from __future__ import annotations

import os
import resource
import tempfile
import time
from pathlib import Path

import numpy as np

from origami_cad.fabrication import fabricate, write_fabrication
from origami_cad.pattern.design import miura_design
from origami_cad.viz.fabrication_plots import save_panels_png
from origami_cad.viz.gltf import write_parts_glb

#: (rows, columns, panel length mm, panel width mm) of the sheets measured
SHEETS = ((4, 6, 20.0, 30.0), (5, 5, 15.0, 15.0), (10, 10, 15.0, 15.0), (20, 20, 15.0, 15.0))
#: the largest sheet, measured for its peak memory too
LARGEST = (32, 32, 15.0, 15.0)


def _one(rows: int, columns: int, length: float, width: float) -> tuple[float, float, dict, int]:
    """Wall and CPU seconds of the build and every export; the stages; the panels."""
    design = miura_design(rows, columns, length, width, 70.0)
    wall, cpu = time.perf_counter(), time.process_time()
    fab = fabricate(design, bed=(1000.0, 1000.0))
    with tempfile.TemporaryDirectory() as tmp:
        write_fabrication(fab, tmp)
        for stage, write in (
            ("glb", lambda: write_parts_glb(fab, Path(tmp) / "parts.glb")),
            ("panels png", lambda: save_panels_png(fab, Path(tmp) / "panels.png")),
        ):
            t0 = time.perf_counter()
            write()
            fab.timings[stage] = time.perf_counter() - t0
    cpu = time.process_time() - cpu
    return time.perf_counter() - wall, cpu, fab.timings, len(fab.outlines)


def _exponent(panels: list[int], seconds: list[float]) -> float:
    """``k`` of the least-squares fit ``log t = log c + k log panels``."""
    return float(np.polyfit(np.log(panels), np.log(seconds), 1)[0])


def run() -> list[tuple[str, float, str]]:
    out = [("load average (1 min) at the start", os.getloadavg()[0], "2 cores")]
    panels, cpus = [], []
    for rows, cols, length, width in SHEETS:
        total, cpu, timings, count = _one(rows, cols, length, width)
        target = {24: "target < 1 s", 400: "target < 10 s"}.get(count, "")
        out.append((f"{rows} x {cols} Miura ({count} panels, holes): all, wall s", total, target))
        out.append(("  CPU s", cpu, target))
        out += [(f"  {stage}, wall s", seconds, "") for stage, seconds in timings.items()]
        if count != 24:
            panels.append(count)
            cpus.append(cpu)
    total, cpu, _, count = _one(*LARGEST)
    panels.append(count)
    cpus.append(cpu)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux
    out += [
        (f"{LARGEST[0]} x {LARGEST[1]} Miura ({count} panels): all, wall s", total, "< 15 s"),
        ("  CPU s", cpu, "< 15 s"),
        ("  peak RSS of the process (resource), MB", rss, "target < 2048"),
        ("cost ~ panels ** k, k (CPU, 25 ... 1,024 panels)", _exponent(panels, cpus), "<= 1.1"),
    ]
    return out
