"""Quasi-static equilibrium of the bar-and-hinge model with strings and ground contact.

Total energy (N mm)::

    E = sum_bars k/2 (L - L0)^2 + sum_hinges k/2 (rho - rho0)^2
      + sum_limits k_lim/2 (|rho| - (rho_max - margin))_+^2           (smooth barrier)
      + sum_strings k_s/2 (L_s - L_free)_+^2                          (tension only)
      + sum_nodes W z + k_g/2 (z_ground - z)_+^2                      (gravity, ground)
      + sum_contacts mu N (sqrt(|d|^2 + s^2) - s)                     (friction)

Friction is the incremental potential of quasi-static Coulomb friction: a node
in contact that slides by ``d`` (its tangential displacement in the step)
dissipates ``mu N |d|``, ``N`` its normal force at the start of the step,
regularised over a slip ``s`` (1 um by default) so that the energy stays smooth
and Newton's method keeps its pace through stick-slip transitions.

Each solve minimises E over the free nodes by Newton's method on the exact
Hessian (bars' and strings' geometric stiffness, the hinges' second
derivatives, the exit points' curvature) and an Armijo backtracking line
search, so the energy decreases at every accepted iteration (recorded, and
asserted by the tests).

Linear algebra (:class:`HessianAssembly`): the Hessian's sparsity pattern, the
place of every element entry in its CSC data and how the matrix is factorised
(:mod:`origami_cad.simulation.factor`: banded Cholesky or SuperLU, whichever
the pattern suits) are computed once per structure; bars and hinges are evaluated and
added in place by compiled kernels. A Newton step is solved by conjugate
gradients preconditioned with the latest factorisation, kept across iterations
and actuation steps, while that converges in a few iterations; otherwise the
Hessian is factorised afresh, which also tells whether it is positive
definite: Levenberg damping is added where it is not. Conjugate gradients also
stop at a direction of non-positive curvature, which sends the step to a fresh
factorisation.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from origami_cad.errors import SimulationError
from origami_cad.simulation.cables import (
    SimString,
    StringSet,
    string_derivatives,
    string_hessian_pattern,
    string_lengths,
)
from origami_cad.simulation.factor import (
    Factor,
    FactorPlan,
    factorise,
    one_blas_thread,
    pardiso_available,
    plan_factorisation,
)
from origami_cad.simulation.mechanics import assemble_bars, assemble_hinges, bar_hinge_energy
from origami_cad.simulation.model import Structure

__all__ = [
    "Factor",
    "Ground",
    "HessianAssembly",
    "HessianOperator",
    "LowRank",
    "SimString",
    "SolveInfo",
    "StringSet",
    "Woodbury",
    "solve_equilibrium",
    "total_energy",
    "whole_newton_step",
]


@dataclass
class Ground:
    """A ground plane ``z = height`` with penalty contact and Coulomb friction.

    Attributes
    ----------
    height : float
        Height of the plane the nodes rest on, mm.
    stiffness : float
        Normal penalty stiffness per node, N/mm.
    friction : float
        Coulomb friction coefficient (0: frictionless).
    slip : float
        Regularisation of the stick-slip transition: a node pushed sideways by
        a force below ``mu N`` creeps by about ``slip`` mm per step, mm.
    anchors : ndarray, optional
        (n, 2) each node's position at the start of the step, mm.
    normal : ndarray, optional
        (n,) each node's normal force at the start of the step, N.
    """

    height: float
    stiffness: float = 100.0
    friction: float = 0.0
    slip: float = 1e-3
    anchors: np.ndarray | None = None
    normal: np.ndarray | None = None

    def start(self, x: np.ndarray) -> None:
        """Begin a step at ``x`` (n, 3): anchor the nodes there, take their normal forces."""
        self.anchors = x[:, :2].copy()
        self.normal = self.stiffness * np.clip(self.height - x[:, 2], 0.0, None)

    def energy(self, x: np.ndarray) -> float:
        below = np.clip(self.height - x[:, 2], 0.0, None)
        out = 0.5 * self.stiffness * float(np.dot(below, below))
        if self.friction > 0 and self.anchors is not None:
            d = x[:, :2] - self.anchors
            r = np.sqrt(np.einsum("ij,ij->i", d, d) + self.slip**2)
            out += self.friction * float(np.dot(self.normal, r - self.slip))
        return out

    def derivatives(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Gradient (n, 3), N, and per-node Hessian blocks (n, 3, 3), N/mm."""
        n = len(x)
        grad = np.zeros((n, 3))
        hess = np.zeros((n, 3, 3))
        below = self.height - x[:, 2]
        touching = below > 0
        grad[touching, 2] = -self.stiffness * below[touching]
        hess[touching, 2, 2] = self.stiffness
        if self.friction > 0 and self.anchors is not None:
            d = x[:, :2] - self.anchors
            r = np.sqrt(np.einsum("ij,ij->i", d, d) + self.slip**2)
            fn = self.friction * self.normal
            grad[:, :2] = (fn / r)[:, None] * d
            hess[:, :2, :2] = (fn / r)[:, None, None] * (
                np.eye(2) - d[:, :, None] * d[:, None, :] / (r**2)[:, None, None]
            )
        return grad, hess


