"""The crawler of the paper's Fig. 7 (issue 17): files, printing and walking in simulation."""

from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest

from origami_cad.cli import main
from origami_cad.errors import DesignError
from origami_cad.fabrication import FabricationParams, fabricate, plan_panels
from origami_cad.pattern import read_pattern
from origami_cad.pattern.check import check_pattern
from origami_cad.simulation.crawler import gait_turns, leg_contraction, load_robot, simulate_gait

HERE = Path(__file__).resolve().parents[1] / "examples" / "crawler"
ROBOT = HERE / "crawler.toml"


def _generator():
    spec = importlib.util.spec_from_file_location("make_crawler", HERE / "make_crawler.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def robot():
    return load_robot(ROBOT)


@pytest.fixture(scope="module")
def forward(robot):
    return simulate_gait(robot, cycles=1, steps=3)


def test_files_are_what_the_generator_writes(robot):
    gen = _generator()
    cp = gen.crawler_pattern()
    on_disk = read_pattern(HERE / "crawler.fold")
    assert np.allclose(cp.vertices, on_disk.vertices)
    assert cp.assignments.tolist() == on_disk.assignments.tolist()
    assert sorted(on_disk.face_labels) == ["body", "leg_fl", "leg_fr", "leg_rl", "leg_rr"]
    for label, servo, name, sx, sy in gen.LEGS:
        text = (HERE / f"route_{label[4:]}.toml").read_text(encoding="utf-8")
        assert text == gen.route_text(cp, label, servo, name, sx, sy)
    # the printed holes are the routed holes
    routed = {p for leg in robot.legs for s in leg.route.strings for p in s.points}
    assert routed == set(robot.holes)


def test_pattern_checks_and_size(robot):
    cp = robot.pattern
    assert [p for p in check_pattern(cp) if p.severity == "error"] == []
    x0, y0, x1, y1 = cp.bounds
    assert (x1 - x0, y1 - y0) == (360.0, 320.0)  # flat; the paper's robot is 340 x 320 standing
    assert len(robot.legs) == 4 and all(len(leg.route.strings) == 4 for leg in robot.legs)
    assert all(cp.assignments[leg.crease] == "M" for leg in robot.legs)
    assert robot.blockers == {leg.crease: 60.0 for leg in robot.legs}


def test_fabrication_prints_every_routed_hole(robot):
    plan = plan_panels(robot.pattern, FabricationParams(holes=robot.holes))
    assert len(plan.holes) == 32
    by_panel = plan.holes_by_label()
    assert {k: len(v) for k, v in by_panel.items()} == {
        "body": 16,
        "leg_fl": 4,
        "leg_fr": 4,
        "leg_rl": 4,
        "leg_rr": 4,
    }
    fab = fabricate(robot.pattern, FabricationParams(holes=robot.holes))
    mass = fab.report()["total_mass_g"]
    # the printed sheet alone: the paper's whole robot is 361 g with servos and driver
    assert 150 < mass < 300


def test_gait_turns_follow_the_string_model(robot):
    leg = robot.legs[0]
    c = leg_contraction(robot.pattern, leg, np.array([0.0, 0.1, 0.2, 0.3]))
    assert c[0] == pytest.approx(0.0, abs=1e-9)
    assert np.all(np.diff(c) > 0)  # folding down shortens the strings under the hinge
    turns = gait_turns(robot)
    assert turns.shape == (7, 4)
    # the front legs (fold 55 deg) need more twist than the standing legs (30 deg)
    assert turns[2, 0] > turns[1, 0] > turns[0, 0] > 0
    assert turns.max() * 2 * math.pi < leg.route.tsa.max_theta()


def test_one_cycle_crawls_forward_and_blockers_hold(robot, forward):
    (per,) = forward.displacement_per_cycle()
    assert per > 10.0  # mm, along +x, the heading the gait intends
    assert forward.blocked.max() <= 60.0 + 1.0  # blocker + the barrier's give
    assert forward.converged.all()
    assert forward.tensions.min() >= 0.0 and forward.torque.max() > 0.0
    # the robot is lifted on its legs while it walks
    assert forward.body[:, 2].max() > 50.0


def test_the_gait_played_backwards_crawls_backwards(robot):
    back = simulate_gait(robot, cycles=1, steps=3, reverse=True)
    (per,) = back.displacement_per_cycle()
    assert per < -10.0


def test_a_gait_past_the_blockers_is_refused(tmp_path):
    text = ROBOT.read_text(encoding="utf-8").replace("0.306, 0.306, 0.167", "0.4, 0.306, 0.167")
    for name in (
        "crawler.fold",
        "route_fl.toml",
        "route_fr.toml",
        "route_rl.toml",
        "route_rr.toml",
    ):
        (tmp_path / name).write_bytes((HERE / name).read_bytes())
    bad = tmp_path / "crawler.toml"
    bad.write_text(text, encoding="utf-8")
    with pytest.raises(DesignError, match="past its blocker"):
        load_robot(bad)


def test_crawl_command(tmp_path, capsys):
    out = tmp_path / "crawl"
    assert main(["crawl", str(ROBOT), "-o", str(out), "--cycles", "1", "--steps", "2"]) == 0
    data = json.loads((out / "crawl.json").read_text())
    assert len(data["displacement_per_cycle_mm"]) == 1
    assert data["paper_mm_per_cycle"] == 63.0
    assert (out / "crawl.gif").read_bytes()[:3] == b"GIF"
    assert (out / "crawl.png").read_bytes()[:4] == b"\x89PNG"
    capsys.readouterr()
    assert main(["crawl", str(ROBOT), "-o", str(tmp_path / "x"), "--cycles", "0"]) == 2
    assert "cycles" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()
