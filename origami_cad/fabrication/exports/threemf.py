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
            if isinstance(text, list):  # the model: its lines streamed into the archive
                rows = sum(len(v) + len(t) for v, t in meshes.values())
                _write_lines(zf, entry, text, large=rows * _ROW_BYTES > zipfile.ZIP64_LIMIT)
            else:
                zf.writestr(entry, text)
    return Path(path)


#: Most bytes a vertex or triangle line of the model takes (whether a member needs ZIP64)
_ROW_BYTES = 128


def _write_lines(zf: zipfile.ZipFile, entry: str, lines: list, large: bool = False) -> None:
    """Lines (``str``, ``bytes``, or iterables of ``bytes`` blocks of whole lines) joined
    by newlines into archive member ``entry``, written as they are made: the text of a
    large mesh is never held whole (a 30 x 30 sheet's model is hundreds of MB). ``large``:
    the member may pass 2 GiB (ZIP64 headers; the archive is otherwise as before)."""
    with zf.open(entry, "w", force_zip64=large) as fh:
        first = True
        for line in lines:
            blocks = [line] if isinstance(line, str | bytes) else line
            for block in blocks:
                if block == b"":
                    continue
                fh.write(_bytes(block) if first else b"\n" + _bytes(block))
                first = False


def _bytes(text: str | bytes) -> bytes:
    return text if isinstance(text, bytes) else text.encode()


def _part_mesh(parts: Parts, part: str) -> tuple[np.ndarray, np.ndarray]:
    """Every solid of a part in one mesh: vertices (mm) and triangles, no vertex shared."""
    return stack_meshes(part_meshes(parts, part))


def _prusa_entries(meshes, name: str, settings) -> dict[str, str | bytes]:
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
        "3D/3dmodel.model": model,
        "Metadata/Slic3r_PE_model.config": "\n".join(prusa),
        "Metadata/model_settings.config": "\n".join(bambu),
        "Metadata/Slic3r_PE.config": _prusa_print_config(settings),
        "Metadata/project_settings.config": _bambu_project_config(settings),
    }


def _bambu_entries(meshes, name: str, settings, slicer: str) -> dict[str, str | bytes]:
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
        "3D/3dmodel.model": model,
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


#: Four ASCII digits per number, by table look-up: "0000" ... "9999" (rows 0 ... 9999), then
#: the same without leading zeros, NUL-padded ("\\0\\0\\00" ... "9999"), then four NULs.
_FOUR_DIGITS = np.frombuffer(
    b"".join(b"%04d" % i for i in range(10000))
    + b"".join((b"%4d" % i).replace(b" ", b"\0") for i in range(10000))
    + b"\0" * 4,
    dtype=np.uint32,
)


def _digit_groups(values: np.ndarray, groups: int, leading: bool) -> np.ndarray:
    """Non-negative integers as ``4 * groups`` ASCII digits each: (n, 4 g) bytes.

    With ``leading``, the leading zeros are NUL (a zero is written ``0``), else kept.
    """
    parts = []
    rest = values
    for _ in range(groups):
        rest, low = np.divmod(rest, 10000)
        parts.append(low)
    out = np.empty((len(values), groups), dtype=np.uint32)
    ahead = np.full(len(values), leading)  # only zeros so far
    for g, low in enumerate(parts[::-1]):
        if not leading:
            out[:, g] = _FOUR_DIGITS[low]
            continue
        row = np.where(ahead, low + 10000, low)
        if g < groups - 1:
            row = np.where(ahead & (low == 0), 20000, row)
        out[:, g] = _FOUR_DIGITS[row]
        ahead &= low == 0
    return out.view(np.uint8)


