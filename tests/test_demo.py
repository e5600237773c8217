"""The main job: `origami-cad demo` (what `make demo` runs, not `--quick`) runs every step and
writes one self-contained page. The slowest test of the suite (about 4 minutes on 2 cores):
the quick demo once hid a Fig. 8 failure that only the full one reaches."""

from __future__ import annotations

import html
import json
import re
from html.parser import HTMLParser
from pathlib import Path

from origami_cad.cli import main
from origami_cad.demo import STEPS


class Links(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.refs: list[str] = []

    def handle_starttag(self, tag, attrs):
        for key, value in attrs:
            if key in ("src", "href") and value and not value.startswith("#"):
                self.refs.append(value)


def test_full_demo_writes_a_report_whose_every_link_resolves(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["demo", "-o", str(out)]) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    for key in (s.key for s in STEPS):
        assert re.search(rf"\[{key}\] done in \d+\.\d s", printed)
    assert "total" in printed
    page = (out / "index.html").read_text()
    parser = Links()
    parser.feed(page)
    assert len(parser.refs) > 20
    for ref in parser.refs:
        assert "://" not in ref  # viewable offline
        assert (out / ref).is_file(), ref
    for step in STEPS:
        assert f"id='{step.key}'" in page
    assert "FAILED" not in printed and "This step failed" not in page
    # 3D views (fig. 2's folding, the printed parts) embedded, the page still small
    assert page.count("<figure class='oc-view'>") >= 2
    assert (out / "index.html").stat().st_size < 5_000_000
    check_against_before(out)


# What the demo wrote before its steps became chains of jobs, and the
# documented changes since: the boat's simulation is written by the simulate job
# (fold.gif as from the command, plus its states.fold) and its TSA module by the
# part job (named after the part).
BEFORE = json.loads((Path(__file__).parent / "data" / "demo_before.json").read_text())
RENAMED = {
    "fig6/folding.gif": "fig6/fold.gif",
    "fig6/tsa_module.step": "fig6/tsa-module.step",
    "fig6/tsa_module.stl": "fig6/tsa-module.stl",
}
# numbers that do not depend on timing, or on the string models,
# or on the arm's design (designed for the fold range its printed creases allow)
STABLE = {
    "fig2": ["shape angles beta_1..beta_4 (eq. 1)", "panels", "creases (M / V)", "pattern size"],
    # "runs x generations" was recorded from the quick demo (4 x 60); the full one runs the
    # task's 10 x 400, checked below
    # the 6 x 4 sheet became the paper's 120 x 120 mm (it was 130.9 x 120 mm), which
    # changed its volumes and mass
    "fig4": ["6 x 4 Miura: panels / holes", "6 x 4 Miura: theta_max, p_max (eq. 6)"],
    "fig6": ["boat: panels / holes", "boat: volumes", "boat: mass estimate"],
    # Fig. 7's servo logs play examples/crawler_gait.toml regenerated from the
    # model (was typed by hand: 15.69 turns at most; the model's string take-up: 3.83)
    "fig7": ["cycle / readings", "maximum commanded twist"],
}


def _numbers(page: str) -> dict[str, dict[str, str]]:
    found = {}
    for key, body in re.findall(r"<section id='(\w+)'>(.*?)</section>", page, re.S):
        rows = re.findall(r"<tr><td>(.*?)</td><td class='v'>(.*?)</td></tr>", body)
        found[key] = {html.unescape(k): html.unescape(v) for k, v in rows}
    return found


def check_against_before(out: Path) -> None:
    """The demo's files and key numbers are those it had before the job layer."""
    written = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    expected = {RENAMED.get(f, f) for f in BEFORE["files"]}
    assert expected <= written, sorted(expected - written)
    numbers = _numbers((out / "index.html").read_text())
    assert numbers["fig3"]["runs x generations"] == "10 x 400"
    for step, keys in STABLE.items():
        for key in keys:
            assert numbers[step][key] == BEFORE["numbers"][step][key], (step, key)
