"""origami_cad as a build123d user meets it: parts in a BuildPart, joints, an assembly STEP.

Written as such a user's script would be: a base plate in ``BuildPart`` with our parts at
``Location`` s, joints that connect, a user's ``Compound`` holding our assembly written
with build123d's own ``export_step`` and read back with ``import_step``, and the fits of
the standalone TSA module (its guide and servo on its mount).
"""

from __future__ import annotations

import numpy as np
import pytest
from build123d import (
    Align,
    BasePartObject,
    Box,
    BuildPart,
    Color,
    Compound,
    Location,
    Locations,
    Mode,
    Part,
    RigidJoint,
    export_step,
    import_step,
)
from origami_cad.parts import Blocker, DriverAdapter, RingRail, TSAModule
from origami_cad.parts.robot import BlockerPlacement, ModulePlacement, robot_assembly

import origami_cad as oc
from origami_cad.fabrication import fabricate
from origami_cad.fabrication.assembly import MATERIAL_COLORS, solids_by_part
from origami_cad.fabrication.solids import PART_MATERIALS
from origami_cad.pattern.design import miura_design

PARTS = [TSAModule, RingRail, Blocker, DriverAdapter]


@pytest.fixture(scope="module")
def fab():
    return fabricate(miura_design(2, 3, 30.0, 30.0, 65.0))


def _points(shape) -> np.ndarray:
    return np.array(sorted(tuple(round(c, 6) for c in v) for v in shape.vertices()))


def _same_place(a, b, tol: float = 1e-6) -> None:
    """Two shapes with the same vertices (to ``tol`` mm) and the same volume."""
    pa, pb = _points(a), _points(b)
    assert pa.shape == pb.shape
    assert np.abs(pa - pb).max() < tol
    assert a.volume == pytest.approx(b.volume, rel=1e-9)


@pytest.mark.parametrize("cls", PARTS, ids=lambda c: c.__name__)
def test_each_part_is_a_build123d_part_built_at_its_defaults(cls):
    part = cls()
    assert isinstance(part, BasePartObject) and isinstance(part, Part)
    assert part.volume > 0 and part.is_valid
    assert part.joints and all(isinstance(j, RigidJoint) for j in part.joints.values())
    assert [c.label for c in part.children]  # labelled children
    assert part.label in part.info


def test_a_base_plate_with_a_module_and_a_blocker_adds_up_exactly():
    module, blocker = TSAModule(), Blocker()
    with BuildPart() as bp:
        plate = Box(200, 100, 4, align=(Align.CENTER, Align.CENTER, Align.MAX))
        with Locations(Location((-40, 0, 0))):
            placed = TSAModule()
        with Locations(Location((60, 20, 0), (0, 0, 1), 30)):
            Blocker()
    assert bp.part.volume == pytest.approx(plate.volume + module.volume + blocker.volume, rel=1e-9)
    # the user's plate is exactly as it was: the part less what we added is the plate
    ours = [placed, Blocker().moved(Location((60, 20, 0), (0, 0, 1), 30))]
    rest = bp.part
    for shape in ours:
        rest = rest - shape
    assert rest.volume == pytest.approx(200 * 100 * 4, rel=1e-9)
    box = rest.bounding_box()
    assert (box.min.X, box.max.X, box.min.Z, box.max.Z) == pytest.approx((-100, 100, -4, 0))
    # the part added at the builder's location, its children and joints with it
    mount = next(c for c in placed.children if c.label == "mount")
    alone = next(c for c in module.children if c.label == "mount")
    assert mount.bounding_box().min.X == pytest.approx(alone.bounding_box().min.X - 40.0)
    assert tuple(placed.joints["mount"].location.position) == pytest.approx((-40.0, 0.0, 0.0))


def test_no_construction_geometry_leaks_into_the_users_builder():
    """The issue's report: a 1,000 mm^3 box became 170,025 mm^3 with a ring rail inside."""
    rail, adapter = RingRail(), DriverAdapter()
    with BuildPart() as bp:
        Box(10, 10, 10)
        with Locations((300, 0, 0)):
            RingRail()
        with Locations((0, 300, 0)):
            DriverAdapter()
    assert bp.part.volume == pytest.approx(1000 + rail.volume + adapter.volume, rel=1e-9)


