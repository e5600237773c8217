"""plan-route on small sheets: the fewest strings, strings sharing panels, refusals that help."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers_exec import InlineExecutor
from helpers_plan import FAST

from origami_cad.errors import StringsError
from origami_cad.pattern import CreasePattern, write_pattern
from origami_cad.pattern.design import load_pattern_source
from origami_cad.strings import TSAParams, load_route, simulate_dcqc
from origami_cad.strings.plan import (
    TSAPlacement,
    plan_geometry,
    plan_messages,
    plan_routes,
    route_spec,
)
from origami_cad.strings.plan_geometry import FACET_CLEARANCE
from origami_cad.strings.route import dump_route


@pytest.fixture(scope="module")
def strip(tmp_path_factory) -> Path:
    """Five 30 x 40 mm panels in a row, creases alternating valley and mountain."""
    v = [(30.0 * i, 0.0) for i in range(6)] + [(30.0 * i, 40.0) for i in range(6)]
    e = [(i, i + 1) for i in range(5)] + [(i + 6, i + 7) for i in range(5)]
    e += [(0, 6), (5, 11)] + [(i, i + 6) for i in range(1, 5)]
    path = tmp_path_factory.mktemp("strip") / "strip5.fold"
    write_pattern(CreasePattern(v, e, "B" * 12 + "VMVM"), path)
    return path


def _plan(path: Path, kind: str, n, panel=None):
    loaded = load_pattern_source(path)
    placement = TSAPlacement(kind, panel, tsa=TSAParams(model=kind))
    planned = plan_routes(
        loaded, placement, n, candidates=8, executor=InlineExecutor(), settings=FAST, check=1
    )
    return loaded, plan_geometry(loaded, placement, settings=FAST), planned


def test_five_panels_onboard_with_four_strings_plan_instead_of_crashing(strip):
    _, _, planned = _plan(strip, "onboard", 4, "f0")
    assert planned and all(len(r.strings) == 4 for r in planned)
    assert all("f0" not in s.names for s in planned[0].strings)  # the TSA's own panel


def test_ring_strings_share_panels_of_a_small_sheet_through_holes_of_their_own(strip, tmp_path):
    loaded, geom, planned = _plan(strip, "ring", 3)  # 3 strings of >= 2 panels: 5 panels
    best = planned[0]
    assert len(best.strings) == 3
    holes = [(n, p) for s in best.strings for n, p in zip(s.names, s.points, strict=True)]
    assert len(set(holes)) == len(holes)  # no hole twice
    panels = [n for s in best.strings for n in s.names]
    assert len(set(panels)) < len(panels)  # some panel carries two strings
    assert len({s.anchor for s in best.strings}) == 3  # a guide each
    path = tmp_path / "route.toml"  # the route file reads back and folds
    path.write_text(dump_route(route_spec(geom, best), loaded.pattern), encoding="utf-8")
    spec = load_route(path, loaded.pattern)
    result = simulate_dcqc(loaded, spec)
    assert result.p[-1] > 0.5 * geom.target_p


def test_without_a_count_the_fewest_strings_that_reach_the_target_are_planned(strip):
    _, geom, planned = _plan(strip, "ring", None)
    n = len(planned[0].strings)
    assert all(len(r.strings) == n for r in planned)
    assert planned[0].checks["dcqc"]["reaches_target"]
    if n > 1:  # fewer strings do not reach it
        with pytest.raises(StringsError):
            _plan(strip, "ring", n - 1)
    (first,) = plan_messages(planned, geom, fewest=True)[:1]
    assert f"{n} string" in first and "the fewest that reach the target" in first


def test_too_many_strings_are_refused_with_the_count_that_fits(strip):
    with pytest.raises(StringsError) as err:
        _plan(strip, "ring", 16)
    message = str(err.value)
    assert "no 16 strings fit together" in message
    assert "leave --strings out" in message and "\n" not in message
    # the remedy named was tried, and the count it found is the one planned without a count
    n = len(_plan(strip, "ring", None)[2][0].strings)
    plural = "s reach" if n > 1 else " reaches"
    assert f"leaving --strings out works: {n} string{plural}" in message


@pytest.fixture(scope="module")
def faceted(tmp_path_factory) -> Path:
    """Three 30 x 40 mm panels in a row, each cut in two by a facet crease (F) at y = 20 mm:
    the printed panel is whole, and its hole's natural place, the centre, is on that line."""
    v = [(30.0 * i, y) for y in (0.0, 40.0, 20.0) for i in range(4)]
    e = [(i, i + 1) for i in (0, 1, 2, 4, 5, 6)] + [(0, 8), (8, 4), (3, 11), (11, 7)]
    e += [(i, i + 8) for i in (1, 2)] + [(i + 8, i + 4) for i in (1, 2)]
    e += [(i, i + 1) for i in (8, 9, 10)]
    path = tmp_path_factory.mktemp("faceted") / "faceted.fold"
    write_pattern(CreasePattern(v, e, "B" * 10 + "VMVM" + "FFF"), path)
    return path


