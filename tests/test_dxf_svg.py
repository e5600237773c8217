"""DXF and SVG: round trips, files in other tools' conventions, and bad input."""

from __future__ import annotations

from pathlib import Path

import ezdxf
import numpy as np
import pytest

from origami_cad.pattern import (
    CreasePattern,
    Hole,
    PatternError,
    miura_pattern,
    read_fold,
    read_fold_frames,
    read_pattern,
    write_pattern,
)
from origami_cad.pattern.formats.dxf import read_dxf, write_dxf
from origami_cad.pattern.formats.svg import read_svg, write_svg

DATA = Path(__file__).resolve().parent / "data"
SQUARE = [(0, 0), (100, 0), (100, 100), (0, 100)]


def miura_with_extras() -> CreasePattern:
    cp = miura_pattern(4, 6, 20.0, 30.0, 60.0)
    return cp.with_holes([Hole(30.0, 15.0, 2.0)])


# ------------------------------------------------------------------ DXF
def test_dxf_round_trip_layers_and_units(tmp_path):
    cp = miura_with_extras()
    path = write_dxf(cp, tmp_path / "m.dxf")
    back = read_dxf(path)
    assert back.same_graph(cp, tolerance=1e-9)
    assert back.holes == cp.holes
    assert read_pattern(write_pattern(cp, tmp_path / "n.dxf")).same_graph(cp)
    doc = ezdxf.readfile(path)
    assert doc.header["$INSUNITS"] == 4
    layers = {layer.dxf.name: layer for layer in doc.layers}
    assert layers["Mountain"].dxf.color == 1 and layers["Valley"].dxf.color == 5
    assert layers["Valley"].dxf.linetype == "DASHED" and layers["Cut"].dxf.color == 3
    assert layers["Border"].dxf.color == 7
    kinds = {e.dxf.layer for e in doc.modelspace().query("LINE")}
    assert kinds == {"Mountain", "Valley", "Border"}


def new_doc(units: int = 4):
    doc = ezdxf.new("R2010", setup=True)
    doc.header["$INSUNITS"] = units
    return doc, doc.modelspace()


def square_outline(msp, layer: str = "0", color: int | None = None):
    attribs = {"layer": layer}
    if color is not None:
        attribs["color"] = color
    for a, b in zip(SQUARE, SQUARE[1:] + SQUARE[:1], strict=True):
        msp.add_line(a, b, dxfattribs=attribs)


def test_oripa_layers_outline_drawn_as_cut_lines(tmp_path):
    doc, msp = new_doc()
    for name, color in (("CutLine", 3), ("MountainLine", 1), ("ValleyLine", 5)):
        doc.layers.add(name, color=color)
    square_outline(msp, "CutLine")
    msp.add_line((0, 0), (100, 100), dxfattribs={"layer": "ValleyLine"})
    msp.add_line((0, 100), (40, 60), dxfattribs={"layer": "MountainLine"})
    msp.add_line((60, 20), (80, 40), dxfattribs={"layer": "CutLine"})  # a slit inside
    doc.saveas(tmp_path / "oripa.dxf")
    cp = read_dxf(tmp_path / "oripa.dxf")
    assert sorted(cp.assignments.tolist()) == ["B"] * 4 + ["C", "M", "V"]
    slit = cp.edges[cp.assignments == "C"][0]
    assert sorted(cp.vertices[slit].tolist()) == [[60.0, 20.0], [80.0, 40.0]]


def test_colour_only_true_colour_and_linetype(tmp_path):
    doc, msp = new_doc()
    square_outline(msp, color=7)
    msp.add_line((0, 0), (100, 100), dxfattribs={"color": 1})
    msp.add_line((0, 100), (50, 50), dxfattribs={"color": 5})
    red = msp.add_line((50, 50), (100, 0))
    red.rgb = (230, 20, 10)
    doc.layers.add("creases", color=2)
    msp.add_line((0, 50), (50, 50), dxfattribs={"layer": "creases", "linetype": "DASHED"})
    doc.saveas(tmp_path / "colours.dxf")
    cp = read_dxf(tmp_path / "colours.dxf")
    mid = (cp.vertices[cp.edges[:, 0]] + cp.vertices[cp.edges[:, 1]]) / 2
    letter = {tuple(np.round(m, 3)): a for m, a in zip(mid, cp.assignments, strict=True)}
    assert letter[(75.0, 25.0)] == "M"  # true-colour red
    assert letter[(25.0, 75.0)] == "V"  # ACI 5
    assert letter[(25.0, 50.0)] == "V"  # dashed on a neutral layer
    assert letter[(50.0, 0.0)] == "B"


def test_polylines_blocks_arcs_and_inches(tmp_path):
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


