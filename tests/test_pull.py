"""A tendon pulled by a test machine: force against pull on PyGamiX's mountain structure."""

from __future__ import annotations

import csv
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from origami_cad.errors import SimulationError
from origami_cad.pattern import read_pattern
from origami_cad.simulation import SimulationParams
from origami_cad.simulation.pull import LinearPull, simulate_pull
from origami_cad.strings.route import route_from_pattern

MOUNTAIN = Path(__file__).parent / "data" / "pygamix" / "descriptionData"
MOUNTAIN = MOUNTAIN / "f-mountain-big-fix-new.json"


@pytest.fixture(scope="module")
def mountain():
    cp = read_pattern(MOUNTAIN)
    return cp, route_from_pattern(cp)


def test_the_machine_draws_the_string_in_by_the_pull() -> None:
    machine = LinearPull()
    x = np.array([3.0, 7.5])
    assert machine.consumed(2.0, x).tolist() == [5.0, 9.5]
    length, by_pull, by_x, curv = machine.consumed_derivatives(2.0, x)
    assert length.tolist() == [5.0, 9.5] and by_pull.tolist() == by_x.tolist() == [1.0, 1.0]
    assert curv.tolist() == [0.0, 0.0] and machine.max_theta() == math.inf


def test_pull_force_grows_with_the_crease_stiffness(mountain) -> None:
    cp, route = mountain
    soft = simulate_pull(cp, route, 12.0, SimulationParams(fold_limit=180.0), step=2.0)
    stiff = simulate_pull(
        cp, route, 12.0, SimulationParams(fold_limit=180.0, crease_modulus=52.0), step=2.0
    )
    assert soft.pull[0] == 0 and soft.pull[-1] == pytest.approx(12.0)
    assert soft.tension[0] == 0 and soft.tension[-1] > 0
    assert soft.tension == pytest.approx(soft.result.tensions.sum(axis=1))
    assert soft.time == pytest.approx(soft.pull / (1000 / 60))
    # the creases resist: twice their stiffness, more force for the same pull
    assert stiff.tension[-1] > 1.5 * soft.tension[-1]
    # the pull folds the sheet: its creases turn more as the machine travels
    turned = np.abs(soft.result.fold_angles[:, cp.edge_mask("M", "V")]).max(axis=1)
    assert np.all(np.diff(turned[1:]) > 0)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan])
def test_a_bad_pull_is_refused(mountain, bad) -> None:
    cp, route = mountain
    with pytest.raises(SimulationError, match="pull"):
        simulate_pull(cp, route, bad)


def _cli(*args: str):
    run = [sys.executable, "-m", "origami_cad.cli", *args]
    return subprocess.run(run, capture_output=True, text=True, check=False)


def test_cli_pull_writes_force_against_pull(tmp_path: Path) -> None:
    out = tmp_path / "pull"
    done = _cli("simulate", str(MOUNTAIN), "--pull", "6", "--pull-step", "2", "-o", str(out))
    assert done.returncode == 0, done.stderr
    with (out / "pull.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [float(r["pull_mm"]) for r in rows] == pytest.approx([0, 2, 4, 6])
    assert float(rows[-1]["tension_N"]) > 0
    assert {p.name for p in out.iterdir()} == {"pull.csv", "states.fold", "simulation.json"}


def test_cli_pull_without_tendons_is_one_line(tmp_path: Path) -> None:
    out = tmp_path / "none"
    done = _cli("simulate", "examples/miura_6x4.toml", "--pull", "5", "-o", str(out))
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1
    assert "carries no tendons" in done.stderr and not out.exists()
