"""Fig. 5: the 6 x 4 Miura's whole folding curve in both string models, and how they agree."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from clock import Clock, cpu_row

from origami_cad.pattern.design import load_design
from origami_cad.simulation import SimulationParams, simulate
from origami_cad.strings import load_route, simulate_dcqc

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def run() -> list[tuple[str, float, str]]:
    design = load_design(EXAMPLES / "miura_6x4.toml")
    route = load_route(EXAMPLES / "miura_route.toml", design.pattern)
    params = SimulationParams.from_fabrication(route.fabrication)
    clock = Clock()
    dcqc = simulate_dcqc(design, route, **params.dcqc_stiffness())
    first = clock.lap()
    sim = simulate(design.pattern, route, params, design=design)
    second = clock.lap()
    gap = np.abs(sim.p - np.interp(sim.turns, dcqc.turns, dcqc.p))
    return [
        (f"DCQC, flat to p = {dcqc.p[-1]:.3f} ({len(dcqc)} states), wall s", first[0], ""),
        cpu_row(first[1]),
        (f"bar-and-hinge, to p = {sim.p[-1]:.3f} ({len(sim)} states), wall s", second[0], ""),
        cpu_row(second[1]),
        ("both models, whole curve, wall s", first[0] + second[0], "target < 5 s"),
        cpu_row(first[1] + second[1], "target < 5 s"),
        ("largest gap in p(turns) between the models", float(gap.max()), "test < 0.02"),
        ("  its median", float(np.median(gap)), ""),
    ]
