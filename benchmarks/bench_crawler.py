"""Crawler: one simulated gait cycle of examples/crawler, free on the ground."""

from __future__ import annotations

import time
from pathlib import Path

from origami_cad.crawler.robot import load_robot
from origami_cad.crawler.walk import simulate_gait

ROBOT = Path(__file__).resolve().parents[1] / "examples" / "crawler" / "crawler.toml"


def run() -> list[tuple[str, float, str]]:
    robot = load_robot(ROBOT)
    out = []
    for steps in (3, 6):
        t0, c0 = time.perf_counter(), time.process_time()
        result = simulate_gait(robot, cycles=1, steps=steps)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        states = len(result.t)
        out.append((f"one gait cycle, {states} states: wall s", wall, "target < 60 s"))
        out.append(("  CPU s (process_time)", cpu, ""))
        out.append(
            ("  mm forward in the cycle (paper: 63)", result.displacement_per_cycle()[0], "")
        )
    return out
