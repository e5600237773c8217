"""The old import path of the exports, kept: everything now lives in :mod:`.exports`.

One module per format there: :mod:`.exports.stl`, :mod:`.exports.step`,
:mod:`.exports.threemf`; the colours in :mod:`.assembly`.
"""

from origami_cad.fabrication.assembly import MATERIAL_COLORS, material_color
from origami_cad.fabrication.exports import export_part
from origami_cad.fabrication.exports.step import export_step_assembly, export_step_tree, lay_on_bed
from origami_cad.fabrication.exports.stl import (
    ANGULAR_TOLERANCE,
    TOLERANCE,
    export_stls,
    part_meshes,
    parts_tessellation,
    read_binary_stl,
    solid_mesh,
)
from origami_cad.fabrication.exports.threemf import (
    EXTRUDERS,
    MATERIAL_SETTINGS,
    SLICERS,
    export_3mf,
    layer_height,
    slicer_settings,
)

__all__ = [
    "ANGULAR_TOLERANCE",
    "EXTRUDERS",
    "MATERIAL_COLORS",
    "MATERIAL_SETTINGS",
    "SLICERS",
    "TOLERANCE",
    "export_3mf",
    "export_part",
    "export_step_assembly",
    "export_step_tree",
    "export_stls",
    "lay_on_bed",
    "layer_height",
    "material_color",
    "part_meshes",
    "parts_tessellation",
    "read_binary_stl",
    "slicer_settings",
    "solid_mesh",
]
