"""DXF reader and writer: round trips, other tools' conventions, blocks, units, bad input.

Every test writes a real DXF file with ezdxf into ``tmp_path`` and reads it back.
"""

from __future__ import annotations

import math

import ezdxf
import numpy as np
import pytest

from origami_cad.pattern import (
    CreasePattern,
    Hole,
    PatternError,
    miura_pattern,
    read_pattern,
    write_pattern,
)
from origami_cad.pattern.formats.dxf import read_dxf, write_dxf

SQUARE = [(0, 0), (100, 0), (100, 100), (0, 100)]


def new_doc(units: int = 4):
    doc = ezdxf.new("R2010", setup=True)
    doc.header["$INSUNITS"] = units
    return doc, doc.modelspace()


def add_square(msp, layer: str = "Border", size: float = 100.0, **attribs) -> None:
    pts = [(x * size / 100, y * size / 100) for x, y in SQUARE]
    for a, b in zip(pts, pts[1:] + pts[:1], strict=True):
        msp.add_line(a, b, dxfattribs={"layer": layer, **attribs})


def letters_by_midpoint(cp: CreasePattern) -> dict[tuple[float, float], str]:
    mid = cp.vertices[cp.edges].mean(axis=1)
    return {
        (round(float(x), 6) + 0.0, round(float(y), 6) + 0.0): str(a)
        for (x, y), a in zip(mid, cp.assignments, strict=True)
    }


# ------------------------------------------------------------------ writing
def test_miura_round_trip_and_file_contents(tmp_path):
    cp = miura_pattern(4, 6, 20.0, 30.0, 60.0)
    path = write_dxf(cp, tmp_path / "miura.dxf")
    assert path == tmp_path / "miura.dxf"
    back = read_dxf(path)
    assert back.same_graph(cp, tolerance=1e-9)
    assert back.title == "miura"
    via_io = read_pattern(write_pattern(cp, tmp_path / "io.dxf"))
    assert via_io.same_graph(cp, tolerance=1e-9)
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []  # atomic

    doc = ezdxf.readfile(path)
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1
    layers = {layer.dxf.name: layer.dxf for layer in doc.layers}
    expected = {
        "Mountain": (1, "CONTINUOUS"),
        "Valley": (5, "DASHED"),
        "Cut": (3, "CONTINUOUS"),
        "Border": (7, "CONTINUOUS"),
        "Flat": (8, "CONTINUOUS"),
        "Unassigned": (9, "CONTINUOUS"),
        "Holes": (4, "Continuous"),
    }
    for name, (color, linetype) in expected.items():
        assert (layers[name].color, layers[name].linetype.upper()) == (color, linetype.upper())
    assert "DASHED" in doc.linetypes
    lines = doc.modelspace().query("LINE")
    assert len(lines) == cp.n_edges == len(doc.modelspace())
    # each line's own ACI colour (ORIPA reads no layers); the outline in the cut colour
    assert {(e.dxf.layer, e.dxf.color) for e in lines} == {
        ("Mountain", 1),
        ("Valley", 5),
        ("Border", 3),
    }
    per_layer = {name: len(lines.query(f'*[layer=="{name}"]')) for name in expected}
    assert per_layer["Mountain"] == int((cp.assignments == "M").sum())
    assert per_layer["Valley"] == int((cp.assignments == "V").sum())
    assert per_layer["Border"] == int((cp.assignments == "B").sum())


def test_every_assignment_round_trips(tmp_path):
    verts = [*SQUARE, (50, 50), (50, 0), (50, 100), (0, 50), (100, 50), (70, 60), (80, 62)]
    edges = [[0, 1], [1, 2], [2, 3], [3, 0], [0, 4], [4, 2], [1, 4], [4, 3]]
    edges += [[5, 4], [4, 6], [7, 4], [9, 10]]
    cp = CreasePattern(verts, edges, "BBBBMMVVFJUC", metadata={"title": "all"})
    back = read_dxf(write_dxf(cp, tmp_path / "all.dxf"))
    assert back.same_graph(cp, tolerance=1e-9)
    assert ezdxf.readfile(tmp_path / "all.dxf").header["$PROJECTNAME"] == "all"


