"""STEP export: the printed parts as a named, coloured assembly, and any labelled tree.

:func:`export_step_tree` writes a build123d shape or ``Compound`` tree keeping every
node's label and colour, from a detached copy: build123d's own ``export_step`` fails
on a tree that has been nested in another ``Compound`` (its node keeps a parent), and
older build123d releases lose nested labels (build123d issues #954, #1197).
"""

from __future__ import annotations

import itertools
import math
import os
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import shapely
from build123d import Location, Shape, export_step
from OCP.APIHeaderSection import APIHeaderSection_MakeHeader
from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Surface
from OCP.BRepTools import BRepTools_WireExplorer
from OCP.collections import IndexedMap_TopoDS_Shape_TopTools_ShapeMapHasher as ShapeMap
from OCP.GeomAbs import GeomAbs_Plane
from OCP.IFSelect import IFSelect_RetDone
from OCP.Interface import Interface_Static
from OCP.Message import Message, Message_Gravity
from OCP.STEPCAFControl import STEPCAFControl_Controller, STEPCAFControl_Writer
from OCP.STEPControl import STEPControl_AsIs
from OCP.TCollection import TCollection_ExtendedString, TCollection_HAsciiString
from OCP.TDataStd import TDataStd_Name
from OCP.TDF import TDF_Label
from OCP.TDocStd import TDocStd_Document
from OCP.TopAbs import TopAbs_FACE, TopAbs_VERTEX
from OCP.TopExp import TopExp, TopExp_Explorer
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS, TopoDS_Iterator
from OCP.XCAFApp import XCAFApp_Application
from OCP.XCAFDoc import XCAFDoc_ColorGen, XCAFDoc_DocumentTool
from OCP.XSControl import XSControl_WorkSession

from origami_cad._args import Arg, checked
from origami_cad._fileio import atomic_path
from origami_cad.errors import FabricationError
from origami_cad.fabrication.assembly import material_color, moved_tree
from origami_cad.fabrication.solids import (
    PART_MATERIALS,
    PART_NAMES,
    Parts,
    motion_location,
    planar_prism,
)

__all__ = ["WRITERS", "export_step_assembly", "export_step_tree", "lay_on_bed"]

#: Whether assembly.step carries each edge's curve on its faces too (pcurves): off, readers
#: rebuild them from the 3D edges (every face is a plane or a cylinder), and the file is
#: smaller and written faster.
WRITE_PCURVES = False


@checked(
    FabricationError,
    shape=Arg("object", types=(Shape,), optional=False),
    path=Arg("path", optional=False),
)
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

    Each distinct solid is written once, as a prototype, and every solid of a part is
    an instance of one, placed: a solid that :func:`~origami_cad.fabrication.solids.build_parts`
    made as a moved copy of another (``Parts.copy_of``) is that solid's prototype, moved
    (:func:`_instances`). A crease sheet of many holes is written as strips
    (:func:`crease_strips`). The XCAF document is built here with OCP
    (:func:`_assembly_document`) and written without layers (there are none): see "How
    assembly.step is laid out" in ``docs/fabrication.md`` for what each step costs.
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
    with atomic_path(path) as tmp, _quiet_occt():
        if writer.Write(str(tmp)) != IFSelect_RetDone:
            raise OSError(f"{path}: the STEP writer failed")
    return Path(path)


#: the name of the assembly's root (and of the STEP file in its header)
ASSEMBLY_NAME = "origami_structure"


def _instances(parts: Parts, name: str) -> list[tuple[int, TopLoc_Location]]:
    """Per solid of part ``name``: ``(prototype, location)``, the solid as placed.

    The prototype is the position of a solid of the part, whose shape (its own location
    removed) moved by ``location`` is that solid. A solid still the one
    :func:`~origami_cad.fabrication.solids.build_parts` built as a moved copy
    (``Parts.copy_of``) of a solid also still as built is an instance of that solid's
    shape, moved by the copy's motion; any other solid is its own prototype, at its own
    location.
    """
    solids, copies = parts.solids[name], parts.copy_of.get(name, [])
    out = []
    for k, solid in enumerate(solids):
        copy = parts.source(name, k)
        if copy is not None and copies[copy[0]] is None:
            source = solids[copy[0]].wrapped.Location()
            out.append((copy[0], motion_location(copy[1]).Multiplied(source)))
        else:
            out.append((k, solid.wrapped.Location()))
    return out


