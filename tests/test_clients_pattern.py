"""Our crease-pattern files read back the way ORIPA and Origami Simulator read them.

Neither client runs here (ORIPA is a Java desktop program, Origami Simulator a WebGL
page), so each test mirrors the client's own loader, from its source:

- ORIPA (oripa/oripa, ``src/main/java/oripa/persistence/doc/loader/LoaderDXF.java``):
  a ``java.io.StreamTokenizer`` splits the whole file at spaces, tabs and line breaks;
  every word ``LINE`` starts a line, whose group codes are read in pairs until the
  next group code ``0``: ``62`` is the colour (ACI 1 or 10-39 mountain, 2, 5 or
  140-199 valley, 3 or 60-129 cut, anything else auxiliary), ``10 20 11 21`` the end
  points; layers are never looked at, and a line with no ``62`` has no type at all.
  Lines shorter than 0.001 drawing units are dropped.
- Origami Simulator (amandaghassaei/OrigamiSimulator, ``js/pattern.js`` and
  ``js/globals.js``): only the ``<line>``/``<path>``/... children of the root element
  are read, in user units (``x1.baseVal.value``) with the element's own transform, the
  viewBox and width/height ignored; stroke colour gives the type; then
  ``FOLD.filter.collapseNearbyVertices(fold, vertTol)`` with ``vertTol = 3`` merges
  vertices closer than 3 user units, and ``findIntersections(fold, vertTol)`` splits an
  edge where another edge's end lies within 3 units of it.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from origami_cad.pattern import CreasePattern, Hole, miura_pattern, read_pattern, write_pattern
from origami_cad.pattern.design import load_design

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
DATA = Path(__file__).resolve().parent / "data"
_SQUARE = [(0, 0), (100, 0), (100, 100), (0, 100)]
ALL_KINDS = CreasePattern(
    [*_SQUARE, (50, 50), (50, 0), (50, 100), (0, 50), (100, 50), (70, 60), (80, 62)],
    [
        (0, 1),
        (1, 2),
        (2, 3),
        (3, 0),
        (0, 4),
        (4, 2),
        (1, 4),
        (4, 3),
        (5, 4),
        (4, 6),
        (7, 4),
        (9, 10),
    ],
    "BBBBMMVVFJUC",
)


# ------------------------------------------------------------------------ ORIPA
def _java_tokens(text: str) -> list[tuple[bool, str]]:
    """``(is_word, text)`` tokens of ORIPA's StreamTokenizer set-up.

    Word characters: ``0``-``\\u00ff``, ``.`` and ``-`` (and, as in Java, every
    character above ``\\u00ff``); white space: space, tab, CR, LF; every other
    character is an "ordinary" token of its own.
    """
    out: list[tuple[bool, str]] = []
    word: list[str] = []
    for c in text:
        if c in " \t\r\n":
            if word:
                out.append((True, "".join(word)))
                word = []
        elif c >= "0" or c in ".-":
            word.append(c)
        else:
            if word:
                out.append((True, "".join(word)))
                word = []
            out.append((False, c))
    if word:
        out.append((True, "".join(word)))
    return out


def _oripa_type(color: int) -> str:
    if color == 1 or 9 < color < 40:
        return "MOUNTAIN"
    if color in (2, 5) or 139 < color < 200:
        return "VALLEY"
    if color == 3 or 59 < color < 130:
        return "CUT"
    return "AUX"


def oripa_load_dxf(path: Path) -> list[tuple[str | None, tuple[float, float, float, float]]]:
    """The lines ORIPA's ``LoaderDXF.load`` finds: ``(type, (x0, y0, x1, y1))``."""
    tokens = _java_tokens(path.read_text(encoding="utf-8"))
    lines: list[dict] = []
    i = 0
    while i < len(tokens):
        is_word, sval = tokens[i]
        i += 1
        if not (is_word and sval == "LINE"):
            continue
        dto: dict = {"type": None}
        while i < len(tokens):
            is_word, sval = tokens[i]
            i += 1
            if is_word and sval == "0":
                lines.append(dto)
                break
            value = tokens[i][1] if i < len(tokens) else ""
            i += 1  # every other group code: its value is skipped
            if is_word and sval == "62":
                dto["type"] = _oripa_type(int(value))
            elif is_word and sval in ("10", "20", "11", "21"):
                dto[sval] = float(value)
                if sval == "21" and np.hypot(dto["11"] - dto["10"], dto["21"] - dto["20"]) < 1e-3:
                    dto["dropped"] = True
    return [
        (d["type"], (d["10"], d["20"], d["11"], d["21"])) for d in lines if not d.get("dropped")
    ]


_ORIPA_OF = {"M": "MOUNTAIN", "V": "VALLEY", "C": "CUT", "B": "CUT"}


def _expected_oripa(cp: CreasePattern) -> dict[tuple, str]:
    out = {}
    for (a, b), letter in zip(cp.edges, cp.assignments, strict=True):
        key = tuple(np.round(np.r_[cp.vertices[a], cp.vertices[b]], 6))
        out[key] = _ORIPA_OF.get(str(letter), "AUX")
    return out


