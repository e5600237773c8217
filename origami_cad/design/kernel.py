"""The compiled core of eq. 5: one pass over each design's sampled chains.

:func:`population_terms` takes the half-turn tangents of eq. 2
(:func:`~origami_cad.kinematics.chain.half_turn_tangents`) and ``alpha_0`` of
eq. 3 for every design and sample, builds each sampled chain (eq. 4, the same
running product of turns as :func:`~origami_cad.kinematics.chain.chain_joints`,
equal to rounding, but one design at a time in a small scratch buffer) and runs the
predicates of :mod:`origami_cad.design.predicates` on it. Nothing of size
designs x samples x joints is allocated, and a design already infeasible
(a prohibited area touched, or ``skip`` set for it) is not tested for
self-intersections, since its improper states do not enter its cost.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from origami_cad.design.predicates import (
    state_inside_area,
    state_self_touches,
    state_touches_area,
)

__all__ = ["population_terms", "reachable_ends", "sampled_turns"]


@njit(cache=True)
def reachable_ends(beta, main):  # pragma: no cover - compiled
    """Each design's end of the reachable fold range, radians (D,): the main crease's
    limit ``main`` (D,) and every leg's, ``2 atan(|cos beta_i| tan(main / 2))``; the
    same arithmetic as :func:`~origami_cad.kinematics.limits.reachable_fold_angle`
    with ``leg_limit`` its default, libm's scalar functions for the trigonometry."""
    n_designs, n = beta.shape
    out = np.empty(n_designs)
    for d in range(n_designs):
        tan_half = math.tan(min(main[d], math.pi) / 2.0)
        end = main[d]
        for i in range(n):
            leg = 2.0 * math.atan(abs(math.cos(beta[d, i])) * tan_half)
            end = min(end, leg)
        out[d] = end
    return out


@njit(cache=True)
def sampled_turns(theta_end, beta, ef0, ramp, hypar):  # pragma: no cover - compiled
    """Eq. 2's half-turn tangents (D, S, n) and eq. 3's ``alpha_0`` (D, S) at the samples
    ``theta = theta_end[d] ramp[s]`` (radians), with the arithmetic of
    :func:`~origami_cad.kinematics.chain.half_turn_tangents` and
    :func:`~origami_cad.kinematics.chain.hypar_alpha0` (``alpha_0`` 0 unless ``hypar``)
    and libm's scalar functions for the trigonometry: the same bits on every CPU."""
    n_designs, n = beta.shape
    n_samples = ramp.shape[0]
    t = np.empty((n_designs, n_samples, n))
    a0 = np.zeros((n_designs, n_samples))
    tb = np.empty(n)
    for d in range(n_designs):
        for i in range(n):
            sign = 1.0 - 2.0 * ((ef0[d] + i) % 2)
            tb[i] = math.tan(beta[d, i]) * sign
        for s in range(n_samples):
            theta = theta_end[d] * ramp[s]
            half = math.sin(theta / 2.0)
            for i in range(n):
                t[d, s, i] = half * tb[i]
            if hypar:
                c = min(max(math.cos(theta / 2.0), 0.0), 1.0)
                r = min(max(math.sqrt(2.0 * c / (1.0 + c)), 0.0), 1.0)
                a0[d, s] = math.acos(r)
    return t, a0


@njit(cache=True)
def _build_chains(t, a0, lengths, start, d, xs, ys, tips):
    """Joints of design ``d``'s sampled chains into ``xs, ys`` (S, m); tips into ``tips[d]``."""
    n_samples, n = t.shape[1], t.shape[2]
    for s in range(n_samples):
        hr, hi = math.cos(a0[d, s]), math.sin(a0[d, s])
        sx, sy = 0.0, 0.0
        xs[s, 0], ys[s, 0] = start[0], start[1]
        for i in range(n + 1):
            if i > 0:
                ti = t[d, s, i - 1]
                inv = 1.0 / (1.0 + ti * ti)
                tr, tim = 2.0 * inv - 1.0, 2.0 * ti * inv
                hr, hi = hr * tr - hi * tim, hr * tim + hi * tr
            sx += hr * lengths[d, i]
            sy += hi * lengths[d, i]
            xs[s, i + 1], ys[s, i + 1] = sx + start[0], sy + start[1]
        tips[d, s, 0], tips[d, s, 1] = xs[s, n + 1], ys[s, n + 1]


