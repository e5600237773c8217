"""How the parts are printed: extruders, layer height, temperatures, walls and infill.

:func:`slicer_settings` gives the print settings as plain data (mm, deg C, g/cm^3); the
3MF export writes them into the slicer's configuration
(:mod:`origami_cad.fabrication.exports.threemf`) and the printed mass
(:mod:`origami_cad.fabrication.printmass`) reads them.
"""

from __future__ import annotations

from origami_cad.errors import FabricationError
from origami_cad.fabrication.assembly import MATERIAL_COLORS
from origami_cad.fabrication.params import DENSITY_G_CM3, FabricationParams, layer_height

__all__ = [
    "EXTRUDERS",
    "MATERIAL_SETTINGS",
    "PRINT_SETTINGS",
    "SLICERS",
    "layer_height",
    "slicer_settings",
]

#: The 3MF flavours: the slicer each is laid out for (``export_3mf(..., slicer=)``).
SLICERS = ("prusa", "bambu", "orca")

#: Extruder of each material (1-based, as slicers count).
EXTRUDERS = {"PLA": 1, "TPU": 2}


#: Per-material slicer settings: nozzle and first-layer temperatures (deg C), bed (deg C),
#: filament type as the slicers name it, and the largest volumetric speed (mm^3/s).
MATERIAL_SETTINGS = {
    "PLA": {
        "temperature": 210,
        "first_layer_temperature": 215,
        "bed": 60,
        "type": "PLA",
        "max_volumetric_speed": 15.0,
    },
    "TPU": {
        "temperature": 230,
        "first_layer_temperature": 230,
        "bed": 60,
        "type": "FLEX",
        "max_volumetric_speed": 3.6,
    },
}


#: How the parts are printed (docs/fabrication.md, "Printed mass"): walls (perimeter
#: loops) and solid skin layers, the sparse infill's fraction, the extrusion width (mm),
#: solid layers between the two materials (``interface_shells``) and no small region
#: filled solid (``solid_infill_below_area``, mm^2) other than by the rules above.
PRINT_SETTINGS = {
    "perimeters": 2,
    "top_solid_layers": 3,
    "bottom_solid_layers": 3,
    "fill_density": 0.15,
    "extrusion_width": 0.45,
    "interface_shells": True,
    "solid_infill_below_area": 0.0,
}


def slicer_settings(
    params: FabricationParams | None = None, print_settings: dict[str, object] | None = None
) -> dict[str, object]:
    """The print settings carried by the 3MF, as plain data (see docs/fabrication.md).

    Extruder 1 prints PLA, extruder 2 TPU (:data:`EXTRUDERS`); ``layer_height`` and
    ``first_layer_height`` come from :func:`layer_height`; temperatures in deg C;
    ``filament_density`` g/cm^3 (``DENSITY_G_CM3``); walls, skins and infill from
    :data:`PRINT_SETTINGS`, each overridden by ``print_settings`` (the same keys; an
    unknown key is a :class:`FabricationError`). ``printmass.printed_mass`` reads them.
    """
    params = params or FabricationParams()
    unknown = set(print_settings or {}) - set(PRINT_SETTINGS)
    if unknown:
        raise FabricationError(
            f"unknown print setting(s) {', '.join(sorted(unknown))}; "
            f"known: {', '.join(PRINT_SETTINGS)}"
        )
    printing = {**PRINT_SETTINGS, **(print_settings or {})}
    if not 0.0 <= float(printing["fill_density"]) <= 1.0:
        raise FabricationError(
            f"fill_density must be a fraction in [0, 1], got {printing['fill_density']!r}"
        )
    h = layer_height(params)
    mats = sorted(EXTRUDERS, key=EXTRUDERS.get)
    per = [MATERIAL_SETTINGS[m] for m in mats]
    return {
        **printing,
        "filament_density": [DENSITY_G_CM3[m] for m in mats],
        "layer_height": h,
        "first_layer_height": h,
        "materials": mats,
        "filament_type": [p["type"] for p in per],
        "temperature": [p["temperature"] for p in per],
        "first_layer_temperature": [p["first_layer_temperature"] for p in per],
        "bed_temperature": [p["bed"] for p in per],
        "filament_max_volumetric_speed": [p["max_volumetric_speed"] for p in per],
        "filament_colour": [MATERIAL_COLORS[m] for m in mats],
    }
