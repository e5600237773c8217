"""TG design (eq. 1), the TG chain (eqs. 2-4) and exact 3D rigid folding."""

from __future__ import annotations

import math

import numpy as np
import pytest

from origami_cad.kinematics import (
    chain_angles,
    chain_points,
    face_normals,
    fold_tessellation,
    hypar_alpha0,
    tip_positions,
    turning_angles,
)
from origami_cad.pattern import PatternError
from origami_cad.pattern.design import miura_design
from origami_cad.pattern.tg import (
    TGDesign,
    design_from_vectors,
    entry_flags,
    shape_angles_eq1,
    tg_pattern,
)

FIG2_VECTORS = [[40, 0], [30, 25], [30, -10], [40, 15], [30, 0]]

DESIGNS = {
    "classic-miura": miura_design(4, 6, 20.0, 30.0, 60.0).tg,
    "curved-tg": design_from_vectors(FIG2_VECTORS, 0.5, 1),
    "beta-over-90": TGDesign((30, 25, 35, 20), (120, 70, 100), 0, 30.0, 2),
    "hypar-on": TGDesign((30, 25, 35, 20), (60, 110, 50), 1, 24.0, 3, hypar_base=True),
}


# ---------------------------------------------------------------- eq. 1 / eq. 2
def test_eq1_both_cases_by_hand():
    # p = 1: beta = atan(tan(|da|/2)); da = 60 deg -> 30 deg, or 150 deg
    beta = shape_angles_eq1(np.radians([60, 60, -60, -60]), np.array([0, 1, 0, 1]), 1.0)
    np.testing.assert_allclose(np.degrees(beta), [30, 150, 150, 30])
    # p = 0.5: sin(pi/4) in the denominator
    beta = shape_angles_eq1(np.radians([40.0]), np.array([0]), 0.5)
    expected = math.degrees(math.atan(math.tan(math.radians(20)) / math.sin(math.pi / 4)))
    assert math.degrees(beta[0]) == pytest.approx(expected, abs=1e-12)


def test_eq2_by_hand():
    beta = np.radians([[30.0, 30.0]])
    da = turning_angles(np.array([math.pi]), beta, entry_flag=0)  # EF_0 = 0, EF_1 = 1
    np.testing.assert_allclose(np.degrees(da[0, 0]), [60.0, -60.0])
    assert np.all(turning_angles(np.array([0.0]), beta, 1) == 0)


@pytest.mark.parametrize("p", [0.2, 0.5, 0.9, 1.0])
@pytest.mark.parametrize("flag", [0, 1])
def test_design_then_fold_gives_back_the_drawn_tg(p, flag):
    d = design_from_vectors(FIG2_VECTORS, p, flag)
    alpha = chain_angles(np.array([p * math.pi]), np.radians(d.shape_angles), flag)[0, 0]
    np.testing.assert_allclose(np.degrees(alpha), [v[1] for v in FIG2_VECTORS], atol=1e-9)
    tip = tip_positions(np.array([p * math.pi]), d.lengths, np.radians(d.shape_angles), flag)
    drawn = sum(
        np.array([v[0] * math.cos(math.radians(v[1])), v[0] * math.sin(math.radians(v[1]))])
        for v in FIG2_VECTORS
    )
    np.testing.assert_allclose(tip[0, 0], drawn, atol=1e-9)


def test_eq3_hypar_base():
    theta = np.array([0.0, math.pi / 2, math.pi])
    a0 = hypar_alpha0(theta)
    c = math.cos(math.pi / 4)
    np.testing.assert_allclose(a0, [0.0, math.acos(math.sqrt(2 * c / (1 + c))), math.pi / 2])
    alpha = chain_angles(theta, np.radians([[45.0]]), 1, hypar_base=True)
    np.testing.assert_allclose(alpha[0, :, 0], a0)


def test_chain_is_vectorised_over_designs_and_samples():
    rng = np.random.default_rng(0)
    lengths = rng.uniform(10, 50, (7, 5))
    beta = rng.uniform(0.3, 2.8, (7, 4))
    flags = rng.integers(0, 2, 7)
    theta = np.linspace(0, math.pi, 46)
    pts = chain_points(theta, lengths, beta, flags, hypar_base=True, start=(5.0, -3.0))
    assert pts.shape == (7, 46, 6, 2)
    tips = tip_positions(theta, lengths, beta, flags, hypar_base=True, start=(5.0, -3.0))
    np.testing.assert_allclose(pts[:, :, -1], tips, atol=1e-12)
    # one design at a time gives the same numbers
    for k in range(7):
        one = chain_points(theta, lengths[k], beta[k], flags[k], True, (5.0, -3.0))
        np.testing.assert_allclose(one[0], pts[k], atol=1e-12)
    # segment lengths are l_i at every sample
    seg = np.linalg.norm(np.diff(pts, axis=2), axis=-1)
    np.testing.assert_allclose(seg, np.broadcast_to(lengths[:, None, :], seg.shape))


