"""The 3MF read back as slicers read it: lib3mf (strict), PrusaSlicer, Bambu Studio, Orca.

- lib3mf in strict mode: every mesh object of every flavour valid, manifold and oriented;
- PrusaSlicer's ``Slic3r_PE_model.config``: the triangle ranges tile the object, each
  part on its material's extruder; its CLI (when installed): ``--info`` and
  ``--export-gcode`` honour the parts, the extruders and the settings carried in the file;
- Bambu Studio / OrcaSlicer: see ``tests/test_clients_bambu.py`` (their importer's rules).
"""

from __future__ import annotations

import itertools
import json
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import lib3mf
import numpy as np
import pytest

from origami_cad.fabrication import FabricationParams, fabricate
from origami_cad.fabrication.exports.threemf import export_3mf
from origami_cad.fabrication.slicer import EXTRUDERS, SLICERS, layer_height, slicer_settings
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES
from origami_cad.pattern.design import miura_design

NS = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}
PRUSA = shutil.which("prusa-slicer") or shutil.which("PrusaSlicer")


@pytest.fixture(scope="module")
def fab():
    return fabricate(miura_design(2, 3, 30.0, 30.0, 65.0), FabricationParams())


@pytest.fixture(scope="module")
def three_mf(fab, tmp_path_factory):
    return export_3mf(fab.parts, tmp_path_factory.mktemp("3mf") / "print.3mf", params=fab.params)


@pytest.mark.parametrize("slicer", SLICERS)
def test_lib3mf_strict_every_mesh_object_is_valid_manifold_and_oriented(fab, slicer, tmp_path):
    path = export_3mf(fab.parts, tmp_path / "print.3mf", params=fab.params, slicer=slicer)
    wrapper = lib3mf.get_wrapper()
    model = wrapper.CreateModel()
    reader = model.QueryReader("3mf")
    reader.SetStrictModeActive(True)
    reader.ReadFromFile(str(path))
    assert reader.GetWarningCount() == 0
    objects = model.GetMeshObjects()
    count = 0
    while objects.MoveNext():
        obj = objects.GetCurrentMeshObject()
        assert obj.IsValid(), obj.GetName()
        assert obj.IsManifoldAndOriented(), obj.GetName()
        count += 1
    assert count >= 1


def _mesh_of(model_xml, object_id: str) -> tuple[np.ndarray, np.ndarray]:
    obj = model_xml.find(f".//m:object[@id='{object_id}']", NS)
    verts = np.array([[float(v.get(k)) for k in "xyz"] for v in obj.iterfind(".//m:vertex", NS)])
    tris = np.array(
        [[int(t.get(k)) for k in ("v1", "v2", "v3")] for t in obj.iterfind(".//m:triangle", NS)]
    )
    return verts, tris


def _edge_uses(tris: np.ndarray) -> np.ndarray:
    edges = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return counts


def test_prusa_model_config_ranges_tile_the_object(three_mf, fab):
    """PrusaSlicer's ``Slic3r_PE_model.config``: each ``<volume>`` a triangle range."""
    with zipfile.ZipFile(three_mf) as zf:
        config = ET.fromstring(zf.read("Metadata/Slic3r_PE_model.config"))
        model_xml = ET.fromstring(zf.read("3D/3dmodel.model"))
    objects = config.findall("object")
    assert len(objects) == 1
    _, tris = _mesh_of(model_xml, objects[0].get("id"))  # the config's object is a mesh object
    parts = []
    for volume in objects[0].findall("volume"):
        meta = {m.get("key"): m.get("value") for m in volume.findall("metadata")}
        parts.append((int(volume.get("firstid")), int(volume.get("lastid")), meta))
    assert [m["name"] for _, _, m in parts] == list(PART_NAMES)
    for _, _, meta in parts:
        assert meta["extruder"] == str(EXTRUDERS[PART_MATERIALS[meta["name"]]])
    # the ranges tile the object's triangles, in order, without overlap
    assert parts[0][0] == 0 and parts[-1][1] == len(tris) - 1
    for (_, last, _), (first, _, _) in itertools.pairwise(parts):
        assert first == last + 1
    # each part's triangles form closed, oriented shells (every edge used twice)
    for first, last, meta in parts:
        sub = tris[first : last + 1]
        assert set(np.unique(_edge_uses(sub))) == {2}, meta["name"]
        assert len(np.intersect1d(sub.ravel(), np.delete(tris, np.s_[first : last + 1], 0))) == 0


