"""PyGamiX's generated ("kl") pieces: the Miura rows PyGamiX draws, its panels and holes."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely

from origami_cad.errors import PatternError
from origami_cad.fabrication import FabricationParams, fabricate
from origami_cad.pattern import read_pattern
from origami_cad.pattern.formats.pygamix_kl import kl_rows
from origami_cad.strings.route import route_from_pattern

IMPORTS = Path(__file__).parent / "data" / "pygamix" / "packedImport"
MIURAS = [IMPORTS / "miura-120.json", IMPORTS / "miura-120-IA.json"]
LETTERS = {0: "V", 1: "M", 2: "B"}


def _rows(data: dict):
    piece, s = data["origami"][0], data["setting"]
    return kl_rows(piece["data"], tuple(piece["tsp"]), s["unit_width"], s["copy_time"],
                   s["entry_flag"] == 1)  # fmt: skip


@pytest.mark.parametrize("path", MIURAS, ids=[p.name for p in MIURAS])
def test_lines_panels_and_holes_are_pygamix_s(path: Path) -> None:
    data = json.loads(path.read_text())
    rows = _rows(data)
    # the lines in PyGamiX's order, with its types (line_features)
    assert rows.letters == [LETTERS[f["type"]] for f in data["line_features"]]
    # each hole is the weighted sum of its panel's corners, in PyGamiX's order
    axis = data["util"]["hole_axis"]
    for point, u, _ in axis:
        hole = np.array(data["contributions"][u]) @ rows.panels[u]
        assert np.abs(hole - point).max() < 1e-9
    cp = read_pattern(path)
    assert len(cp.faces) == len(rows.panels) == len(data["contributions"]) == len(cp.holes)
    assert cp.n_edges == len(data["line_features"])
    given = {u: p for p, u, _ in axis}
    for u, h in enumerate(cp.holes):
        if u in given:  # the file's hole
            assert (h.x, h.y) == tuple(given[u])
        else:  # none in hole_axis: the weighted sum of the panel's corners
            assert (h.x, h.y) == pytest.approx(np.array(data["contributions"][u]) @ rows.panels[u])
        face = shapely.Polygon(cp.vertices[cp.faces[cp.face_of_point(h.x, h.y)]])
        assert face.symmetric_difference(shapely.Polygon(rows.panels[u])).area < 1e-9
    assert cp.holes[0].diameter == data["setting"]["hole_size"]
    assert not [p for p in cp.check() if p.severity == "error"]


def test_a_string_on_generated_panels_is_routed_on_their_faces() -> None:
    path = IMPORTS / "miura-120-IA.json"
    data = json.loads(path.read_text())
    cp = read_pattern(path)
    route = route_from_pattern(cp)
    (string,) = route.strings
    holes = [(h.x, h.y) for h in cp.holes]
    assert list(string.points) == [holes[u] for u in data["strings"]["id"][0][1:]]
    assert route.fixed_panel == cp.face_labels[cp.face_of_point(*holes[data["fix"][0]])]


def test_rows_and_alternating_turns_make_pygamix_s_grid(tmp_path: Path) -> None:
    # the parameters and some holes of PyGamiX's packedImport/8seg-miura.json (MIT, same
    # commit as SOURCE.toml): 5 rows of 40 mm, 8 segments of 25 mm turning by 120 degrees
    a = math.pi / 3
    piece = {
        "type": "kl",
        "tsp": [0.0, 0.0],
        "add_width": False,
        "data": [[25.000000000000004, a if i % 2 == 0 else -a] for i in range(8)],
    }
    holes = {
        0: [12.718169402703921, 10.768493800701375],
        2: [37.5, 9.999999999999998],
        14: [187.27372575868094, 9.231016465435657],
        15: [187.2737257586809, 30.76898353456434],
        16: [12.718169402703921, 50.76849380070138],
        79: [187.2737257586809, 190.76898353456434],
    }
    data = {"origami": [piece], "setting": {"unit_width": 40.0, "copy_time": 5, "entry_flag": 0},
            "util": {"hole_axis": [[p, u, True] for u, p in holes.items()]}}  # fmt: skip
    path = tmp_path / "grid.json"
    path.write_text(json.dumps(data))
    cp = read_pattern(path)
    rows = _rows(data)
    assert len(rows.panels) == len(cp.faces) == len(cp.holes) == 80
    for u, p in holes.items():  # the source's hole lies on the panel we drew for it
        assert shapely.Polygon(rows.panels[u]).contains(shapely.Point(p))
        assert cp.face_of_point(*p) == cp.face_of_point(*rows.panels[u].mean(axis=0))
    problems = [p for p in cp.check() if p.severity == "error"]
    assert not problems
    # the rows meet on shared creases, opposite to the main crease beside them
    assert {cp.assignments[e] for e in range(cp.n_edges)
            if np.allclose(cp.vertices[cp.edges[e]][:, 1], 40.0)} == {"M", "V"}  # fmt: skip


def _piece(tmp_path: Path, **change) -> Path:
    data = json.loads(MIURAS[0].read_text())
    for key, value in change.items():
        where, name = key.split("__")
        (data["origami"][0] if where == "piece" else data[where])[name] = value
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    return path


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"piece__type": "lean"}, r"origami\[0\] is a 'lean' piece.*not supported"),
        ({"piece__add_width": 1}, r"origami\[0\]\.add_width: 1 is neither true nor false"),
        (
            {"setting__enable_connection": True, "setting__con_left_length": -2.0},
            r"setting\.con_left_length",
        ),
        ({"piece__data": [[60.0, 0.0], [60.0, math.pi]]}, r"origami\[0\]\.data\[1\] turns by 180"),
        ({"piece__data": [[-1.0, 0.0]]}, r"origami\[0\]\.data\[0\].*> 0 mm"),
        ({"setting__copy_time": 0}, r"setting\.copy_time"),
        ({"setting__unit_width": -5.0}, r"setting\.unit_width"),
        ({"setting__entry_flag": 3}, r"setting\.entry_flag"),
    ],
)
def test_what_is_not_drawn_is_refused_in_one_line(tmp_path: Path, change, match) -> None:
    with pytest.raises(PatternError, match=match) as err:
        read_pattern(_piece(tmp_path, **change))
    assert "\n" not in str(err.value) and "bad.json" in str(err.value)


def test_width_bias_and_connection_flaps_move_and_lengthen_the_rows(tmp_path: Path) -> None:
    def vertices(**change) -> np.ndarray:
        path = _piece(tmp_path, util__hole_axis=[], **change)  # holes: the panels' own
        return read_pattern(path).vertices

    base = vertices()
    raised = vertices(piece__add_width=True)  # PyGamiX starts it copy_time rows higher
    assert sorted(map(tuple, raised.round(9))) == sorted(
        map(tuple, (base + np.array([0, 120])).round(9))
    )
    flaps = vertices(setting__enable_connection=True, setting__con_left_length=10.0,
                     setting__con_right_length=15.0)  # fmt: skip
    assert np.ptp(flaps[:, 0]) == pytest.approx(np.ptp(base[:, 0]) + 25.0)
    joint = [tuple(v) for v in flaps.round(9) if v[1] == 60.0 and 0 < v[0] < 140]
    assert joint == [(100.0, 60.0)]  # the flap lengthens the first segment: 10 + 90 mm


def test_cli_checks_and_folds_a_generated_piece(tmp_path: Path) -> None:
    run = [sys.executable, "-m", "origami_cad.cli"]
    ok = subprocess.run([*run, "check", str(MIURAS[0])], capture_output=True, text=True,
                        check=False)  # fmt: skip
    assert ok.returncode == 0 and "0 errors" in ok.stdout
    out = tmp_path / "m.fold"
    fold = subprocess.run([*run, "fold", str(MIURAS[0]), "--ratio", "0.3", "-o", str(out)],
                          capture_output=True, text=True, check=False)  # fmt: skip
    assert fold.returncode == 0, fold.stderr
    z = np.array(json.loads(out.read_text())["file_frames"][-1]["vertices_coords"])[:, 2]
    assert np.ptp(z) > 1.0  # folded out of the plane


@pytest.mark.filterwarnings("ignore:the infill is only")
def test_a_generated_piece_is_fabricated_with_its_holes() -> None:
    cp = read_pattern(MIURAS[0], width=150.0)
    fab = fabricate(cp, FabricationParams(holes="pattern"))
    assert len(fab.plan.holes) == len(cp.holes) == 4


@pytest.mark.slow
def test_cli_fabricates_a_generated_piece(tmp_path: Path) -> None:
    run = [sys.executable, "-m", "origami_cad.cli", "fabricate", str(MIURAS[0]), "--width", "150",
           "-o", str(tmp_path / "fab")]  # fmt: skip
    done = subprocess.run(run, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "fab" / "shells.stl").stat().st_size > 0
