"""Bar-and-hinge mechanics: bar lengths and hinge fold angles, their gradients and Hessians.

Over all bars and hinges at once. A hinge is four nodes ``(i, j, k, l)``: the
axis ``i -> j`` shared by the triangles ``(i, j, k)`` and ``(j, i, l)``, ``k`` and
``l`` the wing tips. Its fold angle is 0 when flat and positive for a valley
(FOLD convention), in (-pi, pi). The gradients follow Liu and Paulino (MERLIN,
2017); a test checks them against finite differences.

Each element's formulas are written once, as compiled (numba) functions of one
bar or one hinge. :func:`fold_angles`, :func:`hinge_gradients`,
:func:`bar_hessians` and :func:`hinge_hessians` return them for all elements
(what the tests check against finite differences); the solver's inner loop
calls :func:`assemble_bars`, :func:`assemble_hinges` and
:func:`bar_hinge_energy`, which add the same element values straight into the
gradient and the sparse matrix's data array.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "assemble_bars",
    "assemble_hinges",
    "bar_hessians",
    "bar_hinge_energy",
    "bar_lengths",
    "crease_law",
    "fold_angles",
    "hinge_gradients",
    "hinge_hessians",
    "skew",
]


def bar_lengths(x: np.ndarray, bars: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lengths (mm) and unit vectors ``j - i`` of bars ``(i, j)``; ``x`` is (n, 3)."""
    d = x[bars[:, 1]] - x[bars[:, 0]]
    length = np.linalg.norm(d, axis=1)
    return length, d / length[:, None]


