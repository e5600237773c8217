"""Kirigami: a cut with a panel on both sides parts as the pattern folds.

The general folder opens such cuts (Origami Simulator splits them): each side gets its own
copy of the cut's vertices, so flaps the cut separates fold on their own creases. A
printed panel that would be a ring around another part is split in two by printing two of
its facet creases as hinges (warned, naming them), or refused saying why that fails.
"""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely
import trimesh

from origami_cad.cli import main
from origami_cad.errors import PatternError
from origami_cad.fabrication import FabricationParams, fabricate, write_fabrication
from origami_cad.fabrication.panels import CUT_GAP, sheet_outline
from origami_cad.fabrication.plan import plan_panels
from origami_cad.fabrication.solids import PART_NAMES
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.folder import StrainWarning, fold_general

SIM = Path(__file__).parent / "data" / "origami-simulator"


def _flaps() -> CreasePattern:
    """A 100 mm square: a valley below and a mountain above the middle of x = 50, and a
    cut from the left border to that middle: the left half's two flaps fold apart."""
    verts = [[0, 0], [50, 0], [100, 0], [100, 100], [50, 100], [0, 100], [0, 50], [50, 50]]
    edges = [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 6], [6, 0], [1, 7], [7, 4], [6, 7]]
    return CreasePattern(verts, edges, ["B"] * 7 + ["V", "M", "C"])


def test_opening_a_cut_gives_its_sides_their_own_vertices():
    cp = _flaps()
    opened = cp.with_cuts_opened()
    assert opened.n_vertices == cp.n_vertices + 1  # (0, 50): the cut's free end parts
    assert opened.n_edges == cp.n_edges + 1  # the cut's second side
    np.testing.assert_array_equal(opened.vertices[: cp.n_vertices], cp.vertices)
    np.testing.assert_array_equal(opened.vertices[-1], [0.0, 50.0])
    np.testing.assert_array_equal(opened.assignments[: cp.n_edges], cp.assignments)
    assert opened.assignments[-1] == "C"
    for ring, sides in zip(opened.faces, opened.face_edges, strict=True):
        for k, e in enumerate(sides):
            assert set(opened.edges[e]) == {ring[k], ring[(k + 1) % len(ring)]}
    cuts = opened.edge_mask("C")
    faces_per_edge = np.bincount(np.concatenate(opened.face_edges), minlength=opened.n_edges)
    assert np.all(faces_per_edge[cuts] == 1)  # each side of the cut borders one panel


def test_a_pattern_without_inner_cuts_is_itself():
    square = CreasePattern(
        [[0, 0], [100, 0], [100, 100], [0, 100]], [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]], "BBBBV"
    )
    assert square.with_cuts_opened() is square


def test_flaps_fold_apart_once_the_cut_opens():
    cp = _flaps()
    (state,) = fold_general(cp, [0.3])
    assert state.pattern.n_vertices == cp.n_vertices + 1
    assert state.fold_angles[7] > 40.0 and state.fold_angles[8] < -40.0  # V and M, deg
    assert state.strain < 1.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", StrainWarning)
        (joined,) = fold_general(cp, [0.3], cuts_open=False)
    assert joined.coords.shape == (cp.n_vertices, 3)
    # joined, the left half is one panel: it bends a little, the creases hardly turn
    assert abs(joined.fold_angles[7]) < 20.0 and abs(joined.fold_angles[8]) < 20.0


def test_miyamoto_tower_folds(tmp_path):
    """Origami Simulator's kirigami tower: every crease turns, nothing stretches."""
    out = tmp_path / "tower.fold"
    src = SIM / "miyamotoTower.svg"
    assert main(["fold", str(src), "--width", "150", "--ratio", "0.3", "-o", str(out)]) == 0
    doc = json.loads(out.read_text())
    flat = np.array(doc["vertices_coords"], float)
    folded = np.array(doc["file_frames"][-1]["vertices_coords"], float)
    edges = np.array(doc["edges_vertices"])
    rest = np.linalg.norm(flat[edges[:, 1]] - flat[edges[:, 0]], axis=1)
    now = np.linalg.norm(folded[edges[:, 1]] - folded[edges[:, 0]], axis=1)
    assert np.max(np.abs(now - rest) / rest) < 0.05
    creases = np.isin(doc["edges_assignment"], ["M", "V"])
    angles = np.abs(np.array(doc["file_frames"][-1]["edges_foldAngle"], float))
    assert np.mean(angles[creases] > 5.0) >= 0.5


