"""`fold -o x.glb` and `fabricate` write glTF binaries that Blender-like clients read back.

Read back with trimesh (as a script or a web viewer loads the scene, node transforms
applied), with pygltflib (the raw glTF: animation, morph targets, materials) and, where
it is installed, Khronos' glTF-Validator.
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pygltflib
import pytest
import trimesh

from origami_cad.cli import main
from origami_cad.fabrication.assembly import MATERIAL_COLORS
from origami_cad.fabrication.exports.stl import read_binary_stl
from origami_cad.kinematics.folding import fold_sequence
from origami_cad.kinematics.placement import place_sequence
from origami_cad.pattern.design import load_pattern_source
from origami_cad.viz.gltf import CREASE_COLORS

_TYPES = {5126: np.float32, 5123: np.uint16, 5125: np.uint32}


def _accessor(gltf: pygltflib.GLTF2, index: int) -> np.ndarray:
    acc = gltf.accessors[index]
    view = gltf.bufferViews[acc.bufferView]
    blob = gltf.binary_blob()
    width = {"SCALAR": 1, "VEC3": 3}[acc.type]
    start = view.byteOffset + (acc.byteOffset or 0)
    data = np.frombuffer(blob, _TYPES[acc.componentType], acc.count * width, start)
    return data.reshape(acc.count, width) if width > 1 else data


def _srgb_hex(linear: list[float]) -> str:
    def enc(c: float) -> int:
        s = 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055
        return round(255 * s)

    return "#" + "".join(f"{enc(c):02X}" for c in linear[:3])


def _validator() -> list[str] | None:
    """The command that runs Khronos' glTF-Validator (npm ``gltf-validator``), if installed."""
    node = shutil.which("node")
    npm = shutil.which("npm")
    if not node or not npm:
        return None
    root = subprocess.run([npm, "root", "-g"], capture_output=True, text=True).stdout.strip()
    module = Path(root) / "gltf-validator"
    if not module.is_dir():
        return None
    script = (
        f"const v=require({json.dumps(str(module))});const d=require('fs').readFileSync("
        "process.argv[1]);v.validateBytes(new Uint8Array(d)).then(r=>console.log("
        "JSON.stringify(r.issues)))"
    )
    return [node, "-e", script]


@pytest.fixture(scope="module")
def design_file(tmp_path_factory) -> Path:
    """A 2 x 2-panel Miura (20 x 25 mm panels, 65 deg), fast to fabricate."""
    path = tmp_path_factory.mktemp("design") / "small_miura.toml"
    path.write_text(
        '[pattern]\nkind = "miura"\nrows = 2\ncolumns = 2\npanel_length = 20.0\n'
        "panel_width = 25.0\nsector_angle = 65.0\n"
    )
    return path


