"""The printed sheet as an assembly: its tree, its folded states in STEP, the robot folded,
the curated API and ``show`` on everything it draws.

The folded STEP is written by the command line and read back with build123d's
``import_step``; each panel's solids are checked against the flat solids moved by the
motion that the FOLD file of the same command gives that face (three of its vertices),
not by the code that built them.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from build123d import import_step

import origami_cad as oc
from origami_cad.cli import main
from origami_cad.errors import FabricationError
from origami_cad.fabrication import FabricationParams, fabricate
from origami_cad.fabrication.assembly import MATERIAL_COLORS, leaf_part, solids_by_part
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES
from origami_cad.pattern import read_fold, read_fold_frames
from origami_cad.pattern.design import load_design, miura_design

#: A TG design file (three transition vectors, one copy: 6 panels), as a user writes one.
DESIGN = """[pattern]
kind = "transition-graph"
unit_width = 60.0
copies = 1
entry_flag = 1
fold_ratio = 0.5
vectors = [[40, 0], [30, 25], [40, -10]]
"""


@pytest.fixture(scope="module")
def fab():
    return fabricate(miura_design(2, 3, 30.0, 30.0, 65.0))


def _rgb(material: str) -> tuple[float, float, float]:
    h = MATERIAL_COLORS[material].lstrip("#")
    return tuple(int(h[i : i + 2], 16) / 255 for i in (0, 2, 4))


def test_the_flat_assembly_is_the_fabricated_sheet_panel_by_panel(fab):
    sheet = fab.assembly()
    labels = [c.label for c in sheet.children]
    assert labels == [*fab.pattern.face_labels, "creases"]
    by_part = solids_by_part(sheet)
    for name in PART_NAMES:  # the same solids as the four parts, volume for volume
        assert len(by_part[name]) == len(fab.parts.solids[name])
        assert sum(s.volume for s in by_part[name]) == pytest.approx(fab.volumes()[name])
        for solid in by_part[name]:
            assert tuple(solid.color)[:3] == pytest.approx(_rgb(PART_MATERIALS[name]), abs=1e-6)
    for panel in sheet.children[:-1]:  # each panel: 2 infills, 2 shells, 1 mid-layer, its own
        kinds = sorted(leaf_part(c.label) for c in panel.children)
        assert kinds == ["infills", "infills", "midlayers", "shells", "shells"]
        assert all(c.label.startswith(panel.label + "_") for c in panel.children)
        box = panel.bounding_box()
        outline = fab.plan.outline(panel.label).polygon
        assert box.min.X >= outline[:, 0].min() - 1e-6 and box.max.X <= outline[:, 0].max() + 1e-6
    assert fab.assembly(0.0).fold_ratio == 0.0


def test_bad_fold_ratios_are_refused(fab):
    for ratio in (1.5, -0.1):
        with pytest.raises(FabricationError, match="fold ratio"):
            fab.assembly(ratio)


def _rigid(flat: np.ndarray, folded: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rigid motion of a face from three of its vertices: (R, t) with x -> R x + t."""

    def frame(p):
        e1 = (p[1] - p[0]) / np.linalg.norm(p[1] - p[0])
        n = np.cross(e1, p[2] - p[0])
        n /= np.linalg.norm(n)
        return np.column_stack([e1, np.cross(n, e1), n])

    rot = frame(folded) @ frame(flat).T
    return rot, folded[0] - rot @ flat[0]


def _three(face: list[int], flat: np.ndarray) -> list[int]:
    """Three vertices of a face, the last the farthest from the line of the first two."""
    a, b = face[0], face[1]
    d = flat[b] - flat[a]

    def area(c: int) -> float:
        v = flat[c] - flat[a]
        return abs(d[0] * v[1] - d[1] * v[0])

    far = max(face[2:], key=area)
    return [a, b, far]


