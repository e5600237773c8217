"""The general folder: every crease driven toward its target on the bar-and-hinge model.

Patterns the closed form cannot fold (several degrees of freedom, vertices of any
degree, facet and unassigned creases) fold with all their creases, and the closed form
stays where it applies.
"""

from __future__ import annotations

import json
import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from origami_cad.cli import main
from origami_cad.errors import PatternError
from origami_cad.kinematics.folding import fold_design
from origami_cad.pattern import read_pattern
from origami_cad.pattern.design import Design, miura_design
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.folder import (
    STRAIN_LIMIT,
    StrainWarning,
    closed_form_applies,
    fold,
    fold_general,
    fold_states,
)
from origami_cad.simulation.model import SimulationParams

SIM = Path(__file__).parent / "data" / "origami-simulator"


def _edge_strain(cp: CreasePattern, coords: np.ndarray) -> float:
    """The largest relative change of a pattern edge's length (a fraction)."""
    flat = np.linalg.norm(np.diff(cp.vertices[cp.edges], axis=1)[:, 0], axis=1)
    folded = np.linalg.norm(np.diff(coords[cp.edges], axis=1)[:, 0], axis=1)
    return float(np.max(np.abs(folded - flat) / flat))


def test_a_waterbomb_tessellation_folds_every_crease_the_closed_form_refuses():
    cp = read_pattern(SIM / "waterbomb.svg", width=150)
    assert not closed_form_applies(Design(cp, None, "file"))
    state = fold(cp, 0.3)
    assert state.method == "general"
    creases = cp.edge_mask("M", "V")
    turned = np.abs(state.fold_angles[creases]) > 5.0
    assert turned.mean() > 0.9
    # nearly every crease turns the way its letter says (valley positive); a few pop the
    # other way, as a waterbomb's flat state lets them
    sign = np.where(cp.assignments[creases] == "V", 1.0, -1.0)
    assert np.mean(state.fold_angles[creases] * sign > 5.0) > 0.9
    # the panels barely stretch, and the state says by how much
    assert _edge_strain(cp, state.coords) * 100 <= state.strain + 1e-9
    assert state.strain < 0.5


def test_the_closed_form_stays_where_it_applies():
    design = miura_design(4, 4, 20.0, 15.0, 70.0)
    assert closed_form_applies(design)
    state = fold(design, 0.4)
    exact = fold_design(design, 0.4)
    assert state.method == "closed form" and state.strain == 0.0
    np.testing.assert_array_equal(state.coords, exact.coords)
    np.testing.assert_array_equal(state.fold_angles, exact.fold_angles)


def test_on_a_rigidly_foldable_pattern_the_general_fold_is_a_rigid_folding():
    # a Miura sheet folds with one degree of freedom: driven toward +-180 p deg on every
    # crease, the springs settle on one state of the rigid folding (the closed form's)
    from scipy.optimize import brentq

    design = miura_design(2, 2, 20.0, 15.0, 70.0)
    state = fold_general(design.pattern, [0.3])[0]
    assert state.strain < 1e-3
    creases = design.pattern.edge_mask("M", "V")
    e = int(np.flatnonzero(creases)[0])
    reached = abs(state.fold_angles[e])
    assert reached > 5.0
    q = brentq(lambda r: abs(fold_design(design, r).fold_angles[e]) - reached, 0.0, 1.0)
    exact = fold_design(design, q).fold_angles
    np.testing.assert_allclose(state.fold_angles[creases], exact[creases], atol=0.05)


def _one_crease(angle: float | None, second: str = "B") -> CreasePattern:
    """Two 20 x 20 mm panels on a valley crease x = 20 (fold angle ``angle`` deg, or the
    default), each split by a diagonal of assignment ``second``."""
    v = [(0, 0), (20, 0), (40, 0), (40, 20), (20, 20), (0, 20)]
    edges = [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 0), (1, 4)]
    letters = ["B"] * 6 + ["V"]
    angles = [0.0] * 6 + [180.0 if angle is None else angle]  # 180: a valley's default
    if second != "B":
        edges += [(0, 4), (1, 3)]
        letters += [second, second]
        angles += [0.0, 0.0]
    return CreasePattern(v, edges, letters, angles)