def test_holes_round_trip(tmp_path):
    cp = miura_pattern(2, 2, 20.0, 30.0, 60.0)
    x0, y0, x1, y1 = cp.bounds
    holes = [Hole((x0 + x1) / 2 + 3.0, (y0 + y1) / 2 + 4.0, 2.0), Hole(x0 + 5.0, y0 + 5.0, 1.5)]
    back = read_dxf(write_dxf(cp.with_holes(holes), tmp_path / "holes.dxf"))
    assert back.same_graph(cp, tolerance=1e-9)
    assert sorted(back.holes, key=lambda h: h.x) == sorted(holes, key=lambda h: h.x)  # exact
    circles = ezdxf.readfile(tmp_path / "holes.dxf").modelspace().query("CIRCLE")
    assert {c.dxf.layer for c in circles} == {"Holes"}


# -------------------------------------------------- other tools' conventions
def test_oripa_outline_drawn_as_cut_lines_becomes_border(tmp_path):
    doc, msp = new_doc()
    for name, color in (("CutLine", 3), ("MountainLine", 1), ("ValleyLine", 5)):
        doc.layers.add(name, color=color)
    add_square(msp, "CutLine")
    msp.add_line((0, 0), (100, 100), dxfattribs={"layer": "ValleyLine"})
    msp.add_line((0, 100), (40, 60), dxfattribs={"layer": "MountainLine"})
    msp.add_line((60, 20), (80, 40), dxfattribs={"layer": "CutLine"})  # a slit inside
    doc.saveas(tmp_path / "oripa.dxf")
    cp = read_dxf(tmp_path / "oripa.dxf")
    letters = letters_by_midpoint(cp)
    assert [letters[m] for m in [(50, 0), (100, 50), (50, 100), (0, 50)]] == ["B"] * 4
    assert (letters[(50, 50)], letters[(20, 80)]) == ("V", "M")
    assert letters[(70, 30)] == "C"
    slit = cp.edges[cp.assignments == "C"][0]
    assert sorted(cp.vertices[slit].tolist()) == [[60.0, 20.0], [80.0, 40.0]]
    assert any(n.code == "outline-cuts" for n in cp.notes)


def test_cut_window_inside_a_border_stays_cut(tmp_path):
    doc, msp = new_doc()
    add_square(msp, "Border")
    msp.add_lwpolyline(
        [(40, 40), (60, 40), (60, 60), (40, 60)], close=True, dxfattribs={"layer": "Cut"}
    )
    doc.saveas(tmp_path / "window.dxf")
    cp = read_dxf(tmp_path / "window.dxf")
    assert sorted(cp.assignments.tolist()) == ["B"] * 4 + ["C"] * 4


def test_colour_only_file(tmp_path):
    doc, msp = new_doc()
    add_square(msp, "0", color=7)
    msp.add_line((0, 0), (100, 100), dxfattribs={"color": 1})
    msp.add_line((0, 100), (50, 50), dxfattribs={"color": 5})
    red = msp.add_line((50, 50), (100, 0))
    red.rgb = (230, 20, 10)
    doc.saveas(tmp_path / "colours.dxf")
    letters = letters_by_midpoint(read_dxf(tmp_path / "colours.dxf"))
    assert letters[(25, 25)] == letters[(75, 75)] == "M"  # ACI 1 (split at the centre)
    assert letters[(25, 75)] == "V"  # ACI 5
    assert letters[(50, 0)] == "B"  # ACI 7
    assert letters[(75, 25)] == "M"  # true-colour red


def test_linetype_only_file(tmp_path):
    """Linetype counts only when layer name and colour say nothing (layer colour 2)."""
    doc, msp = new_doc()
    add_square(msp)
    doc.layers.add("creases", color=2)
    msp.add_line((0, 0), (100, 100), dxfattribs={"layer": "creases", "linetype": "DASHED"})
    doc.saveas(tmp_path / "dashed.dxf")
    letters = letters_by_midpoint(read_dxf(tmp_path / "dashed.dxf"))
    assert letters[(50, 50)] == "V"


