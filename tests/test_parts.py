"""Parametric parts: valid closed solids, sensible volumes, and the fits they promise."""

from __future__ import annotations

import math
import runpy
from pathlib import Path

import numpy as np
import origami_cad.parts
import pytest
import shapely
import trimesh
from build123d import Axis, Compound, Vector, import_step
from origami_cad.parts import (
    PARTS,
    BlockerParams,
    Placement,
    RingRailParams,
    blocker,
    blocker_frame,
    build_part,
    driver_adapter,
    parse_part_options,
    parts_listing,
    ring_anchor_points,
    ring_rail,
    tsa_module,
)
from origami_cad.parts.parameters import param_info

import origami_cad as oc
from origami_cad.cli import main
from origami_cad.errors import FabricationError, PatternError
from origami_cad.fabrication import FabricationParams, fabricate, plan_panels, theta_max
from origami_cad.fabrication.exports import export_part
from origami_cad.pattern import CreasePattern
from origami_cad.pattern.design import load_design
from origami_cad.strings import TSAParams

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def solids_of(shape):
    return list(shape.solids())


def assert_valid_and_watertight(shape, tmp_path, name):
    assert shape.is_valid and all(s.is_valid for s in solids_of(shape))
    step, stl = export_part(shape, tmp_path, name)
    bodies = trimesh.load(stl).split(only_watertight=False)
    assert bodies and all(b.is_watertight for b in bodies)
    back = import_step(step)
    assert back.volume == pytest.approx(shape.volume, rel=1e-6)


@pytest.mark.parametrize(
    "name, kwargs",
    [
        ("driver-adapter", {}),
        ("driver-adapter", {"connectors": 7, "board_width": 30.0, "thickness": 4.0}),
        ("ring-rail", {}),
        ("ring-rail", {"inner_diameter": 200.0, "angles": (0.0, 120.0, 240.0)}),
        ("tsa-module", {}),
        ("tsa-module", {"servo": "XL430", "guide_distance": 30.0}),
        ("blocker", {}),
        ("blocker", {"angle": 30.0, "length": 16.0}),
    ],
)
def test_every_part_is_a_valid_closed_solid(name, kwargs, tmp_path):
    shape = build_part(name, kwargs)
    assert_valid_and_watertight(shape, tmp_path, name)
    assert shape.volume > 0


def test_driver_adapter_volume_is_the_plate_minus_its_cuts():
    plate = driver_adapter(
        connectors=5,
        board_width=25,
        board_length=45,
        thickness=3.0,
        margin=6.0,
        pitch=8.0,
        slot_width=7.8,
        slot_depth=2.8,
        mounting_hole=3.2,
        pocket=1.2,
    )
    width, length = 25 + 12, 45 + 5 * 8 + 18
    expected = (
        width * length * 3.0 - 25 * 45 * 1.2 - 5 * 7.8 * 2.8 * 3.0 - 4 * math.pi * 1.6**2 * 3.0
    )
    assert plate.volume == pytest.approx(expected, rel=1e-6)
    with pytest.raises(FabricationError, match=r"connectors: expected an integer in 1\.\.64"):
        driver_adapter(connectors=0)


def test_ring_rail_anchors_sit_in_the_carriage_eyelets():
    angles = (30.0, 150.0, 270.0)
    rail = ring_rail(inner_diameter=150.0, angles=angles, centre=(60.0, 60.0), z_top=20.0)
    labels = [c.label for c in rail.children]
    assert labels[0] == "rail" and len(labels) == 4
    anchors = ring_anchor_points(inner_diameter=150.0, angles=angles, centre=(60, 60), z_top=20)
    for a, (x, y, z) in zip(angles, anchors, strict=True):
        assert math.hypot(x - 60, y - 60) == pytest.approx(73.0)  # the wall's inner face
        carriage = next(c for c in rail.children if f"({a:g} deg)" in c.label)
        ca, sa = math.cos(math.radians(a)), math.sin(math.radians(a))
        for depth in (0.2, 1.0, 1.8):  # along the eyelet, through the wall: no material
            assert not carriage.is_inside(Vector(x + depth * ca, y + depth * sa, z))
        # but the wall is there just beside the eyelet
        assert carriage.is_inside(Vector(x + ca - 1.6 * sa, y + sa + 1.6 * ca, z))
    ring = rail.children[0]
    assert ring.volume == pytest.approx(math.pi * (87**2 - 75**2) * 8.0, rel=1e-3)  # width 12