def _hinge_terms(st: Structure) -> tuple:
    """The hinge arrays the compiled kernels take, in their order: hinges, stiffness
    (N mm/rad), rest angles and fold limits (rad), the limits' stiffness and margin,
    and the crease law (the soft hinges, the law's angles, rad, and stiffness factors).
    """
    return (
        st.hinges,
        st.hinge_k,
        st.hinge_rest,
        st.hinge_limit,
        float(st.limit_k),
        float(st.limit_margin),
        st.hinge_soft,
        st.law_angles,
        st.law_factors,
    )


def total_energy(
    x: np.ndarray,
    st: Structure,
    strings: StringSet | None,
    ground: Ground | None = None,
) -> float:
    """The total energy of configuration ``x`` (n, 3), N mm."""
    energy = bar_hinge_energy(
        np.ascontiguousarray(x, dtype=float),
        st.bars,
        st.bar_k,
        st.bar_rest,
        *_hinge_terms(st),
    )
    energy += float(np.dot(st.weight, x[:, 2]))
    if ground is not None:
        energy += ground.energy(x)
    if strings is not None and strings.strings:
        stretch = np.maximum(string_lengths(x, strings)[0] - _free_lengths(strings), 0.0)
        energy += 0.5 * float(np.dot(_stiffnesses(strings), stretch * stretch))
    return energy


def _free_lengths(strings: StringSet) -> np.ndarray:
    return np.array([s.free_length for s in strings.strings])


def _stiffnesses(strings: StringSet) -> np.ndarray:
    return np.array([s.stiffness for s in strings.strings])


def _dofs(nodes: np.ndarray) -> np.ndarray:
    """Degrees of freedom ``3 node + axis`` of node groups (..., m) -> (..., 3m)."""
    return (3 * nodes[..., :, None] + np.arange(3)).reshape(*nodes.shape[:-1], -1)


#: The strings' axial stiffness is kept out of the factorised matrix (:class:`LowRank`) from
#: this many free unknowns on, where MKL's PARDISO is installed (its nested-dissection
#: fill grows with a string's dense block). Below, and with the band, it stays in: there
#: the split changed no count of factorisations or iterations (measured on the 1,681-node
#: Miura) but the rounding, which moves calibrate's sensitive single-run fit.
SPLIT_STRINGS_SIZE = 20_000


