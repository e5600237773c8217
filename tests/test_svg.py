"""SVG: round trips, Origami Simulator's samples, transforms and colour forms, bad input;
and the FOLD repository's samples. (DXF: tests/test_dxf.py.)"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from origami_cad.pattern import (
    CreasePattern,
    Hole,
    PatternError,
    miura_pattern,
    read_fold,
    read_fold_frames,
)
from origami_cad.pattern.formats.svg import read_svg, write_svg

DATA = Path(__file__).resolve().parent / "data"


def miura_with_extras() -> CreasePattern:
    cp = miura_pattern(4, 6, 20.0, 30.0, 60.0)
    return cp.with_holes([Hole(30.0, 15.0, 2.0)])


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