def test_tsa_hub_holes_follow_the_tsa_model_d1():
    for d1 in (10.0, 14.0):
        module = tsa_module(tsa=TSAParams(d1=d1))
        hub = next(c for c in module.children if c.label == "hub")
        bb = hub.bounding_box()
        x_mid, z_axis = (bb.min.X + bb.max.X) / 2, (bb.min.Z + bb.max.Z) / 2
        for sign in (1, -1):
            assert not hub.is_inside(Vector(x_mid, sign * d1 / 2, z_axis))  # the anchor hole
            assert hub.is_inside(Vector(x_mid, sign * (d1 / 2 + 1.5), z_axis))
        assert hub.is_inside(Vector(x_mid, 0.0, z_axis))


def test_tsa_mount_fits_its_panel_and_its_holes():
    design = load_design(EXAMPLES / "miura_6x4.toml")
    plan = plan_panels(design)  # no solid is built
    module = tsa_module(plan=plan, panel="c0r1s2")
    mount = next(c for c in module.children if c.label == "mount")
    fi = plan.pattern.face_index("c0r1s2")
    outline = plan.outlines[fi]
    bb = mount.bounding_box()
    assert bb.min.Z == pytest.approx(plan.params.height)  # on the panel's outer face
    footprint = shapely.MultiPoint([(v.X, v.Y) for v in mount.vertices()]).convex_hull
    assert shapely.Polygon(outline.outer).buffer(1e-6).contains(footprint)
    (hole,) = [h for h, i in zip(plan.holes, plan.hole_panels, strict=True) if i == fi]
    x, y, d = hole.x, hole.y, hole.diameter
    z = plan.params.height + 1.5
    assert not mount.is_inside(Vector(x, y, z))  # the panel's hole goes through the mount
    assert mount.is_inside(Vector(x + d / 2 + 0.5, y, z))
    with pytest.raises(FabricationError, match="unknown servo"):
        tsa_module(servo="XM999")


def two_panels() -> CreasePattern:
    v = [[0, 0], [40, 0], [80, 0], [80, 40], [40, 40], [0, 40]]
    e = [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 0], [1, 4]]
    return CreasePattern(v, e, ["B"] * 6 + ["V"])


@pytest.mark.parametrize("angle", [60.0, 35.0])
def test_blocker_stops_the_fold_at_its_angle(angle):
    fab = fabricate(two_panels(), FabricationParams(holes="none"))
    crease = int(np.flatnonzero(fab.pattern.assignments == "V")[0])
    blk = blocker(fab.plan, crease, angle=angle)
    start, direction, _, face_a, face_b = blocker_frame(fab.pattern, crease)
    panel_a = Compound(list(fab.parts.halves[face_a]))
    panel_b = Compound(list(fab.parts.halves[face_b]))
    hinge_z = (fab.params.height + fab.params.thickness) / 2
    axis = Axis((start[0], start[1], hinge_z), (direction[0], direction[1], 0.0))

    def overlap(a, b) -> float:
        common = a & b
        return sum(s.volume for s in common.solids()) if common else 0.0

    assert overlap(panel_a, blk) < 1e-9  # it sits on panel A
    for below in (0.0, angle / 2, angle - 2.0):
        turned = panel_b.rotate(axis, -below)
        assert turned.distance_to(blk) > 1e-3 and overlap(turned, blk) < 1e-9
    at = panel_b.rotate(axis, -angle)
    assert at.distance_to(blk) < 1e-6 and overlap(at, blk) < 1e-6  # contact
    assert overlap(panel_b.rotate(axis, -(angle + 2.0)), blk) > 1e-2  # beyond: blocked
    with pytest.raises(FabricationError, match="theta_max"):
        blocker(fab.plan, crease, angle=170.0)


