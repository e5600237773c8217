"""Gait design (issue 31): one gait evaluation, and one whole design-gait search."""

from __future__ import annotations

import time
from pathlib import Path

from origami_cad.crawler.gait import (
    GaitLimits,
    GaitSettings,
    design_gait,
    encode_gait,
    evaluate_gait,
)
from origami_cad.crawler.robot import load_robot

ROBOT = Path(__file__).resolve().parents[1] / "examples" / "crawler" / "crawler.toml"


def run() -> list[tuple[str, float, str]]:
    robot = load_robot(ROBOT)
    settings = GaitSettings(limits=GaitLimits.of(robot))
    t0 = time.perf_counter()
    terms = evaluate_gait(robot, encode_gait(robot), 0.6, settings)
    out = [
        ("one gait evaluation (hand gait's genome, friction 0.6): wall s", time.perf_counter() - t0,
         "one simulated cycle, steps 3"),
        ("  mm forward per cycle (paper: 63)", terms.forward, ""),
    ]  # fmt: skip
    t0 = time.perf_counter()
    design = design_gait(robot, settings)
    wall = time.perf_counter() - t0
    n = len(design.candidates)
    out.append((f"whole search ({n} candidates x 3 frictions): wall s", wall, "target < 600 s"))
    for t in design.best.terms:
        out.append((f"  best gait at friction {t.friction:g}: mm per cycle", t.forward,
                    "target >= 63 at 0.6, >= 45 at 0.4 and 0.8"))  # fmt: skip
        out.append((f"  best gait at friction {t.friction:g}: drift mm per cycle", t.drift,
                    "target < 3"))  # fmt: skip
    return out
