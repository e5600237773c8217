"""Bar-and-hinge mechanics: bar lengths and hinge fold angles with their gradients.

Vectorised over all bars and hinges. A hinge is four nodes ``(i, j, k, l)``: the
axis ``i -> j`` shared by the triangles ``(i, j, k)`` and ``(j, i, l)``, ``k`` and
``l`` the wing tips. Its fold angle is 0 when flat and positive for a valley
(FOLD convention), in (-pi, pi). The gradients follow Liu and Paulino (MERLIN,
2017); a test checks them against finite differences.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "bar_hessians",
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