@pytest.mark.parametrize("source", ["all kinds", "fig2_tg.toml", "miura_6x4.toml"])
def test_oripa_reads_every_line_of_our_dxf_with_its_assignment(tmp_path, source):
    cp = ALL_KINDS if source == "all kinds" else load_design(EXAMPLES / source).pattern
    path = write_pattern(cp, tmp_path / "cp.dxf")
    found = oripa_load_dxf(path)
    assert len(found) == cp.n_edges  # every line, none dropped, none invented
    expected = _expected_oripa(cp)
    got = {tuple(np.round(xy, 6)): kind for kind, xy in found}
    assert got == expected  # mountain, valley, cut and the outline as cut, as ORIPA draws it
    assert {"MOUNTAIN", "VALLEY", "CUT"} <= set(got.values())


def test_our_dxf_still_reads_back_in_our_reader_and_ezdxf(tmp_path):
    import ezdxf

    path = write_pattern(ALL_KINDS, tmp_path / "cp.dxf")
    assert read_pattern(path).same_graph(ALL_KINDS, tolerance=1e-9)  # layers still decide
    lines = ezdxf.readfile(path).modelspace().query("LINE")
    by_layer = {e.dxf.layer: e.dxf.color for e in lines}
    assert by_layer == {
        "Border": 3,  # the sheet outline on the cut colour, as ORIPA's writer does
        "Mountain": 1,
        "Valley": 5,
        "Cut": 3,
        "Flat": 8,
        "Unassigned": 9,
        "Join": 9,
    }


# ----------------------------------------------------------- Origami Simulator
OS_COLOURS = {
    "#000000": "B",
    "#000": "B",
    "black": "B",
    "#ff0000": "M",
    "#f00": "M",
    "red": "M",
    "#0000ff": "V",
    "#00f": "V",
    "blue": "V",
    "#00ff00": "C",
    "#0f0": "C",
    "green": "C",
    "#ffff00": "F",
    "#ff0": "F",
    "yellow": "F",
    "#ff00ff": "U",
    "#f0f": "U",
    "magenta": "U",
}


def os_line_segments(path: Path) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The ``<line>`` children of the root, as Origami Simulator reads them (user units)."""
    root = ET.parse(path).getroot()
    out = []
    for el in root:
        if el.tag.rsplit("}", 1)[-1] != "line":
            continue
        assert "transform" not in el.attrib  # we write none; OS would apply only its own
        kind = OS_COLOURS.get(el.attrib.get("stroke", "").lower())
        a = np.array([float(el.attrib["x1"]), float(el.attrib["y1"])])
        b = np.array([float(el.attrib["x2"]), float(el.attrib["y2"])])
        out.append((kind, a, b))
    return out


def os_collapse(points: np.ndarray, tol: float = 3.0) -> int:
    """How many vertices remain after ``collapseNearbyVertices(fold, tol)``."""
    tree = cKDTree(points)
    pairs = tree.query_pairs(tol - 1e-12)
    parent = list(range(len(points)))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i, j in pairs:
        parent[find(i)] = find(j)
    return len({find(i) for i in range(len(points))})


def os_t_junctions(vertices: np.ndarray, edges: np.ndarray, tol: float = 3.0) -> int:
    """Edges ``findIntersections`` would split at another edge's end (within ``tol``)."""
    count = 0
    a, b = vertices[edges[:, 0]], vertices[edges[:, 1]]
    d = b - a
    length = np.linalg.norm(d, axis=1)
    for v, p in enumerate(vertices):
        t = np.einsum("ij,ij->i", p - a, d) / length**2
        foot = a + np.clip(t, 0, 1)[:, None] * d
        near = np.linalg.norm(p - foot, axis=1) < tol
        inside = (t * length > tol) & (t * length < length - tol)
        other = (edges[:, 0] != v) & (edges[:, 1] != v)
        count += int((near & inside & other).sum())
    return count


def _os_graph(path: Path) -> tuple[np.ndarray, np.ndarray, list[str]]:
    segments = os_line_segments(path)
    assert all(kind is not None for kind, _, _ in segments)  # no "bad colours"
    ends = np.array([p for _, a, b in segments for p in (a, b)])
    uniq, inverse = np.unique(np.round(ends, 9), axis=0, return_inverse=True)
    return uniq, inverse.reshape(-1, 2), [k for k, _, _ in segments]