@pytest.mark.parametrize(
    ("layer", "layer_color", "attribs", "rgb", "expected"),
    [
        ("Mountain", 5, {}, None, "M"),  # layer name beats colour
        ("VALLEY_folds", 1, {}, None, "V"),
        ("Cutting", 7, {}, None, "C"),  # PyGamic
        ("boundary", 1, {}, None, "B"),
        ("AuxLine", 1, {}, None, "F"),  # ORIPA
        ("creases", 5, {}, None, "V"),  # layer colour
        ("creases", 2, {"color": 25}, None, "M"),  # ACI 10-39
        ("creases", 2, {"color": 150}, None, "V"),  # ACI 140-199
        ("creases", 2, {"color": 90}, None, "C"),  # ACI 60-129
        ("creases", 2, {"color": 252}, None, "B"),  # grey
        ("creases", 2, {}, (0, 40, 200), "V"),
        ("creases", 2, {}, (10, 180, 20), "C"),
        ("creases", 2, {}, (128, 128, 128), "B"),
        ("creases", 1, {"linetype": "DASHED"}, None, "M"),  # colour beats linetype
        ("creases", 2, {"linetype": "DASHEDX2"}, None, "V"),
        ("hidden", 2, {"linetype": "HIDDEN"}, None, "V"),
    ],
)
def test_classification_rules(tmp_path, layer, layer_color, attribs, rgb, expected):
    doc, msp = new_doc()
    if "HIDDEN" not in doc.linetypes:
        doc.linetypes.add("HIDDEN", pattern=[0.375, 0.25, -0.125])
    add_square(msp)
    doc.layers.add(layer, color=layer_color)
    line = msp.add_line((0, 0), (100, 100), dxfattribs={"layer": layer, **attribs})
    if rgb is not None:
        line.rgb = rgb
    doc.saveas(tmp_path / "one.dxf")
    assert letters_by_midpoint(read_dxf(tmp_path / "one.dxf"))[(50, 50)] == expected


# ---------------------------------------------------------------- entities
def test_lwpolyline_border_and_polyline_crease(tmp_path):
    doc, msp = new_doc()
    msp.add_lwpolyline(SQUARE, close=True, dxfattribs={"layer": "Border"})
    msp.add_polyline2d([(0, 50), (50, 60), (100, 50)], dxfattribs={"layer": "Mountain"})
    msp.add_polyline3d([(0, 0, 5), (30, 30, 7)], dxfattribs={"layer": "Valley"})  # z ignored
    doc.saveas(tmp_path / "poly.dxf")
    cp = read_dxf(tmp_path / "poly.dxf")
    letters = letters_by_midpoint(cp)
    assert [letters[m] for m in [(50, 0), (100, 25), (100, 75), (50, 100), (0, 25)]] == ["B"] * 5
    assert letters[(25, 55)] == letters[(75, 55)] == "M"
    assert letters[(15, 15)] == "V"
    assert cp.bounds == (0, 0, 100, 100)


def test_block_references_are_transformed(tmp_path):
    doc, msp = new_doc()
    add_square(msp)
    crease = doc.blocks.new("CREASE")
    crease.add_line((0, 0), (0, 20), dxfattribs={"layer": "Mountain"})
    crease.add_line((0, 20), (0, 30))  # layer "0": takes the INSERT's layer
    msp.add_blockref("CREASE", (10, 10))
    msp.add_blockref("CREASE", (90, 50), dxfattribs={"rotation": 90, "layer": "Valley"})
    pair = doc.blocks.new("PAIR")  # nested: a block holding references
    pair.add_blockref("CREASE", (0, 0), dxfattribs={"color": 1})
    pair.add_blockref("CREASE", (10, 0), dxfattribs={"xscale": 0.5, "yscale": 0.5})
    msp.add_blockref("PAIR", (40, 60), dxfattribs={"layer": "Cut"})
    doc.saveas(tmp_path / "blocks.dxf")
    letters = letters_by_midpoint(read_dxf(tmp_path / "blocks.dxf"))
    assert letters[(10, 20)] == "M"  # first copy at (10, 10)
    assert letters[(10, 35)] == "B"  # layer 0 on layer 0: layer colour 7
    assert letters[(80, 50)] == "M"  # second copy, rotated 90 degrees about (90, 50)
    assert letters[(65, 50)] == "V"  # layer 0 entity in the Valley reference
    assert letters[(40, 70)] == "M"
    assert letters[(40, 85)] == "C"  # nested: layer 0 -> PAIR's layer Cut (colour is ACI 1)
    assert letters[(50, 65)] == "M"  # nested and scaled by 0.5
    assert letters[(50, 72.5)] == "C"


def test_byblock_colour_follows_the_reference(tmp_path):
    doc, msp = new_doc()
    add_square(msp)
    block = doc.blocks.new("B")
    block.add_line((0, 0), (50, 50), dxfattribs={"layer": "creases", "color": 0})  # BYBLOCK
    doc.layers.add("creases", color=2)
    msp.add_blockref("B", (0, 0), dxfattribs={"color": 5})
    msp.add_blockref("B", (50, 50), dxfattribs={"color": 1})
    doc.saveas(tmp_path / "byblock.dxf")
    letters = letters_by_midpoint(read_dxf(tmp_path / "byblock.dxf"))
    assert (letters[(25, 25)], letters[(75, 75)]) == ("V", "M")


