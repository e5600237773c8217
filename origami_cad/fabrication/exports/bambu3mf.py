"""The Bambu Studio / OrcaSlicer flavour of ``print.3mf``, laid out as their importer reads it.

Both slicers read a 3MF with ``_BBS_3MF_Importer`` (``src/libslic3r/Format/bbs_3mf.cpp``;
read at bambulab/BambuStudio 0067891 and SoftFever/OrcaSlicer ba52cf4). What this module
writes follows these rules of that importer:

* ``_handle_end_metadata``: the model's ``Application`` metadata must start with
  ``BambuStudio-`` (Orca: or ``OrcaSlicer-``); only then is the file "bbl" and its
  generator version ``Semver::parse(...)`` of the rest set. ``_load_model_from_file``
  sets ``dont_load_config = true`` when that version is missing, and reads
  ``Metadata/project_settings.config`` only ``if (!dont_load_config ...)``.
* ``_extract_project_config_from_archive``: the project settings are JSON loaded by
  ``ConfigBase::load_from_json``: each value a string or an array of strings (an array
  element of another type fails the load), each key a known option.
* ``_handle_start_config_volume``: a ``<part>`` of ``Metadata/model_settings.config``
  with ``lastid > 0`` is a triangle range, any other a reference to the sub-object whose
  ``id`` it carries; ``_generate_volumes_new`` then makes one volume per mesh object
  reached through ``<components>`` and takes a part's metadata only when its ``id`` is
  that mesh object's id (so triangle ranges never become parts). The ``<object id>`` is
  the build item's object id.
* part metadata ``extruder`` is the part's filament (``volume->config``), and an
  extruder above the length of ``filament_settings_id`` is reset to 1.

So the file holds one mesh object per part, an assembly object whose components are
those parts, a ``model_settings.config`` naming each part by its mesh object's id with
its ``extruder``, and ``project_settings.config`` with two filaments.
"""

from __future__ import annotations

import json

from origami_cad._names import xml_text

__all__ = [
    "APPLICATIONS",
    "IDENTITY",
    "bambu_print_settings",
    "config_strings",
    "model_settings_config",
    "project_settings_config",
]

#: The ``Application`` each flavour carries: the importer's prefix and a version its
#: ``Semver::parse`` reads (Bambu Studio writes ``BambuStudio-`` + ``01.09.00.00``-style
#: versions, OrcaSlicer ``OrcaSlicer-`` + ``2.2.0``-style ones).
APPLICATIONS = {"bambu": "BambuStudio-01.09.00.00", "orca": "OrcaSlicer-2.2.0"}

#: A volume's ``matrix`` metadata: the identity (parts are in assembly position).
IDENTITY = "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1"


def config_strings(values) -> list[str]:
    """Values as the JSON settings hold them: strings, floats in ``%g``."""
    return [f"{v:g}" if isinstance(v, float) else str(v) for v in values]


def bambu_print_settings(settings: dict[str, object]) -> dict[str, object]:
    """Walls, skins, infill, line width and filament densities under Bambu / Orca's keys."""
    return {
        "wall_loops": str(settings["perimeters"]),
        "top_shell_layers": str(settings["top_solid_layers"]),
        "bottom_shell_layers": str(settings["bottom_solid_layers"]),
        "sparse_infill_density": f"{100 * settings['fill_density']:g}%",
        "line_width": f"{settings['extrusion_width']:g}",
        "interface_shells": str(int(bool(settings["interface_shells"]))),
        "thick_bridges": "0",
        "filament_density": config_strings(settings["filament_density"]),
    }


def project_settings_config(settings: dict[str, object], version: str) -> str:
    """``Metadata/project_settings.config`` (JSON): every value a string or strings.

    Filament 1 is PLA, filament 2 TPU (``settings`` from
    :func:`~origami_cad.fabrication.slicer.slicer_settings`); temperatures
    deg C, heights mm, volumetric speeds mm^3/s. One 0.4 mm nozzle fed the two
    filaments (an AMS), as the Bambu printers and Orca's defaults have.
    """
    bed = config_strings(settings["bed_temperature"])
    names = [f"origami_cad {m}" for m in settings["materials"]]
    return json.dumps(
        {
            "name": "project_settings",
            "from": "project",
            "version": version,
            "layer_height": f"{settings['layer_height']:g}",
            "initial_layer_print_height": f"{settings['first_layer_height']:g}",
            "filament_settings_id": names,
            "filament_type": ["TPU" if t == "FLEX" else t for t in settings["filament_type"]],
            "filament_colour": list(settings["filament_colour"]),
            "nozzle_temperature": config_strings(settings["temperature"]),
            "nozzle_temperature_initial_layer": config_strings(settings["first_layer_temperature"]),
            "hot_plate_temp": bed,
            "hot_plate_temp_initial_layer": bed,
            "textured_plate_temp": bed,
            "textured_plate_temp_initial_layer": bed,
            "filament_max_volumetric_speed": config_strings(
                settings["filament_max_volumetric_speed"]
            ),
            "nozzle_diameter": ["0.4"],
            **bambu_print_settings(settings),
        },
        indent=1,
    )


def model_settings_config(
    assembly_id: int, parts: list[tuple[int, str, int]], name: str
) -> list[str]:
    """The lines of ``Metadata/model_settings.config``.

    ``parts`` are ``(mesh object id, part name, extruder)``; each becomes a ``<part>``
    whose ``id`` is its mesh object's (no ``firstid``/``lastid``: a reference to the
    sub-object), ``subtype="normal_part"``, with ``name``, ``matrix`` and ``extruder``.
    """
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        "<config>",
        f' <object id="{assembly_id}">',
        f'  <metadata key="name" value="{xml_text(name)}"/>',
        '  <metadata key="extruder" value="1"/>',
    ]
    for object_id, part, extruder in parts:
        lines += [
            f'  <part id="{object_id}" subtype="normal_part">',
            f'   <metadata key="name" value="{xml_text(part)}"/>',
            f'   <metadata key="matrix" value="{IDENTITY}"/>',
            f'   <metadata key="extruder" value="{extruder}"/>',
            "  </part>",
        ]
    return [*lines, " </object>", "</config>"]
