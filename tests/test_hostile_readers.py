"""Readers that used to repair silently, and inputs past the stated limits.

Each file is written here and given to the real command line (``origami_cad.cli.main``):
a refusal is exit code 2 and one line on stderr naming the file and the entity, key or
limit, with nothing written; what a reader leaves out instead is a note ``check -v``
lists, naming the entity.
"""

from __future__ import annotations

import json

import ezdxf
import pytest

from origami_cad.cli import main
from origami_cad.drive.sequence import MAX_DURATION
from origami_cad.pattern.formats.svg import MAX_DEPTH
from origami_cad.pattern.model import MAX_EDGES, MAX_VERTICES

SVG_HEAD = '<svg xmlns="http://www.w3.org/2000/svg"{attrs}>'
BORDER = '<rect id="border" x="0" y="0" width="100" height="100" stroke="black" fill="none"/>'
DIAGONAL = '<line id="crease" x1="0" y1="0" x2="100" y2="100" stroke="red"/>'
SQUARE = [[0, 0], [10, 0], [10, 10], [0, 10]]
SQUARE_EDGES = [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]]


def refused(capsys, tmp_path, argv, *fragments):
    """``argv`` exits with 2, one stderr line naming each fragment; nothing is written
    next to the input and no input changes."""
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("origami-cad: error: "), err
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])
    after = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    assert after == before  # no output, partial or whole; the input unchanged
    return lines[0]


def checked(capsys, path):
    """``check -v`` of ``path``: (exit code, stdout)."""
    code = main(["check", "-v", str(path)])
    return code, capsys.readouterr().out


def svg(tmp_path, body, attrs=' width="100mm" height="100mm" viewBox="0 0 100 100"'):
    p = tmp_path / "in.svg"
    p.write_text(SVG_HEAD.format(attrs=attrs) + BORDER + body + "</svg>", encoding="utf-8")
    return p


# ---------------------------------------------------------------------------- SVG
@pytest.mark.parametrize(
    "attrs, fragments",
    [
        (' viewBox="0 0 0 0" width="10mm" height="10mm"', ["viewBox", "'0 0 0 0'"]),
        (' viewBox="0 0 100 0"', ["viewBox", "empty viewBox"]),
        (' viewBox="0 0 100 100" width="NaNmm" height="10mm"', ["width", "'NaNmm'"]),
        (' viewBox="0 0 100 100" width="10mm" height="infmm"', ["height", "'infmm'"]),
        (' viewBox="0 0 100 100" width="10furlongs"', ["width", "not a length"]),
    ],
)
def test_svg_root_sizes_that_were_replaced_by_1mm_are_refused(tmp_path, capsys, attrs, fragments):
    p = svg(tmp_path, DIAGONAL, attrs)
    refused(capsys, tmp_path, ["convert", p, tmp_path / "out.fold"], "in.svg", *fragments)


def test_svg_relative_sizes_still_read_as_user_units(tmp_path, capsys):
    p = svg(tmp_path, DIAGONAL, ' viewBox="0 0 100 100" width="100%" height="100%"')
    assert main(["convert", str(p), str(tmp_path / "out.fold")]) == 0
    assert json.loads((tmp_path / "out.fold").read_text())["vertices_coords"][2][0] == 100


@pytest.mark.parametrize("transform", ["scale(0)", "scale(1 0)", "matrix(1 2 2 4 0 0)"])
def test_svg_a_crease_collapsed_by_its_groups_transform_is_refused(tmp_path, capsys, transform):
    p = svg(tmp_path, f'<g transform="{transform}"><g>{DIAGONAL}</g></g>')
    refused(capsys, tmp_path, ["convert", p, tmp_path / "o.fold"], "in.svg", "<line id=crease>")


def test_svg_nesting_past_the_limit_is_refused_while_parsing(tmp_path, capsys):
    depth = 100_000
    p = svg(tmp_path, "<g>" * depth + DIAGONAL + "</g>" * depth)
    msg = refused(capsys, tmp_path, ["convert", p, tmp_path / "o.fold"], "in.svg", "<g>")
    assert f"limit of {MAX_DEPTH}" in msg


def test_svg_zero_length_lines_are_noted_by_check(tmp_path, capsys):
    dot = '<line id="dot" x1="50" y1="50" x2="50" y2="50" stroke="blue"/>'
    code, out = checked(capsys, svg(tmp_path, DIAGONAL + dot))
    assert code == 0
    note = next(line for line in out.splitlines() if "zero-length" in line)
    assert note.strip().startswith("warning:") and "<line id=dot>" in note


