"""PyGamiX's JSON designs: read as they are (pattern, holes, tendons, anchors, fixed panels)."""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from origami_cad.errors import PatternError
from origami_cad.pattern import read_pattern
from origami_cad.strings.route import BOTTOM, TOP, route_from_pattern

DATA = Path(__file__).parent / "data" / "pygamix"
SOURCES = tomllib.loads((DATA / "SOURCE.toml").read_text())["design"]
MOUNTAIN = DATA / "descriptionData" / "f-mountain-big-fix-new.json"


def test_the_kept_designs_are_the_sources_and_of_six_kinds() -> None:
    assert (DATA / "LICENSE").read_text().startswith("MIT License")
    kinds = {s["kind"] for s in SOURCES}
    assert {"mountain", "robot", "box", "miura", "waterbomb", "resch"} <= kinds
    for s in SOURCES:
        raw = (DATA / s["file"]).read_bytes()
        assert len(raw.decode("utf-8")) == s["chars"], s["file"]
        assert hashlib.sha256(raw).hexdigest() == s["sha256"], s["file"]
        assert s["file"] == s["path"]


@pytest.mark.parametrize("entry", SOURCES, ids=[s["file"] for s in SOURCES])
def test_each_design_reads_or_is_refused_in_one_line(entry) -> None:
    path = DATA / entry["file"]
    if entry["expect"] == "reads":
        cp = read_pattern(path)
        assert len(cp.faces) == len(cp.holes) > 0
        assert len({cp.face_of_point(h.x, h.y) for h in cp.holes}) == len(cp.faces)
        tendons = json.loads(path.read_text())["strings"]["type"]
        route = route_from_pattern(cp)
        assert (route is None) == (not tendons)
        if route is not None:
            assert [len(s.faces) + 1 for s in route.strings] == [len(t) for t in tendons]
    else:
        with pytest.raises(PatternError) as err:
            read_pattern(path)
        text = str(err.value)
        assert "\n" not in text and "not supported" in text and path.name in text


def test_mountain_pattern_holes_and_tendons_match_the_file() -> None:
    data = json.loads(MOUNTAIN.read_text())
    cp = read_pattern(MOUNTAIN)
    assert cp.n_vertices == len(data["kps"]) == 25
    assert cp.n_edges == len(data["lines"]) == 40
    assert len(cp.faces) == len(data["units"]) == 16
    kinds = {0: "V", 1: "M", 2: "B"}
    for line, feature in zip(data["lines"], data["line_features"], strict=True):
        mid = np.mean(np.array(line)[:, :2], axis=0)
        d = np.linalg.norm(cp.vertices[cp.edges].mean(axis=1) - mid, axis=1)
        assert d.min() < 1e-3
        assert cp.assignments[int(np.argmin(d))] == kinds[feature["type"]]
    # each panel's hole is the weighted sum of its corners, on that panel
    for u, (poly, w) in enumerate(zip(data["units"], data["contributions"], strict=True)):
        hole = np.array(w) @ np.array(poly)[:, :2]
        face = cp.face_of_point(*hole)
        assert (cp.holes[u].x, cp.holes[u].y) == pytest.approx(tuple(hole))
        assert face == cp.face_of_point(*np.mean(np.array(poly)[:, :2], axis=0))
    route = route_from_pattern(cp)
    assert len(route.strings) == len(data["strings"]["id"]) == 2
    assert route.fixed_panel == cp.face_labels[cp.face_of_point(*np.mean(
        np.array(data["units"][data["fix"][0]])[:, :2], axis=0))]  # fmt: skip
    for s, ids, rev in zip(route.strings, data["strings"]["id"], data["strings"]["reverse"],
                           strict=True):  # fmt: skip
        assert s.anchor[:2] == tuple(data["P_candidators"]["points"][ids[0]][:2])
        assert s.anchor_face == -1  # connection -1: fixed off the panels
        assert list(s.sides) == [TOP if r > 0 else BOTTOM for r in rev[1:]]
        assert not s.violations  # the authors' sides keep the DCQC rule


def test_an_anchor_on_a_panel_is_an_onboard_tsa() -> None:
    cp = read_pattern(DATA / "descriptionData" / "f-5panel-robot.json")
    route = route_from_pattern(cp)
    assert route.tsa.model == "onboard"
    assert {s.anchor_face for s in route.strings} == {cp.face_of_point(30.0, 30.0)}
    assert all(s.sides == (BOTTOM,) for s in route.strings)


def test_a_scaled_design_scales_its_tendons() -> None:
    cp = read_pattern(MOUNTAIN)
    a, b = route_from_pattern(cp), route_from_pattern(cp.scaled(2.0))
    assert b.strings[1].points[2] == pytest.approx(tuple(2 * np.array(a.strings[1].points[2])))


def _design(tmp_path: Path, types: list[int], **extra) -> Path:
    square = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]
    lines = [[square[i], square[(i + 1) % 4]] for i in range(4)] + [[square[0], square[2]]]
    units = [[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0]],
             [[0.0, 0.0, 0.0], [10.0, 10.0, 0.0], [0.0, 10.0, 0.0]]]  # fmt: skip
    data = {"kps": square, "lines": lines, "units": units,
            "line_features": [{"type": t} for t in types],
            "contributions": [[1 / 3] * 3, [1 / 3] * 3], **extra}  # fmt: skip
    path = tmp_path / "d.json"
    path.write_text(json.dumps(data))
    return path


def test_facet_lines_are_flat_creases_and_hole_lines_are_refused(tmp_path: Path) -> None:
    cp = read_pattern(_design(tmp_path, [2, 2, 2, 2, 6]))
    assert sorted(cp.assignments.tolist()) == ["B", "B", "B", "B", "F"]
    assert route_from_pattern(cp) is None  # no tendons
    with pytest.raises(PatternError, match=r"line 4 is a hole's outline \(type 4\).*not supported"):
        read_pattern(_design(tmp_path, [2, 2, 2, 2, 4]))


@pytest.mark.parametrize(
    ("extra", "match"),
    [
        ({"strings": {"type": [["A", "X"]], "id": [[0, 0]], "reverse": [[1, 1]]},
          "P_candidators": {"points": [[1, 1, 0]], "connections": [-1]}}, r"strings\[0\]\[1\]"),
        ({"strings": {"type": [["A", "B"]], "id": [[3, 0]], "reverse": [[1, 1]]},
          "P_candidators": {"points": [[1, 1, 0]], "connections": [-1]}}, r"strings\[0\]\[0\]"),
        ({"fix": [7]}, r"fix\[0\]"),
    ],
)  # fmt: skip
def test_bad_tendons_name_the_key(tmp_path: Path, extra, match) -> None:
    with pytest.raises(PatternError, match=match):
        read_pattern(_design(tmp_path, [2, 2, 2, 2, 0], **extra))


def test_cli_checks_a_description_and_refuses_an_unknown_piece(tmp_path: Path) -> None:
    run = [sys.executable, "-m", "origami_cad.cli", "check"]
    ok = subprocess.run([*run, str(MOUNTAIN)], capture_output=True, text=True, check=False)
    assert ok.returncode == 0 and "0 errors" in ok.stdout
    data = json.loads((DATA / "packedImport" / "miura-120.json").read_text())
    data["origami"][0]["type"] = "lean"
    bad = tmp_path / "lean.json"
    bad.write_text(json.dumps(data))
    out = subprocess.run([*run, str(bad)], capture_output=True, text=True, check=False)
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1
    assert "'lean' piece" in out.stderr and "not supported" in out.stderr
