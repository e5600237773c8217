"""3MF export of the printed parts: one slicer-ready package.

The 3MF holds one object made of four parts, PLA parts on extruder 1 and TPU
parts on extruder 2; each solid is its own closed, oriented shell and each part
a range of triangles, described both for PrusaSlicer
(``Metadata/Slic3r_PE_model.config``: volumes as triangle ranges with an
``extruder`` key) and for Bambu Studio / OrcaSlicer
(``Metadata/model_settings.config``: parts with ``firstid``/``lastid`` and an
``extruder`` key), with display colours through ``<basematerials>`` and the
print settings of :func:`slicer_settings` (``Metadata/Slic3r_PE.config``,
``Metadata/project_settings.config``). build123d's own 3MF writer gives each
shape its own object and no extruder, so the package is written here from
build123d's tessellation.
"""

from __future__ import annotations

import json
import os
import zipfile
from pathlib import Path

import numpy as np

from origami_cad import __version__
from origami_cad._fileio import atomic_path
from origami_cad._names import slicer_value, xml_text
from origami_cad.errors import FabricationError
from origami_cad.fabrication.assembly import MATERIAL_COLORS
from origami_cad.fabrication.exports.bambu3mf import (
    APPLICATIONS,
    bambu_print_settings,
    config_strings,
    model_settings_config,
    project_settings_config,
)
from origami_cad.fabrication.exports.stl import part_meshes, stack_meshes
from origami_cad.fabrication.params import DENSITY_G_CM3, FabricationParams
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES, Parts

__all__ = [
    "EXTRUDERS",
    "MATERIAL_SETTINGS",
    "PRINT_SETTINGS",
    "SLICERS",
    "WRITERS",
    "export_3mf",
    "layer_height",
    "slicer_settings",
]

#: Extruder of each material (1-based, as slicers count).
EXTRUDERS = {"PLA": 1, "TPU": 2}


def layer_height(params: FabricationParams, largest: float = 0.2) -> float:
    """The largest layer height (mm, at most ``largest``) that resolves every layer.

    Each panel half ``(h - t) / 2``, the crease layer ``t`` and the shell ``s`` are a
    whole number of layers, so no layer straddles two materials' boundary. Tries
    ``largest``, then steps of 0.01 mm down to 0.05 mm; falls back to 0.05 mm.
    """
    targets = (params.half_height, params.thickness, params.shell)
    for hundredths in range(round(largest * 100), 4, -1):
        h = hundredths / 100
        if all(abs(x / h - round(x / h)) < 1e-6 for x in targets):
            return h
    return 0.05


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


def _prusa_print_config(settings: dict[str, object]) -> str:
    """``Metadata/Slic3r_PE.config``: PrusaSlicer's print settings, ``; key = value`` lines."""

    def join(values, sep=","):
        return sep.join(f"{v:g}" if isinstance(v, float) else str(v) for v in values)

    lines = {
        "layer_height": f"{settings['layer_height']:g}",
        "first_layer_height": f"{settings['first_layer_height']:g}",
        "nozzle_diameter": "0.4,0.4",
        "filament_type": join(settings["filament_type"], ";"),
        "temperature": join(settings["temperature"]),
        "first_layer_temperature": join(settings["first_layer_temperature"]),
        "bed_temperature": join(settings["bed_temperature"]),
        "first_layer_bed_temperature": join(settings["bed_temperature"]),
        "filament_max_volumetric_speed": join(settings["filament_max_volumetric_speed"]),
        "filament_colour": join(settings["filament_colour"], ";"),
        "extruder_colour": join(settings["filament_colour"], ";"),
        "filament_density": join(settings["filament_density"]),
        "perimeters": str(settings["perimeters"]),
        "top_solid_layers": str(settings["top_solid_layers"]),
        "bottom_solid_layers": str(settings["bottom_solid_layers"]),
        "fill_density": f"{100 * settings['fill_density']:g}%",
        "extrusion_width": f"{settings['extrusion_width']:g}",
        "interface_shells": str(int(bool(settings["interface_shells"]))),
        "solid_infill_below_area": f"{settings['solid_infill_below_area']:g}",
        # a skin over the other material is no bridge: no thick, round bridge beads
        "thick_bridges": "0",
    }
    head = f"; generated by origami_cad {__version__}\n\n"
    return head + "".join(f"; {k} = {slicer_value(v)}\n" for k, v in lines.items())


