"""A panel too small for the shell wall even at the smallest inner bias gets a thinner wall.

The sheet: two 40 mm square panels with a sliver panel between them, joined by two valley
creases. The sliver cannot hold the default 0.8 mm TPU wall on both its chamfers even at
``MIN_BIAS``; it gets the thickest wall that fits, in whole print layers, down to
``MIN_SHELL``, and only a sliver too narrow even for that is refused.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers_fabrication import sliver_sheet

from origami_cad.fabrication import FabricationParams, fabricate, plan_panels
from origami_cad.fabrication.panels import panel_fits
from origami_cad.fabrication.params import layer_height
from origami_cad.fabrication.plan import MIN_BIAS, MIN_SHELL
from origami_cad.fabrication.solids import PART_NAMES


def test_a_sliver_too_small_for_the_shell_gets_the_thickest_wall_that_fits():
    cp, sliver = sliver_sheet(1.5)
    params = FabricationParams(midlayer_bias=0.1)  # room for a PLA mid-layer 0.9 mm wide
    # not even the smallest bias leaves room for the 0.8 mm wall
    assert not panel_fits(cp, sliver, params, MIN_BIAS, auto_hole=False)
    with pytest.warns(UserWarning, match="too small for the shell wall 0.8 mm"):
        fab = fabricate(cp, params)
    plan = fab.plan
    label = cp.face_labels[sliver]
    shell = plan.shell_of(sliver)
    assert MIN_SHELL <= shell < params.shell
    layer = layer_height(params)  # a whole number of print layers
    assert shell / layer == pytest.approx(round(shell / layer), abs=1e-9)
    # the thickest that fits at the smallest bias: one layer more does not
    assert panel_fits(cp, sliver, params, MIN_BIAS, auto_hole=False, shell=shell)
    assert not panel_fits(cp, sliver, params, MIN_BIAS, auto_hole=False, shell=shell + layer)
    assert panel_fits(cp, sliver, params, plan.bias_of(sliver), auto_hole=False, shell=shell)
    # the other panels keep the default wall and bias
    others = [f for f in range(len(cp.faces)) if f != sliver]
    assert all(plan.shell_of(f) == params.shell for f in others)
    assert all(plan.bias_of(f) == params.bias for f in others)
    (warning,) = [w for w in plan.warnings if "shell wall" in w and "thickest" in w]
    assert "1 of 3 panels" in warning and f"{label} {shell:.2f} mm" in warning
    # the solids are built with it: the sliver's infill starts at its wall, and all are valid
    for name in PART_NAMES:
        assert fab.parts.solids[name] and all(s.is_valid for s in fab.parts.solids[name]), name
    for face in range(len(cp.faces)):
        infills = [
            s
            for s, f in zip(fab.parts.solids["infills"], fab.parts.owners["infills"], strict=True)
            if f == face
        ]
        lows = [s.bounding_box().min.Z for s in infills]
        assert min(lows) == pytest.approx(plan.shell_of(face), abs=1e-6)
    report = fab.report()
    assert report["panel_shell_mm"] == {
        lab: plan.shell_of(f) for f, lab in enumerate(cp.face_labels)
    }
    assert report["panel_bias_mm"][label] == plan.bias_of(sliver)


def test_a_sheet_that_fits_the_wall_records_no_shells():
    cp, _ = sliver_sheet(4.0)
    plan = plan_panels(cp)
    assert plan.shells is None
    assert not any("shell wall" in w and "thickest" in w for w in plan.warnings)


def test_a_sliver_too_small_even_for_the_thinnest_wall_is_printed_in_tpu_alone():
    # such a panel is printed in TPU alone (tests/test_fabrication_midlayer.py), not refused
    params = FabricationParams(midlayer_bias=0.1)
    cp, sliver = sliver_sheet(0.9)
    assert panel_fits(cp, sliver, params, MIN_BIAS, auto_hole=False, tpu_only=True)
    assert not panel_fits(cp, sliver, params, MIN_BIAS, auto_hole=False, shell=MIN_SHELL)
    plan = plan_panels(cp, params)
    assert plan.tpu_only == frozenset({sliver})
    assert all(np.isnan(plan.shell_of(f)) == (f == sliver) for f in range(len(cp.faces)))
