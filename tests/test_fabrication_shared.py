"""Each distinct panel shape built once and copied, each solid tessellated once.

The copies must be the solids a fresh build gives (valid, same volume, same place), the
shared meshes the meshes OCC gives each solid, and the files written from them closed.
"""

from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest
from build123d import Compound, Solid
from conftest import closed_mesh, mesh_volume

from origami_cad.fabrication import fabricate, write_fabrication
from origami_cad.fabrication.assembly import moved_tree
from origami_cad.fabrication.congruent import congruent_panels
from origami_cad.fabrication.exports.stl import read_binary_stl
from origami_cad.fabrication.meshing import (
    ANGULAR_TOLERANCE,
    TOLERANCE,
    part_meshes,
    solid_mesh,
    stack_meshes,
    weld,
)
from origami_cad.fabrication.panels import PanelOutline
from origami_cad.fabrication.solids import PART_NAMES, panel_solids
from origami_cad.pattern.design import miura_design


@pytest.fixture(scope="module")
def fab():
    return fabricate(miura_design(4, 4, 20.0, 20.0, 65.0))


def test_a_miura_builds_few_shapes_and_every_copy_is_the_fresh_solid(fab):
    copies = fab.parts.panel_copies
    built = [k for k, c in enumerate(copies) if c is None]
    assert len(copies) == 16 and len(built) < 16  # interior panels repeat
    holes_of = [fab.plan.holes_of(o.index) for o in fab.outlines]
    for k, same in enumerate(copies):
        if same is None:
            continue
        assert copies[same[0]] is None  # copies are of built panels
        assert np.linalg.det(same[1][:2, :2]) == pytest.approx(1.0, abs=1e-12)  # no mirror
        fresh = panel_solids(fab.outlines[k], holes_of[k], fab.params)
        for name in ("infills", "shells", "midlayers"):
            mine = [
                s
                for s, o in zip(fab.parts.solids[name], fab.parts.owners[name], strict=True)
                if o == k
            ]
            assert len(mine) == len(fresh[name]), name
            for a, b in zip(mine, fresh[name], strict=True):
                assert a.is_valid and a.wrapped.TShape() != b.wrapped.TShape()
                assert a.volume == pytest.approx(b.volume, rel=1e-9)
                gap = (a - b).volume + (b - a).volume  # same place, not only same size
                assert gap < 1e-6 * b.volume, (name, k, gap)


def _turned(o: PanelOutline, angle: float, shift, mirror: bool = False) -> PanelOutline:
    c, s = np.cos(angle), np.sin(angle)

    def move(ring):
        ring = np.asarray(ring, dtype=float)
        if mirror:  # x -> -x, order reversed to stay counter-clockwise
            ring = (ring * [-1.0, 1.0])[::-1]
        return ring @ np.array([[c, -s], [s, c]]).T + shift

    rings = ("polygon", "inner", "outer", "infill_inner", "infill_outer", "midlayer")
    fields = {name: move(getattr(o, name)) for name in rings}
    return PanelOutline(o.index, o.label, crease_edge=o.crease_edge, region=(), **fields)


def test_congruence_is_a_rotation_and_a_translation_never_a_mirror(fab):
    o = fab.outlines[5]
    moved = _turned(o, 0.7, (12.0, -3.0))
    mirrored = _turned(o, 0.0, (0.0, 0.0), mirror=True)
    found = congruent_panels([o, moved, mirrored], [[], [], []])
    assert found[0] is None and found[2] is None
    _, motion = found[1]
    turn = np.array([[np.cos(0.7), -np.sin(0.7)], [np.sin(0.7), np.cos(0.7)]])
    assert np.allclose(motion[:2, :2], turn, atol=1e-12)
    # a hole elsewhere on the same panel is another shape
    from origami_cad.pattern.model import Hole

    here, there = Hole(*o.inner.mean(0), 2.0), Hole(*(o.inner.mean(0) + 0.5), 2.0)
    assert congruent_panels([o, o], [[here], [there]])[1] is None
    assert congruent_panels([o, o], [[here], [here]])[1] is not None


def test_shared_meshes_are_each_solids_own_mesh_moved(fab):
    for name in ("infills", "shells", "midlayers"):
        meshes = part_meshes(fab.parts, name)
        assert part_meshes(fab.parts, name) is meshes  # tessellated once, then shared
        for k, (v, t) in enumerate(meshes):
            own_v, own_t = solid_mesh(Solid(fab.parts.solids[name][k].wrapped))
            assert len(v) == len(own_v) and len(t) == len(own_t), (name, k)
            assert closed_mesh(t), (name, k)
            assert mesh_volume(v, t) == pytest.approx(mesh_volume(own_v, own_t), rel=1e-9)
            assert np.abs(np.sort(v, axis=0) - np.sort(own_v, axis=0)).max() < 1e-6


