"""Every command writes what it wrote before: its outputs described, and their bytes.

``tests/data/commands_baseline.json`` was recorded by ``tests/commands_baseline.py``
from ``origami_cad/jobs.py`` before the commands became a registry; each fast case runs
again here and its exit code, file names and the contents of its JSON, TOML and MJCF files
must match (numbers within 2e-3 relative: the 4 significant digits the baseline keeps; a
coordinate of a point, a list of 2 or 3 numbers, within 2e-3 of the point's largest
coordinate: a 0.05 mm coordinate of a 30 mm position is compared at the position's
accuracy, not its own). Where the environment is the recording's
(``tests/data/commands_bytes.json``: library versions, processor, Mesa), every file's
bytes must be the recorded ones too (timestamps, timings, versions and the output folder's
path left out). The slow cases (CMA-ES, B-rep solids, the route search, the crawl) are
marked slow: ``make slow`` runs them, or ``pytest -m slow tests/test_commands_baseline.py``
(about 30 s of CPU).

Re-recorded, and why:

* lines on stdout: the command line prints warnings on stderr, never stdout, and draws
  progress bars on stderr and only on a terminal (it left an empty line on stdout): route
  6 -> 2 (4 warnings), fabricate 4 -> 2 and robot 4 -> 2 (2 warnings each), plan-route
  5 -> 2 (2 warnings, the bar), design-arm 9 -> 8, simulate 4 -> 3 and design-gait 3 -> 2
  (the bar). The commands' files are unchanged.
* ``crawl``: ``body_mm[0]`` was 0.05185 mm, recorded under other library versions; the code
  of the commit that recorded it (and of its parent, and of every commit since) gives
  0.052613 mm here, also with ``NPY_DISABLE_CPU_FEATURES`` and one BLAS thread. It is the
  body's settling on the ground at t = 0, 0.0007 mm apart on a 29.4 mm height.
* ``plan-route``: ``route.toml`` is written by the route format's one writer
  (``dump_route``): exact numbers, every setting, the shell.
* ``completion`` and ``calibrate`` (PyGamiX's mountain, one bench run, the hole friction
  fitted): new, a case for every command.
"""

from __future__ import annotations

import json
import math
import re
import sys
import warnings
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))
from commands_baseline import BASELINE, BYTES, CASES, NOT_RECORDED, digests, environment, run_case

RECORDED = json.loads(BASELINE.read_text())
RECORDED_BYTES = json.loads(BYTES.read_text())
_NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:e-?\d+)?")


def _close(a: float, b: float, scale: float = 0.0) -> bool:
    """Equal within 2e-3 of ``a`` or of ``scale`` (the largest coordinate of ``a``'s point)."""
    return math.isclose(a, b, rel_tol=2e-3, abs_tol=max(1e-6, 2e-3 * scale))


def differences(old, new, where: str = "", scale: float = 0.0) -> list[str]:
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
        numbers = [abs(v) for v in old if isinstance(v, int | float) and not isinstance(v, bool)]
        point = len(old) in (2, 3) and len(numbers) == len(old)  # a position: one accuracy
        scale = max(numbers) if point else 0.0
        return [
            d
            for k, (a, b) in enumerate(zip(old, new, strict=False))
            for d in differences(a, b, f"{where}[{k}]", scale)
        ]
    numbers = (int, float)
    if isinstance(old, numbers) and isinstance(new, numbers) and not isinstance(old, bool):
        return [] if _close(float(old), float(new), scale) else [f"{where}: {old} -> {new}"]
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
    position = {"body_mm": [[0.0519, -0.0771, 29.36]]}  # a near-zero coordinate: its row's scale
    assert not differences(position, {"body_mm": [[0.0526, -0.0773, 29.36]]})
    assert differences(position, {"body_mm": [[0.2, -0.0773, 29.36]]})
    assert differences(position, {"body_mm": [[0.0519, -0.0771, 29.5]]})
    series = {"f": [0.05, 1.0, 2.0, 30.0]}  # not a point: each number at its own accuracy
    assert differences(series, {"f": [0.0526, 1.0, 2.0, 30.0]})


