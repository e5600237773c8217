"""Fabrication: exact solids, eq. 6 checked by folding the solids, exports read back."""

from __future__ import annotations

import itertools
import json
import math
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import replace
from pathlib import Path

import lib3mf
import numpy as np
import pytest
import shapely
import trimesh
from build123d import Axis, Compound, Edge, Vertex, import_step
from matplotlib.image import imread

from origami_cad.cli import main
from origami_cad.errors import FabricationError, OrigamiCadError, PatternError
from origami_cad.fabrication import (
    FabricationParams,
    LimitStatus,
    bias_for_theta_max,
    build_fabrication,
    fabricate,
    largest_bias,
    offset_ring,
    plan_panels,
    theta_max,
    write_fabrication,
)
from origami_cad.fabrication.panels import panel_fits
from origami_cad.fabrication.plan import MIN_BIAS
from origami_cad.fabrication.solids import PART_NAMES
from origami_cad.kinematics.folding import fold_sequence
from origami_cad.pattern import CreasePattern
from origami_cad.pattern.design import load_design, miura_design
from origami_cad.viz.fabrication_plots import save_panels_png

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def two_panels(width: float = 40.0, assignment: str = "V") -> CreasePattern:
    """A 2w x w sheet with one crease along x = w."""
    v = [[0, 0], [width, 0], [2 * width, 0], [2 * width, width], [width, width], [0, width]]
    e = [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 0], [1, 4]]
    return CreasePattern(v, e, ["B"] * 6 + [assignment])


@pytest.fixture(scope="module")
def small_fab():
    return fabricate(miura_design(2, 3, 30.0, 30.0, 65.0), FabricationParams(shell=0.5))


def test_eq6_numbers_of_the_paper_and_its_inverse():
    p = FabricationParams(bias=3.0, height=2.2, thickness=0.4)
    assert math.degrees(p.theta_max) == pytest.approx(146.6, abs=0.05)
    assert 100 * p.p_max == pytest.approx(81.4, abs=0.05)
    for target in (60.0, 120.0, 146.6):
        b = bias_for_theta_max(math.radians(target), 2.2, 0.4)
        assert math.degrees(theta_max(b, 2.2, 0.4)) == pytest.approx(target)


def test_offset_ring_is_exact_per_edge():
    square = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    out = offset_ring(square, np.array([1.0, 2.0, 0.0, 0.5]))
    np.testing.assert_allclose(out, [[0.5, 1.0], [8.0, 1.0], [8.0, 10.0], [0.5, 10.0]])
    with pytest.raises(PatternError, match="panel p7 is too small"):
        offset_ring(square, np.full(4, 6.0), "p7")


def test_parts_are_valid_disjoint_and_fill_the_envelope(small_fab):
    fab = small_fab
    parts = {n: Compound(fab.parts.solids[n]) for n in PART_NAMES}
    for name, comp in parts.items():
        assert comp.solids() and all(s.is_valid for s in comp.solids()), name
    total = sum(fab.volumes().values())
    names = list(PART_NAMES)
    for i in range(4):
        for j in range(i + 1, 4):
            common = parts[names[i]] & parts[names[j]]
            vol = sum(s.volume for s in common.solids()) if common else 0.0
            assert vol < 1e-6 * total, (names[i], names[j], vol)
    # the envelope, computed independently: prismatoid halves + crease layer - holes
    p = fab.params
    outline = shapely.union_all(fab.pattern.face_polygons())
    envelope = outline.area * p.thickness
    for o in fab.outlines:
        mid = offset_ring(o.polygon, np.where(o.crease_edge, p.bias / 2, p.border_margin))
        areas = [shapely.Polygon(r).area for r in (o.inner, mid, o.outer)]
        envelope += 2 * p.half_height / 6 * (areas[0] + 4 * areas[1] + areas[2])
    envelope -= sum(math.pi * (h.diameter / 2) ** 2 * p.height for h in fab.holes)
    assert total == pytest.approx(envelope, rel=1e-3)