def test_holes_of_panels_merged_across_facet_creases_stay_inside_one_face(faceted):
    import shapely

    import origami_cad as oc

    loaded = oc.with_fold_path(load_pattern_source(faceted))
    cp = loaded.pattern
    placement = TSAPlacement("ring", None, tsa=TSAParams(model="ring"))
    geom = plan_geometry(loaded, placement, settings=FAST)
    clear = FACET_CLEARANCE
    polys = cp.face_polygons()

    def inside(face: int, xy) -> float:  # mm from the face's outline (its creases)
        return float(polys[face].exterior.distance(shapely.Point(*xy)))

    # every printed panel (a pair of faces) gets candidate holes, none on a facet crease
    columns = {int(x // 30.0) for x in geom.hole_xy[:, 0]}
    assert len(cp.faces) == 6 and columns == {0, 1, 2}
    candidates = zip(geom.hole_face, geom.hole_xy, strict=True)
    assert all(inside(f, xy) >= clear - 1e-9 for f, xy in candidates)
    planned = plan_routes(
        loaded, placement, 1, candidates=8, executor=InlineExecutor(), settings=FAST, check=1
    )
    holes = [(f, xy) for s in planned[0].strings for f, xy in zip(s.faces, s.points, strict=True)]
    assert holes and all(inside(f, xy) >= clear - 1e-9 for f, xy in holes)  # CMA-ES kept them
    spec = route_spec(geom, planned[0])  # the bar-and-hinge model takes its holes
    sim = oc.simulate(cp, spec, oc.SimulationParams.for_route(spec), design=loaded, steps=3)
    assert sim.turns[-1] > 0


def _small_strip(folder: Path, width: float) -> Path:
    """Five panels in a row, ``width`` mm wide in all, each 1.3 times as tall as wide."""
    k = width / 5.0
    v = [(k * i, 0.0) for i in range(6)] + [(k * i, 1.3 * k) for i in range(6)]
    e = [(i, i + 1) for i in range(5)] + [(i + 6, i + 7) for i in range(5)]
    e += [(0, 6), (5, 11)] + [(i, i + 6) for i in range(1, 5)]
    path = folder / f"strip{width:g}.fold"
    write_pattern(CreasePattern(v, e, "B" * 12 + "VMVM"), path)
    return path


def test_a_sheet_too_small_for_any_hole_is_refused_with_a_width_that_was_checked(tmp_path):
    import re

    placement = TSAPlacement("ring", None, tsa=TSAParams(model="ring"))
    small = load_pattern_source(_small_strip(tmp_path, 10.0))
    with pytest.raises(StringsError) as err:
        plan_geometry(small, placement, settings=FAST)
    message = str(err.value)
    assert "no panel has room for a 1 mm hole" in message and "all 5 are too small" in message
    width = float(re.search(r"at --width (\d+)", message).group(1))
    assert width > 10.0
    # the width named gives the panels room: the planner lays out holes there
    larger = load_pattern_source(_small_strip(tmp_path, 10.0), width=width)
    assert len(plan_geometry(larger, placement, settings=FAST).hole_face)


def test_fabricate_places_every_hole_its_fitting_kept_on_panels_of_one_shape(tmp_path):
    from origami_cad.fabrication.params import FabricationParams
    from origami_cad.fabrication.plan import plan_panels

    # five equal panels just large enough for their hole at a narrowed bias: the copies of
    # the first panel's shape must fit what it got, or be fitted again (not refused)
    cp = load_pattern_source(_small_strip(tmp_path, 30.0)).pattern
    plan = plan_panels(cp, FabricationParams(hole_diameter=2.0, holes="auto"))
    assert len(plan.holes) == 5 and sorted(plan.hole_panels.tolist()) == [0, 1, 2, 3, 4]
    assert plan.biases is not None and max(plan.biases) < FabricationParams().bias  # narrowed


def test_panels_with_holes_that_never_meet_are_refused_saying_so(tmp_path):
    # wide panels with holes, each pair parted by a 2 mm panel with no room for one
    xs = [0.0, 30.0, 32.0, 62.0, 64.0, 94.0]
    v = [(x, 0.0) for x in xs] + [(x, 40.0) for x in xs]
    e = [(i, i + 1) for i in range(5)] + [(i + 6, i + 7) for i in range(5)]
    e += [(0, 6), (5, 11)] + [(i, i + 6) for i in range(1, 5)]
    path = tmp_path / "parted.fold"
    write_pattern(CreasePattern(v, e, "B" * 12 + "VMVM"), path)
    loaded = load_pattern_source(path)
    placement = TSAPlacement("ring", None, tsa=TSAParams(model="ring"))
    geom = plan_geometry(loaded, placement, settings=FAST)
    assert len(set(geom.hole_face.tolist())) == 3  # the wide ones
    with pytest.raises(StringsError) as err:
        plan_routes(loaded, placement, None, candidates=8, executor=InlineExecutor(),
                    settings=FAST, check=1, geometry=geom)  # fmt: skip
    message = str(err.value)
    assert "no two of the 3 panels with holes meet at a mountain or valley crease" in message
    assert "\n" not in message, message
