"""The paper task's ten runs (examples/arm_task.toml, seed 1) as recorded in
``tests/data/arm_designs.json``; ``python tests/arm_baseline.py`` records them afresh
(only when a change of the designs is intended and explained)."""

from __future__ import annotations

import dataclasses
import json
import sys
from pathlib import Path

from origami_cad.design import design_arm, load_task

HERE = Path(__file__).resolve().parent
TASK = HERE.parent / "examples" / "arm_task.toml"
BASELINE = HERE / "data" / "arm_designs.json"


def designs(executor=None, runs: int | None = None) -> list[dict]:
    """Every run's design of the paper task, ranked as design_arm ranks them; with ``runs``,
    only the first ``runs`` runs (run k is seeded and flagged as in the whole set)."""
    task, settings = load_task(TASK)
    if runs is not None:
        settings = dataclasses.replace(settings, runs=runs)
    out = []
    for d in design_arm(task, settings, executor=executor):
        out.append(
            {
                "run": d.run,
                "fitness": d.fitness,
                "fold_ratio_end": d.fold_ratio_end,
                "generations": d.generations,
                "entry_flag": d.entry_flag,
                "lengths": list(d.lengths),
                "shape_angles": list(d.shape_angles),
                "bias": d.bias,
            }
        )
    return out


if __name__ == "__main__":
    BASELINE.write_text(json.dumps(designs(), indent=1) + "\n", encoding="utf-8")
    print("wrote", BASELINE)
    sys.exit(0)