@pytest.mark.parametrize("assignment", ["V", "M"])
def test_folding_two_panels_by_theta_max_brings_chamfers_into_contact(assignment):
    params = FabricationParams(holes="none")
    fab = fabricate(two_panels(assignment=assignment), params)
    (a_low, a_up), (b_low, b_up) = fab.parts.halves
    # a valley closes the upper halves, a mountain the lower ones
    if assignment == "V":
        a, b, z, sign = a_up, b_up, params.half_height + params.thickness, 1.0
    else:
        a, b, z, sign = a_low, b_low, params.half_height, -1.0
    axis = Axis((40.0, 0.0, z), (0.0, 1.0, 0.0))
    tmax = math.degrees(params.theta_max)
    # where panel a's chamfer meets its outer face (on the outer face: z = h or 0)
    rim = Vertex(40.0 - params.bias, 20.0, params.height if assignment == "V" else 0.0)

    def fold(total_deg: float):
        return (a.rotate(axis, sign * total_deg / 2), b.rotate(axis, -sign * total_deg / 2))

    def gap(total_deg: float) -> float:
        return fold(total_deg)[1].distance_to(rim.rotate(axis, sign * total_deg / 2))

    assert gap(tmax - 4.0) > 1e-3  # open below theta_max
    assert gap(tmax) < 1e-6  # the chamfers meet face to face
    ra, rb = fold(tmax)
    common = ra & rb
    assert (sum(s.volume for s in common.solids()) if common else 0.0) < 1e-6
    ra, rb = fold(tmax + 2.0)
    common = ra & rb
    assert sum(s.volume for s in common.solids()) > 1e-3  # interference past theta_max


def test_holes_go_through_every_part_at_panel_centres(small_fab):
    fab = small_fab
    assert len(fab.holes) == len(fab.outlines)
    assert fab.plan.hole_panels.tolist() == [o.index for o in fab.outlines]
    for hole, o in zip(fab.holes, fab.outlines, strict=True):
        x, y, d = hole.x, hole.y, hole.diameter
        assert d == 2.0 and fab.pattern.face_of_point(x, y) == o.index
        region = o.region_polygon()
        assert region.contains(shapely.Point(x, y).buffer(d / 2))
        # a pole of inaccessibility: (nearly) the largest clearance in the region ...
        from shapely.ops import polylabel

        best = region.exterior.distance(polylabel(region, tolerance=1e-4))
        assert region.exterior.distance(shapely.Point(x, y)) >= 0.98 * best
        # ... and among those, the one nearest the region's centroid
        c = region.centroid
        core = region.buffer(-0.99 * best)
        assert math.hypot(c.x - x, c.y - y) <= core.distance(c) + 1e-6
    # a vertical line through a hole meets no part
    x, y = fab.holes[0].x, fab.holes[0].y
    probe = Edge.make_line((x, y, -1.0), (x, y, fab.params.height + 1.0))
    for name in PART_NAMES:
        assert Compound(fab.parts.solids[name]).distance_to(probe) > 0.9, name


def test_exports_read_back(tmp_path, small_fab):
    fab = small_fab
    paths = write_fabrication(fab, tmp_path)
    vols = fab.volumes()
    # STL: binary, in assembly position, every body closed
    for name in PART_NAMES:
        raw = paths[name].read_bytes()
        assert not raw.startswith(b"solid")  # binary
        mesh = trimesh.load(paths[name])
        bodies = mesh.split(only_watertight=False)
        assert len(bodies) == len(fab.parts.solids[name])
        assert all(b.is_watertight for b in bodies)
        assert abs(mesh.volume) == pytest.approx(vols[name], rel=2e-3)
        lo, hi = mesh.bounds
        assert lo[2] >= -1e-6 and hi[2] <= fab.params.height + 1e-6
    # STEP: four named, coloured parts
    step = import_step(paths["step"])
    labels = {c.label: c for c in step.children}
    assert set(labels) == set(PART_NAMES)
    red, green, _, _ = tuple(labels["shells"].color)
    assert red > 0.8 > green
    for name in PART_NAMES:
        got = sum(s.volume for s in labels[name].solids())
        assert got == pytest.approx(vols[name], rel=1e-6)
    # 3MF: one object, four volumes on the right extruders
    wrapper = lib3mf.get_wrapper()
    model = wrapper.CreateModel()
    model.QueryReader("3mf").ReadFromFile(str(paths["3mf"]))
    objects = model.GetMeshObjects()
    assert objects.Count() == 1
    objects.MoveNext()
    n_tri = objects.GetCurrentMeshObject().GetTriangleCount()
    with zipfile.ZipFile(paths["3mf"]) as zf:
        prusa = ET.fromstring(zf.read("Metadata/Slic3r_PE_model.config"))
        bambu = ET.fromstring(zf.read("Metadata/model_settings.config"))
        model_xml = ET.fromstring(zf.read("3D/3dmodel.model"))
    volumes = prusa.findall("./object/volume")
    assert len(volumes) == 4
    meta = [{m.get("key"): m.get("value") for m in v.findall("metadata")} for v in volumes]
    assert [m["name"] for m in meta] == list(PART_NAMES)
    assert [m["extruder"] for m in meta] == ["1", "1", "2", "2"]
    assert volumes[0].get("firstid") == "0" and int(volumes[-1].get("lastid")) == n_tri - 1
    for a, b in itertools.pairwise(volumes):
        assert int(b.get("firstid")) == int(a.get("lastid")) + 1
    parts = bambu.findall("./object/part")
    ext = {
        p.find("metadata[@key='name']").get("value"): p.find("metadata[@key='extruder']").get(
            "value"
        )
        for p in parts
    }
    assert ext == {"infills": "1", "midlayers": "1", "shells": "2", "creases": "2"}
    ns = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}
    colours = [b.get("displaycolor") for b in model_xml.findall(".//m:base", ns)]
    assert len(colours) == 2
    # each volume's triangles close up on their own
    verts = np.array(
        [[float(v.get(k)) for k in "xyz"] for v in model_xml.findall(".//m:vertex", ns)]
    )
    tris = np.array(
        [
            [int(t.get(k)) for k in ("v1", "v2", "v3")]
            for t in model_xml.findall(".//m:triangle", ns)
        ]
    )
    for v, name in zip(volumes, PART_NAMES, strict=True):
        sub = trimesh.Trimesh(verts, tris[int(v.get("firstid")) : int(v.get("lastid")) + 1])
        assert abs(sub.volume) == pytest.approx(vols[name], rel=2e-3)
    report = json.loads(paths["json"].read_text())
    assert report["panels"] == len(fab.outlines)
    assert report["theta_max_deg"] == pytest.approx(146.6, abs=0.05)
    assert report["parts"]["shells"]["material"] == "TPU"
    assert report["parts"]["infills"]["mass_g"] == pytest.approx(vols["infills"] / 1000 * 1.24)