def test_arc_on_border_is_flattened(tmp_path):
    doc, msp = new_doc()
    msp.add_lwpolyline([(100, 0), (100, 100), (0, 100), (0, 0)], dxfattribs={"layer": "Border"})
    msp.add_arc((50, 0), 50, 180, 360, dxfattribs={"layer": "Border"})  # bottom: a half disc
    msp.add_line((0, 0), (100, 0), dxfattribs={"layer": "Valley"})
    doc.saveas(tmp_path / "arc.dxf")
    cp = read_dxf(tmp_path / "arc.dxf")
    arc = cp.vertices[cp.vertices[:, 1] < -1e-9]
    assert len(arc) > 20
    assert np.allclose(np.hypot(arc[:, 0] - 50, arc[:, 1]), 50, atol=1e-9)
    assert -50 <= cp.bounds[1] < -49.98  # chords within 0.01 mm of the arc
    assert len(cp.faces) == 2
    assert int((cp.assignments == "V").sum()) == 1


@pytest.mark.parametrize("kind", ["lwpolyline", "polyline", "arc", "spline"])
def test_curved_crease_is_refused_with_its_handle(tmp_path, kind):
    doc, msp = new_doc()
    add_square(msp)
    attribs = {"layer": "Mountain"}
    if kind == "lwpolyline":
        e = msp.add_lwpolyline([(0, 0, 0, 0, 0.3), (100, 100)], dxfattribs=attribs)
    elif kind == "polyline":
        e = msp.add_polyline2d([(0, 0, 0.3), (100, 100)], format="xyb", dxfattribs=attribs)
    elif kind == "arc":
        e = msp.add_arc((0, 100), 100, 270, 360, dxfattribs=attribs)
    else:
        e = msp.add_spline([(0, 0), (30, 60), (100, 100)], dxfattribs=attribs)
    doc.saveas(tmp_path / "curved.dxf")
    with pytest.raises(PatternError, match="curved mountain line") as info:
        read_dxf(tmp_path / "curved.dxf")
    assert str(info.value).startswith(str(tmp_path / "curved.dxf"))
    assert f"handle {e.dxf.handle} " in str(info.value)


# -------------------------------------------------------------------- units
@pytest.mark.parametrize(("code", "factor"), [(0, 1.0), (1, 25.4), (2, 304.8), (5, 10.0)])
def test_insunits_are_converted_to_mm(tmp_path, code, factor):
    doc, msp = new_doc(units=code)
    add_square(msp, size=4)
    msp.add_line((0, 0), (4, 4), dxfattribs={"layer": "Valley"})
    doc.saveas(tmp_path / "units.dxf")
    cp = read_dxf(tmp_path / "units.dxf")
    assert cp.bounds == pytest.approx((0, 0, 4 * factor, 4 * factor))
    assert cp.edge_lengths().max() == pytest.approx(4 * factor * math.sqrt(2))


def test_blocks_and_arcs_are_converted_to_mm_with_the_drawing(tmp_path):
    doc, msp = new_doc(units=1)  # inches
    msp.add_lwpolyline([(0, 0), (4, 0), (4, 4), (0, 4)], close=True, dxfattribs={"layer": "Border"})
    msp.add_polyline2d([(0, 2), (4, 2)], dxfattribs={"layer": "Valley"})
    block = doc.blocks.new("CREASE")
    block.add_line((0, 0), (0, 2), dxfattribs={"layer": "Mountain"})
    msp.add_blockref("CREASE", (1, 0))
    msp.add_blockref("CREASE", (3, 2))
    msp.add_arc((2, 4), 1.0, 0, 180, dxfattribs={"layer": "Border"})  # a bump, flattened
    doc.saveas(tmp_path / "mixed.dxf")
    cp = read_dxf(tmp_path / "mixed.dxf")
    assert cp.bounds[2] == pytest.approx(4 * 25.4) and cp.bounds[3] == pytest.approx(5 * 25.4)
    mountains = cp.vertices[cp.edges[cp.assignments == "M"]]
    xs = sorted({round(float(x), 6) for x in mountains[:, :, 0].ravel()})
    assert xs == pytest.approx([25.4, 3 * 25.4])  # both block references, placed
    assert (cp.assignments == "B").sum() > 8  # the arc became many border segments


