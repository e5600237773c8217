"""docs/patterns.md shows the corpus: every pattern of tests/data with its tool, licence and
each stage's result, in the table ``tests/corpus.py --docs`` writes (``make corpus``)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "patterns.md"
_spec = importlib.util.spec_from_file_location("corpus_script", ROOT / "tests" / "corpus.py")
corpus = importlib.util.module_from_spec(_spec)
sys.modules.setdefault("corpus_script", corpus)  # dataclasses look their module up
_spec.loader.exec_module(corpus)


def _table_lines(text: str) -> list[str]:
    block = text.split(corpus.DOCS_BEGIN, 1)[1].split(corpus.DOCS_END, 1)[0]
    return [ln for ln in block.splitlines() if ln.startswith("| `")]


def test_every_corpus_pattern_is_in_the_page_with_its_tool_and_licence():
    entries = corpus.load_manifest()
    assert len(entries) >= 30
    lines = _table_lines(PAGE.read_text(encoding="utf-8"))
    assert len(lines) == len(entries)
    for entry, line in zip(entries, lines, strict=True):
        cells = [c.strip() for c in line.strip("|").split("|")]
        assert cells[0] == f"`{entry['file']}`"
        assert cells[1] == corpus.tool_of(entry) and cells[1] != entry.get("source")
        assert cells[2] == corpus.licence_of(entry) == "MIT"
        assert cells[3] == entry.get("kind", "")
        assert len(cells) == 4 + len(corpus.STAGES)
    tools = {corpus.tool_of(e) for e in entries}
    assert {"Origami Simulator", "FOLD's examples"} <= tools


def test_a_run_rewrites_its_rows_and_keeps_the_rest(tmp_path):
    page = tmp_path / "patterns.md"
    before = PAGE.read_text(encoding="utf-8")
    page.write_text(before, encoding="utf-8")
    entries = corpus.load_manifest()
    first = entries[0]["file"]
    row = corpus.Row(first, entries[0]["kind"])
    row.stages = [corpus.Stage(s, s != "simulate", 0 if s != "simulate" else 2, 1.0)
                  for s in corpus.STAGES]  # fmt: skip
    row.stages[-1].message = "simulate: a refusal | with a bar"
    corpus.update_docs(page, [row], entries)
    after = page.read_text(encoding="utf-8")
    old, new = _table_lines(before), _table_lines(after)
    assert new[1:] == old[1:]  # the patterns not run keep their results
    assert new[0].endswith("| pass | pass | pass | pass | no (simulate: a refusal / with a bar) |")
    outside = before.split(corpus.DOCS_BEGIN)[0], before.split(corpus.DOCS_END)[1]
    assert after.split(corpus.DOCS_BEGIN)[0] == outside[0]
    assert after.split(corpus.DOCS_END)[1] == outside[1]
    assert "1 patterns run then" in after
    total = next(ln for ln in after.splitlines() if ln.startswith("| **"))
    counts = [c.strip() for c in total.strip("|").split("|")][4:]
    for k in range(len(corpus.STAGES)):
        passed = sum(ln.strip("|").split("|")[4 + k].strip().startswith("pass") for ln in new)
        assert counts[k] == f"**{passed} of {len(entries)}**"


def test_a_page_without_the_table_is_refused(tmp_path):
    page = tmp_path / "other.md"
    page.write_text("# no table\n", encoding="utf-8")
    with pytest.raises(SystemExit, match="no corpus table"):
        corpus.update_docs(page, [])
    assert page.read_text(encoding="utf-8") == "# no table\n"
