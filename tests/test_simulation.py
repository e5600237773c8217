"""Bar-and-hinge simulation: gradients, closed forms, rigid folding, DCQC, limits, errors."""

from __future__ import annotations

import itertools
import json
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import gif_motion, three_hole_string
from scipy.optimize import minimize_scalar

from origami_cad.cli import main
from origami_cad.errors import PatternError
from origami_cad.kinematics.folding import fold_design
from origami_cad.pattern import CreasePattern, read_fold_frames
from origami_cad.pattern.design import Design, load_design
from origami_cad.pattern.tg import TGDesign, tg_pattern
from origami_cad.simulation import SimulationParams, fold_angles, hinge_gradients, simulate
from origami_cad.simulation.cables import StringSet, string_derivatives, string_length
from origami_cad.strings import TOP, TSAParams, load_route, simulate_dcqc
from origami_cad.strings.dcqc_result import StopReason
from origami_cad.strings.route import RouteSpec, StringRoute, auto_holes
from origami_cad.strings.tsa import onboard_contraction, onboard_transmission

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
ONBOARD = TSAParams(model="onboard", length=120.0, radius=0.6, max_helix_angle=75.0)


def test_hinge_and_string_gradients_match_finite_differences():
    rng = np.random.default_rng(0)
    x = rng.normal(size=(8, 3)) * 10
    hinges = np.array([[0, 1, 2, 3], [4, 5, 6, 7], [1, 2, 5, 0]])
    grad = hinge_gradients(x, hinges)
    h = 1e-6
    for k, hinge in enumerate(hinges):
        for a, node in enumerate(hinge):
            for c in range(3):
                xp, xm = x.copy(), x.copy()
                xp[node, c] += h
                xm[node, c] -= h
                num = (fold_angles(xp, hinges)[k] - fold_angles(xm, hinges)[k]) / (2 * h)
                assert grad[k, a, c] == pytest.approx(num, abs=1e-6)
    s = three_hole_string(rng)
    for model in ("ring", "onboard"):
        strings = StringSet([s], 1.1, TSAParams(model=model), theta=4.0)
        nodes, g, _ = string_derivatives(x, s, strings, hessian=False)
        for a, node in enumerate(nodes):
            for c in range(3):
                xp, xm = x.copy(), x.copy()
                xp[node, c] += h
                xm[node, c] -= h
                num = (string_length(xp, s, strings)[0] - string_length(xm, s, strings)[0]) / (
                    2 * h
                )
                assert g[a, c] == pytest.approx(num, abs=1e-6)


def one_crease() -> tuple[CreasePattern, int, int]:
    cp = tg_pattern(TGDesign((40.0,), (), 1, 40.0, 1))  # two 40 x 20 mm panels, one valley
    return cp, cp.face_of_point(20, -10), cp.face_of_point(20, 10)


