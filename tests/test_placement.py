"""Folded states shown to users lie on the table, centred on the flat sheet.

The folders' own frame (one panel kept where it lies flat) is what the string models
and the simulation use; only what is shown is moved, rigidly.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.distance import pdist

from origami_cad.cli import main
from origami_cad.kinematics import fold_angles_from_coords, place_on_table, vector_area
from origami_cad.kinematics.folding import fold_design
from origami_cad.pattern import read_fold, read_fold_frames
from origami_cad.pattern.design import load_design, miura_design

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize("p", [0.0, 0.15, 0.5, 0.9, 0.98])
def test_a_folding_miura_lies_level_on_the_table_centred(p):
    design = miura_design(4, 6, 20.0, 30.0, 60.0)
    cp = design.pattern
    raw = fold_design(design, p).coords
    placed = place_on_table(cp, raw)
    assert placed[:, 2].min() == pytest.approx(0.0, abs=1e-9)
    np.testing.assert_allclose(placed[:, :2].mean(axis=0), cp.vertices.mean(axis=0), atol=1e-9)
    # moved rigidly: every distance and every fold angle as the folder made them
    np.testing.assert_allclose(pdist(placed), pdist(raw), atol=1e-9)
    np.testing.assert_allclose(
        fold_angles_from_coords(cp, placed), fold_angles_from_coords(cp, raw), atol=1e-9
    )
    # level: the sheet's mean normal points straight up
    up = vector_area(cp, placed)
    np.testing.assert_allclose(up / np.linalg.norm(up), [0, 0, 1], atol=1e-9)
    if p == 0.0:
        np.testing.assert_allclose(placed[:, :2], cp.vertices, atol=1e-9)
    else:
        # a corner panel no longer stays put while the far end climbs
        assert np.ptp(placed[:, 2]) < np.ptp(raw[:, 2])


def test_fold_command_writes_placed_frames(tmp_path):
    out = tmp_path / "f.fold"
    assert (
        main(
            ["fold", str(EXAMPLES / "miura_6x4.toml"), "--ratio=0.6", "--frames=4", "-o", str(out)]
        )
        == 0
    )
    cp = read_fold(out)
    frames = read_fold_frames(out)[1:]
    assert len(frames) == 4
    np.testing.assert_allclose(frames[0][:, :2], cp.vertices, atol=1e-9)  # p = 0: the sheet
    for coords in frames:
        assert coords[:, 2].min() == pytest.approx(0.0, abs=1e-9)
        np.testing.assert_allclose(coords[:, :2].mean(axis=0), cp.vertices.mean(axis=0), atol=1e-6)
    design = load_design(EXAMPLES / "miura_6x4.toml")
    raw = fold_design(design, 0.6).coords
    assert np.ptp(frames[-1][:, 2]) < 0.5 * np.ptp(raw[:, 2])
    np.testing.assert_allclose(pdist(frames[-1]), pdist(raw), atol=1e-6)
