"""No writer of the package puts NaN or infinity into a file: each JSON, TOML, XML, 3MF
and glTF writer, handed a record with one non-finite number (a bug upstream, or a
script's value), raises its stage's error naming the key, and writes nothing; handed a
good record, its file reads back through its reader as the same values.

The records are poisoned after they were made (``object.__setattr__`` on a frozen
dataclass, an array's item): what a reader or a constructor refuses must still never
reach a file by another way."""

from __future__ import annotations

import dataclasses
import json
import math
import struct
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest

from origami_cad._toml import finite_toml, json_text, toml_table
from origami_cad.crawler.robot import dump_robot, load_robot
from origami_cad.design.task import dump_task, load_task
from origami_cad.drive.sequence import dump_sequence, load_sequence
from origami_cad.errors import (
    DesignError,
    DriveError,
    FabricationError,
    PatternError,
    SimulationError,
    StringsError,
)
from origami_cad.pattern.design import dump_design, load_design, load_pattern_source
from origami_cad.pattern.formats.fold import read_fold, write_fold
from origami_cad.simulation.materials import dump_materials, load_materials, parse_materials
from origami_cad.strings.route import dump_route, load_route
from origami_cad.viz.gltf import folding_meshes, write_glb

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
NAN, INF = float("nan"), float("inf")


def poison(record, key: str, value: float):
    """A copy of the frozen dataclass ``record`` with ``key`` set, past its checks."""
    copy = dataclasses.replace(record)
    object.__setattr__(copy, key, value)
    return copy


# ------------------------------------------------------------------------ the helpers


@pytest.mark.parametrize("bad", [NAN, INF, -INF, np.float32("nan"), np.array([1.0, INF])])
def test_json_text_names_the_key_path_of_a_non_finite_number(bad):
    data = {"run": {"turns": [0.0, 1.5, {"peak": bad}]}, "name": "x"}
    with pytest.raises(SimulationError, match=r"out\.json: run\.turns\[2\]\.peak"):
        json_text(data, "out.json", SimulationError)


def test_json_text_round_trips_finite_values_and_numpy_numbers():
    data = {"a": [1.0, -0.0, 1e300, 5e-324], "b": np.arange(3.0), "c": np.float64(2.5), "d": None}
    back = json.loads(json_text(data, "x.json", indent=1))
    assert back == {"a": [1.0, -0.0, 1e300, 5e-324], "b": [0.0, 1.0, 2.0], "c": 2.5, "d": None}
    with pytest.raises(DesignError, match="cannot hold"):
        json_text({"a": object()}, "x.json")


def test_toml_writers_spell_non_finite_numbers_then_finite_toml_refuses_them():
    text = "\n".join(toml_table("route", {"step": 20.0, "limits": [1.0, -INF]})) + "\n"
    assert "-inf" in text  # TOML's own spelling, which the readers refuse
    with pytest.raises(StringsError, match=r"r\.toml: route\.limits\[1\] is -inf"):
        finite_toml(text, "r.toml", StringsError)
    good = "\n".join(toml_table("route", {"step": 20.0, "limits": [1.0, 2.0]})) + "\n"
    assert finite_toml(good, "r.toml") == good


# ------------------------------------------------------------------------ TOML files


def test_the_sequence_writer_refuses_a_nan_rate_and_a_nan_keyframe():
    seq = load_sequence(EXAMPLES / "arm_fold.toml")
    with pytest.raises(DriveError, match=r"sequence\.rate is nan"):
        dump_sequence(poison(seq, "rate", NAN))
    frame = poison(seq.keyframes[1], "t", INF)
    with pytest.raises(DriveError, match=r"keyframe\[1\]\.t is inf"):
        dump_sequence(poison(seq, "keyframes", (seq.keyframes[0], frame, *seq.keyframes[2:])))


def test_the_route_writer_refuses_a_nan_thickness_and_an_infinite_tsa_length():
    cp = load_pattern_source(EXAMPLES / "miura_6x4.toml").pattern
    spec = load_route(EXAMPLES / "miura_route.toml", cp)
    with pytest.raises(StringsError, match=r"route\.thickness is nan"):
        dump_route(poison(spec, "thickness", NAN), cp)
    tsa = poison(spec.tsa, "max_helix_angle", INF)
    with pytest.raises(StringsError, match=r"tsa\.max_helix_angle is inf"):
        dump_route(poison(spec, "tsa", tsa), cp)


def test_the_robot_writer_refuses_a_nan_friction_and_a_nan_gait(tmp_path):
    robot = load_robot(EXAMPLES / "crawler" / "crawler.toml")
    with pytest.raises(SimulationError, match=r"robot\.friction is nan"):
        dump_robot(poison(robot, "friction", NAN), tmp_path)
    gait = np.array(robot.gait_p, dtype=float)
    gait[2, 1] = NAN
    with pytest.raises(SimulationError, match=r"gait\.keyframe\[2\]\.p\[1\] is nan"):
        dump_robot(poison(robot, "gait_p", gait), tmp_path)