ADMESH = shutil.which("admesh")


def test_each_stl_is_one_watertight_mesh(tmp_path, small_fab):
    """Each part's STL is watertight when welded by position: neighbouring shells stop short of
    the crease lines (where they met, 76 edges had four triangles)."""
    from origami_cad.fabrication.panels import CREASE_GAP

    paths = write_fabrication(small_fab, tmp_path)
    for name in PART_NAMES:
        mesh = trimesh.load(paths[name])  # welded by position, as every STL reader does
        assert mesh.is_watertight and mesh.is_winding_consistent, name
        _, uses = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
        assert set(uses.tolist()) == {2}, name
    # the stated gap: each panel's halves stop CREASE_GAP / 2 short of its creases
    for o in small_fab.outlines:
        crease = np.flatnonzero(o.crease_edge)
        poly = shapely.Polygon(o.polygon).exterior
        for k in crease:
            mid = (o.inner[k] + o.inner[(k + 1) % len(o.inner)]) / 2
            assert poly.distance(shapely.Point(mid)) == pytest.approx(CREASE_GAP / 2, abs=1e-9)
    if ADMESH is None:
        pytest.skip("admesh is not installed")
    for name in PART_NAMES:
        run = subprocess.run([ADMESH, str(paths[name])], capture_output=True, text=True, check=True)
        stats = dict(re.findall(r"^(\w[\w ]*?)\s*:\s*(\d+)", run.stdout, flags=re.M))
        for key in ("Total disconnected facets", "Degenerate facets", "Edges fixed",
                    "Facets removed", "Facets added",
                    "Facets reversed", "Backwards edges"):  # fmt: skip
            assert stats[key] == "0", (name, key)
        assert int(stats["Number of parts"]) == len(small_fab.parts.solids[name]), name


def test_crease_limits_from_the_rigid_folding(small_fab):
    limits = small_fab.limits
    assert limits.status is LimitStatus.FOLDABLE and limits.foldable
    # the legs of a Miura fold faster than its main creases
    assert 0 < limits.p_max_kinematic < small_fab.params.p_max
    assert len(limits.limiting_edges) > 0 and limits.creases_before_p_max > 0
    # independently: at p_max_kinematic a limiting crease is folded by theta_max
    cp = small_fab.pattern
    design = miura_design(2, 3, 30.0, 30.0, 65.0)
    (state,) = fold_sequence(design, [limits.p_max_kinematic])
    edge = int(limits.limiting_edges[0])
    assert abs(state.fold_angles[edge]) == pytest.approx(
        math.degrees(small_fab.params.theta_max), abs=0.5
    )
    mid = cp.vertices[cp.edges[edge]].mean(axis=0)
    np.testing.assert_allclose(limits.limiting_midpoints[0], mid, atol=1e-3)
    assert limits.limiting_assignments[0] == cp.assignments[edge]