# ---------------------------------------------------------------------------- DXF
def drawing(tmp_path, add, name="in.dxf"):
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    for a, b in [((0, 0), (100, 0)), ((100, 0), (100, 100)), ((100, 100), (0, 100))]:
        msp.add_line(a, b, dxfattribs={"layer": "Border"})
    msp.add_line((0, 100), (0, 0), dxfattribs={"layer": "Border"})
    handle = add(doc, msp)
    doc.saveas(tmp_path / name)
    return tmp_path / name, handle


def test_dxf_a_zero_length_mountain_line_is_noted_by_check(tmp_path, capsys):
    def add(doc, msp):
        msp.add_line((0, 0), (100, 100), dxfattribs={"layer": "Valley"})
        return msp.add_line((30, 30), (30, 30), dxfattribs={"layer": "Mountain"}).dxf.handle

    p, handle = drawing(tmp_path, add)
    code, out = checked(capsys, p)
    assert code == 0
    note = next(line for line in out.splitlines() if "zero-length" in line)
    assert note.strip().startswith("warning:") and f"handle {handle} (LINE)" in note


@pytest.mark.parametrize("layer", ["Holes", "Cut"])
@pytest.mark.parametrize("radius", [float("nan"), float("inf")])
def test_dxf_a_circle_of_radius_nan_or_inf_is_refused(tmp_path, capsys, layer, radius):
    def add(doc, msp):
        msp.add_line((0, 0), (100, 100), dxfattribs={"layer": "Valley"})
        return msp.add_circle((50, 50), radius, dxfattribs={"layer": layer}).dxf.handle

    p, handle = drawing(tmp_path, add)
    refused(
        capsys, tmp_path, ["convert", p, tmp_path / "o.fold"], "in.dxf", f"handle {handle}",
        "radius", "not finite",
    )  # fmt: skip


def grid_of_grids(doc, msp):
    """Vertical valleys at x = 20, 40, 60, 80: a 2-column MINSERT of a 2-column MINSERT."""
    doc.blocks.new("LINE").add_line((0, 0), (0, 100), dxfattribs={"layer": "Valley"})
    doc.blocks.new("PAIR").add_blockref("LINE", (0, 0)).grid(size=(1, 2), spacing=(1, 20))
    return msp.add_blockref("PAIR", (20, 0)).grid(size=(1, 2), spacing=(1, 40)).dxf.handle


def test_dxf_a_minsert_of_a_minsert_reads_and_checks_clean(tmp_path, capsys):
    p, _ = drawing(tmp_path, grid_of_grids)
    code, out = checked(capsys, p)
    assert code == 0, out
    assert main(["convert", str(p), str(tmp_path / "o.fold")]) == 0
    fold = json.loads((tmp_path / "o.fold").read_text())
    xs = sorted(
        fold["vertices_coords"][a][0]
        for (a, b), kind in zip(fold["edges_vertices"], fold["edges_assignment"], strict=True)
        if kind == "V"
    )
    assert xs == [20, 40, 60, 80]


def test_dxf_a_scaled_minsert_scales_the_grid_of_the_minsert_inside(tmp_path, capsys):
    # the block reference scales everything in the block, the inner grid's spacing too
    def add(doc, msp):
        doc.blocks.new("LINE").add_line((0, 0), (0, 20), dxfattribs={"layer": "Valley"})
        doc.blocks.new("PAIR").add_blockref("LINE", (0, 0)).grid(size=(1, 2), spacing=(1, 2))
        ref = msp.add_blockref("PAIR", (20, 0), dxfattribs={"xscale": 5, "yscale": 5})
        return ref.grid(size=(1, 2), spacing=(1, 40)).dxf.handle

    p, _ = drawing(tmp_path, add)
    code, out = checked(capsys, p)
    assert code == 0, out
    assert main(["convert", str(p), str(tmp_path / "o.fold")]) == 0
    fold = json.loads((tmp_path / "o.fold").read_text())
    xs = {
        fold["vertices_coords"][a][0]
        for (a, _), kind in zip(fold["edges_vertices"], fold["edges_assignment"], strict=True)
        if kind == "V"
    }
    assert xs == {20, 30, 60, 70}