def _number_fields(values: np.ndarray, decimals: int) -> list[np.ndarray]:
    """Each value as ``"%.<decimals>f"`` writes it (``%d`` with 0): NUL-padded byte blocks.

    The blocks (sign, whole part, and with decimals the point and the fraction), each
    (n, w) bytes, side by side make the text. Rounded half to even at ``decimals`` (0 to 8);
    a value that rounds to zero has no sign.
    """
    if decimals == 0:
        q = np.asarray(values, dtype=np.int64)
    else:
        q = np.rint(np.asarray(values, dtype=float) * 10.0**decimals).astype(np.int64)
    whole, frac = np.divmod(np.abs(q), 10**decimals)
    top = int(whole.max()) if len(whole) else 0
    digits = _digit_groups(whole, max(1, -(-len(str(top)) // 4)), leading=True)
    sign = np.where(q < 0, ord("-"), 0).astype(np.uint8)[:, None]
    if not decimals:
        return [sign, digits]
    fraction = _digit_groups(frac, 2, leading=False)[:, 8 - decimals :]
    return [sign, digits, np.frombuffer(b".", dtype=np.uint8), fraction]


def _rows(pieces: list[str], columns: np.ndarray, decimals: int) -> bytes:
    """One line per row of ``columns``: ``pieces[0] col0 pieces[1] col1 ... pieces[-1]``.

    The numbers are written as ``%.<decimals>f`` writes them (``%d`` with 0 decimals;
    rounded half to even, no ``-`` on a zero); the lines are joined by newlines.
    Formatted with NumPy, a whole column at once.
    """
    rows = len(columns)
    if not rows:
        return b""
    literal = [np.frombuffer(p.encode(), dtype=np.uint8) for p in pieces]
    literal[-1] = np.append(literal[-1], np.uint8(10))
    blocks = [literal[0]]
    for k in range(columns.shape[1]):
        blocks += [*_number_fields(columns[:, k], decimals), literal[k + 1]]
    widths = [b.shape[-1] for b in blocks]
    text = np.empty((rows, sum(widths)), dtype=np.uint8)
    for block, start in zip(blocks, np.cumsum([0, *widths[:-1]]).tolist(), strict=True):
        text[:, start : start + block.shape[-1]] = block
    flat = text.reshape(-1)  # the NULs dropped by a mask: faster than bytes.replace
    return flat[flat != 0][:-1].tobytes()


def _mesh_lines(verts: np.ndarray, tris: np.ndarray, mat: np.ndarray | None = None) -> list:
    """``<mesh>`` of an object (lines; the vertices and the triangles each one ``bytes``).

    With ``mat``, each triangle's base material index. A NaN or infinite coordinate (which
    the integer formatting would turn into a wrong number) is a :class:`FabricationError`.
    """
    if not np.isfinite(verts).all():
        raise FabricationError("3MF: a mesh vertex is NaN or infinite; 3MF holds finite mm")
    vertex = ['     <vertex x="', '" y="', '" z="', '"/>']
    lines = ["   <mesh>", "    <vertices>", _row_blocks(vertex, verts.reshape(-1, 3), 6)]
    lines += ["    </vertices>", "    <triangles>"]
    if mat is None:
        triangle = ['     <triangle v1="', '" v2="', '" v3="', '"/>']
        lines.append(_row_blocks(triangle, tris.reshape(-1, 3), 0))
    else:
        triangle = ['     <triangle v1="', '" v2="', '" v3="', '" pid="1" p1="', '"/>']
        columns = np.column_stack([tris, np.asarray(mat).reshape(-1, 1)]).astype(np.int64)
        lines.append(_row_blocks(triangle, columns, 0))
    return [*lines, "    </triangles>", "   </mesh>"]


#: Rows formatted at once by :func:`_row_blocks` (bounds the formatting's memory)
ROW_BLOCK = 65_536


def _row_blocks(pieces: list[str], columns: np.ndarray, decimals: int):
    """:func:`_rows` of ``columns``, :data:`ROW_BLOCK` rows at a time (a generator of
    ``bytes`` blocks of whole lines, made as the archive takes them)."""
    for start in range(0, len(columns), ROW_BLOCK):
        yield _rows(pieces, columns[start : start + ROW_BLOCK], decimals)


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