def test_crease_limits_have_one_schema_whatever_the_pattern():
    keys = None
    for source in (miura_design(2, 3, 30.0, 30.0, 65.0), two_panels()):
        limits = plan_panels(source, FabricationParams(holes="none")).limits
        data = json.loads(json.dumps(limits.to_dict()))
        keys = keys or set(data)
        assert set(data) == keys
    assert data["status"] == "not checked" and data["p_max_kinematic"] is None
    assert data["reason"] and data["limiting_creases"] == []


def test_the_plan_is_plain_data_and_the_solids_follow_it():
    design = miura_design(2, 3, 30.0, 30.0, 65.0)
    params = FabricationParams(shell=0.5, holes=[(15.0, 10.0), (45.0, 40.0)], hole_diameter=1.5)
    plan = plan_panels(design, params)
    for value in vars(plan).values():  # no build123d object in the plan
        assert "build123d" not in type(value).__module__
    assert [(h.x, h.y, h.diameter) for h in plan.holes] == [(15.0, 10.0, 1.5), (45.0, 40.0, 1.5)]
    faces = [plan.pattern.face_of_point(h.x, h.y) for h in plan.holes]
    assert plan.hole_panels.tolist() == faces
    label = plan.pattern.face_labels[faces[1]]
    assert plan.holes_by_label()[label] == (plan.holes[1],)
    assert plan.pattern_with_holes.holes == plan.holes
    fab = build_fabrication(plan)
    assert fab.plan is plan and fab.holes == plan.holes
    for hole in plan.holes:  # each planned hole goes through the built parts
        probe = Edge.make_line((hole.x, hole.y, -1.0), (hole.x, hole.y, params.height + 1.0))
        for name in PART_NAMES:
            assert Compound(fab.parts.solids[name]).distance_to(probe) > 0.7 * hole.diameter / 2
    report = fab.report()
    assert [h["panel"] for h in report["holes"]] == [plan.pattern.face_labels[f] for f in faces]
    assert report["crease_limits"] == plan.limits.to_dict()


def test_panels_png_shows_the_sheet(tmp_path, small_fab):
    path = save_panels_png(small_fab.plan, tmp_path / "panels.png")
    image = imread(path)[..., :3]
    ink = np.any(image < 0.9, axis=-1)  # anything but the white background
    assert 0.05 < ink.mean() < 0.8
    # the panels' fill colour covers a box of the sheet's aspect ratio (equal axes)
    fill = np.all(np.abs(image - np.array([246, 239, 224]) / 255) < 0.02, axis=-1)
    rows, cols = np.flatnonzero(fill.any(axis=1)), np.flatnonzero(fill.any(axis=0))
    x0, y0, x1, y1 = small_fab.pattern.bounds
    drawn = (rows[-1] - rows[0]) / (cols[-1] - cols[0])
    assert drawn == pytest.approx((y1 - y0) / (x1 - x0), rel=0.05)
    assert 0.2 < fill.mean() < 0.8


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"height": 0.4}, "must exceed the crease thickness"),
        ({"bias": 0.0}, r"bias: expected a finite number in \[0.01, 10000\], got 0.0"),
        ({"border_margin": 40.0}, "too small for the crease layer even printed in TPU alone"),
        ({"holes": [(500.0, 500.0)]}, "not on any panel"),
        ({"holes": [(15.0, 1.0)]}, "does not fit the operation region of panel c0r0s0"),
        ({"height": 0.4}, r"eq\. 6"),
        ({"shell": 0.9}, r"thinner than a panel half \(h - t\) / 2 = 0\.9 mm"),
    ],
)
def test_bad_parameters_are_named(kwargs, message):
    with pytest.raises((FabricationError, PatternError), match=message):
        fabricate(miura_design(2, 3, 30.0, 30.0, 65.0).pattern, FabricationParams(**kwargs))


