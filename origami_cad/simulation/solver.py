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
derivatives, the exit points' curvature) with Levenberg damping where that
Hessian is not positive definite (checked by the inertia of its LDL^T
factorisation), sparse SuperLU with a symmetric minimum-degree ordering, and an
Armijo backtracking line search, so the energy decreases at every accepted
iteration (recorded, and asserted by the tests).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from origami_cad.errors import SimulationError
from origami_cad.simulation.cables import SimString, StringSet, string_derivatives, string_length
from origami_cad.simulation.mechanics import (
    bar_hessians,
    bar_lengths,
    fold_angles,
    hinge_gradients,
    hinge_hessians,
)
from origami_cad.simulation.model import Structure

__all__ = [
    "Ground",
    "SimString",
    "SolveInfo",
    "StringSet",
    "solve_equilibrium",
    "total_energy",
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


def total_energy(
    x: np.ndarray,
    st: Structure,
    strings: StringSet | None,
    ground: Ground | None = None,
) -> float:
    """The total energy of configuration ``x`` (n, 3), N mm."""
    length, _ = bar_lengths(x, st.bars)
    energy = 0.5 * float(np.sum(st.bar_k * (length - st.bar_rest) ** 2))
    rho = fold_angles(x, st.hinges)
    energy += 0.5 * float(np.sum(st.hinge_k * (rho - st.hinge_rest) ** 2))
    over = np.abs(rho) - (st.hinge_limit - st.limit_margin)
    energy += 0.5 * st.limit_k * float(np.sum(np.where(over > 0, over, 0.0) ** 2))
    energy += float(np.dot(st.weight, x[:, 2]))
    if ground is not None:
        energy += ground.energy(x)
    if strings is not None:
        for s in strings.strings:
            stretch = string_length(x, s, strings)[0] - s.free_length
            if stretch > 0:
                energy += 0.5 * s.stiffness * stretch**2
    return energy


def _dofs(nodes: np.ndarray) -> np.ndarray:
    """Degrees of freedom ``3 node + axis`` of node groups (..., m) -> (..., 3m)."""
    return (3 * nodes[..., :, None] + np.arange(3)).reshape(*nodes.shape[:-1], -1)


class _Assembly:
    """The free-free Hessian's sparsity pattern, computed once per structure.

    Each element block (bars 6 x 6, hinges 12 x 12, a string's nodes, a node's
    3 x 3 for contact and damping) maps its entries to positions in the CSC data
    array, so that each iteration only sums values (``np.bincount``).
    """

    def __init__(self, st: Structure, strings: StringSet | None) -> None:
        n = len(st.x0)
        free = np.repeat(~st.fixed, 3)
        self.free = free
        index = np.full(3 * n, -1)
        index[free] = np.arange(int(free.sum()))
        self.size = int(free.sum())
        groups = [_dofs(st.bars), _dofs(st.hinges), _dofs(np.arange(n)[:, None])]
        if strings is not None:  # every panel a string's points ride on, as string_derivatives
            groups += [_dofs(np.unique(s.frames()[0].ravel())[None, :]) for s in strings.strings]
        keys, spans = [], []
        for dofs in groups:
            r = index[dofs][:, :, None]
            c = index[dofs][:, None, :]
            r, c = np.broadcast_arrays(r, c)
            key = np.where((r >= 0) & (c >= 0), c * self.size + r, -1).ravel()
            keys.append(key)
            spans.append(key.size)
        allkeys = np.concatenate(keys)
        valid = allkeys >= 0
        unique, inverse = np.unique(allkeys[valid], return_inverse=True)
        position = np.full(allkeys.size, unique.size)  # out-of-pattern entries land past the end
        position[valid] = inverse
        self.positions = np.split(position, np.cumsum(spans)[:-1])
        self.nnz = unique.size
        self.indices = (unique % self.size).astype(np.int32)
        cols = unique // self.size
        self.indptr = np.searchsorted(cols, np.arange(self.size + 1)).astype(np.int32)
        diag = unique[(unique % self.size) == (unique // self.size)]
        self.diagonal = np.searchsorted(unique, diag)

    def matrix(self, values: list[np.ndarray], shift: float = 0.0) -> sp.csc_matrix:
        data = np.zeros(self.nnz + 1)
        for pos, val in zip(self.positions, values, strict=False):
            if val is not None:
                data += np.bincount(pos, weights=val.ravel(), minlength=self.nnz + 1)
        data = data[:-1]
        data[self.diagonal] += shift
        return sp.csc_matrix((data, self.indices, self.indptr), shape=(self.size, self.size))


def _gradient_hessian(x, st: Structure, strings: StringSet | None, ground: Ground | None):
    """Gradient (n, 3) and the element Hessian blocks in the assembly's order."""
    n = len(x)
    grad = np.zeros((n, 3))
    length, unit = bar_lengths(x, st.bars)
    force = st.bar_k * (length - st.bar_rest)
    np.add.at(grad, st.bars[:, 1], force[:, None] * unit)
    np.add.at(grad, st.bars[:, 0], -force[:, None] * unit)
    h_bars = bar_hessians(x, st.bars, st.bar_k, st.bar_rest)
    rho = fold_angles(x, st.hinges)
    dr = hinge_gradients(x, st.hinges)
    over = np.abs(rho) - (st.hinge_limit - st.limit_margin)
    active = over > 0
    moment = st.hinge_k * (rho - st.hinge_rest) + np.where(
        active, st.limit_k * over, 0.0
    ) * np.sign(rho)
    np.add.at(grad, st.hinges.ravel(), (moment[:, None, None] * dr).reshape(-1, 3))
    k_rot = st.hinge_k + np.where(active, st.limit_k, 0.0)
    drf = dr.reshape(len(dr), 12)
    h_hinges = k_rot[:, None, None] * drf[:, :, None] * drf[:, None, :]
    h_hinges += moment[:, None, None] * hinge_hessians(x, st.hinges)
    grad[:, 2] += st.weight
    h_nodes = None
    if ground is not None:
        g_ground, h_nodes = ground.derivatives(x)
        grad += g_ground
    values = [h_bars, h_hinges, h_nodes]
    tensions = []
    if strings is not None:
        for s in strings.strings:
            total, _ = string_length(x, s, strings)
            stretch = total - s.free_length
            tension = s.stiffness * stretch if stretch > 0 else 0.0
            tensions.append(tension)
            if tension > 0:
                nodes, g, h = string_derivatives(x, s, strings)
                grad[nodes] += tension * g
                gf = g.ravel()
                values.append(s.stiffness * np.outer(gf, gf) + tension * h)
            else:
                values.append(None)
    return grad, values, tensions


@dataclass
class SolveInfo:
    """What one equilibrium solve did."""

    iterations: int = 0
    factorisations: int = 0
    energies: list[float] = field(default_factory=list)
    gradient_norm: float = math.inf
    converged: bool = False
    tensions: list[float] = field(default_factory=list)


def _factorise(a: sp.csc_matrix):
    """LDL^T-like factorisation with diagonal pivots; None unless ``a`` is positive definite."""
    try:
        lu = splu(
            a,
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    except RuntimeError:  # exactly singular
        return None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return None
    pivots = lu.U.diagonal()
    if not np.all(pivots > 0):
        return None  # Sylvester: a non-positive pivot means the matrix is not positive definite
    return lu


def solve_equilibrium(
    x: np.ndarray,
    st: Structure,
    strings: StringSet | None = None,
    *,
    ground: Ground | None = None,
    tol: float = 1e-7,
    max_iter: int = 200,
    assembly: _Assembly | None = None,
) -> tuple[np.ndarray, SolveInfo]:
    """Minimise the energy from ``x`` (n, 3), mm, with the held nodes fixed.

    Parameters
    ----------
    x : ndarray
        Starting configuration (n, 3), mm.
    st : Structure
        The bar-and-hinge model.
    strings : StringSet, optional
        Strings and the TSA's current rotation.
    ground : Ground, optional
        Ground plane with its friction anchors (advance them with ``ground.slip``
        after each step).
    tol : float
        Convergence: largest residual force on a free node, N.
    max_iter : int
        Newton iterations at most.

    Returns
    -------
    (x, SolveInfo)
        The equilibrium (n, 3), mm, and what the solve did.
    """
    x = np.array(x, dtype=float)
    asm = assembly or _Assembly(st, strings)
    free = asm.free
    info = SolveInfo()
    energy = total_energy(x, st, strings, ground)
    info.energies.append(energy)
    scale = max(float(np.max(st.bar_k)), 1.0)
    damping = 0.0
    for it in range(max_iter):
        grad, values, tensions = _gradient_hessian(x, st, strings, ground)
        g = grad.ravel()[free]
        info.gradient_norm = float(np.max(np.abs(g))) if g.size else 0.0
        info.tensions = tensions
        if not np.all(np.isfinite(g)):
            raise SimulationError("the simulation diverged (a degenerate panel or string?)")
        if info.gradient_norm < tol:
            info.converged = True
            break
        accepted = False
        for _ in range(16):
            a = asm.matrix(values, damping * scale)
            lu = _factorise(a)
            info.factorisations += 1
            if lu is None:
                damping = max(damping * 10.0, 1e-10)
                continue
            step = -lu.solve(g)
            step -= lu.solve(g + a @ step)  # one round of iterative refinement
            slope = float(g @ step)
            t = 1.0
            while t > 1e-6 and slope < 0:
                trial = x.copy()
                trial.reshape(-1)[free] += t * step
                e_trial = total_energy(trial, st, strings, ground)
                if e_trial <= energy + 1e-4 * t * slope:
                    accepted = True
                    break
                t *= 0.5
            if accepted:
                break
            damping = max(damping * 10.0, 1e-10)
        if not accepted:
            break  # no descent possible: as converged as the model allows
        x = trial
        moved = abs(energy - e_trial)
        energy = e_trial
        info.energies.append(energy)
        damping = damping / 100.0 if damping > 1e-12 else 0.0
        info.iterations = it + 1
        if moved <= 1e-15 * max(abs(energy), 1.0) and t * float(np.max(np.abs(step))) < 1e-10:
            info.converged = True
            break
    if strings is not None:
        info.tensions = [
            max(0.0, s.stiffness * (string_length(x, s, strings)[0] - s.free_length))
            for s in strings.strings
        ]
    return x, info
