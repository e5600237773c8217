"""String-driven folding from the first twist to the fold limit, in both string models.

The DCQC model (rigid panels, inextensible strings) and the bar-and-hinge simulation
read the same route file; each state is the continuous successor of the previous
one, and each run ends for a named physical reason.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from origami_cad.pattern import read_fold, write_fold
from origami_cad.pattern.design import Design, load_design
from origami_cad.pattern.tg import TGDesign, tg_pattern
from origami_cad.simulation import SimulationParams, simulate
from origami_cad.strings import TSAParams, load_route, simulate_dcqc
from origami_cad.strings.dcqc import fold_limit, segment_names
from origami_cad.strings.dcqc_result import StopReason

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.fixture(scope="module")
def fig5():
    design = load_design(EXAMPLES / "miura_6x4.toml")
    route = load_route(EXAMPLES / "miura_route.toml", design.pattern)
    params = SimulationParams.from_fabrication(route.fabrication)
    dcqc = simulate_dcqc(design, route, **params.dcqc_stiffness())
    sim = simulate(design.pattern, route, design=design)
    return design, route, dcqc, sim


def _gap(sim, dcqc) -> np.ndarray:
    return np.abs(sim.p - np.interp(sim.turns, dcqc.turns, dcqc.p))


def test_the_sheets_fold_limit_is_its_first_crease_at_eq6_legs_included(fig5):
    design, route, _, _ = fig5
    limit = fold_limit(design, route)
    assert limit.source == "eq6" and limit.p == pytest.approx(0.54, abs=0.01)
    assert limit.p < route.fabrication.p_max - 0.2  # the main creases alone: 0.814
    # at the limit the limiting creases (legs) are exactly at eq. 6's theta_max
    from origami_cad.kinematics.folding import fold_design

    angles = np.abs(fold_design(design, limit.p).fold_angles)
    theta_max = math.degrees(route.fabrication.theta_max)
    assert angles.max() == pytest.approx(theta_max, abs=1e-3)
    assert angles[list(limit.edges)].min() == pytest.approx(theta_max, abs=1e-3)


def test_fig5_dcqc_folds_continuously_from_flat_to_the_fold_limit(fig5):
    design, route, elastic, _ = fig5
    inextensible = simulate_dcqc(design, route)  # DCQC's own assumption: no stretch
    for dcqc in (elastic, inextensible):
        assert dcqc.valid and dcqc.stop is StopReason.FOLD_LIMIT
        assert dcqc.p[0] == 0.0 and dcqc.turns[0] == 0.0
        assert np.all(np.diff(dcqc.p) >= 0) and np.all(np.diff(dcqc.turns) > 0)
        assert np.max(np.diff(dcqc.p)) <= 0.02  # no jumps over states the strings forbid
        assert dcqc.p[-1] == pytest.approx(dcqc.limit.p, abs=0.02)
        assert dcqc.p[1] < 0.02  # the first twist already folds a little, not a leap
    # inextensible: every state fits its strings, the binding ones exactly, the others slack
    g = inextensible.tsa_length + inextensible.routed_length
    g -= np.array(inextensible.initial_length_mm)
    assert np.all(g <= 1e-6)
    assert np.all(np.abs(g[inextensible.taut]) < 1e-6)
    # elastic: the taut strings stretch by tension / (EA / L0), the slack ones fit
    l0 = np.array(elastic.initial_length_mm)
    stretch = elastic.tsa_length + elastic.routed_length - l0
    ea = SimulationParams().string_axial_stiffness
    assert np.all(stretch[~elastic.taut] <= 1e-6)
    assert np.allclose(elastic.tensions, ea / l0 * np.maximum(stretch, 0.0), atol=1e-9)
    assert elastic.tensions.max() < 20.0 and np.all(elastic.torque[1:] > 0)
    # the stretch makes it lag: at the same turns it folds less than inextensible strings
    kinematic = np.interp(elastic.turns, inextensible.turns, inextensible.p)
    assert np.all(elastic.p <= kinematic + 1e-6) and np.max(kinematic - elastic.p) > 0.005
    # and as the strings' EA grows it tends to the inextensible model
    params = SimulationParams.from_fabrication(route.fabrication)
    stiff = simulate_dcqc(
        design, route, crease_stiffness=params.crease_stiffness, string_stiffness=1e8
    )
    assert (
        np.max(np.abs(stiff.p - np.interp(stiff.turns, inextensible.turns, inextensible.p))) < 2e-3
    )
    from origami_cad.errors import SimulationError

    with pytest.raises(SimulationError, match="crease_stiffness"):  # no energy, no stretch
        simulate_dcqc(design, route, string_stiffness=6000.0)
    # inextensible with a crease stiffness: tensions by virtual work, positive while folding
    work = simulate_dcqc(design, route, crease_stiffness=params.crease_stiffness)
    assert np.all(work.tensions[1:][work.taut[1:]] > 0) and np.nanmax(work.torque) > 0


def test_fig5_simulation_folds_to_the_same_limit_for_a_named_reason(fig5):
    _, route, dcqc, sim = fig5
    assert sim.stop is StopReason.FOLD_LIMIT and sim.limited_edges
    assert "fold limit reached" in sim.reason
    assert sim.p[-1] == pytest.approx(dcqc.limit.p, abs=0.02)
    assert np.all(np.diff(sim.p) > -0.005)  # monotone up to the solver's noise
    assert np.max(np.diff(sim.p)) <= 0.02
    assert sim.converged.all()
    # the hardware figures per state
    k = len(route.strings)
    assert sim.tensions.shape == sim.taut.shape == (len(sim), k)
    assert sim.torque.shape == sim.p.shape == (len(sim),)
    assert np.all(sim.tensions >= 0) and sim.tensions.max() < 50.0
    # the torque is the tensions times eq. 8's analytic rate at each string's x_dis
    assert np.all(sim.torque >= 0) and sim.torque.max() > 0


def test_fig5_models_agree(fig5):
    """Within 0.02 in p at every state, at default physics and with DCQC's own assumptions."""
    design, route, dcqc, sim = fig5
    # the same elastic strings and creases in both; the panels bend in the simulation only
    assert _gap(sim, dcqc).max() < 0.02
    rigid = SimulationParams.from_fabrication(
        route.fabrication, string_axial_stiffness=1e5, panel_modulus=35000.0
    )
    stiff = simulate(design.pattern, route, rigid, design=design)
    assert stiff.stop is StopReason.FOLD_LIMIT
    assert _gap(stiff, simulate_dcqc(design, route)).max() < 0.02  # inextensible, rigid


