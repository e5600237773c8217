"""The softening crease law: its moment and stiffness are its energy's derivatives, the
default is the linear spring, and a softer law pulls with less force."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from origami_cad.errors import SimulationError
from origami_cad.pattern import read_pattern
from origami_cad.simulation.materials import Materials, dump_materials, parse_materials
from origami_cad.simulation.mechanics import crease_law
from origami_cad.simulation.model import SimulationParams
from origami_cad.simulation.pull import simulate_pull
from origami_cad.strings.route import route_from_pattern

MOUNTAIN = (
    Path(__file__).parent / "data" / "pygamix" / "descriptionData" / "f-mountain-big-fix-new.json"
)
LAW = (np.radians([0.0, 60.0, 100.0]), np.array([1.0, 0.58, 0.35]))


@pytest.mark.parametrize("turn", [-2.5, -1.2, -0.3, 0.0, 0.4, 1.1, 1.7, 2.9])
def test_the_law_is_its_energys_derivatives(turn):
    h = 1e-6
    moment, stiffness, _ = crease_law(turn, *LAW)
    energy = [crease_law(turn + s * h, *LAW)[2] for s in (-1, 1)]
    moments = [crease_law(turn + s * h, *LAW)[0] for s in (-1, 1)]
    assert moment == pytest.approx((energy[1] - energy[0]) / (2 * h), abs=1e-7)
    assert stiffness == pytest.approx((moments[1] - moments[0]) / (2 * h), abs=1e-6)


def test_one_point_is_the_linear_spring_and_past_the_last_point_the_slope_holds():
    for turn in (-1.3, 0.2, 2.0):
        m, k, e = crease_law(turn, np.zeros(1), np.ones(1))
        assert (m, k) == pytest.approx((turn, 1.0)) and e == pytest.approx(turn**2 / 2)
    assert crease_law(2.5, *LAW)[1] == pytest.approx(0.35)
    assert crease_law(0.5236, *LAW)[1] == pytest.approx(1.0 - 0.42 * 0.5, rel=1e-4)  # 30 deg


@pytest.fixture(scope="module")
def mountain():
    cp = read_pattern(MOUNTAIN)
    return cp, route_from_pattern(cp)


def _pull(mountain, materials: Materials):
    cp, route = mountain
    return simulate_pull(cp, route, 12.0, materials.simulation_params(), step=3.0)


def test_a_flat_law_folds_as_the_linear_spring_and_a_softer_one_pulls_less(mountain):
    linear = _pull(mountain, Materials(crease_stiffness_given=0.1))
    flat = _pull(mountain, Materials(crease_stiffness_given=0.1, law_angles=(0.0, 90.0),
                                     law_factors=(1.0, 1.0)))  # fmt: skip
    soft = _pull(mountain, Materials(crease_stiffness_given=0.1, law_angles=(0.0, 30.0),
                                     law_factors=(1.0, 0.1)))  # fmt: skip
    assert np.allclose(flat.result.states, linear.result.states, atol=1e-6)
    assert flat.tension == pytest.approx(linear.tension, rel=1e-6, abs=1e-9)
    assert soft.tension[-1] < 0.8 * linear.tension[-1]


def test_the_default_is_linear_and_the_file_round_trips():
    assert SimulationParams().crease_law == ((0.0, 1.0),)
    assert "law_" not in dump_materials(Materials())
    m = Materials(law_angles=(0.0, 60.0, 100.0), law_factors=(1.0, 0.58, 0.35))
    back = parse_materials(dump_materials(m))
    assert back.crease_law == m.crease_law
    assert back.simulation_params().crease_law == ((0.0, 1.0), (60.0, 0.58), (100.0, 0.35))


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("[crease]\nlaw_angles = [0, 60]\nlaw_factors = [1]\n", "as long"),
        ("[crease]\nlaw_angles = [10, 60]\nlaw_factors = [1, 0.5]\n", "at 0 deg"),
        ("[crease]\nlaw_angles = [0, 60, 50]\nlaw_factors = [1, 0.5, 0.2]\n", "increase"),
        ("[crease]\nlaw_angles = [0, 60]\nlaw_factors = [1, -0.5]\n", ">= 0"),
    ],
)
def test_a_bad_law_names_the_file_and_key(text, match):
    with pytest.raises(SimulationError, match=match) as err:
        parse_materials(text, "m.toml")
    assert "m.toml" in str(err.value) and "law_" in str(err.value)