def test_panels_too_small_for_the_bias_get_the_largest_that_fits_and_are_named():
    design = miura_design(2, 3, 30.0, 30.0, 65.0)
    params = FabricationParams(bias=16.0)
    plan = plan_panels(design, params)
    assert plan.biases is not None and len(plan.holes) == len(plan.outlines)
    cp = plan.pattern
    assert np.count_nonzero(plan.biases < 16.0) == 2  # the middle column
    for fi, b in enumerate(plan.biases):
        assert MIN_BIAS <= b <= 16.0
        assert panel_fits(cp, fi, params, b)
        if b < 16.0:
            assert not panel_fits(cp, fi, params, b + 0.02)  # the largest, to 0.01 mm
    (warning,) = [w for w in plan.warnings if "too small for the inner bias 16 mm" in w]
    first = int(np.flatnonzero(plan.biases < 16.0)[0])
    assert f"{cp.face_labels[first]} {plan.biases[first]:.2f} mm" in warning
    fab = fabricate(design, params)
    report = fab.report()
    assert report["panel_bias_mm"] == dict(zip(cp.face_labels, plan.biases.tolist(), strict=True))
    for o, b in zip(fab.outlines, plan.biases, strict=True):  # outer face inset by its bias
        want = offset_ring(o.polygon, np.where(o.crease_edge, b, params.border_margin))
        np.testing.assert_allclose(o.outer, want, atol=1e-9)
    default = plan_panels(design)  # the default fits: no per-panel biases, nothing in the file
    assert default.biases is None and "panel_bias_mm" not in fabricate(design).report()


def test_a_hole_too_large_for_every_bias_leaves_its_panel_without_one():
    params = FabricationParams(hole_diameter=25.0)
    plan = plan_panels(load_design(EXAMPLES / "miura_6x4.toml"), params)
    assert len(plan.holes) == 0
    assert any("no room for a 25 mm hole and are printed without one" in w for w in plan.warnings)
    with pytest.raises(PatternError, match="does not fit the operation region"):
        plan_panels(miura_design(2, 3, 30.0, 30.0, 65.0), replace(params, holes=[(15.0, 1.0)]))


def test_facet_creases_are_not_printed_the_panels_are_merged_across_them():
    # two square panels joined by a valley, each split by a facet diagonal
    v = [(0, 0), (40, 0), (80, 0), (0, 40), (40, 40), (80, 40)]
    e = [(0, 1), (1, 2), (3, 4), (4, 5), (0, 3), (2, 5), (1, 4), (0, 4), (1, 5)]
    cp = CreasePattern(v, e, "BBBBBBVFF")
    assert len(cp.faces) == 4
    plan = plan_panels(cp)
    assert len(plan.outlines) == 2 and len(plan.holes) == 2
    assert "F" not in plan.pattern.assignments.tolist()
    for o in plan.outlines:  # whole squares, only the valley chamfered
        assert shapely.Polygon(o.polygon).area == pytest.approx(1600.0)
        assert o.crease_edge.sum() == 1


@pytest.mark.parametrize(
    "p_max, theta_max, message",
    [
        (1.2, None, r"p_max must lie in \(0, 1\) \(eq\. 6"),
        (None, 180.0, r"theta_max must lie in \(0, 180\) deg"),
    ],
)
def test_eq6_limits_of_p_max_and_theta_max_are_named(p_max, theta_max, message):
    from origami_cad.fabrication import fabrication_params

    with pytest.raises(OrigamiCadError, match=message):
        fabrication_params(p_max=p_max, theta_max=theta_max)


def test_a_sheet_larger_than_the_bed_is_refused_before_any_work(tmp_path, capsys):
    from origami_cad.fabrication import check_bed

    # 100 x 100 panels of 20 mm: 2 m across, thousands of panels; refused up front
    huge = miura_design(100, 100, 20.0, 20.0, 65.0)
    with pytest.raises(FabricationError, match=r"larger than the 200 x 200 mm print bed"):
        fabricate(huge, bed=(200.0, 200.0))
    small = miura_design(2, 3, 30.0, 30.0, 65.0).pattern  # 104 x 60 mm
    check_bed(small, (110.0, 70.0))
    check_bed(small, (70.0, 110.0))  # either way round
    with pytest.raises(FabricationError, match=r"104\.0 x 60\.0 mm: larger than the 100 x 100 mm"):
        check_bed(small, (100.0, 100.0))
    with pytest.raises(FabricationError, match="two sizes > 0 mm"):
        check_bed(small, (0.0, 100.0))
    # the command refuses a sheet larger than the bed it is given, naming the option
    design = tmp_path / "long.toml"
    design.write_text(
        '[pattern]\nkind = "miura"\nrows = 2\ncolumns = 12\npanel_length = 20.0\n'
        "panel_width = 20.0\nsector_angle = 65.0\n"
    )
    given = ["fabricate", str(design), "-o", str(tmp_path / "out"), "--bed", "200", "200"]
    assert main(given) == 2
    err = capsys.readouterr().err
    assert "larger than the 200 x 200 mm print bed" in err and "--bed X Y" in err
    assert not (tmp_path / "out").exists()
    # without --bed it does what the library does: builds, and warns against 200 x 200 mm
    assert main(["fabricate", str(design), "-o", str(tmp_path / "free")]) == 0
    err = capsys.readouterr().err
    assert "warning: the sheet is printed flat" in err and "200 x 200 mm print bed" in err
    assert (tmp_path / "free" / "print.3mf").is_file()