def test_single_crease_matches_the_closed_form_moment_balance():
    cp, held, moving = one_crease()
    e, anchor = 1.1, np.array([20.0, -10.0, 30.0])
    string = StringRoute(
        tuple(anchor), (held, moving), ((20.0, -10.0), (20.0, 10.0)), (TOP, TOP), ("a", "b")
    )
    route = RouteSpec(ONBOARD, (string,), 2 * e, math.radians(30), 3.0)
    params = SimulationParams()
    result = simulate(cp, route, params, steps=12, fixed_panel=cp.face_labels[held])
    k_crease = params.crease_stiffness * 40.0
    crease = int(np.flatnonzero(cp.edge_mask("V"))[0])

    def demand(rho: float, theta: float) -> float:
        pa = np.array([20.0, -10.0, e])
        pb = np.array(
            [20.0, 10 * math.cos(rho) - e * math.sin(rho), 10 * math.sin(rho) + e * math.cos(rho)]
        )
        return (
            float(np.linalg.norm(pa - anchor))
            + float(np.linalg.norm(pb - pa))
            + float(onboard_contraction(theta, 120.0, 0.6, math.radians(75.0)))
        )

    rest = demand(0.0, 0.0)  # the string is tight on the flat sheet (eq. 7)
    rest_angle = math.radians(3.0)  # the crease rests pre-folded (simulate's prefold)
    k_string = params.string_axial_stiffness / rest
    assert len(result) == 13
    for k in range(1, len(result)):
        theta = result.theta[k]

        def energy(rho: float, theta: float = theta) -> float:
            return (
                0.5 * k_crease * (rho - rest_angle) ** 2
                + 0.5 * k_string * max(0.0, demand(rho, theta) - rest) ** 2
            )

        best = minimize_scalar(
            energy, bounds=(0.0, 2.5), method="bounded", options={"xatol": 1e-12}
        )
        assert result.fold_angles[k, crease] == pytest.approx(math.degrees(best.x), abs=2e-3)
        # energy decreases monotonically within every solve
        energies = result.energies[k]
        assert all(b <= a + 1e-12 for a, b in itertools.pairwise(energies))
        assert result.converged[k]
    assert result.fold_angles[-1, crease] > 10.0
    assert result.torque[-1] > 0
    # the torque is the tension times eq. 8's (here the onboard model's) analytic rate
    rate = onboard_transmission(result.theta[-1], 120.0, 0.6, math.radians(75.0))
    assert result.torque[-1] == pytest.approx(result.tensions[-1, 0] * rate, rel=1e-9)


def test_miura_follows_the_rigid_folding_and_the_dcqc(tmp_path):
    design = load_design(EXAMPLES / "miura_6x4.toml")
    cp = design.pattern
    hx, hy = auto_holes(cp, 2.0)["c1r0s0"]
    path = tmp_path / "row.toml"
    path.write_text(
        '[tsa]\nmodel = "onboard"\nlength = 120.0\nradius = 0.6\nmax_helix_angle = 75.0\n'
        '[route]\nstep = 60.0\nmax_turns = 23\np_max = 0.8\nfixed_panel = "c1r0s0"\n'
        f"[[route.strings]]\nanchor = [{hx}, {hy}, 8.0]\n"
        'holes = ["c1r0s0", "c1r0s1", "c1r0s2", "c1r0s3", "c1r0s4", "c1r0s5"]\n'
    )
    route = load_route(path, cp)
    result = simulate(cp, route, design=design)
    main_creases = np.flatnonzero(
        np.isin(cp.vertices[cp.edges[:, 0], 1], (30.0, 90.0))
        & (cp.vertices[cp.edges[:, 0], 1] == cp.vertices[cp.edges[:, 1], 1])
    )
    p_sim = np.mean(np.abs(result.fold_angles[:, main_creases]), axis=1) / 180
    # the state's fitted fold ratio is the main creases' (a Miura folded rigidly)
    np.testing.assert_allclose(result.p, p_sim, atol=0.01)
    dcqc = simulate_dcqc(design, route)
    assert p_sim[-1] > 0.15
    for turns, p, x in zip(result.turns, p_sim, result.states, strict=True):
        assert p == pytest.approx(float(np.interp(turns, dcqc.turns, dcqc.p)), abs=0.02)
        rigid = fold_design(design, p).coords
        a, b = rigid - rigid.mean(axis=0), x - x.mean(axis=0)
        u, _, vt = np.linalg.svd(a.T @ b)
        rot = u @ np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))]) @ vt
        assert np.abs(a @ rot - b).max() < 0.01 * cp.size


def test_a_blocker_stops_the_crawler_leg_at_its_angle():
    cp, held, moving = one_crease()
    string = StringRoute(
        (20.0, -10.0, 30.0), (held, moving), ((20.0, -10.0), (20.0, 10.0)), (TOP, TOP), ("a", "b")
    )
    route = RouteSpec(ONBOARD, (string,), 2.2, math.radians(90), 30.0)
    crease = int(np.flatnonzero(cp.edge_mask("V"))[0])
    result = simulate(
        cp, route, steps=60, fixed_panel=cp.face_labels[held], fold_limits={crease: 60.0}
    )
    final = result.fold_angles[-1, crease]
    assert final == pytest.approx(60.0, abs=0.5)
    assert result.stop is StopReason.FOLD_LIMIT and result.limited_edges == (crease,)
    assert "fold limit reached" in result.reason
    assert max(result.fold_angles[:, crease]) < 60.5


