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
  a string coupling far-apart panels);
- **PARDISO** (Intel MKL's sparse direct solver, supernodal Cholesky in a
  nested-dissection order, on one thread), when MKL's runtime is installed
  (``pip install origami-cad[mkl]``, about 720 MB) and the band's arithmetic
  passes :data:`PARDISO_BAND_WORK`: its analysis is done once per pattern and
  each matrix is only factorised numerically. Measured (CPU, one thread): the
  box pleat's 8,100 unknowns 20 ms a factorisation and 1.7 ms a solve against
  the band's 52 ms and 2.8 ms; the 10,201-node Miura's 30,591 unknowns 138 ms
  and 10 ms against 531 ms and 19 ms; the 1,681-node Miura's 5,031 unknowns
  17 ms and 1.1 ms against 18 ms and 0.9 ms (there the band stays).

The banded kernels run on one BLAS thread: on these bands a second thread
saves no time (measured) but doubles the CPU time, which a parallel run of
several simulations needs.

Both refuse a matrix that is not positive definite (Cholesky fails on it; the
SuperLU pivots give its inertia), which is how the solver decides to add
Levenberg damping.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import enum
import functools
import glob
import sys
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.linalg.lapack import dpbtrf, dpbtrs
from scipy.sparse.csgraph import reverse_cuthill_mckee
from scipy.sparse.linalg import splu
from threadpoolctl import ThreadpoolController

__all__ = [
    "Factor",
    "FactorMethod",
    "FactorPlan",
    "factorise",
    "one_blas_thread",
    "pardiso_available",
    "plan_factorisation",
]

#: The banded method is chosen while its arithmetic (size x band^2) is at most this
#: many times the sparse factorisation's (the sum of its columns' squared lengths):
#: dense kernels run that much faster (measured: 3.8x the arithmetic, 1.5x faster).
BANDED_WORK_RATIO = 6.0
#: Largest band storage the banded method may take, bytes.
BANDED_MAX_BYTES = 256 * 2**20
#: PARDISO is chosen (where MKL is installed) once the band's arithmetic, size x band^2,
#: passes this: below it the band is as fast (the 1,681-node Miura's 3.2e8, measured).
PARDISO_BAND_WORK = 5e8


@functools.cache
def _threads() -> ThreadpoolController:
    return ThreadpoolController()


def one_blas_thread():
    """A context in which BLAS runs on one thread (the solver's vector products too: on
    30,000 unknowns OpenBLAS's two threads spin for 26 times the CPU time of one, measured).
    """
    return _threads().limit(limits=1, user_api="blas")


class FactorMethod(enum.StrEnum):
    """How a Hessian is factorised (see the module's docstring)."""

    BANDED = "banded"
    SUPERLU = "superlu"
    PARDISO = "pardiso"


@functools.cache
def _mkl():
    """MKL's runtime library (sequential: one thread), or None when it is not installed."""
    found = sorted(glob.glob(f"{sys.prefix}/lib/libmkl_rt.so*")) or [
        ctypes.util.find_library("mkl_rt")
    ]
    if not found or found[0] is None:
        return None
    try:
        lib = ctypes.CDLL(found[0])
        lib.MKL_Set_Threading_Layer(ctypes.c_int(1))  # MKL_THREADING_SEQUENTIAL
    except (OSError, AttributeError):
        return None
    lib.pardiso.restype = None
    return lib


def pardiso_available() -> bool:
    """Whether MKL's PARDISO can be used here (``pip install origami-cad[mkl]``)."""
    return _mkl() is not None