def test_a_sheet_of_too_many_panels_is_refused_before_any_work(tmp_path, capsys):
    """On a bed it fits, a 70 x 70 sheet would still build past the time budget."""
    from origami_cad.fabrication.plan import (
        FABRICATION_BUDGET_S,
        MAX_FABRICATED_PANELS,
        SECONDS_PER_PANEL,
    )

    assert MAX_FABRICATED_PANELS * SECONDS_PER_PANEL <= FABRICATION_BUDGET_S
    assert (MAX_FABRICATED_PANELS + 1) * SECONDS_PER_PANEL > FABRICATION_BUDGET_S
    huge = miura_design(70, 70, 5.0, 5.0, 65.0)
    assert len(huge.pattern.faces) > MAX_FABRICATED_PANELS
    with pytest.raises(FabricationError, match=r"4,900 panels: fabricate would take about 74 s"):
        fabricate(huge, bed=(1000.0, 1000.0))
    design = tmp_path / "many.toml"
    design.write_text(
        '[pattern]\nkind = "miura"\nrows = 70\ncolumns = 70\npanel_length = 5.0\n'
        "panel_width = 5.0\nsector_angle = 65.0\n"
    )
    out = tmp_path / "out"
    assert main(["fabricate", str(design), "-o", str(out), "--bed", "900", "900"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "MAX_FABRICATED_PANELS" in err
    assert not out.exists()
    edge = miura_design(50, 80, 5.0, 5.0, 65.0).pattern  # exactly the limit: accepted
    from origami_cad.fabrication import check_panel_count

    check_panel_count(edge)


def test_cli_writes_everything_or_nothing(tmp_path, capsys):
    out = tmp_path / "fab"
    design = str(EXAMPLES / "miura_6x4.toml")
    assert main(["fabricate", design, "-o", str(out), "--p-max", "0.7", "--shell", "0.4"]) == 0
    names = {p.name for p in out.iterdir()}
    assert names >= {
        "infills.stl",
        "midlayers.stl",
        "shells.stl",
        "creases.stl",
        "assembly.step",
        "print.3mf",
        "fabrication.json",
        "panels.png",
    }
    report = json.loads((out / "fabrication.json").read_text())
    assert report["p_max"] == pytest.approx(0.7)
    bad = tmp_path / "bad"
    assert main(["fabricate", design, "-o", str(bad), "--border-margin", "40"]) == 2
    assert "too small" in capsys.readouterr().err
    assert not bad.exists()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_a_panel_that_is_not_a_simple_polygon_is_refused(tmp_path):
    outer = [[0, 0], [60, 0], [60, 60], [0, 60]]
    inner = [[20, 20], [40, 20], [40, 40], [20, 40]]
    edges = [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]]
    framed = CreasePattern(outer + inner, edges, ["B"] * 4 + ["C"] * 4)
    with pytest.raises(PatternError, match="cannot fabricate"):
        fabricate(framed)


def test_plots_and_renders_leave_no_global_state(tmp_path):
    """Importing and using the plots and renders selects no backend and sets no global flag."""
    script = f"""
import sys
import matplotlib
before = matplotlib.rcParams._get_backend_or_none()
from origami_cad.pattern.design import miura_design
from origami_cad.kinematics.folding import fold_sequence
from origami_cad.fabrication import plan_panels
from origami_cad.viz import design_plots, drive_plots, tg_plot, parts_render
from origami_cad.viz.fabrication_plots import save_panels_png
from origami_cad.viz.render3d import render_folded
import pyvista
from vtkmodules.vtkRenderingCore import vtkMapper
resolve = vtkMapper.GetResolveCoincidentTopology()
design = miura_design(2, 3, 30.0, 30.0, 65.0)
save_panels_png(plan_panels(design), r"{tmp_path}/panels.png")
(state,) = fold_sequence(design, [0.5])
render_folded(design.pattern, state.coords, r"{tmp_path}/folded.png")
assert matplotlib.rcParams._get_backend_or_none() == before, "backend selected"
pyplot = sys.modules.get("matplotlib.pyplot")  # cma imports it, but no figure is open
assert pyplot is None or not pyplot.get_fignums(), "figures left in pyplot"
assert not pyvista.OFF_SCREEN, "pyvista.OFF_SCREEN set"
assert vtkMapper.GetResolveCoincidentTopology() == resolve, "VTK mapper state changed"
"""
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=env, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]
    folded = imread(tmp_path / "folded.png")[..., :3]
    ink = np.any(folded < 0.9, axis=-1).mean()  # panels and creases on white
    assert 0.05 < ink < 0.9


