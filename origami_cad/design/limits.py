"""Panels of a TG arm too small for their creases' chamfers (eq. 6's bias).

The fold limits themselves (eq. 6, the legs' fold angles, the reachable range) are in
:mod:`origami_cad.kinematics.limits`, below both the design and the fabrication.
"""

from __future__ import annotations

import numpy as np

from origami_cad import _libm

__all__ = ["panel_bias_violations"]


def panel_bias_violations(
    lengths: np.ndarray,
    shape_angles: np.ndarray,
    half_width: float,
    bias: np.ndarray,
    min_face: float,
) -> np.ndarray:
    """Number of panels whose outer face, inset ``bias`` from every crease, is too small.

    A panel next to main-crease segment ``i`` lies between the legs at joints
    ``i`` and ``i + 1`` (the short ends, free edges, for the end segments),
    from the main crease (y = 0) to the long edge (y = ``half_width``). Its
    width along the main crease at height y is
    ``l_i + y (cot beta_{i+1} - cot beta_i)``; the chamfers take
    ``bias / sin beta`` next to each leg and ``bias`` next to the main crease
    and the long edge. A panel fails when its outer face is narrower than
    ``min_face`` everywhere, or its height ``half_width - 2 bias`` is.

    Parameters
    ----------
    lengths : ndarray, shape (D, n + 1)
        ``l_0 .. l_n``, mm.
    shape_angles : ndarray, shape (D, n)
        ``beta_1 .. beta_n``, radians.
    half_width : float
        Height of a panel row (half the unit width), mm.
    bias : ndarray, shape (D,)
        Inner bias of every crease, mm.
    min_face : float
        Smallest width of a panel's outer face, mm.

    Returns
    -------
    ndarray of int, shape (D,)
    """
    lengths = np.atleast_2d(np.asarray(lengths, dtype=float))
    beta = np.atleast_2d(np.asarray(shape_angles, dtype=float))
    b = np.asarray(bias, dtype=float).reshape(-1, 1)
    d, n1 = lengths.shape
    cot = np.zeros((d, n1 + 1))
    inset = np.zeros((d, n1 + 1))  # chamfer width along the main crease at each joint
    if n1 > 1:
        cot[:, 1:-1] = 1.0 / _libm.tan(beta)
        cot[:, 0], cot[:, -1] = cot[:, 1], cot[:, -2]
        inset[:, 1:-1] = b / np.abs(_libm.sin(beta))
    lo, hi = b, half_width - b
    slope = cot[:, 1:] - cot[:, :-1]
    room = inset[:, :-1] + inset[:, 1:] + min_face
    width = np.maximum(lengths + lo * slope, lengths + hi * slope)
    bad = (width < room).sum(axis=1)
    return bad + (half_width - 2.0 * b[:, 0] < min_face) * n1
