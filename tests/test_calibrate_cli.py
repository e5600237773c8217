"""``origami-cad calibrate`` and the fit: measured runs, drive logs, bad input."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from origami_cad.pattern import read_pattern
from origami_cad.simulation.calibrate import (
    ServoModel,
    calibrate,
    drive_log_curve,
    load_runs,
    select_tendons,
    tendons_x_dis,
)
from origami_cad.simulation.materials import Materials, load_materials
from origami_cad.simulation.pull import simulate_pull
from origami_cad.strings.route import route_from_pattern
from origami_cad.strings.tsa import ring_length, ring_length_derivatives

DATA = Path(__file__).parent / "data" / "pygamix"
MOUNTAIN = DATA / "descriptionData" / "f-mountain-big-fix-new.json"
KNOWN = Materials(crease_stiffness_given=0.06, hole_friction=0.15)
PULL = 45.0  # mm: half the bench's pull, where friction shows, keeps the fits short


@pytest.fixture(scope="module")
def mountain():
    cp = read_pattern(MOUNTAIN)
    return cp, route_from_pattern(cp)


@pytest.fixture(scope="module")
def known_pull(mountain):
    cp, route = mountain
    return simulate_pull(cp, route, PULL, KNOWN.simulation_params(), step=3.0)


def _cli(*args: str):
    run = [sys.executable, "-m", "origami_cad.cli", *args]
    return subprocess.run(run, capture_output=True, text=True, check=False)


def _bench_file(path: Path, pull, force, noise: float = 0.0, seed: int = 0) -> Path:
    """A run in PyGamiX's 4-column format (quoted, as its bench writes)."""
    rng = np.random.default_rng(seed)
    grid = np.linspace(0.0, pull[-1], 60)
    values = np.interp(grid, pull, force) * (1.0 + noise * rng.standard_normal(len(grid)))
    rows = [(g / 16.67, g / 16.67 + 0.1, g, f) for g, f in zip(grid, values, strict=True)]
    path.write_text("".join(",".join(f'"{v:.6g}"' for v in r) + "\n" for r in rows))
    return path


def test_the_fit_recovers_the_friction_of_a_simulated_bench(mountain, known_pull, tmp_path):
    """The fast check of the slow test below: one parameter, the other known."""
    cp, route = mountain
    files = [
        _bench_file(tmp_path / f"{i}.csv", known_pull.pull, known_pull.tension, 0.02, i)
        for i in range(2)
    ]
    start = KNOWN.replace(hole_friction=0.4)
    fit = calibrate(cp, route, load_runs(files), start, fit=("hole_friction",), step=3.0,
                    max_evaluations=8)  # fmt: skip
    assert fit.error_before > 0.1 and fit.error < 0.03
    assert fit.values["hole_friction"] == pytest.approx(0.15, abs=0.03)


@pytest.mark.slow
def test_the_fit_recovers_the_parameters_of_a_simulated_bench(mountain, known_pull, tmp_path):
    cp, route = mountain
    files = [
        _bench_file(tmp_path / f"{i}.csv", known_pull.pull, known_pull.tension, 0.02, i)
        for i in range(3)
    ]
    start = Materials(crease_stiffness_given=0.02, hole_friction=0.4)
    fit = calibrate(cp, route, load_runs(files), start, step=3.0, max_evaluations=40)
    assert fit.error_before > 0.2 and fit.error < 0.02
    assert fit.values["crease_stiffness"] == pytest.approx(0.06, rel=0.1)
    assert fit.values["hole_friction"] == pytest.approx(0.15, abs=0.03)
    assert all(s > 0 for s in fit.sigma.values())
    assert fit.materials.crease_stiffness() == pytest.approx(fit.values["crease_stiffness"])


def _drive_log(path: Path, pull, tension, tsa, x_dis, servo: ServoModel) -> Path:
    """``drive``'s CSV log of a ring TSA that takes up the pull: eq. 8 inverted by
    bisection on a fine grid of twists, the torque ``T dl/dtheta`` as current."""
    theta = np.linspace(0.0, 160 * math.pi, 200001)  # up to 80 turns
    taken = ring_length(theta, x_dis, tsa.d1, tsa.d2, tsa.string_width) - ring_length(
        0.0, x_dis, tsa.d1, tsa.d2, tsa.string_width
    )
    twist = np.interp(pull, taken, theta)
    _, rate, _, _ = ring_length_derivatives(twist, x_dis, tsa.d1, tsa.d2, tsa.string_width)
    current = servo.idle_current + tension * rate * servo.stall_current / servo.stall_torque
    with path.open("w", newline="") as fh:
        out = csv.writer(fh)
        out.writerow(["t_s", "id", "target_turns", "measured_turns", "current_mA"])
        for k, (th, i) in enumerate(zip(twist, current, strict=True)):
            turns = th / (2 * math.pi)
            out.writerow([0.05 * k, 3, round(turns + 0.01, 6), round(turns, 9), round(i, 6)])
    return path


