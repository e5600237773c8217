"""Every command writes what it wrote before the commands became a registry (issue 29).

``tests/data/commands_baseline.json`` was recorded by ``tests/commands_baseline.py``
from ``origami_cad/jobs.py`` before the move; each fast case runs again here and its
exit code, file names and the contents of its JSON, TOML and MJCF files must match
(numbers within 1e-3 relative: the 4 significant digits the baseline keeps). The slow
cases (CMA-ES, B-rep solids, the route search, the crawl) run with ``ORIGAMI_BASELINE_ALL=1``.
"""

from __future__ import annotations

import json
import math
import os
import re
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))
from commands_baseline import BASELINE, CASES, NOT_RECORDED, run_case

ALL = os.environ.get("ORIGAMI_BASELINE_ALL") == "1"
RECORDED = json.loads(BASELINE.read_text())
_NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:e-?\d+)?")


def _close(a: float, b: float) -> bool:
    return math.isclose(a, b, rel_tol=2e-3, abs_tol=1e-6)


def differences(old, new, where: str = "") -> list[str]:
    """Where two descriptions differ beyond float noise (empty: the same)."""
    if isinstance(old, dict) and isinstance(new, dict):
        out = [f"{where}/{k}: missing" for k in old.keys() - new.keys()]
        out += [f"{where}/{k}: new" for k in new.keys() - old.keys()]
        for k in old.keys() & new.keys():
            out += differences(old[k], new[k], f"{where}/{k}")
        return out
    if isinstance(old, list) and isinstance(new, list):
        if len(old) != len(new):
            return [f"{where}: {len(old)} items, now {len(new)}"]
        return [
            d
            for k, (a, b) in enumerate(zip(old, new, strict=False))
            for d in differences(a, b, f"{where}[{k}]")
        ]
    numbers = (int, float)
    if isinstance(old, numbers) and isinstance(new, numbers) and not isinstance(old, bool):
        return [] if _close(float(old), float(new)) else [f"{where}: {old} -> {new}"]
    if isinstance(old, str) and isinstance(new, str) and old != new:
        a, b = _NUMBER.split(old), _NUMBER.split(new)
        na, nb = _NUMBER.findall(old), _NUMBER.findall(new)
        same = a == b and len(na) == len(nb)
        if same and all(_close(float(x), float(y)) for x, y in zip(na, nb, strict=False)):
            return []
        lines = [(x, y) for x, y in zip(old.splitlines(), new.splitlines(), strict=False) if x != y]
        return [f"{where}: {lines[:1] or 'line count'}"]
    return [] if old == new else [f"{where}: {old!r} -> {new!r}"]


def test_the_comparison_sees_a_change():
    old = {"a.json": {"x": [1.0, 2.0], "s": "p = 0.5 after 3 turns"}}
    assert not differences(old, {"a.json": {"x": [1.0001, 2.0], "s": "p = 0.5001 after 3 turns"}})
    assert differences(old, {"a.json": {"x": [1.1, 2.0], "s": "p = 0.5 after 3 turns"}})
    assert differences(old, {"a.json": {"x": [1.0, 2.0], "s": "p = 0.5 after 4 turns"}})
    assert differences(old, {"a.json": {"x": [1.0], "s": "p = 0.5 after 3 turns"}})


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_command_writes_what_it_wrote(name, tmp_path):
    if not (CASES[name][1] or ALL):
        pytest.skip("slow: ORIGAMI_BASELINE_ALL=1 runs it")
    found = run_case(name, tmp_path / name)
    assert not differences(RECORDED[name], found, name)


def test_every_command_of_the_command_line_has_a_recorded_case():
    """A command added without a case would change its outputs unseen."""
    from origami_cad.commands import COMMANDS

    visible = {n for n, c in COMMANDS.items() if not getattr(c, "HIDDEN", False)}
    covered = {argv[0] for argv, _ in CASES.values()}
    assert visible - NOT_RECORDED <= covered, sorted(visible - NOT_RECORDED - covered)
    assert set(CASES) <= set(RECORDED), sorted(set(CASES) - set(RECORDED))
