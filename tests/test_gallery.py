"""The report's gallery: six patterns of three other tools, each folded at two ratios
beside its crease pattern (the demo's ``gallery`` step, run directly, and its page)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from imageio.v3 import imread

from origami_cad.demo import GALLERY, GALLERY_RATIOS, STEPS, examples_dir, run_step
from origami_cad.viz.report import write_report

DATA = Path(__file__).resolve().parent / "data"
#: where each gallery folder's files are kept in the test corpus
CORPUS = {
    "origami_simulator": DATA / "origami-simulator",
    "fold": DATA / "fold",
    "pygamix": DATA / "pygamix" / "packedImport",
}


def test_the_gallery_files_are_the_corpus_files_with_their_licences():
    tools = {tool for _, tool, _ in GALLERY}
    assert len(GALLERY) == 6 and len(tools) == 3
    for name, _, _ in GALLERY:
        folder, file = name.split("/")
        copy = examples_dir() / "gallery" / name
        assert copy.read_bytes() == (CORPUS[folder] / file).read_bytes(), name
        licence = (copy.parent / "LICENSE").read_text()
        assert licence.startswith("MIT License"), name
        assert file in (examples_dir() / "gallery" / "README.md").read_text()


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    root = tmp_path_factory.mktemp("demo")
    step = next(s for s in STEPS if s.key == "gallery")
    rep = run_step(step, root)
    return root, rep, write_report(root / "index.html", [rep])


def test_each_pattern_is_drawn_then_folded_at_two_ratios(report):
    root, rep, _ = report
    assert rep.error == ""
    per = 1 + len(GALLERY_RATIOS)
    assert len(rep.images) == per * len(GALLERY)
    for k, (name, tool, title) in enumerate(GALLERY):
        row = rep.images[per * k : per * (k + 1)]
        assert row[0][1] == f"{title} ({tool}): crease pattern"
        pictures = []
        for (path, caption), p in zip(row[1:], GALLERY_RATIOS, strict=True):
            assert caption.startswith(f"{title} folded to p = {p:g} (")
            assert re.search(r"\((closed form|general), largest strain [\d.e+-]+ %\)", caption)
            pictures.append(imread(root / path)[..., :3])
        # the two ratios fold differently: the pictures differ
        assert pictures[0].shape != pictures[1].shape or np.mean(pictures[0] != pictures[1]) > 0.01
        ink = np.mean(np.any(pictures[1] < 230, axis=2))
        assert 0.01 < ink < 0.9, name
    assert len(rep.numbers) == len(GALLERY)


def test_the_page_lays_the_gallery_out_three_to_a_row(report):
    _, rep, page = report
    text = page.read_text()
    section = text[text.index("<section id='gallery'>") :]
    section = section[: section.index("</section>")]
    assert "grid-template-columns:repeat(3,1fr)" in section
    images = re.findall(r"<img src='([^']+)'", section)
    assert images == [p for p, _ in rep.images]
    for _, tool, title in GALLERY:
        assert f"{title} ({tool}): crease pattern" in section.replace("&#x27;", "'")