def _assembly_document(parts: Parts) -> TDocStd_Document:
    """The XCAF document of :func:`export_step_assembly`: root, four parts, their solids.

    Each part is an assembly label, named and coloured (on its shape and on the
    component placing it in the root, where build123d's ``import_step`` reads it). Each
    prototype (:func:`_instances`) is one shape label, named ``"{part} shape {k}"``
    after the first solid it is and coloured; each solid is a component of its part
    placing a prototype, named ``"{part} {k}"`` and not coloured (a per-instance
    colour is one costly styled item per solid in the file; readers take the
    prototype's).
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
        placed = shapes.AddComponent(
            root, _part_label(shapes, colours, parts, name), TopLoc_Location()
        )
        _name_label(placed, name)
        colours.SetColor(placed, colour, XCAFDoc_ColorGen)
    shapes.UpdateAssemblies()
    return doc


def _part_label(shapes, colours, parts: Parts, name: str) -> TDF_Label:
    """Part ``name``'s assembly label: its prototypes placed, one component per solid.

    A crease sheet with many holes is placed as strips (:func:`crease_strips`), each its
    own shape named ``"{part} {k} strip {i}"``.
    """
    colour = material_color(PART_MATERIALS[name]).wrapped
    part = shapes.NewShape()
    _name_label(part, name)
    colours.SetColor(part, colour, XCAFDoc_ColorGen)
    prototypes: dict[str, TDF_Label] = {}

    def place(key: str, shape, location: TopLoc_Location, label: str) -> None:
        if key not in prototypes:
            prototypes[key] = shapes.AddShape(shape.Located(TopLoc_Location()), False, False)
            _name_label(prototypes[key], key)
            colours.SetColor(prototypes[key], colour, XCAFDoc_ColorGen)
        _name_label(shapes.AddComponent(part, prototypes[key], location), label)

    for k, (first, location) in enumerate(_instances(parts, name)):
        solid = parts.solids[name][k]
        strips = crease_strips(solid) if name == "creases" else None
        for i, piece in enumerate(strips or []):
            strip = f"{name} {k} strip {i}"
            place(strip, piece, piece.Location(), strip)
        if strips is None:
            source = parts.solids[name][first].wrapped
            place(f"{name} shape {first}", source, location, f"{name} {k}")
    return part


#: Holes (mid-layer patches) per strip of the crease sheet in assembly.step, about: a
#: sheet with more is written as vertical strips (:func:`crease_strips`)
HOLES_PER_STRIP = 40


def crease_strips(solid) -> list | None:
    """The crease sheet cut into strips of about :data:`HOLES_PER_STRIP` holes, or ``None``.

    OCC's STEP writer checks every pair of wires of a face for shared vertices (its
    ``SplitCommonVertex`` pass, which cannot be turned off from OCP): quadratic in the
    holes of the sheet's top and bottom faces, 1.4 s of the 20 x 20's 2.1 s. The strips
    are the prisms (``TopoDS_Shape``) of the sheet's footprint cut by planes x or y =
    const across its longer side: together exactly its volume. ``None`` when the sheet
    has fewer holes or is not a vertical prism (a solid replaced by the user): then it is
    written as it is.
    """
    footprint = _prism_footprint(solid.wrapped)
    if footprint is None:
        return None
    poly, z0, z1 = footprint
    count = math.ceil(len(poly.interiors) / HOLES_PER_STRIP)
    if count < 2:
        return None
    x0, y0, x1, y1 = poly.bounds
    along_x = x1 - x0 >= y1 - y0
    cuts = np.linspace(x0 if along_x else y0, x1 if along_x else y1, count + 1)
    cuts[0], cuts[-1] = cuts[0] - 1.0, cuts[-1] + 1.0
    pieces = []
    for a, b in itertools.pairwise(cuts.tolist()):
        band = shapely.box(a, y0 - 1, b, y1 + 1) if along_x else shapely.box(x0 - 1, a, x1 + 1, b)
        pieces += [p for p in shapely.get_parts(shapely.intersection(poly, band)) if p.area > 0]
    if any(not isinstance(p, shapely.Polygon) for p in pieces):
        return None
    if abs(sum(p.area for p in pieces) - poly.area) > 1e-9 * poly.area:
        return None
    return [planar_prism(p, z0, z1).wrapped for p in pieces]


def _prism_footprint(shape):
    """``(polygon, z0, z1)`` when ``shape`` is a vertical prism of a planar face, else ``None``.

    Every face must be a plane; its bottom is the horizontal face with the most wires and
    the lowest; every vertex must be one of that face's, at z0 or z1, and the faces its
    sides (one per edge of the bottom), top and bottom.
    """
    horizontal, faces = [], 0
    explorer = TopExp_Explorer(shape, TopAbs_FACE)
    while explorer.More():
        faces += 1
        surface = BRepAdaptor_Surface(TopoDS.Face(explorer.Current()))
        if surface.GetType() != GeomAbs_Plane:
            return None
        plane = surface.Plane()
        if abs(plane.Axis().Direction().Z()) > 1 - 1e-12:
            wires = _children(TopoDS.Face(explorer.Current()))
            horizontal.append((-len(wires), plane.Location().Z(), wires))
        explorer.Next()
    if len(horizontal) != 2:
        return None
    (_, z0, wires), (_, z1, _) = sorted(horizontal, key=lambda f: f[:2])
    rings = [_ring(w) for w in wires]
    if min(len(r) for r in rings) < 3:
        return None
    rings.sort(key=lambda r: -abs(shapely.Polygon(r).area))
    poly = shapely.Polygon(rings[0], rings[1:])
    corners = {(round(x, 9), round(y, 9)) for r in rings for x, y in r}
    vertices = ShapeMap()
    TopExp.MapShapes_s(shape, TopAbs_VERTEX, vertices)
    for i in range(1, vertices.Extent() + 1):
        p = BRep_Tool.Pnt_s(TopoDS.Vertex(vertices.FindKey(i)))
        if (round(p.X(), 9), round(p.Y(), 9)) not in corners or min(
            abs(p.Z() - z0), abs(p.Z() - z1)
        ) > 1e-9:
            return None
    edges = sum(len(r) for r in rings)
    if not poly.is_valid or z1 <= z0 or faces != edges + 2 or vertices.Extent() != 2 * edges:
        return None
    return poly, z0, z1


def _children(shape) -> list:
    out, it = [], TopoDS_Iterator(shape)
    while it.More():
        out.append(it.Value())
        it.Next()
    return out


def _ring(wire) -> list[tuple[float, float]]:
    out, it = [], BRepTools_WireExplorer(TopoDS.Wire(wire))
    while it.More():
        p = BRep_Tool.Pnt_s(it.CurrentVertex())
        out.append((p.X(), p.Y()))
        it.Next()
    return out


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
