"""``print.3mf`` read as Bambu Studio and OrcaSlicer read it, by their importer's rules.

:func:`bbs_import` replays what ``_BBS_3MF_Importer::load_model_from_file`` of
``src/libslic3r/Format/bbs_3mf.cpp`` (bambulab/BambuStudio 0067891, SoftFever/OrcaSlicer
ba52cf4) does with the parts of a 3MF that decide what a user gets:

1. ``_rels/.rels``: the start part is the relationship whose ``Type`` starts with
   ``http://schemas.microsoft.com/3dmanufacturing/`` and ends with ``3dmodel``.
2. ``_handle_end_metadata``: ``Application`` starting with ``BambuStudio-`` (Orca: or
   ``OrcaSlicer-``) sets the generator version ``Semver::parse`` of the rest; without it
   ``dont_load_config = true`` and ``Metadata/project_settings.config`` is not read.
3. ``ConfigBase::load_from_json``: the project settings are JSON whose values are
   strings or arrays of strings (any other element fails the load).
4. ``_handle_start_config_object`` / ``_handle_start_config_volume``: in
   ``Metadata/model_settings.config`` an ``<object id>`` is a build item's object; a
   ``<part>`` with ``lastid > 0`` is a triangle range, any other names the sub-object
   ``id`` it carries.
5. ``_generate_current_object_list`` / ``_generate_volumes_new``: one volume per mesh
   object reached through ``<components>``; a volume takes the metadata (``name``,
   ``extruder``...) of the part whose id is its mesh object's, else none.
6. After loading: an object's ``extruder`` 0 or above ``len(filament_settings_id)``
   becomes 1; a volume's ``extruder`` above it becomes 1.
"""

from __future__ import annotations

import json
import math
import re
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest

from origami_cad.errors import FabricationError
from origami_cad.fabrication import FabricationParams, fabricate, write_fabrication
from origami_cad.fabrication.exports.threemf import export_3mf
from origami_cad.fabrication.slicer import EXTRUDERS
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES
from origami_cad.pattern.design import miura_design

NS = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}
BAMBU = ("BambuStudio-",)
ORCA = ("BambuStudio-", "OrcaSlicer-")
SEMVER = re.compile(r"^\d+\.\d+\.\d+(\.\d+)?$")


def _objects(model: ET.Element) -> dict[int, ET.Element]:
    return {int(o.get("id")): o for o in model.iterfind("m:resources/m:object", NS)}


