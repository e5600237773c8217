"""Friction where strings pass through holes (the capstan law), in both string models."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from origami_cad.errors import SimulationError
from origami_cad.pattern import read_pattern
from origami_cad.pattern.design import load_design
from origami_cad.simulation import SimulationParams
from origami_cad.simulation.pull import simulate_pull
from origami_cad.strings import load_route, simulate_dcqc
from origami_cad.strings.friction import capstan_weights, wrap_angles
from origami_cad.strings.route import route_from_pattern

MOUNTAIN = Path(__file__).parent / "data" / "pygamix" / "descriptionData"
MOUNTAIN = MOUNTAIN / "f-mountain-big-fix-new.json"


def test_wrap_angles_of_straight_bent_and_threaded_strings() -> None:
    anchor = np.array([0.0, 0.0, 0.0])
    straight = np.array([[10.0, 0, 0], [20.0, 0, 0]])
    assert wrap_angles(anchor, straight, straight) == pytest.approx([0.0])
    bent = np.array([[10.0, 0, 0], [10.0, 10.0, 0]])
    assert wrap_angles(anchor, bent, bent) == pytest.approx([math.pi / 2])
    # in on the top face, through the hole, out on the bottom face, back the same way
    arrive = np.array([[10.0, 0, 0.5], [0.0, 0, -0.5]])
    leave = np.array([[10.0, 0, -0.5], [0.0, 0, -0.5]])
    assert wrap_angles(np.array([0.0, 0, 0.5]), arrive, leave) == pytest.approx([math.pi])
    w = capstan_weights(np.array([0.0, 0, 0.5]), arrive, leave, 0.2)
    assert w == pytest.approx([1.0, math.exp(-0.2 * math.pi)])
    assert np.all(capstan_weights(anchor, bent, bent, 0.0) == 1.0)


@pytest.fixture(scope="module")
def mountain():
    cp = read_pattern(MOUNTAIN)
    return cp, route_from_pattern(cp)


def test_a_zero_coefficient_changes_nothing_and_friction_costs_force(mountain) -> None:
    cp, route = mountain
    base = SimulationParams(fold_limit=180.0)
    none = simulate_pull(cp, route, 10.0, base, step=2.5)
    zero = simulate_pull(
        cp, route, 10.0, SimulationParams(fold_limit=180.0, hole_friction=0.0), step=2.5
    )
    rough = simulate_pull(
        cp, route, 10.0, SimulationParams(fold_limit=180.0, hole_friction=0.1), step=2.5
    )
    assert np.array_equal(none.result.states, zero.result.states)
    assert np.array_equal(none.tension, zero.tension)
    assert rough.result.converged.all()
    # the strings lose tension around the holes: the machine pulls harder ...
    assert np.all(rough.tension[1:] > 1.1 * none.tension[1:])
    # ... for the same folding: friction changes the forces, not what the length allows
    folded = cp.edge_mask("M", "V")
    turned = [np.abs(r.result.fold_angles[-1, folded]).max() for r in (none, rough)]
    assert turned[1] == pytest.approx(turned[0], abs=1.0)


def test_dcqc_friction_raises_the_tension_for_the_same_fold() -> None:
    design = load_design("examples/miura_6x4.toml")
    route = load_route("examples/miura_route.toml", design.pattern)
    ks = SimulationParams.for_route(route).dcqc_stiffness()
    assert ks["hole_friction"] == 0.0
    plain = simulate_dcqc(design, route, **ks)
    rough = simulate_dcqc(design, route, **{**ks, "hole_friction": 0.2})
    p = 0.5 * min(plain.p[-1], rough.p[-1])
    at = [np.interp(p, r.p, np.nansum(r.tensions, axis=1)) for r in (plain, rough)]
    assert at[1] > 1.05 * at[0]
    with pytest.raises(SimulationError, match="hole_friction"):
        simulate_dcqc(design, route, crease_stiffness=ks["crease_stiffness"], hole_friction=0.2)
