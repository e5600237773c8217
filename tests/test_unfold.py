"""Folded forms read from FOLD files written by other tools are unfolded into their crease
patterns: lengths kept, assignments and fold angles taken from the form, and the rigid
folder folds the recovered pattern back into the very form the file holds."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import shapely

from origami_cad.cli import main
from origami_cad.kinematics.generic import fold_degree4
from origami_cad.pattern import PatternError, read_fold
from origami_cad.pattern.unfold import fold_angles_of_form, unfold_faces

DATA = Path(__file__).parent / "data" / "fold"


def _form(name: str):
    data = json.loads((DATA / name).read_text())
    return data, np.array(data["vertices_coords"], dtype=float)


def _distances(x: np.ndarray) -> np.ndarray:
    return np.linalg.norm(x[:, None, :] - x[None, :, :], axis=-1)


@pytest.mark.parametrize("name", ["squaretwist.fold", "simple.fold", "box.fold"])
def test_every_face_keeps_its_shape_and_every_crease_its_length(name):
    data, xyz = _form(name)
    cp = read_fold(DATA / name)
    assert any(n.code == "unfolded" for n in cp.notes)
    assert len(cp.faces) == len(data["faces_vertices"])
    flat = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    # the reader keeps the file's vertex numbering; each face is congruent to its folded self
    for face in data["faces_vertices"]:
        np.testing.assert_allclose(_distances(flat[face]), _distances(xyz[face]), atol=1e-5)
    # the assignments are the file's own
    assert cp.assignments.tolist() == data["edges_assignment"]
    # the sheet is seen from its top (faces counter-clockwise) and does not overlap itself:
    # the faces' union is as large as their areas together
    polygons = [shapely.Polygon(cp.vertices[f]) for f in cp.faces]
    assert all(shapely.is_ccw(p.exterior) for p in polygons)
    total = sum(p.area for p in polygons)
    assert shapely.union_all(polygons).area == pytest.approx(total, rel=1e-6)


def test_the_square_twist_folds_back_into_the_form_the_file_holds():
    # Thomas Hull's rigidly folded square twist (Mathematica): unfolded, then folded
    # rigidly by the degree-4 folder to the same driving angle, it is the file's form
    _, xyz = _form("squaretwist.fold")
    cp = read_fold(DATA / "squaretwist.fold")
    twist = np.array([[0.25, 0.5], [0.5, 0.25], [0.75, 0.5], [0.5, 0.75]])
    assert all(np.min(np.linalg.norm(cp.vertices - t, axis=1)) < 1e-5 for t in twist)
    # the form's fold angles became the pattern's: valleys positive, mountains negative
    m, v = cp.edge_mask("M"), cp.edge_mask("V")
    assert np.all(cp.fold_angles[v] > 20) and np.all(cp.fold_angles[m] < -20)
    drive = int(np.flatnonzero(v)[0])
    p = abs(cp.fold_angles[drive]) / 180.0
    coords, angles = fold_degree4(cp, p, driving_edge=drive)
    np.testing.assert_allclose(angles[m | v], cp.fold_angles[m | v], atol=1e-3)
    np.testing.assert_allclose(_distances(coords), _distances(xyz), atol=1e-4)


def test_measured_fold_angles_follow_the_fold_convention():
    data, xyz = _form("squaretwist.fold")
    edges = np.array(data["edges_vertices"])
    angles = fold_angles_of_form(xyz, data["faces_vertices"], edges)
    letters = np.array(data["edges_assignment"])
    assert np.all(angles[letters == "V"] > 0) and np.all(angles[letters == "M"] < 0)
    assert np.all(np.isnan(angles[letters == "B"]))


def test_a_form_that_is_not_developable_is_refused_by_vertex(tmp_path):
    # a square pyramid's four sides around its apex: 4 x 60 deg of paper cannot lie flat
    apex = [0.0, 0.0, 1.0]
    base = [[1.0, 1.0, 0.0], [-1.0, 1.0, 0.0], [-1.0, -1.0, 0.0], [1.0, -1.0, 0.0]]
    xyz = np.array([apex, *base])
    faces = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]]
    with pytest.raises(PatternError, match=r"does not unfold flat: vertex \d lands at two"):
        unfold_faces(xyz, faces)
    path = tmp_path / "pyramid.fold"
    edges = [[0, 1], [0, 2], [0, 3], [0, 4], [1, 2], [2, 3], [3, 4], [4, 1]]
    path.write_text(
        json.dumps(
            {
                "frame_classes": ["foldedForm"],
                "vertices_coords": xyz.tolist(),
                "faces_vertices": faces,
                "edges_vertices": edges,
            }
        )
    )
    out = tmp_path / "cp.svg"
    assert main(["convert", str(path), str(out)]) == 2
    assert not out.exists()


def test_a_folded_form_without_faces_cannot_be_unfolded(tmp_path):
    path = tmp_path / "bent.fold"
    path.write_text(
        json.dumps(
            {
                "vertices_coords": [[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 1]],
                "edges_vertices": [[0, 1], [1, 2], [2, 3], [3, 0]],
            }
        )
    )
    with pytest.raises(PatternError, match="no folded form has faces_vertices to unfold"):
        read_fold(path)


def test_a_form_that_would_overlap_itself_when_flat_is_refused():
    # seven 55-degree triangles around one vertex, each beside the last: 385 degrees of
    # paper, so laid flat the seventh covers part of the first (paper lies in one layer)
    angles = np.radians(np.arange(0, 386, 55.0))
    xyz = np.vstack(
        [[0.0, 0.0, 0.0], np.column_stack([np.cos(angles), np.sin(angles), 0 * angles])]
    )
    faces = [[0, k, k + 1] for k in range(1, len(angles))]
    with pytest.raises(PatternError, match="does not unfold into one layer: faces 0 and 6"):
        unfold_faces(xyz, faces)
    # six of them (330 degrees) lie flat
    assert unfold_faces(xyz[:-1], faces[:-1]).shape == (len(xyz) - 1, 2)


def _write_form(path: Path, xyz, faces, edges=None, letters=None) -> Path:
    doc = {"frame_classes": ["foldedForm"], "vertices_coords": np.asarray(xyz).tolist()}
    doc["faces_vertices"] = faces
    if edges is None:
        edges = sorted({tuple(sorted((f[k], f[(k + 1) % len(f)]))) for f in faces for k in
                        range(len(f))})  # fmt: skip
    doc["edges_vertices"] = [list(e) for e in edges]
    if letters is not None:
        doc["edges_assignment"] = letters
    path.write_text(json.dumps(doc))
    return path


def test_a_concave_face_keeps_its_shape(tmp_path):
    # an L-shaped face standing on a square's edge (folded 90 degrees), listed from its
    # inner corner: laid flat it must stay an L, not fold its arm over onto the square
    square = [[0, 0, 0], [10, 0, 0], [10, 20, 0], [0, 20, 0]]
    ell = [[10, 20, 20], [10, 10, 20], [10, 10, 10], [10, 0, 10]]  # vertices 4-7
    xyz = np.array(square + ell, dtype=float)
    faces = [[0, 1, 2, 3], [6, 5, 4, 2, 1, 7]]
    flat = unfold_faces(xyz, faces)
    for face in faces:
        np.testing.assert_allclose(_distances(flat[face]), _distances(xyz[face]), atol=1e-9)
    polygons = [shapely.Polygon(flat[f]) for f in faces]
    assert all(p.is_valid for p in polygons)
    assert shapely.union_all(polygons).area == pytest.approx(10 * 20 + 300.0)
    cp = read_fold(_write_form(tmp_path / "ell.fold", xyz, faces))
    assert cp.n_vertices == len(xyz) and len(cp.faces) == 2


def test_faces_listed_either_way_round_give_the_same_fold(tmp_path):
    # a 30 degree valley: the second face listed clockwise or counter-clockwise
    t = np.radians(30.0)
    c, z = 10 + 10 * np.cos(t), 10 * np.sin(t)
    xyz = [[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0], [c, 0, z], [c, 10, z]]
    edge = np.array([[1, 2]])
    same = fold_angles_of_form(xyz, [[0, 1, 2, 3], [1, 4, 5, 2]], edge)
    other = fold_angles_of_form(xyz, [[0, 1, 2, 3], [2, 5, 4, 1]], edge)
    np.testing.assert_allclose(same, [30.0], atol=1e-9)
    np.testing.assert_allclose(other, same, atol=1e-9)


@pytest.mark.parametrize(
    ("faces", "match"),
    [
        ([[0, 1, 2, 3], [1, 0, 4], [1, 0, 5]], "borders 3 faces"),
        ([[0, 1, 2, 0, 3]], "lists a vertex twice"),
    ],
)
def test_faces_that_are_no_sheet_of_paper_are_refused(faces, match):
    xyz = np.array([[0, 0, 0], [100, 0, 0], [100, 100, 0], [0, 100, 0], [50, -1, 1],
                    [50, -1, -1]], dtype=float)  # fmt: skip
    with pytest.raises(PatternError, match=match):
        unfold_faces(xyz, faces)
