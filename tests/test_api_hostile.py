"""The library keeps the command line's promise: hostile arguments to public calls raise the
``origami_cad.errors`` type of their stage, naming the argument, within a time bound; never a
bare Python error, a silent repair or a call that does not return."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from helpers_exec import bounded
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import origami_cad as oc
from origami_cad.errors import (
    FabricationError,
    OrigamiCadError,
    OutputError,
    PatternError,
    SimulationError,
    StringsError,
)

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

#: Values a careless or hostile script passes where a number belongs.
HOSTILE = st.sampled_from(
    [math.nan, math.inf, -math.inf, -1.0, 0.0, -1e-300, 1e300, 10**9, "1", b"1", [], {}, True]
)


def _only_our_errors(call, expected: type[OrigamiCadError]):
    """Run ``call``: it returns, or raises ``expected`` (never another type)."""
    with bounded():
        try:
            call()
        except OrigamiCadError as exc:
            assert isinstance(exc, expected), f"{type(exc).__name__}: {exc}"
            assert "\n" not in str(exc)


@pytest.fixture(scope="module")
def miura():
    design = oc.load_design(EXAMPLES / "miura_6x4.toml")
    route = oc.load_route(EXAMPLES / "miura_route.toml", design.pattern)
    return design, route


FAST = settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


@FAST
@given(
    name=st.sampled_from(["grid", "crease_stiffness", "max_dp", "string_stiffness"]),
    value=HOSTILE,
)
def test_simulate_dcqc_refuses_hostile_arguments(miura, name, value):
    design, route = miura
    kwargs = {name: value}
    if name == "string_stiffness":
        kwargs["crease_stiffness"] = 0.01
    with bounded():
        try:
            oc.simulate_dcqc(design, route, **kwargs)
        except SimulationError as exc:
            assert name in str(exc)


@pytest.mark.parametrize(
    ("name", "value"),
    [("max_dp", 0), ("max_dp", math.nan), ("max_dp", 1e-9), ("grid", 10**9)],
)
def test_simulate_dcqc_never_runs_without_bound(miura, name, value):
    design, route = miura
    with bounded(), pytest.raises(SimulationError, match=name):
        oc.simulate_dcqc(design, route, **{name: value})


SIM_FIELDS = [
    "panel_modulus",
    "panel_thickness",
    "crease_modulus",
    "crease_thickness",
    "hinge_zone",
    "string_axial_stiffness",
    "fold_limit",
    "density",
    "friction",
    "ground_stiffness",
]


@FAST
@given(name=st.sampled_from(SIM_FIELDS), value=HOSTILE)
def test_simulation_params_refuse_hostile_fields(name, value):
    def make():
        oc.SimulationParams(**{name: value})

    _only_our_errors(make, SimulationError)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"panel_modulus": -1},
        {"density": 0},
        {"fold_limit": 200},
        {"friction": math.nan},
    ],
)
def test_simulation_params_name_the_field(kwargs):
    (name,) = kwargs
    with pytest.raises(SimulationError, match=f"SimulationParams: {name}"):
        oc.SimulationParams(**kwargs)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"steps": 0},
        {"steps": -1},
        {"tension_limit": -1},
        {"jam_ratio": math.nan},
        {"fold_limits": {99999: 10}},
        {"fold_limits": {5: math.nan}},
    ],
)
def test_simulate_refuses_before_any_work(miura, kwargs):
    design, route = miura
    with bounded(), pytest.raises(SimulationError, match="simulate: "):
        oc.simulate(design.pattern, route, design=design, **kwargs)


@FAST
@given(name=st.sampled_from(["length", "x_dis", "d1", "radius"]), value=HOSTILE)
def test_tsa_params_refuse_hostile_fields(name, value):
    _only_our_errors(lambda: oc.TSAParams(**{name: value}), StringsError)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"timestep": 0},
        {"timestep": math.nan},
        {"gravity": math.nan},
        {"friction": -1},
        {"crease_damping": math.inf},
        {"armature": -1},
    ],
)
def test_to_mjcf_refuses_what_it_would_write_as_nan(kwargs):
    (name,) = kwargs
    with pytest.raises(SimulationError, match=f"to_mjcf: {name}"):
        oc.to_mjcf(EXAMPLES / "miura_6x4.toml", **kwargs)


def test_to_mjcf_names_a_missing_file(tmp_path):
    with pytest.raises(SimulationError, match=r"nope\.toml: no such file"):
        oc.to_mjcf(tmp_path / "nope.toml")


@FAST
@given(
    name=st.sampled_from(["fold_ratio", "entry_flag", "unit_width", "copies", "min_turn"]),
    value=HOSTILE,
)
def test_tg_design_refuses_hostile_arguments(name, value):
    vectors = [[40, 0], [30, 25], [30, -10], [40, 15], [30, 0]]
    args = {"vectors": vectors, "fold_ratio": 0.5, name: value}
    _only_our_errors(lambda: oc.tg_design(**args), PatternError)


@pytest.mark.parametrize(
    "vectors", [[[40, 0], [30]], [[40, "a"]], None, [[40, 0, 1]], [[math.nan, 0]]]
)
def test_tg_design_refuses_malformed_vectors(vectors):
    with pytest.raises(PatternError, match="vectors"):
        oc.tg_design(vectors, 0.5)


def test_writers_refuse_nan_and_leave_no_file(tmp_path, miura):
    design, _ = miura
    out = tmp_path / "f.fold"
    with pytest.raises(PatternError, match="NaN"):
        oc.write_fold(design.pattern, out, frames=[{"vertices_coords": [[math.nan, 0, 0]]}])
    assert not out.exists()


def test_write_fabrication_into_a_file_is_an_output_error(tmp_path):
    fab = oc.fabricate(oc.miura_design(2, 2, 20.0, 20.0, 60.0))
    target = tmp_path / "existing_file"
    target.write_text("mine")
    with pytest.raises(OutputError, match="existing_file"):
        oc.write_fabrication(fab, target)
    assert target.read_text() == "mine"


@FAST
@given(
    part=st.sampled_from(["TSAModule", "RingRail", "Blocker", "DriverAdapter"]),
    value=HOSTILE,
)
def test_parts_refuse_hostile_numbers(part, value):
    name = {
        "TSAModule": "guide_hole",
        "RingRail": "eyelet",
        "Blocker": "clearance",
        "DriverAdapter": "mounting_hole",
    }[part]
    _only_our_errors(lambda: getattr(oc, part)(**{name: value}), FabricationError)