def test_each_crease_goes_to_its_files_fold_angle_times_the_ratio():
    cp = _one_crease(60.0)
    crease = int(np.flatnonzero(cp.edge_mask("V"))[0])
    states = fold_general(cp, [1.0, 0.5])  # any order: one continuation
    assert [s.p for s in states] == [1.0, 0.5]
    assert states[0].fold_angles[crease] == pytest.approx(60.0, abs=1e-3)
    assert states[1].fold_angles[crease] == pytest.approx(30.0, abs=1e-3)
    # without a fold angle in the file: +180 for a valley (capped short of the wrap)
    assert fold_general(_one_crease(None), [0.5])[0].fold_angles[crease] == pytest.approx(
        90.0, abs=1e-3
    )


def test_facet_creases_stay_flat_and_stiff():
    cp = _one_crease(None, second="F")
    state = fold_general(cp, [0.5])[0]
    facets = cp.edge_mask("F")
    assert facets.sum() == 2
    assert np.all(np.abs(state.fold_angles[facets]) < 0.01)
    assert state.fold_angles[cp.edge_mask("V")][0] == pytest.approx(90.0, abs=0.01)


def _vertex(odd: str) -> CreasePattern:
    """One interior vertex of an 80 x 80 mm square: creases at 0, 60, 160 and 280 deg
    (sectors 60, 100, 120, 80: flat-foldable), valleys but the one at 60 deg, ``odd``
    (a mountain makes it fold rigidly: one opposite pair the same, the other not)."""
    verts, edges, letters = [(0.0, 0.0)], [], []
    for k, a in enumerate((0.0, 60.0, 160.0, 280.0)):
        d = np.array([math.cos(math.radians(a)), math.sin(math.radians(a))])
        verts.append(tuple(40.0 / np.max(np.abs(d)) * d))  # on the square's side
        edges.append((0, k + 1))
        letters.append(odd if k == 1 else "V")
    verts += [(40.0, 40.0), (-40.0, 40.0), (-40.0, -40.0), (40.0, -40.0)]
    ring = sorted(range(1, len(verts)), key=lambda i: math.atan2(verts[i][1], verts[i][0]))
    edges += list(zip(ring, ring[1:] + ring[:1], strict=True))
    letters += ["B"] * len(ring)
    return CreasePattern(verts, edges, letters)


def test_an_unassigned_crease_is_a_free_hinge_a_facet_crease_is_not():
    # three valleys and one unassigned crease: the free hinge folds as the vertex needs
    # (as a mountain, with no target of its own) and the valleys fold
    cp = _vertex("U")
    free = fold_general(cp, [0.3])[0]
    u = int(np.flatnonzero(cp.edge_mask("U"))[0])
    valleys = cp.edge_mask("V")
    assert free.fold_angles[u] < -5.0
    assert np.all(free.fold_angles[valleys] > 5.0)
    assert free.strain < 0.01
    # a facet crease there leaves a degree-3 vertex, rigid unless its panels bend: the
    # stiffened drive bends them (as Origami Simulator bends its facets), and the facet
    # crease bends as a panel does, far less than the free hinge turned, with no stretch
    cp = _vertex("F")
    stiff = fold_general(cp, [0.3])[0]
    facet = int(np.flatnonzero(cp.edge_mask("F"))[0])
    assert abs(stiff.fold_angles[facet]) < 0.7 * abs(free.fold_angles[u])
    assert np.all(stiff.fold_angles[valleys] > 5.0)
    assert stiff.strain < 0.5  # percent: the panels bend, they barely stretch


def test_a_strain_over_the_limit_warns_and_says_by_how_much():
    # four valleys round one flat vertex cannot fold without stretching or bending the
    # panels: on very soft panels they stretch, and the fold says so
    cp = _vertex("V")
    soft = SimulationParams(panel_modulus=1e-6)
    with pytest.warns(StrainWarning, match=r"stretches an edge by [\d.]+ %, over the 5 % limit"):
        state = fold_general(cp, [0.5], params=soft)[0]
    assert state.strain > STRAIN_LIMIT
    assert _edge_strain(cp, state.coords) * 100 <= state.strain + 1e-9
    with warnings.catch_warnings():
        warnings.simplefilter("error", StrainWarning)
        assert fold_general(cp, [0.5])[0].strain < STRAIN_LIMIT  # printed panels: no warning