def _bambu_project_config(settings: dict[str, object]) -> str:
    """``Metadata/project_settings.config``: Bambu Studio / OrcaSlicer settings (JSON)."""
    return json.dumps(
        {
            "layer_height": f"{settings['layer_height']:g}",
            "initial_layer_print_height": f"{settings['first_layer_height']:g}",
            "filament_type": ["TPU" if t == "FLEX" else t for t in settings["filament_type"]],
            "nozzle_temperature": config_strings(settings["temperature"]),
            "nozzle_temperature_initial_layer": config_strings(settings["first_layer_temperature"]),
            "hot_plate_temp": config_strings(settings["bed_temperature"]),
            "hot_plate_temp_initial_layer": config_strings(settings["bed_temperature"]),
            "filament_max_volumetric_speed": config_strings(
                settings["filament_max_volumetric_speed"]
            ),
            "filament_colour": list(settings["filament_colour"]),
            "nozzle_diameter": ["0.4", "0.4"],
            **bambu_print_settings(settings),
        },
        indent=1,
    )


#: zlib level of the package: 1 compresses the model text about as well as the default
#: (6) for a third of the time.
ZIP_LEVEL = 1

#: The 3MF flavours: the slicer each is laid out for (``export_3mf(..., slicer=)``).
SLICERS = ("prusa", "bambu", "orca")

_CONTENT_TYPES = (
    '<?xml version="1.0" encoding="UTF-8"?>\n'
    '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
    '<Default Extension="rels" '
    'ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
    '<Default Extension="model" '
    'ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
    '<Default Extension="config" ContentType="text/xml"/>'
    "</Types>"
)
_RELS = (
    '<?xml version="1.0" encoding="UTF-8"?>\n'
    '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
    '<Relationship Target="/3D/3dmodel.model" Id="rel0" '
    'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>'
    "</Relationships>"
)


def export_3mf(
    parts: Parts,
    path: str | os.PathLike[str],
    name: str = "origami",
    params: FabricationParams | None = None,
    slicer: str = "prusa",
    print_settings: dict[str, object] | None = None,
) -> Path:
    """Write a 3MF of the four parts with their extruders and print settings, for a slicer.

    ``slicer`` (:data:`SLICERS`) chooses the layout (docs/fabrication.md, "Printing"):

    * ``"prusa"``: one object whose mesh holds every solid as its own closed, oriented
      shell (no vertex shared between solids), the triangles of each part in one range;
      PrusaSlicer reads the ranges and extruders from ``Metadata/Slic3r_PE_model.config``
      and the settings from ``Metadata/Slic3r_PE.config``;
    * ``"bambu"``, ``"orca"``: one mesh object per part, the components of one object,
      with the ``Application``, ``Metadata/model_settings.config`` and
      ``Metadata/project_settings.config`` that Bambu Studio's / OrcaSlicer's importer
      reads (:mod:`.bambu3mf`).

    ``print_settings`` overrides :data:`PRINT_SETTINGS` (:func:`slicer_settings`).

    Raises
    ------
    FabricationError
        If ``slicer`` is not one of :data:`SLICERS`.
    """
    if slicer not in SLICERS:
        raise FabricationError(f"slicer must be one of {', '.join(SLICERS)}, got {slicer!r}")
    meshes = {n: _part_mesh(parts, n) for n in PART_NAMES}
    settings = slicer_settings(params, print_settings)
    if slicer == "prusa":
        entries = _prusa_entries(meshes, name, settings)
    else:
        entries = _bambu_entries(meshes, name, settings, slicer)
    with (
        atomic_path(path) as tmp,
        zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED, compresslevel=ZIP_LEVEL) as zf,
    ):
        zf.writestr("[Content_Types].xml", _CONTENT_TYPES)
        zf.writestr("_rels/.rels", _RELS)
        for entry, text in entries.items():
            zf.writestr(entry, text)
    return Path(path)


