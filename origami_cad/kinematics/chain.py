"""The TG chain: eqs. 2-4, vectorised over designs and fold angles.

Shapes follow ``(designs, samples, vectors)``: ``theta`` has shape ``(S,)``,
per-design arrays have a leading design axis ``D`` (1-D input is one design).
Angles are radians; lengths mm.

Examples
--------
>>> import numpy as np
>>> theta = np.radians([0.0, 90.0, 180.0])
>>> pts = chain_points(theta, [[40.0, 30.0]], np.radians([[60.0]]), entry_flag=[1])
>>> pts.shape  # (designs, samples, joints incl. T_s and T_e, xy)
(1, 3, 3, 2)
>>> float(pts[0, 0, -1, 0])  # flat: T_e = T_s + (l0 + l1, 0)
70.0
"""

from __future__ import annotations

import numpy as np

from origami_cad import _libm

__all__ = [
    "chain_angles",
    "chain_joints",
    "chain_points",
    "half_turn_tangents",
    "hypar_alpha0",
    "tip_positions",
    "turning_angles",
]


def hypar_alpha0(theta: np.ndarray) -> np.ndarray:
    """Eq. 3: absolute angle of ``v_0`` on a half hypar base, radians.

    ``alpha_0 = arccos(sqrt(2 cos(theta/2) / (1 + cos(theta/2))))``,
    ``0 <= theta <= pi``; 0 when flat, pi/2 when fully folded.
    """
    c = _libm.cos(np.asarray(theta, dtype=float) / 2.0)
    c = np.clip(c, 0.0, 1.0)
    return _libm.arccos(np.clip(np.sqrt(2.0 * c / (1.0 + c)), 0.0, 1.0))


def half_turn_tangents(
    theta: np.ndarray, shape_angles: np.ndarray, entry_flag: np.ndarray
) -> np.ndarray:
    """``tan(Delta alpha_i / 2) = sin(theta/2) tan(beta_i) (-1)^EF_{i-1}``, the core of eq. 2.

    Shapes as :func:`turning_angles`: returns (D, S, n).
    """
    beta = np.atleast_2d(np.asarray(shape_angles, dtype=float))
    ef0 = np.broadcast_to(np.asarray(entry_flag, dtype=np.int64).reshape(-1), (beta.shape[0],))
    n = beta.shape[1]
    flags_before = (ef0[:, None] + np.arange(n)[None, :]) % 2  # EF_0 .. EF_{n-1}
    sign = 1.0 - 2.0 * flags_before  # (-1)^EF
    s = _libm.sin(_theta_2d(theta) / 2.0)  # (1, S) or (D, S)
    return s[:, :, None] * (_libm.tan(beta) * sign)[:, None, :]


def _theta_2d(theta: np.ndarray) -> np.ndarray:
    """Fold angles as a ``(1, S)`` row shared by all designs, or ``(D, S)`` per design."""
    th = np.asarray(theta, dtype=float)
    return th.reshape(1, -1) if th.ndim < 2 else th


def _alpha0(
    theta: np.ndarray, hypar_base: bool | np.ndarray, d: int, alpha0: float = 0.0
) -> np.ndarray:
    """``alpha_0`` of each of ``d`` designs, (D, S) radians: eq. 3 on a half hypar base
    (``hypar_base`` per design or for all), else ``alpha0``; ``theta`` as :func:`_theta_2d`."""
    hyp = np.broadcast_to(np.asarray(hypar_base, dtype=bool).reshape(-1), (d,))
    return np.where(hyp[:, None], hypar_alpha0(theta), alpha0)


def turning_angles(
    theta: np.ndarray, shape_angles: np.ndarray, entry_flag: np.ndarray
) -> np.ndarray:
    """Eq. 2: ``Delta alpha_i = 2 arctan(sin(theta/2) tan(beta_i) (-1)^EF_{i-1})``.

    Parameters
    ----------
    theta : ndarray, shape (S,) or (D, S)
        Fold angles of the main crease, radians in [0, pi]; one row shared by
        every design, or one row per design.
    shape_angles : ndarray, shape (D, n) or (n,)
        ``beta_1 .. beta_n``, radians.
    entry_flag : ndarray of int, shape (D,) or scalar
        ``EF_0`` of each design.

    Returns
    -------
    ndarray, shape (D, S, n)
        Turning angle at each joint, radians.
    """
    return 2.0 * _libm.arctan(half_turn_tangents(theta, shape_angles, entry_flag))