@dataclass(frozen=True)
class LowRank:
    """The taut strings' axial stiffness ``U diag(k) U^T``, N/mm, kept out of the sparse
    Hessian: a string's ``g`` (the gradient of its length) spans every panel it rides on,
    so ``k g g^T`` would fill the factorised matrix along the whole string.

    Attributes
    ----------
    u : ndarray
        (size, r) each taut string's length gradient on the free degrees of freedom.
    k : ndarray
        (r,) their stiffnesses, N/mm.
    """

    u: np.ndarray
    k: np.ndarray

    def apply(self, p: np.ndarray) -> np.ndarray:
        """``U diag(k) U^T p`` for ``p`` (size,): column by column (a matrix product with
        a (size, 1) operand takes NumPy's slow path: 9 ms at 30,000 unknowns, measured)."""
        out = np.zeros_like(p)
        for column, k in zip(self.u.T, self.k, strict=True):
            out += (k * float(column @ p)) * column
        return out

    def dense(self) -> np.ndarray:
        """(size, size) the terms as a dense matrix (for tests and small checks)."""
        return (self.u * self.k) @ self.u.T


class HessianOperator:
    """The whole Hessian ``A + U diag(k) U^T``: the sparse part and the strings' low rank."""

    def __init__(self, a: sp.csc_matrix, low: LowRank) -> None:
        self.a = a
        self.low = low

    def __matmul__(self, p: np.ndarray) -> np.ndarray:
        out = self.a @ p
        if self.low.k.size:
            out += self.low.apply(p)
        return out

    def toarray(self) -> np.ndarray:
        """(size, size) the whole Hessian, dense."""
        return self.a.toarray() + self.low.dense()


class Woodbury:
    """``(A + U diag(k) U^T)^-1`` from a factorisation of ``A`` (Sherman-Morrison-Woodbury):
    ``A^-1 r - Z (diag(1/k) + U^T Z)^-1 U^T A^-1 r`` with ``Z = A^-1 U``, one solve by
    ``A``'s factor per application after ``r`` solves to set up (one per taut string).
    """

    def __init__(self, factor: Factor, low: LowRank) -> None:
        self.factor = factor
        self.low = low
        self.z = None
        if low.k.size:
            self.z = [factor.solve(np.ascontiguousarray(c)) for c in low.u.T]
            self.capacitance = np.diag(1.0 / low.k) + np.array(
                [[float(a @ b) for b in self.z] for a in low.u.T]
            )

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """The whole Hessian's inverse applied to ``rhs`` (size,)."""
        y = self.factor.solve(rhs)
        if self.z is not None:
            weights = np.linalg.solve(self.capacitance, [float(c @ y) for c in self.low.u.T])
            for z, w in zip(self.z, weights, strict=True):
                y -= w * z
        return y


