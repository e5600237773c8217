"""Assemble the designed origami arm with its TSA module into one STEP file.

Run: python examples/assemble_arm.py [OUT_DIR]
The arm comes from examples/arm_design.toml (the CMA-ES winner of examples/arm_task.toml);
the TSA module is mounted on the arm's base panel, its hub holes at the TSA model's d1.
"""

from __future__ import annotations

import sys
from pathlib import Path

from build123d import Compound, export_step
from origami_cad.parts import tsa_module

from origami_cad.fabrication import fabricate
from origami_cad.fabrication.solids import PART_NAMES
from origami_cad.pattern.design import load_design
from origami_cad.strings import TSAParams

HERE = Path(__file__).resolve().parent


def main(out: Path) -> Path:
    design = load_design(HERE / "arm_design.toml")
    fab = fabricate(design)
    children = []
    for name in PART_NAMES:
        part = fab.parts.compound(name)
        part.label = name
        children.append(part)
    # the TSA twists the strings that run along the arm, from its base panel
    module = tsa_module(
        servo="XL330", tsa=TSAParams(d1=10.0), plan=fab.plan, panel="c1r0s0", heading=0.0
    )
    children.append(module)
    arm = Compound(children=children)
    arm.label = "origami arm with TSA module"
    out.mkdir(parents=True, exist_ok=True)
    path = out / "arm_assembly.step"
    export_step(arm, str(path))
    print(f"wrote {path}: {len(fab.outlines)} panels + TSA module")
    return path


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out/arm"))
