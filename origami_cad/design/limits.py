"""Fold limits of a printed TG arm: eq. 6 per crease and the fold range it leaves.

A printed crease stops folding when the chamfers of its two panels meet, at
``theta_max`` of eq. 6 (:func:`crease_fold_limit`). In a TG tessellation every
joint of the main crease is a Miura-type degree-4 vertex: the two halves of the
main crease are collinear and the two legs make the shape angle ``beta`` with it
(sector angles ``beta, pi - beta, pi - beta, beta``). For such a flat-foldable
vertex the fold angles of the crease pairs keep a constant ratio of half-angle
tangents; here

.. math::

    \\tan\\frac{\\rho_{leg}}{2} = \\frac{\\tan(\\theta / 2)}{|\\cos\\beta|}

with ``theta`` the main crease's fold angle (:func:`leg_fold_angles`). So the
legs fold faster than the main crease, the more so the closer ``beta`` is to
90 deg, and they reach their limit first: with ``theta_max`` = 146.6 deg (b = 3,
h = 2.2, t = 0.4 mm) a leg with ``beta`` = 70 deg stops the arm at
``p = theta / pi`` = 0.54, one with 80 deg at 0.33. The long edges between
copies fold like the main crease. :func:`reachable_fold_angle` is the largest
main-crease angle at which no crease exceeds its limit: the end of the fold
range the printed arm can reach, over which the fitness of eq. 5 is evaluated.

Examples
--------
>>> import math
>>> import numpy as np
>>> lim = crease_fold_limit(3.0, 2.2, 0.4)
>>> round(math.degrees(float(lim)), 1)
146.6
>>> ends = reachable_fold_angle(np.radians([[70.0], [80.0]]), lim)
>>> np.round(ends / math.pi, 2).tolist()
[0.54, 0.33]
"""

from __future__ import annotations

import numpy as np

from origami_cad import _libm

__all__ = [
    "crease_fold_limit",
    "leg_fold_angles",
    "panel_bias_violations",
    "reachable_fold_angle",
]


def crease_fold_limit(bias, height, thickness):
    """Eq. 6: ``theta_max = 2 atan(2 b / (h - t))``, radians, element-wise.

    Parameters
    ----------
    bias : float or ndarray
        Inner bias ``b`` of the crease, mm.
    height : float or ndarray
        Panel height ``h``, mm.
    thickness : float or ndarray
        Crease layer thickness ``t``, mm (``t < h``).

    Returns
    -------
    float or ndarray
        The largest fold angle before the chamfers meet, radians in (0, pi).
    """
    return 2.0 * _libm.arctan(2.0 * np.asarray(bias, dtype=float) / (height - thickness))


def leg_fold_angles(theta, shape_angles) -> np.ndarray:
    """Fold angle of the legs of a Miura-type vertex, radians.

    ``tan(rho_leg / 2) = tan(theta / 2) / |cos beta|`` (degree-4 vertex with
    sector angles ``beta, pi - beta, pi - beta, beta``; exact for rigid folding).

    Parameters
    ----------
    theta : float or ndarray
        Fold angle of the main crease, radians in [0, pi].
    shape_angles : float or ndarray
        ``beta`` of the legs, radians (broadcast against ``theta``).

    Returns
    -------
    ndarray
        Unsigned fold angle of the legs, radians in [0, pi].
    """
    half = _libm.tan(np.asarray(theta, dtype=float) / 2.0)
    return 2.0 * _libm.arctan2(half, np.abs(_libm.cos(shape_angles)))


def reachable_fold_angle(shape_angles, main_limit, leg_limit=None) -> np.ndarray:
    """The largest main-crease fold angle at which no crease passes its limit, radians.

    The inverse of :func:`leg_fold_angles` for every leg, and the main crease's
    own limit: ``min(main_limit, min_i 2 atan(|cos beta_i| tan(leg_limit / 2)))``.

    Parameters
    ----------
    shape_angles : ndarray, shape (D, n)
        ``beta_1 .. beta_n`` of each design, radians.
    main_limit : float or ndarray, shape (D,)
        Fold limit of the main crease (and long edges), radians.
    leg_limit : float or ndarray, shape (D,) or (D, n), optional
        Fold limit of the legs, radians (default ``main_limit``).

    Returns
    -------
    ndarray, shape (D,)
        ``theta`` at the end of the reachable range, radians in (0, pi].
    """
    beta = np.atleast_2d(np.asarray(shape_angles, dtype=float))
    main = np.broadcast_to(np.asarray(main_limit, dtype=float).reshape(-1), (beta.shape[0],))
    legs = main if leg_limit is None else np.asarray(leg_limit, dtype=float)
    legs = legs.reshape(-1, 1) if legs.ndim == 1 else legs
    tan_half = _libm.tan(np.minimum(legs, np.pi) / 2.0)
    ends = 2.0 * _libm.arctan(np.abs(_libm.cos(beta)) * tan_half)
    if beta.shape[1] == 0:
        return main.copy()
    return np.minimum(main, ends.min(axis=1))


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
