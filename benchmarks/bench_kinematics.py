"""Kinematics: TG chain throughput (eqs. 2-4) and the 3D fold of a 100 x 100 tessellation."""

from __future__ import annotations

import math

import numpy as np
from clock import Clock, cpu_row

from origami_cad.kinematics import fold_tessellation, tip_positions
from origami_cad.pattern.tg import TGDesign, tg_pattern


def run() -> list[tuple[str, float, str]]:
    rng = np.random.default_rng(1)
    designs, vectors, samples = 2000, 10, 46
    lengths = rng.uniform(10, 120, (designs, vectors))
    beta = np.radians(rng.uniform(10, 170, (designs, vectors - 1)))
    flags = rng.integers(0, 2, designs)
    theta = np.linspace(0, math.pi, samples)
    tip_positions(theta, lengths[:10], beta[:10], flags[:10], True)  # warm up
    reps = 5
    clock = Clock()
    for _ in range(reps):
        tip_positions(theta, lengths, beta, flags, True)
    dt, cpu = (v / reps for v in clock.lap())
    rate = designs * samples * vectors
    out = [
        ("TG chain: vector evaluations per second (10 vectors, 46 samples)", rate / dt, "(wall)"),
        ("  by this process's CPU time", rate / cpu, "target >= 2e6"),
        ("TG chain: design-samples per second (wall)", designs * samples / dt, ""),
        ("  by this process's CPU time", designs * samples / cpu, ""),
    ]
    d = TGDesign((10.0,) * 100, (60.0,) * 99, 1, 20.0, 100)
    clock = Clock()
    cp = tg_pattern(d)
    wall, cpu = clock.lap()
    out.append(
        (f"100 x 100 unit tessellation pattern ({cp.n_vertices} vertices), wall s", wall, "")
    )
    out.append(cpu_row(cpu))
    fold_tessellation(d, cp, 0.3)
    clock.lap()
    fold_tessellation(d, cp, 0.5)
    wall, cpu = clock.lap()
    out.append(("3D fold of the 100 x 100 tessellation at one p, wall s", wall, "target < 0.5 s"))
    out.append(cpu_row(cpu, "target < 0.5 s"))
    return out