def test_solid_mesh_is_the_mesh_build123d_gives(fab):
    """The face-by-face reader gives what build123d's ``tessellate`` gave (the old path)."""
    solid = Solid(fab.parts.solids["shells"][3].wrapped)
    v, t = solid_mesh(solid)
    points, triangles = solid.tessellate(TOLERANCE, ANGULAR_TOLERANCE)
    old_v = np.array([(p.X, p.Y, p.Z) for p in points])
    old_w, inverse = weld(np.round(old_v / 1e-6))
    old_t = inverse[np.array(triangles)]
    old_t = old_t[(old_t[:, 0] != old_t[:, 1]) & (old_t[:, 1] != old_t[:, 2])]
    assert np.allclose(v, old_w * 1e-6, atol=1e-6)
    assert sorted(map(tuple, np.sort(t, axis=1).tolist())) == sorted(
        map(tuple, np.sort(old_t, axis=1).tolist())
    )


def test_the_stls_are_the_shared_meshes_closed_and_outward(fab, tmp_path):
    paths = write_fabrication(fab, tmp_path)
    for name in PART_NAMES:
        v, t = stack_meshes(part_meshes(fab.parts, name))
        read_v, read_t = read_binary_stl(paths[name])
        assert len(read_t) == len(t)
        volume = mesh_volume(read_v, read_t)
        assert volume == pytest.approx(fab.parts.volume(name), rel=2e-3)  # chordal error only
        assert volume == pytest.approx(mesh_volume(v, t), rel=1e-5)  # float32 corners
        raw = paths[name].read_bytes()
        record = np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
        data = np.frombuffer(raw, dtype=record, offset=84)
        corners = data["v"].astype(float)
        cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        assert np.all(np.einsum("ij,ij->i", cross, data["normal"]) > 0)  # normals agree


def test_weld_is_numpys_unique_by_rows():
    rng = np.random.default_rng(3)
    points = np.round(rng.random((5000, 3)) * 4) / 4
    want, inverse = np.unique(points, axis=0, return_inverse=True)
    got, got_inverse = weld(points)
    assert np.array_equal(got, want) and np.array_equal(got_inverse, inverse.ravel())


def test_moved_tree_copies_a_leaf_without_its_tree():
    a, b = Solid.make_box(1, 1, 1), Solid.make_box(2, 1, 1)
    a.label, b.label = "a", "b"
    tree = Compound(children=[a, b])
    copy = moved_tree(a, a.location)
    assert copy.parent is None and copy.label == "a"
    assert copy.wrapped.TShape() != a.wrapped.TShape()  # its own geometry
    assert [c.label for c in tree.children] == ["a", "b"] and a.parent is tree
    assert copy.volume == pytest.approx(1.0)


ADMESH = shutil.which("admesh")


def test_a_sheet_of_copies_reads_back_closed_in_admesh_trimesh_and_lib3mf(fab, tmp_path):
    """The client checks of a sheet without copies (test_fabrication, test_clients_3mf),
    on one made mostly of copies."""
    import lib3mf
    import trimesh

    paths = write_fabrication(fab, tmp_path)
    for name in PART_NAMES:
        mesh = trimesh.load(paths[name])
        assert mesh.is_watertight and mesh.is_winding_consistent, name
        if ADMESH is not None:
            run = subprocess.run([ADMESH, str(paths[name])], capture_output=True, check=True)
            out = run.stdout.decode("utf-8", "replace")
            stats = dict(re.findall(r"^(\w[\w ]*?)\s*:\s*(\d+)", out, flags=re.M))
            for key in ("Total disconnected facets", "Degenerate facets", "Edges fixed",
                        "Facets removed", "Facets added", "Facets reversed",
                        "Backwards edges"):  # fmt: skip
                assert stats[key] == "0", (name, key)
            assert int(stats["Number of parts"]) == len(fab.parts.solids[name]), name
    model = lib3mf.get_wrapper().CreateModel()
    reader = model.QueryReader("3mf")
    reader.SetStrictModeActive(True)
    reader.ReadFromFile(str(paths["3mf"]))
    assert reader.GetWarningCount() == 0
    objects = model.GetMeshObjects()
    while objects.MoveNext():
        obj = objects.GetCurrentMeshObject()
        assert obj.IsValid() and obj.IsManifoldAndOriented(), obj.GetName()


@pytest.mark.skipif(
    shutil.which("freecadcmd") is None, reason="FreeCAD is not installed (apt install freecad)"
)
def test_freecad_reads_every_copied_solid_valid_coloured_and_of_its_volume(
    fab, tmp_path, monkeypatch
):
    """assembly.step of a sheet of copies (each distinct solid written once, placed as
    many times as it is used; no pcurves; the crease sheet in strips) in FreeCAD itself,
    in both merge modes."""
    from test_clients_freecad import SOLIDS_SCRIPT, _freecad, _rgb, check_freecad_solids

    from origami_cad.fabrication.assembly import MATERIAL_COLORS
    from origami_cad.fabrication.exports import step as step_module
    from origami_cad.fabrication.exports.step import export_step_assembly

    monkeypatch.setattr(step_module, "HOLES_PER_STRIP", 4)  # 16 holes: 4 strips
    strips = len(step_module.crease_strips(fab.parts.solids["creases"][0]))
    step = export_step_assembly(fab.parts, tmp_path / "assembly.step")
    modes = _freecad(tmp_path, SOLIDS_SCRIPT, step)
    assert set(modes) == {"merge", "no merge"}
    assert any(r[1] == "App::Link" for r in modes["no merge"])  # shared shapes, linked
    for rows in modes.values():
        check_freecad_solids(rows, fab.parts, names=("infills", "midlayers", "shells"))
        creases = [r for r in rows if r[0].startswith("creases")]
        assert len(creases) == strips >= 4
        assert all(r[2] for r in creases)
        assert all(r[3] == pytest.approx(_rgb(MATERIAL_COLORS["TPU"]), abs=2e-3) for r in creases)
        volume = sum(r[4] for r in creases)
        assert volume == pytest.approx(fab.parts.solids["creases"][0].volume, rel=1e-6)


