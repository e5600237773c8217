"""The crease-pattern model: normalisation, faces, validation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from origami_cad.pattern import CreasePattern, Hole, PatternError, Severity, miura_pattern

SQUARE = np.array([[0, 0], [100, 0], [100, 100], [0, 100]], dtype=float)
BORDER = [[0, 1], [1, 2], [2, 3], [3, 0]]


def codes(cp: CreasePattern, severity: Severity = Severity.ERROR) -> list[str]:
    return [p.code for p in cp.check() if p.severity == severity]


def test_diagonal_fold_faces_and_defaults():
    cp = CreasePattern(SQUARE, [*BORDER, [0, 2]], ["B"] * 4 + ["V"])
    assert len(cp.faces) == 2
    np.testing.assert_allclose(sorted(cp.face_areas()), [5000.0, 5000.0])
    assert cp.fold_angles.tolist() == [0, 0, 0, 0, 180.0]
    # faces are counter-clockwise and every side is an edge
    for ring, sides in zip(cp.faces, cp.face_edges, strict=True):
        xy = cp.vertices[ring]
        area = 0.5 * np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - xy[:, 1] * np.roll(xy[:, 0], -1))
        assert area > 0
        assert (sides >= 0).all()
    # the diagonal separates the two faces
    ef = cp.edge_faces()
    assert (ef[cp.assignments == "V"] >= 0).all()
    assert codes(cp) == []


def test_assignments_as_one_letter_a_string_of_letters_or_a_list():
    edges = [*BORDER, [0, 2]]
    assert CreasePattern(SQUARE, edges, "BBBBV").assignments.tolist() == ["B"] * 4 + ["V"]
    assert CreasePattern(SQUARE, edges, "u").assignments.tolist() == ["U"] * 5
    with pytest.raises(PatternError, match="4 assignments given for 5 edges"):
        CreasePattern(SQUARE, edges, "BBBV")
    with pytest.raises(PatternError, match="'VV' is not one letter"):
        CreasePattern(SQUARE, edges, ["B", "B", "B", "B", "VV"])


def test_snapping_merges_close_vertices_and_reports_it():
    verts = np.vstack([SQUARE, [[100 + 1e-8, 100 - 1e-8], [50, 50]]])
    edges = [*BORDER, [0, 4]]  # diagonal ends at a near-duplicate of vertex 2
    cp = CreasePattern(verts, edges, ["B"] * 4 + ["M"])
    assert cp.n_vertices == 4  # the near-duplicate merged, the unused vertex dropped
    assert cp.n_edges == 5
    assert any(p.code == "merged" and "merged" in p.message for p in cp.notes)
    assert cp.cleanup.merged == 1 and 0 < cp.cleanup.merged_gap < 2e-8


def test_crossing_and_t_junction_are_split():
    verts = np.vstack([SQUARE, [[50, 0], [50, 100]]])
    edges = [*BORDER, [0, 2], [1, 3], [4, 5]]  # two diagonals and a vertical line
    cp = CreasePattern(verts, edges, ["B"] * 4 + ["V", "V", "M"])
    # the crossing point (50, 50) became one vertex shared by all three lines
    centre = np.flatnonzero(np.all(np.isclose(cp.vertices, [50, 50]), axis=1))
    assert len(centre) == 1
    deg = np.bincount(cp.edges.ravel())[centre[0]]
    assert deg == 6
    # the T-junctions at (50, 0) and (50, 100) split the border edges
    assert np.sum(cp.assignments == "B") == 6
    assert len(cp.faces) == 6


def test_duplicates_in_either_direction_are_dropped_with_conflicts_reported():
    cp = CreasePattern(SQUARE, [*BORDER, [0, 2], [2, 0], [0, 2]], ["B"] * 4 + ["V", "V", "M"])
    assert cp.n_edges == 5
    conflict = [p for p in cp.notes if p.code == "duplicate-conflict"]
    assert conflict and conflict[0].severity == Severity.WARNING
    assert conflict[0].location == (50.0, 50.0)


def test_overlapping_collinear_edges_become_one_chain():
    verts = np.array([[0, 0], [10, 0], [5, 0], [15, 0]], float)
    cp = CreasePattern(verts, [[0, 1], [2, 3]], "M")
    xs = sorted(cp.vertices[:, 0].tolist())
    assert xs == [0, 5, 10, 15]
    assert cp.n_edges == 3


def test_normalisation_scales_as_n_log_n_on_large_input():
    # correctness on a large input; speed is measured in benchmarks/
    cp = miura_pattern(30, 30, 10.0, 10.0, 60.0)
    assert cp.n_edges == 30 * 31 + 31 * 30
    assert len(cp.faces) == 900
    assert codes(cp) == []


def test_miura_is_flat_foldable_everywhere():
    cp = miura_pattern(4, 6, 20.0, 30.0, 60.0)
    # 120 x 120 mm between the main-crease ends; the zigzag ends lean by h cot(60 deg)
    x0, y0, x1, y1 = cp.bounds
    assert (x0, y0, y1) == (0.0, 0.0, 120.0)
    assert x1 == pytest.approx(120.0 + 30.0 / math.tan(math.radians(60.0)))
    assert cp.check() == []
    assert len(set(cp.face_labels)) == 24
    assert cp.face_labels[0] == "c0r0s0"


@pytest.mark.parametrize("assign, code", [("MMVV", "maekawa"), ("MMMM", "maekawa")])
def test_maekawa_violation_is_located(assign, code):
    verts = np.array(
        [[0, 0], [100, 0], [100, 100], [0, 100], [50, 0], [100, 50], [50, 100], [0, 50], [50, 50]],
        float,
    )
    edges = [[0, 4], [4, 1], [1, 5], [5, 2], [2, 6], [6, 3], [3, 7], [7, 0]]
    edges += [[8, 4], [8, 5], [8, 6], [8, 7]]
    cp = CreasePattern(verts, edges, ["B"] * 8 + list(assign))
    found = [p for p in cp.check() if p.code == code]
    assert len(found) == 1
    assert found[0].location == (50.0, 50.0)
    assert "vertex" in found[0].message


def test_kawasaki_violation_measures_the_defect():
    # degree-4 vertex whose fourth crease is bent 10 degrees off the straight line
    c = np.array([50.0, 50.0])
    tips = np.array([[100, 50], [50, 100], [0, 50], [50 + 50 / math.tan(math.radians(80)), 0]])
    verts = np.vstack([SQUARE, c, tips])
    edges = [*BORDER, [4, 5], [4, 6], [4, 7], [4, 8]]
    cp = CreasePattern(verts, edges, ["B"] * 4 + ["M", "M", "M", "V"])
    kaw = [p for p in cp.check() if p.code == "kawasaki"]
    assert len(kaw) == 1
    assert "by 10 deg" in kaw[0].message
    assert kaw[0].location == (50.0, 50.0)
    assert "maekawa" not in codes(cp)


def test_dangling_crease_is_reported():
    verts = np.vstack([SQUARE, [[50, 50], [100, 50]]])
    cp = CreasePattern(verts, [*BORDER, [4, 5]], ["B"] * 4 + ["V"])
    found = [p for p in cp.check() if p.code == "dangling-crease"]
    assert found and found[0].location == (50.0, 50.0)


def test_open_and_self_crossing_border_are_reported():
    open_cp = CreasePattern(SQUARE, BORDER[:3], "B")
    assert "open-border" in codes(open_cp)
    bowtie = np.array([[0, 0], [100, 100], [100, 0], [0, 100]], float)
    cross = CreasePattern(bowtie, [[0, 1], [1, 2], [2, 3], [3, 0]], "B")
    problems = [p for p in cross.check() if p.code == "border-crossing"]
    assert problems and problems[0].location == (50.0, 50.0)


def test_bad_input_is_named():
    with pytest.raises(PatternError, match="edge 1 refers to vertex"):
        CreasePattern(SQUARE, [[0, 1], [1, 9]], "B")
    with pytest.raises(PatternError, match="unknown assignment 'X'"):
        CreasePattern(SQUARE, BORDER, ["B", "B", "X", "B"])
    with pytest.raises(PatternError, match="no edges"):
        CreasePattern(SQUARE, np.zeros((0, 2)), "B")
    with pytest.raises(PatternError, match="non-finite"):
        CreasePattern([[0, 0], [math.nan, 1]], [[0, 1]], "B")
    with pytest.raises(PatternError, match="not flat"):
        CreasePattern([[0, 0, 0], [1, 0, 1]], [[0, 1]], "B")
    with pytest.raises(PatternError, match="diameter"):
        Hole(1.0, 2.0, -1.0)


def test_holes_and_labels_ride_along():
    cp = miura_pattern(2, 3, 20.0, 20.0, 60.0)
    face = cp.face_index("c0r1s1")
    cx, cy = cp.face_centroids()[face]
    cp2 = cp.with_holes([Hole(cx, cy, 2.0)])
    assert cp2.face_of_point(cx, cy) == face
    assert cp2.holes[0].diameter == 2.0
    assert cp.holes == ()
    with pytest.raises(PatternError, match="no panel labelled"):
        cp.face_index("nope")


def test_faces_of_points_is_face_of_point_for_each():
    from origami_cad.pattern.design import miura_design

    cp = miura_design(3, 4, 15.0, 20.0, 70.0).pattern
    x0, y0, x1, y1 = cp.bounds
    rng = np.random.default_rng(5)
    points = np.column_stack([rng.uniform(x0 - 2, x1 + 2, 400), rng.uniform(y0 - 2, y1 + 2, 400)])
    points = np.vstack([points, cp.vertices])  # on the edges: no face contains them
    want = [cp.face_of_point(x, y) for x, y in points]
    assert cp.faces_of_points(points).tolist() == want
    assert cp.faces_of_points(np.zeros((0, 2))).shape == (0,)
