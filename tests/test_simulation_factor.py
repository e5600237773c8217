"""Factorisations of the solver's Hessians: the banded Cholesky, SuperLU and (where MKL is
installed) PARDISO plans solve the same systems, refuse the same indefinite matrices, and
each is chosen where it pays."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from origami_cad.pattern.design import miura_design
from origami_cad.simulation import SimulationParams, build_structure
from origami_cad.simulation.factor import (
    FactorMethod,
    factorise,
    pardiso_available,
    plan_factorisation,
)
from origami_cad.simulation.solver import HessianAssembly

#: the methods this machine has (PARDISO needs MKL's runtime: origami-cad[mkl])
METHODS = [m for m in FactorMethod if m is not FactorMethod.PARDISO or pardiso_available()]


def _flat_sheet_hessian():
    """The free-free Hessian of a held 12 x 12-panel Miura, flat, plus a small shift (SPD)."""
    cp = miura_design(12, 12, 15.0, 15.0, 60.0).pattern
    st = build_structure(cp, SimulationParams(), cp.face_labels[0], None)
    asm = HessianAssembly(st, None)
    _grad, data, _, _ = asm.assemble(st.x0, st, None, None)
    return asm.matrix(data, 1e-3)


def _pattern(a: sp.csc_matrix):
    a = sp.csc_matrix(a)
    a.sort_indices()
    cols = np.repeat(np.arange(a.shape[0]), np.diff(a.indptr))
    return a, np.flatnonzero(a.indices == cols)


@pytest.mark.parametrize("method", METHODS)
def test_both_methods_solve_the_sheet_and_refuse_an_indefinite_matrix(method):
    a, diagonal = _pattern(_flat_sheet_hessian())
    plan = plan_factorisation(a.indices, a.indptr, diagonal, method)
    assert plan.method is method
    assert sorted(plan.order) == list(range(a.shape[0]))
    factor = factorise(plan, a.data)
    assert factor is not None
    rhs = np.random.default_rng(2).normal(size=a.shape[0])
    x = factor.solve(rhs)
    np.testing.assert_allclose(x, np.linalg.solve(a.toarray(), rhs), rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(a @ x, rhs, atol=1e-8 * np.abs(rhs).max())
    shifted = a.data.copy()
    shifted[diagonal] -= 1.0  # the flat sheet's folding modes have almost no stiffness
    assert factorise(plan, shifted) is None


def test_a_sheet_numbered_row_by_row_is_factorised_banded():
    a, diagonal = _pattern(_flat_sheet_hessian())
    plan = plan_factorisation(a.indices, a.indptr, diagonal)
    assert plan.method is FactorMethod.BANDED
    # the band is a few rows of nodes, far narrower than the matrix
    assert plan.bandwidth < a.shape[0] / 3


def test_a_randomly_numbered_sheet_is_reordered_into_a_band():
    a, _ = _pattern(_flat_sheet_hessian())
    natural = _bandwidth(a)
    shuffle = np.random.default_rng(5).permutation(a.shape[0])
    b, diagonal = _pattern(a[shuffle][:, shuffle])
    assert _bandwidth(b) > 3 * natural  # the shuffle really spread the band
    plan = plan_factorisation(b.indices, b.indptr, diagonal)
    # reverse Cuthill-McKee recovers a band about as narrow as the mesh's own numbering
    assert plan.bandwidth < 1.5 * natural
    factor = factorise(plan, b.data)
    rhs = np.random.default_rng(6).normal(size=b.shape[0])
    np.testing.assert_allclose(b @ factor.solve(rhs), rhs, atol=1e-8 * np.abs(rhs).max())


def test_a_dense_coupling_goes_to_the_sparse_factorisation():
    # a string pulls on every node of a long sheet: one row and column couple everything,
    # which no ordering keeps in a narrow band, while minimum degree eliminates it last
    n = 3000
    main = sp.diags([np.full(n - 1, -1.0), np.full(n, 4.0), np.full(n - 1, -1.0)], [-1, 0, 1])
    coupling = sp.lil_matrix((n, n))
    coupling[n // 2, :] = 0.01
    coupling[:, n // 2] = 0.01
    a, diagonal = _pattern(main + coupling.tocsc() + sp.eye(n))
    plan = plan_factorisation(a.indices, a.indptr, diagonal)
    sparse = FactorMethod.PARDISO if pardiso_available() else FactorMethod.SUPERLU
    assert plan.method is sparse
    rhs = np.random.default_rng(7).normal(size=n)
    x = factorise(plan, a.data).solve(rhs)
    np.testing.assert_allclose(a @ x, rhs, atol=1e-9 * np.abs(rhs).max())


def _bandwidth(a: sp.csc_matrix) -> int:
    coo = a.tocoo()
    return int(np.abs(coo.row - coo.col).max())


@pytest.mark.parametrize("method", METHODS)
def test_a_matrix_with_a_value_that_is_not_finite_is_refused(method):
    a, diagonal = _pattern(_flat_sheet_hessian())
    plan = plan_factorisation(a.indices, a.indptr, diagonal, method)
    values = a.data.copy()
    values[diagonal[3]] = np.nan
    assert factorise(plan, values) is None


@pytest.mark.skipif(not pardiso_available(), reason="MKL's runtime is not installed")
def test_pardiso_keeps_the_last_positive_definite_factorisation_until_replaced():
    a, diagonal = _pattern(_flat_sheet_hessian())
    plan = plan_factorisation(a.indices, a.indptr, diagonal, FactorMethod.PARDISO)
    rhs = np.random.default_rng(3).normal(size=a.shape[0])
    first = factorise(plan, a.data)
    shifted = a.data.copy()
    shifted[diagonal] -= 1.0
    assert factorise(plan, shifted) is None  # refused: the kept one stays good
    assert first.valid
    np.testing.assert_allclose(a @ first.solve(rhs), rhs, atol=1e-8 * np.abs(rhs).max())
    stiffer = a.data.copy()
    stiffer[diagonal] += 2.0
    second = factorise(plan, stiffer)  # the other slot: both good
    assert first.valid and second.valid
    b = sp.csc_matrix((stiffer, a.indices, a.indptr), shape=a.shape)
    np.testing.assert_allclose(b @ second.solve(rhs), rhs, atol=1e-8 * np.abs(rhs).max())
    np.testing.assert_allclose(a @ first.solve(rhs), rhs, atol=1e-8 * np.abs(rhs).max())
    third = factorise(plan, a.data)  # takes the older one's place
    assert third.valid and second.valid and not first.valid
    with pytest.raises(ValueError, match="replaced"):
        first.solve(rhs)
