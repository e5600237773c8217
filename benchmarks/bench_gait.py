"""Gait design: one gait evaluation, and one whole design-gait search."""

from __future__ import annotations

from pathlib import Path

from clock import Clock, cpu_row

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
    clock = Clock()
    terms = evaluate_gait(robot, encode_gait(robot), 0.6, settings)
    wall, cpu = clock.lap()
    out = [
        ("one gait evaluation (hand gait's genome, friction 0.6): wall s", wall,
         "one simulated cycle, steps 3"),
        cpu_row(cpu),
        ("  mm forward per cycle (paper: 63)", terms.forward, ""),
    ]  # fmt: skip
    clock.lap()
    design = design_gait(robot, settings)
    wall, cpu = clock.lap()
    n = len(design.candidates)
    out.append((f"whole search ({n} candidates x 3 frictions): wall s", wall, "target < 600 s"))
    out.append(("  CPU s of this process (its workers' not counted)", cpu, ""))
    for t in design.best.terms:
        out.append((f"  best gait at friction {t.friction:g}: mm per cycle", t.forward,
                    "target >= 63 at 0.6, >= 45 at 0.4 and 0.8"))  # fmt: skip
        out.append((f"  best gait at friction {t.friction:g}: drift mm per cycle", t.drift,
                    "target < 3"))  # fmt: skip
    return out