def test_offset_ring_keeps_a_vanished_edge_of_a_convex_panel_as_a_corner():
    # two creases converging on a 0.5 mm border edge (like Fig. 2's 0.734 mm one)
    sliver = np.array([[0.0, 0.0], [0.5, 0.0], [30.0, 12.0], [0.0, 12.0]])
    crease = np.array([0.0, 2.0, 2.0, 2.0])  # border edge 0 keeps offset 0
    out = offset_ring(sliver, crease, "s")
    assert out.shape == (4, 2)
    assert np.allclose(out[0], out[1])  # the border edge vanished: a corner of zero length
    poly = shapely.Polygon(sliver)
    for k in (1, 2, 3):  # the other edges are exactly 2 mm inside their own sides
        a, b = sliver[k], sliver[(k + 1) % 4]
        side = shapely.LineString([a, b])
        for p in (out[k], out[(k + 1) % 4]):
            assert side.distance(shapely.Point(p)) >= 2.0 - 1e-9
    assert shapely.Polygon(out).area > 0 and poly.contains(shapely.Polygon(out).buffer(-1e-9))
    # a non-convex panel still refuses an edge that would vanish
    notch = np.array([[0, 0], [10, 0], [10, 10], [5.5, 10], [5, 4], [4.5, 10], [0, 10]], float)
    with pytest.raises(PatternError, match="panel n is too small"):
        offset_ring(notch, np.full(7, 1.0), "n")


def _on_offset_line(point, a, b, offset) -> bool:
    """Whether ``point`` lies ``offset`` mm inside the line through ``a`` and ``b`` (CCW)."""
    d = (b - a) / np.hypot(*(b - a))
    return abs((point - a) @ np.array([-d[1], d[0]]) - offset) < 1e-9


def test_offset_ring_joins_collinear_edges_of_different_insets_by_a_jog():
    # a 20 x 10 rectangle whose bottom side is a hinge (inset 1) then a border (inset 0)
    ring = np.array([[0, 0], [8, 0], [20, 0], [20, 10], [0, 10]], float)
    out = offset_ring(ring, np.array([1.0, 0.0, 0.5, 0.5, 0.5]), "j", kinds=[1, 0, 0, 0, 0])
    np.testing.assert_allclose(out, [[0.5, 1], [8, 1], [8, 0], [19.5, 0], [19.5, 9.5], [0.5, 9.5]])
    # equal insets across the jog: two equal points, so every ring of the panel matches
    same = offset_ring(ring, np.full(5, 0.5), "j", kinds=[1, 0, 0, 0, 0])
    assert same.shape == out.shape and np.allclose(same[1], same[2])
    # a side drawn in two nearly straight pieces (the corner 1 um off the line): each piece
    # keeps its own inset, and the jog of every inset lies on one line through the corner
    bent = ring.copy()
    bent[1, 1] = -1e-3
    jogs = []
    for hinge in (0.005, 1.0, 3.0):
        got = offset_ring(bent, np.array([hinge, 0.0, 0.5, 0.5, 0.5]), "b", kinds=[1, 0, 0, 0, 0])
        assert len(got) == 6 and shapely.Polygon(got).is_valid
        assert _on_offset_line(got[1], bent[0], bent[1], hinge)
        assert _on_offset_line(got[2], bent[1], bent[2], 0.0)
        jogs += [got[1], got[2]]
    jogs = np.array(jogs) - bent[1]
    assert np.abs(jogs[:, 0] * jogs[0, 1] - jogs[:, 1] * jogs[0, 0]).max() < 1e-12
    with pytest.raises(PatternError, match="collinear edges with different insets"):
        offset_ring(ring, np.array([1.0, 0.0, 0.5, 0.5, 0.5]), "j", kinds=np.zeros(5))


