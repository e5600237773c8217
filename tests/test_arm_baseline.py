"""The paper task's runs give the designs recorded in tests/data/arm_designs.json
(recorded before the fitness's trigonometry moved into the compiled kernel).

The first two runs (one of each entry flag, a few seconds) are checked by ``make test``;
all ten (about 25 s) are marked ``slow`` and run by ``make slow``."""

from __future__ import annotations

import json

import arm_baseline
import pytest


def _check(got: list[dict], runs: int) -> None:
    expected = json.loads(arm_baseline.BASELINE.read_text(encoding="utf-8"))
    expected = [d for d in expected if d["run"] < runs]
    assert len(got) == len(expected) == runs
    assert [d["run"] for d in got] == [d["run"] for d in expected]
    for g, e in zip(got, expected, strict=True):
        # the same search, step by step: the same numbers to the last bit
        assert g == e, (g["run"], g["fitness"], e["fitness"])


def test_the_first_runs_of_the_paper_task_give_the_recorded_designs():
    got = arm_baseline.designs(runs=2)
    assert {d["entry_flag"] for d in got} == {0, 1}
    _check(got, 2)


@pytest.mark.slow
def test_the_paper_task_gives_the_recorded_designs():
    _check(arm_baseline.designs(), 10)
