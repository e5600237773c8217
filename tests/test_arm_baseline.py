"""The paper task's ten runs give the designs recorded in tests/data/arm_designs.json
(recorded before the fitness's trigonometry moved into the compiled kernel)."""

from __future__ import annotations

import json

import arm_baseline


def test_the_paper_task_gives_the_recorded_designs():
    expected = json.loads(arm_baseline.BASELINE.read_text(encoding="utf-8"))
    got = arm_baseline.designs()
    assert len(got) == len(expected) == 10
    assert [d["run"] for d in got] == [d["run"] for d in expected]
    for g, e in zip(got, expected, strict=True):
        # the same search, step by step: the same numbers to the last bit
        assert g == e, (g["run"], g["fitness"], e["fitness"])
