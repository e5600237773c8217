"""Factorisations of the solver's symmetric Hessians: banded Cholesky or sparse SuperLU.

The Newton solver (:mod:`origami_cad.simulation.solver`) factorises Hessians
of one fixed sparsity pattern many times: to take a Newton step, to learn
whether the matrix is positive definite, and as the preconditioner of the
conjugate-gradient steps that follow. :func:`plan_factorisation` looks at the
pattern once and picks the cheaper of two exact methods:

- **banded Cholesky** (LAPACK ``pbtrf``/``pbtrs``) in the natural or the
  reverse Cuthill-McKee order, whichever has the narrower band. A sheet meshed
  row by row has a band of a few rows of nodes; dense LAPACK kernels on that
  band beat a general sparse factorisation by about 1.5x to factorise and 3x
  to solve (measured on the benchmark's 20 x 20-cell Miura, 5,031 unknowns,
  band 251), although they do about 4x its arithmetic;
- **SuperLU** (symmetric mode, diagonal pivots only) in a symmetric minimum
  degree order, for patterns whose band is wide (vertices numbered at random,
  a string coupling far-apart panels).

The banded kernels run on one BLAS thread: on these bands a second thread
saves no time (measured) but doubles the CPU time, which a parallel run of
several simulations needs.

Both refuse a matrix that is not positive definite (Cholesky fails on it; the
SuperLU pivots give its inertia), which is how the solver decides to add
Levenberg damping.
"""

from __future__ import annotations

import enum
import functools
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.linalg.lapack import dpbtrf, dpbtrs
from scipy.sparse.csgraph import reverse_cuthill_mckee
from scipy.sparse.linalg import splu
from threadpoolctl import ThreadpoolController

__all__ = ["Factor", "FactorMethod", "FactorPlan", "factorise", "plan_factorisation"]

#: The banded method is chosen while its arithmetic (size x band^2) is at most this
#: many times the sparse factorisation's (the sum of its columns' squared lengths):
#: dense kernels run that much faster (measured: 3.8x the arithmetic, 1.5x faster).
BANDED_WORK_RATIO = 6.0
#: Largest band storage the banded method may take, bytes.
BANDED_MAX_BYTES = 256 * 2**20


@functools.cache
def _threads() -> ThreadpoolController:
    return ThreadpoolController()


def _one_thread():
    """A context in which BLAS runs on one thread."""
    return _threads().limit(limits=1, user_api="blas")


class FactorMethod(enum.StrEnum):
    """How a Hessian is factorised (see the module's docstring)."""

    BANDED = "banded"
    SUPERLU = "superlu"


@dataclass(frozen=True)
class FactorPlan:
    """How every matrix of one sparsity pattern is factorised, computed once.

    Attributes
    ----------
    method : FactorMethod
        Banded Cholesky or SuperLU.
    order : ndarray
        (size,) the elimination order: row and column ``order[k]`` of the matrix
        is the factorised matrix's ``k``-th.
    size : int
        The matrix's order.
    source, target : ndarray
        Banded: where each stored lower-band entry comes from in the pattern's
        data and goes in the flat (band + 1, size) storage. SuperLU: the data's
        permutation and the permuted pattern's CSC indices and pointers.
    bandwidth : int
        The band's half-width in ``order`` (both methods report it).
    """

    method: FactorMethod
    order: np.ndarray
    size: int
    source: np.ndarray
    target: np.ndarray
    indptr: np.ndarray | None
    bandwidth: int