def test_origami_simulator_keeps_every_vertex_of_the_fig2_pattern(tmp_path):
    cp = load_design(EXAMPLES / "fig2_tg.toml").pattern
    assert (cp.n_vertices, cp.n_edges) == (42, 71)
    centre = cp.face_centroids()[3]
    cp = cp.with_holes([Hole(float(centre[0]), float(centre[1]), 2.0)])
    lengths = cp.edge_lengths()
    assert lengths.min() < 1.0  # the 0.734 mm edges that used to merge at 1 unit per mm
    path = write_pattern(cp, tmp_path / "fig2.svg")
    vertices, edges, kinds = _os_graph(path)
    assert (len(vertices), len(edges)) == (cp.n_vertices, cp.n_edges)
    assert os_collapse(vertices) == cp.n_vertices  # vertTol = 3 merges nothing
    gaps = cKDTree(vertices).query(vertices, k=2)[0][:, 1]
    assert gaps.min() >= 3.0
    assert os_t_junctions(vertices, edges) == 0  # and splits no edge
    assert sorted(kinds) == sorted(map(str, cp.assignments))
    # the physical size is still right: our reader, and the root's width/height in mm
    back = read_pattern(path)
    assert back.same_graph(cp, tolerance=1e-6)
    (hole,) = back.holes
    assert (hole.x, hole.y, hole.diameter) == pytest.approx((*centre, 2.0))
    root = ET.parse(path).getroot()
    x0, y0, x1, y1 = cp.bounds
    assert float(root.attrib["width"].removesuffix("mm")) == pytest.approx(x1 - x0)
    assert float(root.attrib["height"].removesuffix("mm")) == pytest.approx(y1 - y0)
    box = [float(v) for v in root.attrib["viewBox"].split()]
    scale = box[2] / (x1 - x0)  # user units per mm
    assert box[3] / (y1 - y0) == pytest.approx(scale)
    assert np.ptp(vertices[:, 0]) == pytest.approx(box[2])  # the drawing fills the viewBox


def test_patterns_with_large_features_keep_one_unit_per_mm(tmp_path):
    cp = miura_pattern(4, 6, 20.0, 30.0, 60.0)
    path = write_pattern(cp, tmp_path / "miura.svg")
    root = ET.parse(path).getroot()
    x0, _, x1, _ = cp.bounds
    assert float(root.attrib["viewBox"].split()[2]) == pytest.approx(x1 - x0)
    vertices, edges, _ = _os_graph(path)
    assert os_collapse(vertices) == cp.n_vertices and os_t_junctions(vertices, edges) == 0
    assert read_pattern(path).same_graph(cp, tolerance=1e-9)


@pytest.mark.parametrize(
    "name, width_px", [("mapfold.svg", 3456), ("huffmanWaterbomb.svg", 2261.271)]
)
def test_origami_simulator_samples_still_read_at_their_size(name, width_px):
    cp = read_pattern(DATA / "origami-simulator" / name)
    x0, _, x1, _ = cp.bounds
    assert x1 - x0 <= width_px * 25.4 / 96 + 1e-6  # px at 96 per inch, within the page
    assert x1 - x0 > 0.5 * width_px * 25.4 / 96


_FOLD_JS = """
const FOLD = require("fold");
const fold = JSON.parse(require("fs").readFileSync(0, "utf8"));
FOLD.filter.collapseNearbyVertices(fold, 3);  // Origami Simulator's vertTol
FOLD.filter.removeLoopEdges(fold);
FOLD.filter.removeDuplicateEdges_vertices(fold);
console.log(JSON.stringify([new Set(fold.edges_vertices.flat()).size, fold.edges_vertices.length]));
"""


def _node_with_fold() -> tuple[list[str], dict[str, str]] | None:
    """``node`` and the environment that finds the npm ``fold`` package, if both exist."""
    import os
    import shutil
    import subprocess

    node, npm = shutil.which("node"), shutil.which("npm")
    if node is None or npm is None:
        return None
    root = subprocess.run([npm, "root", "-g"], capture_output=True, text=True, timeout=60)
    env = {**os.environ, "NODE_PATH": os.environ.get("NODE_PATH") or root.stdout.strip()}
    probe = subprocess.run(
        [node, "-e", "require('fold')"], capture_output=True, env=env, timeout=60
    )
    return ([node, "-e", _FOLD_JS], env) if probe.returncode == 0 else None


def test_the_fold_library_origami_simulator_uses_keeps_every_vertex(tmp_path):
    """The real npm ``fold`` package (``npm install -g fold``), which Origami Simulator
    requires, collapses our Fig. 2 SVG's vertices with its 3-unit tolerance."""
    import json
    import subprocess

    found = _node_with_fold()
    if found is None:
        pytest.skip("node with the npm package 'fold' is not installed (npm install -g fold)")
    cp = load_design(EXAMPLES / "fig2_tg.toml").pattern
    segments = os_line_segments(write_pattern(cp, tmp_path / "fig2.svg"))
    fold = {
        "vertices_coords": [p.tolist() for _, a, b in segments for p in (a, b)],
        "edges_vertices": [[2 * i, 2 * i + 1] for i in range(len(segments))],
        "edges_assignment": [kind for kind, _, _ in segments],
    }
    command, env = found
    run = subprocess.run(
        command, input=json.dumps(fold), capture_output=True, text=True, env=env, timeout=120
    )
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout) == [cp.n_vertices, cp.n_edges]  # 42 and 71, not 38 and 67
