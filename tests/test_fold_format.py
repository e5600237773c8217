"""FOLD 1.2 reading and writing."""

from __future__ import annotations

import json

import numpy as np
import pytest

from origami_cad.pattern import (
    CreasePattern,
    Hole,
    PatternError,
    folded_frame,
    miura_pattern,
    read_fold,
    read_fold_frames,
    read_pattern,
    write_fold,
    write_pattern,
)


def test_round_trip_keeps_graph_angles_labels_and_holes(tmp_path):
    cp = miura_pattern(4, 6, 20.0, 30.0, 60.0)
    face = cp.face_index("c1r0s3")
    cx, cy = cp.face_centroids()[face]
    cp = cp.with_holes([Hole(cx, cy, 2.5)]).with_metadata(title="test miura")
    path = write_fold(cp, tmp_path / "m.fold")
    back = read_fold(path)
    assert back.same_graph(cp, tolerance=1e-9)
    assert back.face_labels == cp.face_labels
    assert back.holes == cp.holes
    assert back.title == "test miura"
    data = json.loads(path.read_text())
    assert data["file_spec"] == 1.2
    assert data["frame_unit"] == "mm"
    assert data["file_creator"].startswith("origami_cad")
    assert len(data["faces_vertices"]) == len(cp.faces)
    assert data["faces_origami_cad:holes"][face] == [[cx, cy, 2.5]]
    # valley positive, mountain negative
    angles = dict(zip(data["edges_assignment"], data["edges_foldAngle"], strict=False))
    assert angles["V"] == 180 and angles["M"] == -180


def test_dispatch_by_extension(tmp_path):
    cp = miura_pattern(2, 2, 30.0, 10.0, 45.0)
    write_pattern(cp, tmp_path / "a.fold")
    assert read_pattern(tmp_path / "a.fold").same_graph(cp)
    with pytest.raises(PatternError, match=r"unknown crease-pattern format '\.txt'"):
        read_pattern(tmp_path / "a.txt")


def test_folded_frames_share_indexing(tmp_path):
    cp = miura_pattern(2, 2, 30.0, 10.0, 45.0)
    coords = np.column_stack([cp.vertices, np.linspace(0, 1, cp.n_vertices)])
    write_fold(cp, tmp_path / "f.fold", frames=[folded_frame(coords, cp.fold_angles / 2)])
    data = json.loads((tmp_path / "f.fold").read_text())
    frame = data["file_frames"][0]
    assert frame["frame_classes"] == ["foldedForm"] and frame["frame_inherit"] is True
    frames = read_fold_frames(tmp_path / "f.fold")
    np.testing.assert_allclose(frames[1], coords, atol=1e-12)
    assert read_fold(tmp_path / "f.fold").same_graph(cp)


def test_file_from_another_tool_without_faces_and_old_key(tmp_path):
    data = {
        "file_spec": 1.1,
        "vertices_coords": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
        "edges_vertices": [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]],
        "edges_foldAngles": [0, 0, 0, 0, -90],
        "frame_unit": "cm",
    }
    p = tmp_path / "other.fold"
    p.write_text(json.dumps(data))
    cp = read_fold(p)
    assert len(cp.faces) == 2  # computed
    assert cp.bounds == (0.0, 0.0, 10.0, 10.0)  # cm -> mm
    # no assignments: taken from the fold-angle sign
    assert sorted(cp.assignments.tolist()) == ["M", "U", "U", "U", "U"]
    assert cp.fold_angles[cp.assignments == "M"].tolist() == [-90.0]


@pytest.mark.parametrize(
    "content, message",
    [
        ("{not json", "not valid JSON"),
        ('{"vertices_coords": [[0, 0], [1, 0]]}', "no edges"),
        ('{"vertices_coords": [[0, 0], [1, 0]], "edges_vertices": []}', "is empty"),
        ("[1, 2]", "must hold a JSON object"),
        (
            '{"vertices_coords": [[0, 0], [1, 0]], "edges_vertices": [[0, 5]]}',
            "refers to vertex",
        ),
        (
            '{"vertices_coords": [[0,0],[1,0]], "edges_vertices": [[0,1]], '
            '"edges_foldAngle": [270]}',
            "within \\[-180, 180\\]",
        ),
    ],
)
def test_malformed_files_name_the_file_and_problem(tmp_path, content, message):
    p = tmp_path / "bad.fold"
    p.write_text(content)
    with pytest.raises(PatternError, match=message) as info:
        read_fold(p)
    assert "bad.fold" in str(info.value)


def test_missing_file(tmp_path):
    with pytest.raises(PatternError, match="no such file"):
        read_pattern(tmp_path / "nothing.fold")


def test_writer_leaves_no_partial_file(tmp_path):
    cp = CreasePattern([[0, 0], [1, 0], [1, 1]], [[0, 1], [1, 2], [2, 0]], "B")
    cp = cp.with_holes([Hole(50.0, 50.0, 1.0)])  # outside every panel: writing fails
    target = tmp_path / "x.fold"
    with pytest.raises(PatternError, match="not on any panel"):
        write_fold(cp, target)
    assert not target.exists()
    assert list(tmp_path.iterdir()) == []
