"""The compiled fitness against the NumPy functions it stands for, and one design per call
against the population it belongs to, bit for bit."""

from __future__ import annotations

import math

import numpy as np
import shapely

from origami_cad.design import ArmTask, arm_fitness, decode, decode_bias
from origami_cad.design.limits import panel_bias_violations
from origami_cad.kinematics.chain import tip_positions
from origami_cad.kinematics.limits import crease_fold_limit, reachable_fold_angle
from origami_cad.pattern.miura import leg_gaps

TASK = ArmTask(
    points=[[250.0, 0.0], [180.0, 90.0], [50.0, 133.3]],
    weights=[40.0],
    vectors=7,
    codesign=True,
    max_bias=6.0,
    prohibited=(shapely.box(150.0, 40.0, 400.0, 400.0),),
)


def _population(count: int = 400):
    x = np.random.default_rng(11).uniform(size=(count, TASK.dimension))
    lengths, beta = decode(TASK, x)
    return lengths, beta, np.arange(count) % 2, decode_bias(TASK, x)


def test_the_compiled_terms_are_the_numpy_functions_terms():
    lengths, beta, flags, bias = _population()
    res = arm_fitness(TASK, lengths, beta, flags, bias)
    half = TASK.unit_width / 2.0
    legs = (leg_gaps(lengths, beta, half) < TASK.min_leg_gap).sum(axis=1)
    panels = panel_bias_violations(lengths, beta, half, bias, TASK.min_panel_face)
    limit = crease_fold_limit(bias, TASK.height, TASK.thickness)
    ends = reachable_fold_angle(beta, limit)
    assert np.array_equal(res.leg_violations, legs)
    assert np.array_equal(res.panel_violations, panels)
    assert 0 < legs.sum() < len(legs) and 0 < panels.sum()  # both checks are exercised
    assert np.array_equal(res.crease_limit, limit)
    assert np.array_equal(res.fold_ratio_end, ends / math.pi)
    ramp = np.linspace(0.0, 1.0, TASK.samples)
    want = tip_positions(ends[:, None] * ramp[None, :], lengths, beta, flags, True, TASK.start)
    assert np.allclose(res.tips, want, rtol=0, atol=1e-9)  # the same chain, to rounding
    d_end = np.hypot(*(res.tips[:, -1] - TASK.points[-1]).T)
    assert np.allclose(res.d_end, d_end, rtol=0, atol=1e-12)
    feasible = res.feasible
    assert 0 < feasible.sum() < len(feasible) and (res.prohibited_hits > 0).any()
    f = 120.0 / (10 + res.d_start) + 480.0 / (10 + res.d_end) + 40.0 / (10 + res.d_mid[:, 0])
    f = f - 4.0 * res.improper
    assert np.array_equal(res.fitness[feasible], f[feasible])
    assert np.all(np.isneginf(res.fitness[~feasible]))


def test_one_design_per_call_gives_the_populations_bits():
    lengths, beta, flags, bias = _population(60)
    both = arm_fitness(TASK, lengths, beta, flags, bias)
    for k in range(60):
        one = arm_fitness(TASK, lengths[k], beta[k], flags[k], bias[k : k + 1])
        for name in both.__dataclass_fields__:
            a, b = getattr(both, name)[k], getattr(one, name)[0]
            assert np.array_equal(a, b), (k, name)
