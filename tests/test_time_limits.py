"""Time limits that hold: a deadline stops the solver inside its Newton loop, the general
folder inside its path, ``simulate`` inside a step (keeping only equilibria), and the
commands ``simulate`` and ``plan-route`` end cleanly, their files complete and saying so.

No test measures time: a deadline already passed, or a clock that ticks a second per
reading, decides where each stops."""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pytest
from helpers_plan import SQUARE_BASE, square_base

import origami_cad as oc
from origami_cad.cli import main
from origami_cad.errors import SimulationError
from origami_cad.pattern.design import load_pattern_source
from origami_cad.simulation import simulate, solve_equilibrium
from origami_cad.simulation.model import SimulationParams, build_structure
from origami_cad.strings import load_route
from origami_cad.strings.dcqc_result import StopReason

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
BOAT = EXAMPLES / "data" / "boat.dxf"
BOAT_ROUTE = EXAMPLES / "boat_route.toml"


@pytest.fixture
def ticking(monkeypatch):
    """``time.monotonic`` as a clock that moves on one second at each reading."""
    now = [0.0]

    def tick() -> float:
        now[0] += 1.0
        return now[0]

    monkeypatch.setattr(time, "monotonic", tick)
    return now


def _boat():
    loaded = load_pattern_source(BOAT)
    return loaded, load_route(BOAT_ROUTE, loaded.pattern)


def test_a_solve_past_its_deadline_stops_unconverged_and_says_so():
    cp = load_pattern_source(BOAT).pattern
    st = build_structure(cp, SimulationParams(), None)
    st.hinge_rest[st.folds] = 0.05  # somewhere to go from flat
    x, info = solve_equilibrium(st.x0.copy(), st)
    assert info.converged and not info.timed_out and info.iterations > 0
    y, late = solve_equilibrium(st.x0.copy(), st, deadline=time.monotonic() - 1.0)
    assert late.timed_out and not late.converged and late.iterations == 0
    assert np.array_equal(y, st.x0)  # no step taken: where it started
    assert not np.allclose(x, st.x0)


def test_the_general_folder_refuses_past_its_deadline_in_one_sentence():
    with pytest.raises(SimulationError, match="ran out of time at fold ratio") as caught:
        oc.with_fold_path(square_base(), deadline=time.monotonic() - 1.0)
    assert "\n" not in str(caught.value)


def test_simulate_cut_short_keeps_only_equilibria_and_says_why(ticking):
    loaded, route = _boat()
    whole = simulate(loaded.pattern, route, design=loaded, steps=12)
    assert whole.stop is not StopReason.TIME_LIMIT and whole.converged.all()
    ticking[0] = 0.0
    cut = simulate(loaded.pattern, route, design=loaded, steps=12, time_limit=60.0)
    assert cut.stop is StopReason.TIME_LIMIT and "time limit of 60 s" in cut.reason
    assert 1 <= len(cut) < len(whole) and cut.converged.all()  # the cut solve is dropped
    assert cut.reason in cut.notes
    n = len(cut)  # the same states as the whole run, so far
    assert np.allclose(cut.theta, whole.theta[:n]) and np.allclose(cut.states, whole.states[:n])


def test_simulate_with_no_time_at_all_keeps_its_first_state_unconverged():
    loaded, route = _boat()
    result = simulate(loaded.pattern, route, design=loaded, time_limit=1e-9)
    assert result.stop is StopReason.TIME_LIMIT and len(result) == 1
    assert not result.converged[0] and result.theta[0] == 0.0


def test_the_simulate_command_past_its_limit_writes_every_file_saying_it_stopped(tmp_path, capsys):
    out = tmp_path / "sim"
    code = main(["simulate", str(BOAT), str(BOAT_ROUTE), "-o", str(out), "--time-limit", "1e-3"])
    assert code == 0
    err = capsys.readouterr().err
    assert "warning: the time limit ran out" in err
    data = json.loads((out / "simulation.json").read_text())
    assert data["stop"] == "time_limit" and "time limit" in data["reason"]
    states = len(data["states"]["turns"])
    fold = json.loads((out / "states.fold").read_text())
    assert len(fold["file_frames"]) == states
    assert "stopped early" in fold["file_frames"][-1]["frame_title"]
    assert all("stopped early" not in f["frame_title"] for f in fold["file_frames"][:-1])
    assert (out / "fold.gif").read_bytes()[:4] == b"GIF8"
    for name in ("folded.png", "route.png"):
        assert (out / name).read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize(
    ("pattern", "extra", "message"),
    [
        (BOAT, ["--tsa", "onboard:f0", "--strings", "2"], "ran out before the route search"),
        (SQUARE_BASE, ["--width", "150"], "ran out of time at fold ratio"),
    ],
)
def test_plan_route_with_no_time_refuses_in_one_line_and_writes_nothing(
    tmp_path, capsys, pattern, extra, message
):
    out = tmp_path / "plan" / "route.toml"
    argv = ["plan-route", str(pattern), *extra, "--time-limit", "1e-3", "-o", str(out)]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]
    assert not (tmp_path / "plan").exists()