def chain_angles(
    theta: np.ndarray,
    shape_angles: np.ndarray,
    entry_flag: np.ndarray,
    hypar_base: bool | np.ndarray = False,
    alpha0: float = 0.0,
) -> np.ndarray:
    """Absolute angles ``alpha_0 .. alpha_n`` of the transition vectors, radians.

    ``alpha_0`` is eq. 3 with ``hypar_base`` (per design or for all), else ``alpha0``.
    Returns shape ``(D, S, n + 1)``.
    """
    da = turning_angles(theta, shape_angles, entry_flag)
    d, s, _ = da.shape
    a0 = _alpha0(_theta_2d(theta), hypar_base, d, alpha0)  # (D, S)
    out = np.empty((d, s, da.shape[2] + 1))
    out[..., 0] = a0
    np.cumsum(da, axis=2, out=out[..., 1:])
    out[..., 1:] += a0[..., None]
    return out


def chain_joints(
    theta: np.ndarray,
    lengths: np.ndarray,
    shape_angles: np.ndarray,
    entry_flag: np.ndarray,
    hypar_base: bool | np.ndarray = False,
    start: np.ndarray | tuple[float, float] = (0.0, 0.0),
) -> np.ndarray:
    """Joints of the TG chain as complex numbers ``x + iy``, ``T_s`` first, ``T_e`` last.

    Eq. 4, ``T_e = T_s + sum v_i``, with every partial sum: shape ``(D, S, n + 2)``,
    mm. Arguments as :func:`chain_points`. The headings are built without
    trigonometry: with ``t = tan(Delta alpha / 2)`` from eq. 2, the turn
    ``exp(i Delta alpha) = (1 - t^2 + 2 i t) / (1 + t^2)`` exactly, and each heading
    is the running product of the turns.
    """
    lengths = np.atleast_2d(np.asarray(lengths, dtype=float))
    theta = _theta_2d(theta)
    t = half_turn_tangents(theta, shape_angles, entry_flag)  # eq. 2
    d, n_samples, n = t.shape
    d = max(d, lengths.shape[0])
    a0 = _alpha0(theta, hypar_base, d)  # eq. 3, (D, S)
    heading = np.empty((d, n_samples, n + 1), dtype=complex)
    heading[..., 0] = np.exp(1j * a0)
    inv = 1.0 / (1.0 + t * t)  # the turns, real and imaginary parts (no complex division)
    heading.real[..., 1:] = 2.0 * inv - 1.0  # (1 - t^2) / (1 + t^2)
    heading.imag[..., 1:] = 2.0 * t * inv
    np.cumprod(heading, axis=2, out=heading)
    out = np.empty((d, n_samples, n + 2), dtype=complex)
    st = np.asarray(start, dtype=float).reshape(-1, 2)
    out[:, :, 0] = (st[:, 0] + 1j * st[:, 1])[:, None]
    heading *= lengths[:, None, :]
    np.cumsum(heading, axis=2, out=out[:, :, 1:])
    out[:, :, 1:] += out[:, :, :1]
    return out


def chain_points(
    theta: np.ndarray,
    lengths: np.ndarray,
    shape_angles: np.ndarray,
    entry_flag: np.ndarray,
    hypar_base: bool | np.ndarray = False,
    start: np.ndarray | tuple[float, float] = (0.0, 0.0),
) -> np.ndarray:
    """Joints of the TG chain, ``T_s`` first and ``T_e`` last (eq. 4), mm.

    Parameters
    ----------
    theta : ndarray, shape (S,) or (D, S)
        Fold angles, radians (a row per design, or one for all).
    lengths : ndarray, shape (D, n + 1) or (n + 1,)
        ``l_0 .. l_n``, mm.
    shape_angles : ndarray, shape (D, n) or (n,)
        ``beta_1 .. beta_n``, radians.
    entry_flag : ndarray, shape (D,) or scalar
        ``EF_0``.
    hypar_base : bool or ndarray of bool
        Use eq. 3 for ``alpha_0``.
    start : (float, float) or ndarray (D, 2)
        ``T_s``, mm.

    Returns
    -------
    ndarray, shape (D, S, n + 2, 2)
    """
    z = chain_joints(theta, lengths, shape_angles, entry_flag, hypar_base, start)
    return np.stack([z.real, z.imag], axis=-1)


def tip_positions(
    theta: np.ndarray,
    lengths: np.ndarray,
    shape_angles: np.ndarray,
    entry_flag: np.ndarray,
    hypar_base: bool | np.ndarray = False,
    start: np.ndarray | tuple[float, float] = (0.0, 0.0),
) -> np.ndarray:
    """``T_e = T_s + sum v_i`` (eq. 4) for every design and sample, shape (D, S, 2), mm."""
    z = chain_joints(theta, lengths, shape_angles, entry_flag, hypar_base, start)[:, :, -1]
    return np.stack([z.real, z.imag], axis=-1)
