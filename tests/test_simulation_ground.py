"""Simulation: exact Hessians, ground friction, free structures, TSAs riding on panels."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
from conftest import three_hole_string

from origami_cad.errors import SimulationError, StringsError
from origami_cad.pattern import CreasePattern
from origami_cad.simulation import SimulationParams, simulate
from origami_cad.simulation.cables import StringSet, string_derivatives
from origami_cad.simulation.mechanics import (
    bar_hessians,
    bar_lengths,
    hinge_gradients,
    hinge_hessians,
)
from origami_cad.strings import TOP, TSAParams, load_route
from origami_cad.strings.route import RouteSpec, StringRoute

ONBOARD = TSAParams(model="onboard", length=120.0, radius=0.6, max_helix_angle=75.0)
EARTH = 9810.0  # mm/s^2
PLA = 1.24e-6  # kg/mm^3


def _fd_jacobian(f, x: np.ndarray, nodes: np.ndarray, h: float = 1e-6) -> np.ndarray:
    cols = []
    for node in nodes:
        for c in range(3):
            xp, xm = x.copy(), x.copy()
            xp[node, c] += h
            xm[node, c] -= h
            cols.append((f(xp) - f(xm)).ravel() / (2 * h))
    return np.column_stack(cols)


def test_hessians_match_finite_differences_of_the_gradients():
    rng = np.random.default_rng(3)
    x = rng.normal(size=(9, 3)) * 10
    hinges = np.array([[0, 1, 2, 3], [4, 5, 6, 7], [1, 2, 5, 0]])
    hess = hinge_hessians(x, hinges)
    for k, hinge in enumerate(hinges):
        num = _fd_jacobian(lambda y, k=k: hinge_gradients(y, hinges)[k], x, hinge)
        np.testing.assert_allclose(hess[k], num, atol=1e-8 * np.abs(num).max())
    bars = np.array([[0, 1], [2, 8]])
    k_bar, rest = np.array([50.0, 7.0]), np.array([3.0, 25.0])

    def bar_grad(y, b):
        length, unit = bar_lengths(y, bars)
        f = k_bar[b] * (length[b] - rest[b])
        return np.r_[-f * unit[b], f * unit[b]]

    hb = bar_hessians(x, bars, k_bar, rest)
    for b, bar in enumerate(bars):
        num = _fd_jacobian(lambda y, b=b: bar_grad(y, b), x, bar)
        np.testing.assert_allclose(hb[b], num, atol=1e-6 * np.abs(num).max())
    # a string through three holes; its anchor fixed in space, then riding on a panel
    s = three_hole_string(rng)
    for mounted in (False, True):
        if mounted:
            s.anchor_tri, s.anchor_ab = np.array([6, 8, 1]), np.array([0.3, 0.2])
            s.anchor, s.anchor_orient = np.array([1.0, 2.0, 7.5]), -1.0
        strings = StringSet([s], 1.1, ONBOARD, theta=4.0)
        nodes, _, hess = string_derivatives(x, s, strings)
        num = _fd_jacobian(lambda y, ss=strings: string_derivatives(y, s, ss, False)[1], x, nodes)
        # the TSA's share is differentiated numerically: 3e-5 of the largest term
        np.testing.assert_allclose(hess, num, atol=3e-5 * np.abs(num).max())
        np.testing.assert_allclose(hess, hess.T, atol=1e-12)


def _plate(w: float = 40.0, h: float = 40.0) -> CreasePattern:
    return CreasePattern([(0, 0), (w, 0), (w, h), (0, h)], [(0, 1), (1, 2), (2, 3), (3, 0)], "B")


def test_friction_holds_a_free_plate_until_the_string_pulls_mu_times_its_weight():
    cp = _plate()
    weight = 40 * 40 * 2.2 * PLA * EARTH / 1000.0  # kg mm/s^2 -> N
    mid = 1.1  # the plate's mid-surface rests half its thickness above the ground
    # a fixed TSA pulls horizontally on a hole on the top face (1.1 mm above the mid-surface)
    string = StringRoute((-60.0, 20.0, mid + 1.1), (0,), ((5.0, 20.0),), (TOP,), ("a",))
    route = RouteSpec(ONBOARD, (string,), 2.2, math.radians(10), 12.0)
    for mu in (0.5, 0.2):
        params = SimulationParams(gravity=EARTH, ground=0.0, friction=mu)
        result = simulate(cp, route, params, steps=12, free=True)
        assert "no panel is held" in result.notes[0]
        assert result.converged.all()
        start, end = result.states[0], result.states[-1]
        # it slides: the tension stays at Coulomb's mu W while the TSA takes up string
        for tension in result.tensions[2:, 0]:
            assert tension == pytest.approx(mu * weight, rel=1e-3)
        moved = start[:, 0].mean() - end[:, 0].mean()
        x_dis = 60.0 + 5.0
        taken = ONBOARD.consumed(12 * 2 * math.pi, x_dis) - ONBOARD.consumed(0.0, x_dis)
        assert moved == pytest.approx(float(taken), rel=0.02)
        # and rests on the ground, not in it
        assert end[:, 2].min() > mid - 1e-3


def test_an_onboard_tsa_folds_a_free_sheet_whose_heavy_panel_stays_put():
    # a 40 x 40 panel and a 20 x 40 flap on a valley; the TSA rides on the big panel
    cp = CreasePattern(
        [(0, 0), (40, 0), (60, 0), (60, 40), (40, 40), (0, 40)],
        [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 0), (1, 4)],
        "BBBBBBV",
    )
    big, flap = cp.face_of_point(20, 20), cp.face_of_point(50, 20)
    string = StringRoute(
        (10.0, 20.0, 5.0),
        (big, flap),
        ((30.0, 20.0), (50.0, 20.0)),
        (TOP, TOP),
        ("a", "b"),
        anchor_face=big,
    )
    route = RouteSpec(ONBOARD, (string,), 2.2, math.radians(10), 10.0)
    params = SimulationParams(gravity=EARTH, ground=0.0, friction=0.5)
    result = simulate(cp, route, params, steps=20, free=True)
    crease = int(np.flatnonzero(cp.assignments == "V")[0])
    angles = result.fold_angles[:, crease]
    assert angles[-1] > 60.0
    assert all(b >= a - 1e-6 for a, b in itertools.pairwise(angles))
    corners = [cp.face_of_point(1, 1), cp.face_of_point(1, 39)]
    assert corners == [big, big]
    outer = [int(np.argmin(np.linalg.norm(cp.vertices - p, axis=1))) for p in ((0, 0), (0, 40))]
    drift = np.linalg.norm(result.states[-1][outer, :2] - result.states[0][outer, :2], axis=1)
    assert drift.max() < 0.05  # friction holds the heavy panel
    assert result.states[-1][:, 2].min() > 1.1 - 1e-3
    assert result.converged.all()


def test_a_free_structure_needs_gravity_and_a_ground():
    cp = _plate()
    string = StringRoute((-60.0, 20.0, 2.2), (0,), ((5.0, 20.0),), (TOP,), ("a",))
    route = RouteSpec(ONBOARD, (string,), 2.2, math.radians(10), 1.0)
    with pytest.raises(SimulationError, match="needs gravity > 0 and a ground"):
        simulate(cp, route, SimulationParams(ground=0.0), steps=2, free=True)
    with pytest.raises(SimulationError, match="needs gravity > 0 and a ground"):
        simulate(cp, route, SimulationParams(gravity=EARTH), steps=2, free=True)


def test_route_files_mount_the_tsa_on_a_panel(tmp_path):
    cp = _plate()
    label = cp.face_labels[0]
    text = f"""
