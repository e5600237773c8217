"""The route planner's tests' set-up: a short search, a ring TSA, Origami Simulator's square
base."""

from __future__ import annotations

from pathlib import Path

import origami_cad as oc
from origami_cad.pattern.design import Design
from origami_cad.strings import TSAParams
from origami_cad.strings.plan import PlanSettings, TSAPlacement

#: a short search: the sheets are small
FAST = PlanSettings(generations=20, grid=17)
#: a ring TSA, its panel the planner's choice
RING = TSAPlacement("ring", None, tsa=TSAParams(model="ring"))
SQUARE_BASE = Path(__file__).parent / "data" / "origami-simulator" / "squareBase.svg"


def square_base() -> Design:
    """Origami Simulator's square base, 150 mm wide: one interior vertex of six creases, which
    the degree-4 closed form does not fold."""
    return Design(oc.read_pattern(SQUARE_BASE, width=150.0), None, "file", SQUARE_BASE)
