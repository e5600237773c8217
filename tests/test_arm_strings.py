"""The designed arm folded by its strings: its route, the sequence command, Fig. 8."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from conftest import colour_pixels, frame_lines

from origami_cad.cli import main
from origami_cad.design import load_task
from origami_cad.design.arm_route import arm_chain_path, arm_route
from origami_cad.drive.from_model import fold_curve, parse_keyframes, turns_at
from origami_cad.drive.sequence import load_sequence
from origami_cad.errors import DriveError
from origami_cad.kinematics import chain_points, tessellation_vertices
from origami_cad.pattern.design import load_design
from origami_cad.strings import StopReason, load_route, simulate_dcqc

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
DESIGN = EXAMPLES / "arm_design.toml"
ROUTE = EXAMPLES / "arm_route.toml"
TASK = EXAMPLES / "arm_task.toml"


@pytest.fixture(scope="module")
def arm():
    design = load_design(DESIGN)
    route = load_route(ROUTE, design.pattern)
    return design, route, simulate_dcqc(design, route)


def _designed_p_end(design) -> float:
    from origami_cad.design import reachable_fold_angle

    task, _ = load_task(TASK)
    beta = np.radians([design.tg.shape_angles])
    return float(reachable_fold_angle(beta, task.crease_limit())[0] / math.pi)


def test_the_route_is_what_design_arm_writes_and_obeys_dcqc(arm):
    design, route, _ = arm
    assert route == arm_route(design.tg)  # the example's hand-written file: the same route
    assert route.tsa.model == "onboard" and route.violations == []
    base = design.pattern.face_index("c1r0s0")
    assert all(s.anchor_face == base for s in route.strings)
    n = len(design.tg.lengths) - 1
    for row, string in enumerate(route.strings):
        assert list(string.names) == [f"c1r{row}s{k}" for k in range(1, n + 1)]
    assert route.fabrication is not None and route.fabrication.bias == 3.0


def test_dcqc_folds_the_arm_over_its_whole_design_range(arm):
    design, _, result = arm
    p_e = _designed_p_end(design)
    assert result.stop == StopReason.FOLD_LIMIT and result.limit.source == "eq6"
    assert result.p[-1] == pytest.approx(p_e, abs=2e-3)
    assert np.all(np.diff(result.p) >= -1e-9)  # it folds on as the TSA turns
    assert result.jam is None


def test_arm_chain_path_recovers_the_tg_from_any_placed_rigid_fold():
    design = load_design(DESIGN)
    ratios = np.array([0.0, 0.1, 0.2, 0.33])
    grid = tessellation_vertices(design.tg, ratios).reshape(len(ratios), -1, 3)
    rng = np.random.default_rng(4)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.linalg.det(q))
    moved = grid @ q.T + rng.normal(size=3) * 50
    got = arm_chain_path(design.tg, moved, ratios)
    tg = design.tg
    want = chain_points(
        ratios * math.pi, tg.lengths, np.radians(tg.shape_angles), tg.entry_flag, True, tg.start
    )[0]
    np.testing.assert_allclose(got, want, atol=1e-6)


def test_arm_scene_strings_bring_the_printed_tip_to_p_end_outside_the_prohibited_area(tmp_path):
    out = tmp_path / "fig8"
    assert main(["arm-scene", str(TASK), str(DESIGN), str(ROUTE), "-o", str(out)]) == 0
    data = json.loads((out / "arm_scene.json").read_text())
    task, _ = load_task(TASK)
    tips = np.array(data["simulated_tip_mm"])
    assert data["final_distance_from_P_end_mm"] <= 10.0
    assert np.linalg.norm(tips[-1] - task.points[-1]) == pytest.approx(
        data["final_distance_from_P_end_mm"]
    )
    # state by state, the printed arm follows the designed tip path at its fold ratio
    assert data["max_distance_from_designed_tip_mm"] <= 10.0
    assert data["states_touching_prohibited_area"] == 0
    area = task.prohibited[0]
    assert not shapely.intersects(shapely.LineString(tips), area)
    assert data["stop"] == "fold_limit" and 10 < data["tsa_turns"] < 60
    assert data["max_tsa_torque_Nmm"] > 0
    # fig8.png, equal axes: the simulated tip path (red) has the proportions of the data
    left, right = frame_lines(out / "fig8.png", vertical=True)
    rows, cols = colour_pixels(out / "fig8.png", "#d62728")
    inside = (cols > left) & (cols < right)  # not the legend's line
    assert inside.sum() > 500
    drawn = np.ptp(cols[inside]) / np.ptp(rows[inside])
    assert drawn == pytest.approx(np.ptp(tips[:, 0]) / np.ptp(tips[:, 1]), rel=0.03)


def test_sequence_reproduces_the_dcqc_curve_and_drives_the_emulator(arm, tmp_path, capsys):
    design, _, result = arm
    seq_path = tmp_path / "arm_fold.toml"
    top = math.floor(_designed_p_end(design) * 1000) / 1000  # the end of the design range
    frames = ["0:0", "5:0.1", "10:0.25", f"15:{top}", "20:0"]
    argv = ["sequence", str(DESIGN), str(ROUTE), "-o", str(seq_path), "--keyframes", *frames]
    assert main(argv) == 0
    seq = load_sequence(seq_path)
    p, turns = fold_curve(result.p, result.turns)
    for (t, values), frame in zip(parse_keyframes(frames, 1), seq.keyframes, strict=True):
        want = float(turns_at(p, turns, values[0]))
        got = seq.turns_at(frame.t)[1]
        assert got == pytest.approx(want, rel=0.01, abs=1e-6), (t, got, want)
    assert seq.turns_at(15.0)[1] > 10
    assert "origami-cad sequence" in seq_path.read_text()
    log = tmp_path / "log.csv"
    code = main(["drive", str(seq_path), "--dry-run", "--speed", "40", "--log", str(log)])
    assert code == 0, capsys.readouterr().err
    rows = list(csv.DictReader(log.open()))
    assert max(float(r["target_turns"]) for r in rows) == pytest.approx(
        float(turns_at(p, turns, top)), rel=0.01
    )


def test_examples_are_generated_by_the_string_models():
    """arm_fold.toml comes from `sequence` (DCQC), crawler_gait.toml from `crawl`; both say how."""
    text = (EXAMPLES / "arm_fold.toml").read_text()
    assert "#   origami-cad sequence examples/arm_design.toml examples/arm_route.toml" in text
    assert "not typed by" in text
    seq = load_sequence(EXAMPLES / "arm_fold.toml")
    design = load_design(DESIGN)
    assert seq.tsas[0].mapping[-1, 0] == pytest.approx(_designed_p_end(design), abs=2e-3)
    gait = (EXAMPLES / "crawler_gait.toml").read_text()
    assert "#   origami-cad crawl examples/crawler/crawler.toml" in gait
    assert "written by origami-cad crawl" in gait and "from the model" in gait


def test_sequence_bad_inputs_exit_2_and_write_nothing(tmp_path, capsys):
    out = tmp_path / "seq.toml"
    base = ["sequence", str(DESIGN), str(ROUTE), "-o", str(out), "--keyframes"]
    for frames, message in [
        (["0:0", "10:0.9"], "outside what its strings reach"),
        (["0:0"], "at least two keyframes"),
        (["0:0", "x:0.2"], "expected TIME:P"),
        (["1:0", "5:0.2"], "first keyframe must be at t = 0"),
    ]:
        assert main([*base, *frames]) == 2
        err = capsys.readouterr().err
        assert message in err and err.count("\n") == 1
        assert not out.exists()
    ring = EXAMPLES / "miura_route.toml"
    miura = EXAMPLES / "miura_6x4.toml"
    code = main(["sequence", str(miura), str(ring), "-o", str(out), "--keyframes", "0:0", "5:0.2"])
    assert code == 2 and "onboard" in capsys.readouterr().err
    with pytest.raises(DriveError, match="2 fold ratios for 1 TSAs"):
        parse_keyframes(["0:0,0.1", "1:0.2"], 1)
