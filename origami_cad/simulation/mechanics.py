"""Bar-and-hinge mechanics: bar lengths and hinge fold angles with their gradients.

Vectorised over all bars and hinges. A hinge is four nodes ``(i, j, k, l)``: the
axis ``i -> j`` shared by the triangles ``(i, j, k)`` and ``(j, i, l)``, ``k`` and
``l`` the wing tips. Its fold angle is 0 when flat and positive for a valley
(FOLD convention), in (-pi, pi). The gradients follow Liu and Paulino (MERLIN,
2017); a test checks them against finite differences.
"""

from __future__ import annotations

import numpy as np

__all__ = ["bar_lengths", "fold_angles", "hinge_gradients"]


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


def hinge_gradients(x: np.ndarray, hinges: np.ndarray) -> np.ndarray:
    """Gradient of every hinge's fold angle w.r.t. its four nodes, shape (H, 4, 3).

    Rows follow ``(i, j, k, l)``. The sign matches :func:`fold_angles`.
    """
    i, j, k, l = hinges.T
    # Liu & Paulino: axis nodes j, k -> here i, j; wings i, l -> here k, l
    r_axis = x[j] - x[i]
    axis_len2 = np.einsum("ij,ij->i", r_axis, r_axis)
    axis_len = np.sqrt(axis_len2)
    a = x[k] - x[i]  # wing k from the axis start
    b = x[l] - x[i]  # wing l from the axis start
    n1 = np.cross(r_axis, a)
    n2 = np.cross(b, r_axis)
    n1_2 = np.einsum("ij,ij->i", n1, n1)
    n2_2 = np.einsum("ij,ij->i", n2, n2)
    # moving a wing tip along its triangle's normal opens or closes the hinge
    g_k = (axis_len / n1_2)[:, None] * n1
    g_l = (axis_len / n2_2)[:, None] * n2
    # the axis nodes take the rest, weighted by where the wing tips project on the axis
    t_k = np.einsum("ij,ij->i", a, r_axis) / axis_len2
    t_l = np.einsum("ij,ij->i", b, r_axis) / axis_len2
    g_i = (t_k - 1.0)[:, None] * g_k + (t_l - 1.0)[:, None] * g_l
    g_j = -t_k[:, None] * g_k - t_l[:, None] * g_l
    return np.stack([g_i, g_j, g_k, g_l], axis=1)
