"""The project's TOML formats, each read and written by one module: the example files
(written by hand or by the commands) read, written back and read again give the same
design, task, route, sequence and robot; a second write gives the same text."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from origami_cad.crawler.robot import dump_robot, load_robot
from origami_cad.design.task import ArmTask, SearchSettings, dump_task, load_task
from origami_cad.drive.sequence import dump_sequence, load_sequence
from origami_cad.errors import OrigamiCadError
from origami_cad.pattern import read_pattern
from origami_cad.pattern.design import dump_design, load_design, load_pattern_source
from origami_cad.pattern.tg import TGDesign
from origami_cad.strings.route import dump_route, load_route

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def again(tmp_path: Path, text: str, name: str) -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


# ---------------------------------------------------------------------------- designs


@pytest.mark.parametrize("name", ["fig2_tg.toml", "arm_design.toml", "miura_6x4.toml"])
def test_a_design_written_back_is_the_same_tessellation(tmp_path, name):
    design = load_design(EXAMPLES / name)
    text = dump_design(design.tg)
    back = load_design(again(tmp_path, text, "d.toml"))
    assert back.kind == "transition-graph" and back.tg == design.tg
    np.testing.assert_array_equal(back.pattern.vertices, design.pattern.vertices)
    assert list(back.pattern.assignments) == list(design.pattern.assignments)
    assert dump_design(back.tg) == text


def test_a_rounded_design_and_a_pattern_file_design(tmp_path):
    design = load_design(EXAMPLES / "arm_design.toml")
    back = load_design(again(tmp_path, dump_design(design.tg, digits=3), "d.toml"))
    np.testing.assert_allclose(back.tg.lengths, design.tg.lengths, atol=5e-4)
    # kind = "file": the path as written, relative to the design file
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "boat.dxf").write_bytes((EXAMPLES / "data" / "boat.dxf").read_bytes())
    loaded = load_pattern_source(again(tmp_path, dump_design("data/boat.dxf"), "boat.toml"))
    assert loaded.kind == "file"
    expected = read_pattern(EXAMPLES / "data" / "boat.dxf")
    np.testing.assert_array_equal(loaded.pattern.vertices, expected.vertices)


# ---------------------------------------------------------------------------- tasks


def _same_task(a: ArmTask, b: ArmTask) -> None:
    for field in ("start", "alpha", "vectors", "length_range", "shape_angle_range",
                  "entry_flag", "hypar_base", "samples", "unit_width", "min_leg_gap", "bias",
                  "height", "thickness", "fold_limit", "codesign", "max_bias",
                  "min_panel_face"):  # fmt: skip
        assert getattr(a, field) == getattr(b, field), field
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.weights, b.weights)
    for kind in ("warning", "prohibited"):
        assert len(getattr(a, kind)) == len(getattr(b, kind))
        for pa, pb in zip(getattr(a, kind), getattr(b, kind), strict=True):
            assert shapely.equals_exact(pa, pb, tolerance=0.0), kind


def test_the_example_task_written_back_is_the_same_task(tmp_path):
    task, settings = load_task(EXAMPLES / "arm_task.toml")
    text = dump_task(task, settings)
    back, back_settings = load_task(again(tmp_path, text, "task.toml"))
    _same_task(task, back)
    assert back_settings == settings
    assert dump_task(back, back_settings) == text


def test_a_task_with_circles_holes_and_a_fold_limit(tmp_path):
    source = again(
        tmp_path,
        "[arm]\n"
        "points = [[250.0, 0.0], [120.0, 90.0], [50.0, 133.3]]\n"
        "weights = [3.5]\n"
        "entry_flag = 0\nhypar_base = false\n"
        "[[arm.warning]]\ncircle = [100.0, 100.0, 20.0]\n"
        "[[arm.prohibited]]\n"
        "polygon = [[150, 40], [400, 40], [400, 400], [150, 400]]\n"
        "holes = [[[200, 100], [300, 100], [300, 200]]]\n"
        "[fabrication]\nfold_limit = 150.5\n"
        "[search]\nruns = 2\nseed = 7\nsigma0 = 0.3\n",
        "src.toml",
    )
    task, settings = load_task(source)
    back, back_settings = load_task(again(tmp_path, dump_task(task, settings), "task.toml"))
    _same_task(task, back)
    assert back_settings == settings and back.fold_limit == 150.5
    assert len(back.prohibited[0].interiors) == 1
    # without settings: the defaults
    assert load_task(again(tmp_path, dump_task(task), "t2.toml"))[1] == SearchSettings()


# ---------------------------------------------------------------------------- routes

ROUTES = [
    ("miura_route.toml", "miura_6x4.toml"),
    ("arm_route.toml", "arm_design.toml"),
    ("boat_route.toml", "data/boat.dxf"),
    ("crawler/route_fl.toml", "crawler/crawler.fold"),
]


@pytest.mark.parametrize(("route", "pattern"), ROUTES)
def test_a_route_written_back_is_the_same_routing(tmp_path, route, pattern):
    cp = load_pattern_source(EXAMPLES / pattern).pattern
    spec = load_route(EXAMPLES / route, cp)
    text = dump_route(spec, cp)
    back = load_route(again(tmp_path, text, "route.toml"), cp)
    assert back.tsa == spec.tsa and back.fabrication == spec.fabrication
    for key in ("thickness", "max_turns", "p0", "p_max", "fixed_panel", "take_up",
                "max_tension", "max_torque"):  # fmt: skip
        assert getattr(back, key) == getattr(spec, key), key
    assert math.isclose(back.step, spec.step, rel_tol=1e-15)
    assert len(back.strings) == len(spec.strings)
    for a, b in zip(spec.strings, back.strings, strict=True):
        assert (a.anchor, a.faces, a.points, a.sides) == (b.anchor, b.faces, b.points, b.sides)
        assert (a.anchor_face, a.bad_segments) == (b.anchor_face, b.bad_segments)
    assert dump_route(back, cp).replace("(", "").count("\n") == text.count("\n")


# ---------------------------------------------------------------------------- sequences


@pytest.mark.parametrize("name", ["arm_fold.toml", "crawler_gait.toml"])
def test_a_sequence_written_back_is_the_same_sequence(tmp_path, name):
    seq = load_sequence(EXAMPLES / name)
    text = dump_sequence(seq)
    back = load_sequence(again(tmp_path, text, "seq.toml"))
    assert (back.repeat, back.rate, back.current_limit) == (seq.repeat, seq.rate, seq.current_limit)
    assert back.keyframes == seq.keyframes
    for a, b in zip(seq.tsas, back.tsas, strict=True):
        assert (a.dxl_id, a.name, a.tsa) == (b.dxl_id, b.name, b.tsa)
        np.testing.assert_array_equal(a.mapping, b.mapping)
        assert (a.load is None) == (b.load is None)
        if a.load is not None:
            np.testing.assert_array_equal(a.load, b.load)
    assert back.loads().keys() == seq.loads().keys()
    assert dump_sequence(back) == text


# ---------------------------------------------------------------------------- robots


def test_the_crawler_written_elsewhere_is_the_same_robot(tmp_path):
    robot = load_robot(EXAMPLES / "crawler" / "crawler.toml")
    text = dump_robot(robot, tmp_path)  # its files named from tmp_path
    back = load_robot(again(tmp_path, text, "crawler.toml"))
    assert back.pattern_path == robot.pattern_path
    for key in ("body", "blocker_angle", "friction", "holes", "masses", "adapter_at",
                "adapter_heading"):  # fmt: skip
        assert getattr(back, key) == getattr(robot, key), key
    assert [(g.panel, g.face, g.crease, g.servo, g.name, g.route_path) for g in back.legs] == [
        (g.panel, g.face, g.crease, g.servo, g.name, g.route_path) for g in robot.legs
    ]
    np.testing.assert_array_equal(back.gait_t, robot.gait_t)
    np.testing.assert_array_equal(back.gait_p, robot.gait_p)
    # given holes (not the routes' own) are written and read back
    holes = robot.holes[:3]
    import dataclasses

    fewer = dataclasses.replace(robot, holes=holes)
    text = dump_robot(fewer, tmp_path)
    assert "[fabrication]" in text
    assert load_robot(again(tmp_path, text, "few.toml")).holes == holes


# ---------------------------------------------------------------------------- any design


@st.composite
def tg_designs(draw) -> TGDesign:
    """A TG tessellation of 1..4 vectors, lengths 20..90 mm, angles 40..140 deg, any
    float (not only round ones)."""
    n = draw(st.integers(1, 4))
    lengths = draw(st.lists(st.floats(20.0, 90.0), min_size=n + 1, max_size=n + 1))
    angles = draw(st.lists(st.floats(40.0, 140.0), min_size=n, max_size=n))
    start = (draw(st.floats(-500.0, 500.0)), draw(st.floats(-500.0, 500.0)))
    return TGDesign(
        tuple(lengths), tuple(angles), draw(st.integers(0, 1)), draw(st.floats(10.0, 60.0)),
        draw(st.integers(1, 4)), start=start, hypar_base=draw(st.booleans()),
    )  # fmt: skip


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(tg=tg_designs())
def test_any_design_written_reads_back_the_same(tmp_path, tg):
    text = dump_design(tg)
    try:
        back = load_design(again(tmp_path, text, "any.toml"))
    except OrigamiCadError:  # a tessellation the pattern refuses (overlapping panels...)
        assume(False)
    assert back.tg == tg  # every float exactly: the writer keeps all their digits
    assert dump_design(back.tg) == text


@settings(
    max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    points=st.lists(
        st.tuples(st.floats(-400.0, 400.0), st.floats(-400.0, 400.0)), min_size=2, max_size=5
    ),
    vectors=st.integers(2, 8),
    limit=st.none() | st.floats(60.0, 180.0),
    runs=st.integers(1, 50),
    seed=st.integers(0, 2**32 - 1 - 50),  # run k is seeded seed + k
)
def test_any_task_written_reads_back_the_same(tmp_path, points, vectors, limit, runs, seed):
    task = ArmTask(points=[list(p) for p in points], vectors=vectors, fold_limit=limit)
    settings_ = SearchSettings(runs=runs, seed=seed)
    text = dump_task(task, settings_)
    back, back_settings = load_task(again(tmp_path, text, "any_task.toml"))
    _same_task(task, back)
    assert back_settings == settings_ and dump_task(back, back_settings) == text
