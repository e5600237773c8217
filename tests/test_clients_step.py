"""STEP read back as FreeCAD reads it: OCP's XCAF reader, colours resolved per solid.

FreeCAD's STEP importer walks the XCAF label tree and gives each solid the colour of
its own label (or of the component that places it); a solid without one takes its
parent's label colour only when that parent holds that single solid. A colour set on
a compound of many solids is lost (once only ``creases`` came in red).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from OCP.collections import Sequence_TDF_Label as TDF_LabelSequence
from OCP.IFSelect import IFSelect_RetDone
from OCP.Quantity import Quantity_Color, Quantity_TOC_sRGB
from OCP.STEPCAFControl import STEPCAFControl_Reader
from OCP.TCollection import TCollection_ExtendedString
from OCP.TDataStd import TDataStd_Name
from OCP.TDF import TDF_Label
from OCP.TDocStd import TDocStd_Document
from OCP.TopAbs import TopAbs_SOLID
from OCP.TopExp import TopExp_Explorer
from OCP.XCAFDoc import XCAFDoc_ColorGen, XCAFDoc_ColorSurf, XCAFDoc_DocumentTool

from origami_cad.fabrication import FabricationParams, fabricate
from origami_cad.fabrication.assembly import MATERIAL_COLORS
from origami_cad.fabrication.exports.step import export_step_assembly
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES
from origami_cad.pattern.design import miura_design


def _name(label: TDF_Label) -> str:
    attr = TDataStd_Name()
    if label.FindAttribute(TDataStd_Name.GetID_s(), attr):
        return attr.Get().ToExtString()
    return ""


def _own_colour(color_tool, label: TDF_Label) -> tuple[float, float, float] | None:
    colour = Quantity_Color()
    for kind in (XCAFDoc_ColorSurf, XCAFDoc_ColorGen):
        if color_tool.GetColor_s(label, kind, colour):
            rgb = colour.Values(Quantity_TOC_sRGB)
            return tuple(round(c, 3) for c in rgb)
    return None


def _solids(shape) -> int:
    exp, n = TopExp_Explorer(shape, TopAbs_SOLID), 0
    while exp.More():
        n += 1
        exp.Next()
    return n


def read_step_colours(path: Path) -> dict[str, list[tuple[float, float, float] | None]]:
    """The colour FreeCAD would give each solid, grouped by the name of its top-level part.

    A leaf label (no components) that holds one solid takes its own colour (or that of
    the component placing it), else its parent's; a leaf holding several solids gives
    each the colour of the solid sub-shape itself, if any (a compound's colour is lost).
    """
    doc = TDocStd_Document(TCollection_ExtendedString("XmlOcaf"))
    reader = STEPCAFControl_Reader()
    reader.SetColorMode(True)
    reader.SetNameMode(True)
    assert reader.ReadFile(str(path)) == IFSelect_RetDone
    assert reader.Transfer(doc)
    shape_tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    color_tool = XCAFDoc_DocumentTool.ColorTool_s(doc.Main())
    out: dict[str, list] = {}

    def walk(label, inherited, part):
        ref = TDF_Label()
        target = label
        if shape_tool.IsReference_s(label) and shape_tool.GetReferredShape_s(label, ref):
            target = ref
        own = _own_colour(color_tool, label) or _own_colour(color_tool, target)
        name = _name(label) or _name(target)
        children = TDF_LabelSequence()
        shape_tool.GetComponents_s(target, children)
        if children.Length():
            for i in range(1, children.Length() + 1):
                walk(children.Value(i), own or inherited, part)
            return
        shape = shape_tool.GetShape_s(target)
        n = _solids(shape)
        colour = (own or inherited) if n == 1 else None
        key = part or name
        out.setdefault(key, []).extend([colour] * n)

    def walk_top(label):
        children = TDF_LabelSequence()
        shape_tool.GetComponents_s(label, children)
        for i in range(1, children.Length() + 1):
            comp = children.Value(i)
            ref = TDF_Label()
            target = comp
            if shape_tool.IsReference_s(comp) and shape_tool.GetReferredShape_s(comp, ref):
                target = ref
            part = _name(target) or _name(comp)
            own = _own_colour(color_tool, comp) or _own_colour(color_tool, target)
            sub = TDF_LabelSequence()
            shape_tool.GetComponents_s(target, sub)
            if not sub.Length():  # a part that is one leaf shape
                shape = shape_tool.GetShape_s(target)
                n = _solids(shape)
                out.setdefault(part, []).extend([own if n == 1 else None] * n)
                continue
            for j in range(1, sub.Length() + 1):
                walk(sub.Value(j), own, part)

    free = TDF_LabelSequence()
    shape_tool.GetFreeShapes(free)
    assert free.Length() == 1
    walk_top(free.Value(1))
    return out


def _rgb(hexa: str) -> tuple[float, float, float]:
    h = hexa.lstrip("#")
    return tuple(round(int(h[i : i + 2], 16) / 255, 3) for i in (0, 2, 4))


@pytest.fixture(scope="module")
def fab():
    return fabricate(miura_design(2, 3, 30.0, 30.0, 65.0), FabricationParams(shell=0.5))


def test_every_solid_of_every_part_resolves_to_its_part_colour(tmp_path, fab):
    path = export_step_assembly(fab.parts, tmp_path / "assembly.step")
    colours = read_step_colours(path)
    assert set(colours) == set(PART_NAMES)
    for name in PART_NAMES:
        expected = _rgb(MATERIAL_COLORS[PART_MATERIALS[name]])
        got = colours[name]
        assert len(got) == len(fab.parts.solids[name]) > 0, name
        assert all(c is not None for c in got), f"{name}: solids without a colour"
        assert all(c == pytest.approx(expected, abs=2e-3) for c in got), name


def test_the_reader_sees_the_defect_of_a_colour_on_a_compound(tmp_path, fab):
    """The emulation is strict enough: the old layout (colour on a compound) fails it."""
    from build123d import Compound, export_step

    from origami_cad.fabrication.assembly import material_color

    children = []
    for name in PART_NAMES:
        comp = fab.parts.compound(name)
        comp.label = name
        comp.color = material_color(PART_MATERIALS[name])
        children.append(comp)
    old = tmp_path / "old.step"
    export_step(Compound(children=children), str(old))
    colours = read_step_colours(old)
    assert any(c is None for c in colours["shells"])  # grey in FreeCAD, as reported


def read_step_instances(path: Path) -> dict[str, list]:
    """Per part: ``(name, shape placed, prototype label)`` of each solid, in file order.

    Each solid is a component of its part placing a prototype shape (its location
    applied), as any XCAF reader sees it.
    """
    doc = TDocStd_Document(TCollection_ExtendedString("XmlOcaf"))
    reader = STEPCAFControl_Reader()
    reader.SetNameMode(True)
    assert reader.ReadFile(str(path)) == IFSelect_RetDone
    assert reader.Transfer(doc)
    shape_tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    free = TDF_LabelSequence()
    shape_tool.GetFreeShapes(free)
    parts = TDF_LabelSequence()
    shape_tool.GetComponents_s(free.Value(1), parts)
    out: dict[str, list] = {}
    for i in range(1, parts.Length() + 1):
        part = TDF_Label()
        assert shape_tool.GetReferredShape_s(parts.Value(i), part)
        solids = TDF_LabelSequence()
        shape_tool.GetComponents_s(part, solids)
        rows = out.setdefault(_name(part), [])
        for j in range(1, solids.Length() + 1):
            comp, proto = solids.Value(j), TDF_Label()
            assert shape_tool.GetReferredShape_s(comp, proto)
            placed = shape_tool.GetShape_s(proto).Moved(shape_tool.GetLocation_s(comp))
            rows.append((_name(comp), placed, proto.Tag()))
    return out


def test_each_distinct_solid_is_written_once_and_every_instance_is_its_solid(tmp_path):
    """Prototypes and placed instances: every solid where it is, of its volume."""
    from build123d import Solid

    fab = fabricate(miura_design(4, 4, 20.0, 20.0, 65.0))
    path = export_step_assembly(fab.parts, tmp_path / "assembly.step")
    parts = read_step_instances(path)
    assert set(parts) == set(PART_NAMES)
    for name in PART_NAMES:
        rows, solids = parts[name], fab.parts.solids[name]
        assert [r[0] for r in rows] == [f"{name} {k}" for k in range(len(solids))]
        prototypes = {r[2] for r in rows}
        copies = sum(c is not None for c in fab.parts.copy_of[name])
        assert len(prototypes) == len(solids) - copies, name
        for (label, placed, _), solid in zip(rows, solids, strict=True):
            got = Solid(placed)
            assert got.volume == pytest.approx(solid.volume, rel=1e-6), label
            assert (got.center() - solid.center()).length < 1e-6, label
            a, b = got.bounding_box(), solid.bounding_box()
            assert (a.min - b.min).length < 1e-6 and (a.max - b.max).length < 1e-6, label
    assert len({r[2] for r in parts["shells"]}) < len(parts["shells"])  # shared


def test_a_solid_replaced_after_the_build_is_its_own_prototype(tmp_path):
    from build123d import Solid

    fab = fabricate(miura_design(3, 4, 20.0, 20.0, 65.0))
    copies = fab.parts.copy_of["shells"]
    k = next(i for i, c in enumerate(copies) if c is not None)
    fab.parts.solids["shells"][k] = Solid.make_box(3, 4, 5)
    path = export_step_assembly(fab.parts, tmp_path / "assembly.step")
    label, placed, _ = read_step_instances(path)["shells"][k]
    assert label == f"shells {k}" and Solid(placed).volume == pytest.approx(60.0, rel=1e-9)


def test_a_crease_sheet_with_many_holes_is_written_as_strips_of_its_volume(tmp_path, monkeypatch):
    """Strips of the sheet, cut across its longer side: valid solids, together its volume
    (1e-9 relative), each in the crease colour."""
    from build123d import Solid
    from OCP.BRepCheck import BRepCheck_Analyzer

    from origami_cad.fabrication.exports import step

    fab = fabricate(miura_design(4, 4, 20.0, 20.0, 65.0))
    monkeypatch.setattr(step, "HOLES_PER_STRIP", 4)
    sheet = fab.parts.solids["creases"][0]
    strips = step.crease_strips(sheet)
    assert strips is not None and len(strips) >= 4
    assert all(BRepCheck_Analyzer(s).IsValid() for s in strips)
    assert sum(Solid(s).volume for s in strips) == pytest.approx(sheet.volume, rel=1e-9)
    path = export_step_assembly(fab.parts, tmp_path / "assembly.step")
    rows = read_step_instances(path)["creases"]
    assert [r[0] for r in rows] == [f"creases 0 strip {i}" for i in range(len(strips))]
    assert sum(Solid(r[1]).volume for r in rows) == pytest.approx(sheet.volume, rel=1e-9)
    colours = read_step_colours(path)["creases"]
    expected = _rgb(MATERIAL_COLORS["TPU"])
    assert len(colours) == len(strips)
    assert all(c == pytest.approx(expected, abs=2e-3) for c in colours)


def test_a_sheet_that_is_no_prism_is_written_as_it_is(monkeypatch):
    from build123d import Axis, Cylinder, Solid

    from origami_cad.fabrication.exports import step

    monkeypatch.setattr(step, "HOLES_PER_STRIP", 1)
    assert step.crease_strips(Solid.make_box(10, 20, 1)) is None  # no holes: one strip
    assert step.crease_strips(Cylinder(5, 1).solid()) is None
    tilted = Solid.make_box(10, 10, 1) - Solid.make_box(10, 10, 1).rotate(Axis.X, 30)
    assert step.crease_strips(tilted) is None
