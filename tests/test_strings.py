"""TSA models, DCQC routing and the quasi-static folding they produce."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import colour_pixels, ink, panel_frames
from scipy.optimize import brentq

from origami_cad.cli import main
from origami_cad.errors import StringsError
from origami_cad.pattern.design import Design, load_design
from origami_cad.pattern.tg import TGDesign, tg_pattern
from origami_cad.strings import (
    BOTTOM,
    TOP,
    load_route,
    onboard_angle,
    onboard_compliant_length,
    onboard_contraction,
    onboard_transmission,
    ring_length,
    simulate_dcqc,
)
from origami_cad.strings.dcqc import segment_names
from origami_cad.strings.dcqc_result import StopReason

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


# ------------------------------------------------------------------ TSA models
def test_eq8_by_hand_on_both_branches():
    x, d1, d2, ds = 60.0, 10.0, 8.0, 0.5
    # theta = 0: (d2 - d1)^2 / 4 = 1
    assert ring_length(0.0, x, d1, d2, ds) == pytest.approx(math.sqrt(3600 + 1))
    # theta = pi/2: ((8)^2 + (10)^2) / 4 = 41
    assert ring_length(math.pi / 2, x, d1, d2, ds) == pytest.approx(math.sqrt(3600 + 41))
    # theta = pi: second branch, (d2 + d1)^2 / 4 = 81, and the first branch agrees
    assert ring_length(math.pi, x, d1, d2, ds) == pytest.approx(math.sqrt(3600 + 81))
    below = ring_length(math.pi - 1e-9, x, d1, d2, ds)
    assert below == pytest.approx(ring_length(math.pi, x, d1, d2, ds), abs=1e-8)
    # theta = 3 pi: (18 + 2 pi 0.5)^2 / 4
    expected = math.sqrt(3600 + (18 + 2 * math.pi * 0.5) ** 2 / 4)
    assert ring_length(3 * math.pi, x, d1, d2, ds) == pytest.approx(expected)
    with pytest.raises(StringsError):
        ring_length(-1.0, x, d1, d2, ds)


def test_onboard_model_closed_form_inverse_and_limits():
    length, r = 100.0, 0.5
    theta = np.linspace(0, 150.0, 7)
    x = onboard_contraction(theta, length, r)
    np.testing.assert_allclose(x, length - np.sqrt(length**2 - (theta * r) ** 2))
    np.testing.assert_allclose(onboard_angle(x, length, r), theta, atol=1e-9)
    tau = onboard_transmission(theta, length, r)
    np.testing.assert_allclose(tau, theta * r**2 / np.sqrt(length**2 - (theta * r) ** 2))
    # with no force the compliant model is the rigid one
    np.testing.assert_allclose(onboard_compliant_length(theta, 0.0, length, r, 500.0), length - x)
    assert onboard_compliant_length(50.0, 10.0, length, r, 500.0) > length - onboard_contraction(
        50.0, length, r
    )
    with pytest.raises(StringsError, match="exceeds"):
        onboard_contraction(length / r, length, r)  # theta r = L0
    with pytest.raises(StringsError, match="exceeds"):
        onboard_angle(length, length, r)
    with pytest.raises(StringsError):
        onboard_compliant_length(1e6, 0.0, length, r, 500.0)


# ------------------------------------------------------------------ one crease
def test_single_valley_crease_matches_the_closed_form(tmp_path):
    """Two 40 x 20 mm panels on a valley crease, one string over it from an onboard TSA."""
    tg = TGDesign((40.0,), (), 1, 40.0, 1)
    design = Design(tg_pattern(tg), tg, "transition-graph")
    # the anchor sits out along the string, 5 mm up: the string shortens from the
    # first twist (an anchor right above the crease, as this test had, makes it
    # lengthen first, +0.5 mm per radian: DCQC now reports that as a jam)
    a, e, y_a, z_a, length, radius = 10.0, 1.1, -40.0, 5.0, 100.0, 0.5
    route = tmp_path / "one.toml"
    route.write_text(
        f"""