def _fold_file_miura(tmp_path: Path):
    write_fold(load_design(EXAMPLES / "miura_6x4.toml").pattern, tmp_path / "miura.fold")
    cp = read_fold(tmp_path / "miura.fold")
    route = tmp_path / "row.toml"
    route.write_text(
        '[tsa]\nmodel = "ring"\n[fabrication]\nbias = 3.0\n[route]\ntake_up = 0.3\nmax_turns = 60\n'
        "[[route.strings]]\nanchor = [-20.0, 45.0, 10.0]\n"
        'holes = ["c0r1s0", "c0r1s1", "c0r1s2", "c0r1s3", "c0r1s4", "c0r1s5"]\n'
    )
    return Design(cp, None, "file"), load_route(route, cp)


def test_a_miura_from_a_fold_file_folds_past_p03_in_both_models(tmp_path):
    design, route = _fold_file_miura(tmp_path)
    assert route.p_max is None and route.fixed_panel is None
    # both models take the printed sheet's limit from [fabrication] (eq. 6, legs first)
    assert fold_limit(design, route).p == pytest.approx(0.54, abs=0.01)
    # without it, the degree-4 folder's own limit: p = 1, the flat-folded state
    bare = tmp_path / "bare.toml"
    bare.write_text((tmp_path / "row.toml").read_text().replace("[fabrication]\nbias = 3.0\n", ""))
    bare_route = load_route(bare, design.pattern)
    assert bare_route.fabrication is None and fold_limit(design, bare_route).p == 1.0
    assert simulate_dcqc(design, bare_route).p[-1] > 0.3
    # both models as the commands run them: one route file, its materials
    dcqc = simulate_dcqc(design, route, **SimulationParams.for_route(route).dcqc_stiffness())
    sim = simulate(design.pattern, route, design=design)
    for result in (dcqc, sim):
        assert result.stop in StopReason and result.reason
        assert result.p[-1] > 0.3
        assert np.all(np.diff(result.p) > -0.005)
    assert np.all(np.diff(dcqc.p) >= 0)
    assert _gap(sim, dcqc).max() < 0.05


