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
