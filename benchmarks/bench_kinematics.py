"""Kinematics: TG chain throughput (eqs. 2-4) and the 3D fold of a 100 x 100 tessellation."""

from __future__ import annotations

import math
import time

import numpy as np

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
    t0 = time.perf_counter()
    for _ in range(reps):
        tip_positions(theta, lengths, beta, flags, True)
    dt = (time.perf_counter() - t0) / reps
    rate = designs * samples * vectors / dt
    out = [
        ("TG chain: vector evaluations per second (10 vectors, 46 samples)", rate, "target >= 2e6"),
        ("TG chain: design-samples per second", designs * samples / dt, ""),
    ]
    d = TGDesign((10.0,) * 100, (60.0,) * 99, 1, 20.0, 100)
    t0 = time.perf_counter()
    cp = tg_pattern(d)
    out.append(
        (
            f"100 x 100 unit tessellation pattern ({cp.n_vertices} vertices), s",
            time.perf_counter() - t0,
            "",
        )
    )
    fold_tessellation(d, cp, 0.3)
    t0 = time.perf_counter()
    fold_tessellation(d, cp, 0.5)
    out.append(
        (
            "3D fold of the 100 x 100 tessellation at one p, s",
            time.perf_counter() - t0,
            "target < 0.5 s",
        )
    )
    return out