def test_breaking_the_side_rule_on_one_crease_jams_both_models(tmp_path):
    design = load_design(EXAMPLES / "miura_6x4.toml")
    text = (EXAMPLES / "miura_route.toml").read_text()
    text += (  # a fifth string across one valley, below it
        '\n[[route.strings]]\nanchor = [66.0, 180.0, 10.0]\nholes = ["c1r1s2", "c1r1s3"]\n'
        'sides = ["top", "bottom"]\n'
    )
    path = tmp_path / "jam.toml"
    path.write_text(text)
    route = load_route(path, design.pattern)
    assert route.violations == [
        "string 5: segment c1r1s2 -> c1r1s3 runs below a valley crease; DCQC needs it above"
    ]
    dcqc = simulate_dcqc(design, route)
    elastic = simulate_dcqc(design, route, **SimulationParams.for_route(route).dcqc_stiffness())
    sim = simulate(design.pattern, route, design=design)
    for result in (dcqc, elastic, sim):
        assert result.stop is StopReason.JAM
        assert result.jam.string == 4 and result.jam.segment == "c1r1s2 -> c1r1s3"
        assert "string 5" in result.reason and "c1r1s2 -> c1r1s3" in result.reason
        assert result.jam.stretch_mm > 0
    assert not dcqc.valid and dcqc.p[-1] == 0.0  # inextensible: it never folds
    # elastic: string 5 is taut from the first step and stretches as the others fold a little
    assert elastic.p[-1] < 0.05 and "has stretched" in elastic.reason
    assert elastic.tensions[-1, 4] == elastic.tensions[-1].max()
    # the elastic string 5 lets the other strings fold the sheet a little before the jam
    assert sim.p[-1] < 0.3 and sim.stretch[-1, 4] == sim.stretch[-1].max()
    assert sim.to_dict()["jam"]["segment"] == "c1r1s2 -> c1r1s3"


# ------------------------------------------------------------------ one stop reason each
def _one_crease(tmp_path: Path, extra: str = "", tsa: str = "") -> tuple[Design, object]:
    """Two 40 x 20 mm panels on a valley; an onboard TSA's string over it."""
    tg = TGDesign((40.0,), (), 1, 40.0, 1)
    design = Design(tg_pattern(tg), tg, "transition-graph")
    path = tmp_path / "one.toml"
    path.write_text(
        f'[tsa]\nmodel = "onboard"\nlength = 100.0\nradius = 0.5\n{tsa}\n'
        f"[route]\nthickness = 2.2\ntake_up = 0.2\nmax_turns = 8\np_max = 0.9\n{extra}\n"
        "[[route.strings]]\nanchor = [20.0, -40.0, 5.0]\n"
        "holes = [[20.0, -10.0], [20.0, 10.0]]\n"
    )
    return design, load_route(path, design.pattern)