[tsa]
model = "onboard"
length = 120.0
radius = 0.6
max_helix_angle = 75.0
[route]
[[route.strings]]
anchor = [10.0, 20.0, 6.0]
anchor_panel = "{label}"
holes = [[30.0, 20.0]]
"""
    path = tmp_path / "r.toml"
    path.write_text(text)
    route = load_route(path, cp)
    assert route.strings[0].anchor_face == 0
    path.write_text(text.replace("[10.0, 20.0, 6.0]", "[80.0, 20.0, 6.0]"))
    with pytest.raises(StringsError, match=r"anchor.*not on panel"):
        load_route(path, cp)
    path.write_text(text.replace(f'"{label}"', '"nope"'))
    with pytest.raises(StringsError, match=r"anchor_panel.*no panel labelled 'nope'"):
        load_route(path, cp)


def test_cli_free_structure_without_gravity_exits_2_and_writes_nothing(tmp_path, capsys):
    from origami_cad.cli import main
    from origami_cad.pattern import write_fold

    write_fold(_plate(), tmp_path / "plate.fold")
    route = tmp_path / "r.toml"
    route.write_text(
        '[tsa]\nmodel = "onboard"\nlength = 120.0\nradius = 0.6\n[route]\nmax_turns = 2\n'
        "[[route.strings]]\nanchor = [-60.0, 20.0, 2.2]\nholes = [[5.0, 20.0]]\n"
    )
    out = tmp_path / "sim"
    args = ["simulate", str(tmp_path / "plate.fold"), str(route), "-o", str(out), "--free"]
    assert main(args) == 2
    assert "needs gravity > 0 and a ground" in capsys.readouterr().err
    assert not out.exists()
    assert main([*args, "--ground", "0", "--gravity", "9810", "--friction", "-1"]) == 2
    assert "--friction: expected a finite number in [0, 100], got -1" in capsys.readouterr().err
    assert main([*args, "--ground", "0", "--gravity", "9810", "--steps", "4"]) == 0
    data = json.loads((out / "simulation.json").read_text())
    assert data["notes"][0].startswith("no panel is held")
    assert data["states"]["tensions_N"][-1][0] > 0


def test_an_anchor_on_the_held_panel_acts_as_the_same_anchor_fixed_in_space():
    # the TSA rides on the held panel, which has no hole of its own: the string runs
    # from it straight to the flap, so the result must equal a fixed anchor there
    cp = CreasePattern(
        [(0, 0), (40, 0), (60, 0), (60, 40), (40, 40), (0, 40)],
        [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5), (5, 0), (1, 4)],
        "BBBBBBV",
    )
    body, flap = cp.face_of_point(20, 20), cp.face_of_point(50, 20)
    held = cp.face_labels[body]
    mounted = StringRoute(
        (20.0, 20.0, 8.0), (flap,), ((50.0, 20.0),), (TOP,), ("b",), anchor_face=body
    )
    fixed = StringRoute((20.0, 20.0, 8.0 + 1.1), (flap,), ((50.0, 20.0),), (TOP,), ("b",))
    results = [
        simulate(
            cp, RouteSpec(ONBOARD, (s,), 2.2, math.radians(10), 6.0), steps=6, fixed_panel=held
        )
        for s in (mounted, fixed)
    ]
    crease = int(np.flatnonzero(cp.assignments == "V")[0])
    assert results[0].fold_angles[-1, crease] > 10.0
    np.testing.assert_allclose(results[0].states[-1], results[1].states[-1], atol=1e-6)