def test_a_solid_replaced_after_the_build_is_meshed_as_itself():
    fab = fabricate(miura_design(3, 4, 20.0, 20.0, 65.0))
    copies = fab.parts.copy_of["shells"]
    k = next(i for i, c in enumerate(copies) if c is not None)
    before = part_meshes(fab.parts, "shells")[k]
    box = Solid.make_box(3, 4, 5)
    fab.parts.solids["shells"][k] = box  # no longer the copy it was built as
    v, t = part_meshes(fab.parts, "shells")[k]
    assert len(v) != len(before[0]) and closed_mesh(t)
    assert mesh_volume(v, t) == pytest.approx(60.0, rel=1e-9)


def test_a_parts_volume_counts_each_copy_as_its_own_solids(fab):
    for name in PART_NAMES:
        own = sum(Solid(s.wrapped).volume for s in fab.parts.solids[name])
        assert fab.parts.volume(name) == pytest.approx(own, rel=1e-9), name


def test_the_crease_sheet_is_meshed_from_its_polygon_as_occ_meshes_it(fab):
    from origami_cad.fabrication.meshing import prism_mesh

    (v, t), sheet = part_meshes(fab.parts, "creases")[0], fab.parts.solids["creases"][0]
    assert fab.parts.prism("creases", 0) is not None
    assert prism_mesh(*fab.parts.prism("creases", 0))[1].shape == t.shape
    own_v, own_t = solid_mesh(Solid(sheet.wrapped))
    assert closed_mesh(t) and len(t) == len(own_t) and len(v) == len(own_v)
    assert mesh_volume(v, t) == pytest.approx(sheet.volume, rel=1e-9)
    assert np.abs(np.sort(v, axis=0) - np.sort(own_v, axis=0)).max() < 1e-6


def test_a_step_export_failing_fails_write_fabrication_and_leaves_no_step(
    fab, tmp_path, monkeypatch
):
    from origami_cad.fabrication import exports

    def failing(fab, folder):
        raise OSError(f"{folder / 'assembly.step'}: the STEP writer failed")

    monkeypatch.setitem(exports.WRITERS, "step", failing)
    with pytest.raises(OSError, match=r"assembly\.step: the STEP writer failed"):
        write_fabrication(fab, tmp_path)
    assert not (tmp_path / "assembly.step").exists()
    assert not list(tmp_path.glob(".oc-*"))


def test_an_stl_read_back_is_welded_as_weld_welds_it(tmp_path):
    from origami_cad.fabrication.exports.stl import write_mesh_stl

    rng = np.random.default_rng(7)
    v = np.round(rng.uniform(-20, 20, (3000, 3)) * 4) / 4
    v[:3] = [[0.0, -0.0, 1.0], [-0.0, 0.0, 1.0], [-1e-30, 2.0, -3.0]]
    t = rng.integers(0, len(v), (4000, 3))
    path = write_mesh_stl((v, t), tmp_path / "m.stl")
    got_v, got_t = read_binary_stl(path)
    want_v, inverse = weld(v.astype(np.float32).astype(float)[t].reshape(-1, 3))
    assert np.array_equal(got_v, want_v) and np.array_equal(got_t, inverse.reshape(-1, 3))


def test_the_3mf_text_is_what_percent_formatting_writes(fab, tmp_path):
    import zipfile

    from origami_cad.fabrication.exports.threemf import export_3mf

    for slicer in ("prusa", "bambu"):
        path = export_3mf(fab.parts, tmp_path / f"{slicer}.3mf", slicer=slicer)
        model = zipfile.ZipFile(path).read("3D/3dmodel.model").decode()
        v, t = stack_meshes([m for n in PART_NAMES for m in part_meshes(fab.parts, n)])
        want = [f'<vertex x="{x:.6f}" y="{y:.6f}" z="{z:.6f}"/>' for x, y, z in v.tolist()]
        got = re.findall(r"<vertex [^>]*/>", model)
        assert [w.replace('"-0.000000"', '"0.000000"') for w in want] == got
        rows = re.findall(r'<triangle v1="(\d+)" v2="(\d+)" v3="(\d+)"', model)
        offsets = np.cumsum([0, *[len(part_meshes(fab.parts, n)) for n in PART_NAMES]])
        assert len(rows) == len(t) and offsets[-1] > 0
        if slicer == "prusa":  # one mesh: the stacked triangles as they are
            assert np.array_equal(np.array(rows, dtype=np.int64), t)