def _part_mesh(parts: Parts, part: str) -> tuple[np.ndarray, np.ndarray]:
    """Every solid of a part in one mesh: vertices (mm) and triangles, no vertex shared."""
    return stack_meshes(part_meshes(parts, part))


def _prusa_entries(meshes, name: str, settings) -> dict[str, str]:
    """The files of the PrusaSlicer flavour (one object, a triangle range per part)."""
    all_v, all_t, ranges, mats, voff, toff = [], [], [], [], 0, 0
    for n in PART_NAMES:
        v, t = meshes[n]
        all_v.append(v)
        all_t.append(t + voff)
        ranges.append((toff, toff + len(t) - 1))
        mats.append(np.full(len(t), list(MATERIAL_COLORS).index(PART_MATERIALS[n])))
        voff, toff = voff + len(v), toff + len(t)
    verts, tris, mat = np.vstack(all_v), np.vstack(all_t), np.concatenate(mats)
    head = _model_head(f"origami_cad {__version__}", name)
    model = [
        *head,
        f'  <object id="2" type="model" name="{xml_text(name)}" pid="1" pindex="0">',
        *_mesh_lines(verts, tris, mat),
        "  </object>",
        *_model_tail(2),
    ]
    prusa, bambu = _slicer_configs(ranges, name)
    return {
        "3D/3dmodel.model": "\n".join(model),
        "Metadata/Slic3r_PE_model.config": "\n".join(prusa),
        "Metadata/model_settings.config": "\n".join(bambu),
        "Metadata/Slic3r_PE.config": _prusa_print_config(settings),
        "Metadata/project_settings.config": _bambu_project_config(settings),
    }


def _bambu_entries(meshes, name: str, settings, slicer: str) -> dict[str, str]:
    """The files of the Bambu Studio / OrcaSlicer flavour (a mesh object per part)."""
    application = APPLICATIONS[slicer]
    head = _model_head(application, name, bambu=True)
    model, parts = list(head), []
    for k, n in enumerate(PART_NAMES):
        object_id, material = k + 2, PART_MATERIALS[n]
        pindex = list(MATERIAL_COLORS).index(material)
        model.append(
            f'  <object id="{object_id}" type="model" name="{xml_text(n)}" pid="1" '
            f'pindex="{pindex}">'
        )
        model += [*_mesh_lines(*meshes[n]), "  </object>"]
        parts.append((object_id, n, EXTRUDERS[material]))
    assembly = len(PART_NAMES) + 2
    model.append(f'  <object id="{assembly}" type="model" name="{xml_text(name)}">')
    model.append("   <components>")
    model += [f'    <component objectid="{i}"/>' for i, _, _ in parts]
    model += ["   </components>", "  </object>", *_model_tail(assembly)]
    version = application.split("-", 1)[1]
    return {
        "3D/3dmodel.model": "\n".join(model),
        "Metadata/model_settings.config": "\n".join(model_settings_config(assembly, parts, name)),
        "Metadata/project_settings.config": project_settings_config(settings, version),
    }


def _model_head(application: str, name: str, bambu: bool = False) -> list[str]:
    """``3D/3dmodel.model`` up to the objects: metadata and the two base materials."""
    xmlns = ' xmlns:BambuStudio="http://schemas.bambulab.com/package/2021"' if bambu else ""
    head = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        '<model unit="millimeter" xml:lang="en-US" '
        f'xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02"{xmlns}>',
        f' <metadata name="Application">{xml_text(application)}</metadata>',
    ]
    if bambu:  # the 3MF layout version Bambu Studio writes (VERSION_BBS_3MF)
        head.append(' <metadata name="BambuStudio:3mfVersion">1</metadata>')
    head += [f' <metadata name="Title">{xml_text(name)}</metadata>', " <resources>"]
    head.append('  <basematerials id="1">')
    for material, color in MATERIAL_COLORS.items():
        head.append(f'   <base name="{material}" displaycolor="{color}FF"/>')
    return [*head, "  </basematerials>"]


