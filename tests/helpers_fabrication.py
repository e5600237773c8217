"""The sheets the panel tests build on, and their distinct panels."""

from __future__ import annotations

from pathlib import Path

from origami_cad.fabrication import FabricationParams, largest_bias, plan_panels
from origami_cad.fabrication.congruent import congruent_panels
from origami_cad.pattern import CreasePattern
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


def sliver_sheet(width: float) -> tuple[CreasePattern, int]:
    """Two 40 mm squares and a ``width`` mm sliver between them (mm), and the sliver's face."""
    xs = (0.0, 40.0, 40.0 + width, 80.0 + width)
    v = [(x, 0.0) for x in xs] + [(x, 40.0) for x in xs]
    e = [(0, 1), (1, 2), (2, 3), (4, 5), (5, 6), (6, 7), (0, 4), (3, 7), (1, 5), (2, 6)]
    cp = CreasePattern(v, e, "BBBBBBBBVV")
    return cp, int(cp.face_of_point(40.0 + width / 2.0, 20.0))
