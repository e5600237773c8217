"""The compiled core of eq. 5: every term of a population's fitness in one pass.

:func:`population_fitness` runs, for each design in turn, everything
:func:`~origami_cad.design.fitness.arm_fitness` needs: whether its crease pattern
can be built (:func:`~origami_cad.pattern.miura.leg_gaps` and
:func:`~origami_cad.design.limits.panel_bias_violations`, the same arithmetic), the
crease limit of eq. 6 and the reachable end of the fold range
(:func:`~origami_cad.kinematics.limits.reachable_fold_angle`), the half-turn
tangents of eq. 2 and ``alpha_0`` of eq. 3 at every sample
(:func:`~origami_cad.kinematics.chain.half_turn_tangents`,
:func:`~origami_cad.kinematics.chain.hypar_alpha0`), the sampled chains of eq. 4
(the same running product of turns as
:func:`~origami_cad.kinematics.chain.chain_joints`, equal to rounding) in a small
scratch buffer, the predicates of :mod:`origami_cad.design.predicates` on them,
and eq. 5 itself. The trigonometry is libm's scalar functions (the same bits as
:mod:`math`, whatever numpy's SIMD kernels), and no operation is contracted or
reordered (no fast-math): the same bits on every CPU, and the same bits as the
NumPy expressions the docstrings name. Nothing of size designs x samples x joints
is allocated but the tips, and a design already infeasible (a prohibited area
touched, or not buildable) is not tested for self-intersections, since its
improper states do not enter its cost. Lengths are mm, angles radians.
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

__all__ = ["population_fitness"]


@njit(cache=True, error_model="numpy")
def _leg_violations(lengths, tanb, d, row_height, min_gap, off):
    """Segments of design ``d`` whose neighbouring legs are closer than ``min_gap`` (mm);
    ``tanb`` holds ``tan(beta_i)``."""
    n = tanb.shape[0]
    count = 0
    if n == 0:
        for k in range(lengths.shape[1]):
            if lengths[d, k] < min_gap:
                count += 1
        return count
    for i in range(n):
        off[i] = row_height / tanb[i]
    for k in range(n + 1):
        right = off[min(k, n - 1)]
        left = off[max(k - 1, 0)]
        if lengths[d, k] + right - left < min_gap:
            count += 1
    return count


@njit(cache=True, error_model="numpy")
def _panel_violations(lengths, beta, tanb, d, half_width, b, min_face, cot, inset):
    """Panels of design ``d`` too small for the bias ``b`` (mm), as ``panel_bias_violations``."""
    n1 = lengths.shape[1]
    for k in range(n1 + 1):
        cot[k], inset[k] = 0.0, 0.0
    if n1 > 1:
        for i in range(n1 - 1):
            cot[i + 1] = 1.0 / tanb[i]
            inset[i + 1] = b / abs(math.sin(beta[d, i]))
        cot[0], cot[n1] = cot[1], cot[n1 - 1]
    hi = half_width - b
    bad = 0
    for k in range(n1):
        slope = cot[k + 1] - cot[k]
        room = inset[k] + inset[k + 1] + min_face
        low, high = lengths[d, k] + b * slope, lengths[d, k] + hi * slope
        if low != low or high != high:  # NaN, as numpy's maximum keeps it: not counted
            continue
        if max(low, high) < room:
            bad += 1
    if half_width - 2.0 * b < min_face:
        bad += n1
    return bad


@njit(cache=True, error_model="numpy")
def _reachable_end(beta, d, main):
    """The end of design ``d``'s fold range, radians: ``reachable_fold_angle``'s arithmetic."""
    tan_half = math.tan(min(main, math.pi) / 2.0)
    end = main
    for i in range(beta.shape[1]):
        leg = 2.0 * math.atan(abs(math.cos(beta[d, i])) * tan_half)
        end = min(end, leg)
    return end


@njit(cache=True, error_model="numpy")
def _build_chains(tanb, lengths, d, ef0, theta_end, ramp, hypar, start, xs, ys, tips, tb):
    """Joints of design ``d``'s sampled chains into ``xs, ys`` (S, m), mm; tips into ``tips[d]``.

    The turns are eq. 2's half-turn tangents ``sin(theta / 2) tan(beta_i) (-1)^(EF_0 + i)``
    at ``theta = theta_end ramp[s]``, and ``alpha_0`` eq. 3's (0 unless ``hypar``).
    """
    n = tanb.shape[0]
    for i in range(n):
        sign = 1.0 - 2.0 * ((ef0 + i) % 2)
        tb[i] = tanb[i] * sign
    for s in range(ramp.shape[0]):
        theta = theta_end * ramp[s]
        half = math.sin(theta / 2.0)
        a0 = 0.0
        if hypar:
            c = min(max(math.cos(theta / 2.0), 0.0), 1.0)
            r = min(max(math.sqrt(2.0 * c / (1.0 + c)), 0.0), 1.0)
            a0 = math.acos(r)
        hr, hi = math.cos(a0), math.sin(a0)
        sx, sy = 0.0, 0.0
        xs[s, 0], ys[s, 0] = start[0], start[1]
        for i in range(n + 1):
            if i > 0:
                ti = half * tb[i - 1]
                inv = 1.0 / (1.0 + ti * ti)
                tr, tim = 2.0 * inv - 1.0, 2.0 * ti * inv
                hr, hi = hr * tr - hi * tim, hr * tim + hi * tr
            sx += hr * lengths[d, i]
            sy += hi * lengths[d, i]
            xs[s, i + 1], ys[s, i + 1] = sx + start[0], sy + start[1]
        tips[d, s, 0], tips[d, s, 1] = xs[s, n + 1], ys[s, n + 1]


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
def _count_hits(xs, ys, pro_edges, pro_offsets, pro_boxes) -> int:
    """Number of sampled states whose chain touches a prohibited area."""
    count = 0
    m = xs.shape[1]
    for s in range(xs.shape[0]):
        lox, hix, loy, hiy = xs[s, 0], xs[s, 0], ys[s, 0], ys[s, 0]
        nan = False
        for i in range(m):
            px, py = xs[s, i], ys[s, i]
            nan = nan or px != px or py != py
            lox, hix = min(lox, px), max(hix, px)
            loy, hiy = min(loy, py), max(hiy, py)
        for a in range(pro_boxes.shape[0]):
            box = pro_boxes[a]
            if not nan and (hix < box[0] or lox > box[2] or hiy < box[1] or loy > box[3]):
                continue  # the test's own first rejection, from the chain's box
            if state_touches_area(xs, ys, s, pro_edges, pro_offsets, pro_boxes, a):
                count += 1
                break
    return count


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
def _distance(tips, d, s, target):
    """``|T_e(sample s) - target|`` of design ``d``, mm."""
    dx, dy = tips[d, s, 0] - target[0], tips[d, s, 1] - target[1]
    return math.sqrt(dx * dx + dy * dy)


@njit(cache=True, error_model="numpy")
def _results(n_designs, n_mid, n_samples):
    """The arrays :func:`population_fitness` fills, in ``FitnessResult``'s order (the
    buildability counts, improper states and hits start at 0)."""
    return (
        np.empty(n_designs), np.empty(n_designs), np.empty(n_designs),
        np.zeros((n_designs, n_mid)), np.zeros((n_designs, n_mid), dtype=np.int64),
        np.zeros(n_designs, dtype=np.int64), np.zeros(n_designs, dtype=np.int64),
        np.zeros(n_designs, dtype=np.int64), np.empty((n_designs, n_samples, 2)),
        np.empty(n_designs), np.empty(n_designs), np.empty(n_designs),
        np.zeros(n_designs, dtype=np.int64),
    )  # fmt: skip


@njit(cache=True, error_model="numpy")
def _scratch(n, n_samples):
    """The buffers one design at a time reuses: the chain's joints ``xs, ys`` (S, n + 2)
    mm, the turns' tangents ``tb``, ``tan(beta_i)``, the legs' offsets (n,), the panels'
    cotangents and insets (n + 2)."""
    xs, ys = np.empty((n_samples, n + 2)), np.empty((n_samples, n + 2))
    return xs, ys, np.empty(n), np.empty(n), np.empty(n), np.empty(n + 2), np.empty(n + 2)


@njit(cache=True, error_model="numpy")
def _crease_limit(fixed_limit, b, eq6_span):
    """Every crease's fold limit at inner bias ``b`` mm, radians: ``fixed_limit``, or when
    it is NaN eq. 6's ``2 atan(2 b / (h - t))`` (``eq6_span = h - t`` mm)."""
    return fixed_limit if fixed_limit == fixed_limit else 2.0 * math.atan(2.0 * b / eq6_span)


