"""The printed mass from the print settings the 3MF carries.

The estimate (``origami_cad.fabrication.printmass``) against geometry worked by hand,
against the settings written into ``print.3mf``, and against PrusaSlicer's own
``filament used [g]`` for the same 3MF (when ``prusa-slicer`` is installed).
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import zipfile

import numpy as np
import pytest

from origami_cad.errors import FabricationError
from origami_cad.fabrication import FabricationParams, fabricate
from origami_cad.fabrication.exports.threemf import export_3mf
from origami_cad.fabrication.printmass import (
    mesh_print_areas,
    print_volume,
    printed_mass,
    sheet_print_mass,
)
from origami_cad.fabrication.slicer import PRINT_SETTINGS, slicer_settings
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES
from origami_cad.pattern.design import miura_design

PRUSA = shutil.which("prusa-slicer") or shutil.which("PrusaSlicer")


def _box(dx: float, dy: float, dz: float):
    v = np.array([[x, y, z] for x in (0, dx) for y in (0, dy) for z in (0, dz)], dtype=float)
    t = np.array(
        [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
         [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]
    )  # fmt: skip
    return v, t


@pytest.fixture(scope="module")
def fab():
    return fabricate(miura_design(2, 3, 30.0, 30.0, 65.0), FabricationParams())


@pytest.mark.parametrize("size", [(10.0, 20.0, 2.0), (3.0, 7.0, 11.0)])
def test_mesh_areas_of_a_box(size):
    dx, dy, dz = size
    areas = mesh_print_areas(*_box(dx, dy, dz))
    assert areas["volume_mm3"] == pytest.approx(dx * dy * dz)
    assert areas["side_mm2"] == pytest.approx(2 * (dx + dy) * dz)
    assert areas["top_mm2"] == pytest.approx(dx * dy)
    assert areas["bottom_mm2"] == pytest.approx(dx * dy)


def test_a_chamfer_counts_as_side_and_skin():
    # a wedge: the sloped face (45 deg) is seen from the side and from above
    v = np.array([[0, 0, 0], [10, 0, 0], [0, 5, 0], [10, 5, 0], [0, 0, 5], [10, 0, 5]], float)
    t = np.array([[0, 2, 3], [0, 3, 1], [0, 1, 5], [0, 5, 4], [2, 4, 5], [2, 5, 3],
                  [0, 4, 2], [1, 3, 5]])  # fmt: skip
    areas = mesh_print_areas(v, t)
    assert areas["volume_mm3"] == pytest.approx(125.0)
    assert areas["top_mm2"] == pytest.approx(50.0) and areas["bottom_mm2"] == pytest.approx(50.0)
    assert areas["side_mm2"] == pytest.approx(50.0 + 50.0 + 2 * 12.5)


def test_print_volume_follows_the_settings():
    s = slicer_settings()
    volume, side, top, bottom = 400.0, 120.0, 200.0, 200.0
    solid = print_volume(volume, side, top, bottom, {**s, "fill_density": 1.0})
    empty = print_volume(volume, side, top, bottom, {**s, "fill_density": 0.0})
    h, layers = s["layer_height"], s["top_solid_layers"] + s["bottom_solid_layers"]
    bead = s["extrusion_width"] - h * (1 - np.pi / 4)  # a bead's cross-section / h
    walls = s["perimeters"] * bead * side * (1 - layers * h / (volume / top))
    shell = walls + h * (s["top_solid_layers"] * top + s["bottom_solid_layers"] * bottom)
    assert solid == pytest.approx(volume) and empty == pytest.approx(shell)
    half = print_volume(volume, side, top, bottom, {**s, "fill_density": 0.5})
    assert half == pytest.approx((solid + empty) / 2)
    more = print_volume(volume, side, top, bottom, {**s, "perimeters": s["perimeters"] + 1})
    assert more > print_volume(volume, side, top, bottom, s)
    # a part thinner than its walls and skins is printed solid, never more
    assert print_volume(10.0, 100.0, 50.0, 50.0, s) == pytest.approx(10.0)


def test_printed_mass_is_grams_per_material(fab):
    from origami_cad.fabrication.meshing import part_meshes
    from origami_cad.fabrication.params import DENSITY_G_CM3

    s = slicer_settings(fab.params, {"fill_density": 1.0})
    grams = sheet_print_mass(fab, s)
    solid = {m: 0.0 for m in grams}
    for n in PART_NAMES:
        solid[PART_MATERIALS[n]] += fab.parts.volume(n) / 1000.0 * DENSITY_G_CM3[PART_MATERIALS[n]]
    for m in grams:  # at 100 % infill the print is the solid (meshed at 1e-3 relative)
        assert grams[m] == pytest.approx(solid[m], rel=5e-3)
    sparse = sheet_print_mass(fab)
    assert all(sparse[m] <= grams[m] + 1e-9 for m in grams)
    assert sum(sparse.values()) < sum(grams.values())
    # a build123d solid and its mesh give the same grams
    one = fab.parts.solids["shells"][0]
    mesh = part_meshes(fab.parts, "shells")[0]
    assert printed_mass({"TPU": [one]})["TPU"] == pytest.approx(
        printed_mass({"TPU": [mesh]})["TPU"], rel=1e-9
    )


def test_fabrication_json_reports_the_solid_and_the_printed_mass(fab, tmp_path):
    """fabrication.json: total_mass_g the solid mass (unchanged), printed_mass_g the mass
    as printed with the 3MF's settings, the sheet's figure in robot.json."""
    from origami_cad.fabrication import write_fabrication
    from origami_cad.fabrication.params import DENSITY_G_CM3

    report = json.loads(write_fabrication(fab, tmp_path)["json"].read_text(encoding="utf-8"))
    solid = sum(fab.parts.volume(n) / 1000 * DENSITY_G_CM3[PART_MATERIALS[n]] for n in PART_NAMES)
    assert report["total_mass_g"] == pytest.approx(solid, rel=1e-12)
    printed = sum(sheet_print_mass(fab).values())
    assert report["printed_mass_g"] == pytest.approx(printed, rel=1e-12)
    parts = report["parts"].values()
    assert sum(p["printed_mass_g"] for p in parts) == pytest.approx(printed, rel=1e-12)
    assert all(p["printed_mass_g"] <= p["mass_g"] * (1 + 5e-3) for p in parts)  # meshed
    assert report["printed_mass_g"] < report["total_mass_g"]  # sparse infill


def test_slicer_settings_refuse_an_unknown_setting_or_a_bad_fraction():
    with pytest.raises(FabricationError, match=r"unknown print setting.*walls"):
        slicer_settings(print_settings={"walls": 3})
    with pytest.raises(FabricationError, match="fill_density"):
        slicer_settings(print_settings={"fill_density": 15})


@pytest.mark.parametrize("slicer", ["prusa", "bambu"])
def test_the_3mf_carries_the_settings_of_the_estimate(fab, slicer, tmp_path):
    overrides = {"perimeters": 3, "top_solid_layers": 4, "fill_density": 0.35}
    path = export_3mf(
        fab.parts, tmp_path / "p.3mf", params=fab.params, slicer=slicer, print_settings=overrides
    )
    s = slicer_settings(fab.params, overrides)
    with zipfile.ZipFile(path) as zf:
        bambu = json.loads(zf.read("Metadata/project_settings.config"))
        prusa = zf.read("Metadata/Slic3r_PE.config").decode() if slicer == "prusa" else None
    assert bambu["wall_loops"] == "3" and bambu["top_shell_layers"] == "4"
    assert bambu["bottom_shell_layers"] == str(PRINT_SETTINGS["bottom_solid_layers"])
    assert bambu["sparse_infill_density"] == "35%"
    assert float(bambu["line_width"]) == s["extrusion_width"]
    if prusa is not None:
        keys = dict(re.findall(r"^; (\w+) = (.*)$", prusa, flags=re.M))
        assert keys["perimeters"] == "3" and keys["top_solid_layers"] == "4"
        assert keys["fill_density"] == "35%" and keys["interface_shells"] == "1"
        assert [float(x) for x in keys["filament_density"].split(",")] == s["filament_density"]


def _prusa_grams(path, cwd) -> list[float]:
    gcode = cwd / "print.gcode"
    run = subprocess.run(
        [PRUSA, "--export-gcode", str(path), "-o", str(gcode)],
        cwd=cwd, capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    (line,) = re.findall(r"^; filament used \[g\] = (.*)$", gcode.read_text(), flags=re.M)
    return [float(x) for x in line.split(",")]


@pytest.mark.skipif(PRUSA is None, reason="PrusaSlicer's CLI is not installed (apt prusa-slicer)")
@pytest.mark.parametrize(
    "overrides", [{}, {"fill_density": 0.6, "top_solid_layers": 2, "perimeters": 3}]
)
def test_estimate_within_10_percent_of_prusaslicer(fab, overrides, tmp_path):
    """PrusaSlicer slices the 3MF with the settings it carries; its grams per extruder."""
    path = export_3mf(fab.parts, tmp_path / "p.3mf", params=fab.params, print_settings=overrides)
    s = slicer_settings(fab.params, overrides)
    estimate = sheet_print_mass(fab, s)
    sliced = dict(zip(s["materials"], _prusa_grams(path, tmp_path), strict=True))
    for material, grams in sliced.items():
        assert estimate[material] == pytest.approx(grams, rel=0.10), (material, estimate, sliced)
    assert sum(estimate.values()) == pytest.approx(sum(sliced.values()), rel=0.10)
