"""Fabrication: the Miura with holes built and every export fabricate writes, against its size.

Each sheet is built (``fabricate``) and written as ``origami-cad fabricate`` writes it:
the four STLs, ``assembly.step``, ``print.3mf``, the FOLD and JSON
(``write_fabrication``), ``parts.glb`` and ``panels.png``. Times are wall-clock and
CPU (``time.process_time``: this process and its threads; on a shared machine the CPU
time is the steadier figure). The cost against the panel count is fitted as
``t = c * panels ** k`` over 5 x 5 ... 32 x 32 (CPU times; the 32 x 32, 1,024 panels, is the
issue's 1,000-panel sheet). Each stage (the build, each writer) is timed by wall and CPU.

Peak memory is a fresh process's peak RSS (``VmHWM``, else ``resource``): the
30 x 30 sheet built and exported alone in a child (``python bench_fabrication.py 30``), so
the figure is that sheet's with the imports (build123d/OCP alone take about 430 MB),
not the whole benchmark's; it counts OCC's C++ allocations, which
``tracemalloc`` does not see. Benchmarks, never tests.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from clock import Clock

from origami_cad.fabrication import fabricate, write_fabrication
from origami_cad.fabrication.exports import WRITERS
from origami_cad.pattern.design import miura_design
from origami_cad.viz.fabrication_plots import save_panels_png
from origami_cad.viz.gltf import write_parts_glb

#: (rows, columns, panel length mm, panel width mm) of the sheets measured
SHEETS = ((4, 6, 20.0, 30.0), (5, 5, 15.0, 15.0), (10, 10, 15.0, 15.0), (20, 20, 15.0, 15.0))
#: the largest sheet, measured for its peak memory too
LARGEST = (32, 32, 15.0, 15.0)
#: the sheet of the memory goal (< 1 GB peak, < 10 s wall, every export)
MEMORY_SHEET = (30, 30, 15.0, 15.0)


class _Timed:
    """A writer of :data:`WRITERS` that records its (wall s, CPU s) in ``stages``."""

    def __init__(self, name: str, write, stages: dict) -> None:
        self.name, self.write, self.stages = name, write, stages

    def __call__(self, fab, out):
        clock = Clock()
        paths = self.write(fab, out)
        self.stages[self.name] = clock.lap()
        return paths


def _one(rows: int, columns: int, length: float, width: float) -> tuple[float, float, dict, int]:
    """Wall and CPU seconds of the build and every export; each stage's (wall, CPU); panels."""
    design = miura_design(rows, columns, length, width, 70.0)
    stages: dict[str, tuple[float, float]] = {}
    wall, cpu = time.perf_counter(), time.process_time()
    clock = Clock()
    fab = fabricate(design, bed=(1000.0, 1000.0))
    stages["build (panels, holes, solids)"] = clock.lap()
    original = dict(WRITERS)
    WRITERS.update({name: _Timed(name, write, stages) for name, write in original.items()})
    try:
        with tempfile.TemporaryDirectory() as tmp:
            clock.lap()
            write_fabrication(fab, tmp)
            files = clock.lap()
            stages["fold and json"] = tuple(
                a - sum(s[k] for n, s in stages.items() if n in original)
                for k, a in enumerate(files)
            )
            write_parts_glb(fab, Path(tmp) / "parts.glb")
            stages["glb"] = clock.lap()
            save_panels_png(fab, Path(tmp) / "panels.png")
            stages["panels png"] = clock.lap()
    finally:
        WRITERS.clear()
        WRITERS.update(original)
    cpu = time.process_time() - cpu
    return time.perf_counter() - wall, cpu, stages, len(fab.outlines)


def _stage_rows(stages: dict, target: str = "") -> list[tuple[str, float, str]]:
    """Each stage's wall and CPU seconds, the slowest marked with ``target``."""
    slowest = max(stages, key=lambda name: stages[name][1])
    out = []
    for name, (wall, cpu) in stages.items():
        mark = target if name == slowest else ""
        out += [(f"  {name}, wall s", wall, mark), ("    CPU s", cpu, mark)]
    return out


def _in_child(sheet: tuple) -> dict:
    """Build and export ``sheet`` in a fresh process: its times, stages and peak RSS, MB."""
    done = subprocess.run(
        [sys.executable, str(Path(__file__).resolve()), *map(str, sheet)],
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def _peak_mb() -> float:
    """This process's peak RSS, MB: ``VmHWM``, which a fresh program starts afresh (a
    child's ``ru_maxrss`` keeps the peak of the parent it was forked from)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux


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
        out += _stage_rows(timings, "goal < 1 s (largest stage)" if count == 400 else "")
        if count != 24:
            panels.append(count)
            cpus.append(cpu)
    total, cpu, _, count = _one(*LARGEST)
    panels.append(count)
    cpus.append(cpu)
    out += [
        (f"{LARGEST[0]} x {LARGEST[1]} Miura ({count} panels): all, wall s", total, "< 15 s"),
        ("  CPU s", cpu, "< 15 s"),
        ("cost ~ panels ** k, k (CPU, 25 ... 1,024 panels)", _exponent(panels, cpus), "<= 1.1"),
    ]
    child = _in_child(MEMORY_SHEET)
    rows, cols = MEMORY_SHEET[:2]
    out += [
        (f"{rows} x {cols} Miura alone in a fresh process: all, wall s", child["wall"], "< 10 s"),
        ("  CPU s", child["cpu"], ""),
        ("  peak RSS of that process (imports included), MB", child["rss_mb"], "goal < 1024"),
        ("  peak RSS after the imports alone (build123d, OCP), MB", child["import_mb"], ""),
    ]
    return out


if __name__ == "__main__":  # one sheet in this process, for the parent's peak memory
    import build123d  # noqa: F401  (what fabricate imports on first use, measured apart)

    import_mb = _peak_mb()
    wall, cpu, stages, count = _one(*(int(a) for a in sys.argv[1:3]), *map(float, sys.argv[3:5]))
    peak = {"rss_mb": _peak_mb(), "import_mb": import_mb}
    print(json.dumps({"wall": wall, "cpu": cpu, "panels": count, **peak}))