@pytest.mark.parametrize(
    "group, value, fragment",
    [(" 70\n37\n", " 70\n0\n", "column_count = 0"), (" 71\n41\n", " 71\n-2\n", "row_count = -2")],
)
def test_dxf_a_minsert_of_no_cells_is_refused(tmp_path, capsys, group, value, fragment):
    def add(doc, msp):
        doc.blocks.new("V").add_line((0, 0), (100, 100), dxfattribs={"layer": "Valley"})
        grid = msp.add_blockref("V", (0, 0)).grid(size=(41, 37), spacing=(0, 0))
        return grid.dxf.handle

    p, handle = drawing(tmp_path, add)
    text = p.read_text()
    assert text.count(group) == 1  # ezdxf writes no such grid: edit the file
    p.write_text(text.replace(group, value))
    refused(
        capsys, tmp_path, ["convert", p, tmp_path / "o.fold"], "in.dxf", f"handle {handle}",
        "MINSERT", fragment,
    )  # fmt: skip


def test_dxf_an_insert_of_scale_zero_is_refused(tmp_path, capsys):
    def add(doc, msp):
        doc.blocks.new("V").add_line((0, 0), (100, 100), dxfattribs={"layer": "Valley"})
        return msp.add_blockref("V", (0, 0), dxfattribs={"yscale": 7.0}).dxf.handle

    p, handle = drawing(tmp_path, add)
    p.write_text(p.read_text().replace(" 42\n7.0\n", " 42\n0.0\n"))
    refused(
        capsys, tmp_path, ["convert", p, tmp_path / "o.fold"], "in.dxf", f"handle {handle}",
        "yscale = 0",
    )  # fmt: skip


# --------------------------------------------------------------------------- FOLD
def fold_file(tmp_path, text):
    p = tmp_path / "in.fold"
    p.write_text(text, encoding="utf-8")
    return p


def test_fold_duplicate_keys_that_contradict_each_other_are_refused(tmp_path, capsys):
    body = json.dumps({"vertices_coords": SQUARE, "edges_vertices": SQUARE_EDGES})[:-1]
    text = body + ', "edges_assignment": ["B","B","B","B","M"]'
    p = fold_file(tmp_path, text + ', "edges_assignment": ["B","B","B","B","V"]}')
    refused(capsys, tmp_path, ["convert", p, tmp_path / "o.svg"], "in.fold", "edges_assignment")
    p.write_text(text + ', "edges_assignment": ["B","B","B","B","M"]}')  # the same twice
    assert main(["convert", str(p), str(tmp_path / "o.svg")]) == 0


@pytest.mark.parametrize(
    "letter, angle", [("M", 90), ("V", -180), ("m", 45), ("B", 90), ("F", -30)]
)
def test_fold_a_fold_angle_against_its_assignment_is_refused(tmp_path, capsys, letter, angle):
    doc = {
        "vertices_coords": SQUARE,
        "edges_vertices": SQUARE_EDGES,
        "edges_assignment": ["B", "B", "B", "B", letter],
        "edges_foldAngle": [0, 0, 0, 0, angle],
    }
    p = fold_file(tmp_path, json.dumps(doc))
    refused(
        capsys, tmp_path, ["convert", p, tmp_path / "o.svg"], "in.fold", "edge 4",
        f"edges_foldAngle[4] = {angle}", f"edges_assignment[4] = '{letter}'",
    )  # fmt: skip