# ---------------------------------------------------------------- bad input
def test_missing_and_corrupt_files(tmp_path):
    with pytest.raises(PatternError, match=r"nothing\.dxf: no such file"):
        read_dxf(tmp_path / "nothing.dxf")
    garbage = tmp_path / "garbage.dxf"
    garbage.write_bytes(b"\x00\x01\xff not a dxf at all")
    with pytest.raises(PatternError, match=r"garbage\.dxf: not a readable DXF"):
        read_dxf(garbage)
    truncated = tmp_path / "truncated.dxf"
    truncated.write_text("0\nSECTION\n2\nHEADER\n")
    with pytest.raises(PatternError, match=r"truncated\.dxf: not a readable DXF"):
        read_dxf(truncated)


def test_unclassifiable_lines_are_reported_not_guessed(tmp_path):
    doc, msp = new_doc()
    yellow = msp.add_line((0, 0), (10, 0), dxfattribs={"color": 2})  # yellow on layer 0
    doc.saveas(tmp_path / "yellow.dxf")
    with pytest.raises(PatternError, match="classif") as info:
        read_dxf(tmp_path / "yellow.dxf")
    message = str(info.value)
    assert message.startswith(f"{tmp_path / 'yellow.dxf'}: 1 lines")
    assert f"handle {yellow.dxf.handle} (LINE) on layer '0', colour 2" in message


def test_own_meaningless_colour_is_not_replaced_by_the_layer_colour(tmp_path):
    doc, msp = new_doc()
    add_square(msp)
    doc.layers.add("red", color=1)
    for k in range(5):
        msp.add_line((10 * k, 0), (10 * k + 5, 50), dxfattribs={"layer": "red", "color": 6})
    block = doc.blocks.new("MAGENTA")
    block.add_line((0, 0), (1, 1), dxfattribs={"color": 6})
    msp.add_blockref("MAGENTA", (60, 60))
    doc.saveas(tmp_path / "magenta.dxf")
    with pytest.raises(PatternError, match=r"magenta\.dxf: 6 lines cannot be classif") as info:
        read_dxf(tmp_path / "magenta.dxf")
    assert "; and 3 more" in str(info.value)


def test_unclassified_line_in_a_block_names_the_block(tmp_path):
    doc, msp = new_doc()
    add_square(msp)
    block = doc.blocks.new("DETAIL")
    block.add_line((0, 0), (1, 1), dxfattribs={"color": 2})
    ref = msp.add_blockref("DETAIL", (60, 60))
    doc.saveas(tmp_path / "detail.dxf")
    with pytest.raises(PatternError, match=f"in block 'DETAIL' \\(INSERT {ref.dxf.handle}\\)"):
        read_dxf(tmp_path / "detail.dxf")


def test_file_without_lines(tmp_path):
    doc, msp = new_doc()
    msp.add_text("hello")
    msp.add_circle((5, 5), 1, dxfattribs={"layer": "Holes"})
    doc.saveas(tmp_path / "text.dxf")
    with pytest.raises(PatternError, match=r"text\.dxf: no crease lines found \(found 1 TEXT"):
        read_dxf(tmp_path / "text.dxf")


def test_minsert_mirrored_ocs_and_holes_in_blocks(tmp_path):
    doc, msp = new_doc()
    outline = [(0, 0), (-100, 0), (-100, 100), (0, 100)]  # OCS x is mirrored: WCS 0..100
    msp.add_lwpolyline(outline, close=True, dxfattribs={"layer": "Border", "extrusion": (0, 0, -1)})
    cell = doc.blocks.new("CELL")
    cell.add_line((0, 0), (0, 10), dxfattribs={"layer": "Valley"})
    cell.add_circle((5, 5), 1.0, dxfattribs={"layer": "Hole"})
    msp.add_blockref("CELL", (10, 10), dxfattribs={"xscale": 2, "yscale": 2}).grid(
        size=(2, 3), spacing=(40, 30)
    )
    doc.saveas(tmp_path / "grid.dxf")
    cp = read_dxf(tmp_path / "grid.dxf")
    assert cp.bounds == (0, 0, 100, 100)
    assert int((cp.assignments == "V").sum()) == 6
    assert sorted((h.x, h.y, h.diameter) for h in cp.holes) == [
        (x, y, 4.0) for x in (20.0, 50.0, 80.0) for y in (20.0, 60.0)
    ]
    assert not cp.notes  # shared end points are not reported as repairs


def test_unknown_unit_code(tmp_path):
    doc, msp = new_doc(units=99)
    add_square(msp)
    doc.saveas(tmp_path / "odd.dxf")
    with pytest.raises(PatternError, match=r"odd\.dxf: \$INSUNITS = 99"):
        read_dxf(tmp_path / "odd.dxf")