def test_a_part_combines_in_the_mode_given():
    adapter = DriverAdapter()
    box = adapter.bounding_box()
    with BuildPart() as bp:
        Box(box.size.X + 10, box.size.Y + 10, 2, align=(Align.MIN, Align.MIN, Align.MIN))
        with Locations((5, 5, 0)):
            DriverAdapter(mode=Mode.SUBTRACT)
    full = (box.size.X + 10) * (box.size.Y + 10) * 2
    inside = adapter.moved(Location((5, 5, 0))) & Box(
        box.size.X + 10, box.size.Y + 10, 2, align=(Align.MIN, Align.MIN, Align.MIN)
    )
    assert bp.part.volume == pytest.approx(full - inside.volume, rel=1e-9)
    assert bp.part.volume < full - 100  # really cut


def test_rotation_and_align_move_the_part_its_children_and_joints():
    flat = TSAModule()
    turned = TSAModule(rotation=(0, 0, 90), align=(Align.MIN, Align.MIN, Align.MIN))
    assert turned.volume == pytest.approx(flat.volume, rel=1e-9)
    a, b = flat.bounding_box(), turned.bounding_box()
    assert (b.size.X, b.size.Y) == pytest.approx((a.size.Y, a.size.X))  # turned by 90 deg
    # align MIN then a 90 deg turn about z: y from 0, x up to 0
    assert (b.max.X, b.min.Y, b.min.Z) == pytest.approx((0.0, 0.0, 0.0), abs=1e-9)
    union = Compound([c for c in turned.children]).bounding_box()
    assert (union.min.X, union.max.Y) == pytest.approx((b.min.X, b.max.Y))
    hub = turned.joints["hub"].location  # the twist axis turned to +y
    assert tuple(hub.z_axis.direction) == pytest.approx((0.0, 1.0, 0.0), abs=1e-9)


def test_connect_to_places_a_module_and_a_blocker_where_robot_places_them(fab):
    label, crease = "c0r1s1", 14  # a valley crease with c0r1s0 on its left
    assert fab.pattern.assignments[crease] == "V"
    ratio = 0.3
    robot = robot_assembly(
        fab,
        modules=[ModulePlacement("module", label)],
        blockers=[BlockerPlacement("stop", crease, 60.0), BlockerPlacement("under", 11, 50.0)],
        ratio=ratio,
    )
    sheet = fab.assembly(ratio)
    panels = {c.label: c for c in sheet.children}
    # a module for that panel, somewhere else entirely, put on by the joints
    module = TSAModule(plan=fab.plan, panel=label).moved(Location((500, -80, 40), (1, 1, 0), 70))
    panels[label].joints["mount"].connect_to(module.joints["mount"])
    _same_place(module, robot.solids["module"])
    for child in module.children:  # the children went with it, the mount on the panel
        twin = next(c for c in robot.solids["module"].children if c.label == child.label)
        _same_place(child, twin)
    left = fab.pattern.face_labels[int(fab.pattern.edge_faces()[crease][0])]
    stop = Blocker(fab.plan, crease, angle=60.0).moved(Location((-20, 30, 5)))
    panels[left].joints[f"blocker {crease}"].connect_to(stop.joints["crease"])
    _same_place(stop, robot.solids["stop"])
    # a mountain crease: the mirrored blocker, under the sheet
    assert fab.pattern.assignments[11] == "M"
    left = fab.pattern.face_labels[int(fab.pattern.edge_faces()[11][0])]
    under = Blocker(fab.plan, 11, angle=50.0, mountain=True).moved(Location((3, 4, 5)))
    panels[left].joints["blocker 11"].connect_to(under.joints["crease"])
    _same_place(under, robot.solids["under"])


def test_a_standalone_module_connects_to_a_users_joint():
    base = Box(80, 80, 5, align=(Align.CENTER, Align.CENTER, Align.MAX))
    RigidJoint("seat", base, Location((10, -5, 0), (0, 0, 1), 45))
    module = TSAModule()
    base.joints["seat"].connect_to(module.joints["mount"])
    assert tuple(module.joints["mount"].location.position) == pytest.approx((10, -5, 0))
    mount = next(c for c in module.children if c.label == "mount")
    assert mount.bounding_box().min.Z == pytest.approx(0.0, abs=1e-9)  # on the base's top
    assert (mount & base) is None or (mount & base).volume < 1e-9


def test_crease_joints_carry_the_fold_angle(fab):
    sheet = fab.assembly(0.4)
    panels = list(sheet.children[:-1])
    checked = 0
    for a in panels:
        for name, joint in a.joints.items():
            if not hasattr(joint, "fold_angle"):
                continue
            b = next(p for p in panels if p is not a and name in p.joints)
            # at its fold angle the revolute joint leaves panel B where the folding put it
            place = a.location * joint.relative_to(b.joints[name], angle=joint.fold_angle)
            assert np.abs(tuple(place.position)).max() < 1e-6
            assert np.abs(tuple(place.orientation)).max() < 1e-6
            # any other angle moves it
            other = a.location * joint.relative_to(b.joints[name], angle=joint.fold_angle + 5)
            assert (
                np.abs(tuple(other.position)).max() > 1e-3
                or np.abs(tuple(other.orientation)).max() > 1.0
            )
            e = int(name.split()[1])
            sign = 1 if fab.pattern.assignments[e] == "V" else -1
            assert sign * joint.fold_angle > 0  # valley positive
            checked += 1
    assert checked == 7  # the 2 x 3 Miura's inner creases