def _model_tail(item: int) -> list[str]:
    """``3D/3dmodel.model`` after the objects: the one build item."""
    return [" </resources>", " <build>", f'  <item objectid="{item}"/>', " </build>", "</model>"]


def _rows(template: str, values: list, width: int, chunk: int = 4096) -> list[str]:
    """``template % row`` for each row of ``width`` values (a flat list), one string per chunk.

    One ``%`` per chunk of rows rather than one per row: the same text, formatted in C.
    """
    out = []
    for start in range(0, len(values), chunk * width):
        part = values[start : start + chunk * width]
        out.append("\n".join([template] * (len(part) // width)) % tuple(part))
    return out


def _mesh_lines(verts: np.ndarray, tris: np.ndarray, mat: np.ndarray | None = None) -> list[str]:
    """``<mesh>`` of an object; with ``mat``, each triangle's base material index."""
    vertex = '     <vertex x="%.6f" y="%.6f" z="%.6f"/>'
    lines = ["   <mesh>", "    <vertices>", *_rows(vertex, verts.ravel().tolist(), 3)]
    lines += ["    </vertices>", "    <triangles>"]
    if mat is None:
        triangle = '     <triangle v1="%d" v2="%d" v3="%d"/>'
        lines += _rows(triangle, tris.ravel().tolist(), 3)
    else:
        triangle = '     <triangle v1="%d" v2="%d" v3="%d" pid="1" p1="%d"/>'
        lines += _rows(triangle, np.column_stack([tris, mat]).ravel().tolist(), 4)
    return [*lines, "    </triangles>", "   </mesh>"]


def _slicer_configs(ranges: list[tuple[int, int]], name: str) -> tuple[list[str], list[str]]:
    """The lines of PrusaSlicer's and Bambu Studio's configs: each part's triangles and extruder."""
    prusa = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        "<config>",
        ' <object id="2" instances_count="1">',
        f'  <metadata type="object" key="name" value="{xml_text(name)}"/>',
    ]
    bambu = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        "<config>",
        ' <object id="2">',
        f'  <metadata key="name" value="{xml_text(name)}"/>',
        '  <metadata key="extruder" value="1"/>',
    ]
    for k, (n, (first, last)) in enumerate(zip(PART_NAMES, ranges, strict=True)):
        ext = EXTRUDERS[PART_MATERIALS[n]]
        prusa += [
            f'  <volume firstid="{first}" lastid="{last}">',
            f'   <metadata type="volume" key="name" value="{n}"/>',
            '   <metadata type="volume" key="volume_type" value="ModelPart"/>',
            f'   <metadata type="volume" key="extruder" value="{ext}"/>',
            "  </volume>",
        ]
        bambu += [
            f'  <part id="{k + 1}" subtype="normal_part" firstid="{first}" lastid="{last}">',
            f'   <metadata key="name" value="{n}"/>',
            f'   <metadata key="extruder" value="{ext}"/>',
            f'   <metadata key="source_volume_id" value="{k}"/>',
            "  </part>",
        ]
    prusa += [" </object>", "</config>"]
    bambu += [" </object>", "</config>"]
    return prusa, bambu


def _write_fabrication_3mf(fab, folder: Path) -> dict[str, Path]:
    name = fab.pattern.title or "origami"
    path = folder / "print.3mf"
    return {"3mf": export_3mf(fab.parts, path, name=name, params=fab.params, slicer=fab.slicer)}


#: What ``write_fabrication`` writes of this format: ``{format: writer(fab, folder)}``.
WRITERS = {"3mf": _write_fabrication_3mf}