@njit(cache=True)
def _match_points(tips, d, mids, d_mid, mid_index):
    """Greedy in-order match of each intermediate point to its closest later tip sample."""
    lowest = 0
    for j in range(mids.shape[0]):
        best, k_best = np.inf, lowest
        for k in range(lowest, tips.shape[1]):
            dist = math.sqrt((tips[d, k, 0] - mids[j, 0]) ** 2 + (tips[d, k, 1] - mids[j, 1]) ** 2)
            if dist < best:
                best, k_best = dist, k
        d_mid[d, j], mid_index[d, j] = best, k_best
        lowest = k_best


@njit(cache=True)
def _count_hits(xs, ys, pro_edges, pro_offsets, pro_boxes) -> int:
    """Number of sampled states whose chain touches a prohibited area."""
    count = 0
    for s in range(xs.shape[0]):
        for a in range(pro_boxes.shape[0]):
            if state_touches_area(xs, ys, s, pro_edges, pro_offsets, pro_boxes, a):
                count += 1
                break
    return count


@njit(cache=True)
def _count_improper(xs, ys, warn_edges, warn_offsets, warn_boxes) -> int:
    """``N`` of eq. 5: states with the tip in a warning area or two segments touching."""
    count = 0
    m = xs.shape[1]
    for s in range(xs.shape[0]):
        bad = False
        for a in range(warn_boxes.shape[0]):
            if state_inside_area(
                xs[s, m - 1], ys[s, m - 1], warn_edges, warn_offsets, warn_boxes, a
            ):
                bad = True
                break
        if bad or state_self_touches(xs, ys, s):
            count += 1
    return count


@njit(cache=True)
def population_terms(
    t, a0, lengths, start, mids, skip, warn_edges, warn_offsets, warn_boxes,
    pro_edges, pro_offsets, pro_boxes,
):  # fmt: skip
    """Tips, matched intermediate points, ``N`` and prohibited hits of every design.

    Parameters
    ----------
    t : ndarray, shape (D, S, n)
        ``tan(Delta alpha_i / 2)`` of eq. 2 at every sample.
    a0 : ndarray, shape (D, S)
        ``alpha_0`` at every sample, radians.
    lengths : ndarray, shape (D, n + 1)
        ``l_0 .. l_n``, mm.
    start : ndarray, shape (2,)
        ``T_s``, mm.
    mids : ndarray, shape (K, 2)
        Intermediate points, mm.
    skip : ndarray of bool, shape (D,)
        Designs already infeasible: their ``N`` is not counted (left 0).
    warn_edges, warn_offsets, warn_boxes, pro_edges, pro_offsets, pro_boxes
        The warning and prohibited areas, packed by
        :func:`~origami_cad.design.predicates.pack_areas`.

    Returns
    -------
    tips : ndarray, shape (D, S, 2)
    d_mid : ndarray, shape (D, K)
    mid_index : ndarray of int, shape (D, K)
    improper : ndarray of int, shape (D,)
    hits : ndarray of int, shape (D,)
    """
    n_designs, n_samples, n = t.shape
    m = n + 2
    tips = np.empty((n_designs, n_samples, 2))
    d_mid = np.zeros((n_designs, mids.shape[0]))
    mid_index = np.zeros((n_designs, mids.shape[0]), dtype=np.int64)
    improper = np.zeros(n_designs, dtype=np.int64)
    hits = np.zeros(n_designs, dtype=np.int64)
    xs = np.empty((n_samples, m))
    ys = np.empty((n_samples, m))
    for d in range(n_designs):
        _build_chains(t, a0, lengths, start, d, xs, ys, tips)
        _match_points(tips, d, mids, d_mid, mid_index)
        hits[d] = _count_hits(xs, ys, pro_edges, pro_offsets, pro_boxes)
        if hits[d] == 0 and not skip[d]:
            improper[d] = _count_improper(xs, ys, warn_edges, warn_offsets, warn_boxes)
    return tips, d_mid, mid_index, improper, hits