def test_cli_part_and_the_assembly_example(tmp_path, capsys):
    assert main(["part", "--list"]) == 0
    listing = capsys.readouterr().out
    assert listing.strip() == parts_listing()
    for name, spec in PARTS.items():
        assert f"{name}: " in listing
        for info in param_info(spec.params):
            if info.text:
                assert f"--{info.name.replace('_', '-')} " in listing
    assert "--horn-offset FLOAT or none (mm)" in listing
    assert "--angles FLOAT,... (deg)" in listing
    assert main(["part", "driver-adapter", "-o", str(tmp_path), "--connectors", "3"]) == 0
    assert (tmp_path / "driver-adapter.step").is_file()
    assert main(["part", "driver-adapter", "-o", str(tmp_path), "--connectors", "x"]) == 2
    assert main(["part", "nope", "-o", str(tmp_path)]) == 2
    module = runpy.run_path(str(EXAMPLES / "assemble_arm.py"))
    path = module["main"](tmp_path / "arm")
    assembly = import_step(path)

    def labels(shape) -> set[str]:
        out = {shape.label}
        for child in getattr(shape, "children", ()):
            out |= labels(child)
        return out

    found = labels(assembly)
    assert {"infills", "shells", "creases", "midlayers"} <= found
    assert {"servo", "hub", "guide", "mount"} <= found


def test_text_parameters_get_their_declared_types():
    # the default of horn_offset is None: the text must still become a float (it was '12')
    module = build_part("tsa-module", {"horn-offset": "12"})
    servo = next(c for c in module.children if c.label == "servo")
    assert servo.bounding_box().min.Y == pytest.approx(-12.0)
    rail = build_part("ring-rail", {"angles": "0, 120, 240", "centre": "10,20"})
    assert [c.label for c in rail.children[1:]] == [
        "carriage 1 (0 deg)",
        "carriage 2 (120 deg)",
        "carriage 3 (240 deg)",
    ]
    assert rail.children[0].center().X == pytest.approx(10.0, abs=1e-6)
    plate = build_part("driver-adapter", {"connectors": 2, "thickness": 4})  # typed values
    assert plate.label == "driver adapter (2 connectors)"
    assert plate.bounding_box().size.Z == pytest.approx(4.0)
    assert parse_part_options(["--horn-offset", "12"]) == {"horn_offset": "12"}
    with pytest.raises(FabricationError, match="--angle is given twice"):
        parse_part_options(["--angle", "30", "--angle", "45"])