class Factor:
    """A factorisation of a symmetric positive-definite matrix ``A``.

    :meth:`solve` takes and returns vectors in ``A``'s own order.
    """

    def __init__(self, plan: FactorPlan, factor) -> None:
        self.plan = plan
        self.factor = factor

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``A^-1 rhs`` for ``rhs`` (size,)."""
        order = self.plan.order
        out = np.empty_like(rhs)
        if self.plan.method is FactorMethod.BANDED:
            with _one_thread():  # LAPACK's own call: scipy's wrapper costs 1/10 of a solve
                x, info = dpbtrs(self.factor, rhs[order], lower=1, overwrite_b=1)
            if info != 0:
                raise ValueError(f"dpbtrs: illegal argument {-info}")
            out[order] = x
        else:
            out[order] = self.factor.solve(rhs[order])
        return out


def _bandwidth(rows: np.ndarray, cols: np.ndarray, inverse: np.ndarray) -> int:
    return int(np.max(np.abs(inverse[rows] - inverse[cols]), initial=0))


def plan_factorisation(
    indices: np.ndarray,
    indptr: np.ndarray,
    diagonal: np.ndarray,
    method: FactorMethod | None = None,
) -> FactorPlan:
    """Plan the factorisations of every matrix with this symmetric CSC pattern.

    Parameters
    ----------
    indices, indptr : ndarray
        The pattern's CSC row indices and column pointers (both triangles).
    diagonal : ndarray
        The positions of the diagonal entries in the data array.
    method : FactorMethod, optional
        Force one method (default: the cheaper, see :data:`BANDED_WORK_RATIO`).
    """
    size = len(indptr) - 1
    nnz = len(indices)
    template = sp.csc_matrix((np.arange(nnz, dtype=float), indices, indptr), shape=(size, size))
    # minimum degree depends on the pattern only: take it, and the fill, from a
    # diagonally dominant matrix of the same pattern
    probe = template.copy()
    probe.data[:] = -1.0
    probe.data[diagonal] = np.diff(indptr) + 1.0
    lu = splu(
        probe, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
    )
    sparse_work = float(np.sum(np.diff(lu.L.tocsc().indptr).astype(float) ** 2))
    rows = np.asarray(indices, dtype=np.int64)
    cols = np.repeat(np.arange(size), np.diff(indptr))
    natural = np.arange(size)
    rcm = reverse_cuthill_mckee(template.tocsr(), symmetric_mode=True).astype(np.int64)
    band_order = min((natural, rcm), key=lambda o: _bandwidth(rows, cols, np.argsort(o)))
    inverse = np.argsort(band_order)
    band = _bandwidth(rows, cols, inverse)
    fits = size * (band + 1) * 8 <= BANDED_MAX_BYTES
    if method is None:
        cheap = size * float(band) ** 2 <= BANDED_WORK_RATIO * sparse_work
        method = FactorMethod.BANDED if fits and cheap else FactorMethod.SUPERLU
    if method is FactorMethod.BANDED:
        r, c = inverse[rows], inverse[cols]
        lower = np.flatnonzero(r >= c)
        target = (r[lower] - c[lower]) * size + c[lower]
        return FactorPlan(method, band_order, size, lower, target, None, band)
    order = np.argsort(lu.perm_c)  # order[new] = old
    permuted = template[order][:, order].tocsc()
    permuted.sort_indices()
    inverse = np.argsort(order)
    return FactorPlan(
        method,
        order,
        size,
        permuted.data.astype(np.int64),
        permuted.indices.astype(np.int32),
        permuted.indptr.astype(np.int32),
        _bandwidth(rows, cols, inverse),
    )


def factorise(plan: FactorPlan, values: np.ndarray) -> Factor | None:
    """Factorise the matrix with ``values`` (nnz,) in the planned pattern.

    Returns None unless it is positive definite (or when it is exactly singular, or
    holds a value that is not finite).
    """
    if not np.all(np.isfinite(values)):
        return None
    if plan.method is FactorMethod.BANDED:
        ab = np.zeros((plan.bandwidth + 1) * plan.size)
        ab[plan.target] = values[plan.source]
        with _one_thread():
            chol, info = dpbtrf(ab.reshape(plan.bandwidth + 1, plan.size), lower=1, overwrite_ab=1)
        if info > 0:  # a leading minor is not positive definite
            return None
        if info < 0:
            raise ValueError(f"dpbtrf: illegal argument {-info}")
        return Factor(plan, chol)
    a = sp.csc_matrix((values[plan.source], plan.target, plan.indptr), shape=(plan.size,) * 2)
    try:
        lu = splu(a, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    except RuntimeError:  # exactly singular
        return None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return None
    if not np.all(lu.U.diagonal() > 0):
        return None  # Sylvester: a non-positive pivot means the matrix is not positive definite
    return Factor(plan, lu)