def test_degenerate_input_is_a_clear_error():
    cp, held, moving = one_crease()
    on_crease = StringRoute(
        (20.0, -10.0, 30.0), (held, moving), ((20.0, -10.0), (20.0, 0.0)), (TOP, TOP), ("a", "b")
    )
    with pytest.raises(PatternError, match="lies on a crease line"):
        simulate(
            cp,
            RouteSpec(ONBOARD, (on_crease,), 2.2, 0.5, 1.0),
            steps=2,
            fixed_panel=cp.face_labels[held],
        )
    sliver = CreasePattern(
        [[0, 0], [10, 0], [5, 1e-6]], [[0, 1], [1, 2], [2, 0]], "B", tolerance=1e-9
    )
    with pytest.raises(PatternError, match="zero area"):
        simulate(sliver, RouteSpec(ONBOARD, (), 2.2, 0.5, 1.0), steps=1)
    lines = CreasePattern([[0, 0], [10, 0], [10, 10]], [[0, 1], [1, 2]], "B")
    with pytest.raises(PatternError, match="no panels"):
        simulate(lines, RouteSpec(ONBOARD, (), 2.2, 0.5, 1.0), steps=1)


def test_cli_simulate_writes_states_json_and_gif(tmp_path):
    design = Design(*_one_design())
    cp = design.pattern
    route = tmp_path / "r.toml"
    route.write_text(
        '[tsa]\nmodel = "onboard"\nlength = 120.0\nradius = 0.6\n[route]\nmax_turns = 6\n'
        'fixed_panel = "c0r0s0"\n[[route.strings]]\nanchor = [20.0, -10.0, 30.0]\n'
        "holes = [[20.0, -10.0], [20.0, 10.0]]\n"
    )
    from origami_cad.pattern import write_fold

    write_fold(cp, tmp_path / "leg.fold")
    out = tmp_path / "sim"
    assert (
        main(
            [
                "simulate",
                str(tmp_path / "leg.fold"),
                str(route),
                "-o",
                str(out),
                "--steps",
                "8",
                "--blocker",
                f"{int(np.flatnonzero(cp.edge_mask('V'))[0])}:45",
            ]
        )
        == 0
    )
    frames = read_fold_frames(out / "states.fold")
    data = json.loads((out / "simulation.json").read_text())
    states = data["states"]
    assert {"theta_s_deg", "tensions_N", "tsa_torque_Nmm", "fold_angles_deg", "taut", "p"} <= set(
        states
    )
    assert len(frames) == 1 + len(states["turns"]) > 4 and frames[-1][:, 2].max() > 1.0
    assert data["stop"] in {r.value for r in StopReason}
    frames, moved = gif_motion(out / "fold.gif")
    assert frames >= 3 and 0.005 < moved < 0.5  # the leg folds; the view stays put


def _one_design():
    tg = TGDesign((40.0,), (), 1, 40.0, 1)
    return tg_pattern(tg), tg, "transition-graph"


def test_the_boat_from_dxf_folds_up_when_its_tsa_turns():
    from origami_cad.pattern import read_pattern

    cp = read_pattern(EXAMPLES / "data" / "boat.dxf")
    route = load_route(EXAMPLES / "boat_route.toml", cp)
    result = simulate(cp, route, steps=40)
    keel = int(np.flatnonzero(cp.edge_mask("V"))[0])
    angles = result.fold_angles[:, keel]
    assert angles[-1] > 60.0  # the sides have risen
    assert all(b >= a - 1e-6 for a, b in itertools.pairwise(angles))
    lifted = result.states[-1][:, 2].max()
    assert lifted > 30.0  # mm above the held panel