@pytest.mark.parametrize(
    "name, values, message",
    [
        (
            "tsa-module",
            {"horn_offset": "twelve"},
            r"horn_offset \(mm\): .* in \[-10000, 10000\], got twelve",
        ),
        ("tsa-module", {"body": "20,34"}, "parameter body: expected 3 comma-separated"),
        ("tsa-module", {"tsa": "10"}, "parameter tsa: expected a TSAParams"),
        (
            "driver-adapter",
            {"connectors": "2.5"},
            "connectors: expected an integer in 1..64, got 2.5",
        ),
        ("driver-adapter", {"connectors": 2.5}, "parameter connectors: expected an integer"),
        (
            "driver-adapter",
            {"pitch": "-3"},
            r"parameter pitch \(mm\): .* in \[0.001, 10000\], got -3",
        ),
        ("ring-rail", {"angles": "0,nan"}, r"angles \(deg\): .* in \[-360, 360\], got nan"),
        ("blocker", {"angel": "30"}, "unknown parameter 'angel'"),
        ("blocker", {"angle": True}, r"parameter angle \(deg\): expected a finite .* got True"),
        ("nope", {}, "unknown part 'nope'"),
        # stated bounds, before the B-rep kernel fails on them (or never ends)
        (
            "tsa-module",
            {"guide_distance": "1e300"},
            r"guide_distance \(mm\): .* in \[0.5, 10000\], got 1e300",
        ),
        (
            "tsa-module",
            {"centre": "-1e300,0"},
            r"centre \(mm\): .* in \[-10000, 10000\], got -1e300",
        ),
        ("blocker", {"reach": -1e300}, r"reach \(mm\): .* in \[0.001, 10000\], got -1e\+300"),
        ("tsa-module", {"heading": "1e300"}, r"heading \(deg\): .* in \[-360, 360\], got 1e300"),
        ("driver-adapter", {"connectors": 10**12}, r"connectors: .* in 1\.\.64, got 1000000000000"),
        ("ring-rail", {"angles": ",".join(["1"] * 65)}, "angles: 65 values, at most 64"),
        # parameters that cannot make the part, refused by name with the limit
        ("ring-rail", {"eyelet": 50, "width": 12}, r"eyelet: 50 mm .* must be < 8 mm"),
        ("ring-rail", {"lock_screw": 40}, r"lock_screw: 40 mm .* must be < 12 mm"),
        ("ring-rail", {"angles": "0,90,90"}, r"angles: carriages 2 \(90 deg\) and 3 .* overlap"),
        ("ring-rail", {"angles": "0,359"}, r"carriages 2 \(359 deg\) and 1 \(0 deg\) overlap"),
        ("driver-adapter", {"slot_depth": 9, "pitch": 8}, r"slot_depth: 9 mm .* must be < 8 mm"),
        ("driver-adapter", {"mounting_hole": 60}, r"mounting_hole: 60 mm .* must be < 6 mm"),
        ("tsa-module", {"guide_hole": 500}, r"guide_hole: 500 mm .* must be < \d+ mm"),
        ("tsa-module", {"horn_offset": 1e4}, r"horn_offset: 10000 mm .* in \[0, 34\] mm"),
        ("blocker", {"clearance": -1}, r"clearance \(mm\): .* in \[0, 10000\], got -1"),
        ("blocker", {"reach": -2}, r"reach \(mm\): .* in \[0.001, 10000\], got -2"),
        (
            "tsa-module",
            {"guide_distance": 0.01},
            r"guide_distance \(mm\): .* \[0.5, 10000\], got 0.01",
        ),
    ],
)
def test_bad_part_parameters_are_named(name, values, message):
    with pytest.raises(FabricationError, match=message):
        build_part(name, values)


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (["tsa-module", "--guide-distance", "0.1"], "--guide-distance (mm): expected a finite "
         "number in [0.5, 10000], got 0.1"),
        (["blocker", "--reach", "-1"], "--reach (mm): expected a finite number in [0.001, 10000]"),
        (["ring-rail", "--eyelet", "50"], "--eyelet: 50 mm does not fit"),
    ],
)  # fmt: skip
def test_the_command_line_names_a_part_parameter_as_it_was_typed(tmp_path, capsys, argv, said):
    code = main(["part", *argv, "-o", str(tmp_path / "p")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and said in err, err
    assert not (tmp_path / "p").exists()


def test_placement_follows_the_registry(tmp_path):
    assert {n: s.placement for n, s in PARTS.items()} == {
        "tsa-module": Placement.PANEL,
        "ring-rail": Placement.NONE,
        "blocker": Placement.CREASE,
        "driver-adapter": Placement.NONE,
    }
    design = EXAMPLES / "miura_6x4.toml"
    with pytest.raises(FabricationError, match="give the panel label"):
        build_part("tsa-module", pattern=design)
    with pytest.raises(FabricationError, match="give the crease edge"):
        build_part("blocker", pattern=design)
    with pytest.raises(FabricationError, match="not placed on a pattern"):
        build_part("ring-rail", pattern=design)
    with pytest.raises(FabricationError, match="need --pattern"):
        build_part("blocker", crease=3)
    with pytest.raises(PatternError, match="no panel labelled 'zz'"):
        build_part("tsa-module", pattern=design, panel="zz")
    code = main(["part", "tsa-module", "-o", str(tmp_path), "--pattern", str(design)])
    assert code == 2


def test_every_part_parameter_has_a_type_a_unit_or_none_and_a_doc():
    for spec in PARTS.values():
        for info in param_info(spec.params):
            assert info.doc, (spec.name, info.name)
            assert info.unit in ("", "mm", "deg"), (spec.name, info.name)
            if info.unit:  # lengths and angles are numbers
                assert "FLOAT" in info.type_name, (spec.name, info.name)


def test_blocker_limit_is_eq6_of_its_panels():
    params = BlockerParams(bias=1.0, height=3.0, thickness=1.0)
    limit = math.degrees(theta_max(1.0, 3.0, 1.0))  # 90 deg
    blocker(params=params, angle=limit - 1.0)
    with pytest.raises(FabricationError, match=f"\\(0, {limit:.1f}\\) deg"):
        blocker(params=params, angle=limit + 1.0)


def test_parts_are_installed_inside_the_package():
    import tomllib

    import origami_cad.parts

    root = Path(__file__).resolve().parents[1]
    assert Path(origami_cad.parts.__file__).parent == root / "parts"
    setup = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"]
    assert setup["package-dir"] == {
        "origami_cad.parts": "parts",
        "origami_cad.examples": "examples",
    }
    found = {
        ".".join(p.parent.relative_to(root).parts)
        for p in (root / "origami_cad").rglob("__init__.py")
    }
    # the examples' data folders are listed as packages too (no setuptools warning)
    data = {
        ".".join(("origami_cad", *p.relative_to(root).parts))
        for p in (root / "examples").rglob("*")
        if p.is_dir() and p.name != "__pycache__"
    }
    assert len(data) >= 4
    assert set(setup["packages"]) == found | {"origami_cad.parts", "origami_cad.examples"} | data


@pytest.mark.parametrize(
    "kwargs",
    [
        {},
        {"inner_diameter": 200.0, "angles": (0.0, 120.0, 240.0)},
        {"inner_diameter": 60.0, "width": 8.0, "carriage_length": 30.0, "angles": (-30.0, 90.0)},
    ],
)
def test_ring_rail_carriages_fit_the_ring_with_clearance_everywhere(kwargs):
    """No carriage overlaps the curved ring, and each keeps the clearance from it (straight
    carriages overlapped it by 39 mm^3 each)."""
    from origami_cad.parts.ring_rail import CLEARANCE

    rail = ring_rail(**kwargs)
    ring, carriages = rail.children[0], rail.children[1:]
    assert len(carriages) == len(kwargs.get("angles", RingRailParams().angles))
    for carriage in carriages:
        assert carriage.is_valid and carriage.volume > 0
        common = ring & carriage
        overlap = sum(s.volume for s in common.solids()) if common else 0.0
        assert overlap == 0.0, carriage.label
        assert ring.distance_to(carriage) >= CLEARANCE - 1e-6, carriage.label
        # and the carriage does hold the ring: it is no further than the clearance
        assert ring.distance_to(carriage) == pytest.approx(CLEARANCE, abs=1e-6)


def _placed_parts():
    design = load_design(EXAMPLES / "miura_6x4.toml")
    plan = plan_panels(design)
    crease = int(np.flatnonzero(plan.pattern.assignments == "V")[0])
    return [
        ("blocker-on-crease", blocker(plan, crease, angle=45.0)),
        ("tsa-module-on-panel", tsa_module(plan=plan, panel="c0r1s2")),
        ("ring-rail-high", ring_rail(z_top=35.0)),
    ]


def test_every_exported_part_lies_on_the_bed(tmp_path):
    """Every part's STL and STEP has its lowest point at z = 0 (slicers place it there)."""
    shapes = [(name, build_part(name)) for name in PARTS] + _placed_parts()
    for name, shape in shapes:
        step, stl = export_part(shape, tmp_path / name, name)
        mesh = trimesh.load(stl)
        assert mesh.bounds[0][2] == pytest.approx(0.0, abs=1e-6), name
        size = shape.bounding_box().size
        assert mesh.extents[2] == pytest.approx(size.Z, abs=1e-3), name  # moved, not cut
        back = import_step(step)
        assert back.bounding_box().min.Z == pytest.approx(0.0, abs=1e-6), name
        assert back.volume == pytest.approx(shape.volume, rel=1e-6), name
        # x and y as built
        assert back.bounding_box().min.X == pytest.approx(shape.bounding_box().min.X, abs=1e-6)
    # an assembly keeps its named children
    _, rail = shapes[list(PARTS).index("ring-rail")]
    step, _ = export_part(rail, tmp_path / "labels", "ring-rail")
    children = import_step(step).children
    assert children[0].label == "rail" and len(children) == len(rail.children)


def test_parts_refuse_what_cannot_be_placed():
    fab = fabricate(load_design(EXAMPLES / "arm_design.toml"))
    with pytest.raises(FabricationError, match="larger than panel 'c1r0s0'"):
        oc.parts.TSAModule(plan=fab.plan, panel="c1r0s0", body=(200, 200, 200), horn_offset=10)
    with pytest.raises(FabricationError, match="panel needs plan"):
        oc.parts.TSAModule(panel="c1r0s0")
    crease = int(np.flatnonzero(fab.plan.pattern.assignments == "V")[0])
    with pytest.raises(FabricationError, match=r"crease must be an edge index .* got 1.5"):
        oc.parts.Blocker(fab.plan, 1.5)
    with pytest.raises(FabricationError, match="crease needs plan"):
        oc.parts.Blocker(None, crease)
    assert oc.parts.Blocker(fab.plan, crease).volume > 0  # the valid call still builds
