"""The fitness of eq. 5, vectorised over whole populations of arm designs.

The printed arm folds only as far as its creases allow (eq. 6): for each design,
the end of its fold range ``theta_e`` is the largest main-crease angle at which
no crease, legs included, passes its limit
(:func:`~origami_cad.kinematics.limits.reachable_fold_angle`). ``theta`` is sampled
from 0 to ``theta_e`` (``task.samples`` states, both ends included) and the TG
chain is evaluated with eqs. 2-4. Then

.. math::

    f = \\frac{\\alpha}{10 + \\|T_e(0) - P_{start}\\|}
      + \\frac{600 - \\alpha}{10 + \\|T_e(\\theta_e) - P_{end}\\|}
      + \\sum_j \\frac{w_j}{10 + d_j} - 4N   \\qquad (5)

with distances in mm. ``d_j`` is the smallest distance from intermediate point
``P_j`` to ``T_e`` over the samples, matched in order: ``P_j`` is matched at a
sample index no smaller than the one of ``P_{j-1}`` (greedy, in order). ``N``
counts the improper sampled states: two non-adjacent transition vectors
intersect or touch, or ``T_e`` lies in a warning area. A design whose chain
touches a prohibited area in any sampled state is infeasible, and so is one
whose crease pattern cannot be built at ``task.unit_width`` (neighbouring legs
closer than ``task.min_leg_gap``, or a panel whose outer face, inset by the
chamfers of eq. 6's bias, would be narrower than ``task.min_panel_face``). With
``task.fold_limit = 180`` ``theta_e = pi``: the paper's eq. 5 over the whole range.

Examples
--------
>>> import numpy as np
>>> from origami_cad.design import ArmTask, arm_fitness
>>> task = ArmTask(points=[[250.0, 0.0], [50.0, 133.3]], vectors=3)  # b, h, t = 3, 2.2, 0.4
>>> res = arm_fitness(task, np.array([[100.0, 80.0, 70.0]]), np.radians([[40.0, 140.0]]), [1])
>>> round(float(res.d_start[0]), 6)  # flat: the chain is straight along +x, 250 mm long
0.0
>>> round(float(res.fold_ratio_end[0]), 3)  # the legs at 40 deg stop the arm at p = 0.76
0.762
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from origami_cad.design.kernel import population_fitness
from origami_cad.design.predicates import area_edges
from origami_cad.design.task import ArmTask

__all__ = [
    "INFEASIBLE_COST",
    "FitnessResult",
    "FitnessTerms",
    "area_edges",
    "arm_fitness",
    "sample_angles",
]

#: Cost (negated fitness) of an infeasible design, above that of any feasible one.
INFEASIBLE_COST = 1.0e4


@dataclass(frozen=True)
class FitnessTerms:
    """Eq. 5 and its terms for one design, as plain numbers.

    Attributes
    ----------
    fitness : float
        ``f`` of eq. 5 (``-inf`` for an infeasible design).
    d_start, d_end : float
        ``|T_e(0) - P_start|`` and ``|T_e(theta_e) - P_end|``, mm.
    d_intermediate : tuple of float
        Distance of each intermediate point to its matched ``T_e`` sample, mm.
    intermediate_sample : tuple of int
        Sample index at which each intermediate point is matched.
    improper_states : int
        ``N``: the number of improper sampled states.
    prohibited_states : int
        Number of sampled states in which the chain touches a prohibited area.
    leg_gap_violations : int
        Number of segments whose neighbouring legs are closer than ``min_leg_gap``.
    fold_ratio_end : float
        ``p_e = theta_e / pi``: the end of the fold range the printed arm reaches.
    bias : float
        Inner bias of every crease, mm (the task's, or the co-designed one).
    crease_limit : float
        Fold limit of every crease at that bias, degrees (eq. 6 or ``fold_limit``).
    panel_violations : int
        Number of panels too small for the bias (see :class:`FitnessResult`).
    """

    fitness: float
    d_start: float
    d_end: float
    d_intermediate: tuple[float, ...]
    intermediate_sample: tuple[int, ...]
    improper_states: int
    prohibited_states: int
    leg_gap_violations: int
    fold_ratio_end: float = 1.0
    bias: float = 3.0
    crease_limit: float = 180.0
    panel_violations: int = 0

    def to_dict(self) -> dict[str, Any]:
        """The terms for a JSON file, with units in the keys."""
        return {
            "fitness": self.fitness,
            "d_start_mm": self.d_start,
            "d_end_mm": self.d_end,
            "d_intermediate_mm": list(self.d_intermediate),
            "intermediate_sample": list(self.intermediate_sample),
            "improper_states": self.improper_states,
            "prohibited_states": self.prohibited_states,
            "leg_gap_violations": self.leg_gap_violations,
            "fold_ratio_end": self.fold_ratio_end,
            "bias_mm": self.bias,
            "crease_limit_deg": self.crease_limit,
            "panel_violations": self.panel_violations,
        }


@dataclass(frozen=True)
class FitnessResult:
    """Eq. 5 and its terms for every design of a population (shape (D,) unless noted).

    Attributes
    ----------
    fitness : ndarray
        ``f`` of eq. 5 (``-inf`` for infeasible designs).
    d_start, d_end : ndarray
        ``|T_e(0) - P_start|`` and ``|T_e(theta_e) - P_end|``, mm.
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
    fold_ratio_end : ndarray
        ``p_e = theta_e / pi``: the samples are ``theta = p theta_e`` for ``p`` in
        ``linspace(0, 1, S)``.
    bias : ndarray
        Inner bias of every crease of each design, mm.
    crease_limit : ndarray
        Fold limit of every crease of each design, radians.
    panel_violations : ndarray of int
        Number of panels too small for the bias (their outer face, inset by the
        chamfers, narrower than ``task.min_panel_face``; 0 without a unit width).
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
    fold_ratio_end: np.ndarray
    bias: np.ndarray
    crease_limit: np.ndarray
    panel_violations: np.ndarray

    @property
    def feasible(self) -> np.ndarray:
        return (
            (self.prohibited_hits == 0) & (self.leg_violations == 0) & (self.panel_violations == 0)
        )

    def cost(self) -> np.ndarray:
        """What CMA-ES minimises: ``-f``, or ``INFEASIBLE_COST + violations`` when infeasible."""
        violations = (self.prohibited_hits + self.leg_violations + self.panel_violations).astype(
            float
        )
        return np.where(self.feasible, -self.fitness, INFEASIBLE_COST + violations)

    def terms(self, k: int) -> FitnessTerms:
        """The fitness terms of design ``k``."""
        return FitnessTerms(
            fitness=float(self.fitness[k]),
            d_start=float(self.d_start[k]),
            d_end=float(self.d_end[k]),
            d_intermediate=tuple(self.d_mid[k].tolist()),
            intermediate_sample=tuple(self.mid_index[k].tolist()),
            improper_states=int(self.improper[k]),
            prohibited_states=int(self.prohibited_hits[k]),
            leg_gap_violations=int(self.leg_violations[k]),
            fold_ratio_end=float(self.fold_ratio_end[k]),
            bias=float(self.bias[k]),
            crease_limit=float(np.degrees(self.crease_limit[k])),
            panel_violations=int(self.panel_violations[k]),
        )


def sample_angles(samples: int) -> np.ndarray:
    """``samples`` fold angles from 0 to pi, both included, radians (46: every 4 deg)."""
    return np.linspace(0.0, math.pi, samples)


def arm_fitness(
    task: ArmTask,
    lengths: np.ndarray,
    shape_angles: np.ndarray,
    entry_flags: np.ndarray,
    bias: np.ndarray | None = None,
) -> FitnessResult:
    """Eq. 5 for a population of arm designs, over the fold range each can reach.

    The improper states ``N`` are counted for designs that are feasible so far
    (no prohibited area touched, buildable); an infeasible design's ``N`` is 0,
    since only its violations enter its cost.

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
    bias : ndarray, shape (D,), optional
        Inner bias of every crease of each design, mm (co-design); default the
        task's ``b`` (or its ``fold_limit``).

    Returns
    -------
    FitnessResult
    """
    lengths = np.asarray(lengths, dtype=float)
    beta = np.asarray(shape_angles, dtype=float)
    if lengths.ndim != 2 or beta.ndim != 2:
        lengths, beta = np.atleast_2d(lengths), np.atleast_2d(beta)
    n_designs = max(lengths.shape[0], beta.shape[0])
    if lengths.shape[0] != n_designs or not lengths.flags.c_contiguous:
        lengths = np.ascontiguousarray(np.broadcast_to(lengths, (n_designs, lengths.shape[1])))
    if beta.shape[0] != n_designs or not beta.flags.c_contiguous:
        beta = np.ascontiguousarray(np.broadcast_to(beta, (n_designs, beta.shape[1])))
    flags = np.asarray(entry_flags, dtype=np.int64).reshape(-1)
    if flags.shape[0] != n_designs:
        flags = np.ascontiguousarray(np.broadcast_to(flags, (n_designs,)))
    b = np.asarray(task.bias if bias is None else bias, dtype=float).reshape(-1)
    if b.shape[0] != n_designs:
        b = np.ascontiguousarray(np.broadcast_to(b, (n_designs,)))
    c = task.fitness_constants
    return FitnessResult(*population_fitness(lengths, beta, flags, b, *c))