@pytest.fixture(scope="module")
def folding_glb(design_file, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("fold") / "folding.glb"
    assert main(["fold", str(design_file), "-o", str(out), "--ratio", "0.7"]) == 0
    return out


@pytest.fixture(scope="module")
def parts_folder(design_file, tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("fab") / "fab"
    assert main(["fabricate", str(design_file), "-o", str(folder)]) == 0
    return folder


def test_fold_writes_an_animated_glb_of_the_folding(design_file, folding_glb):
    out = folding_glb
    design = load_pattern_source(design_file)
    cp = design.pattern
    states = fold_sequence(design, np.linspace(0.0, 0.7, 30))  # one frame asked: 30, as a gif
    placed = place_sequence(cp, [s.coords for s in states])  # as `fold` lays them on the table

    scene = trimesh.load(out)  # the base pose, the flat sheet: mm -> m, z up -> y up
    assert set(scene.geometry) == {"panels", "mountain", "valley", "border"}
    x0, y0, x1, y1 = cp.bounds
    np.testing.assert_allclose(
        scene.bounds, [[x0 / 1e3, 0, -y1 / 1e3], [x1 / 1e3, 0, -y0 / 1e3]], atol=1e-7
    )
    panels = scene.geometry["panels"]
    assert np.isclose(panels.area, cp.face_areas().sum(), rtol=1e-6)  # mm^2, mesh units

    gltf = pygltflib.GLTF2().load(str(out))
    (anim,) = gltf.animations
    assert len(anim.channels) == 4 and {c.target.path for c in anim.channels} == {"weights"}
    times = _accessor(gltf, anim.samplers[0].input)
    np.testing.assert_allclose(times, np.linspace(0.0, 3.0, 30), atol=1e-6)
    weights = _accessor(gltf, anim.samplers[0].output).reshape(30, 29)
    node = gltf.nodes[anim.channels[0].target.node]
    prim = gltf.meshes[node.mesh].primitives[0]
    assert gltf.meshes[node.mesh].name == "panels" and len(prim.targets) == 29
    base = _accessor(gltf, prim.attributes.POSITION)
    for k in (12, 29):  # the state the animation shows at times[k]
        (target,) = np.flatnonzero(weights[k])
        moved = base + _accessor(gltf, prim.targets[target]["POSITION"])
        np.testing.assert_allclose(moved, placed[k], atol=1e-3)
    colours = {m.name: _srgb_hex(m.pbrMetallicRoughness.baseColorFactor) for m in gltf.materials}
    assert colours["mountain"] == CREASE_COLORS["M"] and colours["valley"] == CREASE_COLORS["V"]


def test_fabricate_writes_the_printed_parts_as_a_glb_coloured_by_material(parts_folder):
    folder = parts_folder
    glb = folder / "parts.glb"
    scene = trimesh.load(glb)
    assert set(scene.geometry) == {"infills", "midlayers", "shells", "creases"}
    for name, mesh in scene.geometry.items():
        verts, tris = read_binary_stl(folder / f"{name}.stl")
        assert len(mesh.faces) == len(tris)
        np.testing.assert_allclose(mesh.bounds, [verts.min(0), verts.max(0)], atol=1e-4)
    # the scene in metres, y up: its lowest point is the STLs lowest z
    stl_lo = np.min([read_binary_stl(folder / f"{n}.stl")[0].min(0) for n in scene.geometry], 0)
    assert np.isclose(scene.bounds[0][1], stl_lo[2] / 1e3, atol=1e-7)

    gltf = pygltflib.GLTF2().load(str(glb))
    material = {}
    for node in gltf.nodes:
        if node.mesh is not None:
            mat = gltf.materials[gltf.meshes[node.mesh].primitives[0].material]
            material[node.name] = (mat.name, _srgb_hex(mat.pbrMetallicRoughness.baseColorFactor))
    assert material == {
        "infills": ("PLA", MATERIAL_COLORS["PLA"]),
        "midlayers": ("PLA", MATERIAL_COLORS["PLA"]),
        "shells": ("TPU", MATERIAL_COLORS["TPU"]),
        "creases": ("TPU", MATERIAL_COLORS["TPU"]),
    }
    assert not gltf.animations


@pytest.mark.parametrize("which", ["folding", "parts"])
def test_khronos_gltf_validator_finds_no_issue(which, request):
    command = _validator()
    if command is None:
        pytest.skip("Khronos glTF-Validator absent (npm install -g gltf-validator)")
    path = request.getfixturevalue("folding_glb" if which == "folding" else "parts_folder")
    path = path if which == "folding" else path / "parts.glb"
    done = subprocess.run([*command, str(path)], capture_output=True, text=True, timeout=120)
    issues = json.loads(done.stdout)
    assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, issues["messages"]


def test_the_parts_glb_of_a_folder_is_the_one_of_its_fabrication(parts_folder, tmp_path):
    """``write_parts_glb`` of the STL folder (read back) draws what the fabrication's
    shared meshes draw (``fabricate`` passes the fabrication: no STL read)."""
    from origami_cad.viz.gltf import write_parts_glb

    again = write_parts_glb(parts_folder, tmp_path / "again.glb")
    ours, theirs = trimesh.load(parts_folder / "parts.glb"), trimesh.load(again)
    assert set(ours.geometry) == set(theirs.geometry)
    for name, mesh in ours.geometry.items():
        assert len(mesh.faces) == len(theirs.geometry[name].faces), name
        np.testing.assert_allclose(mesh.bounds, theirs.geometry[name].bounds, atol=1e-4)
        assert mesh.volume == pytest.approx(theirs.geometry[name].volume, rel=1e-5), name