def test_a_drive_log_becomes_force_against_pull(mountain, known_pull, tmp_path):
    """The fast check of the slow fit on a drive log below: the log's curve."""
    _, route = mountain
    x_dis, servo = tendons_x_dis(route), ServoModel()
    log = _drive_log(tmp_path / "log.csv", known_pull.pull, known_pull.tension, route.tsa,
                     x_dis, servo)  # fmt: skip
    pull, tension = drive_log_curve(log, route.tsa, x_dis, servo)
    assert pull[-1] == pytest.approx(PULL, abs=0.05)
    expected = np.interp(pull, known_pull.pull, known_pull.tension)
    assert tension == pytest.approx(expected, rel=0.02, abs=0.02)


@pytest.mark.slow
def test_the_fit_on_a_drive_log_recovers_its_materials(mountain, known_pull, tmp_path):
    cp, route = mountain
    x_dis, servo = tendons_x_dis(route), ServoModel()
    log = _drive_log(tmp_path / "log.csv", known_pull.pull, known_pull.tension, route.tsa,
                     x_dis, servo)  # fmt: skip
    runs = load_runs([log], tsa=route.tsa, x_dis=x_dis)
    start = Materials(crease_stiffness_given=0.02, hole_friction=0.4)
    fit = calibrate(cp, route, runs, start, step=3.0, max_evaluations=40)
    assert fit.values["crease_stiffness"] == pytest.approx(0.06, rel=0.1)
    assert fit.values["hole_friction"] == pytest.approx(0.15, abs=0.03)


def test_cli_calibrate_writes_its_three_files(known_pull, tmp_path):
    runs = [_bench_file(tmp_path / f"run{i}.csv", known_pull.pull, known_pull.tension, 0.05, i)
            for i in range(2)]  # fmt: skip
    out = tmp_path / "fit"
    done = _cli("calibrate", str(MOUNTAIN), *map(str, runs), "--step", "3",
                "--evaluations", "8", "-o", str(out))  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert {p.name for p in out.iterdir()} == {"materials.toml", "calibration.json", "fit.png"}
    report = json.loads((out / "calibration.json").read_text())
    fitted = report["parameters"]["crease_stiffness"]["value"]
    assert load_materials(out / "materials.toml").crease_stiffness() == pytest.approx(fitted)
    assert set(report["nrmse_per_run"]) == {"run0.csv", "run1.csv"}
    assert report["nrmse_mean"] < report["nrmse_mean_before"]
    assert (out / "fit.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("0,0.1,0,1\n0.02,0.12,2,abc\n0.04,0.14,3,1\n", "row 2, column 4"),
        ("0,0.1,0,1\n0.02,0.12\n", "row 2: no column 3"),
        ("0,0.1,0,1\n0.02,0.12,2,1\n0.04,0.14,1.5,1\n", "row 3: the pull decreases"),
        ("pull_mm,time_s\n0,1\n1,2\n", "tension_N"),
    ],
)
def test_cli_bad_runs_are_one_line_and_write_nothing(tmp_path, text, match):
    bad = tmp_path / "bad.csv"
    bad.write_text(text)
    out = tmp_path / "out"
    done = _cli("calibrate", str(MOUNTAIN), str(bad), "-o", str(out))
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert match in done.stderr and "bad.csv" in done.stderr and not out.exists()


def test_cli_a_design_without_tendons_is_refused(tmp_path):
    run = tmp_path / "run.csv"
    run.write_text("pull_mm,tension_N\n0,0\n1,1\n2,1.5\n")
    out = tmp_path / "out"
    done = _cli("calibrate", "examples/miura_6x4.toml", str(run), "-o", str(out))
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1
    assert "tendons" in done.stderr and "miura_6x4.toml" in done.stderr and not out.exists()


def test_pull_json_is_labelled_by_the_pull(known_pull):
    states = known_pull.to_dict()["simulation"]["states"]
    assert states["pull_mm"] == pytest.approx(known_pull.pull.tolist())
    assert not {"turns", "theta_s_deg", "tsa_torque_Nmm"} & set(states)


def test_cli_a_tendon_the_design_lacks_is_refused(tmp_path):
    run = tmp_path / "run.csv"
    run.write_text("pull_mm,tension_N\n0,0\n1,1\n2,1.5\n")
    out = tmp_path / "out"
    done = _cli("calibrate", str(MOUNTAIN), str(run), "--tendons", "3", "-o", str(out))
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert "tendon 3" in done.stderr and "1..2" in done.stderr and not out.exists()


def test_select_tendons_keeps_the_ones_named(mountain):
    _, route = mountain
    assert select_tendons(route, (2,)).strings == (route.strings[1],)
    assert select_tendons(route, None) is route