def test_bad_ratios_and_methods_are_refused():
    cp = _one_crease(None)
    with pytest.raises(PatternError, match=r"p: expected a finite number in \[0, 1\], got 1.5"):
        fold(cp, 1.5)
    with pytest.raises(PatternError, match="fold method must be one of"):
        fold_states(cp, [0.5], method="rigid")
    with pytest.raises(PatternError, match="no mountain or valley crease"):
        fold_general(
            CreasePattern([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1), (1, 2), (2, 3), (3, 0)], "B"),
            [0.5],
        )


def test_fold_writes_the_general_folding_as_frames_and_says_how(tmp_path, capsys):
    out = tmp_path / "w.fold"
    argv = ["fold", str(SIM / "birdBase.svg"), "--width", "150", "--ratio", "0.3"]
    assert main([*argv, "--frames", "3", "-o", str(out)]) == 0
    said = capsys.readouterr().out
    assert re.search(r"3 states, p up to 0\.3; general, largest strain [\d.e-]+ %", said), said
    frames = json.loads(out.read_text())["file_frames"]
    assert len(frames) == 3
    cp = read_pattern(out)
    angles = np.abs(np.array(frames[-1]["edges_foldAngle"], dtype=float))
    assert np.mean(angles[cp.edge_mask("M", "V")] > 5.0) > 0.5
    first = np.array(frames[0]["vertices_coords"], dtype=float)
    assert np.ptp(first[:, 2]) < 1e-6  # p = 0: flat


def test_fold_renders_a_general_folding(tmp_path):
    out = tmp_path / "w.png"
    argv = ["fold", str(SIM / "squareBase.svg"), "--width", "150", "--ratio", "0.3"]
    assert main([*argv, "-o", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_asking_for_the_closed_form_where_it_does_not_apply_is_one_line(tmp_path, capsys):
    out = tmp_path / "w.fold"
    argv = ["fold", str(SIM / "birdBase.svg"), "--method", "closed-form", "-o", str(out)]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "vertex" in err[0]
    assert not out.exists()


def test_a_dangling_creases_far_end_moves_with_its_panel():
    # two panels on a valley, and a mountain crease from the valley's middle into the left
    # panel that ends there: its far end is on no panel's outline, and folds with the panel
    v = [(0, 0), (20, 0), (40, 0), (40, 20), (20, 20), (0, 20), (20, 10), (8, 10)]
    edges = [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 0), (1, 6), (6, 4), (6, 7)]
    cp = CreasePattern(v, edges, ["B"] * 6 + ["V", "V", "M"])
    state = fold_general(cp, [0.5])[0]
    assert state.strain < 0.01  # every pattern edge keeps its length, the dangling one too
    assert _edge_strain(cp, state.coords) * 100 <= state.strain + 1e-9
    assert abs(state.fold_angles[cp.edge_mask("V")][0]) == pytest.approx(90.0, abs=0.05)


@pytest.mark.parametrize("name", ["openSinkBase", "traditionalCrane", "popupSimple"])
def test_patterns_whose_panels_must_bend_fold_most_creases(name):
    # none of these folds rigidly from flat: the printed creases alone leave them nearly
    # flat, the stiffened drive bends the panels, as Origami Simulator does, and the
    # panels barely stretch (popupSimple's cuts open: its state's pattern has them open)
    state = fold(read_pattern(SIM / f"{name}.svg", width=150), 0.3)
    assert state.method == "general"
    cp = state.pattern
    creases = cp.edge_mask("M", "V")
    assert np.mean(np.abs(state.fold_angles[creases]) > 5.0) >= 0.5
    assert _edge_strain(cp, state.coords) * 100 <= state.strain + 1e-9 < STRAIN_LIMIT


def test_the_drive_is_relaxed_where_it_stretches_the_panels(monkeypatch):
    # thick panels bend stiffly and stretch easily (E h^3 against E h): the drive, as
    # stiff as their bending, stretches them past DRIVE_STRAIN unless it is relaxed
    import origami_cad.simulation.folder as folder

    cp = read_pattern(SIM / "openSinkBase.svg", width=150)
    thick = SimulationParams(panel_thickness=10.0)
    relaxed = fold_general(cp, [0.3], params=thick)[0]
    monkeypatch.setattr(folder, "DRIVE_RELAXATIONS", 0)
    stiff = fold_general(cp, [0.3], params=thick)[0]
    assert stiff.strain > folder.DRIVE_STRAIN
    assert relaxed.strain <= folder.DRIVE_STRAIN < stiff.strain
    creases = cp.edge_mask("M", "V")
    assert np.mean(np.abs(relaxed.fold_angles[creases]) > 5.0) >= 0.5