class _Pardiso:
    """One pattern's PARDISO handle: analysed once, two numerical factorisations kept.

    Each factorisation goes to the slot that does not hold the latest positive-definite
    one (the solver's preconditioner), and stamps its slot: a :class:`Factor` whose slot
    has been factorised again since is no longer :attr:`Factor.valid`.
    """

    def __init__(self, indptr: np.ndarray, indices: np.ndarray, values: np.ndarray) -> None:
        self.lib = _mkl()
        self.pt = np.zeros(64, dtype=np.int64)
        self.iparm = np.zeros(64, dtype=np.int32)
        # own settings; METIS nested dissection; report fill; zero-based indices
        self.iparm[[0, 1, 17, 34]] = (1, 2, -1, 1)
        self.ia = np.ascontiguousarray(indptr, dtype=np.int32)
        self.ja = np.ascontiguousarray(indices, dtype=np.int32)
        self.size = len(indptr) - 1
        self.stamps = [0, 0]
        self.values = [np.zeros(len(indices)), np.zeros(len(indices))]  # each slot's matrix
        self.last = 1
        zero = np.zeros(self.size)
        if self._call(11, values, 0, zero, zero.copy()) != 0:
            raise ValueError("PARDISO analysis failed")

    def _call(self, phase: int, values, slot: int, rhs: np.ndarray, out: np.ndarray) -> int:
        i32, ptr = ctypes.c_int32, ctypes.POINTER
        error = i32(0)
        perm = np.zeros(1, dtype=np.int32)
        self.lib.pardiso(
            self.pt.ctypes.data_as(ptr(ctypes.c_int64)),
            ctypes.byref(i32(2)),  # maxfct: two factorisations kept
            ctypes.byref(i32(slot + 1)),
            ctypes.byref(i32(2)),  # real symmetric positive definite
            ctypes.byref(i32(phase)),
            ctypes.byref(i32(self.size)),
            values.ctypes.data_as(ctypes.c_void_p),
            self.ia.ctypes.data_as(ptr(i32)),
            self.ja.ctypes.data_as(ptr(i32)),
            perm.ctypes.data_as(ptr(i32)),
            ctypes.byref(i32(1)),
            self.iparm.ctypes.data_as(ptr(i32)),
            ctypes.byref(i32(0)),
            rhs.ctypes.data_as(ctypes.c_void_p),
            out.ctypes.data_as(ctypes.c_void_p),
            ctypes.byref(error),
        )
        return error.value

    def factorise(self, values: np.ndarray) -> tuple[int, int] | None:
        """Factorise into the free slot: ``(slot, stamp)``, or None unless positive definite."""
        slot = 1 - self.last
        self.stamps[slot] += 1
        self.values[slot] = np.ascontiguousarray(values, dtype=float)
        zero = np.zeros(self.size)
        if self._call(22, self.values[slot], slot, zero, zero.copy()) != 0:
            return None  # -4: a pivot that is not positive
        self.last = slot
        return slot, self.stamps[slot]

    def solve(self, slot: int, rhs: np.ndarray) -> np.ndarray:
        out = np.zeros(self.size)
        rhs = np.ascontiguousarray(rhs, dtype=float)
        if self._call(33, self.values[slot], slot, rhs, out) != 0:
            raise ValueError("PARDISO solve failed")
        return out

    def __del__(self) -> None:
        try:  # release every factorisation (not at interpreter exit: the process frees it)
            if getattr(self, "lib", None) is not None and sys.meta_path is not None:
                zero = np.zeros(1)
                self._call(-1, zero, 0, zero, zero.copy())
        except Exception:  # a finaliser must not raise
            pass


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
    pardiso: _Pardiso | None = None


class Factor:
    """A factorisation of a symmetric positive-definite matrix ``A``.

    :meth:`solve` takes and returns vectors in ``A``'s own order.
    """

    def __init__(self, plan: FactorPlan, factor) -> None:
        self.plan = plan
        self.factor = factor

    @property
    def valid(self) -> bool:
        """False once a later factorisation took this one's place (PARDISO keeps two)."""
        if self.plan.method is not FactorMethod.PARDISO:
            return True
        slot, stamp = self.factor
        return self.plan.pardiso.stamps[slot] == stamp

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``A^-1 rhs`` for ``rhs`` (size,)."""
        order = self.plan.order
        out = np.empty_like(rhs)
        if self.plan.method is FactorMethod.PARDISO:
            if not self.valid:
                raise ValueError("this factorisation was replaced by a later one")
            return self.plan.pardiso.solve(self.factor[0], rhs)
        if self.plan.method is FactorMethod.BANDED:
            with one_blas_thread():  # LAPACK's own call: scipy's wrapper costs 1/10 of a solve
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
        if pardiso_available() and not (cheap and size * float(band) ** 2 < PARDISO_BAND_WORK):
            method = FactorMethod.PARDISO
    if method is FactorMethod.PARDISO:
        return _pardiso_plan(indices, indptr, diagonal, band)
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


def _pardiso_plan(
    indices: np.ndarray, indptr: np.ndarray, diagonal: np.ndarray, band: int
) -> FactorPlan:
    """PARDISO's plan: the upper triangle's CSR pattern, analysed on a diagonally
    dominant matrix of that pattern (the analysis depends on the pattern only)."""
    size = len(indptr) - 1
    positions = np.arange(1, len(indices) + 1, dtype=float)  # data positions + 1: none zero
    whole = sp.csc_matrix((positions, indices, indptr), shape=(size, size))
    upper = sp.triu(whole.tocsr(), format="csr")
    upper.sort_indices()
    source = np.rint(upper.data).astype(np.int64) - 1
    probe = np.where(np.isin(source, diagonal), float(size), -1e-3)
    handle = _Pardiso(upper.indptr, upper.indices, probe)
    natural = np.arange(size)
    return FactorPlan(
        FactorMethod.PARDISO, natural, size, source, upper.indices, upper.indptr, band, handle
    )


def factorise(plan: FactorPlan, values: np.ndarray) -> Factor | None:
    """Factorise the matrix with ``values`` (nnz,) in the planned pattern.

    Returns None unless it is positive definite (or when it is exactly singular, or
    holds a value that is not finite).
    """
    if not np.all(np.isfinite(values)):
        return None
    if plan.method is FactorMethod.PARDISO:
        done = plan.pardiso.factorise(values[plan.source])
        return None if done is None else Factor(plan, done)
    if plan.method is FactorMethod.BANDED:
        ab = np.zeros((plan.bandwidth + 1) * plan.size)
        ab[plan.target] = values[plan.source]
        with one_blas_thread():
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