def _chamfer_violation(points: np.ndarray, outline, params) -> float:
    """How far (mm) any point lies outside the eq. 6 chamfer planes of its panel's creases."""
    half, b = params.half_height, params.bias
    poly = outline.polygon
    worst = 0.0
    for k in np.flatnonzero(outline.crease_edge):
        a, c = poly[k], poly[(k + 1) % len(poly)]
        u = (c - a) / np.linalg.norm(c - a)
        n = np.array([-u[1], u[0]])
        inward = (points[:, :2] - a) @ n
        z = points[:, 2]
        # the chamfer of a half runs from inset b at the outer face to 0 at the crease layer
        depth = np.where(z <= half, (half - z), (z - (params.height - half))) / half
        need = b * np.clip(depth, 0.0, 1.0)
        worst = max(worst, float(np.max(need - inward)))
    return worst


def test_fig2_design_fabricates_or_names_the_panel_and_the_largest_bias(tmp_path):
    """The paper's Fig. 2 design fabricates: the panels too small for the bias get less, named
    in a warning with the largest bias, and the solids are valid."""
    design = load_design(EXAMPLES / "fig2_tg.toml")
    best = largest_bias(design)
    assert 1.5 < best < 2.0
    plan = plan_panels(design)  # b = 3 mm: the panels too small for it get less
    reduced = [plan.pattern.face_labels[i] for i in np.flatnonzero(plan.biases < 3.0)]
    assert "c0r0s3" in reduced and len(reduced) < len(plan.outlines)
    assert plan.biases.min() == pytest.approx(best, abs=0.011)
    assert any(f"{reduced[0]} " in w for w in plan.warnings)
    fab = fabricate(design, FabricationParams(bias=best))
    assert len(fab.outlines) == len(design.pattern.faces) == len(fab.holes)
    for name in PART_NAMES:
        assert fab.parts.solids[name] and all(s.is_valid for s in fab.parts.solids[name])
    # the 0.734 mm border edge of c0r0s3 vanished from its outer face, not the panel
    sliver = fab.plan.outline("c0r0s3")
    lengths = np.hypot(*(np.roll(sliver.polygon, -1, 0) - sliver.polygon).T)
    assert lengths.min() == pytest.approx(0.734, abs=1e-3)
    outer_lengths = np.hypot(*(np.roll(sliver.outer, -1, 0) - sliver.outer).T)
    assert np.sum(outer_lengths < 1e-9) == 1
    # no solid of any panel reaches past its chamfer planes: eq. 6 still holds
    for o, (lower, upper) in zip(fab.outlines, fab.parts.halves, strict=True):
        pts = np.array([[v.X, v.Y, v.Z] for s in (lower, upper) for v in s.vertices()])
        assert _chamfer_violation(pts, o, fab.params) < 1e-6, o.label
    # and its files open in the clients: lib3mf strict reads a valid manifold
    path = write_fabrication(fab, tmp_path)["3mf"]
    model = lib3mf.get_wrapper().CreateModel()
    reader = model.QueryReader("3mf")
    reader.SetStrictModeActive(True)
    reader.ReadFromFile(str(path))
    objects = model.GetMeshObjects()
    while objects.MoveNext():
        mesh = objects.GetCurrentMeshObject()
        assert mesh.IsValid() and mesh.IsManifoldAndOriented()


def test_the_6x4_example_sheet_measures_120_by_120_mm():
    cp = load_design(EXAMPLES / "miura_6x4.toml").pattern
    size = cp.vertices.max(axis=0) - cp.vertices.min(axis=0)
    np.testing.assert_allclose(size, [120.0, 120.0], atol=1e-3)
    plan = plan_panels(cp)  # fabricable at the paper's b = 3 mm, one hole per panel
    assert len(plan.holes) == 24


def test_a_panel_too_small_even_at_the_least_bias_names_the_width_that_prints_it():
    from origami_cad.fabrication.plan import plan_panels

    cp = miura_design(2, 3, 0.3, 0.3, 65.0).pattern  # too small even in TPU alone
    x0, _, x1, _ = cp.bounds
    with pytest.raises(PatternError, match=r"print the pattern at least ([\d.]+) mm wide") as info:
        plan_panels(cp)
    width = float(re.search(r"at least ([\d.]+) mm wide", str(info.value)).group(1))
    assert width > x1 - x0
    # at that width the panels print (at some inner bias), not all of them in TPU alone
    plan = plan_panels(cp.scaled(width / (x1 - x0)))
    assert plan.pattern.faces and len(plan.tpu_only) < len(cp.faces)