def _both(design, route):
    params = SimulationParams()
    dcqc = simulate_dcqc(design, route, **params.dcqc_stiffness())
    sim = simulate(design.pattern, route, params, design=design)
    return dcqc, sim


def test_stop_turn_limit(tmp_path):
    design, route = _one_crease(tmp_path, tsa="")
    route = dataclasses.replace(route, max_turns=3.0)
    for result in _both(design, route):
        assert result.stop is StopReason.TURN_LIMIT and "3 turns" in result.reason
        assert result.turns[-1] == pytest.approx(3.0)
        assert result.p[-1] > 0.05


def test_stop_helix_limit(tmp_path):
    design, route = _one_crease(tmp_path, tsa="max_helix_angle = 10.0")
    helix = route.tsa.max_theta() / (2 * math.pi)
    assert helix < route.max_turns
    for result in _both(design, route):
        assert result.stop is StopReason.HELIX_LIMIT and "helix" in result.reason
        assert result.turns[-1] == pytest.approx(helix, rel=1e-6)


def test_stop_tension_limit(tmp_path):
    design, route = _one_crease(tmp_path, extra="max_tension = 0.1")
    assert route.max_tension == 0.1
    for result in _both(design, route):
        assert result.stop is StopReason.TENSION_LIMIT and "0.1 N" in result.reason
        assert np.nanmax(result.tensions[-1]) > 0.1 >= np.nanmax(result.tensions[-2])


def test_stop_torque_limit(tmp_path):
    design, route = _one_crease(tmp_path, extra="max_torque = 0.01")
    for result in _both(design, route):
        assert result.stop is StopReason.TORQUE_LIMIT and "max_torque" in result.reason
        assert result.torque[-1] > 0.01 >= result.torque[-2]


def test_stop_fold_limit_from_the_route_and_a_blocker(tmp_path):
    design, route = _one_crease(tmp_path)
    route = dataclasses.replace(route, p_max=0.3, max_turns=40.0)
    crease = int(np.flatnonzero(design.pattern.edge_mask("V"))[0])
    # the route's p_max stops both models: the simulation limits the crease to its angle there
    for result in _both(design, route):
        assert result.stop is StopReason.FOLD_LIMIT and result.p[-1] == pytest.approx(0.3, abs=0.01)
    assert _both(design, route)[1].limited_edges == (crease,)
    # a blocker: a limit on one crease (54 deg: p = 0.3 for this crease)
    free = dataclasses.replace(route, p_max=None)
    sim = simulate(design.pattern, free, design=design, fold_limits={crease: 54.0})
    assert sim.stop is StopReason.FOLD_LIMIT and sim.limited_edges == (crease,)
    assert sim.p[-1] == pytest.approx(0.3, abs=0.01)


def test_one_route_file_gives_both_models_one_fold_limit(tmp_path):
    """With [fabrication]: eq. 6 (legs first) in both; without: the folder's p = 1 and no
    printed limit on the creases (they may fold flat, 180 deg); p_max: that in both."""
    design, route = _fold_file_miura(tmp_path)
    bare = dataclasses.replace(route, fabrication=None)
    printed = SimulationParams.for_route(route)
    assert printed == SimulationParams.from_fabrication(route.fabrication)
    assert printed.fold_limit == pytest.approx(math.degrees(route.fabrication.theta_max))
    assert fold_limit(design, route).source == "eq6"
    # the rigid folding at the DCQC limit puts its first crease exactly at the sim's limit
    from origami_cad.kinematics.folding import fold_design

    angles = np.abs(fold_design(design, fold_limit(design, route).p).fold_angles)
    assert angles.max() == pytest.approx(printed.fold_limit, abs=1e-3)
    assert fold_limit(design, bare).p == 1.0 and SimulationParams.for_route(bare).fold_limit == 180
    assert np.abs(fold_design(design, 1.0).fold_angles).max() == pytest.approx(180.0, abs=1e-6)
    # the route's p_max: the DCQC limit, and the creases' angles there in the simulation
    capped = dataclasses.replace(bare, p_max=0.4, max_turns=200.0)
    assert fold_limit(design, capped).p == 0.4
    sim = simulate(design.pattern, capped, design=design)
    assert sim.stop is StopReason.FOLD_LIMIT and sim.p[-1] == pytest.approx(0.4, abs=0.02)
    assert "p_max = 0.4" in " ".join(sim.notes)


