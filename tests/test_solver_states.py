"""The solver's folded states stay those recorded (tests/data/solver_states.npz) within
1e-6 mm, on the 6 x 4 example Miura and the benchmark's 10 x 10-panel Miura."""

from __future__ import annotations

import numpy as np
import pytest
import solver_cases


@pytest.mark.parametrize("name", sorted(solver_cases.CASES))
def test_the_folded_states_are_the_recorded_ones(name):
    baseline = np.load(solver_cases.BASELINE)
    result = solver_cases.CASES[name]()
    assert len(result.states) == int(baseline[f"{name}_count"])
    states = solver_cases.recorded(result.states)
    expected = baseline[name]
    # the string really folds the sheet: the last state is far from the first
    assert np.abs(expected[-1] - expected[0]).max() > 10.0
    np.testing.assert_allclose(states, expected, rtol=0, atol=1e-6)


def test_the_strings_kept_out_of_the_factorisation_fold_to_the_same_states(monkeypatch):
    # every assembly splits the strings' k g g^T off as a low rank (Woodbury), as the large
    # patterns do where PARDISO is installed: the 6 x 4 Miura still folds to its states
    from origami_cad.simulation import solver

    monkeypatch.setattr(solver, "SPLIT_STRINGS_SIZE", 0)
    monkeypatch.setattr(solver, "pardiso_available", lambda: True)
    baseline = np.load(solver_cases.BASELINE)
    result = solver_cases.miura_6x4()
    assert len(result.states) == int(baseline["miura_6x4_count"])
    states = solver_cases.recorded(result.states)
    np.testing.assert_allclose(states, baseline["miura_6x4"], rtol=0, atol=1e-6)
