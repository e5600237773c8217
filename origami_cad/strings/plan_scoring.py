"""The route planner's score: the fast DCQC model, vectorised over candidates and fold ratios.

Lengths mm, TSA rotations rad, torques N mm (see :mod:`origami_cad.strings.plan`).
"""

from __future__ import annotations

import math

import numpy as np

from origami_cad.strings.plan_model import PlanGeometry, PlanSettings, RouteScores
from origami_cad.strings.tsa import TSAParams, ring_length

__all__ = ["evaluate_routes", "string_curves"]


def string_curves(
    geom: PlanGeometry,
    anchors: np.ndarray,
    faces: np.ndarray,
    xy: np.ndarray,
    sides: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Lengths of C strings over the grid: ``(x_dis, rest, cuts)``, vectorised.

    ``anchors`` (C, G, 3) mm; ``faces`` (C, K) panel of each hole, ``xy`` (C, K, 2)
    mm, ``sides`` (C, K) the side (+1 top, -1 bottom) along which the string
    reaches each hole. Shorter strings repeat their last hole and side. Returns
    ``x_dis`` (C, G) anchor to the first hole exit, ``rest`` (C, G) the routed
    length beyond it (as :func:`~origami_cad.strings.route.string_lengths`) and
    ``cuts`` (C,) True where a segment cuts through a panel in some state.
    """
    ab = np.einsum("ckij,ckj->cki", geom.flat_inv[faces], xy - geom.flat_v0[faces])
    v0, e1, e2, n = (arr[:, faces] for arr in (geom.v0, geom.e1, geom.e2, geom.normal))
    centre = v0 + ab[None, ..., :1] * e1 + ab[None, ..., 1:] * e2  # (G, C, K, 3)
    e = geom.thickness / 2.0
    s = sides.astype(float)
    s_leave = np.concatenate([s[:, 1:], s[:, -1:]], axis=1)
    arrive = centre + e * s[None, ..., None] * n
    leave = centre + e * s_leave[None, ..., None] * n
    anchor = np.swapaxes(anchors, 0, 1)  # (G, C, 3)
    first = anchor - arrive[:, :, 0]
    x_dis = np.linalg.norm(first, axis=-1)
    d = arrive[:, :, 1:] - leave[:, :, :-1]
    seg = np.linalg.norm(d, axis=-1).sum(axis=-1)
    through = geom.thickness * (np.diff(s, axis=1) != 0).sum(axis=1)
    rest = seg + through[None]
    tol = -1e-6
    cuts = np.any(np.einsum("gci,gci->gc", first, s[None, :, :1] * n[:, :, 0]) < tol, axis=0)
    sn = s[None, :, 1:, None]
    out_k = np.einsum("gcki,gcki->gck", d, sn * n[:, :, :-1])
    in_k = np.einsum("gcki,gcki->gck", -d, sn * n[:, :, 1:])
    cuts |= np.any((out_k < tol) | (in_k < tol), axis=(0, 2))
    return x_dis.T, rest.T, cuts


def _consumed(tsa: TSAParams, theta: np.ndarray, x: np.ndarray) -> np.ndarray:
    """String between the TSA and the first hole (eq. 8 or onboard), NaN past the strands."""
    if tsa.model == "ring":
        xx = x if tsa.x_dis is None else np.full_like(x, tsa.x_dis)
        return ring_length(
            np.maximum(np.nan_to_num(theta), 0.0), xx, tsa.d1, tsa.d2, tsa.string_width
        )
    twist = (np.clip(np.nan_to_num(theta), 0.0, 1e12) * tsa.radius) ** 2
    with np.errstate(invalid="ignore"):
        return x + tsa.length - np.sqrt(tsa.length**2 - twist)


def _theta_for(tsa: TSAParams, x: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The TSA rotation (rad) at which the TSA's share is ``target`` mm (eq. 8 inverted).

    NaN where the string would have to lengthen (the share falls below its untwisted
    length), +inf past an onboard TSA's largest twist.
    """
    if tsa.model == "ring":
        d1, d2, ds = tsa.d1, tsa.d2, tsa.string_width
        xx = x if tsa.x_dis is None else np.full_like(x, tsa.x_dis)
        q = target**2 - xx**2
        q0, q1 = (d2 - d1) ** 2 / 4.0, (d1 + d2) ** 2 / 4.0
        cos = np.clip((d1**2 + d2**2 - 4.0 * q) / (2.0 * d1 * d2), -1.0, 1.0)
        with np.errstate(invalid="ignore"):
            wound = math.pi + (2.0 * np.sqrt(np.maximum(q, 0.0)) - d1 - d2) / ds
        theta = np.where(q <= q1, np.arccos(cos), wound)
        return np.where(q < q0 - 1e-6 * (1.0 + q0), np.nan, theta)
    c = target - x
    top = tsa.length * (1.0 - math.cos(math.radians(tsa.max_helix_angle)))
    with np.errstate(invalid="ignore"):
        theta = np.sqrt(np.maximum(tsa.length**2 - (tsa.length - c) ** 2, 0.0)) / tsa.radius
    theta = np.where(c >= top, np.inf, theta)
    return np.where(c < -1e-6, np.nan, theta)


def evaluate_routes(
    geom: PlanGeometry,
    settings: PlanSettings,
    x_dis: np.ndarray,
    rest: np.ndarray,
    cuts: np.ndarray,
) -> RouteScores:
    """Score R candidate routes of n strings each on the DCQC model, vectorised.

    ``x_dis``, ``rest`` (R, n, G) mm and ``cuts`` (R, n) from :func:`string_curves`.
    Each string binds at ``theta_i(p)`` (eq. 8 inverted); the TSA reaches ``p`` at
    ``theta(p) = min_i theta_i(p)``. Valid: no segment cuts a panel, no string
    lengthens as the sheet folds from one state to the next (at that state's TSA
    rotation), ``theta(p)`` never falls, and the TSA can take the string up. The
    torque is ``dE / dtheta`` (virtual work), the load share the fraction of
    string states within ``settings.share_tolerance`` mm of taut.
    """
    tsa = geom.placement.tsa
    l0 = _consumed(tsa, np.zeros(x_dis.shape[:2]), x_dis[..., 0]) + rest[..., 0]
    target = l0[..., None] - rest
    theta_i = _theta_for(tsa, x_dis, target)  # (R, n, G)
    shrink_fail = np.isnan(theta_i).any(axis=(1, 2))
    theta = np.nan_to_num(theta_i, nan=np.inf).min(axis=1)  # (R, G)
    helix = ~np.isfinite(theta).all(axis=1)
    th = np.where(np.isfinite(theta), theta, 0.0)
    now = _consumed(tsa, th[:, None, :-1], x_dis[..., :-1]) + rest[..., :-1]
    nxt = _consumed(tsa, th[:, None, :-1], x_dis[..., 1:]) + rest[..., 1:]
    stretch = np.nan_to_num(nxt - now, nan=np.inf).max(axis=(1, 2))
    falls = (np.diff(th, axis=1) < -1e-9).any(axis=1)
    turns = th[:, -1] / (2.0 * math.pi)
    d_theta = np.maximum(np.diff(th, axis=1), 1e-9)
    torque = np.maximum(np.diff(geom.energy), 0.0)[None] / d_theta
    peak = torque.max(axis=1)
    slack = target - _consumed(tsa, th[:, None, :], x_dis)
    share = (np.nan_to_num(slack[..., 1:], nan=np.inf) <= settings.share_tolerance).mean(
        axis=(1, 2)
    )
    why = np.zeros(len(th), dtype=np.int64)
    why[(stretch > 1e-7) | shrink_fail | falls | (turns < 1e-6)] = 2
    why[helix] = 3
    why[cuts.any(axis=1)] = 1
    valid = why == 0
    with np.errstate(divide="ignore", invalid="ignore"):
        cost = np.log(np.maximum(turns, 1e-9)) + np.log(np.maximum(peak, 1e-12))
    cost = cost + settings.share_weight * (1.0 - share)
    over_turns = np.maximum(turns / settings.max_turns - 1.0, 0.0)
    over_torque = np.maximum(np.nan_to_num(peak / settings.max_torque) - 1.0, 0.0)
    cost = cost + np.where(over_turns > 0, 5.0 + 10.0 * over_turns, 0.0)
    cost = cost + np.where(over_torque > 0, 5.0 + 10.0 * over_torque, 0.0)
    bad = 1e3 + 10.0 * why + np.minimum(np.nan_to_num(stretch, posinf=1e3), 1e3)
    cost = np.where(valid, cost, bad)
    return RouteScores(valid, turns, peak, share, cost, th, torque, why)
