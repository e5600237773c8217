"""Fold limits of printed creases: eq. 6 per crease and the fold range it leaves a TG arm.

This module sits below both the arm's design (:mod:`origami_cad.design`, whose fitness
is evaluated over the reachable range) and the fabrication (:mod:`origami_cad.fabrication`,
whose panels are cut by eq. 6), so that neither imports the other for it.

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

import math

import numpy as np

from origami_cad import _libm
from origami_cad.errors import FabricationError

__all__ = [
    "bias_for_theta_max",
    "crease_fold_limit",
    "leg_fold_angles",
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


def bias_for_theta_max(theta: float, height: float, thickness: float) -> float:
    """Eq. 6 inverted: the inner bias ``b`` (mm) that gives ``theta_max = theta`` (radians).

    ``b = (h - t) / 2 tan(theta / 2)``, with panel height ``h`` and crease thickness
    ``t`` in mm; :class:`~origami_cad.errors.FabricationError` unless ``theta`` lies in
    (0, pi).

    >>> round(bias_for_theta_max(float(crease_fold_limit(3.0, 2.2, 0.4)), 2.2, 0.4), 6)
    3.0
    """
    if not 0.0 < theta < math.pi:
        raise FabricationError(f"theta_max must lie in (0, 180) deg, got {math.degrees(theta):g}")
    return (height - thickness) / 2.0 * math.tan(theta / 2.0)


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