def skew(v: np.ndarray) -> np.ndarray:
    """Cross-product matrices ``[v]x`` (``[v]x w = v x w``) of vectors ``v`` (..., 3)."""
    out = np.zeros((*v.shape, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def _coords(x: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(x, dtype=np.float64)


def _elements(nodes: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(nodes, dtype=np.int64)


# --- one element (compiled) ---


@njit(cache=True, inline="always")
def _bar_element(x, i, j, k, rest, unit, block):  # pragma: no cover - compiled
    """Bar ``(i, j)``: its force ``k (L - L0)`` (returned, N), unit vector ``j - i`` into
    ``unit`` (3,), and the 3 x 3 block ``k u u^T + f / L (I - u u^T)`` into ``block``.
    """
    d0 = x[j, 0] - x[i, 0]
    d1 = x[j, 1] - x[i, 1]
    d2 = x[j, 2] - x[i, 2]
    length = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    unit[0], unit[1], unit[2] = d0 / length, d1 / length, d2 / length
    force = k * (length - rest)
    geo = force / length
    for r in range(3):
        for c in range(3):
            uu = unit[r] * unit[c]
            block[r, c] = k * uu + geo * ((1.0 if r == c else 0.0) - uu)
    return force


@njit(cache=True, inline="always")
def _fold_angle(x, i, j, k, l):  # pragma: no cover - compiled
    """Signed fold angle of hinge ``(i, j, k, l)``, rad (valley positive)."""
    e0, e1, e2 = x[j, 0] - x[i, 0], x[j, 1] - x[i, 1], x[j, 2] - x[i, 2]
    a0, a1, a2 = x[k, 0] - x[i, 0], x[k, 1] - x[i, 1], x[k, 2] - x[i, 2]
    b0, b1, b2 = x[l, 0] - x[i, 0], x[l, 1] - x[i, 1], x[l, 2] - x[i, 2]
    m0, m1, m2 = e1 * a2 - e2 * a1, e2 * a0 - e0 * a2, e0 * a1 - e1 * a0  # n1 = e x a
    p0, p1, p2 = b1 * e2 - b2 * e1, b2 * e0 - b0 * e2, b0 * e1 - b1 * e0  # n2 = b x e
    elen = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
    c0, c1, c2 = p1 * m2 - p2 * m1, p2 * m0 - p0 * m2, p0 * m1 - p1 * m0  # n2 x n1
    return np.arctan2((c0 * e0 + c1 * e1 + c2 * e2) / elen, m0 * p0 + m1 * p1 + m2 * p2)


@njit(cache=True, inline="always")
def _cross_rows(m, v, out):  # pragma: no cover - compiled
    """Rows of ``m`` (3, 3) crossed with ``v`` (3,), into ``out``."""
    for r in range(3):
        out[r, 0] = m[r, 1] * v[2] - m[r, 2] * v[1]
        out[r, 1] = m[r, 2] * v[0] - m[r, 0] * v[2]
        out[r, 2] = m[r, 0] * v[1] - m[r, 1] * v[0]


@njit(cache=True)
def _hinge_work():  # pragma: no cover - compiled
    """Scratch arrays of :func:`_hinge_element`, allocated once per loop.

    Seven 3-vectors (rows of ``vec``: ``e``, ``a``, ``b``, ``n1``, ``n2``, ``gk``,
    ``gl``), nine 3 x 3 matrices (``mat``: ``f1``, ``f2``, ``f1a``, ``f1e``, ``f2b``,
    ``f2e``, ``dgk``, ``dgl``, ``outer``), the normals' derivatives ``dn`` (2, 4, 3, 3)
    and the derivatives ``dq`` of ``|e|``, ``tk``, ``tl`` (3, 4, 3); the entries that
    the element never writes (nodes a term does not depend on) stay zero. Plain
    arrays indexed in place, not a tuple of arrays unpacked into views at each
    element: that unpacking took half of the hinges' assembly time (measured).
    """
    return np.empty((7, 3)), np.empty((9, 3, 3)), np.zeros((2, 4, 3, 3)), np.zeros((3, 4, 3))


@njit(cache=True, inline="always")
def _hinge_element(x, ni, nj, nk, nl, g, hess, w, second):  # pragma: no cover - compiled
    """Hinge ``(i, j, k, l)``: the gradient of its fold angle into ``g`` (12,), 1/mm, and,
    when ``second``, its second derivatives into ``hess`` (12, 12), 1/mm^2.

    Rows and columns follow the nodes ``(i, j, k, l)``, three coordinates each.
    Axis ``e = x_j - x_i``; wings ``a = x_k - x_i``, ``b = x_l - x_i``; triangle
    normals ``n1 = e x a``, ``n2 = b x e``. Moving a wing tip along its
    triangle's normal opens or closes the hinge (``gk = |e| n1 / |n1|^2``,
    ``gl = |e| n2 / |n2|^2``, Liu and Paulino); the axis nodes take the rest,
    weighted by where the wing tips project on the axis (``tk``, ``tl``).
    ``w`` is scratch space from :func:`_hinge_work`.
    """
    vec, mat, dn, dq = w
    elen, e2, n1_2, n2_2, tk, tl = _hinge_gradient(x, ni, nj, nk, nl, g, vec)
    if second:
        _hinge_hessian(hess, vec, mat, dn, dq, elen, e2, n1_2, n2_2, tk, tl)


@njit(cache=True, inline="always")
def _hinge_gradient(x, ni, nj, nk, nl, g, v):  # pragma: no cover - compiled
    """The gradient of hinge ``(i, j, k, l)``'s fold angle into ``g`` (12,), 1/mm.

    Fills the scratch vectors ``v`` (7, 3) (``e``, ``a``, ``b``, ``n1``, ``n2``, ``gk``,
    ``gl``, see :func:`_hinge_element`) and returns what the second derivatives
    need: ``|e|`` (mm), ``|e|^2``, ``|n1|^2``, ``|n2|^2`` and the projections
    ``tk``, ``tl`` of the wing tips on the axis (fractions of ``e``).
    """
    for r in range(3):
        v[0, r] = x[nj, r] - x[ni, r]
        v[1, r] = x[nk, r] - x[ni, r]
        v[2, r] = x[nl, r] - x[ni, r]
    v[3, 0] = v[0, 1] * v[1, 2] - v[0, 2] * v[1, 1]  # n1 = e x a
    v[3, 1] = v[0, 2] * v[1, 0] - v[0, 0] * v[1, 2]
    v[3, 2] = v[0, 0] * v[1, 1] - v[0, 1] * v[1, 0]
    v[4, 0] = v[2, 1] * v[0, 2] - v[2, 2] * v[0, 1]  # n2 = b x e
    v[4, 1] = v[2, 2] * v[0, 0] - v[2, 0] * v[0, 2]
    v[4, 2] = v[2, 0] * v[0, 1] - v[2, 1] * v[0, 0]
    e2 = v[0, 0] * v[0, 0] + v[0, 1] * v[0, 1] + v[0, 2] * v[0, 2]
    elen = np.sqrt(e2)
    n1_2 = v[3, 0] * v[3, 0] + v[3, 1] * v[3, 1] + v[3, 2] * v[3, 2]
    n2_2 = v[4, 0] * v[4, 0] + v[4, 1] * v[4, 1] + v[4, 2] * v[4, 2]
    tk = (v[1, 0] * v[0, 0] + v[1, 1] * v[0, 1] + v[1, 2] * v[0, 2]) / e2
    tl = (v[2, 0] * v[0, 0] + v[2, 1] * v[0, 1] + v[2, 2] * v[0, 2]) / e2
    for r in range(3):
        gk = elen / n1_2 * v[3, r]
        gl = elen / n2_2 * v[4, r]
        v[5, r] = gk
        v[6, r] = gl
        g[r] = (tk - 1.0) * gk + (tl - 1.0) * gl
        g[3 + r] = -tk * gk - tl * gl
        g[6 + r] = gk
        g[9 + r] = gl
    return elen, e2, n1_2, n2_2, tk, tl


@njit(cache=True, inline="always")
def _cross_rows(mat, m, v, row, out):  # pragma: no cover - compiled
    """Rows of ``mat[m]`` (3, 3) crossed with ``v[row]`` (3,), into ``mat[out]``."""
    for r in range(3):
        mat[out, r, 0] = mat[m, r, 1] * v[row, 2] - mat[m, r, 2] * v[row, 1]
        mat[out, r, 1] = mat[m, r, 2] * v[row, 0] - mat[m, r, 0] * v[row, 2]
        mat[out, r, 2] = mat[m, r, 0] * v[row, 1] - mat[m, r, 1] * v[row, 0]


@njit(cache=True, inline="always")
def _hinge_hessian(hess, v, mat, dn, dq, elen, e2, n1_2, n2_2, tk, tl):  # pragma: no cover
    """Second derivatives of a hinge's fold angle into ``hess`` (12, 12), 1/mm^2.

    From the scratch that :func:`_hinge_gradient` filled (``v``) and the scalars it
    returned (``|e|`` mm, ``|e|^2``, ``|n1|^2``, ``|n2|^2``, ``tk``, ``tl``); ``mat``,
    ``dn`` and ``dq`` are :func:`_hinge_work`'s (compiled).
    """
    # d(n/|n|^2)/dn = (I - 2 n n^T/|n|^2) / |n|^2, times |e|; M [v]x has rows m_r x v
    for r in range(3):
        for c in range(3):
            eye = 1.0 if r == c else 0.0
            mat[0, r, c] = (eye - 2.0 * v[3, r] * v[3, c] / n1_2) * (elen / n1_2)
            mat[1, r, c] = (eye - 2.0 * v[4, r] * v[4, c] / n2_2) * (elen / n2_2)
    _cross_rows(mat, 0, v, 1, 2)  # f1a
    _cross_rows(mat, 0, v, 0, 3)  # f1e
    _cross_rows(mat, 1, v, 2, 4)  # f2b
    _cross_rows(mat, 1, v, 0, 5)  # f2e
    for r in range(3):
        # d n1 / d x_(i, j, k, l) = ([a]x - [e]x, -[a]x, [e]x, 0)
        # d n2 / d x_(i, j, k, l) = ([e]x - [b]x, [b]x, 0, -[e]x)
        for c in range(3):
            dn[0, 0, r, c] = mat[2, r, c] - mat[3, r, c]
            dn[0, 1, r, c] = -mat[2, r, c]
            dn[0, 2, r, c] = mat[3, r, c]
            dn[1, 0, r, c] = mat[5, r, c] - mat[4, r, c]
            dn[1, 1, r, c] = mat[4, r, c]
            dn[1, 3, r, c] = -mat[5, r, c]
        e, a, b = v[0, r], v[1, r], v[2, r]
        dq[0, 0, r] = -e / elen  # d|e| / d x_q
        dq[0, 1, r] = e / elen
        dq[1, 0, r] = (-e - a) / e2 + 2.0 * tk * e / e2
        dq[1, 1, r] = a / e2 - 2.0 * tk * e / e2
        dq[1, 2, r] = e / e2
        dq[2, 0, r] = (-e - b) / e2 + 2.0 * tl * e / e2
        dq[2, 1, r] = b / e2 - 2.0 * tl * e / e2
        dq[2, 3, r] = e / e2
    for q in range(4):  # d g_p / d x_q, for each wing tip p, then the axis nodes
        for r in range(3):
            for c in range(3):
                mat[6, r, c] = v[3, r] / n1_2 * dq[0, q, c] + dn[0, q, r, c]  # dgk
                mat[7, r, c] = v[4, r] / n2_2 * dq[0, q, c] + dn[1, q, r, c]  # dgl
                mat[8, r, c] = v[5, r] * dq[1, q, c] + v[6, r] * dq[2, q, c]  # outer
        for r in range(3):
            for c in range(3):
                col = 3 * q + c
                dgk, dgl, outer = mat[6, r, c], mat[7, r, c], mat[8, r, c]
                hess[r, col] = outer + (tk - 1.0) * dgk + (tl - 1.0) * dgl
                hess[3 + r, col] = -outer - tk * dgk - tl * dgl
                hess[6 + r, col] = dgk
                hess[9 + r, col] = dgl


# --- all elements ---


@njit(cache=True)
def _fold_angles(x, hinges):  # pragma: no cover - compiled
    out = np.empty(hinges.shape[0])
    for h in range(hinges.shape[0]):
        out[h] = _fold_angle(x, hinges[h, 0], hinges[h, 1], hinges[h, 2], hinges[h, 3])
    return out


@njit(cache=True)
def _hinge_derivatives(x, hinges, grads, hesses, second):  # pragma: no cover - compiled
    w = _hinge_work()
    dummy = np.empty((12, 12))
    for h in range(hinges.shape[0]):
        hess = hesses[h] if second else dummy
        _hinge_element(
            x, hinges[h, 0], hinges[h, 1], hinges[h, 2], hinges[h, 3], grads[h], hess, w, second
        )


@njit(cache=True)
def _bar_blocks(x, bars, k, rest, out):  # pragma: no cover - compiled
    unit = np.empty(3)
    block = np.empty((3, 3))
    for b in range(bars.shape[0]):
        _bar_element(x, bars[b, 0], bars[b, 1], k[b], rest[b], unit, block)
        for r in range(3):
            for c in range(3):
                out[b, r, c] = block[r, c]
                out[b, r + 3, c + 3] = block[r, c]
                out[b, r, c + 3] = -block[r, c]
                out[b, r + 3, c] = -block[r, c]


def fold_angles(x: np.ndarray, hinges: np.ndarray) -> np.ndarray:
    """Signed fold angle of every hinge, radians (valley positive); ``x`` is (n, 3), mm."""
    return _fold_angles(_coords(x), _elements(hinges))


def hinge_gradients(x: np.ndarray, hinges: np.ndarray) -> np.ndarray:
    """Gradient of every hinge's fold angle w.r.t. its four nodes, shape (H, 4, 3), 1/mm.

    Rows follow ``(i, j, k, l)``. The sign matches :func:`fold_angles`.
    """
    hinges = _elements(hinges)
    grads = np.empty((len(hinges), 12))
    _hinge_derivatives(_coords(x), hinges, grads, np.empty((0, 12, 12)), False)
    return grads.reshape(-1, 4, 3)


def hinge_hessians(x: np.ndarray, hinges: np.ndarray) -> np.ndarray:
    """Second derivatives of every hinge's fold angle, shape (H, 12, 12), 1/mm^2.

    Rows and columns follow the nodes ``(i, j, k, l)``, three coordinates each;
    the analytic derivative of :func:`hinge_gradients` (a test checks it
    against finite differences).
    """
    hinges = _elements(hinges)
    hesses = np.empty((len(hinges), 12, 12))
    _hinge_derivatives(_coords(x), hinges, np.empty((len(hinges), 12)), hesses, True)
    return hesses


def bar_hessians(x: np.ndarray, bars: np.ndarray, k: np.ndarray, rest: np.ndarray) -> np.ndarray:
    """Exact Hessians of the bars' energies ``k/2 (L - L0)^2``, shape (B, 6, 6), N/mm.

    Axial stiffness ``k u u^T`` plus the geometric stiffness of the bar force
    ``f = k (L - L0)``: ``f / L (I - u u^T)``; rows and columns follow ``(i, j)``.
    """
    bars = _elements(bars)
    out = np.empty((len(bars), 6, 6))
    _bar_blocks(_coords(x), bars, np.asarray(k, dtype=float), np.asarray(rest, dtype=float), out)
    return out


# --- assembly kernels of the solver: element values straight into the CSC data ---


@njit(cache=True)
def assemble_bars(
    x: np.ndarray,
    bars: np.ndarray,
    k: np.ndarray,
    rest: np.ndarray,
    positions: np.ndarray,
    grad: np.ndarray,
    data: np.ndarray,
) -> None:  # pragma: no cover - compiled; checked against a dense assembly by the tests
    """Add the bars' gradients and exact Hessians (as :func:`bar_hessians`) in place.

    Parameters
    ----------
    x : ndarray
        (n, 3) node positions, mm.
    bars : ndarray
        (B, 2) node pairs.
    k, rest : ndarray
        (B,) axial stiffness, N/mm, and rest length, mm.
    positions : ndarray
        (B, 36) where entry ``6 r + c`` of each bar's 6 x 6 block goes in ``data``
        (rows and columns ``3 node + axis`` in the order ``(i, j)``).
    grad : ndarray
        (n, 3) gradient to add to, N.
    data : ndarray
        Sparse matrix values to add to, N/mm (empty: the gradient only).
    """
    unit = np.empty(3)
    block = np.empty((3, 3))
    second = data.shape[0] > 0
    for b in range(bars.shape[0]):
        i, j = bars[b, 0], bars[b, 1]
        force = _bar_element(x, i, j, k[b], rest[b], unit, block)
        pos = positions[b]
        for r in range(3):
            grad[j, r] += force * unit[r]
            grad[i, r] -= force * unit[r]
            for c in range(3 if second else 0):
                v = block[r, c]
                data[pos[6 * r + c]] += v
                data[pos[6 * (r + 3) + c + 3]] += v
                data[pos[6 * r + c + 3]] -= v
                data[pos[6 * (r + 3) + c]] -= v


@njit(cache=True)
def crease_law(turn: float, angles: np.ndarray, factors: np.ndarray) -> tuple:
    """A softening crease's law at ``turn`` rad: ``(F, f, G)``, the moment, stiffness and
    energy per unit of the hinge's stiffness (rad, 1, rad^2), odd / even in ``turn``.

    The stiffness factor ``f`` is piecewise linear in ``|turn|`` through ``(angles,
    factors)`` (rad, dimensionless; ``angles[0] = 0``) and constant past the last point;
    the moment is its integral ``F = int_0^|turn| f`` (with ``turn``'s sign) and the
    energy ``G = int_0^|turn| F``. One point ``(0, 1)`` is the linear spring:
    ``(turn, 1, turn^2 / 2)``.
    """
    a = abs(turn)
    moment = 0.0
    energy = 0.0
    n = angles.shape[0]
    for s in range(n):
        f0 = factors[s]
        end = angles[s + 1] if s + 1 < n else np.inf
        slope = (factors[s + 1] - f0) / (end - angles[s]) if s + 1 < n else 0.0
        d = min(a, end) - angles[s]
        energy += moment * d + 0.5 * f0 * d * d + slope * d * d * d / 6.0
        moment += f0 * d + 0.5 * slope * d * d
        if a <= end:
            sign = 1.0 if turn >= 0 else -1.0
            return sign * moment, f0 + slope * d, energy
    return moment, factors[n - 1], energy  # pragma: no cover - the last segment never ends


@njit(cache=True)
def assemble_hinges(
    x: np.ndarray,
    hinges: np.ndarray,
    k: np.ndarray,
    rest: np.ndarray,
    limit: np.ndarray,
    limit_k: float,
    limit_margin: float,
    soft: np.ndarray,
    law_angles: np.ndarray,
    law_factors: np.ndarray,
    positions: np.ndarray,
    grad: np.ndarray,
    data: np.ndarray,
) -> None:  # pragma: no cover - compiled; checked against a dense assembly by the tests
    """Add the hinges' gradients and exact Hessians in place.

    Each hinge's energy is ``k/2 (rho - rest)^2`` (a ``soft`` hinge's: ``k G(rho -
    rest)`` of :func:`crease_law` through ``law_angles`` rad and ``law_factors``) plus
    the fold-limit barrier ``limit_k/2 (|rho| - (limit - limit_margin))_+^2``; its
    Hessian block is
    ``k_rot g g^T + M d2rho`` with ``g`` the fold angle's gradient
    (:func:`hinge_gradients`), ``d2rho`` its second derivatives
    (:func:`hinge_hessians`), ``M`` the moment and ``k_rot`` the rotational
    stiffness.

    Parameters
    ----------
    x : ndarray
        (n, 3) node positions, mm.
    hinges : ndarray
        (H, 4) nodes ``(i, j, k, l)``.
    k, rest, limit : ndarray
        (H,) rotational stiffness, N mm/rad; rest angle and fold limit, rad.
    limit_k, limit_margin : float
        The barrier's stiffness, N mm/rad, and how early it starts, rad.
    soft, law_angles, law_factors : ndarray
        (H,) bool: the hinges that follow the crease law; the law's points (P,), rad
        and stiffness factors (one point: every hinge is linear).
    positions : ndarray
        (H, 144) where entry ``12 r + c`` of each hinge's 12 x 12 block goes.
    grad : ndarray
        (n, 3) gradient to add to, N.
    data : ndarray
        Sparse matrix values to add to, N/mm (empty: the gradient only, a twentieth
        of the cost).
    """
    w = _hinge_work()
    second = data.shape[0] > 0
    g = np.empty(12)
    hess = np.empty((12, 12))
    nodes = np.empty(4, dtype=np.int64)
    for h in range(hinges.shape[0]):
        for p in range(4):
            nodes[p] = hinges[h, p]
        rho = _fold_angle(x, nodes[0], nodes[1], nodes[2], nodes[3])
        over = abs(rho) - (limit[h] - limit_margin)
        if soft[h] and law_angles.shape[0] > 1:
            factor_m, factor_k, _ = crease_law(rho - rest[h], law_angles, law_factors)
            moment = k[h] * factor_m
            k_rot = k[h] * factor_k
        else:
            moment = k[h] * (rho - rest[h])
            k_rot = k[h]
        if over > 0:
            moment += limit_k * over * np.sign(rho)
            k_rot += limit_k
        _hinge_element(x, nodes[0], nodes[1], nodes[2], nodes[3], g, hess, w, second)
        for p in range(4):
            for r in range(3):
                grad[nodes[p], r] += moment * g[3 * p + r]
        for r in range(
            12 if second else 0
        ):  # no view of positions[h]: one per hinge cost 5 % (measured)
            for c in range(12):
                data[positions[h, 12 * r + c]] += k_rot * g[r] * g[c] + moment * hess[r, c]


@njit(cache=True)
def bar_hinge_energy(
    x: np.ndarray,
    bars: np.ndarray,
    bar_k: np.ndarray,
    bar_rest: np.ndarray,
    hinges: np.ndarray,
    hinge_k: np.ndarray,
    hinge_rest: np.ndarray,
    limit: np.ndarray,
    limit_k: float,
    limit_margin: float,
    soft: np.ndarray,
    law_angles: np.ndarray,
    law_factors: np.ndarray,
) -> float:  # pragma: no cover - compiled; checked against the NumPy energy by the tests
    """Elastic energy of the bars, the hinges and the fold-limit barrier, N mm.

    ``sum k/2 (L - L0)^2 + sum k/2 (rho - rest)^2 + limit_k/2 (|rho| - (limit -
    limit_margin))_+^2``, with :func:`bar_lengths` and :func:`fold_angles` (a ``soft``
    hinge's ``k G(rho - rest)``: :func:`crease_law`).
    """
    bar_energy = 0.0
    for b in range(bars.shape[0]):
        i, j = bars[b, 0], bars[b, 1]
        d0 = x[j, 0] - x[i, 0]
        d1 = x[j, 1] - x[i, 1]
        d2 = x[j, 2] - x[i, 2]
        stretch = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) - bar_rest[b]
        bar_energy += bar_k[b] * stretch * stretch
    hinge_energy = 0.0
    limit_energy = 0.0
    for h in range(hinges.shape[0]):
        rho = _fold_angle(x, hinges[h, 0], hinges[h, 1], hinges[h, 2], hinges[h, 3])
        turn = rho - hinge_rest[h]
        if soft[h] and law_angles.shape[0] > 1:
            hinge_energy += 2.0 * hinge_k[h] * crease_law(turn, law_angles, law_factors)[2]
        else:
            hinge_energy += hinge_k[h] * turn * turn
        over = abs(rho) - (limit[h] - limit_margin)
        if over > 0:
            limit_energy += over * over
    return 0.5 * bar_energy + 0.5 * hinge_energy + 0.5 * limit_k * limit_energy
