"""Quasi-static equilibrium of the bar-and-hinge model with strings.

Total energy (N mm)::

    E = sum_bars k/2 (L - L0)^2 + sum_hinges k/2 (rho - rho0)^2
      + sum_limits k_lim/2 (|rho| - (rho_max - margin))_+^2           (smooth barrier)
      + sum_strings k_s/2 (L_s - L_free)_+^2                          (tension only)
      + sum_nodes W z + k_g/2 (z_ground - z)_+^2                      (gravity, ground)

Each solve minimises E over the free nodes by Gauss-Newton with Levenberg
damping on sparse matrices and an Armijo backtracking line search, so the
energy decreases at every accepted iteration (recorded, and asserted by the
tests). A string's length runs from its anchor through its holes (on the panel
faces, half the thickness off the mid-surface); its TSA's share follows the
same model as the DCQC simulation (``TSAParams.consumed``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from origami_cad.errors import OrigamiCadError
from origami_cad.simulation.mechanics import bar_lengths, fold_angles, hinge_gradients
from origami_cad.simulation.model import Structure

__all__ = ["SimString", "SolveInfo", "StringSet", "solve_equilibrium", "total_energy"]


@dataclass
class SimString:
    """A string in the model: anchor (mm), holes as node triples with affine coordinates."""

    anchor: np.ndarray  # (3,)
    tri: np.ndarray  # (k, 3) node indices of each hole's panel frame
    ab: np.ndarray  # (k, 2) affine coordinates of each hole in that frame
    orient: np.ndarray  # (k,) +1/-1: keeps the frame normal on the top face
    sides: np.ndarray  # (k,) +1 top / -1 bottom: face along which the string reaches hole k
    through: float  # length spent crossing the sheet where the side changes, mm
    free_length: float = math.inf  # L0: the string's length (mm)
    stiffness: float = 0.0  # EA / L0, N/mm


@dataclass
class StringSet:
    strings: list[SimString]
    offset: float  # half the panel thickness, mm
    tsa: object  # TSAParams
    theta: float = 0.0  # TSA rotation, rad


def _exits(x: np.ndarray, s: SimString, e: float) -> tuple[np.ndarray, np.ndarray]:
    v0, v1, v2 = x[s.tri[:, 0]], x[s.tri[:, 1]], x[s.tri[:, 2]]
    e1, e2 = v1 - v0, v2 - v0
    centre = v0 + s.ab[:, :1] * e1 + s.ab[:, 1:] * e2
    n = np.cross(e1, e2) * s.orient[:, None]
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    arrive = centre + e * s.sides[:, None] * n
    leave_sides = np.r_[s.sides[1:], s.sides[-1]]
    leave = centre + e * leave_sides[:, None] * n
    return arrive, leave


def string_length(x: np.ndarray, s: SimString, strings: StringSet) -> tuple[float, float]:
    """(length demanded by the string incl. the TSA's share, x_dis), mm."""
    arrive, leave = _exits(x, s, strings.offset)
    x_dis = float(np.linalg.norm(arrive[0] - s.anchor))
    rest = float(np.linalg.norm(arrive[1:] - leave[:-1], axis=1).sum()) + s.through
    return float(strings.tsa.consumed(strings.theta, x_dis)) + rest, x_dis


def _skew(v: np.ndarray) -> np.ndarray:
    """Cross-product matrices ``[v]x`` of vectors ``v`` (k, 3), shape (k, 3, 3)."""
    out = np.zeros((len(v), 3, 3))
    out[:, 0, 1], out[:, 0, 2] = -v[:, 2], v[:, 1]
    out[:, 1, 0], out[:, 1, 2] = v[:, 2], -v[:, 0]
    out[:, 2, 0], out[:, 2, 1] = -v[:, 1], v[:, 0]
    return out


def _exit_jacobians(x: np.ndarray, s: SimString, e: float, sides: np.ndarray) -> np.ndarray:
    """d(exit point)/d(v0, v1, v2) for each hole, shape (k, 3, 3, 3): [hole, node, out, in]."""
    v0, v1, v2 = x[s.tri[:, 0]], x[s.tri[:, 1]], x[s.tri[:, 2]]
    e1, e2 = v1 - v0, v2 - v0
    n = np.cross(e1, e2) * s.orient[:, None]
    norm = np.linalg.norm(n, axis=1)
    nh = n / norm[:, None]
    proj = (np.eye(3)[None] - nh[:, :, None] * nh[:, None, :]) / norm[:, None, None]
    # d n = o (d e1 x e2 + e1 x d e2) = o (-[e2]x d e1 + [e1]x d e2)
    dn_de1 = -_skew(e2) * s.orient[:, None, None]
    dn_de2 = _skew(e1) * s.orient[:, None, None]
    off = (e * sides)[:, None, None]
    eye = np.eye(3)[None]
    d1 = s.ab[:, 0, None, None] * eye + off * proj @ dn_de1
    d2 = s.ab[:, 1, None, None] * eye + off * proj @ dn_de2
    d0 = eye - d1 - d2
    return np.stack([d0, d1, d2], axis=1)


def _string_gradient(x: np.ndarray, s: SimString, strings: StringSet):
    """Gradient of a string's length w.r.t. its panels' nodes (analytic): (nodes, (m, 3))."""
    arrive, leave = _exits(x, s, strings.offset)
    leave_sides = np.r_[s.sides[1:], s.sides[-1]]
    ja = _exit_jacobians(x, s, strings.offset, s.sides)
    jl = _exit_jacobians(x, s, strings.offset, leave_sides)
    # d length / d points
    ga = np.zeros_like(arrive)
    gl = np.zeros_like(leave)
    first = arrive[0] - s.anchor
    x_dis = float(np.linalg.norm(first))
    h = 1e-6 * max(x_dis, 1.0)
    rate = (
        float(strings.tsa.consumed(strings.theta, x_dis + h))
        - float(strings.tsa.consumed(strings.theta, x_dis - h))
    ) / (2 * h)
    ga[0] += rate * first / x_dis
    seg = arrive[1:] - leave[:-1]
    unit = seg / np.linalg.norm(seg, axis=1, keepdims=True)
    ga[1:] += unit
    gl[:-1] -= unit
    per_node = np.einsum("ko,kjoi->kji", ga, ja) + np.einsum("ko,kjoi->kji", gl, jl)
    nodes, inverse = np.unique(s.tri.ravel(), return_inverse=True)
    grad = np.zeros((len(nodes), 3))
    np.add.at(grad, inverse, per_node.reshape(-1, 3))
    return nodes, grad


def total_energy(
    x: np.ndarray,
    st: Structure,
    strings: StringSet | None,
    ground_k: float = 0.0,
    ground: float | None = None,
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
        below = ground - x[:, 2]
        energy += 0.5 * ground_k * float(np.sum(np.where(below > 0, below, 0.0) ** 2))
    if strings is not None:
        for s in strings.strings:
            stretch = string_length(x, s, strings)[0] - s.free_length
            if stretch > 0:
                energy += 0.5 * s.stiffness * stretch**2
    return energy


def _gradient_hessian(x, st: Structure, strings: StringSet | None, ground_k, ground):
    n = len(x)
    grad = np.zeros((n, 3))
    rows, cols, vals = [], [], []

    def add_block(nodes: np.ndarray, g: np.ndarray, k: np.ndarray) -> None:
        # Gauss-Newton term k g g^T over the dofs of ``nodes`` (batched)
        dofs = (3 * nodes[:, :, None] + np.arange(3)[None, None, :]).reshape(len(nodes), -1)
        gflat = g.reshape(len(nodes), -1)
        m = dofs.shape[1]
        rows.append(np.repeat(dofs, m, axis=1).ravel())
        cols.append(np.tile(dofs, (1, m)).ravel())
        vals.append((k[:, None, None] * gflat[:, :, None] * gflat[:, None, :]).ravel())

    length, unit = bar_lengths(x, st.bars)
    force = st.bar_k * (length - st.bar_rest)
    np.add.at(grad, st.bars[:, 1], force[:, None] * unit)
    np.add.at(grad, st.bars[:, 0], -force[:, None] * unit)
    add_block(st.bars, np.stack([-unit, unit], axis=1), st.bar_k)
    rho = fold_angles(x, st.hinges)
    dr = hinge_gradients(x, st.hinges)
    over = np.abs(rho) - (st.hinge_limit - st.limit_margin)
    active = over > 0
    moment = st.hinge_k * (rho - st.hinge_rest) + np.where(
        active, st.limit_k * over, 0.0
    ) * np.sign(rho)
    for c in range(4):
        np.add.at(grad, st.hinges[:, c], moment[:, None] * dr[:, c])
    add_block(st.hinges, dr, st.hinge_k + np.where(active, st.limit_k, 0.0))
    grad[:, 2] += st.weight
    if ground is not None:
        below = ground - x[:, 2]
        touching = below > 0
        grad[touching, 2] -= ground_k * below[touching]
        idx = np.flatnonzero(touching)
        rows.append(3 * idx + 2)
        cols.append(3 * idx + 2)
        vals.append(np.full(len(idx), ground_k))
    tensions = []
    if strings is not None:
        for s in strings.strings:
            total, _ = string_length(x, s, strings)
            stretch = total - s.free_length
            tension = s.stiffness * stretch if stretch > 0 else 0.0
            tensions.append(tension)
            if tension > 0:
                nodes, g = _string_gradient(x, s, strings)
                np.add.at(grad, nodes, tension * g)
                add_block(nodes[None, :], g[None, :, :], np.array([s.stiffness]))
    hess = sp.coo_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(3 * n, 3 * n)
    ).tocsr()
    return grad, hess, tensions


@dataclass
class SolveInfo:
    """What one equilibrium solve did."""

    iterations: int = 0
    energies: list[float] = field(default_factory=list)
    gradient_norm: float = math.inf
    converged: bool = False
    tensions: list[float] = field(default_factory=list)


def solve_equilibrium(
    x: np.ndarray,
    st: Structure,
    strings: StringSet | None = None,
    *,
    tol: float = 1e-7,
    max_iter: int = 200,
    ground_k: float = 100.0,
    ground: float | None = None,
) -> tuple[np.ndarray, SolveInfo]:
    """Minimise the energy from ``x`` with the held nodes fixed; returns (x, info)."""
    x = np.array(x, dtype=float)
    free = np.repeat(~st.fixed, 3)
    info = SolveInfo()
    energy = total_energy(x, st, strings, ground_k, ground)
    info.energies.append(energy)
    damping = 1e-9
    scale = max(float(np.max(st.bar_k)), 1.0)
    for it in range(max_iter):
        grad, hess, tensions = _gradient_hessian(x, st, strings, ground_k, ground)
        g = grad.ravel()[free]
        info.gradient_norm = float(np.max(np.abs(g))) if g.size else 0.0
        info.tensions = tensions
        if not np.all(np.isfinite(g)):
            raise OrigamiCadError("the simulation diverged (a degenerate panel or string?)")
        if info.gradient_norm < tol:
            info.converged = True
            break
        h = hess[free][:, free]
        accepted = False
        for _ in range(12):
            a = h + sp.identity(h.shape[0], format="csr") * (damping * scale)
            step = -spsolve(a.tocsc(), g)
            slope = float(g @ step)
            t = 1.0
            while t > 1e-6:
                trial = x.copy()
                trial.reshape(-1)[free] += t * step
                e_trial = total_energy(trial, st, strings, ground_k, ground)
                if e_trial <= energy + 1e-4 * t * slope:
                    accepted = True
                    break
                t *= 0.5
            if accepted:
                break
            damping = max(damping * 100.0, 1e-9)
        if not accepted:
            break  # no descent possible: as converged as the model allows
        x = trial
        moved = abs(energy - e_trial)
        energy = e_trial
        info.energies.append(energy)
        damping = max(damping / 10.0, 1e-12)
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
