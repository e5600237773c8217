"""Exports of the printed parts: four STL files, a STEP assembly and a slicer-ready 3MF.

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
from build123d import Color, Compound, Location, Solid, export_step, export_stl

from origami_cad import __version__
from origami_cad._fileio import atomic_path
from origami_cad._names import slicer_value, xml_text
from origami_cad.fabrication.params import FabricationParams
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES, Parts

__all__ = [
    "EXTRUDERS",
    "MATERIAL_COLORS",
    "MATERIAL_SETTINGS",
    "export_3mf",
    "export_part",
    "export_step_assembly",
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

#: Extruder of each material (1-based, as slicers count).
EXTRUDERS = {"PLA": 1, "TPU": 2}
#: Display colour of each material (sRGB hex): PLA white, TPU red.
MATERIAL_COLORS = {"PLA": "#F2F2F2", "TPU": "#D62728"}

#: Tessellation of the exports: chordal tolerance (mm) and angular tolerance (rad).
TOLERANCE, ANGULAR_TOLERANCE = 0.01, 0.1


def export_stls(parts: Parts, folder: str | os.PathLike[str]) -> dict[str, Path]:
    """Write ``<part>.stl`` (binary, assembly position) for each of the four parts."""
    out = {}
    for name in PART_NAMES:
        path = Path(folder) / f"{name}.stl"
        with atomic_path(path) as tmp:
            ok = export_stl(
                parts.compound(name),
                str(tmp),
                tolerance=TOLERANCE,
                angular_tolerance=ANGULAR_TOLERANCE,
                ascii_format=False,
            )
            if ok is False:
                raise OSError(f"{path}: the STL writer failed")
        out[name] = path
    return out


def material_color(material: str) -> Color:
    """The display colour of a material (``"PLA"`` or ``"TPU"``) as a build123d colour."""
    hexa = MATERIAL_COLORS[material].lstrip("#")
    return Color(*(int(hexa[i : i + 2], 16) / 255 for i in (0, 2, 4)))


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
    with atomic_path(path) as tmp:
        ok = export_step(assembly, str(tmp))
        if ok is False:
            raise OSError(f"{path}: the STEP writer failed")
    return Path(path)


def read_binary_stl(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (welded, mm) and triangles of a binary STL file."""
    raw = Path(path).read_bytes()
    count = int(np.frombuffer(raw, dtype="<u4", count=1, offset=80)[0])
    record = np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    data = np.frombuffer(raw, dtype=record, count=count, offset=84)
    corners = data["v"].reshape(-1, 3).astype(float)
    verts, inverse = np.unique(corners, axis=0, return_inverse=True)
    return verts, inverse.reshape(-1, 3)


def solid_mesh(solid: Solid) -> tuple[np.ndarray, np.ndarray]:
    """One solid meshed by OCC: vertices (mm) welded within the solid, triangles.

    Vertices are welded only inside one solid, never across solids: neighbouring
    shell chamfers meet on a line, and welding them would join four triangles on one
    edge. Triangles that collapse in the weld are dropped.
    """
    points, triangles = solid.tessellate(TOLERANCE, ANGULAR_TOLERANCE)
    v = np.array([(p.X, p.Y, p.Z) for p in points], dtype=float).reshape(-1, 3)
    t = np.array(triangles, dtype=np.int64).reshape(-1, 3)
    key = np.round(v / 1e-6).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    t = inverse.reshape(-1)[t]
    t = t[(t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 2] != t[:, 0])]
    return v[first], t


def part_meshes(parts: Parts, name: str) -> list[tuple[np.ndarray, np.ndarray]]:
    """The meshes of every solid of a part (see :func:`solid_mesh`)."""
    return [solid_mesh(s) for s in parts.solids[name]]


