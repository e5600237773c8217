"""Hostile and careless FOLD files.

Every input here is made in the test. A bad file must give a PatternError naming
the file and the key or entry, in one line (the CLI's exit 2), never another
exception, a silent repair or a hang.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import refused as refused_by

from origami_cad.cli import main
from origami_cad.errors import PatternError
from origami_cad.pattern import CreasePattern, read_fold, read_fold_frames
from origami_cad.pattern.model import MAX_CLOSE_PAIRS, MAX_COORDINATE, MAX_CROSSINGS

SQUARE = {
    "file_spec": 1.2,
    "vertices_coords": [[0, 0], [10, 0], [10, 10], [0, 10]],
    "edges_vertices": [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]],
    "edges_assignment": ["B", "B", "B", "B", "V"],
    "edges_foldAngle": [0, 0, 0, 0, 90],
    "faces_vertices": [[0, 1, 2], [0, 2, 3]],
}

TRIANGLE = np.array([[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]])


def write(tmp_path, data, name="bad.fold"):
    p = tmp_path / name
    p.write_text(data if isinstance(data, str) else json.dumps(data))
    return p


def refused(path, *fragments, reader=read_fold):
    """Read ``path`` expecting a one-line PatternError naming the file and ``fragments``."""
    return refused_by(reader, path, *fragments, error=PatternError)


def with_(**changes):
    data = json.loads(json.dumps(SQUARE))
    for k, v in changes.items():
        if v is ...:
            data.pop(k)
        else:
            data[k] = v
    return data


def test_the_square_reads():
    # the base every case below breaks one field of
    cp = CreasePattern(
        SQUARE["vertices_coords"], SQUARE["edges_vertices"], SQUARE["edges_assignment"]
    )
    assert len(cp.faces) == 2


@pytest.mark.parametrize(
    "field, value, fragment",
    [
        ("vertices_coords", "0,0 10,0", "'vertices_coords' must be an array"),
        ("vertices_coords", 42, "'vertices_coords' must be an array"),
        ("vertices_coords", {"0": [0, 0]}, "'vertices_coords' must be an array"),
        ("vertices_coords", [[0, 0], [10, 0, 0], [10, 10], [0, 10]], "vertices_coords[1]"),
        ("vertices_coords", [[0, 0], [10], [10, 10], [0, 10]], "vertices_coords[1]"),
        ("vertices_coords", [[0, 0], [10, "0"], [10, 10], [0, 10]], "vertices_coords[1]"),
        ("vertices_coords", [[0, 0], [10, None], [10, 10], [0, 10]], "vertices_coords[1]"),
        ("vertices_coords", [[0, 0], [True, 0], [10, 10], [0, 10]], "vertices_coords[1]"),
        ("vertices_coords", [[0, 0], [[1], 0], [10, 10], [0, 10]], "vertices_coords[1]"),
        ("edges_vertices", "0 1", "'edges_vertices' must be an array"),
        ("edges_vertices", [[0, 1], [1, 2], [2, 3], [3, 0], [0, 1e30]], "edges_vertices[4]"),
        ("edges_vertices", [[0, 1], [1, 2], [2, 3], [3, 0], [0, 1.5]], "not a whole"),
        ("edges_vertices", [[0, 1], [1, 2], [2, 3], [3, 0], [0, True]], "edges_vertices[4]"),
        ("edges_vertices", [[0, 1], [1, 2], [2, 3], [3, 0], [0, -1]], "refers to vertex -1"),
        ("edges_vertices", [[0, 1], [1, 2], [2, 3], [3, 0], [0, 1, 2]], "edges_vertices[4]"),
        ("edges_vertices", [[0, 1], [1, 2], [2, 3], [3, 0], "02"], "edges_vertices[4]"),
        ("edges_assignment", "BBBBV", "'edges_assignment' must be an array"),
        ("edges_assignment", ["B", "B", "B", "B", 7], "edges_assignment[4]"),
        ("edges_assignment", ["B", "B", "B", "B", "Valley"], "not one letter"),
        ("edges_assignment", ["B", "B", "B", "B"], "4 entries for 5 edges"),
        ("edges_foldAngle", 90, "'edges_foldAngle' must be an array"),
        ("edges_foldAngle", [0, 0, 0, 0, "90"], "edges_foldAngle[4]"),
        ("edges_foldAngle", [0, 0, 0, 0, 1e308], "edges_foldAngle[4]"),
        ("edges_foldAngle", [0, 0, 0, 0, False], "edges_foldAngle[4]"),
        ("faces_vertices", "012", "'faces_vertices' must be an array"),
        ("faces_vertices", [[0, 1, 2], [0, 2, 3.5]], "not a whole"),
        ("faces_vertices", [[0, 1, 2], 7], "faces_vertices[1]"),
        ("file_frames", {"frame_title": "x"}, "file_frames must be an array"),
        ("file_frames", [1, 2], "file_frames[0] must be a JSON object"),
        ("file_title", ["a"], "file_title must be a string"),
        ("frame_unit", 1000, "frame_unit must be a string"),
        ("faces_origami_cad:holes", {"x": 1}, "'faces_origami_cad:holes' must be an array"),
        ("faces_origami_cad:holes", [[[5, 3, "2"]], []], "faces_origami_cad:holes[0]"),
        ("faces_origami_cad:holes", [[[5, 3, -2]], []], "diameter must be > 0"),
        ("faces_origami_cad:holes", [5, []], "faces_origami_cad:holes[0]"),
        ("faces_origami_cad:labels", "ab", "'faces_origami_cad:labels' must be an array"),
        ("faces_origami_cad:labels", ["a", 3], "faces_origami_cad:labels[1]"),
        ("faces_origami_cad:labels", ["a", "a"], "used twice"),
    ],
)
def test_fields_of_the_wrong_type_or_shape_are_refused(tmp_path, field, value, fragment):
    refused(write(tmp_path, with_(**{field: value})), fragment)


def test_the_old_key_edges_fold_angles_is_checked_too(tmp_path):
    data = with_(edges_foldAngle=...)
    data["edges_foldAngles"] = [0, 0, 0, 0, {"deg": 90}]
    refused(write(tmp_path, data), "edges_foldAngles[4]")


@pytest.mark.parametrize(
    "frame, fragment",
    [
        ({"frame_inherit": True, "frame_parent": "0"}, "frame_parent holds a string"),
        ({"frame_inherit": True, "frame_parent": 0.5}, "not a frame index"),
        ({"frame_inherit": True, "frame_parent": 1e30}, "does not exist"),
        ({"frame_inherit": True, "frame_parent": 5}, "frame_parent 5 does not exist"),
        ({"frame_inherit": True, "frame_parent": True}, "frame_parent holds a boolean"),
        ({"frame_inherit": "yes"}, "frame_inherit must be true or false"),
    ],
)
def test_frames_of_the_wrong_type_are_refused(tmp_path, frame, fragment):
    data = with_(vertices_coords=[[0, 0, 0], [10, 0, 0], [10, 10, 5], [0, 10, 0]])
    data["file_frames"] = [frame]
    p = write(tmp_path, data)
    refused(p, fragment)
    refused(p, fragment, reader=read_fold_frames)


@pytest.mark.parametrize("big", [1e308, -1e308, 1.7e308, MAX_COORDINATE * 1.01])
def test_huge_coordinates_are_refused_with_the_limit(tmp_path, big):
    p = write(tmp_path, with_(vertices_coords=[[0, 0], [big, 0], [10, 10], [0, 10]]))
    msg = refused(p, "vertices_coords[1]", f"{MAX_COORDINATE:g} mm")
    assert "limited" in msg


def test_a_unit_that_scales_coordinates_past_the_limit_is_refused(tmp_path):
    data = with_(vertices_coords=[[0, 0], [5e6, 0], [5e6, 10], [0, 10]], frame_unit="m")
    refused(write(tmp_path, data), "vertices_coords[1]")
    data["frame_unit"] = "mm"
    assert read_fold(write(tmp_path, data, "ok.fold")).bounds[2] == 5e6


@pytest.mark.parametrize("literal", ["NaN", "Infinity", "-Infinity", "1e999"])
def test_non_finite_json_numbers_are_refused(tmp_path, literal):
    text = json.dumps(with_(vertices_coords=[[0, 0], [10, 0], [10, 10], [0, 10]]))
    text = text.replace("[10, 0]", f"[{literal}, 0]", 1)
    refused(write(tmp_path, text), "vertices_coords[1]", "not a finite number")


@pytest.mark.parametrize("depth", [1_000, 100_000])
def test_deeply_nested_json_is_refused(tmp_path, depth):
    p = write(tmp_path, '{"vertices_coords": ' + "[" * depth + "]" * depth + "}")
    msg = refused(p)
    assert "nested too deeply" in msg or "vertices_coords" in msg


def test_an_integer_with_thousands_of_digits_is_refused(tmp_path):
    p = write(tmp_path, '{"vertices_coords": [[0, ' + "9" * 5000 + "]]}")
    refused(p, "not valid JSON")


def test_fractional_edge_indices_are_not_truncated(tmp_path):
    # the reader and the model both refuse them (the model for API callers)
    refused(write(tmp_path, with_(edges_vertices=[[0, 1], [1, 2], [2, 3], [3, 0], [0, 2.7]])))
    with pytest.raises(PatternError, match="not a whole number"):
        CreasePattern(TRIANGLE, [[0, 1], [1, 2.5], [2, 0]], "B")
    with pytest.raises(PatternError, match="booleans"):
        CreasePattern(TRIANGLE, np.ones((3, 2), bool), "B")
    # whole numbers written as floats (some tools do) still read
    ok = read_fold(
        write(tmp_path, with_(edges_vertices=[[0.0, 1], [1, 2], [2, 3], [3, 0], [0, 2]]))
    )
    assert ok.n_edges == 5


def test_booleans_are_not_coordinates(tmp_path):
    refused(write(tmp_path, with_(vertices_coords=[[0, 0], [10, 0], [10, 10], [False, True]])))
    with pytest.raises(PatternError, match="not booleans"):
        CreasePattern(TRIANGLE > 0, [[0, 1], [1, 2]], "B")


def test_infinite_fold_angles_are_refused_by_the_model():
    with pytest.raises(PatternError, match="edge 1: fold angle inf"):
        CreasePattern(TRIANGLE, [[0, 1], [1, 2], [2, 0]], "BVB", [0, np.inf, 0])
    # NaN is refused too (no silent default); a FOLD file's null is the letter's default
    with pytest.raises(PatternError, match="edge 1: fold angle nan is not a finite number"):
        CreasePattern(TRIANGLE, [[0, 1], [1, 2], [2, 0]], "BVB", [0, np.nan, 0])


def test_three_thousand_crossing_creases_are_refused_quickly(tmp_path):
    rng = np.random.default_rng(19)
    n = 3000
    left = np.column_stack([np.zeros(n), rng.uniform(0, 100, n)])
    right = np.column_stack([np.full(n, 100.0), rng.uniform(0, 100, n)])
    data = {
        "vertices_coords": np.vstack([left, right]).round(4).tolist(),
        "edges_vertices": [[i, i + n] for i in range(n)],
        "edges_assignment": ["M"] * n,
    }
    p = write(tmp_path, data)
    # refused in about 0.3 s here; the issue measured 27 s and 2.7 GB before the budget
    refused(p, f"more than {MAX_CROSSINGS:,} points where edges cross")


def test_thousands_of_copies_of_one_point_are_merged_or_refused():
    # exact duplicates are merged cheaply (no quadratic pair list) ...
    n = 20_000
    verts = np.zeros((n + 2, 2))
    verts[-2:] = [[100, 0], [0, 100]]
    edges = [[k, n] for k in range(n)] + [[n, n + 1]]
    cp = CreasePattern(verts, edges, "B")
    assert cp.n_vertices == 3
    # ... but a cloud of distinct points all within the tolerance is refused
    m = 4_000
    cloud = np.column_stack([np.arange(m) * 1e-12, np.zeros(m)])
    verts = np.vstack([cloud, [[100, 0], [0, 100]]])
    edges = [[k, m] for k in range(m)] + [[m, m + 1]]
    assert m * (m - 1) // 2 > MAX_CLOSE_PAIRS
    with pytest.raises(PatternError, match="closer than the tolerance"):
        CreasePattern(verts, edges, "B")


def test_the_cli_turns_each_into_one_line_and_exit_2(tmp_path, capsys):
    for k, data in enumerate(
        [
            with_(vertices_coords="x"),
            with_(edges_vertices=[[0, 1], [1, 2], [2, 3], [3, 0], [0, 1e30]]),
            '{"a": ' + "[" * 100_000 + "]" * 100_000 + "}",
        ]
    ):
        p = write(tmp_path, data, f"case{k}.fold")
        assert main(["check", str(p)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f"case{k}.fold" in err, err


@pytest.mark.parametrize("kind", ["long", "nul", "folder", "fifo", "device"])
def test_input_paths_that_are_not_regular_files(tmp_path, kind):
    import os

    from origami_cad.pattern import read_pattern
    from origami_cad.pattern.formats.dxf import read_dxf
    from origami_cad.pattern.formats.svg import read_svg

    path = {
        "long": tmp_path / ("n" * 400 + ".fold"),
        "nul": tmp_path / "a\x00b.fold",
        "folder": tmp_path / "folder.fold",
        "fifo": tmp_path / "pipe.fold",
        "device": "/dev/zero",
    }[kind]
    if kind == "folder":
        path.mkdir()
    if kind == "fifo":
        os.mkfifo(path)  # reading it would block for ever
    for reader in (read_fold, read_svg, read_dxf, read_fold_frames):
        with pytest.raises(PatternError) as info:
            reader(path)
        msg = str(info.value)
        assert msg.isprintable() and len(msg) < 400, msg
        assert any(w in msg for w in ("no such file", "not a regular file", "too long")), msg
    if kind != "device":
        with pytest.raises(PatternError):
            read_pattern(path)
