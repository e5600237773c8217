"""Small DXF files that used to exhaust time or memory, and more.

Every drawing is made here with ezdxf. Block references and MINSERT grids are
counted from the block definitions before anything is expanded; curves are
flattened with a chord tolerance relative to the drawing's size; coordinates
are bounded.
"""

from __future__ import annotations

import ezdxf
import numpy as np
import pytest
from conftest import refused as refused_by

from origami_cad.errors import PatternError
from origami_cad.pattern import miura_pattern, read_pattern, write_pattern
from origami_cad.pattern.formats.dxf import MAX_ENTITIES, read_dxf


def new_doc(units=4):
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = units
    return doc, doc.modelspace()


def refused(path, *fragments):
    return refused_by(read_dxf, path, *fragments, error=PatternError)


def test_a_3000_by_3000_minsert_is_refused_before_expanding(tmp_path):
    doc, msp = new_doc()
    cell = doc.blocks.new("CELL")
    cell.add_line((0, 0), (1, 0), dxfattribs={"layer": "Valley"})
    msp.add_blockref("CELL", (0, 0)).grid(size=(3000, 3000), spacing=(2, 2))
    doc.saveas(tmp_path / "minsert.dxf")
    assert (tmp_path / "minsert.dxf").stat().st_size < 40_000
    refused(tmp_path / "minsert.dxf", f"more than {MAX_ENTITIES:,} entities", "9,000,000-cell")


def test_seven_levels_of_ten_nested_blocks_are_refused(tmp_path):
    doc, msp = new_doc()
    doc.blocks.new("B0").add_line((0, 0), (1, 0), dxfattribs={"layer": "Mountain"})
    for k in range(1, 8):
        blk = doc.blocks.new(f"B{k}")
        for j in range(10):
            blk.add_blockref(f"B{k - 1}", (j * 3.0**k, 0))
    msp.add_blockref("B7", (0, 0))
    doc.saveas(tmp_path / "nested.dxf")
    refused(tmp_path / "nested.dxf", "through its block references")


def test_a_minsert_with_zero_spacing_and_huge_counts_is_one_insert(tmp_path):
    # ezdxf's multi_insert() would loop over every (duplicate) cell
    doc, msp = new_doc()
    for x0, y0, x1, y1 in [(0, 0, 10, 0), (10, 0, 10, 10), (10, 10, 0, 10), (0, 10, 0, 0)]:
        msp.add_line((x0, y0), (x1, y1), dxfattribs={"layer": "Border"})
    cell = doc.blocks.new("DIAG")
    cell.add_line((0, 0), (10, 10), dxfattribs={"layer": "Valley"})
    ref = msp.add_blockref("DIAG", (0, 0))
    ref.dxf.row_count, ref.dxf.column_count = 30_000, 30_000
    ref.dxf.row_spacing, ref.dxf.column_spacing = 0.0, 0.0
    doc.saveas(tmp_path / "zero.dxf")
    cp = read_dxf(tmp_path / "zero.dxf")  # 900 million duplicate cells: one insert
    assert int((cp.assignments == "V").sum()) == 1 and len(cp.faces) == 2


def test_a_block_that_contains_itself_is_refused(tmp_path):
    doc, msp = new_doc()
    loop = doc.blocks.new("LOOP")
    loop.add_line((0, 0), (1, 0), dxfattribs={"layer": "Valley"})
    loop.add_blockref("LOOP", (1, 1))
    msp.add_blockref("LOOP", (0, 0))
    doc.saveas(tmp_path / "loop.dxf")
    refused(tmp_path / "loop.dxf", "nested deeper than")


def test_a_circle_of_ten_thousand_km_is_refused_not_flattened(tmp_path):
    doc, msp = new_doc(units=6)  # metres
    msp.add_circle((0, 0), 1e7, dxfattribs={"layer": "Border"})
    msp.add_line((-10, 0), (10, 0), dxfattribs={"layer": "Valley"})
    doc.saveas(tmp_path / "planet.dxf")
    refused(tmp_path / "planet.dxf", "handle", "farther than 1e+09 mm")


@pytest.mark.parametrize("radius_m", [0.05, 1.0, 100.0, 100_000.0])
def test_curves_flatten_into_a_bounded_number_of_chords(tmp_path, radius_m):
    doc, msp = new_doc(units=6)
    msp.add_circle((0, 0), radius_m, dxfattribs={"layer": "Border"})
    msp.add_line((-radius_m, 0), (radius_m, 0), dxfattribs={"layer": "Valley"})
    doc.saveas(tmp_path / "disc.dxf")
    cp = read_dxf(tmp_path / "disc.dxf")
    r = radius_m * 1000
    tol = max(0.01, 1e-6 * 2 * r * np.sqrt(2))  # the chord tolerance, mm
    on_circle = np.hypot(*cp.vertices.T)
    # every vertex on the circle or within the chord tolerance inside it (where the
    # diameter meets a chord); chords within the tolerance of the arc, so at most a
    # few thousand of them whatever the size (a 100 km disc used to need millions)
    assert np.all(on_circle <= r * (1 + 1e-12)) and np.all(on_circle >= r - 1.01 * tol)
    n_chords = cp.n_vertices
    assert r * (1 - np.cos(np.pi / n_chords)) <= tol * 1.01
    assert cp.n_vertices < 3000
    assert len(cp.faces) == 2


def test_lines_beyond_the_coordinate_limit_are_refused(tmp_path):
    doc, msp = new_doc()
    msp.add_line((0, 0), (1e300, 0), dxfattribs={"layer": "Border"})
    doc.saveas(tmp_path / "far.dxf")
    refused(tmp_path / "far.dxf", "farther than")


def test_a_block_scaled_past_the_limit_is_refused(tmp_path):
    doc, msp = new_doc()
    doc.blocks.new("S").add_line((0, 0), (1, 1), dxfattribs={"layer": "Valley"})
    msp.add_blockref("S", (0, 0), dxfattribs={"xscale": 1e200, "yscale": 1e200})
    doc.saveas(tmp_path / "scaled.dxf")
    refused(tmp_path / "scaled.dxf", "farther than")


def test_layer_names_with_control_characters_stay_on_one_line(tmp_path):
    doc, msp = new_doc()
    msp.add_line((0, 0), (1, 1), dxfattribs={"layer": "odd\tlayer", "color": 2})
    doc.saveas(tmp_path / "odd.dxf")
    msg = refused(tmp_path / "odd.dxf", "cannot be classified")
    assert "\t" not in msg


@pytest.mark.parametrize(
    "title", ["two\nlines\n0\nLINE\n8\nValley", "</title><script>", "lone \ud800 surrogate"]
)
def test_a_title_cannot_inject_dxf_groups(tmp_path, title):
    cp = miura_pattern(2, 2, 20.0, 30.0, 60.0).with_metadata(title=title)
    path = write_pattern(cp, tmp_path / "t.dxf")
    back = read_pattern(path)  # the file we wrote is a readable DXF ...
    assert back.same_graph(cp)  # ... with no injected entity
    assert "\n" not in ezdxf.readfile(path).header["$PROJECTNAME"]
