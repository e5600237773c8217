"""The fitness of eq. 5, vectorised over whole populations of arm designs.

For each design, ``theta`` is sampled from 0 to pi (``task.samples`` states,
both ends included) and the TG chain is evaluated with eqs. 2-4. Then

.. math::

    f = \\frac{\\alpha}{10 + \\|T_e(0) - P_{start}\\|}
      + \\frac{600 - \\alpha}{10 + \\|T_e(\\pi) - P_{end}\\|}
      + \\sum_j \\frac{w_j}{10 + d_j} - 4N   \\qquad (5)

with distances in mm. ``d_j`` is the smallest distance from intermediate point
``P_j`` to ``T_e`` over the samples, matched in order: ``P_j`` is matched at a
sample index no smaller than the one of ``P_{j-1}`` (greedy, in order). ``N``
counts the improper sampled states: two non-adjacent transition vectors
intersect or touch, or ``T_e`` lies in a warning area. A design whose chain
touches a prohibited area in any sampled state is infeasible, and so is one
whose crease pattern cannot be built at ``task.unit_width`` (neighbouring legs
closer than ``task.min_leg_gap``).

Examples
--------
>>> import numpy as np
>>> from origami_cad.design import ArmTask, arm_fitness
>>> task = ArmTask(points=[[250.0, 0.0], [50.0, 133.3]], vectors=3)
>>> res = arm_fitness(task, np.array([[100.0, 80.0, 70.0]]), np.radians([[40.0, 140.0]]), [1])
>>> round(float(res.d_start[0]), 6)  # flat: the chain is straight along +x, 250 mm long
0.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely

from origami_cad.design import _kernels
from origami_cad.design.task import ArmTask
from origami_cad.kinematics.chain import chain_joints
from origami_cad.pattern.miura import leg_gaps

__all__ = ["INFEASIBLE_COST", "FitnessResult", "area_edges", "arm_fitness", "sample_angles"]

#: Cost (negated fitness) of an infeasible design, above that of any feasible one.
INFEASIBLE_COST = 1.0e4


@dataclass(frozen=True)
class FitnessResult:
    """Eq. 5 and its terms for every design of a population (shape (D,) unless noted).

    Attributes
    ----------
    fitness : ndarray
        ``f`` of eq. 5 (``-inf`` for infeasible designs).
    d_start, d_end : ndarray
        ``|T_e(0) - P_start|`` and ``|T_e(pi) - P_end|``, mm.
    d_mid : ndarray, shape (D, n_p - 2)
        Distance of each intermediate point to its matched ``T_e`` sample, mm.
    mid_index : ndarray of int, shape (D, n_p - 2)
        Sample index at which each intermediate point is matched.
    improper : ndarray of int
        ``N``: the number of improper sampled states.
    prohibited_hits : ndarray of int
        Number of sampled states in which the chain touches a prohibited area.
    leg_violations : ndarray of int
        Number of segments whose neighbouring legs are closer than ``min_leg_gap``
        at ``unit_width`` (the crease pattern cannot be built).
    tips : ndarray, shape (D, S, 2)
        ``T_e`` at every sample, mm.
    """

    fitness: np.ndarray
    d_start: np.ndarray
    d_end: np.ndarray
    d_mid: np.ndarray
    mid_index: np.ndarray
    improper: np.ndarray
    prohibited_hits: np.ndarray
    leg_violations: np.ndarray
    tips: np.ndarray

    @property
    def feasible(self) -> np.ndarray:
        return (self.prohibited_hits == 0) & (self.leg_violations == 0)

    def cost(self) -> np.ndarray:
        """What CMA-ES minimises: ``-f``, or ``INFEASIBLE_COST + violations`` when infeasible."""
        violations = (self.prohibited_hits + self.leg_violations).astype(float)
        return np.where(self.feasible, -self.fitness, INFEASIBLE_COST + violations)

    def terms(self, k: int) -> dict[str, Any]:
        """The fitness terms of design ``k`` as plain numbers."""
        return {
            "fitness": float(self.fitness[k]),
            "d_start_mm": float(self.d_start[k]),
            "d_end_mm": float(self.d_end[k]),
            "d_intermediate_mm": self.d_mid[k].tolist(),
            "intermediate_sample": self.mid_index[k].tolist(),
            "improper_states": int(self.improper[k]),
            "prohibited_states": int(self.prohibited_hits[k]),
            "leg_gap_violations": int(self.leg_violations[k]),
        }


def sample_angles(samples: int) -> np.ndarray:
    """``samples`` fold angles from 0 to pi, both included, radians (46: every 4 deg)."""
    return np.linspace(0.0, math.pi, samples)


def area_edges(areas: tuple[Any, ...]) -> list[np.ndarray]:
    """The boundary segments of each shapely polygon (exterior and holes), shape (E, 2, 2)."""
    out = []
    for poly in areas:
        rings = [poly.exterior, *poly.interiors]
        segs = []
        for ring in rings:
            c = shapely.get_coordinates(ring)
            segs.append(np.stack([c[:-1], c[1:]], axis=1))
        out.append(np.concatenate(segs))
    return out


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def _segments_touch(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Whether segments ab and cd intersect or touch (broadcasting over leading axes)."""
    o1 = _cross(
        b[..., 0] - a[..., 0], b[..., 1] - a[..., 1], c[..., 0] - a[..., 0], c[..., 1] - a[..., 1]
    )
    o2 = _cross(
        b[..., 0] - a[..., 0], b[..., 1] - a[..., 1], d[..., 0] - a[..., 0], d[..., 1] - a[..., 1]
    )
    o3 = _cross(
        d[..., 0] - c[..., 0], d[..., 1] - c[..., 1], a[..., 0] - c[..., 0], a[..., 1] - c[..., 1]
    )
    o4 = _cross(
        d[..., 0] - c[..., 0], d[..., 1] - c[..., 1], b[..., 0] - c[..., 0], b[..., 1] - c[..., 1]
    )
    boxes = (
        (np.minimum(a[..., 0], b[..., 0]) <= np.maximum(c[..., 0], d[..., 0]))
        & (np.minimum(c[..., 0], d[..., 0]) <= np.maximum(a[..., 0], b[..., 0]))
        & (np.minimum(a[..., 1], b[..., 1]) <= np.maximum(c[..., 1], d[..., 1]))
        & (np.minimum(c[..., 1], d[..., 1]) <= np.maximum(a[..., 1], b[..., 1]))
    )
    return (o1 * o2 <= 0) & (o3 * o4 <= 0) & boxes


