"""The public corpus is what its manifest says: every file unchanged from its source, licensed."""

from __future__ import annotations

import hashlib
import tomllib
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"
ENTRIES = tomllib.loads((DATA / "corpus.toml").read_text())["pattern"]


def test_corpus_is_large_enough_and_from_several_tools():
    assert len(ENTRIES) >= 30
    assert {e["source"] for e in ENTRIES} >= {"amandaghassaei/OrigamiSimulator", "edemaine/fold"}


@pytest.mark.parametrize("entry", ENTRIES, ids=[e["file"] for e in ENTRIES])
def test_corpus_file_matches_its_source_record(entry):
    path = DATA / entry["file"]
    data = path.read_bytes()
    assert len(data) == entry["bytes"]
    assert hashlib.sha256(data).hexdigest() == entry["sha256"]
    licence = (path.parent / "LICENSE").read_text()
    assert "MIT License" in licence and "Permission is hereby granted" in licence
