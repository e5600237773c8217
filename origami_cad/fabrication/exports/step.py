"""STEP export: the printed parts as a named, coloured assembly, and any labelled tree.

:func:`export_step_tree` writes a build123d shape or ``Compound`` tree keeping every
node's label and colour, from a detached copy: build123d's own ``export_step`` fails
on a tree that has been nested in another ``Compound`` (its node keeps a parent), and
older build123d releases lose nested labels (build123d issues #954, #1197).
"""

from __future__ import annotations

import os
from contextlib import contextmanager
from pathlib import Path

from build123d import Location, export_step
from OCP.APIHeaderSection import APIHeaderSection_MakeHeader
from OCP.IFSelect import IFSelect_RetDone
from OCP.Interface import Interface_Static
from OCP.Message import Message, Message_Gravity
from OCP.STEPCAFControl import STEPCAFControl_Controller, STEPCAFControl_Writer
from OCP.STEPControl import STEPControl_AsIs
from OCP.TCollection import TCollection_ExtendedString, TCollection_HAsciiString
from OCP.TDataStd import TDataStd_Name
from OCP.TDocStd import TDocStd_Document
from OCP.TopLoc import TopLoc_Location
from OCP.XCAFApp import XCAFApp_Application
from OCP.XCAFDoc import XCAFDoc_ColorGen, XCAFDoc_DocumentTool
from OCP.XSControl import XSControl_WorkSession

from origami_cad._fileio import atomic_path
from origami_cad.fabrication.assembly import material_color, moved_tree
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES, Parts

__all__ = ["WRITERS", "export_step_assembly", "export_step_tree", "lay_on_bed"]

#: Whether assembly.step carries each edge's curve on its faces too (pcurves): off, readers
#: rebuild them from the 3D edges (every face is a plane or a cylinder), and the file is
#: smaller and written faster.
WRITE_PCURVES = False


def export_step_tree(shape, path: str | os.PathLike[str]) -> Path:
    """Write a shape or labelled tree as one STEP (atomic), labels and colours kept.

    The tree is copied first (:func:`~origami_cad.fabrication.assembly.moved_tree`), so a
    tree held inside a user's ``Compound`` is written as it is, on its own.
    """
    tree = moved_tree(shape, Location())
    with atomic_path(path) as tmp:
        if export_step(tree, str(tmp)) is False:
            raise OSError(f"{path}: the STEP writer failed")
    return Path(path)


def export_step_assembly(parts: Parts, path: str | os.PathLike[str]) -> Path:
    """Write one STEP with four named parts, each solid a separately coloured child.

    The assembly ``origami_structure`` holds the four parts (``infills``,
    ``midlayers``, ``shells``, ``creases``); each part holds its solids
    (``shells 0``, ``shells 1``...), every one carrying its part's colour. FreeCAD
    resolves a colour from a solid's own label, then its parent's: colours set on a
    compound alone come in grey.

    The XCAF document is built here with OCP (:func:`_assembly_document`), the same
    tree build123d's ``export_step`` builds from a ``Compound`` of ``Compound`` s, and
    written without layers (there are none): see the speed section of
    ``docs/fabrication.md`` for what each step costs.
    """
    doc = _assembly_document(parts)
    writer = STEPCAFControl_Writer(XSControl_WorkSession(), False)
    writer.SetColorMode(True)
    writer.SetNameMode(True)
    writer.SetLayerMode(False)
    header = APIHeaderSection_MakeHeader(writer.Writer().Model())
    if not header.IsDone():
        header = APIHeaderSection_MakeHeader(0)
        header.Apply(writer.Writer().Model())
    header.SetName(TCollection_HAsciiString(ASSEMBLY_NAME))
    header.SetOriginatingSystem(TCollection_HAsciiString("origami_cad"))
    STEPCAFControl_Controller.Init_s()
    Interface_Static.SetIVal_s("write.surfacecurve.mode", int(WRITE_PCURVES))
    Interface_Static.SetIVal_s("write.precision.mode", 0)  # average, as build123d's default
    with _quiet_occt():
        writer.Transfer(doc, STEPControl_AsIs)
    with atomic_path(path) as tmp:
        if writer.Write(str(tmp)) != IFSelect_RetDone:
            raise OSError(f"{path}: the STEP writer failed")
    return Path(path)


#: the name of the assembly's root (and of the STEP file in its header)
ASSEMBLY_NAME = "origami_structure"


def _assembly_document(parts: Parts) -> TDocStd_Document:
    """The XCAF document of :func:`export_step_assembly`: root, four parts, their solids.

    Each solid is its own shape label (never shared: FreeCAD would import shared
    shapes as link arrays), named on both the shape and the component that places it
    in its part, as build123d does; coloured on the shape only. build123d colours the
    component too, which the writer turns into a per-instance (context-dependent)
    style, each one costly to transfer; readers take the shape's colour all the same.
    """
    doc = TDocStd_Document(TCollection_ExtendedString("XmlOcaf"))
    app = XCAFApp_Application.GetApplication_s()
    app.NewDocument(TCollection_ExtendedString("MDTV-XCAF"), doc)
    app.InitDocument(doc)
    XCAFDoc_DocumentTool.SetLengthUnit_s(doc, 0.001)  # millimetres
    shapes = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    colours = XCAFDoc_DocumentTool.ColorTool_s(doc.Main())
    shapes.SetAutoNaming_s(False)
    root = shapes.NewShape()
    _name_label(root, ASSEMBLY_NAME)
    for name in PART_NAMES:
        colour = material_color(PART_MATERIALS[name]).wrapped
        part = shapes.NewShape()
        _name_label(part, name)
        colours.SetColor(part, colour, XCAFDoc_ColorGen)
        for k, solid in enumerate(parts.solids[name]):
            shape = shapes.AddShape(solid.wrapped, False, False)
            placed = shapes.AddComponent(part, shape, TopLoc_Location())
            _name_label(shape, f"{name} {k}")
            _name_label(placed, f"{name} {k}")
            colours.SetColor(shape, colour, XCAFDoc_ColorGen)
        _name_label(shapes.AddComponent(root, part, TopLoc_Location()), name)
    shapes.UpdateAssemblies()
    return doc


def _name_label(label, name: str) -> None:
    TDataStd_Name.Set_s(label, TCollection_ExtendedString(name))


@contextmanager
def _quiet_occt():
    """OCCT's messages to the console held to failures (as build123d's export does)."""
    printers = list(Message.DefaultMessenger_s().Printers())
    levels = [p.GetTraceLevel() for p in printers]
    for p in printers:
        p.SetTraceLevel(Message_Gravity.Message_Fail)
    try:
        yield
    finally:
        for p, level in zip(printers, levels, strict=True):
            p.SetTraceLevel(level)


def lay_on_bed(shape):
    """A copy of a part or assembly moved along z so that its lowest point is at z = 0.

    x and y are kept; an assembly keeps its tree of named, coloured children (each
    child moved by the same amount), so slicers place it on the bed as built.
    """
    dz = -shape.bounding_box().min.Z
    return moved_tree(shape, Location((0.0, 0.0, dz)))


def _write_fabrication_step(fab, folder: Path) -> dict[str, Path]:
    return {"step": export_step_assembly(fab.parts, folder / "assembly.step")}


#: What ``write_fabrication`` writes of this format: ``{format: writer(fab, folder)}``.
WRITERS = {"step": _write_fabrication_step}