@njit(cache=True, error_model="numpy")
def _eq5(alpha, d_start, d_end, weights, d_mid, improper, feasible):
    """Eq. 5 of one design: ``alpha / (10 + d_start) + (600 - alpha) / (10 + d_end)``, the
    intermediate points' ``w_j / (10 + d_j)``, ``-4`` per improper state; ``-inf`` when
    not ``feasible`` (a prohibited area touched, or not buildable). Distances mm."""
    f = alpha / (10.0 + d_start) + (600.0 - alpha) / (10.0 + d_end)
    for j in range(weights.shape[0]):
        f = f + weights[j] / (10.0 + d_mid[j])
    f = f - 4.0 * improper
    if not feasible:
        f = -np.inf
    return f


@njit(cache=True, error_model="numpy")
def population_fitness(
    lengths, beta, ef0, bias, fixed_limit, eq6_span, ramp, hypar, start, points, weights,
    alpha, half_width, min_gap, min_face, warn_edges, warn_offsets, warn_boxes,
    pro_edges, pro_offsets, pro_boxes,
):  # fmt: skip  # pragma: no cover - compiled
    """Eq. 5 and its terms for every design, in the order of ``FitnessResult``'s fields.

    Parameters
    ----------
    lengths : ndarray, shape (D, n + 1)
        ``l_0 .. l_n``, mm.
    beta : ndarray, shape (D, n)
        ``beta_1 .. beta_n``, radians.
    ef0 : ndarray of int, shape (D,)
        ``EF_0`` of each design.
    bias : ndarray, shape (D,)
        Inner bias of every crease of each design, mm.
    fixed_limit : float
        The fold limit of every crease, radians; NaN: eq. 6's
        ``2 atan(2 b / eq6_span)`` at each design's bias.
    eq6_span : float
        ``h - t`` of eq. 6, mm.
    ramp : ndarray, shape (S,)
        The samples' fraction of the fold range, from 0 to 1.
    hypar : bool
        ``alpha_0`` by eq. 3 (else 0).
    start : ndarray, shape (2,)
        ``T_s``, mm.
    points : ndarray, shape (P, 2)
        ``P_start``, the intermediate points and ``P_end``, mm.
    weights : ndarray, shape (P - 2,)
        The intermediate points' weights.
    alpha : float
        ``P_start``'s weight.
    half_width : float
        Height of a panel row, mm; 0: the build is not checked.
    min_gap, min_face : float
        The smallest leg gap and panel face, mm.
    warn_edges, warn_offsets, warn_boxes, pro_edges, pro_offsets, pro_boxes
        The warning and prohibited areas, packed by
        :func:`~origami_cad.design.predicates.pack_areas`.

    Returns
    -------
    tuple
        ``fitness, d_start, d_end, d_mid (D, P - 2), mid_index (D, P - 2), improper,
        prohibited_hits, leg_violations, tips (D, S, 2), fold_ratio_end, bias,
        crease_limit`` (radians) ``, panel_violations``: (D,) unless noted.
    """
    n_designs, n = beta.shape
    n_samples = ramp.shape[0]
    n_mid = points.shape[0] - 2
    mids = points[1 : n_mid + 1]
    out = _results(n_designs, n_mid, n_samples)
    fitness, d_start, d_end, d_mid, mid_index, improper, hits, legs, tips = out[:9]
    ratio_end, b_out, limits, panels = out[9:]
    xs, ys, tb, tanb, off, cot, inset = _scratch(n, n_samples)
    p_start, p_end = points[0], points[n_mid + 1]
    for d in range(n_designs):
        b = b_out[d] = bias[d]
        for i in range(n):
            tanb[i] = math.tan(beta[d, i])
        limit = limits[d] = _crease_limit(fixed_limit, b, eq6_span)
        if half_width > 0:  # the build: the legs' gaps, the panels' faces
            legs[d] = _leg_violations(lengths, tanb, d, half_width, min_gap, off)
            panels[d] = _panel_violations(
                lengths, beta, tanb, d, half_width, b, min_face, cot, inset
            )
        theta_end = _reachable_end(beta, d, limit)
        ratio_end[d] = theta_end / math.pi
        _build_chains(tanb, lengths, d, ef0[d], theta_end, ramp, hypar, start, xs, ys, tips, tb)
        _match_points(tips, d, mids, d_mid, mid_index)
        hits[d] = _count_hits(xs, ys, pro_edges, pro_offsets, pro_boxes)
        feasible = hits[d] == 0 and legs[d] == 0 and panels[d] == 0
        if feasible:  # an infeasible design's improper states do not enter its cost
            improper[d] = _count_improper(xs, ys, warn_edges, warn_offsets, warn_boxes)
        d_start[d] = _distance(tips, d, 0, p_start)
        d_end[d] = _distance(tips, d, n_samples - 1, p_end)
        fitness[d] = _eq5(alpha, d_start[d], d_end[d], weights, d_mid[d], improper[d], feasible)
    return out
