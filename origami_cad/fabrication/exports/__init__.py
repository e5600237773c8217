"""Exports of the printed parts, one module per format, and their registry.

* :mod:`.stl`: one binary STL per part (and the meshes behind every export; those of
  the solids assembled from their faces made by :mod:`.polymesh`);
* :mod:`.step`: the STEP assembly of named, coloured solids, any labelled tree;
* :mod:`.threemf`: the slicer-ready 3MF (extruders, colours, print settings).

:data:`WRITERS` merges each module's ``WRITERS``: what ``write_fabrication`` writes,
``{format: writer(fab, folder) -> {key: path}}``, in this order.
"""

from __future__ import annotations

import os
from pathlib import Path

from origami_cad.fabrication.exports import step, stl, threemf
from origami_cad.fabrication.exports.step import export_step_tree, lay_on_bed
from origami_cad.fabrication.exports.stl import write_stl

__all__ = ["WRITERS", "export_part"]

#: Every format ``write_fabrication`` writes, by name, in order.
WRITERS = {**stl.WRITERS, **step.WRITERS, **threemf.WRITERS}


def export_part(part, folder: str | os.PathLike[str], name: str) -> list[Path]:
    """Write ``name.step`` and ``name.stl`` (binary) of a part or assembly (atomic).

    Both files hold the part laid on the print bed (:func:`lay_on_bed`: its lowest
    point at z = 0, x and y as built), so a slicer places it where it prints.
    """
    part = lay_on_bed(part)
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    step_path, stl_path = out / f"{name}.step", out / f"{name}.stl"
    return [export_step_tree(part, step_path), write_stl(part, stl_path)]
