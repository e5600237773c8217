"""Route planning on a pattern the closed form does not fold (Origami Simulator's square base).

The square base has one interior vertex of six creases: the degree-4 closed form refuses
it, so the planner folds it along the general folder's path (``oc.with_fold_path``);
what ``plan-route`` writes is then read by ``simulate`` and ``route``, through the Python
API and the command line.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers_exec import InlineExecutor
from helpers_plan import FAST, RING, SQUARE_BASE, square_base

import origami_cad as oc
from origami_cad.commands import execute
from origami_cad.errors import PatternError
from origami_cad.kinematics.folding import FoldPath, PathDesign
from origami_cad.pattern.design import Design
from origami_cad.strings import load_route, simulate_dcqc
from origami_cad.strings.plan import plan_geometry, route_spec
from origami_cad.strings.route import dump_route


@pytest.fixture(scope="module")
def base() -> Design:
    return square_base()


@pytest.fixture(scope="module")
def folded(base) -> Design:
    return oc.with_fold_path(base)


def test_the_path_is_the_general_folders_states_and_interpolates_between_them(base, folded):
    assert isinstance(folded, PathDesign) and isinstance(folded.path, FoldPath)
    path = folded.path
    general = oc.fold_states(base, [path.ratios[10], 0.3], method="general")
    at_sample = oc.fold_design(folded, float(path.ratios[10]))
    assert np.allclose(at_sample.coords, general[0].coords, atol=1e-6)
    between = oc.fold_design(folded, 0.3)  # not a sample: interpolated
    assert between.method == "general"
    assert np.allclose(between.fold_angles, general[1].fold_angles, atol=0.5)
    many = oc.fold_sequence(folded, [0.0, 0.3])
    assert np.allclose(many[0].coords[:, 2], 0.0) and np.allclose(many[1].coords, between.coords)
    assert oc.with_fold_path(folded) is folded  # a path is not folded again


def test_a_ratio_beyond_the_path_is_refused(folded):
    short = PathDesign(
        folded.pattern,
        None,
        "file",
        path=FoldPath.from_states(oc.fold_states(folded.pattern, [0.0, 0.2], method="general")),
    )
    with pytest.raises(PatternError, match=r"outside the folded path's \[0, 0\.2\]"):
        oc.fold_design(short, 0.5)


def test_without_the_path_the_planner_says_what_folds_it(base):
    with pytest.raises(PatternError, match=r"has 6 creases.*with_fold_path"):
        plan_geometry(base, RING, settings=FAST)


def test_python_api_plan_then_both_string_models_fold_the_written_route(folded, tmp_path):
    planned = oc.plan_routes(folded, RING, candidates=8, executor=InlineExecutor(), settings=FAST)
    geom = plan_geometry(folded, RING, settings=FAST)
    best = planned[0]
    assert best.checks["dcqc"]["reaches_target"] and len(best.strings) >= 1
    path = tmp_path / "route.toml"
    path.write_text(dump_route(route_spec(geom, best), folded.pattern))
    spec = load_route(path, folded.pattern)
    dcqc = simulate_dcqc(folded, spec)
    assert dcqc.valid and dcqc.p[-1] >= geom.target_p - 1e-3
    params = oc.SimulationParams.for_route(spec)
    sim = oc.simulate(folded.pattern, spec, params, design=folded, steps=12)
    assert np.isfinite(sim.p[-1])  # p fitted against the path (NaN without it)
    assert sim.turns[-1] > 0


def test_cli_plan_route_then_simulate_and_route_read_what_it_wrote(tmp_path):
    route = tmp_path / "route" / "route.toml"
    out = execute("plan-route", SQUARE_BASE, route, width=150.0, candidates=16, verify=1)
    assert out.status == 0 and route.exists()
    assert any("the fewest that reach the target" in m for m in out.messages)
    assert any("general solver" in m for m in out.messages)
    sim = execute("simulate", SQUARE_BASE, route, tmp_path / "sim", width=150.0, steps=12)
    assert sim.status == 0 and (tmp_path / "sim" / "states.fold").exists()
    assert sim.result.turns[-1] > 0 and np.isfinite(sim.result.p[-1])
    dcqc = execute("route", SQUARE_BASE, route, tmp_path / "dcqc", width=150.0)
    assert dcqc.status == 0 and dcqc.result.valid
    assert (tmp_path / "dcqc" / "dcqc.json").exists()