def _tree(shape) -> list[tuple[int, str, tuple | None]]:
    """(depth, label, leaf colour) of every node; labels as build123d's ``import_step``
    gives them (it turns spaces, dots and brackets into underscores)."""
    out, stack = [], [(0, shape)]
    while stack:
        depth, node = stack.pop(0)
        color = tuple(round(c, 2) for c in tuple(node.color)[:3]) if node.color else None
        label = node.label.translate(str.maketrans(" .()", "____"))
        out.append((depth, label, color if not node.children else None))
        stack[:0] = [(depth + 1, c) for c in node.children]
    return out


def test_an_assembly_nested_in_a_users_compound_keeps_its_tree_in_step(fab, tmp_path):
    sheet = fab.assembly(0.2)
    module = TSAModule(plan=fab.plan, panel="c0r1s1")
    sheet.children[4].joints["mount"].connect_to(module.joints["mount"])
    module.color = Color(0.25, 0.25, 0.25)
    stand = Box(20, 20, 20).moved(Location((0, 0, -30)))
    stand.label, stand.color = "stand", Color(0.1, 0.4, 0.8)
    user = Compound(children=[sheet, module, stand])
    user.label = "user_robot"
    export_step(user, str(tmp_path / "user.step"))  # build123d's own exporter
    back = import_step(tmp_path / "user.step")
    assert _tree(back)[0][1] == "user_robot"
    got, want = _tree(back), _tree(user)
    # same labels at the same depths; every solid of the sheet in its material's colour
    assert [(d, lbl) for d, lbl, _ in got] == [(d, lbl) for d, lbl, _ in want]
    leaves = {lbl: c for d, lbl, c in got if c is not None}
    for leaf in solids_by_part(sheet)["shells"] + solids_by_part(sheet)["midlayers"]:
        part = "shells" if "_shell_" in leaf.label else "midlayers"
        hexa = MATERIAL_COLORS[PART_MATERIALS[part]].lstrip("#")
        rgb = tuple(round(int(hexa[i : i + 2], 16) / 255, 2) for i in (0, 2, 4))
        assert leaves[leaf.label] == pytest.approx(rgb, abs=0.01)
    # where build123d bites: the sheet, once nested, no longer exports on its own;
    # export_step_tree writes it, tree and colours kept
    with pytest.raises(RuntimeError):
        export_step(sheet, str(tmp_path / "alone.step"))
    oc.export_step_tree(sheet, tmp_path / "alone.step")
    alone = import_step(tmp_path / "alone.step")
    assert [(d, lbl, c) for d, lbl, c in _tree(alone)] == [
        (d - 1, lbl, c) for d, lbl, c in got[1 : 1 + len(_tree(sheet))]
    ]


def test_the_standalone_module_stands_on_its_mount():
    module = TSAModule()
    parts = {c.label: c for c in module.children}
    mount, guide, servo = parts["mount"], parts["guide"], parts["servo"]
    top = mount.bounding_box().max.Z
    for name in ("guide", "servo"):
        box = parts[name].bounding_box()
        assert box.min.Z == pytest.approx(top, abs=1e-9), name  # touching the mount
        # its footprint inside the mount's
        m = mount.bounding_box()
        assert m.min.X <= box.min.X and box.max.X <= m.max.X, name
        assert m.min.Y <= box.min.Y and box.max.Y <= m.max.Y, name
    # the guide's whole bottom face touches the mount's top face: shared area, not a gap
    bottom = guide.faces().sort_by()[0]
    face_top = mount.faces().sort_by()[-1]
    assert (bottom & face_top).area == pytest.approx(bottom.area, rel=1e-9)
    assert servo.bounding_box().min.Z == pytest.approx(top)
    # and it still fits at another heading and servo
    other = TSAModule(servo="XL430", heading=35.0)
    parts = {c.label: c for c in other.children}
    for name in ("guide", "servo"):
        inter = parts[name].faces().sort_by()[0] & parts["mount"].faces().sort_by()[-1]
        assert inter.area == pytest.approx(parts[name].faces().sort_by()[0].area, rel=1e-6)