class HessianAssembly:
    """The free-free Hessian's sparsity pattern and its assembly, computed once per structure.

    Every element block (bars 6 x 6, hinges 12 x 12, a node's 3 x 3 for contact,
    a string's nodes) has each of its entries mapped once to a position in the
    CSC data array (entries on held nodes go to one spare slot past the end).
    Each Newton iteration then only evaluates the elements and adds their
    values at those positions (:meth:`assemble`, compiled for bars and hinges),
    and factorises by a plan (banded Cholesky or SuperLU, and the elimination
    order) that is also computed once (:meth:`factorise`, :attr:`plan`).

    Parameters
    ----------
    st : Structure
        The bar-and-hinge model (its held nodes are left out of the matrix).
    strings : StringSet, optional
        The strings (their nodes couple through the string Hessians).
    split_strings : bool, optional
        Keep the taut strings' ``k g g^T`` out of the sparse matrix, as the
        :class:`LowRank` of :meth:`assemble` (default: from
        :data:`SPLIT_STRINGS_SIZE` free unknowns on, where PARDISO is installed).

    Attributes
    ----------
    free : ndarray
        (3n,) bool: which degrees of freedom ``3 node + axis`` are free.
    size, nnz : int
        The matrix's order (free degrees of freedom) and its stored entries.
    indices, indptr : ndarray
        The CSC pattern (int32).
    diagonal : ndarray
        Positions of the diagonal entries in the data array.
    preconditioner : Factor or None
        The latest positive-definite factorisation: kept between Newton
        iterations and between solves as the conjugate-gradient preconditioner.
    stale : bool
        Whether the next Newton step should factorise afresh instead.
    damping_hint : float
        The Levenberg damping (relative to the stiffest bar) that last made a
        refused Hessian positive definite: the next refusal goes straight to it
        instead of climbing from 1e-10 by tens (each try a factorisation).
    reuse_factorisations : bool
        Class-wide switch (default True): False factorises at every Newton step
        (the plain Newton method, for comparisons).
    plan : FactorPlan
        How the Hessian is factorised; its ``order`` is :attr:`ordering`.
    """

    def __init__(
        self, st: Structure, strings: StringSet | None = None, split_strings: bool | None = None
    ) -> None:
        n = len(st.x0)
        free = np.repeat(~st.fixed, 3)
        self.free = free
        index = np.full(3 * n, -1)
        index[free] = np.arange(int(free.sum()))
        self.size = int(free.sum())
        groups = [_dofs(st.bars), _dofs(st.hinges), _dofs(np.arange(n)[:, None])]
        masks = [True] * 3
        self.string_dofs: list[np.ndarray] = []
        if split_strings is None:
            split_strings = pardiso_available() and self.size >= SPLIT_STRINGS_SIZE
        self.split_strings = split_strings
        if strings is not None:  # a string's panels, as string_derivatives: neighbours only
            for s in strings.strings:
                nodes, mask = string_hessian_pattern(s)
                groups.append(_dofs(nodes[None, :]))
                masks.append(mask[None] if self.split_strings else True)
                self.string_dofs.append(index[_dofs(nodes)])
        keys, spans = [], []
        for dofs, mask in zip(groups, masks, strict=True):
            r = index[dofs][:, :, None]
            c = index[dofs][:, None, :]
            r, c = np.broadcast_arrays(r, c)
            key = np.where((r >= 0) & (c >= 0) & mask, c * self.size + r, -1).ravel()
            keys.append(key)
            spans.append(key.size)
        allkeys = np.concatenate(keys)
        valid = allkeys >= 0
        unique, inverse = np.unique(allkeys[valid], return_inverse=True)
        position = np.full(allkeys.size, unique.size)  # out-of-pattern entries land past the end
        position[valid] = inverse
        positions = np.split(position, np.cumsum(spans)[:-1])
        self.nnz = unique.size
        self.bar_positions = positions[0].reshape(len(st.bars), 36)
        self.hinge_positions = positions[1].reshape(len(st.hinges), 144)
        self.node_positions = positions[2].reshape(n, 9)
        self.string_positions = positions[3:]
        self.indices = (unique % self.size).astype(np.int32)
        cols = unique // self.size
        self.indptr = np.searchsorted(cols, np.arange(self.size + 1)).astype(np.int32)
        diag = unique[(unique % self.size) == (unique // self.size)]
        self.diagonal = np.searchsorted(unique, diag)
        self.preconditioner: Factor | None = None
        self.stale = False
        self.damping_hint = 0.0
        self._plan: FactorPlan | None = None

    def keep(self, factor: Factor) -> None:
        """Keep ``factor`` as the preconditioner of the next solves."""
        self.preconditioner = factor
        self.stale = False

    def count_iterations(self, iterations: int) -> None:
        """Record a preconditioned solve: past a few iterations, factorise afresh next time."""
        self.stale = iterations > _CG_REFRESH

    @property
    def positions(self) -> list[np.ndarray]:
        """Each group's entry positions, flat, in the order bars, hinges, nodes, strings."""
        return [
            self.bar_positions.ravel(),
            self.hinge_positions.ravel(),
            self.node_positions.ravel(),
            *self.string_positions,
        ]

    def assemble(
        self,
        x: np.ndarray,
        st: Structure,
        strings: StringSet | None,
        ground: Ground | None,
        hessian: bool = True,
    ) -> tuple[np.ndarray, np.ndarray | None, LowRank | None, list[float]]:
        """The energy's gradient and Hessian at ``x`` (n, 3), mm.

        Returns
        -------
        (grad, data, low_rank, tensions)
            The gradient (n, 3), N, on every node; the Hessian's values in the
            CSC pattern (nnz + 1,), N/mm, the last being the spare slot (see
            :meth:`matrix`), without the taut strings' axial stiffness ``k g g^T``,
            which is ``low_rank`` (:class:`LowRank`); each string's tension, N.
            Without ``hessian``, ``data`` and ``low_rank`` are None and the
            gradient (the same bits) costs about a tenth.
        """
        n = len(x)
        x = np.ascontiguousarray(x, dtype=float)
        grad = np.zeros((n, 3))
        data = np.zeros(self.nnz + 1 if hessian else 0)
        assemble_bars(x, st.bars, st.bar_k, st.bar_rest, self.bar_positions, grad, data)
        assemble_hinges(x, *_hinge_terms(st), self.hinge_positions, grad, data)
        grad[:, 2] += st.weight
        if ground is not None:
            g_ground, h_nodes = ground.derivatives(x)
            grad += g_ground
            if hessian:
                data[self.node_positions] += h_nodes.reshape(n, 9)  # one node: distinct
        tensions = []
        columns, stiffness = [], []
        if strings is not None:
            tensions = _string_tensions(x, strings)
            for s, pos, dofs, tension in zip(
                strings.strings, self.string_positions, self.string_dofs, tensions, strict=True
            ):
                if tension > 0:
                    nodes, g, h = string_derivatives(x, s, strings)
                    grad[nodes] += tension * g
                    if not hessian:
                        continue
                    if not self.split_strings:
                        gf = g.ravel()
                        data[pos] += (s.stiffness * np.outer(gf, gf) + tension * h).ravel()
                        continue
                    data[pos] += tension * h.ravel()  # zero outside the pattern's mask
                    column = np.zeros(self.size)
                    column[dofs[dofs >= 0]] = g.ravel()[dofs >= 0]
                    columns.append(column)
                    stiffness.append(s.stiffness)
        if not hessian:
            return grad, None, None, tensions
        u = np.zeros((self.size, len(columns)), order="F")  # columns contiguous
        for j, column in enumerate(columns):
            u[:, j] = column
        low = LowRank(u, np.array(stiffness, dtype=float))
        return grad, data, low, tensions

    def matrix(self, data: np.ndarray, shift: float = 0.0) -> sp.csc_matrix:
        """The free-free Hessian's sparse part (size, size) from :meth:`assemble`'s values,
        plus ``shift`` I (the strings' low rank apart: :meth:`operator`)."""
        values = data[: self.nnz].copy()
        values[self.diagonal] += shift
        return sp.csc_matrix((values, self.indices, self.indptr), shape=(self.size, self.size))

    def operator(self, data: np.ndarray, low: LowRank, shift: float = 0.0) -> HessianOperator:
        """The whole free-free Hessian plus ``shift`` I: :meth:`matrix` and ``low``."""
        return HessianOperator(self.matrix(data, shift), low)

    reuse_factorisations = True

    @property
    def plan(self) -> FactorPlan:
        """How this pattern is factorised (computed at the first use, then kept)."""
        if self._plan is None:
            self._plan = plan_factorisation(self.indices, self.indptr, self.diagonal)
        return self._plan

    @property
    def ordering(self) -> np.ndarray:
        """(size,) the elimination order: row and column ``ordering[k]`` of the Hessian
        is the factorised matrix's ``k``-th."""
        return self.plan.order

    def factorise(self, data: np.ndarray, shift: float = 0.0) -> Factor | None:
        """Factorisation of the Hessian plus ``shift`` I (:func:`factor.factorise`).

        Returns None unless the matrix is positive definite (or when it is exactly
        singular).
        """
        values = data[: self.nnz].copy()
        values[self.diagonal] += shift
        return factorise(self.plan, values)


def _pcg(a: HessianOperator, rhs: np.ndarray, factor: Woodbury, rtol: float, max_iter: int):
    """Conjugate gradients on ``a x = rhs`` preconditioned by an earlier factorisation.

    Returns ``(x, iterations)``; ``x`` is None when it did not reach ``rtol``
    (relative residual) within ``max_iter`` iterations, unless its residual is
    then within :data:`_CG_LOOSE` (an inexact Newton step, which the line search
    still checks), or when it met a direction of non-positive curvature (``a``
    not positive definite there).
    """
    x = np.zeros_like(rhs)
    r = rhs.copy()
    z = factor.solve(r)
    p = z.copy()
    rz = float(r @ z)
    target = rtol * float(np.linalg.norm(rhs))
    for it in range(1, max_iter + 1):
        ap = a @ p
        curvature = float(p @ ap)
        if not curvature > 0 or not rz > 0:
            return None, it
        alpha = rz / curvature
        x += alpha * p
        r -= alpha * ap
        if float(np.linalg.norm(r)) <= target:
            return x, it
        z = factor.solve(r)
        rz_next = float(r @ z)
        p = z + (rz_next / rz) * p
        rz = rz_next
    if float(np.linalg.norm(r)) <= _CG_LOOSE * float(np.linalg.norm(rhs)):
        return x, max_iter  # an inexact Newton step still: keep what it cost
    return None, max_iter


@dataclass
class SolveInfo:
    """What one equilibrium solve did.

    Attributes
    ----------
    iterations : int
        Accepted Newton iterations.
    factorisations : int
        Sparse factorisations (a damped retry counts again).
    cg_iterations : int
        Preconditioned conjugate-gradient iterations, over all Newton steps.
    energies : list of float
        The energy at the start and after each accepted iteration, N mm.
    gradient_norm : float
        The largest residual force on a free node at the end, N.
    converged : bool
        Whether that residual fell below the tolerance.
    tensions : list of float
        Each string's tension at the end, N.
    timed_out : bool
        Whether the solve stopped at its ``deadline`` before it converged.
    """

    iterations: int = 0
    factorisations: int = 0
    cg_iterations: int = 0
    energies: list[float] = field(default_factory=list)
    gradient_norm: float = math.inf
    converged: bool = False
    tensions: list[float] = field(default_factory=list)
    timed_out: bool = False


# conjugate gradients: relative residual and iterations at most, and the iterations
# beyond which the preconditioner counts as stale (measured on the benchmark's
# Miura: a factorisation costs about 20 preconditioned iterations, and the
# iterations grow quickly as the preconditioner ages)
_CG_RTOL = 1e-3
_CG_MAX_ITER = 30
_CG_REFRESH = 5
# the relative residual at which a solve that ran out of iterations is still taken
# (the box pleat's slow solves end at 2e-3 to 1e-2: a factorisation saved each)
_CG_LOOSE = 1e-2
# the least Levenberg damping (relative to the stiffest bar) tried on a Hessian that is
# not positive definite: smaller ones never made the box pleat's positive definite
# (1e-10 to 1e-7: three wasted factorisations at each refusal, measured)
_LEAST_DAMPING = 1e-7


def _line_search(x, step, g, energy, free, st, strings, ground):
    """Armijo backtracking along ``step``: (accepted, t, trial x, trial energy)."""
    slope = float(g @ step)
    t = 1.0
    while t > 1e-6 and slope < 0:
        trial = x.copy()
        trial.reshape(-1)[free] += t * step
        e_trial = total_energy(trial, st, strings, ground)
        if e_trial <= energy + 1e-4 * t * slope:
            return True, t, trial, e_trial
        t *= 0.5
    return False, t, x, energy


def solve_equilibrium(
    x: np.ndarray,
    st: Structure,
    strings: StringSet | None = None,
    *,
    ground: Ground | None = None,
    tol: float = 1e-7,
    max_iter: int = 200,
    assembly: HessianAssembly | None = None,
    whole_step: bool = False,
    deadline: float = math.inf,
) -> tuple[np.ndarray, SolveInfo]:
    """Minimise the energy from ``x`` (n, 3), mm, with the held nodes fixed.

    Each Newton step solves ``H step = -g`` by conjugate gradients preconditioned
    with the latest factorisation of ``H`` (kept in the assembly) while that takes
    few iterations, else by a fresh one (Levenberg damping where not positive definite).

    Parameters
    ----------
    x : ndarray
        Starting configuration (n, 3), mm.
    st : Structure
        The bar-and-hinge model.
    strings : StringSet, optional
        Strings and the TSA's current rotation.
    ground : Ground, optional
        Ground plane with its friction anchors (``ground.start`` after each step).
    tol : float
        Convergence: largest residual force on a free node, N.
    max_iter : int
        Newton iterations at most.
    assembly : HessianAssembly, optional
        The structure's Hessian pattern (built here when not given); pass the
        same one to successive solves to reuse its ordering and preconditioner.
    whole_step : bool
        First one whole step of :func:`whole_newton_step` (from the flat sheet).
    deadline : float
        A :func:`time.monotonic` time, s: no Newton iteration starts after it; the solve
        then returns where it is, unconverged, with ``info.timed_out`` (default: none).

    Returns
    -------
    (x, SolveInfo)
        The equilibrium (n, 3), mm, and what the solve did.
    """
    with one_blas_thread():  # its vector products are too short for two threads
        return _newton(x, st, strings, ground, tol, max_iter, assembly, whole_step, deadline)


def _newton(x, st, strings, ground, tol, max_iter, assembly, whole_step, deadline=math.inf):
    """:func:`solve_equilibrium`'s Newton iterations (its arguments, in its order)."""
    x = np.array(x, dtype=float)
    asm = assembly or HessianAssembly(st, strings)
    x = whole_newton_step(x, st, asm) if whole_step else x
    problem = (asm.free, st, strings, ground)
    info = SolveInfo()
    energy = total_energy(x, st, strings, ground)
    info.energies.append(energy)
    scale = max(float(np.max(st.bar_k)), 1.0)
    damping = 0.0
    for it in range(max_iter):
        # the gradient first (a tenth of the Hessian's cost): a converged state needs no more
        grad, _, _, tensions = asm.assemble(x, st, strings, ground, hessian=False)
        g = grad.ravel()[asm.free]
        info.gradient_norm = float(np.max(np.abs(g))) if g.size else 0.0
        info.tensions = tensions
        if not np.all(np.isfinite(g)):
            raise SimulationError("the simulation diverged (a degenerate panel or string?)")
        if info.gradient_norm < tol:
            info.converged = True
            break
        if time.monotonic() > deadline:
            info.timed_out = True
            break
        _, *hessian, _ = asm.assemble(x, st, strings, ground)  # values, low rank
        found = _preconditioned_step(x, g, hessian, energy, damping * scale, asm, info, problem)
        if found is None:
            damping, found = _factorised_step(
                x, g, hessian, energy, damping, scale, asm, info, problem
            )
        if found is None:
            break  # no descent possible: as converged as the model allows
        t, step, x, e_trial = found
        moved = abs(energy - e_trial)
        energy = e_trial
        info.energies.append(energy)
        damping = damping / 100.0 if damping > 1e-12 else 0.0
        info.iterations = it + 1
        if moved <= 1e-15 * max(abs(energy), 1.0) and t * float(np.max(np.abs(step))) < 1e-10:
            info.converged = True
            break
    if strings is not None:
        info.tensions = _string_tensions(x, strings)
    return x, info


def whole_newton_step(x: np.ndarray, st: Structure, assembly: HessianAssembly) -> np.ndarray:
    """``x`` (n, 3), mm, moved by one whole Newton step of the structure's energy
    (no strings, no ground), without a line search; ``x`` itself where the Hessian is
    not positive definite.

    From the flat sheet (a bifurcation point) this is the start that
    :func:`solve_equilibrium` needs: there the step folds the creases toward their
    rest angles linearly, and the line search would cut it about 16-fold (the bars
    stretch to second order in the out-of-plane motion), after which Newton's
    method wanders for tens of iterations. From the whole step it converges in a
    third of the iterations, to the same state (within 1e-7 mm on the benchmark's
    Miura, measured).
    """
    grad, values, _, _ = assembly.assemble(x, st, None, None)
    factor = assembly.factorise(values)
    out = np.array(x, dtype=float)
    if factor is not None:
        out.reshape(-1)[assembly.free] -= factor.solve(grad.ravel()[assembly.free])
    return out if np.all(np.isfinite(out)) else np.array(x, dtype=float)


def _string_tensions(x: np.ndarray, strings: StringSet) -> list[float]:
    """Each string's tension at ``x`` (n, 3) mm, N: its stiffness times its stretch, or 0."""
    if not strings.strings:
        return []
    stretch = string_lengths(x, strings)[0] - _free_lengths(strings)
    return (_stiffnesses(strings) * np.maximum(stretch, 0.0)).tolist()


def _preconditioned_step(x, g, hessian, energy, shift, asm, info, problem):
    """A Newton step by conjugate gradients preconditioned by the latest factorisation.

    ``hessian`` is ``(values, low rank)`` of :meth:`HessianAssembly.assemble`,
    ``shift`` the Levenberg damping (N/mm) added to the Hessian's diagonal and
    ``problem`` ``(free dofs, structure, strings, ground)``. The preconditioner is
    the latest factorisation of the sparse part with the strings' present low rank
    (:class:`Woodbury`). Returns ``(t, step, trial x, trial energy)`` when the line
    search accepts it, else None (and the preconditioner is marked stale when it
    was tried).
    """
    pre = asm.preconditioner
    if not (asm.reuse_factorisations and pre is not None and pre.valid and not asm.stale):
        return None
    values, low = hessian
    a = asm.operator(values, low, shift)
    step, cg_iterations = _pcg(a, -g, Woodbury(pre, low), _CG_RTOL, _CG_MAX_ITER)
    info.cg_iterations += cg_iterations
    asm.count_iterations(cg_iterations)
    if step is not None:
        accepted, t, trial, e_trial = _line_search(x, step, g, energy, *problem)
        if accepted:
            return t, step, trial, e_trial
    asm.stale = True
    return None


def _factorised_step(x, g, hessian, energy, damping, scale, asm, info, problem):
    """A Newton step by a fresh factorisation, the damping raised until it descends.

    The factorisation's pivots check that the damped Hessian's sparse part
    (``damping * scale`` on its diagonal) is positive definite, and so the whole
    Hessian (the strings' low rank adds a positive semi-definite term); the step
    solves the whole Hessian (:class:`Woodbury`). Returns ``(damping, (t, step,
    trial x, trial energy))``, the step None when 16 tries found no descent.
    """
    values, low = hessian
    refused = False
    for _ in range(16):
        factor = asm.factorise(values, damping * scale)
        info.factorisations += 1
        if factor is None:  # not positive definite: straight to the damping that last did
            refused = True
            damping = max(damping * 10.0, _LEAST_DAMPING, asm.damping_hint)
            continue
        if refused:
            asm.damping_hint = damping
        asm.keep(factor)
        a = asm.operator(values, low, damping * scale)
        whole = Woodbury(factor, low)
        step = -whole.solve(g)
        step -= whole.solve(g + a @ step)  # one round of iterative refinement
        accepted, t, trial, e_trial = _line_search(x, step, g, energy, *problem)
        if accepted:
            return damping, (t, step, trial, e_trial)
        damping = max(damping * 10.0, 1e-10)
    return damping, None
