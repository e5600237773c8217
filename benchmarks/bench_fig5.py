"""Fig. 5: the 6 x 4 Miura's whole folding curve in both string models, and how they agree."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from origami_cad.pattern.design import load_design
from origami_cad.simulation import SimulationParams, simulate
from origami_cad.strings import load_route, simulate_dcqc

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def run() -> list[tuple[str, float, str]]:
    design = load_design(EXAMPLES / "miura_6x4.toml")
    route = load_route(EXAMPLES / "miura_route.toml", design.pattern)
    params = SimulationParams.from_fabrication(route.fabrication)
    t0, c0 = time.perf_counter(), time.process_time()
    dcqc = simulate_dcqc(design, route, **params.dcqc_stiffness())
    t1 = time.perf_counter()
    sim = simulate(design.pattern, route, params, design=design)
    t2, c2 = time.perf_counter(), time.process_time()
    gap = np.abs(sim.p - np.interp(sim.turns, dcqc.turns, dcqc.p))
    return [
        (f"DCQC, flat to p = {dcqc.p[-1]:.3f} ({len(dcqc)} states), s", t1 - t0, ""),
        (f"bar-and-hinge, to p = {sim.p[-1]:.3f} ({len(sim)} states), s", t2 - t1, ""),
        ("both models, whole curve, s", t2 - t0, "target < 5 s"),
        ("  CPU time of both (what a loaded machine does not inflate), s", c2 - c0, ""),
        ("largest gap in p(turns) between the models", float(gap.max()), "test < 0.02"),
        ("  its median", float(np.median(gap)), ""),
    ]