def parts_tessellation(parts: Parts) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each part as one plain mesh: vertices (mm, assembly position) and triangles.

    The solids of a part are stacked (:func:`part_meshes`, no vertex shared between
    solids); this is what other stages draw, as NumPy arrays rather than build123d
    shapes.
    """
    out = {}
    for name in PART_NAMES:
        verts, tris, offset = [np.zeros((0, 3))], [np.zeros((0, 3), dtype=np.int64)], 0
        for v, t in part_meshes(parts, name):
            verts.append(v)
            tris.append(t + offset)
            offset += len(v)
        out[name] = (np.vstack(verts), np.vstack(tris))
    return out


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


def slicer_settings(params: FabricationParams | None = None) -> dict[str, object]:
    """The print settings carried by the 3MF, as plain data (see docs/fabrication.md).

    Extruder 1 prints PLA, extruder 2 TPU (:data:`EXTRUDERS`); ``layer_height`` and
    ``first_layer_height`` come from :func:`layer_height`; temperatures in deg C.
    """
    params = params or FabricationParams()
    h = layer_height(params)
    mats = sorted(EXTRUDERS, key=EXTRUDERS.get)
    per = [MATERIAL_SETTINGS[m] for m in mats]
    return {
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
    }
    head = f"; generated by origami_cad {__version__}\n\n"
    return head + "".join(f"; {k} = {slicer_value(v)}\n" for k, v in lines.items())


def _strings(values) -> list[str]:
    return [f"{v:g}" if isinstance(v, float) else str(v) for v in values]


def _bambu_project_config(settings: dict[str, object]) -> str:
    """``Metadata/project_settings.config``: Bambu Studio / OrcaSlicer settings (JSON)."""
    return json.dumps(
        {
            "layer_height": f"{settings['layer_height']:g}",
            "initial_layer_print_height": f"{settings['first_layer_height']:g}",
            "filament_type": ["TPU" if t == "FLEX" else t for t in settings["filament_type"]],
            "nozzle_temperature": _strings(settings["temperature"]),
            "nozzle_temperature_initial_layer": _strings(settings["first_layer_temperature"]),
            "hot_plate_temp": _strings(settings["bed_temperature"]),
            "hot_plate_temp_initial_layer": _strings(settings["bed_temperature"]),
            "filament_max_volumetric_speed": _strings(settings["filament_max_volumetric_speed"]),
            "filament_colour": list(settings["filament_colour"]),
            "nozzle_diameter": ["0.4", "0.4"],
        },
        indent=1,
    )


def export_3mf(
    parts: Parts,
    path: str | os.PathLike[str],
    name: str = "origami",
    params: FabricationParams | None = None,
) -> Path:
    """Write a 3MF with one four-part object, the slicers' extruder metadata and settings.

    The object's mesh holds every solid as its own closed, oriented shell (no vertex
    shared between solids), the triangles of each part in one range. PrusaSlicer reads
    the ranges from ``Metadata/Slic3r_PE_model.config`` and its settings from
    ``Metadata/Slic3r_PE.config``; Bambu Studio and OrcaSlicer read the ranges
    (``firstid``/``lastid`` on each ``<part>``) from ``Metadata/model_settings.config``
    and their settings from ``Metadata/project_settings.config``.
    """
    all_v, all_t, ranges, mats, voff, toff = [], [], [], [], 0, 0
    for n in PART_NAMES:
        first = toff
        for v, t in part_meshes(parts, n):
            all_v.append(v)
            all_t.append(t + voff)
            voff += len(v)
            toff += len(t)
        ranges.append((first, toff - 1))
        mats.append(np.full(toff - first, list(MATERIAL_COLORS).index(PART_MATERIALS[n])))
    verts, tris, mat = np.vstack(all_v), np.vstack(all_t), np.concatenate(mats)
    model = _model_xml(verts, tris, mat, name)
    prusa, bambu = _slicer_configs(ranges, name)
    settings = slicer_settings(params)
    content_types = (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
        '<Default Extension="rels" '
        'ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
        '<Default Extension="model" '
        'ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
        '<Default Extension="config" ContentType="text/xml"/>'
        "</Types>"
    )
    rels = (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
        '<Relationship Target="/3D/3dmodel.model" Id="rel0" '
        'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>'
        "</Relationships>"
    )
    with atomic_path(path) as tmp, zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("[Content_Types].xml", content_types)
        zf.writestr("_rels/.rels", rels)
        zf.writestr("3D/3dmodel.model", "\n".join(model))
        zf.writestr("Metadata/Slic3r_PE_model.config", "\n".join(prusa))
        zf.writestr("Metadata/model_settings.config", "\n".join(bambu))
        zf.writestr("Metadata/Slic3r_PE.config", _prusa_print_config(settings))
        zf.writestr("Metadata/project_settings.config", _bambu_project_config(settings))
    return Path(path)


def _model_xml(verts: np.ndarray, tris: np.ndarray, mat: np.ndarray, name: str) -> list[str]:
    """The lines of ``3D/3dmodel.model``: one object, a material index per triangle."""
    model = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        '<model unit="millimeter" xml:lang="en-US" '
        'xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">',
        f' <metadata name="Application">origami_cad {__version__}</metadata>',
        f' <metadata name="Title">{xml_text(name)}</metadata>',
        " <resources>",
        '  <basematerials id="1">',
    ]
    for material, color in MATERIAL_COLORS.items():
        model.append(f'   <base name="{material}" displaycolor="{color}FF"/>')
    model += [
        "  </basematerials>",
        f'  <object id="2" type="model" name="{xml_text(name)}" pid="1" pindex="0">',
        "   <mesh>",
        "    <vertices>",
    ]
    vertex = '     <vertex x="%.6f" y="%.6f" z="%.6f"/>'
    model += [vertex % tuple(v) for v in verts.tolist()]
    model += ["    </vertices>", "    <triangles>"]
    model += [
        f'     <triangle v1="{a}" v2="{b}" v3="{c}" pid="1" p1="{m}"/>'
        for (a, b, c), m in zip(tris.tolist(), mat.tolist(), strict=True)
    ]
    model += [
        "    </triangles>",
        "   </mesh>",
        "  </object>",
        " </resources>",
        " <build>",
        '  <item objectid="2"/>',
        " </build>",
        "</model>",
    ]
    return model


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


def lay_on_bed(shape):
    """A copy of a part or assembly moved along z so that its lowest point is at z = 0.

    x and y are kept; an assembly keeps its tree of named, coloured children (each
    child moved by the same amount), so slicers place it on the bed as built.
    """
    dz = -shape.bounding_box().min.Z
    return _moved_tree(shape, Location((0.0, 0.0, dz)))


def _moved_tree(shape, loc: Location):
    children = list(getattr(shape, "children", ()) or ())
    if not children:
        out = shape.moved(loc)
    else:
        out = Compound(children=[_moved_tree(c, loc) for c in children])
    out.label = shape.label
    if getattr(shape, "color", None) is not None:
        out.color = shape.color
    return out


def export_part(part, folder: str | os.PathLike[str], name: str) -> list[Path]:
    """Write ``name.step`` and ``name.stl`` (binary) of a part or assembly (atomic).

    Both files hold the part laid on the print bed (:func:`lay_on_bed`: its lowest
    point at z = 0, x and y as built), so a slicer places it where it prints.
    """
    part = lay_on_bed(part)
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    step, stl = out / f"{name}.step", out / f"{name}.stl"
    with atomic_path(step) as tmp:
        if export_step(part, str(tmp)) is False:
            raise OSError(f"{step}: the STEP writer failed")
    with atomic_path(stl) as tmp:
        if (
            export_stl(
                part,
                str(tmp),
                tolerance=TOLERANCE,
                angular_tolerance=ANGULAR_TOLERANCE,
                ascii_format=False,
            )
            is False
        ):
            raise OSError(f"{stl}: the STL writer failed")
    return [step, stl]
