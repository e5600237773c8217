"""ORIPA's plain-text .cp: ORIPA's conventions (types, y down), written and read back, and
hostile text refused in one line naming the file and the line."""

from __future__ import annotations

import numpy as np
import pytest

from origami_cad.cli import main
from origami_cad.errors import PatternError
from origami_cad.pattern import miura_pattern, read_pattern, write_pattern

# ORIPA's square of side 200 centred on the origin (its cut lines the outline), y down,
# a valley diagonal, a mountain from the centre to (100, -100) and an auxiliary line
SHEET = """1 -100 -100 100 -100
1 100 -100 100 100
1 100 100 -100 100
1 -100 100 -100 -100
3 -100 -100 100 100
2 0 0 100 -100
0 -100 100 0 0
"""


def test_oripa_conventions(tmp_path):
    path = tmp_path / "sheet.cp"
    path.write_text(SHEET)
    cp = read_pattern(path)
    letters = {a: int((cp.assignments == a).sum()) for a in "BCMVF"}
    assert letters == {"B": 4, "C": 0, "M": 1, "V": 2, "F": 1}  # outline cuts are border
    mountain = cp.edges[cp.assignments == "M"][0]
    ends = {tuple(np.round(cp.vertices[v], 6)) for v in mountain}
    assert ends == {(0.0, 0.0), (100.0, 100.0)}  # ORIPA's y down, turned up
    assert cp.bounds == (-100.0, -100.0, 100.0, 100.0)


def test_written_and_read_back(tmp_path):
    cp = miura_pattern(3, 2, 20.0, 25.0, 65.0)
    back = read_pattern(write_pattern(cp, tmp_path / "m.cp"))
    assert back.n_edges == cp.n_edges and back.n_vertices == cp.n_vertices
    for letter in "MVB":
        assert (back.assignments == letter).sum() == (cp.assignments == letter).sum()
    assert np.allclose(sorted(map(tuple, back.vertices)), sorted(map(tuple, cp.vertices)))


@pytest.mark.parametrize(
    "text, says",
    [
        ("", "no crease lines"),
        ("2 0 0 1\n", "line 1: expected 'type x0 y0 x1 y1'"),
        ("1 0 0 1 0\n2 0 0 x 1\n", "line 2:"),
        ("2 0 0 nan 1\n", "line 1: a coordinate is not finite"),
        ("2 0 0 1e300 1\n", "line 1: a coordinate is not finite or farther"),
        ("2 0 0 0 0\n", "no crease lines"),
    ],
)
def test_bad_text_is_one_line_naming_the_file_and_line(tmp_path, capsys, text, says):
    path = tmp_path / "bad.cp"
    path.write_text(text)
    with pytest.raises(PatternError, match=says):
        read_pattern(path)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bad.cp" in err[0] and says.split(":")[0] in err[0], err


def test_binary_garbage_is_refused(tmp_path):
    path = tmp_path / "bin.cp"
    path.write_bytes(b"\xff\xfe\x00garbage\x80")
    with pytest.raises(PatternError, match=r"bin\.cp"):
        read_pattern(path)
