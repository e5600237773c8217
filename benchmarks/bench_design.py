"""Arm design: eq. 5 fitness throughput and the paper's ten-run design task."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from origami_cad.design import arm_fitness, decode, design_arm, load_task
from origami_cad.design.task import ArmTask

TASK = Path(__file__).resolve().parents[1] / "examples" / "arm_task.toml"


def run() -> list[tuple[str, float, str]]:
    paper, settings = load_task(TASK)
    task = ArmTask(
        start=paper.start,
        points=paper.points,
        vectors=10,
        warning=paper.warning,
        prohibited=paper.prohibited,
    )
    x = np.random.default_rng(0).uniform(size=(1000, task.dimension))
    lengths, beta = decode(task, x)
    flags = np.ones(1000, dtype=int)
    arm_fitness(task, lengths[:10], beta[:10], flags[:10])
    best = np.inf
    for _ in range(5):
        t0 = time.perf_counter()
        arm_fitness(task, lengths, beta, flags)
        best = min(best, time.perf_counter() - t0)
    out = [
        (
            "fitness: designs per second (1,000 designs, 10 vectors, 46 samples)",
            1000 / best,
            "target >= 20,000",
        ),
        ("fitness: microseconds per design", best * 1e6 / 1000, "target <= 50"),
    ]
    t0 = time.perf_counter()
    results = design_arm(paper, settings)
    wall = time.perf_counter() - t0
    out.append(
        (
            "paper task (Fig. 3a): 10 runs x 400 generations, wall s",
            wall,
            "target < 10 s on 2 cores",
        )
    )
    out.append(("  best fitness (max 60)", results[0].fitness, ""))
    out.append(("  best |T_e(0) - P_start|, mm", results[0].terms.d_start, "<= 2"))
    out.append(("  best |T_e(pi) - P_end|, mm", results[0].terms.d_end, "<= 5"))
    return out
