"""A panel too small for the mid-layer gets a narrower one, one too small for any PLA is
printed in TPU alone, and only a panel too small for its TPU halves is refused (issue 39).

The sheet: two 40 mm square panels with a sliver panel between them, joined by two valley
creases. At ``MIN_BIAS`` and ``MIN_SHELL`` a 1.9 mm sliver keeps its infill but not the
default 0.5 mm mid-layer margin (a mid-layer ``MIN_PLA_WIDTH`` = 0.8 mm wide would need 2.2
mm); a 1.3 mm sliver has room for a mid-layer only 0.5 mm wide, and a 0.9 mm sliver none,
so both are printed in TPU alone (their TPU halves need 0.4 mm); a 0.3 mm sliver keeps
nothing.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import replace

import numpy as np
import pytest
import shapely
import trimesh
from helpers_fabrication import sliver_sheet
from shapely.ops import polylabel

from origami_cad.cli import main
from origami_cad.errors import PatternError
from origami_cad.fabrication import FabricationParams, fabricate, plan_panels, write_fabrication
from origami_cad.fabrication.panels import MIN_PLA_WIDTH, offset_ring, panel_fits
from origami_cad.fabrication.plan import MIN_BIAS, MIN_MIDLAYER_BIAS, MIN_SHELL
from origami_cad.fabrication.solids import PART_NAMES
from origami_cad.pattern import CreasePattern
from origami_cad.pattern.design import miura_design
from origami_cad.pattern.io import write_pattern


def _owned(fab, name: str, face: int) -> list:
    return [
        s for s, f in zip(fab.parts.solids[name], fab.parts.owners[name], strict=True) if f == face
    ]


def _watertight(paths) -> None:
    for name in PART_NAMES:
        mesh = trimesh.load(paths[name])
        assert mesh.is_watertight and mesh.is_winding_consistent, name
        _, uses = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
        assert set(uses.tolist()) == {2}, name


def test_a_panel_too_small_for_the_midlayer_gets_the_widest_that_fits(tmp_path):
    width = 1.9  # at the smallest bias, a mid-layer of MIN_PLA_WIDTH needs m <= 0.35 mm
    cp, sliver = sliver_sheet(width)
    params = FabricationParams()
    label = cp.face_labels[sliver]
    # not even the thinnest wall and smallest bias leave room for b + m and a wide PLA patch
    assert not panel_fits(cp, sliver, params, MIN_BIAS, auto_hole=False, shell=MIN_SHELL)
    with pytest.warns(UserWarning, match="mid-layer margin"):
        fab = fabricate(cp, params)
    plan = fab.plan
    m, s, b = plan.midlayer_of(sliver), plan.shell_of(sliver), plan.bias_of(sliver)
    assert MIN_MIDLAYER_BIAS <= m < params.midlayer_bias
    # the widest margin that fits at the smallest bias and thinnest wall: 0.01 mm more does not
    fits = dict(auto_hole=False, shell=MIN_SHELL)
    assert panel_fits(cp, sliver, params, MIN_BIAS, **fits, midlayer_bias=m)
    assert not panel_fits(cp, sliver, params, MIN_BIAS, **fits, midlayer_bias=m + 0.01)
    assert panel_fits(cp, sliver, params, b, auto_hole=False, shell=s, midlayer_bias=m)
    assert plan.outlines[sliver].midlayer_bias == m and plan.outlines[sliver].has_midlayer
    # the other panels keep every default
    for f in range(len(cp.faces)):
        if f != sliver:
            assert (
                plan.midlayer_of(f) == params.midlayer_bias
                and plan.outlines[f].midlayer_bias is None
            )
            assert plan.bias_of(f) == params.bias
    (warning,) = [w for w in plan.warnings if "mid-layer margin" in w]
    assert "1 of 3 panels" in warning and f"{label} {m:.2f} mm" in warning
    assert not plan.tpu_only
    # the mid-layer is there, b + m from both creases: as wide as the sliver less 2 (b + m)
    (mid,) = _owned(fab, "midlayers", sliver)
    box = mid.bounding_box()
    assert box.max.X - box.min.X == pytest.approx(width - 2 * (b + m), abs=1e-6)
    assert box.max.X - box.min.X >= MIN_PLA_WIDTH
    report = fab.report()
    assert report["panel_midlayer_bias_mm"][label] == m
    assert report["panels_tpu_only"] == []
    _watertight(write_fabrication(fab, tmp_path))


def test_a_pla_midlayer_narrower_than_printable_is_not_emitted():
    cp, sliver = sliver_sheet(1.3)
    params = FabricationParams()
    # at the smallest bias and margin the sliver would keep a PLA mid-layer 0.5 mm wide
    poly = cp.vertices[cp.faces[sliver]]
    inset = MIN_BIAS + MIN_MIDLAYER_BIAS
    crease = ~np.isin(cp.assignments[cp.face_edges[sliver]], ("B", "C"))
    thin = shapely.Polygon(offset_ring(poly, np.where(crease, inset, inset - MIN_BIAS)))
    assert 0.0 < 2 * thin.exterior.distance(polylabel(thin, 1e-6)) < MIN_PLA_WIDTH
    assert not panel_fits(
        cp, sliver, params, MIN_BIAS, auto_hole=False, shell=MIN_SHELL, midlayer_bias=0.2
    )
    plan = plan_panels(cp, params)
    assert plan.tpu_only == frozenset({sliver})
    (warning,) = [w for w in plan.warnings if "TPU alone" in w]
    assert cp.face_labels[sliver] in warning
    for o in plan.outlines:  # every mid-layer emitted holds a disc MIN_PLA_WIDTH wide
        if o.has_midlayer:
            assert not shapely.Polygon(o.midlayer).buffer(-MIN_PLA_WIDTH / 2 + 1e-6).is_empty


def test_a_panel_too_small_for_any_pla_is_printed_in_tpu_alone(tmp_path):
    cp, sliver = sliver_sheet(0.9)
    params = FabricationParams()
    label = cp.face_labels[sliver]
    with pytest.warns(UserWarning, match="TPU alone"):
        fab = fabricate(cp, params)
    plan = fab.plan
    assert plan.tpu_only == frozenset({sliver})
    o = plan.outlines[sliver]
    assert not o.has_infill and not o.has_midlayer and not o.region
    assert math.isnan(plan.shell_of(sliver)) and math.isnan(plan.midlayer_of(sliver))
    # the largest bias that keeps its halves: half the sliver, less a step
    assert plan.bias_of(sliver) == pytest.approx(0.44)
    # no PLA and no hole on it; its two halves are TPU, the crease sheet runs through it
    assert not _owned(fab, "infills", sliver) and not _owned(fab, "midlayers", sliver)
    assert all(i != sliver for i in plan.hole_panels.tolist())
    halves = _owned(fab, "shells", sliver)
    assert len(halves) == 2 and all(h.is_valid for h in halves)
    assert sum(h.volume for h in halves) == pytest.approx(
        sum(h.volume for h in fab.parts.halves[sliver]), rel=1e-9
    )
    (sheet,) = fab.parts.prisms["creases"]
    assert sheet[0].contains(shapely.Polygon(o.inner).buffer(-1e-6))
    # the square panels keep their PLA and holes
    for f in range(len(cp.faces)):
        if f != sliver:
            assert len(_owned(fab, "infills", f)) == 2 and len(_owned(fab, "midlayers", f)) == 1
    (warning,) = [w for w in plan.warnings if "TPU alone" in w]
    assert "1 of 3 panels" in warning and label in warning
    report = fab.report()
    assert report["panels_tpu_only"] == [label]
    assert report["panel_shell_mm"][label] is None
    assert report["panel_midlayer_bias_mm"][label] is None
    paths = write_fabrication(fab, tmp_path)
    _watertight(paths)
    on_disk = json.loads(paths["json"].read_text())
    assert on_disk["panels_tpu_only"] == [label] and on_disk["panel_shell_mm"][label] is None


def test_a_given_hole_on_a_tpu_panel_is_refused_naming_a_width_and_place_that_work():
    cp, sliver = sliver_sheet(0.9)
    params = FabricationParams(holes=[(40.45, 20.0)], hole_diameter=0.1)
    with pytest.raises(PatternError, match="no operation region") as info:
        plan_panels(cp, params)
    message = str(info.value)
    assert "\n" not in message and f"panel {cp.face_labels[sliver]}" in message
    found = re.search(r"at least ([\d.]+) mm wide.*hole at \(([-\d.]+), ([-\d.]+)\) mm", message)
    width, x, y = (float(g) for g in found.groups())
    x0, _, x1, _ = cp.bounds
    wide = plan_panels(cp.scaled(width / (x1 - x0)), replace(params, holes=[(x, y)]))
    assert sliver not in wide.tpu_only and wide.hole_panels.tolist() == [sliver]


def test_a_given_hole_outside_its_region_is_refused_naming_a_place_that_works():
    cp = miura_design(2, 3, 30.0, 30.0, 65.0).pattern
    with pytest.raises(PatternError, match="does not fit the operation region") as info:
        plan_panels(cp, FabricationParams(holes=[(15.0, 1.0)]))
    found = re.search(r"up to ([\d.]+) mm at \(([-\d.]+), ([-\d.]+)\) mm", str(info.value))
    room, x, y = (float(g) for g in found.groups())
    plan = plan_panels(cp, FabricationParams(holes=[(x, y)], hole_diameter=room))
    assert len(plan.holes) == 1


def test_a_panel_too_small_for_its_tpu_halves_is_refused_naming_a_width_that_works(
    tmp_path, capsys
):
    cp, sliver = sliver_sheet(0.3)
    with pytest.raises(PatternError, match="TPU alone") as info:
        plan_panels(cp)
    message = str(info.value)
    assert "\n" not in message and f"panel {cp.face_labels[sliver]}" in message
    width = float(re.search(r"at least ([\d.]+) mm wide", message).group(1))
    x0, _, x1, _ = cp.bounds
    assert width > x1 - x0
    # the command says so in one line, exit 2, nothing written
    path = tmp_path / "sliver.fold"
    write_pattern(cp, path)
    out = tmp_path / "fab"
    assert main(["fabricate", str(path), "-o", str(out)]) == 2
    err = [ln for ln in capsys.readouterr().err.splitlines() if "warning:" not in ln]
    assert len(err) == 1 and "TPU alone" in err[0] and f"{width:g} mm wide" in err[0]
    assert not out.exists()
    # at the width it names, the command prints it (the sliver in TPU alone at least)
    assert main(["fabricate", str(path), "-o", str(out), "--width", f"{width:g}"]) == 0
    report = json.loads((out / "fabrication.json").read_text())
    assert report["panel_bias_mm"][cp.face_labels[sliver]] >= MIN_BIAS


def test_a_sheet_whose_panels_fit_records_no_midlayers():
    cp, _ = sliver_sheet(4.0)
    plan = plan_panels(cp)
    assert plan.midlayers is None and not plan.tpu_only
    assert not any("mid-layer margin" in w or "TPU alone" in w for w in plan.warnings)
    assert all(o.midlayer_bias is None for o in plan.outlines)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["6ptHypar-anti.svg", "whirlpool.svg"])
def test_corpus_patterns_with_tiny_panels_fabricate_at_150_mm(name, tmp_path, capsys):
    from corpus import DATA

    out = tmp_path / "fab"
    path = DATA / "origami-simulator" / name
    assert main(["fabricate", str(path), "--width", "150", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    report = json.loads((out / "fabrication.json").read_text())
    narrowed = [k for k, m in report["panel_midlayer_bias_mm"].items() if m is not None and m < 0.5]
    assert narrowed and all(
        report["panel_midlayer_bias_mm"][k] >= MIN_MIDLAYER_BIAS for k in narrowed
    )
    assert "mid-layer margin" in err and narrowed[0] in err
    if report["panels_tpu_only"]:
        assert "TPU alone" in err and report["panels_tpu_only"][0] in err
    for name_ in PART_NAMES:
        mesh = trimesh.load(out / f"{name_}.stl")
        assert mesh.is_watertight and mesh.is_winding_consistent, name_
    assert (out / "print.3mf").stat().st_size > 0 and (out / "assembly.step").stat().st_size > 0


def test_a_pattern_whose_every_panel_is_tpu_only_is_refused_naming_a_width_that_works(tmp_path):
    # the FOLD project's diagonal-cp.fold read as 1 x 1 mm: both panels would be TPU alone
    from pathlib import Path

    from origami_cad.pattern.io import read_pattern

    cp = read_pattern(Path(__file__).parent / "data" / "fold" / "diagonal-cp.fold")
    with pytest.raises(PatternError, match="every panel is too small for a PLA infill") as info:
        plan_panels(cp)
    width = float(re.search(r"at least ([\d.]+) mm wide", str(info.value)).group(1))
    x0, _, x1, _ = cp.bounds
    plan = plan_panels(cp.scaled(width / (x1 - x0)))
    assert len(plan.tpu_only) < len(cp.faces)


def test_congruent_small_panels_get_the_biases_each_gets_alone():
    # the fitting searches once per panel shape; a rotated and moved copy gets the same
    from origami_cad.fabrication.fitting import panel_biases

    cp, sliver = sliver_sheet(1.2)
    alone = panel_biases(cp, FabricationParams())
    c, s = np.cos(np.radians(37.0)), np.sin(np.radians(37.0))
    turned = cp.vertices @ np.array([[c, s], [-s, c]]) + (200.0, -50.0)
    both = CreasePattern(
        np.vstack([cp.vertices, turned]),
        np.vstack([cp.edges, cp.edges + len(cp.vertices)]),
        np.concatenate([cp.assignments, cp.assignments]),
    )
    twice = panel_biases(both, FabricationParams())
    moved = both.face_of_point(*(turned[[1, 2, 6, 5]].mean(axis=0)))
    first = both.face_of_point(40.6, 20.0)
    assert alone.bias[sliver] < FabricationParams().bias
    assert twice.bias[first] == twice.bias[moved] == alone.bias[sliver]
