"""The main job: `origami-cad demo --quick` runs every step and writes one self-contained page."""

from __future__ import annotations

import re
from html.parser import HTMLParser

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


def test_quick_demo_writes_a_report_whose_every_link_resolves(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["demo", "-o", str(out), "--quick"]) == 0
    printed = capsys.readouterr().out
    for key, _ in STEPS:
        assert re.search(rf"\[{key}\] done in \d+\.\d s", printed)
    assert "total" in printed
    page = (out / "index.html").read_text()
    parser = Links()
    parser.feed(page)
    assert len(parser.refs) > 20
    for ref in parser.refs:
        assert "://" not in ref  # viewable offline
        assert (out / ref).is_file(), ref
    for key, _ in STEPS:
        assert f"id='{key}'" in page
    assert "FAILED" not in printed and "This step failed" not in page