def _frame(assign: str = "BBBB" + "VCCC" + "FFFF") -> CreasePattern:
    """A frame of four faces joined by facet creases around a square flap hinged on a
    valley and cut on its other sides: the printed frame would be a panel with a hole."""
    v = [(0, 0), (90, 0), (90, 90), (0, 90), (30, 30), (60, 30), (60, 60), (30, 60)]
    e = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4)]
    e += [(0, 4), (1, 5), (2, 6), (3, 7)][: len(assign) - 8]
    return CreasePattern(v, e, assign)


def test_a_ring_panel_is_split_by_two_facet_creases_printed_as_hinges_and_warned():
    cp = _frame()
    plan = plan_panels(cp)
    said = [w for w in plan.warnings if "encloses another part" in w]
    assert len(said) == 1 and said[0].endswith("which splits the rings in two")
    named = [int(m) for m in re.findall(r"\be(\d+) \(", said[0])]
    assert len(named) == 2 and all(cp.assignments[k] == "F" for k in named)
    assert len(plan.pattern.faces) == 3  # the flap and the frame's two halves
    hinges = plan.pattern.edges[plan.pattern.assignments == "J"]
    assert {frozenset(h) for h in hinges.tolist()} == {frozenset(cp.edges[k]) for k in named}
    joined = cp.assignments.copy()
    joined[named] = "J"
    alike = plan_panels(CreasePattern(cp.vertices, cp.edges, joined))  # the same sheet
    for a, b in zip(plan.outlines, alike.outlines, strict=True):
        np.testing.assert_array_equal(a.outer, b.outer)


def test_a_ring_panel_that_cannot_be_split_or_print_split_is_refused_saying_why():
    no_facet = r"encloses another part .* mm: no two facet creases cross the ring .*F"
    with pytest.raises(PatternError, match=no_facet):
        plan_panels(_frame("BBBB" + "VCCC"))  # no facet crease to split the frame
    with pytest.raises(PatternError, match=r"splits the rings in two, but then .*--width"):
        plan_panels(_frame().scaled(0.02))  # split, but 1.8 mm wide: too small to print


def _half_cut() -> CreasePattern:
    """A 100 mm square folded on a valley along y = 50 from x = 50 on, and cut along it
    before: a hinge and a cut on one line, meeting at (50, 50)."""
    verts = [[0, 0], [100, 0], [100, 50], [100, 100], [0, 100], [0, 50], [50, 50]]
    edges = [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 0], [5, 6], [6, 2]]
    return CreasePattern(verts, edges, "BBBBBBCV")


def test_a_hinge_and_a_cut_on_one_line_fabricate_apart_and_watertight(tmp_path):
    cp = _half_cut()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fab = fabricate(cp)
    for name in PART_NAMES:
        assert all(s.is_valid for s in fab.parts.solids[name]), name
    paths = write_fabrication(fab, tmp_path)
    for name in PART_NAMES:  # one watertight mesh per part, welded by position
        mesh = trimesh.load(paths[name])
        assert mesh.is_watertight and mesh.is_winding_consistent, name
        _, uses = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
        assert set(uses.tolist()) == {2}, name
    # each panel's halves stop CUT_GAP / 2 short of the cut, and jog to the hinge's chamfer
    cut = shapely.LineString([(0, 50), (50, 50)])
    for o in fab.outlines:
        for ring in (o.inner, o.outer):
            near = shapely.Polygon(ring).intersection(shapely.box(0, 40, 49.9, 60))
            assert near.distance(cut) == pytest.approx(CUT_GAP / 2, abs=1e-9)
        assert len(o.inner) == len(o.outer) == len(o.polygon) + 1  # the jog's two corners
    # the crease sheet parts along the cut, not along the hinge
    sheet = sheet_outline(fab.pattern)
    assert not sheet.contains(shapely.Point(25, 50)) and sheet.contains(shapely.Point(75, 50))
    assert len(shapely.get_parts(fab.parts.prisms["creases"][0][0])) == 1


def test_a_hinge_beside_a_free_edge_takes_no_border_margin():
    with pytest.raises(PatternError, match=r"hinge and a free edge on one line .*border_margin"):
        plan_panels(_half_cut(), FabricationParams(border_margin=0.5))