def test_no_edge_is_shared_by_more_than_two_triangles(three_mf):
    """Each object's mesh is closed and its own: every edge is used by exactly two triangles
    (shells welded across solids shared edges among four)."""
    with zipfile.ZipFile(three_mf) as zf:
        model_xml = ET.fromstring(zf.read("3D/3dmodel.model"))
    for obj in model_xml.iterfind(".//m:object", NS):
        _, tris = _mesh_of(model_xml, obj.get("id"))
        assert set(np.unique(_edge_uses(tris))) == {2}


def test_slicer_settings_in_the_3mf(three_mf, fab):
    settings = slicer_settings(fab.params)
    with zipfile.ZipFile(three_mf) as zf:
        prusa = zf.read("Metadata/Slic3r_PE.config").decode()
        bambu = json.loads(zf.read("Metadata/project_settings.config"))
    keys = dict(re.findall(r"^; (\w+) = (.*)$", prusa, flags=re.M))
    assert keys["temperature"] == "210,230" and keys["filament_type"] == "PLA;FLEX"
    assert float(keys["layer_height"]) == settings["layer_height"] == 0.1
    assert bambu["nozzle_temperature"] == ["210", "230"]
    assert bambu["filament_type"] == ["PLA", "TPU"]
    assert float(bambu["layer_height"]) == 0.1
    # the layer height resolves the panel halves, the crease layer and the shell
    p = fab.params
    for z in (p.half_height, p.thickness, p.shell):
        assert z / settings["layer_height"] == pytest.approx(round(z / settings["layer_height"]))


@pytest.mark.parametrize(
    "kwargs, expected",
    [
        ({}, 0.1),  # halves 0.9, crease 0.4, shell 0.8
        ({"height": 2.4, "thickness": 0.4, "shell": 0.6}, 0.2),  # halves 1.0
        ({"height": 2.0, "thickness": 0.3, "shell": 0.5}, 0.05),  # halves 0.85
        ({"height": 3.0, "thickness": 0.6, "shell": 0.6}, 0.2),  # halves 1.2
    ],
)
def test_layer_height_resolves_every_layer(kwargs, expected):
    assert layer_height(FabricationParams(**kwargs)) == pytest.approx(expected)


def _prusa(*args: str, cwd: Path) -> str:
    run = subprocess.run(
        [PRUSA, *args], cwd=cwd, capture_output=True, text=True, timeout=600, check=False
    )
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    return run.stdout


@pytest.mark.skipif(PRUSA is None, reason="PrusaSlicer's CLI is not installed (apt prusa-slicer)")
def test_prusaslicer_reads_and_slices_the_3mf_with_its_settings(three_mf, fab, tmp_path):
    info = _prusa("--info", str(three_mf), cwd=tmp_path)
    values = dict(re.findall(r"^(\w+) = +(.*)$", info, flags=re.M))
    assert values["manifold"] == "yes"
    assert float(values["min_z"]) == pytest.approx(0.0, abs=1e-6)
    assert float(values["max_z"]) == pytest.approx(fab.params.height, abs=1e-4)
    total = sum(fab.volumes().values())
    assert float(values["volume"]) == pytest.approx(total, rel=2e-3)
    gcode = tmp_path / "print.gcode"
    _prusa("--export-gcode", str(three_mf), "-o", str(gcode), cwd=tmp_path)
    text = gcode.read_text()
    config = dict(re.findall(r"^; (\w+) = (.*)$", text, flags=re.M))
    assert config["layer_height"] == "0.1" and config["first_layer_height"] == "0.1"
    assert config["temperature"] == "210,230"
    assert config["first_layer_temperature"] == "215,230"
    assert config["filament_type"] == "PLA;FLEX"
    assert re.search(r"^M109 S230 T1", text, flags=re.M)  # TPU heated on extruder 2
    assert re.search(r"^M109 S215 T0", text, flags=re.M)  # PLA first layer on extruder 1
    # both extruders print: moves that extrude follow a T0 and a T1
    tools = re.findall(r"^(T[01])\s*$|^G1 [^;\n]*E(\d*\.?\d+)", text, flags=re.M)
    used, current = set(), "T0"
    for tool, extrusion in tools:
        if tool:
            current = tool
        elif extrusion and float(extrusion) > 0:
            used.add(current)
    assert used == {"T0", "T1"}
    heights = [float(z) for z in re.findall(r"^;Z:(\d*\.?\d+)", text, flags=re.M)]
    assert max(heights) == pytest.approx(fab.params.height, abs=1e-6)
    assert np.allclose(np.round(np.array(heights) / 0.1) * 0.1, heights, atol=1e-6)