def _nearest(points: np.ndarray, cloud: np.ndarray) -> float:
    d = np.linalg.norm(points[:, None, :] - cloud[None, :, :], axis=2)
    return float(d.min(axis=1).max())


def test_fold_writes_the_folded_structure_as_the_fold_frame_says(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "arm.toml").write_text(DESIGN)
    design = "arm.toml"
    assert main(["fold", design, "--ratio", "0.35", "-o", "folded.step"]) == 0
    assert main(["fold", design, "--ratio", "0.35", "-o", "folded.fold"]) == 0
    cp = read_fold("folded.fold")
    folded = read_fold_frames("folded.fold")[-1]
    flat3 = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    fab = fabricate(load_design(design), FabricationParams(holes="pattern"))
    h = fab.params.height
    lift = np.array([0.0, 0.0, h / 2])
    back = import_step("folded.step")
    panels = {c.label: c for c in back.children}
    assert set(panels) == {*fab.pattern.face_labels, "creases"}
    flat_sheet = fab.assembly(0.0)
    checked = 0
    for face, flat_panel in enumerate(flat_sheet.children[:-1]):
        label = flat_panel.label
        idx = _three(list(cp.faces[face]), flat3)
        rot, t = _rigid(flat3[idx], folded[idx])
        got = {c.label: c for c in panels[label].children}
        assert set(got) == {c.label for c in flat_panel.children}
        for leaf in flat_panel.children:
            want = np.array([tuple(v) for v in leaf.vertices()])
            moved = (want - lift) @ rot.T + t + lift  # the FOLD's motion, about z = h/2
            have = np.array([tuple(v) for v in got[leaf.label].vertices()])
            assert len(have) == len(want)
            assert _nearest(moved, have) < 0.01, leaf.label
            assert got[leaf.label].volume == pytest.approx(leaf.volume, rel=1e-6)
            checked += 1
    assert checked == sum(len(c.children) for c in flat_sheet.children[:-1])
    # the crease strips: cut per face, moved with it, the TPU volume kept
    strips = panels["creases"]
    tpu = sum(s.volume for s in strips.solids())
    assert tpu == pytest.approx(fab.volumes()["creases"], rel=1e-6)
    assert all(tuple(s.color)[:3] == pytest.approx(_rgb("TPU"), abs=0.01) for s in strips.children)


def test_the_robot_folded_keeps_its_parts_on_their_panels(fab, tmp_path):
    from origami_cad.parts.robot import (
        BlockerPlacement,
        FreePlacement,
        ModulePlacement,
        robot_assembly,
        write_robot_step,
    )

    placements = {
        "modules": [ModulePlacement("module", "c0r1s2")],
        "blockers": [BlockerPlacement("stop", 14, 80.0), BlockerPlacement("stop_m", 11, 80.0)],
        "free": [FreePlacement("adapter", "driver-adapter", (45.0, 45.0))],
    }
    flat = robot_assembly(fab, **placements)
    # flat: the valley's blocker on the top face, the mountain's under the sheet
    assert flat.solids["stop"].bounding_box().min.Z == pytest.approx(fab.params.height)
    assert flat.solids["stop_m"].bounding_box().max.Z == pytest.approx(0.0, abs=1e-9)
    assert [c.label for c in flat.solids["stop_m"].children] == ["blocker 80 deg"]
    folded = robot_assembly(fab, **placements, ratio=0.4)
    sheet0, sheet1 = fab.assembly(0.0), fab.assembly(0.4)
    faces = {"module": "c0r1s2", "stop": "c0r1s0", "stop_m": "c0r0s1", "adapter": "c0r1s1"}
    for name, label in faces.items():
        # each part rides on its panel: the panel's motion takes flat to folded
        a0 = next(c for c in sheet0.children if c.label == label)
        a1 = next(c for c in sheet1.children if c.label == label)
        motion = a1.joints["mount"].location * a0.joints["mount"].location.inverse()
        moved = flat.solids[name].moved(motion)
        box, want = folded.solids[name].bounding_box(), moved.bounding_box()
        assert np.abs(np.subtract(tuple(box.min), tuple(want.min))).max() < 1e-6, name
        assert folded.solids[name].volume == pytest.approx(flat.solids[name].volume, rel=1e-9)
    assert folded.ratio == 0.4
    path = write_robot_step(folded, tmp_path / "robot.step", label="crawler")
    back = import_step(path)
    assert [c.label for c in back.children] == ["sheet", "module", "stop", "stop_m", "adapter"]
    module = back.children[1]
    assert module.bounding_box().min.Z == pytest.approx(
        folded.solids["module"].bounding_box().min.Z, abs=1e-6
    )
    assert all(leaf.color is not None for leaf in back.leaves)
    with pytest.raises(FabricationError, match="fold ratio"):
        robot_assembly(fab, ratio=-0.1)