# ---------------------------------------------------------------------- resources
def test_a_fold_past_the_vertex_limit_is_refused_before_it_is_converted(tmp_path, capsys):
    n = MAX_VERTICES + 1
    doc = {"vertices_coords": [[k % 1000, k // 1000] for k in range(n)], "edges_vertices": []}
    p = fold_file(tmp_path, json.dumps(doc))
    refused(
        capsys, tmp_path, ["convert", p, tmp_path / "o.svg"], "in.fold", "vertices_coords",
        f"{n:,} vertices", "MAX_VERTICES",
    )  # fmt: skip


def test_lines_whose_crossings_pass_the_vertex_limit_are_refused_before_the_faces(tmp_path, capsys):
    # 2 x 226 lines (904 vertices given) cross in 51,076 vertices: refused naming the limit
    # once split, not converted for a minute into a pattern past MAX_VERTICES
    n = 226
    lines = [f'<line x1="0" y1="{k}" x2="{n}" y2="{k}" stroke="#f00"/>' for k in range(n)]
    lines += [f'<line x1="{k}" y1="0" x2="{k}" y2="{n}" stroke="#00f"/>' for k in range(n)]
    p = svg(tmp_path, "".join(lines), f' width="{n}mm" height="{n}mm" viewBox="0 0 {n} {n}"')
    refused(
        capsys, tmp_path, ["convert", p, tmp_path / "o.dxf"], "in.svg", "where they cross",
        f"{MAX_VERTICES:,} (MAX_VERTICES)",
    )  # fmt: skip


def test_a_fold_past_the_edge_limit_is_refused(tmp_path, capsys):
    doc = {"vertices_coords": [[0, 0], [1, 0]], "edges_vertices": [[0, 1]] * (MAX_EDGES + 1)}
    p = fold_file(tmp_path, json.dumps(doc))
    refused(capsys, tmp_path, ["check", p], "in.fold", "edges_vertices", "MAX_EDGES")


def tg_design(tmp_path, copies, pattern):
    p = tmp_path / "tg.toml"
    p.write_text(
        f'[pattern]\nkind = "transition-graph"\nunit_width = 20.0\ncopies = {copies}\n'
        f"entry_flag = 1\n{pattern}\n"
    )
    return p


def test_a_tg_of_9000_copies_is_refused_naming_the_copies(tmp_path, capsys):
    vectors = "fold_ratio = 0.5\nvectors = [[40, 0], [30, 25], [30, -10], [40, 15], [30, 0]]"
    p = tg_design(tmp_path, 9000, vectors)
    refused(
        capsys, tmp_path, ["pattern", p, "-o", tmp_path / "o.fold"], "tg.toml", "'copies'",
        "MAX_VERTICES",
    )  # fmt: skip


def test_a_tg_too_tall_for_its_smallest_feature_is_refused_not_repaired(tmp_path, capsys):
    # a 0.01 mm segment: 1,000 copies (the most a TG takes) make the pattern 20 m tall
    p = tg_design(tmp_path, 1000, "lengths = [10, 0.01, 10]\nshape_angles = [90, 90]")
    msg = refused(
        capsys, tmp_path, ["pattern", p, "-o", tmp_path / "o.fold"], "tg.toml", "rows",
        "smallest feature is 0.01 mm",
    )  # fmt: skip
    assert "needed repair" not in msg and "internal" not in msg


def test_a_drive_repeated_a_million_times_is_refused_before_it_starts(tmp_path, capsys):
    seq = tmp_path / "seq.toml"
    seq.write_text(
        '[sequence]\nrepeat = 1000000\nrate = 5\n[[tsa]]\nid = 1\nname = "arm"\n'
        "length = 150\nradius = 0.6\nmax_helix_angle = 75\nmapping = [[0.0, 0.0], [0.5, 10.0]]\n"
        "[[keyframe]]\nt = 0\np = [0.0]\n[[keyframe]]\nt = 0.1\np = [0.1]\n"
    )
    refused(
        capsys, tmp_path, ["drive", seq, "--dry-run", "--log", tmp_path / "log.csv"], "seq.toml",
        f"at most {MAX_DURATION:g} s", "MAX_DURATION",
    )  # fmt: skip


# ----------------------------------------------------------- names of the robot's STLs
@pytest.mark.parametrize("bad", ["../escape", "CON", "a\nb", ".hidden"])
def test_robot_stl_names_go_through_path_component(tmp_path, bad):
    build123d = pytest.importorskip("build123d")
    from origami_cad.parts.robot import RobotAssembly, write_robot_stls

    from origami_cad.errors import FabricationError

    def robot(names):
        solids = {n: build123d.Box(1, 1, 1) for n in names}
        return RobotAssembly(solids, dict.fromkeys(names, "PLA"), dict.fromkeys(names, "part"))

    out = tmp_path / "out"
    out.mkdir()
    with pytest.raises(FabricationError, match="cannot be a file name") as info:
        write_robot_stls(robot(["tsa_1", bad]), out)
    assert "\n" not in str(info.value)
    assert list(tmp_path.rglob("*.stl")) == []  # not even the good one: checked first
    written = write_robot_stls(robot(["tsa_1"]), out)
    assert [p.name for p in written.values()] == ["tsa_1.stl"]


def test_the_model_checks_its_limits_before_normalising():
    import numpy as np

    from origami_cad.errors import PatternError
    from origami_cad.pattern import CreasePattern

    with pytest.raises(PatternError, match="MAX_EDGES"):
        CreasePattern(np.zeros((2, 2)), np.zeros((MAX_EDGES + 1, 2), int), "U")
    n = MAX_VERTICES + 1  # a zigzag through n distinct vertices: n - 1 edges
    verts = np.column_stack([np.arange(n, dtype=float), np.arange(n) % 2])
    edges = np.column_stack([np.arange(n - 1), np.arange(1, n)])
    with pytest.raises(PatternError, match=f"{n:,} vertices.*MAX_VERTICES"):
        CreasePattern(verts, edges, "U")