def test_stop_jam_names_string_and_segment_on_one_crease(tmp_path):
    design, route = _one_crease(tmp_path)
    s = route.strings[0]
    wrong = dataclasses.replace(s, sides=(s.sides[0], -s.sides[1]), bad_segments=(1,))
    route = dataclasses.replace(route, strings=(wrong,))
    dcqc = simulate_dcqc(design, route)
    assert dcqc.stop is StopReason.JAM and dcqc.jam.string == 0
    assert dcqc.jam.segment == segment_names(wrong)[1] == "(20, -10) -> (20, 10)"


def test_route_file_limits_and_fabrication_are_read(tmp_path):
    design = load_design(EXAMPLES / "miura_6x4.toml")
    route = load_route(EXAMPLES / "miura_route.toml", design.pattern)
    assert route.fabrication.bias == 3.0 and route.thickness == route.fabrication.height
    assert route.p_max is None and route.take_up == 0.1
    params = SimulationParams.from_fabrication(route.fabrication)
    assert params.fold_limit == pytest.approx(math.degrees(route.fabrication.theta_max))
    assert params.hinge_zone == 7.0 and params.panel_thickness == 2.2
    bad = tmp_path / "bad.toml"
    bad.write_text("[fabrication]\nbias = -1\n[route]\n[[route.strings]]\nanchor = [0, 0, 1]\n")
    from origami_cad.errors import StringsError

    with pytest.raises(StringsError, match="key 'bias'"):
        load_route(bad, design.pattern)
    bad.write_text("[route]\nmax_tension = 0\n[[route.strings]]\nanchor = [0, 0, 1]\n")
    with pytest.raises(StringsError, match="key 'max_tension'"):
        load_route(bad, design.pattern)


def test_eq8_analytic_derivatives_match_finite_differences():
    h = 1e-6
    for model in ("ring", "onboard"):
        tsa = TSAParams(model=model)
        for theta in (0.3, 2.0, math.pi + 1e-4, 9.0, 40.0):
            for x in (20.0, 70.0):
                value, dth, dx, dxx = (float(v) for v in tsa.consumed_derivatives(theta, x))
                assert value == pytest.approx(float(tsa.consumed(theta, x)))
                num_th = (tsa.consumed(theta + h, x) - tsa.consumed(theta - h, x)) / (2 * h)
                num_x = (tsa.consumed(theta, x + h) - tsa.consumed(theta, x - h)) / (2 * h)
                num_xx = (
                    tsa.consumed(theta, x + 1e-3)
                    - 2 * tsa.consumed(theta, x)
                    + tsa.consumed(theta, x - 1e-3)
                ) / 1e-6
                assert dth == pytest.approx(float(num_th), rel=1e-6, abs=1e-7)
                assert dx == pytest.approx(float(num_x), rel=1e-6)
                assert dxx == pytest.approx(float(num_xx), rel=1e-3, abs=1e-7)
    # eq. 8's rate jumps at theta = pi (the strings start winding): right-hand rate there
    ring = TSAParams()
    at_pi = float(ring.consumed_derivatives(math.pi, 60.0)[1])
    right = (ring.consumed(math.pi + h, 60.0) - ring.consumed(math.pi, 60.0)) / h
    assert at_pi == pytest.approx(float(right), rel=1e-4) and at_pi > 0.01
    assert float(ring.consumed_derivatives(math.pi - 1e-9, 60.0)[1]) < 1e-6
