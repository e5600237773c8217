"""Bar-and-hinge mechanics: bar lengths and hinge fold angles with their gradients.

Vectorised over all bars and hinges. A hinge is four nodes ``(i, j, k, l)``: the
axis ``i -> j`` shared by the triangles ``(i, j, k)`` and ``(j, i, l)``, ``k`` and
``l`` the wing tips. Its fold angle is 0 when flat and positive for a valley
(FOLD convention), in (-pi, pi). The gradients follow Liu and Paulino (MERLIN,
2017); a test checks them against finite differences.

The NumPy functions return per-element arrays (the reference, and what the
tests check against finite differences). The solver's inner loop uses the
compiled kernels :func:`assemble_bars`, :func:`assemble_hinges` and
:func:`bar_hinge_energy` (numba), which evaluate the same formulas element by
element and add the gradients and Hessian blocks straight into the gradient and
the sparse matrix's data array; a test checks that both give the same matrix.
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


def fold_angles(x: np.ndarray, hinges: np.ndarray) -> np.ndarray:
    """Signed fold angle of every hinge, radians (valley positive)."""
    i, j, k, l = hinges.T
    e = x[j] - x[i]
    n1 = np.cross(e, x[k] - x[i])  # normal of the triangle on the left of i -> j
    n2 = np.cross(x[l] - x[i], e)  # normal of the triangle on the right
    unit = e / np.linalg.norm(e, axis=1, keepdims=True)
    sin = np.einsum("ij,ij->i", np.cross(n2, n1), unit)
    cos = np.einsum("ij,ij->i", n1, n2)
    return np.arctan2(sin, cos)


def _hinge_terms(x: np.ndarray, hinges: np.ndarray) -> dict[str, np.ndarray]:
    """What the hinges' first and second derivatives share (Liu and Paulino's terms).

    Axis ``e = x_j - x_i``; wings ``a = x_k - x_i``, ``b = x_l - x_i``; triangle
    normals ``n1 = e x a``, ``n2 = b x e``; ``gk``, ``gl`` the wing tips'
    gradients; ``tk``, ``tl`` where the wing tips project on the axis.
    """
    i, j, k, l = hinges.T
    e = x[j] - x[i]
    e2 = np.einsum("ij,ij->i", e, e)
    elen = np.sqrt(e2)
    a = x[k] - x[i]
    b = x[l] - x[i]
    n1 = np.cross(e, a)
    n2 = np.cross(b, e)
    n1_2 = np.einsum("ij,ij->i", n1, n1)
    n2_2 = np.einsum("ij,ij->i", n2, n2)
    return {
        "e": e,
        "e2": e2,
        "elen": elen,
        "a": a,
        "b": b,
        "n1": n1,
        "n2": n2,
        "n1_2": n1_2,
        "n2_2": n2_2,
        # moving a wing tip along its triangle's normal opens or closes the hinge
        "gk": (elen / n1_2)[:, None] * n1,
        "gl": (elen / n2_2)[:, None] * n2,
        "tk": np.einsum("ij,ij->i", a, e) / e2,
        "tl": np.einsum("ij,ij->i", b, e) / e2,
    }


def hinge_gradients(x: np.ndarray, hinges: np.ndarray) -> np.ndarray:
    """Gradient of every hinge's fold angle w.r.t. its four nodes, shape (H, 4, 3), 1/mm.

    Rows follow ``(i, j, k, l)``. The sign matches :func:`fold_angles`.
    """
    t = _hinge_terms(x, hinges)
    g_k, g_l, t_k, t_l = t["gk"], t["gl"], t["tk"], t["tl"]
    # the axis nodes take the rest, weighted by where the wing tips project on the axis
    g_i = (t_k - 1.0)[:, None] * g_k + (t_l - 1.0)[:, None] * g_l
    g_j = -t_k[:, None] * g_k - t_l[:, None] * g_l
    return np.stack([g_i, g_j, g_k, g_l], axis=1)


def skew(v: np.ndarray) -> np.ndarray:
    """Cross-product matrices ``[v]x`` (``[v]x w = v x w``) of vectors ``v`` (..., 3)."""
    out = np.zeros((*v.shape, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def bar_hessians(x: np.ndarray, bars: np.ndarray, k: np.ndarray, rest: np.ndarray) -> np.ndarray:
    """Exact Hessians of the bars' energies ``k/2 (L - L0)^2``, shape (B, 6, 6), N/mm.

    Axial stiffness ``k u u^T`` plus the geometric stiffness of the bar force
    ``f = k (L - L0)``: ``f / L (I - u u^T)``; rows and columns follow ``(i, j)``.
    """
    length, unit = bar_lengths(x, bars)
    force = k * (length - rest)
    uu = unit[:, :, None] * unit[:, None, :]
    block = k[:, None, None] * uu + (force / length)[:, None, None] * (np.eye(3) - uu)
    return np.block([[block, -block], [-block, block]])


def hinge_hessians(x: np.ndarray, hinges: np.ndarray) -> np.ndarray:
    """Second derivatives of every hinge's fold angle, shape (H, 12, 12), 1/mm^2.

    Rows and columns follow the nodes ``(i, j, k, l)``, three coordinates each;
    the analytic derivative of :func:`hinge_gradients` (a test checks it
    against finite differences).
    """
    t = _hinge_terms(x, hinges)
    e, e2, elen, a, b = t["e"], t["e2"], t["elen"], t["a"], t["b"]
    n1, n2, n1_2, n2_2 = t["n1"], t["n2"], t["n1_2"], t["n2_2"]
    gk, gl, tk, tl = t["gk"], t["gl"], t["tk"], t["tl"]
    ehat = e / elen[:, None]
    eye = np.eye(3)
    zero = np.zeros((len(hinges), 3))
    # d(n/|n|^2)/dn = (I - 2 n n^T/|n|^2) / |n|^2, times |e|; M [v]x has rows m_r x v
    f1 = (eye - 2 * n1[:, :, None] * n1[:, None, :] / n1_2[:, None, None]) * (elen / n1_2)[
        :, None, None
    ]
    f2 = (eye - 2 * n2[:, :, None] * n2[:, None, :] / n2_2[:, None, None]) * (elen / n2_2)[
        :, None, None
    ]
    f1a, f1e = np.cross(f1, a[:, None, :]), np.cross(f1, e[:, None, :])
    f2b, f2e = np.cross(f2, b[:, None, :]), np.cross(f2, e[:, None, :])
    z33 = np.zeros_like(f1)
    # d n1 / d x_(i, j, k, l) = ([a]x - [e]x, -[a]x, [e]x, 0); d n2 = ([e]x - [b]x, [b]x, 0, -[e]x)
    dn1 = np.stack([f1a - f1e, -f1a, f1e, z33], axis=1)  # (H, q, 3, 3)
    dn2 = np.stack([f2e - f2b, f2b, z33, -f2e], axis=1)
    de_len = np.stack([-ehat, ehat, zero, zero], axis=1)  # d|e| / d x_q, (H, q, 3)
    dgk = (n1 / n1_2[:, None])[:, None, :, None] * de_len[:, :, None, :] + dn1
    dgl = (n2 / n2_2[:, None])[:, None, :, None] * de_len[:, :, None, :] + dn2
    inv = (1.0 / e2)[:, None]
    dtk = np.stack(
        [
            (-e - a) * inv + 2 * tk[:, None] * e * inv,
            a * inv - 2 * tk[:, None] * e * inv,
            e * inv,
            zero,
        ],
        axis=1,
    )
    dtl = np.stack(
        [
            (-e - b) * inv + 2 * tl[:, None] * e * inv,
            b * inv - 2 * tl[:, None] * e * inv,
            zero,
            e * inv,
        ],
        axis=1,
    )
    outer = gk[:, None, :, None] * dtk[:, :, None, :] + gl[:, None, :, None] * dtl[:, :, None, :]
    tk4, tl4 = tk[:, None, None, None], tl[:, None, None, None]
    rows = np.stack(  # (H, p, q, 3, 3): d g_p / d x_q
        [
            outer + (tk4 - 1.0) * dgk + (tl4 - 1.0) * dgl,
            -outer - tk4 * dgk - tl4 * dgl,
            dgk,
            dgl,
        ],
        axis=1,
    )
    return rows.transpose(0, 1, 3, 2, 4).reshape(len(hinges), 12, 12)


# --- compiled kernels (numba): one element at a time, straight into the CSC data ---


@njit(cache=True)
def assemble_bars(
    x: np.ndarray,
    bars: np.ndarray,
    k: np.ndarray,
    rest: np.ndarray,
    positions: np.ndarray,
    grad: np.ndarray,
    data: np.ndarray,
) -> None:  # pragma: no cover - compiled; checked against bar_hessians by the tests
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
        Sparse matrix values to add to, N/mm.
    """
    blk = np.empty((3, 3))
    for b in range(bars.shape[0]):
        i, j = bars[b, 0], bars[b, 1]
        d0 = x[j, 0] - x[i, 0]
        d1 = x[j, 1] - x[i, 1]
        d2 = x[j, 2] - x[i, 2]
        length = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        u = (d0 / length, d1 / length, d2 / length)
        force = k[b] * (length - rest[b])
        geo = force / length
        for r in range(3):
            grad[j, r] += force * u[r]
            grad[i, r] -= force * u[r]
            for c in range(3):
                uu = u[r] * u[c]
                blk[r, c] = k[b] * uu + geo * ((1.0 if r == c else 0.0) - uu)
        pos = positions[b]
        for r in range(3):
            for c in range(3):
                v = blk[r, c]
                data[pos[6 * r + c]] += v
                data[pos[6 * (r + 3) + c + 3]] += v
                data[pos[6 * r + c + 3]] -= v
                data[pos[6 * (r + 3) + c]] -= v