def test_the_task_design_and_materials_writers_refuse_nan(tmp_path):
    task, settings = load_task(EXAMPLES / "arm_task.toml")
    with pytest.raises(DesignError, match=r"is nan; the file holds finite numbers only"):
        dump_task(poison(task, "alpha", NAN), settings)
    tg = load_design(EXAMPLES / "fig2_tg.toml").tg
    with pytest.raises(DesignError, match=r"pattern\.shape_angles\[0\] is nan"):
        dump_design(poison(tg, "shape_angles", (NAN, *tg.shape_angles[1:])))
    m = load_materials(EXAMPLES / "materials.toml")
    with pytest.raises(SimulationError, match=r"materials file: crease\.modulus is nan"):
        dump_materials(poison(m, "crease_modulus", NAN))


def test_the_materials_file_round_trips():
    m = load_materials(EXAMPLES / "materials.toml")
    assert parse_materials(dump_materials(m)) == m


# ------------------------------------------------------------------------ JSON files


def test_write_fold_refuses_nan_in_a_frame_and_round_trips_a_good_one(tmp_path):
    cp = load_design(EXAMPLES / "miura_6x4.toml").pattern
    frame = {"frame_classes": ["foldedForm"], "vertices_coords": [[0.5, 1.0, 2.0]]}
    path = write_fold(cp, tmp_path / "p.fold", frames=[frame])
    back = read_fold(path)  # FOLD keeps 12 decimals of a mm
    np.testing.assert_allclose(back.vertices, cp.vertices, rtol=0, atol=1e-11)
    assert json.loads(path.read_text())["file_frames"][0]["vertices_coords"] == [[0.5, 1.0, 2.0]]
    with pytest.raises(PatternError, match="NaN"):
        write_fold(cp, tmp_path / "q.fold", frames=[{"vertices_coords": [[NAN, 0, 0]]}])
    assert not (tmp_path / "q.fold").exists()


def test_a_glb_with_a_nan_coordinate_is_refused_and_a_good_one_reads_back(tmp_path):
    cp = load_design(EXAMPLES / "miura_6x4.toml").pattern
    flat = np.column_stack([cp.vertices, np.zeros(len(cp.vertices))])
    path = write_glb(tmp_path / "a.glb", folding_meshes(cp, [flat]))
    data = path.read_bytes()
    (length,) = struct.unpack_from("<I", data, 12)
    doc = json.loads(data[20 : 20 + length])  # strict JSON: a bare NaN would not parse
    position = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    assert all(math.isfinite(v) for v in position["min"] + position["max"])
    bad = flat.copy()
    bad[3, 2] = NAN
    with pytest.raises(PatternError, match="is nan; JSON holds finite numbers only"):
        write_glb(tmp_path / "b.glb", folding_meshes(cp, [bad]))
    assert not (tmp_path / "b.glb").exists()


# ------------------------------------------------------------------------ XML files


def test_the_mjcf_writer_reads_back_finite_and_refuses_nan(tmp_path):
    pytest.importorskip("build123d")
    from origami_cad.simulation.mjcf import to_mjcf

    xml = to_mjcf(EXAMPLES / "miura_6x4.toml")
    root = ET.fromstring(xml)
    numbers = [
        float(x)
        for el in root.iter()
        for key, value in el.attrib.items()
        if key in ("pos", "size", "timestep", "gravity", "mass", "range", "damping")
        for x in value.split()
    ]
    assert numbers and all(math.isfinite(v) for v in numbers)
    with pytest.raises(SimulationError, match="gravity"):
        to_mjcf(EXAMPLES / "miura_6x4.toml", gravity=NAN)


def test_the_3mf_is_finite_xml_and_fabrication_json_refuses_nan(tmp_path, small_miura_toml):
    from origami_cad.fabrication import build_fabrication, plan_panels
    from origami_cad.fabrication.exports.threemf import export_3mf

    fab = build_fabrication(plan_panels(load_design(small_miura_toml)))
    path = export_3mf(fab.parts, tmp_path / "print.3mf")
    with zipfile.ZipFile(path) as z:
        model = z.read("3D/3dmodel.model").decode()
    assert "nan" not in model.lower() and "inf" not in model.lower().replace("info", "")
    ET.fromstring(model)  # well-formed
    json_back = json.loads(json_text(fab.report(), "fabrication.json", FabricationError))
    assert json_back == json.loads(json.dumps(fab.report()))
    fab.timings["3mf"] = NAN
    with pytest.raises(FabricationError, match=r"fabrication\.json: timings.*3mf is nan"):
        json_text(fab.report(), "fabrication.json", FabricationError)
