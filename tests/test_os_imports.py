"""Origami Simulator's other example files: how their drawings are read.

Black outlines inside the sheet enclosing nothing but a hole are holes (its
``removeBorderFaces``); a sheet whose outline is drawn as creases has that outline as
border; vertices chain within the tolerance, but a finely cut curve does not chain into
a blob; a crease ending just short of a line reaches it.
"""

from __future__ import annotations

import numpy as np

from origami_cad.pattern.formats.svg import read_svg
from origami_cad.pattern.model import CreasePattern
from origami_cad.pattern.outline import outline_creases_as_border
from origami_cad.pattern.planar import CHAIN_REACH, merge_close


def _sheet_with_diamond(diamond: str) -> CreasePattern:
    """A 100 mm square with a valley up x = 50, broken by a 20 mm diamond around
    (50, 50) drawn in ``diamond``'s letter."""
    verts = [[0, 0], [50, 0], [100, 0], [100, 100], [50, 100], [0, 100]]
    verts += [[50, 40], [60, 50], [50, 60], [40, 50]]
    edges = [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 0], [1, 6], [8, 4]]
    edges += [[6, 7], [7, 8], [8, 9], [9, 6]]
    return CreasePattern(verts, edges, ["B"] * 6 + ["V", "V"] + [diamond] * 4)


def test_a_black_outline_inside_the_sheet_is_a_hole():
    holed = _sheet_with_diamond("B")
    assert len(holed.faces) == 2
    np.testing.assert_allclose(sorted(holed.face_areas()), [4900.0, 4900.0])
    # drawn as facet lines, the diamond is a panel
    assert len(_sheet_with_diamond("F").faces) == 3


def test_black_lines_across_the_sheet_leave_its_panels():
    verts = [[0, 0], [50, 0], [100, 0], [100, 100], [50, 100], [0, 100]]
    edges = [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 0], [1, 4]]
    cp = CreasePattern(verts, edges, ["B"] * 7)
    np.testing.assert_allclose(sorted(cp.face_areas()), [5000.0, 5000.0])


def test_merging_does_not_chain_a_finely_cut_curve_into_a_blob():
    line = np.column_stack([np.arange(20) * 0.4, np.zeros(20)])  # mm, a finely cut curve
    rep = merge_close(line, 1.0)
    gaps = np.linalg.norm(line - line[rep], axis=1)
    assert gaps.max() <= 1.0  # split: each vertex within the tolerance of its own
    assert len(np.unique(rep)) > 1
    # a short chain, within CHAIN_REACH tolerances of its first vertex, still merges
    short = np.array([[0.0, 0.0], [0.8, 0.0], [1.6, 0.0]])
    assert 1.6 <= CHAIN_REACH * 1.0
    assert merge_close(short, 1.0).tolist() == [0, 0, 0]
    # a cluster within the tolerance of its first vertex still merges into it
    blob = np.array([[0.0, 0.0], [0.5, 0.0], [0.0, 0.6], [10.0, 0.0]])
    assert merge_close(blob, 1.0).tolist() == [0, 0, 0, 3]


def test_creases_drawn_as_the_outline_are_its_border(tmp_path):
    svg = tmp_path / "outline.svg"
    svg.write_text(
        '<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" '
        'viewBox="0 0 100 100">'
        '<polygon points="0,0 100,0 100,100 0,100" fill="none" stroke="#ff0000"/>'
        '<line x1="0" y1="0" x2="100" y2="100" stroke="#0000ff"/></svg>'
    )
    cp = read_svg(svg)
    assert sorted(cp.assignments.tolist()) == ["B", "B", "B", "B", "V"]
    assert np.all(cp.fold_angles[cp.assignments == "B"] == 0)
    assert any(n.code == "outline-creases" for n in cp.notes)
    assert outline_creases_as_border(cp) is cp  # nothing left to change


def test_black_lines_inside_the_sheet_are_not_its_outline_crossing():
    # a 100 mm square with black lines across it both ways: they meet the outline and
    # each other, with a panel on both sides; the outline is closed and simple
    verts = [[0, 0], [50, 0], [100, 0], [100, 50], [100, 100], [50, 100], [0, 100], [0, 50]]
    verts += [[50, 50]]
    outline = [[i, (i + 1) % 8] for i in range(8)]
    cp = CreasePattern(verts, [*outline, [1, 8], [8, 5], [7, 8], [8, 3]], ["B"] * 12)
    codes = {p.code for p in cp.check()}
    assert "border-crossing" not in codes and "open-border" not in codes
    # a figure-eight outline still crosses itself
    bowtie = CreasePattern(
        [[0, 0], [100, 100], [100, 0], [0, 100]], [[0, 1], [1, 2], [2, 3], [3, 0]], "B"
    )
    assert "border-crossing" in {p.code for p in bowtie.check()}


def test_a_crease_ending_just_short_of_a_line_reaches_it():
    # a valley up x = 50 that stops 0.3 mm under the top edge of a 100 mm square, read
    # at a 0.2 mm tolerance: its end is put on the border, so no crease dangles
    verts = [[0, 0], [50, 0], [100, 0], [100, 100], [0, 100], [50, 99.7]]
    edges = [[0, 1], [1, 2], [2, 3], [3, 4], [4, 0], [1, 5]]
    cp = CreasePattern(verts, edges, ["B"] * 5 + ["V"], tolerance=0.2)
    assert "dangling-crease" not in {p.code for p in cp.check()}
    assert len(cp.faces) == 2 and cp.cleanup.reached == 1
    np.testing.assert_allclose(cp.cleanup.reached_gap, 0.3)
    # 2 mm short, it is a crease that ends inside the sheet
    verts[5] = [50, 98]
    far = CreasePattern(verts, edges, ["B"] * 5 + ["V"], tolerance=0.2)
    assert "dangling-crease" in {p.code for p in far.check()} and far.cleanup.reached == 0
