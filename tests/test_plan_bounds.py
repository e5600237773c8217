"""The route planner and the simulation end within their time, and the planner's holes
follow small panels (Origami Simulator's square base and hypar)."""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from helpers_exec import InlineExecutor
from helpers_plan import FAST, RING, square_base

import origami_cad as oc
from origami_cad.pattern.design import Design
from origami_cad.simulation import simulate
from origami_cad.strings.dcqc_result import StopReason
from origami_cad.strings.plan import (
    plan_geometry,
    plan_routes,
    route_spec,
    truncated_geometry,
)
from origami_cad.strings.plan_geometry import HOLE_LADDER, MIN_HOLE_DIAMETER

DATA = Path(__file__).parent / "data" / "origami-simulator"


@pytest.fixture(scope="module")
def base() -> Design:
    return oc.with_fold_path(square_base())


def test_a_spent_time_limit_keeps_the_first_count_and_stops_the_simulation(base):
    ex = InlineExecutor()
    geom = plan_geometry(base, RING, settings=FAST)
    spent = replace(FAST, deadline=time.time() - 1.0)  # no time left at all
    planned = plan_routes(base, RING, settings=spent, executor=ex, geometry=geom, check=1)
    assert planned and len(planned[0].strings) >= 1  # one count is always tried
    result = simulate(base.pattern, route_spec(geom, planned[0]), design=base, time_limit=1e-6)
    assert result.stop is StopReason.TIME_LIMIT and "time limit" in result.reason
    assert len(result) >= 1


def test_a_truncated_geometry_plans_to_its_last_ratio(base):
    geom = plan_geometry(base, RING, settings=FAST)
    short = truncated_geometry(geom, 9)
    assert short.target_p == pytest.approx(geom.ratios[8]) and short.limit_p == geom.limit_p
    assert short.v0.shape[0] == short.anchors.shape[1] == len(short.energy) == 9
    assert truncated_geometry(geom, len(geom.ratios)).target_p == geom.target_p


def test_small_panels_get_a_smaller_hole_than_asked_and_say_so():
    hypar = Design(oc.read_pattern(DATA / "hypar.svg", width=150.0), None, "file")
    geom = plan_geometry(oc.with_fold_path(hypar), RING, settings=FAST)
    d = geom.fabrication.hole_diameter
    assert d in HOLE_LADDER and d >= MIN_HOLE_DIAMETER and len(geom.hole_face)
    assert geom.notes and f"{d:g} mm" in geom.notes[0]
    # every candidate hole lies on the panel it is said to be on
    faces = hypar.pattern.faces_of_points(geom.hole_xy)
    assert np.array_equal(faces, geom.hole_face)