def _mesh_volume(obj: ET.Element) -> float:
    verts = np.array([[float(v.get(k)) for k in "xyz"] for v in obj.iterfind(".//m:vertex", NS)])
    tris = np.array(
        [[int(t.get(k)) for k in ("v1", "v2", "v3")] for t in obj.iterfind(".//m:triangle", NS)]
    )
    a, b, c = verts[tris[:, 0]], verts[tris[:, 1]], verts[tris[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def _config_volumes(zf: zipfile.ZipFile, object_id: int) -> tuple[dict, list[dict]]:
    """Rule 4: the object's metadata and its volume entries."""
    if "Metadata/model_settings.config" not in zf.namelist():
        return {}, []
    config = ET.fromstring(zf.read("Metadata/model_settings.config"))
    for obj in config.findall("object"):
        if int(obj.get("id")) != object_id:
            continue
        meta = {m.get("key"): m.get("value") for m in obj.findall("metadata")}
        volumes = []
        for part in obj.findall("part"):
            last = int(part.get("lastid", "0") or 0)
            volumes.append(
                {
                    "subobject_id": -1 if last > 0 else int(part.get("id")),
                    "metadata": {m.get("key"): m.get("value") for m in part.findall("metadata")},
                }
            )
        return meta, volumes
    return {}, []


def _project_config(zf: zipfile.ZipFile, application: str, prefixes) -> dict | None:
    """Rules 2 and 3: the project settings, or None when the importer does not read them."""
    version = next((application[len(p) :] for p in prefixes if application.startswith(p)), None)
    if version is None or not SEMVER.match(version):
        return None  # dont_load_config
    config = json.loads(zf.read("Metadata/project_settings.config"))
    for key, value in config.items():
        assert isinstance(value, str) or (
            isinstance(value, list) and all(isinstance(v, str) for v in value)
        ), f"{key}: load_from_json fails on {value!r}"
    return config


def bbs_import(path, prefixes) -> tuple[list[dict], dict | None]:
    """What Bambu Studio (``prefixes=BAMBU``) or OrcaSlicer (``ORCA``) loads: volumes, config."""
    with zipfile.ZipFile(path) as zf:
        rels = ET.fromstring(zf.read("_rels/.rels"))
        start = next(
            r.get("Target")
            for r in rels
            if r.get("Type").startswith("http://schemas.microsoft.com/3dmanufacturing/")
            and r.get("Type").endswith("3dmodel")
        )
        model = ET.fromstring(zf.read(start.lstrip("/")))
        meta = {m.get("name"): (m.text or "") for m in model.findall("m:metadata", NS)}
        config = _project_config(zf, meta.get("Application", ""), prefixes)
        (item,) = model.iterfind("m:build/m:item", NS)
        object_id = int(item.get("objectid"))
        obj_meta, entries = _config_volumes(zf, object_id)
    objects = _objects(model)
    subs, queue = [], [object_id]  # rule 5: mesh objects reached through components
    while queue:
        obj = objects[queue.pop(0)]
        comps = obj.findall("m:components/m:component", NS)
        if comps:
            queue += [int(c.get("objectid")) for c in comps]
        elif obj.find("m:mesh", NS) is not None:
            subs.append(int(obj.get("id")))
    top = len(config.get("filament_settings_id", [])) if config else 0
    top = top or math.inf
    object_extruder = int(obj_meta.get("extruder", "0"))
    object_extruder = 1 if object_extruder == 0 or object_extruder > top else object_extruder
    volumes = []
    for index, sub in enumerate(subs):
        data = next((e for e in entries if e["subobject_id"] == sub), None)
        if index < len(entries) and entries[index]["subobject_id"] == sub:
            data = entries[index]
        md = data["metadata"] if data else {}
        extruder = int(md.get("extruder", object_extruder))  # rule 6
        extruder = 1 if extruder > top else extruder
        volume = _mesh_volume(objects[sub])
        volumes.append({"name": md.get("name"), "extruder": extruder, "volume": volume})
    return volumes, config


@pytest.fixture(scope="module")
def fab():
    return fabricate(miura_design(2, 3, 30.0, 30.0, 65.0), FabricationParams())


@pytest.fixture(scope="module")
def flavours(fab, tmp_path_factory):
    folder = tmp_path_factory.mktemp("flavours")
    return {
        s: export_3mf(fab.parts, folder / f"{s}.3mf", params=fab.params, slicer=s)
        for s in ("prusa", "bambu", "orca")
    }


@pytest.mark.parametrize("slicer, prefixes", [("bambu", BAMBU), ("orca", ORCA)])
def test_each_part_on_its_filament_with_the_print_settings(fab, flavours, slicer, prefixes):
    volumes, config = bbs_import(flavours[slicer], prefixes)
    assert [v["name"] for v in volumes] == list(PART_NAMES)
    for v in volumes:  # PLA on filament 1, TPU on filament 2
        assert v["extruder"] == EXTRUDERS[PART_MATERIALS[v["name"]]], v["name"]
    expected = fab.volumes()
    for v in volumes:  # the mesh of each part is that part, outward
        assert v["volume"] == pytest.approx(expected[v["name"]], rel=2e-3), v["name"]
    assert config is not None, "the importer would not read project_settings.config"
    assert config["name"] == "project_settings"
    assert float(config["layer_height"]) == 0.1
    assert float(config["initial_layer_print_height"]) == 0.1
    assert config["filament_settings_id"] == ["origami_cad PLA", "origami_cad TPU"]
    assert config["filament_type"] == ["PLA", "TPU"]
    assert config["nozzle_temperature"] == ["210", "230"]
    assert config["nozzle_temperature_initial_layer"] == ["215", "230"]
    assert config["filament_max_volumetric_speed"] == ["15", "3.6"]  # the TPU's limit
    assert config["hot_plate_temp"] == ["60", "60"]


def test_file_names_and_application_of_each_flavour(flavours):
    for slicer, prefix in (("bambu", "BambuStudio-"), ("orca", "OrcaSlicer-")):
        with zipfile.ZipFile(flavours[slicer]) as zf:
            names = set(zf.namelist())
            model = ET.fromstring(zf.read("3D/3dmodel.model"))
        assert {
            "[Content_Types].xml",
            "_rels/.rels",
            "3D/3dmodel.model",
            "Metadata/model_settings.config",
            "Metadata/project_settings.config",
        } == names
        (app,) = [m.text for m in model.findall("m:metadata", NS) if m.get("name") == "Application"]
        assert app.startswith(prefix) and SEMVER.match(app[len(prefix) :]), app


def test_orca_flavour_is_for_orca_and_bambu_flavour_reads_in_both(flavours):
    # Bambu Studio's importer knows only "BambuStudio-": the orca flavour's settings are lost there
    assert bbs_import(flavours["orca"], BAMBU)[1] is None
    assert bbs_import(flavours["bambu"], ORCA)[1] is not None


def test_the_prusa_flavour_in_bambu_and_orca_is_one_volume_without_settings(flavours):
    """Why the flavours exist: the PrusaSlicer layout loses the parts and the settings there."""
    for prefixes in (BAMBU, ORCA):
        volumes, config = bbs_import(flavours["prusa"], prefixes)
        assert config is None  # Application "origami_cad ..." fails the prefix test
        assert len(volumes) == 1 and volumes[0]["name"] is None  # triangle ranges unread
        assert volumes[0]["extruder"] == 1  # everything on filament 1


def test_write_fabrication_chooses_the_flavour_and_refuses_an_unknown_one(fab, tmp_path):
    path = write_fabrication(fab, tmp_path / "bambu", slicer="bambu")["3mf"]
    assert bbs_import(path, BAMBU)[1] is not None
    with pytest.raises(FabricationError, match="prusa, bambu, orca"):
        write_fabrication(fab, tmp_path / "x", slicer="cura")
    with pytest.raises(FabricationError, match="prusa, bambu, orca"):
        export_3mf(fab.parts, tmp_path / "x.3mf", slicer="cura")
    assert not (tmp_path / "x.3mf").exists()


def test_write_fabrication_leaves_the_fabrication_as_it_was(fab, tmp_path):
    """The slicer and the export times are the call's: the next write is unchanged by it."""
    import json

    slicer, timings = fab.slicer, dict(fab.timings)
    bambu = write_fabrication(fab, tmp_path / "bambu", slicer="bambu")
    assert fab.slicer == slicer == "prusa" and fab.timings == timings  # nothing changed
    assert bambu.slicer == "bambu" and list(bambu.timings) == ["stl", "step", "3mf"]
    assert all(t > 0 for t in bambu.timings.values())
    report = json.loads(bambu["json"].read_text())
    assert report["timings_s"] == {**timings, **bambu.timings}  # build and export times
    again = write_fabrication(fab, tmp_path / "again")  # the default layout, not bambu's
    assert again.slicer == "prusa" and bbs_import(again["3mf"], BAMBU)[1] is None
    assert bbs_import(bambu["3mf"], BAMBU)[1] is not None
    assert set(again) == set(bambu) and all(again[k].parent == tmp_path / "again" for k in again)