# ---------------------------------------------------------------- crease patterns
@pytest.mark.parametrize("name", list(DESIGNS))
def test_tg_patterns_are_flat_foldable(name):
    cp = tg_pattern(DESIGNS[name])
    assert cp.check() == []
    d = DESIGNS[name]
    assert len(cp.faces) == 2 * d.copies * d.n_vectors
    # main crease segments alternate from EF_0 along y = T_s.y
    ys = cp.vertices[cp.edges, 1]
    main = np.all(np.isclose(ys, d.start[1]), axis=1)
    order = np.argsort(cp.vertices[cp.edges[main], 0].mean(axis=1))
    expected = ["V" if f else "M" for f in entry_flags(d.entry_flag, d.n_vectors)]
    assert cp.assignments[main][order].tolist() == expected


def test_small_turn_is_an_error_naming_the_vector_or_merged_on_request():
    vectors = [[40, 0], [30, 2], [30, 30]]
    with pytest.raises(PatternError, match=r"vectors\[1\].*merge_small_turns"):
        design_from_vectors(vectors, 0.5, 1)
    d = design_from_vectors(vectors, 0.5, 1, merge_small_turns=True)
    assert d.n_vectors == 2
    assert "realised heading error" in d.notes[0]
    assert d.lengths[0] == pytest.approx(abs(40 + 30 * complex(math.cos(0.0349), 0)), rel=1e-3)


def test_crossing_legs_are_an_error():
    with pytest.raises(PatternError, match="legs of joints"):
        tg_pattern(TGDesign((5.0, 5.0, 5.0), (20.0, 160.0), 1, 36.0, 1))


# ---------------------------------------------------------------- 3D folding
def _main_crease_mask(cp, design):
    ys = cp.vertices[cp.edges, 1]
    return np.all(np.isclose(ys, design.start[1]), axis=1)


@pytest.mark.parametrize("name", list(DESIGNS))
@pytest.mark.parametrize("p", [0.0, 0.15, 0.5, 0.85, 1.0])
def test_3d_fold_invariants(name, p):
    design = DESIGNS[name]
    cp = tg_pattern(design)
    coords, angles = fold_tessellation(design, cp, p)
    # isometry: every crease keeps its flat length
    flat_len = cp.edge_lengths()
    folded_len = np.linalg.norm(coords[cp.edges[:, 1]] - coords[cp.edges[:, 0]], axis=1)
    np.testing.assert_allclose(folded_len, flat_len, rtol=1e-9)
    # every panel stays planar
    normals = face_normals(cp, coords)
    for ring, n in zip(cp.faces, normals, strict=True):
        dev = (coords[ring] - coords[ring].mean(axis=0)) @ n
        assert np.abs(dev).max() < 1e-9 * cp.size
    # every main-crease dihedral equals theta with its M/V sign
    main = _main_crease_mask(cp, design)
    sign = np.where(cp.assignments[main] == "V", 1.0, -1.0)
    if p < 1.0:
        np.testing.assert_allclose(angles[main], sign * 180.0 * p, atol=1e-7)
        # every crease folds in the sense of its assignment
        crease = cp.edge_mask("M", "V")
        if p > 0:
            ok = np.sign(angles[crease]) == np.where(cp.assignments[crease] == "V", 1, -1)
            assert ok.all()
    # turning angles of the 3D main crease equal eq. 2
    joints = coords[np.isclose(cp.vertices[:, 1], design.start[1])]
    joints = joints[np.argsort(cp.vertices[np.isclose(cp.vertices[:, 1], design.start[1]), 0])]
    assert np.allclose(joints[:, 1], design.start[1])  # the main crease stays in its plane
    seg = np.diff(joints, axis=0)
    heading = np.arctan2(-seg[:, 2], seg[:, 0])  # TG (a, b) = (x, -z)
    expected = chain_angles(
        np.array([p * math.pi]),
        np.radians(design.shape_angles),
        design.entry_flag,
        design.hypar_base,
    )[0, 0]
    np.testing.assert_allclose(np.unwrap(heading), expected, atol=1e-9)
    # copies lie in parallel planes
    if p == 0.0:
        np.testing.assert_allclose(coords[:, :2], cp.vertices, atol=1e-12)
        assert np.all(coords[:, 2] == 0)


def test_fold_rejects_foreign_pattern_and_bad_ratio():
    d = DESIGNS["curved-tg"]
    with pytest.raises(PatternError, match="not the tessellation"):
        fold_tessellation(d, tg_pattern(DESIGNS["classic-miura"]), 0.3)
    with pytest.raises(PatternError, match=r"\[0, 1\]"):
        fold_tessellation(d, tg_pattern(d), 1.2)


def test_a_fold_sequence_is_each_state_folded_alone():
    from origami_cad.kinematics.folding import fold_design, fold_sequence
    from origami_cad.pattern.design import miura_design

    design = miura_design(3, 4, 15.0, 20.0, 70.0)
    ratios = [0.0, 0.13, 0.5, 0.97, 1.0]
    for state, p in zip(fold_sequence(design, ratios), ratios, strict=True):
        alone = fold_design(design, p)
        assert state.p == p
        np.testing.assert_allclose(state.coords, alone.coords, atol=1e-12)
        np.testing.assert_allclose(state.fold_angles, alone.fold_angles, atol=1e-9)
    with pytest.raises(PatternError, match=r"in \[0, 1\], got 1.5"):
        fold_sequence(design, [0.2, 1.5])
