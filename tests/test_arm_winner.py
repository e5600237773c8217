"""The arm search's winner: one rule (string check, refusals, tie) for scripts and the CLI."""

from __future__ import annotations

import dataclasses
import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from helpers_exec import InlineExecutor

import origami_cad as oc
from origami_cad.cli import main
from origami_cad.design import ArmDesign, ArmSearch, choose_arm_winner, load_task
from origami_cad.design.arm import AT_TOLERANCE
from origami_cad.errors import DesignWarning
from origami_cad.pattern.design import load_design

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TASK = EXAMPLES / "arm_task.toml"


def _arm(run: int, fitness: float, p_end: float) -> ArmDesign:
    """The example arm (examples/arm_design.toml) claiming the fold range ``0 .. p_end``."""
    tg = load_design(EXAMPLES / "arm_design.toml").tg
    return ArmDesign(
        tg.lengths, tg.shape_angles, tg.entry_flag, fitness, None, np.empty((0, 2)),
        run=run, generations=0, history=(), fold_ratio_end=p_end,
    )  # fmt: skip


def _paper_task_at_180(tmp_path: Path) -> Path:
    """The paper's Fig. 3 task as the paper states it: every crease folds to 180 deg."""
    lines = TASK.read_text(encoding="utf-8").splitlines(keepends=True)
    kept = [x for x in lines if x.split("=")[0].strip() not in ("bias", "height", "thickness")]
    text = "".join(kept).replace("\n[fabrication]", "\n[fabrication]\nfold_limit = 180\n#", 1)
    path = tmp_path / "task180.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_the_tolerance_is_drives():
    from origami_cad.drive.from_model import AT_TOLERANCE as DRIVE

    assert AT_TOLERANCE == DRIVE


def test_a_design_its_strings_cannot_fold_never_wins_over_one_they_can():
    task, _ = load_task(TASK)
    # the example arm's strings fold it to p = 0.335 (eq. 6 stops it there): claiming
    # p_e = 0.9 it is refused, claiming its own range it is accepted
    short, good = _arm(0, 60.0, 0.9), _arm(1, 59.0, 0.3345)
    with warnings.catch_warnings():
        warnings.simplefilter("error", DesignWarning)  # one design is accepted: no warning
        search = choose_arm_winner([short, good], task)
    assert search.winner is good and [d.run for d in search] == [1, 0]
    assert not search.all_refused and search.shortfall() is None
    assert set(search.refused) == {0} and "p = 0.33" in search.refused[0]
    assert search.folded_to == pytest.approx(0.3345, abs=AT_TOLERANCE)
    assert f"20:{good.fold_ratio_end:.3f} 30:" in search.strings.text  # the winner's route


def test_when_every_design_is_refused_the_best_by_eq5_wins_with_a_warning():
    task, _ = load_task(TASK)
    first, second = _arm(3, 60.0, 0.9), _arm(5, 59.0, 0.8)
    with pytest.warns(DesignWarning, match=r"run 3: its strings fold it to p = 0\.33"):
        search = choose_arm_winner([first, second], task)
    assert search.winner is first and search.all_refused and len(search) == 2
    assert set(search.refused) == {3, 5}
    assert search.folded_to < 0.9 - AT_TOLERANCE
    assert "run 3" in search.shortfall()


def test_a_script_and_the_command_line_get_the_same_winner(tmp_path):
    task, settings = load_task(TASK)
    settings = dataclasses.replace(settings, runs=2, max_generations=4)
    search = oc.design_arm(task, settings, executor=InlineExecutor())
    assert isinstance(search, ArmSearch) and search.checked
    assert main(["design-arm", str(TASK), "-o", str(tmp_path / "arm"), "--runs", "2",
                 "--max-generations", "4"]) == 0  # fmt: skip
    data = json.loads((tmp_path / "arm" / "results.json").read_text())
    assert [d["run"] for d in data["designs"]] == [d.run for d in search]
    assert data["designs"][0]["lengths_mm"] == pytest.approx(search.winner.lengths)
    assert data["tie"]["refused"] == {str(k): v for k, v in search.refused.items()}
    assert (tmp_path / "arm" / "route.toml").read_text() == search.strings.text
    # without the string check, eq. 5's ranking alone
    ranked = oc.design_arm(task, settings, executor=InlineExecutor(), check_strings=False)
    assert not ranked.checked and ranked.strings is None
    assert sorted(d.run for d in ranked) == sorted(d.run for d in search)


def test_the_papers_task_at_180_deg_writes_its_designs_and_says_how_far_they_fold(tmp_path, capsys):
    task = _paper_task_at_180(tmp_path)
    assert load_task(task)[0].fold_limit == 180.0
    out = tmp_path / "arm"
    argv = ["design-arm", str(task), "-o", str(out), "--runs", "1", "--max-generations", "4"]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert err.startswith("origami-cad: warning: every design was refused") and "p = " in err
    assert len(err.strip().splitlines()) == 1
    data = json.loads((out / "results.json").read_text())
    short = data["winner_refused"]
    assert short["run"] == data["designs"][0]["run"] and short["stop"]
    assert short["strings_fold_to_p"] < short["fold_ratio_end"] - AT_TOLERANCE
    assert math.isclose(short["fold_ratio_end"], 1.0)
    assert "every design is refused" in data["tie"]["rule"]
    assert load_design(out / "best.toml").pattern.check() == []
    for name in ("route.toml", "trajectories.png", "convergence.png", "best_pattern.png"):
        assert (out / name).stat().st_size > 0


@pytest.mark.slow
def test_the_papers_whole_search_at_180_deg_exits_0(tmp_path, capsys):
    """Ten runs of 400 generations, as the task file says (about 15 s)."""
    out = tmp_path / "arm"
    assert main(["design-arm", str(_paper_task_at_180(tmp_path)), "-o", str(out)]) == 0
    data = json.loads((out / "results.json").read_text())
    assert len(data["designs"]) == 10 and data["designs"][0]["fitness"] > 59.9
    assert data["winner_refused"]["run"] == data["designs"][0]["run"]
    assert "origami-cad: warning:" in capsys.readouterr().err