@pytest.mark.parametrize(
    "name", [n if CASES[n][1] else pytest.param(n, marks=pytest.mark.slow) for n in sorted(CASES)]
)
def test_a_command_writes_what_it_wrote(name, tmp_path):
    found = run_case(name, tmp_path / name)
    assert not differences(RECORDED[name], found, name)
    if RECORDED_BYTES["environment"] != environment():
        recorded_under = RECORDED_BYTES["environment"]
        warnings.warn(f"{name}: bytes recorded under {recorded_under}, not compared", stacklevel=1)
        return
    recorded = RECORDED_BYTES["cases"].get(name)
    if recorded is None:  # a slow case recorded before its bytes were
        pytest.skip(f"{name}: no bytes recorded yet: python tests/commands_baseline.py {name}")
    written = digests(tmp_path / name)
    changed = sorted(
        n for n in recorded.keys() | written.keys() if recorded.get(n) != written.get(n)
    )
    assert not changed, f"{name}: these files' bytes changed: {changed}"


def test_the_bytes_are_compared_file_by_file(tmp_path):
    """A changed number changes a file's digest; a timing or a path does not."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "a.json").write_text(json.dumps({"p": 0.5, "seconds": 1.0, "file": str(out / "x")}))
    (out / "b.step").write_text("FILE_NAME('b','2026-12-05T17:00:00',(''),(''),'','','');\nX")
    first = digests(out)
    (out / "a.json").write_text(json.dumps({"p": 0.5, "seconds": 9.0, "file": str(out / "x")}))
    (out / "b.step").write_text("FILE_NAME('b','2027-01-01T00:00:00',(''),(''),'','','');\nX")
    assert digests(out) == first  # the timing and the time stamp are left out
    (out / "a.json").write_text(json.dumps({"p": 0.5000001, "seconds": 9.0, "file": "x"}))
    assert digests(out)["a.json"] != first["a.json"] and digests(out)["b.step"] == first["b.step"]


def _step(occurrences: list[tuple[int, str]], colours: list[tuple[int, str]]) -> str:
    """A STEP text of assembly occurrences and of styled items, each with its colour."""
    lines = [f"#{k + 7} = NEXT_ASSEMBLY_USAGE_OCCURRENCE('{n}','{name}','',#5,#39,$);"
             for k, (n, name) in enumerate(occurrences)]  # fmt: skip
    for k, (target, rgb) in enumerate(colours):
        style, colour = 100 + 2 * k, 101 + 2 * k
        lines += [f"#{style} = STYLED_ITEM('color',(#{colour}),#{target});",
                  f"#{colour} = COLOUR_RGB('',{rgb});"]  # fmt: skip
    return "\n".join(lines) + "\n"


def test_what_varies_between_two_exports_is_left_out_and_the_rest_kept(tmp_path):
    """STEP occurrences numbered on from an earlier export, lines wrapped by that number's
    width, the styles in another order, and what emulated servos measured in real time,
    change no digest; another colour, another order of parts, another command do."""
    out = tmp_path / "out"
    out.mkdir()
    log = "t_s,id,target_turns,measured_turns,current_mA\n0.1,1,{},{},{}\n"
    parts, colours = [(1, "servo"), (2, "hub")], [(7, "0.5,0.5,0.5"), (8, "1.,0.,0.")]
    (out / "a.step").write_text(_step(parts, colours))
    (out / "log.csv").write_text(log.format(0.5, 0.4, 60))
    first = digests(out)
    later = _step([(15, "servo"), (16, "hub")], colours[::-1]).replace(",#5,", ",#5,\n  ")
    (out / "a.step").write_text(later)
    (out / "log.csv").write_text(log.format(0.5, 0.3, 70))
    assert digests(out) == first
    for changed in (
        _step(parts[::-1], colours),
        _step(parts, [(7, "0.5,0.5,0.5"), (8, "0.,0.,1.")]),
    ):
        (out / "a.step").write_text(changed)
        assert digests(out)["a.step"] != first["a.step"]
    (out / "log.csv").write_text(log.format(0.6, 0.4, 60))
    assert digests(out)["log.csv"] != first["log.csv"]


def test_every_command_of_the_command_line_has_a_recorded_case():
    """A command added without a case would change its outputs unseen."""
    from origami_cad.commands import COMMANDS

    visible = {n for n, c in COMMANDS.items() if not getattr(c, "HIDDEN", False)}
    covered = {argv[0] for argv, _ in CASES.values()}
    assert visible - NOT_RECORDED <= covered, sorted(visible - NOT_RECORDED - covered)
    assert set(CASES) <= set(RECORDED), sorted(set(CASES) - set(RECORDED))