def test_the_curated_api_imports_lazily_and_resolves_every_name():
    names = set(oc.__all__) - {"__version__"}
    assert len(names) > 30 and names <= set(dir(oc))
    for name in sorted(names):
        assert getattr(oc, name) is not None, name
    assert oc.TSAModule.__module__ == "origami_cad.parts.tsa_module"
    assert oc.fabricate is fabricate
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        _ = oc.nothing
    code = "import sys, origami_cad; print(json.dumps(sorted(m for m in sys.modules))); "
    run = subprocess.run(
        [sys.executable, "-c", "import json; " + code],
        capture_output=True,
        text=True,
        check=True,
    )
    loaded = set(json.loads(run.stdout))
    assert not loaded & {"build123d", "numpy", "pyvista", "OCP", "shapely"}


@pytest.mark.parametrize(
    "what", ["pattern", "folded", "assembly", "TSAModule", "RingRail", "Blocker", "DriverAdapter"]
)
def test_show_draws_each_thing_off_screen(what):
    design = miura_design(2, 2, 20.0, 25.0, 65.0)
    pattern = None
    if what == "pattern":
        obj = design
    elif what == "folded":
        obj, pattern = oc.fold_design(design, 0.4), design
    elif what == "assembly":
        obj = fabricate(design).assembly(0.3)
    else:
        obj = getattr(oc, what)()
    image = oc.show(obj, pattern, mode="offscreen", window_size=(240, 180))
    assert image.shape == (180, 240, 3)
    drawn = (image.reshape(-1, 3) != image[0, 0]).any(axis=1).mean()
    assert 0.02 < drawn < 0.9  # something drawn, not a blank or filled picture
    blocks = oc.to_pyvista(obj, pattern)
    if what == "assembly":
        for name in blocks.keys():
            material = str(blocks[name].field_data["material"][0])
            want = np.round(np.array(_rgb(material)) * 255)
            assert np.array_equal(blocks[name].field_data["color"], want), name
    if what in ("TSAModule", "RingRail", "Blocker", "DriverAdapter"):
        assert sorted(blocks.keys()) == sorted(c.label for c in obj.children)
        assert sum(blocks[n].volume for n in blocks.keys()) == pytest.approx(obj.volume, rel=0.02)


def test_bad_ratios_on_the_command_line_are_one_line_and_exit_2(tmp_path, capsys):
    from pathlib import Path

    robot = Path(__file__).resolve().parents[1] / "examples" / "crawler" / "crawler.toml"
    (tmp_path / "arm.toml").write_text(DESIGN)
    runs = [
        ["robot", str(robot), "-o", str(tmp_path / "out"), "--ratio", "1.5"],
        ["fold", str(tmp_path / "arm.toml"), "--ratio", "-0.2", "-o", str(tmp_path / "f.step")],
    ]
    for args in runs:
        assert main(args) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--ratio: expected a finite number in [0, 1]" in err[0], err
    assert not (tmp_path / "out").exists() and not (tmp_path / "f.step").exists()