[tsa]
model = "onboard"
length = {length}
radius = {radius}
[route]
thickness = {2 * e}
step = 10.0
max_turns = 8
p_max = 0.9
[[route.strings]]
anchor = [20.0, {y_a}, {z_a}]
holes = [[20.0, {-a}], [20.0, {a}]]
"""
    )
    spec = load_route(route, design.pattern)
    assert spec.strings[0].sides == (TOP, TOP)  # above the valley
    result = simulate_dcqc(design, spec)
    assert result.valid

    # independent geometry: each panel turns up by phi = theta / 2 about the crease; the
    # sheet is placed with its vertex centroid fixed (4 outer vertices at 20 sin(phi))
    def demand(phi: float, theta_s: float) -> float:
        shift = 4 * 20.0 * math.sin(phi) / 6
        y = a * math.cos(phi) - e * math.sin(phi)
        z = a * math.sin(phi) + e * math.cos(phi) - shift
        first = math.hypot(-y - y_a, z_a - z)
        return first + float(onboard_contraction(theta_s, length, radius)) + 2 * y

    l0 = demand(0.0, 0.0)
    phis = np.linspace(0.0, 0.9 * math.pi / 2, 200)
    assert np.all(np.diff([demand(f, 0.0) for f in phis]) < 0)  # continuous folding
    assert len(result) > 10
    for theta_s, p in zip(result.theta[1:], result.p[1:], strict=True):
        if demand(0.0, theta_s) - l0 <= 0:
            expected = 0.0
        elif demand(0.9 * math.pi / 2, theta_s) - l0 > 0:
            break
        else:
            phi = brentq(lambda f, t=theta_s: demand(f, t) - l0, 0.0, 0.9 * math.pi / 2)
            expected = 2 * phi / math.pi
        assert p == pytest.approx(expected, abs=2e-5)
    assert result.p[-1] > 0.3


# ------------------------------------------------------------------ Fig. 5
@pytest.fixture(scope="module")
def miura():
    return load_design(EXAMPLES / "miura_6x4.toml")


def test_fig5_auto_routing_folds_the_miura(miura):
    spec = load_route(EXAMPLES / "miura_route.toml", miura.pattern)
    assert len(spec.strings) == 4 and not spec.violations
    for s in spec.strings:  # the DCQC rule, segment by segment
        assert s.sides[0] == TOP
    result = simulate_dcqc(miura, spec)
    assert result.valid
    p = result.p
    assert np.all(np.diff(p) >= 0) and p[-1] > 0.5
    assert result.stop is StopReason.FOLD_LIMIT and "fold limit" in result.reason
    # the routed length of the binding strings really shrinks
    assert np.all(result.routed_length[-1] < result.routed_length[0])


def test_wrong_side_routing_is_flagged_and_does_not_fold(miura, tmp_path):
    spec = load_route(EXAMPLES / "miura_route.toml", miura.pattern)
    text = '[tsa]\nmodel = "ring"\n[route]\nmax_turns = 10\np_max = 0.814\n'
    for s in spec.strings:  # every segment after the first on the wrong side
        wrong = ["top"] + ["bottom" if side == TOP else "top" for side in s.sides[1:]]
        text += (
            f"[[route.strings]]\nanchor = {list(s.anchor)}\nholes = {json.dumps(list(s.names))}"
            f"\nsides = {json.dumps(wrong)}\n"
        )
    path = tmp_path / "wrong.toml"
    path.write_text(text)
    bad = load_route(path, miura.pattern)
    assert any(side == BOTTOM for s in bad.strings for side in s.sides[1:])
    assert len(bad.violations) >= 4
    assert "DCQC needs it" in bad.violations[0]
    result = simulate_dcqc(miura, bad)
    assert not result.valid and result.stop is StopReason.JAM
    assert result.p[-1] == 0.0 and result.jam.segment in {
        n for s in bad.strings for n in segment_names(s)
    }
    assert result.violations == bad.violations


def test_route_file_errors_name_the_key(miura, tmp_path):
    path = tmp_path / "r.toml"
    path.write_text('[route]\n[[route.strings]]\nanchor = [0, 0, 10]\nholes = ["nope"]\n')
    with pytest.raises(StringsError, match="no panel labelled 'nope'"):
        load_route(path, miura.pattern)
    path.write_text('[route]\n[[route.strings]]\nanchor = [0, 0]\nholes = ["c0r0s0"]\n')
    with pytest.raises(StringsError, match="key 'anchor'"):
        load_route(path, miura.pattern)
    path.write_text(
        '[tsa]\nmodel = "spring"\n[route]\n[[route.strings]]\nanchor = [0, 0, 1]\n'
        'holes = ["c0r0s0"]\n'
    )
    with pytest.raises(StringsError, match="key 'model'"):
        load_route(path, miura.pattern)


def test_cli_route_writes_its_outputs(tmp_path):
    out = tmp_path / "route"
    code = main(
        [
            "route",
            str(EXAMPLES / "miura_6x4.toml"),
            str(EXAMPLES / "miura_route.toml"),
            "-o",
            str(out),
        ]
    )
    assert code == 0
    data = json.loads((out / "dcqc.json").read_text())
    assert data["valid"] and data["final"]["p"] > 0.5 and data["stop"] == "fold_limit"
    states = data["states"]
    assert {"theta_s_deg", "p", "routed_length_mm", "tensions_N", "taut"} <= set(states)
    assert len(states["p"]) == len(states["turns"]) > 10
    for name in ("dcqc.png", "route.png", "route_folded.png"):
        covered, _ = ink(out / name)
        assert 0.01 < covered < 0.3, name  # creases, strings, the sheet: not blank, not black
    # dcqc.png: p (axis 0 to 1) against turns in one panel, its end marked at the final p
    ((top, bottom),) = panel_frames(out / "dcqc.png")
    rows, _ = colour_pixels(out / "dcqc.png", "#d62728")
    assert rows.size > 20
    assert (bottom - rows.mean()) / (bottom - top) == pytest.approx(data["final"]["p"], abs=0.01)
