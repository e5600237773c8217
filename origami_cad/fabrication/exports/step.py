"""STEP export: the printed parts as a named, coloured assembly, and any labelled tree.

:func:`export_step_tree` writes a build123d shape or ``Compound`` tree keeping every
node's label and colour, from a detached copy: build123d's own ``export_step`` fails
on a tree that has been nested in another ``Compound`` (its node keeps a parent), and
older build123d releases lose nested labels (build123d issues #954, #1197).
"""

from __future__ import annotations

import os
from pathlib import Path

from build123d import Compound, Location, Solid, export_step

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
    """
    children = []
    for name in PART_NAMES:
        color = material_color(PART_MATERIALS[name])
        solids = []
        for k, solid in enumerate(parts.solids[name]):
            child = Solid(solid.wrapped)
            child.label = f"{name} {k}"
            child.color = color
            solids.append(child)
        comp = Compound(children=solids)
        comp.label = name
        comp.color = color
        children.append(comp)
    assembly = Compound(children=children)
    assembly.label = "origami_structure"
    with atomic_path(path) as tmp:  # a new tree, attached nowhere: no copy needed
        if export_step(assembly, str(tmp), write_pcurves=WRITE_PCURVES) is False:
            raise OSError(f"{path}: the STEP writer failed")
    return Path(path)


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
