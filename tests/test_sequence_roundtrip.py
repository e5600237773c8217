"""A sequence the project writes always reads back.

`model_mapping` samples a model's fold curve, `model_sequence` makes the sequence and
`dump_sequence` writes it; `load_sequence`
is `drive`'s reader. Over random fold curves and keyframes at, just inside and just
outside the ends of the reachable range, what is written reads back, and a keyframe
beyond the range gets the clear error it always got.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from origami_cad.drive.from_model import (
    AT_TOLERANCE,
    DECIMALS,
    model_mapping,
    model_sequence,
    parse_keyframes,
)
from origami_cad.drive.sequence import dump_sequence, load_sequence
from origami_cad.errors import OrigamiCadError
from origami_cad.strings import TSAParams

TSA = TSAParams(model="onboard", length=150.0, radius=0.6, max_helix_angle=75.0)


@st.composite
def curves(draw):
    """A model's states: fold ratios (some repeated, some pausing) against TSA turns."""
    n = draw(st.integers(2, 60))
    lo = draw(st.floats(0.0, 0.6))
    span = draw(st.floats(1e-5, 1.0 - lo))
    steps = draw(
        st.lists(st.floats(0.0, 1.0), min_size=n - 1, max_size=n - 1).filter(lambda v: sum(v) > 0)
    )
    p = lo + span * np.r_[0.0, np.cumsum(steps)] / sum(steps)
    turns = np.linspace(0.0, draw(st.floats(0.5, 20.0)), n)
    return np.minimum(p, 1.0), turns


# where a keyframe sits relative to the reachable range [lo, hi]: at an end, just inside
# it, just outside it (within the tolerance drive allows), or anywhere inside
PLACES = st.sampled_from(["lo", "hi", "lo+", "hi-", "lo-", "hi+", "mid"])


def _at(place: str, lo: float, hi: float, u: float) -> float:
    eps = min(1e-7, (hi - lo) / 4)
    return {
        "lo": lo,
        "hi": hi,
        "lo+": lo + eps,
        "hi-": hi - eps,
        "lo-": lo - AT_TOLERANCE / 2,
        "hi+": hi + AT_TOLERANCE / 2,
        "mid": lo + u * (hi - lo),
    }[place]


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(curve=curves(), places=st.lists(PLACES, min_size=1, max_size=4), u=st.floats(0, 1))
def test_a_written_sequence_reads_back(tmp_path_factory, curve, places, u):
    p, turns = curve
    lo, hi = float(p[0]), float(np.maximum.accumulate(p)[-1])
    at = [min(max(_at(place, lo, hi, u), 0.0), 1.0) for place in places]
    if round(hi, DECIMALS) == round(lo, DECIMALS):  # one point once written: refused by name
        with pytest.raises(OrigamiCadError, match="too little for a mapping"):
            model_mapping(p, turns, TSA, at=at, points=21)
        return
    mapping = model_mapping(p, turns, TSA, at=at, points=21)
    frames = [(0.0, (at[0],)), *((10.0 * (k + 1), (v,)) for k, v in enumerate(at))]
    text = _model_text(
        [{"id": 1, "name": "tsa", "tsa": TSA, "mapping": mapping}], frames, rate=10.0
    )
    path = tmp_path_factory.mktemp("seq") / "s.toml"
    path.write_text(text, encoding="utf-8")
    seq = load_sequence(path)  # no "fold ratios must increase", no unreachable keyframe
    back = seq.tsas[0].mapping
    assert np.all(np.diff(back[:, 0]) > 0) and np.all(np.diff(back[:, 1]) >= 0)
    # what was read is what was computed, to the precision it is written with
    assert back == pytest.approx(mapping, abs=0.6 * 10.0**-DECIMALS)
    for frame, (_, (want,)) in zip(seq.keyframes, frames, strict=True):
        assert frame.values[0] == pytest.approx(min(max(want, back[0, 0]), back[-1, 0]), abs=1e-6)


@settings(max_examples=60, deadline=None)
@given(curve=curves(), beyond=st.floats(2 * AT_TOLERANCE, 0.5), high=st.booleans())
def test_a_keyframe_outside_the_range_gets_a_clear_error(curve, beyond, high):
    p, turns = curve
    lo, hi = float(p[0]), float(np.maximum.accumulate(p)[-1])
    at = hi + beyond if high else lo - beyond
    if not 0.0 <= at <= 1.0:
        return
    with pytest.raises(OrigamiCadError, match=r"outside what its strings reach, p = "):
        model_mapping(p, turns, TSA, at=[at], where="route.toml (dcqc)")


def test_the_fig8_case_that_failed_reads_back(tmp_path):
    """The demo's keyframe at p_e written to 4 decimals, the curve ending 1.5e-8 past it."""
    p_e = 0.42890015
    p = np.linspace(0.0, p_e, 40)
    turns = np.linspace(0.0, 30.0, 40)
    frames = parse_keyframes(["0:0", f"20:{p_e:.4f}", f"30:{p_e:.4f}", "40:0"], 1)
    at = [v[0] for _, v in frames]
    mapping = model_mapping(p, turns, TSA, at=at)
    path = tmp_path / "arm_fold.toml"
    path.write_text(_model_text([{"id": 1, "name": "arm", "tsa": TSA, "mapping": mapping}], frames))
    seq = load_sequence(path)
    assert seq.tsas[0].mapping[-1, 0] == pytest.approx(p_e, abs=1e-6)
    assert math.isclose(seq.keyframes[1].values[0], 0.4289, abs_tol=1e-9)


def test_keyframe_times_are_written_exactly(tmp_path):
    """Two keyframes 0.2 s apart at 1e6 s stay apart (``:g`` once printed both as 1e+06)."""
    p, turns = np.linspace(0, 0.5, 10), np.linspace(0, 10, 10)
    frames = [(0.0, (0.0,)), (1_000_000.1, (0.2,)), (1_000_000.3, (0.3,))]
    mapping = model_mapping(p, turns, TSA, at=[0.0, 0.2, 0.3])
    path = tmp_path / "s.toml"
    path.write_text(_model_text([{"id": 1, "name": "a", "tsa": TSA, "mapping": mapping}], frames))
    with pytest.raises(OrigamiCadError, match="command cycles"):  # bounded, and read to there
        load_sequence(path)
    text = path.read_text()
    assert "t = 1000000.1" in text and "t = 1000000.3" in text


def _model_text(tsas, frames, **options) -> str:
    """The sequence file ``sequence`` writes from string models (its layout)."""
    return dump_sequence(model_sequence(tsas, frames, **options), layout="model")