def test_dxf_bad_input(tmp_path):
    with pytest.raises(PatternError, match=r"nothing.dxf: no such file"):
        read_dxf(tmp_path / "nothing.dxf")
    garbage = tmp_path / "garbage.dxf"
    garbage.write_bytes(b"\x00\x01 not a dxf at all")
    with pytest.raises(PatternError, match=r"garbage.dxf"):
        read_dxf(garbage)
    doc, msp = new_doc()
    msp.add_line((0, 0), (10, 0), dxfattribs={"color": 2})  # yellow on layer 0
    doc.saveas(tmp_path / "yellow.dxf")
    with pytest.raises(PatternError, match=r"yellow.dxf: 1 lines cannot be classif"):
        read_dxf(tmp_path / "yellow.dxf")
    doc, msp = new_doc()
    msp.add_lwpolyline([(0, 0, 0, 0, 0.5), (10, 0)], dxfattribs={"layer": "Mountain"})
    doc.saveas(tmp_path / "curved.dxf")
    with pytest.raises(PatternError, match="curved mountain line"):
        read_dxf(tmp_path / "curved.dxf")
    doc, msp = new_doc()
    msp.add_text("hello")
    doc.saveas(tmp_path / "empty.dxf")
    with pytest.raises(PatternError, match="no crease lines"):
        read_dxf(tmp_path / "empty.dxf")


# ------------------------------------------------------------------ SVG
def test_svg_round_trip_with_partial_angles_and_holes(tmp_path):
    cp = miura_with_extras()
    angles = cp.fold_angles.copy()
    angles[cp.assignments == "V"] = 90.0
    cp = CreasePattern(cp.vertices, cp.edges, cp.assignments, angles).with_holes(cp.holes)
    back = read_svg(write_svg(cp, tmp_path / "m.svg"))
    assert back.same_graph(cp, tolerance=1e-9)
    assert back.holes == cp.holes
    text = (tmp_path / "m.svg").read_text()
    assert 'stroke-opacity="0.5"' in text and 'width="' in text and "mm" in text


def test_origami_simulator_samples():
    simple = read_svg(DATA / "origami-simulator" / "simpleVertex.svg")
    assert (simple.assignments == "M").sum() == 3 and (simple.assignments == "V").sum() == 1
    assert simple.check() == [] or all(p.severity != "error" for p in simple.check())
    mapfold = read_svg(DATA / "origami-simulator" / "mapfold.svg")
    assert [p for p in mapfold.check() if p.severity == "error"] == []
    huffman = read_svg(DATA / "origami-simulator" / "huffmanWaterbomb.svg")
    partial = np.abs(huffman.fold_angles[huffman.assignments == "M"])
    assert np.allclose(partial, 90.0)  # opacity 0.5 on its mountains
    hypar = read_svg(DATA / "origami-simulator" / "hypar.svg")
    assert (hypar.assignments == "U").sum() > 50  # magenta: undriven hinges
    waterbomb = read_svg(DATA / "origami-simulator" / "waterbomb.svg")
    assert len(waterbomb.faces) > 100
    # px are 1/96 in: the simple vertex's 2052.941 px square is 543.17 mm wide
    x0, _, x1, _ = simple.bounds
    assert x1 - x0 == pytest.approx(2052.941 * 25.4 / 96, rel=1e-6)


def test_svg_transforms_paths_and_colour_forms(tmp_path):
    svg = """<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
      <g transform="translate(10 0) rotate(90 50 50)" style="stroke:#000">
        <path d="M0 0 h100 v100 H0 z"/>
      </g>
      <g transform="matrix(1 0 0 1 10 0)">
        <line x1="0" y1="0" x2="100" y2="100" style="stroke:rgb(255,0,0)"/>
        <polyline points="0,100 50,50" stroke="#00f"/>
        <polygon points="60,20 80,20 70,40" stroke="lime"/>
      </g>
    </svg>"""
    path = tmp_path / "t.svg"
    path.write_text(svg)
    cp = read_svg(path)
    assert cp.bounds == pytest.approx((10.0, -100.0, 110.0, 0.0))
    assert sorted(set(cp.assignments.tolist())) == ["B", "C", "M", "V"]


def test_svg_bad_input(tmp_path):
    with pytest.raises(PatternError, match=r"none.svg: no such file"):
        read_svg(tmp_path / "none.svg")
    bad = tmp_path / "bad.svg"
    bad.write_text("<svg><line")
    with pytest.raises(PatternError, match=r"bad.svg: not valid XML"):
        read_svg(bad)
    colour = tmp_path / "colour.svg"
    colour.write_text(
        '<svg xmlns="http://www.w3.org/2000/svg"><line id="l3" x1="0" y1="0" '
        'x2="1" y2="1" stroke="#123456"/></svg>'
    )
    with pytest.raises(PatternError, match=r"colour.svg: <line id=l3>.*#123456"):
        read_svg(colour)
    curve = tmp_path / "curve.svg"
    curve.write_text(
        '<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C 1 1 2 2" stroke="red"/></svg>'
    )
    with pytest.raises(PatternError, match=r"curve.svg.*'C' needs 6 numbers"):
        read_svg(curve)


# ------------------------------------------------------------------ FOLD samples
def test_fold_samples_from_the_fold_repository():
    diagonal = read_fold(DATA / "fold" / "diagonal-cp.fold")
    assert diagonal.n_edges == 5 and (diagonal.assignments == "V").sum() == 1
    for name in ("simple.fold", "squaretwist.fold", "box.fold"):
        # folded forms only: unfolded into their crease patterns (tests/test_unfold.py)
        unfolded = read_fold(DATA / "fold" / name)
        assert unfolded.metadata["unfolded"] and unfolded.vertices.shape[1] == 2
        frames = read_fold_frames(DATA / "fold" / name)
        assert frames[0].shape[1] == 3 and np.ptp(frames[0][:, 2]) > 0
