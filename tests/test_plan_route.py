"""Automatic string routing (plan-route): the fast DCQC model, the paper's set-ups, executors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from helpers_exec import InlineExecutor

from origami_cad.cli import main
from origami_cad.fabrication.params import FabricationParams
from origami_cad.pattern.design import load_pattern_source
from origami_cad.simulation import SimulationParams
from origami_cad.simulation.verify import verify_route
from origami_cad.strings import TSAParams, load_route, simulate_dcqc
from origami_cad.strings.dcqc_result import StopReason
from origami_cad.strings.plan import (
    DEFAULT_CREASE_STIFFNESS,
    PlanSettings,
    TSAPlacement,
    evaluate_routes,
    plan_geometry,
    plan_routes,
    route_spec,
    string_curves,
)
from origami_cad.strings.route import dump_route

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SHEET = FabricationParams(bias=3.0, height=2.2, thickness=0.4)  # the printed sheet of Figs. 4-5


def _example(design: str, route: str):
    loaded = load_pattern_source(EXAMPLES / design)
    spec = load_route(EXAMPLES / route, loaded.pattern)
    return loaded, spec, simulate_dcqc(loaded, spec, crease_stiffness=DEFAULT_CREASE_STIFFNESS)


def _written(tmp_path: Path, loaded, geom, planned, name: str = "route.toml"):
    """The planned route written as a route file and read back as `route` reads it."""
    path = tmp_path / name
    path.write_text(dump_route(route_spec(geom, planned), loaded.pattern), encoding="utf-8")
    return load_route(path, loaded.pattern)


def test_the_default_crease_stiffness_is_the_simulators():
    assert DEFAULT_CREASE_STIFFNESS == pytest.approx(SimulationParams().crease_stiffness)


def test_the_fast_model_scores_the_fig5_route_as_the_dcqc_simulation_folds_it():
    loaded, spec, full = _example("miura_6x4.toml", "miura_route.toml")
    settings = PlanSettings(grid=65)
    geom = plan_geometry(loaded, TSAPlacement("ring", tsa=spec.tsa), spec.fabrication, settings)
    k = max(len(s.faces) for s in spec.strings)

    def pad(seq):
        return list(seq) + [seq[-1]] * (k - len(seq))

    faces = np.array([pad(s.faces) for s in spec.strings])
    xy = np.array([pad(s.points) for s in spec.strings], dtype=float)
    sides = np.array([pad(s.sides) for s in spec.strings])
    anchors = np.repeat(np.array([s.anchor for s in spec.strings])[:, None], len(geom.ratios), 1)
    x, rest, cuts = string_curves(geom, anchors, faces, xy, sides)
    assert full.stop is StopReason.FOLD_LIMIT and geom.target_p == pytest.approx(full.p[-1])
    scores = evaluate_routes(geom, settings, x[None], rest[None], np.zeros_like(cuts)[None])
    assert scores.valid[0]
    assert scores.turns[0] == pytest.approx(full.turns[-1], rel=1e-4)
    assert scores.peak_torque[0] == pytest.approx(np.nanmax(full.torque), rel=0.01)
    # the hand-made route's anchor segments cut through the tilting corner panels, which
    # the full model reports too: the planner rejects such routes
    assert cuts.all() and len(full.cutting) == 4
    assert not evaluate_routes(geom, settings, x[None], rest[None], cuts[None]).valid[0]


def test_fig5_miura_on_the_ring_folds_to_eq6_in_fewer_turns_at_less_torque_than_the_example(
    tmp_path,
):
    loaded, _, example = _example("miura_6x4.toml", "miura_route.toml")
    turns, torque = float(example.turns[-1]), float(np.nanmax(example.torque))
    # the example's figures as the budgets, less the fast model's error (< 1 %, above)
    settings = PlanSettings(max_turns=0.99 * turns, max_torque=0.98 * torque)
    placement = TSAPlacement("ring", radius=126.0, height=10.0)
    planned = plan_routes(
        loaded, placement, 4, candidates=16, seed=0, executor=InlineExecutor(),
        fabrication=SHEET, settings=settings, check=1,
    )  # fmt: skip
    geom = plan_geometry(loaded, placement, SHEET, settings)
    best = _written(tmp_path, loaded, geom, planned[0])
    assert len(best.strings) == 4 and not best.violations
    result = simulate_dcqc(loaded, best, crease_stiffness=DEFAULT_CREASE_STIFFNESS)
    assert result.stop is StopReason.FOLD_LIMIT and result.valid
    assert result.p[-1] == pytest.approx(example.p[-1])  # eq. 6's limit, p = 0.542
    assert not result.cutting  # the example's four anchor segments cut their panels
    assert np.nanmax(result.torque) <= torque
    assert result.turns[-1] <= turns


def _boat_plan(executor, candidates: int = 8, seed: int = 0, check: int = 1):
    loaded = load_pattern_source(EXAMPLES / "data" / "boat.dxf")
    placement = TSAPlacement("onboard", "f0", height=10.0, tsa=TSAParams(model="onboard"))
    settings = PlanSettings(generations=15)
    planned = plan_routes(
        loaded, placement, 3, candidates=candidates, seed=seed, executor=executor,
        settings=settings, check=check,
    )  # fmt: skip
    return loaded, plan_geometry(loaded, placement, settings=settings), planned


def test_fig6_boat_with_an_onboard_tsa_closes_in_both_string_models(tmp_path):
    loaded, geom, planned = _boat_plan(InlineExecutor())
    cp = loaded.pattern
    spec = _written(tmp_path, loaded, geom, planned[0])
    assert spec.fixed_panel == "f0" and all(
        s.anchor_face == cp.face_index("f0") for s in spec.strings
    )
    dcqc = simulate_dcqc(loaded, spec, crease_stiffness=DEFAULT_CREASE_STIFFNESS)
    assert dcqc.stop is StopReason.FOLD_LIMIT and not dcqc.cutting
    keel = int(np.flatnonzero(cp.edge_mask("V") & (cp.edge_faces().min(axis=1) >= 0))[0])
    sim = verify_route(loaded, spec, steps=30)
    assert sim["reaches_target"] and sim["stop"] == "fold_limit"
    # the sides stand up (the keel folds past 90 deg) and the triangles close bow and stern
    angles = np.abs(simulate_dcqc(loaded, spec).fold_angles[-1])
    assert angles[keel] > 90.0
    ends = [e for e in range(cp.n_edges) if cp.assignments[e] in "MV" and e != keel]
    assert min(angles[e] for e in ends) > 90.0


def test_the_arm_is_folded_with_fewer_turns_and_less_torque_than_strings_along_its_rows(
    tmp_path,
):
    loaded, spec, example = _example("arm_design.toml", "arm_route.toml")
    placement = TSAPlacement("onboard", "c1r0s0", height=10.0, tsa=spec.tsa)
    settings = PlanSettings(max_holes=5, generations=20)
    planned = plan_routes(
        loaded, placement, 2, candidates=12, executor=InlineExecutor(),
        fabrication=SHEET, settings=settings, check=1,
    )  # fmt: skip
    geom = plan_geometry(loaded, placement, SHEET, settings)
    best = _written(tmp_path, loaded, geom, planned[0])
    result = simulate_dcqc(loaded, best, crease_stiffness=DEFAULT_CREASE_STIFFNESS)
    assert result.stop is StopReason.FOLD_LIMIT and example.stop is StopReason.FOLD_LIMIT
    assert result.p[-1] == pytest.approx(example.p[-1])
    assert not result.cutting and example.cutting  # the row strings cut panel c1r0s1
    assert result.turns[-1] <= example.turns[-1]
    assert np.nanmax(result.torque) <= np.nanmax(example.torque)


def test_routes_and_arm_designs_are_identical_on_a_dask_cluster_and_a_process_pool(
    tmp_path, capsys
):
    distributed = pytest.importorskip("distributed")
    import dataclasses

    from origami_cad.design import design_arm, load_task

    task_file = EXAMPLES / "arm_task.toml"
    task, settings = load_task(task_file)
    settings = dataclasses.replace(settings, runs=2, seed=3, max_generations=8)
    local_routes = [r.to_dict() for r in _boat_plan(None, candidates=6, seed=5, check=0)[2]]
    local_arms = design_arm(task, settings)  # the default process pool
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
            dashboard_address=None,
        ) as cluster,
        distributed.Client(cluster) as client,
    ):  # fmt: skip
        executor = client.get_executor()
        remote_routes = [
            r.to_dict() for r in _boat_plan(executor, candidates=6, seed=5, check=0)[2]
        ]
        workers = {w["host"] for w in client.scheduler_info()["workers"].values()}
        argv = ["design-arm", str(task_file), "--runs", "2", "--seed", "3"]
        argv += ["--max-generations", "8", "--scheduler", cluster.scheduler_address]
        assert main([*argv, "-o", str(tmp_path / "arm")]) == 0
    capsys.readouterr()
    assert workers == {"127.0.0.1"}
    assert json.dumps(remote_routes) == json.dumps(local_routes) and local_routes
    remote_arms = json.loads((tmp_path / "arm" / "results.json").read_text())["designs"]
    assert [(d["run"], d["lengths_mm"], d["best_fitness_per_generation"]) for d in remote_arms] == [
        (a.run, list(a.lengths), list(a.history)) for a in local_arms
    ]


def test_plan_route_command_writes_a_route_the_route_command_folds(tmp_path, capsys):
    out = tmp_path / "plan" / "route.toml"
    boat = str(EXAMPLES / "data" / "boat.dxf")
    argv = ["plan-route", boat, "--tsa", "onboard:f0", "--strings", "2", "--candidates", "6"]
    assert main([*argv, "-o", str(out)]) == 0
    data = json.loads((out.parent / "routes.json").read_text())
    assert data["routes"] and data["routes"][0]["rank"] == 1
    curve = data["routes"][0]["dcqc_curve"]
    assert len(curve["p"]) == len(curve["turns"]) and curve["p"][-1] == pytest.approx(
        data["target_p"]
    )
    assert np.all(np.diff(curve["turns"]) >= 0)
    assert data["routes"][0]["checks"]["simulation"]["reaches_target"]
    for name in ("routes.png", "routes_turns.png"):
        assert (out.parent / name).read_bytes()[:4] == b"\x89PNG"
    assert main(["route", boat, str(out), "-o", str(tmp_path / "folded")]) == 0
    folded = json.loads((tmp_path / "folded" / "dcqc.json").read_text())
    assert folded["stop"] == "fold_limit" and folded["valid"]
    capsys.readouterr()


@pytest.mark.parametrize(
    ("option", "message"),
    [
        (["--tsa", "onboard:nope"], "no panel labelled 'nope'"),
        (["--tsa", "rail"], "--tsa: expected 'ring' or 'onboard:PANEL', got 'rail'"),
        (["--budget", "20,-1"], "--budget: expected TURNS"),
    ],
)
def test_plan_route_refuses_a_bad_tsa_in_one_line_and_writes_nothing(
    tmp_path, capsys, option, message
):
    out = tmp_path / "plan" / "route.toml"
    boat = str(EXAMPLES / "data" / "boat.dxf")
    assert main(["plan-route", boat, *option, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]
    assert not (tmp_path / "plan").exists()


def test_a_target_crease_angle_gives_the_fold_ratio_where_the_crease_reaches_it():
    from origami_cad.strings.plan import target_ratio

    boat = load_pattern_source(EXAMPLES / "data" / "boat.dxf")
    cp = boat.pattern
    keel = int(np.flatnonzero(cp.edge_mask("V") & (cp.edge_faces().min(axis=1) >= 0))[0])
    p = target_ratio(boat, 1.0, target_angles={keel: 90.0})
    assert p == pytest.approx(0.5, abs=1e-5)  # the degree-4 folder turns the keel 180 p deg
    from origami_cad.kinematics.folding import fold_design

    assert abs(fold_design(boat, p).fold_angles[keel]) == pytest.approx(90.0, abs=1e-3)
    with pytest.raises(Exception, match="does not reach"):
        target_ratio(boat, 0.3, target_angles={keel: 90.0})


def test_free_panels_get_no_hole_and_existing_holes_are_candidates():
    from origami_cad.pattern.design import miura_design

    sheet = miura_design(2, 3, 30.0, 30.0, 65.0)
    cp = sheet.pattern
    free = "c0r0s1"
    existing = tuple(cp.vertices[cp.faces[cp.face_index("c0r1s1")]].mean(axis=0))
    placement = TSAPlacement("ring", radius=80.0)
    settings = PlanSettings(generations=5)
    geom = plan_geometry(
        sheet, placement, settings=settings, free_panels=[free], existing_holes=[existing]
    )
    assert cp.face_index(free) not in set(geom.hole_face.tolist())
    assert np.isclose(geom.hole_xy, existing).all(axis=1).any()
    planned = plan_routes(
        sheet, placement, 2, candidates=4, executor=InlineExecutor(), settings=settings,
        free_panels=[free], existing_holes=[existing], check=1,
    )  # fmt: skip
    assert planned and all(free not in s.names for r in planned for s in r.strings)
    assert planned[0].checks["dcqc"]["reaches_target"]
