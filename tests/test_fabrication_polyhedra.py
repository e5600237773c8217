"""A panel's solids assembled from their faces are the boolean chain's solids.

:func:`~origami_cad.fabrication.polyhedra.fast_panel_solids` builds each solid face by
face; :func:`~origami_cad.fabrication.solids.boolean_panel_solids` cuts the same solids
by booleans. On every distinct panel of a few sheets (holes placed automatically, none,
several per panel; the Fig. 2 design's panels with vanished edges) both must give valid
solids of the same volume, in the same place, with the same faces
(planes and cylinders), edges, vertices and shells.
"""

from __future__ import annotations

from collections import Counter

import pytest
import shapely
from build123d import Face, Solid, Vector, Wire
from helpers_fabrication import SHEETS, distinct_panels
from OCP.BRepCheck import BRepCheck_Analyzer

from origami_cad.fabrication import FabricationParams, plan_panels
from origami_cad.fabrication.polyhedra import fast_panel_solids, holes_clear
from origami_cad.fabrication.solids import (
    boolean_panel_solids,
    crease_sheet,
    panel_solids,
    planar_prism,
    prism_rings,
)
from origami_cad.pattern.design import miura_design
from origami_cad.pattern.model import Hole

PLANS = {
    "6 x 4, auto holes": (miura_design(4, 6, 20.0, 30.0, 70.0), FabricationParams()),
    **SHEETS,
}


def _topology(solid) -> tuple:
    kinds = Counter(str(f.geom_type) for f in solid.faces())
    counts = (len(solid.faces()), len(solid.edges()), len(solid.vertices()))
    return counts, len(solid.shells()), sorted(kinds.items())


def _same(fast: dict, boolean: dict, where: str) -> None:
    assert fast.keys() == boolean.keys()
    for name, solids in boolean.items():
        assert len(fast[name]) == len(solids), (where, name)
        for a, b in zip(fast[name], solids, strict=True):
            assert BRepCheck_Analyzer(a.wrapped).IsValid() and a.is_valid, (where, name)
            assert a.volume == pytest.approx(b.volume, rel=1e-9), (where, name)
            assert _topology(a) == _topology(b), (where, name)
            gap = (a - b).volume + (b - a).volume  # same place, not only same size
            assert gap < 1e-6 * b.volume, (where, name, gap)


@pytest.mark.parametrize("case", sorted(PLANS))
def test_solids_from_their_faces_are_the_boolean_solids(case):
    design, params = PLANS[case]
    plan, panels = distinct_panels(design, params)
    for o, holes in panels:
        fast = fast_panel_solids(o, holes, plan.params)
        assert fast is not None, (case, o.label)  # convex panels, holes clear
        _same(fast, boolean_panel_solids(o, holes, plan.params), f"{case}: {o.label}")


def test_a_hole_near_a_footprint_is_cut_by_booleans():
    plan = plan_panels(miura_design(2, 3, 30.0, 30.0, 65.0), FabricationParams(holes="none"))
    o = plan.outlines[0]
    x, y = o.infill_outer.min(axis=0)
    holes = (Hole(float(x) + 1.0, float(y) + 1.0, 3.0),)  # crosses the infill's side
    assert not holes_clear(o, holes)
    assert fast_panel_solids(o, holes, plan.params) is None
    built, boolean = (
        panel_solids(o, holes, plan.params),
        boolean_panel_solids(o, holes, plan.params),
    )
    assert {n: [s.volume for s in v] for n, v in built.items()} == {
        n: [s.volume for s in v] for n, v in boolean.items()
    }


def test_a_planar_prism_is_build123ds_face_of_its_rings_extruded():
    plan = plan_panels(miura_design(3, 4, 15.0, 15.0, 70.0), FabricationParams())
    sheet = shapely.union_all([shapely.Polygon(o.polygon) for o in plan.outlines])
    polys = [*shapely.get_parts(crease_sheet(plan.outlines, sheet))]
    polys += [shapely.Polygon(o.midlayer) for o in plan.outlines[:2]]
    polys.append(shapely.Polygon(plan.outlines[0].midlayer[::-1]))  # clockwise
    for poly in polys:
        wires = [
            Wire.make_polygon([Vector(x, y, 1.0) for x, y in ring], close=True)
            for ring in prism_rings(poly)
        ]
        want = Solid.extrude(Face(wires[0], wires[1:]), Vector(0, 0, 0.4))
        got = planar_prism(poly, 1.0, 1.4)
        assert BRepCheck_Analyzer(got.wrapped).IsValid()
        assert got.volume == pytest.approx(want.volume, rel=1e-12)
        assert _topology(got) == _topology(want)
        assert (got - want).volume + (want - got).volume < 1e-9 * want.volume