@njit(cache=True, inline="always")
def _cross_rows(m: np.ndarray, v: np.ndarray, out: np.ndarray) -> None:
    """Rows of ``m`` (3, 3) crossed with ``v`` (3,), into ``out``."""
    for r in range(3):
        out[r, 0] = m[r, 1] * v[2] - m[r, 2] * v[1]
        out[r, 1] = m[r, 2] * v[0] - m[r, 0] * v[2]
        out[r, 2] = m[r, 0] * v[1] - m[r, 1] * v[0]


@njit(cache=True)
def assemble_hinges(
    x: np.ndarray,
    hinges: np.ndarray,
    k: np.ndarray,
    rest: np.ndarray,
    limit: np.ndarray,
    limit_k: float,
    limit_margin: float,
    positions: np.ndarray,
    grad: np.ndarray,
    data: np.ndarray,
) -> None:  # pragma: no cover - compiled; checked against hinge_hessians by the tests
    """Add the hinges' gradients and exact Hessians in place.

    Each hinge's energy is ``k/2 (rho - rest)^2`` plus the fold-limit barrier
    ``limit_k/2 (|rho| - (limit - limit_margin))_+^2``; its Hessian block is
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
    positions : ndarray
        (H, 144) where entry ``12 r + c`` of each hinge's 12 x 12 block goes.
    grad : ndarray
        (n, 3) gradient to add to, N.
    data : ndarray
        Sparse matrix values to add to, N/mm.
    """
    eye = np.eye(3)
    e = np.empty(3)
    a = np.empty(3)
    b = np.empty(3)
    n1 = np.empty(3)
    n2 = np.empty(3)
    gk = np.empty(3)
    gl = np.empty(3)
    g = np.empty(12)
    f1 = np.empty((3, 3))
    f2 = np.empty((3, 3))
    f1a = np.empty((3, 3))
    f1e = np.empty((3, 3))
    f2b = np.empty((3, 3))
    f2e = np.empty((3, 3))
    dn1 = np.zeros((4, 3, 3))
    dn2 = np.zeros((4, 3, 3))
    dlen = np.zeros((4, 3))
    dtk = np.zeros((4, 3))
    dtl = np.zeros((4, 3))
    dgk = np.empty((3, 3))
    dgl = np.empty((3, 3))
    outer = np.empty((3, 3))
    hess = np.empty((12, 12))
    for h in range(hinges.shape[0]):
        ni, nj, nk, nl = hinges[h, 0], hinges[h, 1], hinges[h, 2], hinges[h, 3]
        for r in range(3):
            e[r] = x[nj, r] - x[ni, r]
            a[r] = x[nk, r] - x[ni, r]
            b[r] = x[nl, r] - x[ni, r]
        n1[0] = e[1] * a[2] - e[2] * a[1]
        n1[1] = e[2] * a[0] - e[0] * a[2]
        n1[2] = e[0] * a[1] - e[1] * a[0]
        n2[0] = b[1] * e[2] - b[2] * e[1]
        n2[1] = b[2] * e[0] - b[0] * e[2]
        n2[2] = b[0] * e[1] - b[1] * e[0]
        e2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2]
        elen = np.sqrt(e2)
        n1_2 = n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]
        n2_2 = n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]
        # fold angle, as fold_angles: sin from (n2 x n1) . e/|e|, cos from n1 . n2
        c0 = n2[1] * n1[2] - n2[2] * n1[1]
        c1 = n2[2] * n1[0] - n2[0] * n1[2]
        c2 = n2[0] * n1[1] - n2[1] * n1[0]
        sin = (c0 * e[0] + c1 * e[1] + c2 * e[2]) / elen
        cos = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2]
        rho = np.arctan2(sin, cos)
        over = abs(rho) - (limit[h] - limit_margin)
        moment = k[h] * (rho - rest[h])
        k_rot = k[h]
        if over > 0:
            moment += limit_k * over * np.sign(rho)
            k_rot += limit_k
        tk = (a[0] * e[0] + a[1] * e[1] + a[2] * e[2]) / e2
        tl = (b[0] * e[0] + b[1] * e[1] + b[2] * e[2]) / e2
        for r in range(3):
            gk[r] = elen / n1_2 * n1[r]
            gl[r] = elen / n2_2 * n2[r]
            g[r] = (tk - 1.0) * gk[r] + (tl - 1.0) * gl[r]
            g[3 + r] = -tk * gk[r] - tl * gl[r]
            g[6 + r] = gk[r]
            g[9 + r] = gl[r]
        # second derivatives, as hinge_hessians
        for r in range(3):
            for c in range(3):
                f1[r, c] = (eye[r, c] - 2.0 * n1[r] * n1[c] / n1_2) * (elen / n1_2)
                f2[r, c] = (eye[r, c] - 2.0 * n2[r] * n2[c] / n2_2) * (elen / n2_2)
        _cross_rows(f1, a, f1a)
        _cross_rows(f1, e, f1e)
        _cross_rows(f2, b, f2b)
        _cross_rows(f2, e, f2e)
        for r in range(3):
            for c in range(3):
                dn1[0, r, c] = f1a[r, c] - f1e[r, c]
                dn1[1, r, c] = -f1a[r, c]
                dn1[2, r, c] = f1e[r, c]
                dn2[0, r, c] = f2e[r, c] - f2b[r, c]
                dn2[1, r, c] = f2b[r, c]
                dn2[3, r, c] = -f2e[r, c]
            dlen[0, r] = -e[r] / elen
            dlen[1, r] = e[r] / elen
            dtk[0, r] = (-e[r] - a[r]) / e2 + 2.0 * tk * e[r] / e2
            dtk[1, r] = a[r] / e2 - 2.0 * tk * e[r] / e2
            dtk[2, r] = e[r] / e2
            dtl[0, r] = (-e[r] - b[r]) / e2 + 2.0 * tl * e[r] / e2
            dtl[1, r] = b[r] / e2 - 2.0 * tl * e[r] / e2
            dtl[3, r] = e[r] / e2
        for q in range(4):
            for r in range(3):
                for c in range(3):
                    dgk[r, c] = n1[r] / n1_2 * dlen[q, c] + dn1[q, r, c]
                    dgl[r, c] = n2[r] / n2_2 * dlen[q, c] + dn2[q, r, c]
                    outer[r, c] = gk[r] * dtk[q, c] + gl[r] * dtl[q, c]
            for r in range(3):
                for c in range(3):
                    col = 3 * q + c
                    hess[r, col] = outer[r, c] + (tk - 1.0) * dgk[r, c] + (tl - 1.0) * dgl[r, c]
                    hess[3 + r, col] = -outer[r, c] - tk * dgk[r, c] - tl * dgl[r, c]
                    hess[6 + r, col] = dgk[r, c]
                    hess[9 + r, col] = dgl[r, c]
        nodes = (ni, nj, nk, nl)
        for p in range(4):
            for r in range(3):
                grad[nodes[p], r] += moment * g[3 * p + r]
        pos = positions[h]
        for r in range(12):
            for c in range(12):
                data[pos[12 * r + c]] += k_rot * g[r] * g[c] + moment * hess[r, c]


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
) -> float:  # pragma: no cover - compiled; checked against the NumPy energy by the tests
    """Elastic energy of the bars, the hinges and the fold-limit barrier, N mm.

    ``sum k/2 (L - L0)^2 + sum k/2 (rho - rest)^2 + limit_k/2 (|rho| - (limit -
    limit_margin))_+^2``, as :func:`bar_lengths` and :func:`fold_angles` give them.
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
        ni, nj, nk, nl = hinges[h, 0], hinges[h, 1], hinges[h, 2], hinges[h, 3]
        e0, e1, e2 = x[nj, 0] - x[ni, 0], x[nj, 1] - x[ni, 1], x[nj, 2] - x[ni, 2]
        a0, a1, a2 = x[nk, 0] - x[ni, 0], x[nk, 1] - x[ni, 1], x[nk, 2] - x[ni, 2]
        b0, b1, b2 = x[nl, 0] - x[ni, 0], x[nl, 1] - x[ni, 1], x[nl, 2] - x[ni, 2]
        m0, m1, m2 = e1 * a2 - e2 * a1, e2 * a0 - e0 * a2, e0 * a1 - e1 * a0
        p0, p1, p2 = b1 * e2 - b2 * e1, b2 * e0 - b0 * e2, b0 * e1 - b1 * e0
        elen = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        c0, c1, c2 = p1 * m2 - p2 * m1, p2 * m0 - p0 * m2, p0 * m1 - p1 * m0
        rho = np.arctan2((c0 * e0 + c1 * e1 + c2 * e2) / elen, m0 * p0 + m1 * p1 + m2 * p2)
        turn = rho - hinge_rest[h]
        hinge_energy += hinge_k[h] * turn * turn
        over = abs(rho) - (limit[h] - limit_margin)
        if over > 0:
            limit_energy += over * over
    return 0.5 * bar_energy + 0.5 * hinge_energy + 0.5 * limit_k * limit_energy
