"""The sheets the panel tests build on, and their distinct panels."""

from __future__ import annotations

from pathlib import Path

from origami_cad.fabrication import FabricationParams, largest_bias, plan_panels
from origami_cad.fabrication.congruent import congruent_panels
from origami_cad.pattern.design import load_design, miura_design

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
FIG2 = load_design(EXAMPLES / "fig2_tg.toml")

#: Sheets by name: (design, fabrication parameters). Vanished edges (corners of zero
#: length on some footprints), no hole, several holes in one panel.
SHEETS = {
    "Fig. 2 at its largest bias": (FIG2, FabricationParams(bias=largest_bias(FIG2))),
    "2 x 3, no holes": (miura_design(2, 3, 30.0, 30.0, 65.0), FabricationParams(holes="none")),
    "2 x 3, two holes in a panel": (
        miura_design(2, 3, 30.0, 30.0, 65.0),
        FabricationParams(shell=0.5, holes=[(12.0, 10.0), (18.0, 12.0), (45.0, 40.0)]),
    ),
}


def distinct_panels(design, params: FabricationParams):
    """The plan of ``design`` and, of its panels, those that are no copy of an earlier one
    (a copy is built once): ``(plan, [(outline, holes), ...])``."""
    plan = plan_panels(design, params)
    holes_of = [plan.holes_of(o.index) for o in plan.outlines]
    copies = congruent_panels(plan.outlines, holes_of)
    panels = zip(plan.outlines, holes_of, copies, strict=True)
    return plan, [(o, holes) for o, holes, same in panels if same is None]
