"""Folding any pattern: `check` and `fold` of the 2,704-vertex box-pleat pyramid.

Origami Simulator's ``BoxPleatPyramid.fold`` (tests/data, MIT), read at 150 mm wide and folded
to p = 0.3 as ``origami-cad fold --ratio 0.3`` folds it (the closed form does not apply:
several degrees of freedom), once to compile the kernels, then timed: wall clock and this
process's CPU time. ``check`` is timed as the command runs it: read (normalise, faces) and
check the pattern.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from origami_cad.pattern import read_pattern
from origami_cad.simulation.factor import pardiso_available
from origami_cad.simulation.folder import fold

PATTERN = Path(__file__).resolve().parents[1] / "tests/data/origami-simulator/BoxPleatPyramid.fold"


def run() -> list[tuple[str, float, str]]:
    t0, c0 = time.perf_counter(), time.process_time()
    cp = read_pattern(PATTERN, width=150.0)
    problems = cp.check()
    check_wall, check_cpu = time.perf_counter() - t0, time.process_time() - c0
    assert not [p for p in problems if p.severity == "error"]
    small = read_pattern(PATTERN.parent / "birdBase.svg", width=150.0)
    fold(small, 0.3)  # compile the solver's kernels
    t0, c0 = time.perf_counter(), time.process_time()
    state = fold(cp, 0.3)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    creases = cp.edge_mask("M", "V")
    turned = float(np.mean(np.abs(state.fold_angles[creases]) > 5.0))
    return [
        (f"check of the {cp.n_vertices}-vertex box pleat (read + check), s", check_wall, "< 2 s"),
        ("  CPU s (process_time)", check_cpu, ""),
        (
            f"fold of the {cp.n_vertices}-vertex box pleat at p = 0.3 ({state.method}), s",
            wall,
            "target < 5 s (wall: shared machine)",
        ),
        ("  CPU s (process_time)", cpu, "goal < 5 s CPU"),
        (
            "  MKL's PARDISO installed (1: it factorises this pattern)",
            float(pardiso_available()),
            "",
        ),
        ("  creases turned by more than 5 deg, fraction", turned, "target >= 0.5"),
        ("  largest edge strain, %", state.strain, "target <= 5"),
    ]