def _inside(points: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Even-odd point-in-polygon test of ``points (..., 2)`` against boundary ``edges``."""
    px, py = points[..., 0, None], points[..., 1, None]
    x0, y0 = edges[:, 0, 0], edges[:, 0, 1]
    x1, y1 = edges[:, 1, 0], edges[:, 1, 1]
    straddle = (y0 > py) != (y1 > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_at = x0 + (py - y0) * (x1 - x0) / (y1 - y0)
    crossings = straddle & (px < x_at)
    return (np.count_nonzero(crossings, axis=-1) % 2) == 1


def _self_intersections(z: np.ndarray) -> np.ndarray:
    """Per sample, whether two non-adjacent segments of the chain intersect or touch.

    ``z``: complex joints ``(..., m)``. The orientation of joint ``k`` to segment
    ``i`` is ``cross(v_i, z_k - z_i)``; all of them come from one outer product.
    Two segments cross when each one's end points lie on opposite sides of the
    other; a zero orientation (touching, collinear) is decided exactly with boxes.
    """
    m = z.shape[-1]
    i, j = np.triu_indices(m - 1, k=2)
    lead = z.shape[:-1]
    if len(i) == 0:
        return np.zeros(lead, dtype=bool)
    zf = z.reshape(-1, m)
    # (joint, sample) layout: every operation runs over long contiguous rows
    x, y = np.ascontiguousarray(zf.real.T), np.ascontiguousarray(zf.imag.T)
    vx, vy = np.diff(x, axis=0), np.diff(y, axis=0)
    c = vx[:, None, :] * y[None, :, :]
    c -= vy[:, None, :] * x[None, :, :]
    c -= np.diagonal(c, axis1=0, axis2=1).T[:, None, :]
    o = c.reshape(-1, len(zf))
    p12 = o[i * m + j] * o[i * m + j + 1]
    p34 = o[j * m + i] * o[j * m + i + 1]
    hit = ((p12 < 0) & (p34 < 0)).any(axis=0)
    p12, p34 = p12.T, p34.T
    x, y = x.T, y.T
    rows, pairs = np.nonzero((p12 <= 0) & (p34 <= 0) & ~hit[:, None])
    if len(rows):
        pts = np.stack([x, y], axis=-1)
        ii, jj = i[pairs], j[pairs]
        touch = _segments_touch(pts[rows, ii], pts[rows, ii + 1], pts[rows, jj], pts[rows, jj + 1])
        hit[rows[touch]] = True
    return hit.reshape(lead)


def _touches_area(z: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Per sample, whether the chain (complex joints ``z``) touches the polygon with ``edges``.

    True if a joint lies inside the polygon or a chain segment meets a boundary
    segment (touching included).
    """
    lead = z.shape[:-1]
    zf = z.reshape(-1, z.shape[-1])
    out = np.zeros(len(zf), dtype=bool)
    lo, hi = edges.min(axis=(0, 1)), edges.max(axis=(0, 1))
    x, y = zf.real, zf.imag
    cand = np.flatnonzero(
        (x.max(axis=1) >= lo[0])
        & (x.min(axis=1) <= hi[0])
        & (y.max(axis=1) >= lo[1])
        & (y.min(axis=1) <= hi[1])
    )
    if not len(cand):
        return out.reshape(lead)
    x, y = x[cand], y[cand]
    vx, vy = np.diff(x, axis=1), np.diff(y, axis=1)
    hit = np.zeros(len(cand), dtype=bool)
    parity = np.zeros(x.shape, dtype=bool)
    for (ax, ay), (bx, by) in edges:
        ex, ey = bx - ax, by - ay
        # joints against the edge line, edge ends against each chain segment
        oj = ex * (y - ay) - ey * (x - ax)
        s12 = oj[:, :-1] * oj[:, 1:]
        oa = vx * (ay - y[:, :-1]) - vy * (ax - x[:, :-1])
        ob = vx * (by - y[:, :-1]) - vy * (bx - x[:, :-1])
        s34 = oa * ob
        meet = (s12 <= 0) & (s34 <= 0)
        boxes = (
            (np.minimum(x[:, :-1], x[:, 1:]) <= max(ax, bx))
            & (np.maximum(x[:, :-1], x[:, 1:]) >= min(ax, bx))
            & (np.minimum(y[:, :-1], y[:, 1:]) <= max(ay, by))
            & (np.maximum(y[:, :-1], y[:, 1:]) >= min(ay, by))
        )
        hit |= (meet & boxes).any(axis=1)
        # even-odd ray cast of every joint towards +x
        if ay != by:
            straddle = (ay > y) != (by > y)
            x_at = ax + (y - ay) * (bx - ax) / (by - ay)
            parity ^= straddle & (x < x_at)
    out[cand] = hit | parity.any(axis=1)
    return out.reshape(lead)


def arm_fitness(
    task: ArmTask,
    lengths: np.ndarray,
    shape_angles: np.ndarray,
    entry_flags: np.ndarray,
) -> FitnessResult:
    """Eq. 5 for a population of arm designs.

    Parameters
    ----------
    task : ArmTask
        Target points, weights, obstacles, samples.
    lengths : ndarray, shape (D, n + 1)
        ``l_0 .. l_n`` of each design, mm.
    shape_angles : ndarray, shape (D, n)
        ``beta_1 .. beta_n``, radians.
    entry_flags : array_like of int, shape (D,)
        ``EF_0`` of each design.

    Returns
    -------
    FitnessResult
    """
    lengths = np.atleast_2d(np.asarray(lengths, dtype=float))
    theta = sample_angles(task.samples)
    z = chain_joints(theta, lengths, shape_angles, entry_flags, task.hypar_base, task.start)
    tips = np.stack([z[:, :, -1].real, z[:, :, -1].imag], axis=-1)
    d_start = np.linalg.norm(tips[:, 0] - task.points[0], axis=-1)
    d_end = np.linalg.norm(tips[:, -1] - task.points[-1], axis=-1)
    f = task.alpha / (10.0 + d_start) + (600.0 - task.alpha) / (10.0 + d_end)
    n_designs, n_samples = tips.shape[:2]
    mids = task.points[1:-1]
    d_mid = np.zeros((n_designs, len(mids)))
    mid_index = np.zeros((n_designs, len(mids)), dtype=np.int64)
    lowest = np.zeros(n_designs, dtype=np.int64)
    sample_idx = np.arange(n_samples)
    for j, point in enumerate(mids):
        dist = np.linalg.norm(tips - point, axis=-1)
        dist = np.where(sample_idx[None, :] >= lowest[:, None], dist, np.inf)
        k = np.argmin(dist, axis=1)
        d_mid[:, j] = dist[np.arange(n_designs), k]
        mid_index[:, j] = k
        lowest = k
        f = f + task.weights[j] / (10.0 + d_mid[:, j])
    kernels = _kernels.AVAILABLE
    improper = _kernels.self_intersections(z) if kernels else _self_intersections(z)
    for edges in area_edges(task.warning):
        improper |= _kernels.inside_counts(tips, edges) if kernels else _inside(tips, edges)
    n_improper = improper.sum(axis=1)
    f = f - 4.0 * n_improper
    hits = np.zeros((n_designs, n_samples), dtype=bool)
    for edges in area_edges(task.prohibited):
        hits |= _kernels.touches_area(z, edges) if kernels else _touches_area(z, edges)
    n_hits = hits.sum(axis=1)
    legs = np.zeros(n_designs, dtype=np.int64)
    if task.unit_width > 0:
        gaps = leg_gaps(lengths, shape_angles, task.unit_width / 2.0)
        legs = (gaps < max(task.min_leg_gap, 1e-9)).sum(axis=1)
    f = np.where((n_hits > 0) | (legs > 0), -np.inf, f)
    return FitnessResult(f, d_start, d_end, d_mid, mid_index, n_improper, n_hits, legs, tips)