@pytest.mark.skipif(PRUSA is None, reason="PrusaSlicer's CLI is not installed (apt prusa-slicer)")
def test_prusaslicer_finds_every_part_on_the_bed_and_manifold(tmp_path):
    """``origami-cad part`` files: PrusaSlicer reads each closed, with its lowest point at z = 0."""
    from origami_cad.parts import PARTS, build_part

    from origami_cad.fabrication.exports import export_part

    stls = []
    for name in PARTS:
        shape = build_part(name)
        _, stl = export_part(shape, tmp_path / name, name)
        stls.append((name, stl, shape.volume, len(shape.solids())))
    info = _prusa("--info", *(str(s) for _, s, _, _ in stls), cwd=tmp_path)
    blocks = dict(re.findall(r"^\[(.+?)\.stl\]\n((?:.+\n?)+?)(?=^\[|\Z)", info, flags=re.M))
    for name, _, volume, solids in stls:
        values = dict(re.findall(r"^(\w+) = +(.*)$", blocks[name], flags=re.M))
        assert float(values["min_z"]) == pytest.approx(0.0, abs=1e-6), name
        assert values["manifold"] == "yes", name
        assert int(values["number_of_parts"]) == solids, name
        assert float(values["volume"]) == pytest.approx(volume, rel=5e-3), name


def test_a_sheet_larger_than_the_default_bed_is_warned_about():
    from origami_cad.fabrication import plan_panels
    from origami_cad.pattern.design import miura_design

    small = plan_panels(miura_design(4, 4, 20.0, 20.0, 65.0))  # about 100 mm
    assert not any("bed" in w for w in small.warnings)
    large = plan_panels(miura_design(4, 12, 20.0, 20.0, 65.0))  # about 250 mm long
    (warning,) = [w for w in large.warnings if "bed" in w]
    x0, y0, x1, y1 = large.pattern.bounds
    assert f"{x1 - x0:.1f} x {y1 - y0:.1f} mm" in warning and "200 x 200" in warning


@pytest.mark.skipif(PRUSA is None, reason="PrusaSlicer's CLI is not installed (apt prusa-slicer)")
def test_prusaslicer_slices_a_large_sheet_on_a_bed_that_holds_it(tmp_path):
    # what the warning says: the 3MF is sound, only PrusaSlicer's default bed is too small
    from origami_cad.fabrication import FabricationParams, fabricate
    from origami_cad.fabrication.exports.threemf import export_3mf
    from origami_cad.pattern.design import miura_design

    fab = fabricate(miura_design(2, 10, 22.0, 20.0, 65.0), FabricationParams(holes="none"))
    x0, _, x1, _ = fab.plan.pattern.bounds
    assert x1 - x0 > 200.0
    path = export_3mf(fab.parts, tmp_path / "print.3mf", params=fab.params)
    failed = subprocess.run(
        [PRUSA, "--export-gcode", str(path), "-o", str(tmp_path / "a.gcode")],
        cwd=tmp_path, capture_output=True, text=True, timeout=600, check=False,
    )  # fmt: skip
    assert failed.returncode != 0 and "could not fit on the bed" in failed.stdout + failed.stderr
    bed = "0x0,300x0,300x300,0x300"
    _prusa("--export-gcode", "--bed-shape", bed, str(path), "-o", "b.gcode", cwd=tmp_path)
    assert (tmp_path / "b.gcode").stat().st_size > 10_000
