"""The domain logic that left the commands (issue 29), called as a script calls it: no files."""

from __future__ import annotations

import math

import numpy as np
import pytest

from origami_cad.errors import FabricationError, StringsError
from origami_cad.fabrication import fabrication_params, theta_max
from origami_cad.pattern.design import load_design
from origami_cad.strings import load_route, simulate_dcqc
from origami_cad.strings.route import parse_route


@pytest.fixture(scope="module")
def miura(examples):
    return load_design(examples / "miura_6x4.toml")


def test_fabrication_params_from_a_fold_limit_meet_eq6():
    for degrees in (120.0, 146.6, 170.0):
        params = fabrication_params(theta_max=degrees, height=3.0)
        got = math.degrees(theta_max(params.bias, params.height, params.thickness))
        assert got == pytest.approx(degrees, abs=1e-6) and params.height == 3.0
    ratio = fabrication_params(p_max=0.7)
    assert theta_max(ratio.bias, ratio.height, ratio.thickness) == pytest.approx(0.7 * math.pi)
    with pytest.raises(FabricationError, match="only one"):
        fabrication_params(bias=2.0, theta_max=120.0)


def test_a_route_parsed_from_text_is_the_file_read(examples, miura):
    text = (examples / "miura_route.toml").read_text()
    assert parse_route(text, miura.pattern) == load_route(
        examples / "miura_route.toml", miura.pattern
    )
    with pytest.raises(StringsError, match=r"^mine\.toml: "):
        parse_route(text.replace("[route]", "[rout]"), miura.pattern, "mine.toml")


def test_fold_by_strings_is_the_dcqc_model_and_holds_the_panel_asked(examples, miura):
    from origami_cad.simulation import SimulationParams
    from origami_cad.simulation.string_models import fold_by_strings

    spec = load_route(examples / "miura_route.toml", miura.pattern)
    direct = simulate_dcqc(miura, spec, **SimulationParams.for_route(spec).dcqc_stiffness())
    folded = fold_by_strings(miura, spec, "dcqc")
    assert np.allclose(folded.p, direct.p) and np.allclose(folded.turns, direct.turns)
    with pytest.raises(StringsError, match="no panel labelled 'nope'"):
        fold_by_strings(miura, spec, "dcqc", fixed_panel="nope")
    with pytest.raises(StringsError, match="model must be one of dcqc, simulation"):
        fold_by_strings(miura, spec, "rigid")
