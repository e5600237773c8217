"""DXF reader and writer (ezdxf).

Writing: one LINE per edge on layers ``Mountain`` (ACI 1, red), ``Valley`` (ACI 5,
blue, dashed), ``Cut`` (ACI 3, green), ``Border`` (ACI 7), ``Flat`` (ACI 8) and
``Unassigned`` (ACI 9); holes as CIRCLEs on layer ``Holes``; ``$INSUNITS`` = 4 (mm).

Reading: LINE, LWPOLYLINE and POLYLINE entities, in model space and inside block
references (transformed); ARC, CIRCLE, ELLIPSE and SPLINE are flattened, for
border and cut lines only (a curved crease cannot fold rigidly); circles on a
``Hole`` layer become holes. Each entity is classified, in this order:

1. by layer name (any case): mountain, valley, cut (also ORIPA's ``CutLine``),
   border / boundary / outline, flat / aux;
2. by colour, the entity's own or else its layer's: ACI 1 or 10-39 mountain,
   5 or 140-199 valley, 3 or 60-129 cut, 7, 8, 9 and 250-255 (black, white and
   greys) border; true colours by their dominant channel (grey: border);
3. by linetype: dashed (``DASH``, ``HIDDEN``) means valley.

Anything still unclassified is an error that names the entities, never a guess.
ORIPA draws the outline of the sheet as cut lines: cut lines on the outer
boundary become border; cut lines inside stay cuts. ``$INSUNITS`` is honoured
(inches, feet, cm, m are converted to mm; unitless is taken as mm).
"""

from __future__ import annotations

import itertools
import os
from pathlib import Path

import numpy as np
import shapely

from origami_cad._fileio import atomic_path
from origami_cad.errors import PatternError
from origami_cad.pattern.model import CreasePattern, Hole

__all__ = ["read_dxf", "write_dxf"]

_LAYERS = {
    "M": ("Mountain", 1, "CONTINUOUS"),
    "V": ("Valley", 5, "DASHED"),
    "C": ("Cut", 3, "CONTINUOUS"),
    "B": ("Border", 7, "CONTINUOUS"),
    "F": ("Flat", 8, "CONTINUOUS"),
    "U": ("Unassigned", 9, "CONTINUOUS"),
    "J": ("Unassigned", 9, "CONTINUOUS"),
}
_HOLE_LAYER = ("Holes", 4)
#: $INSUNITS code -> millimetres per unit
_UNITS = {
    0: 1.0,
    1: 25.4,
    2: 304.8,
    4: 1.0,
    5: 10.0,
    6: 1000.0,
    8: 25.4e-6,
    9: 25.4e-3,
    10: 914.4,
    13: 1e-3,
    14: 100.0,
}


def write_dxf(cp: CreasePattern, path: str | os.PathLike[str]) -> Path:
    """Write ``cp`` as a DXF (R2010) in millimetres, atomically."""
    import ezdxf

    doc = ezdxf.new("R2010", setup=True)
    doc.header["$INSUNITS"] = 4
    doc.header["$MEASUREMENT"] = 1
    msp = doc.modelspace()
    for name, color, linetype in {v[0]: v for v in _LAYERS.values()}.values():
        doc.layers.add(name, color=color, linetype=linetype)
    doc.layers.add(_HOLE_LAYER[0], color=_HOLE_LAYER[1])
    for (a, b), letter in zip(cp.edges, cp.assignments, strict=True):
        pa, pb = cp.vertices[a], cp.vertices[b]
        msp.add_line(
            (float(pa[0]), float(pa[1])),
            (float(pb[0]), float(pb[1])),
            dxfattribs={"layer": _LAYERS[str(letter)][0]},
        )
    for h in cp.holes:
        msp.add_circle((h.x, h.y), h.diameter / 2, dxfattribs={"layer": _HOLE_LAYER[0]})
    with atomic_path(path) as tmp:
        doc.saveas(tmp)
    return Path(path)


def _by_layer_name(name: str) -> str | None:
    low = name.lower()
    for words, letter in (
        (("mountain",), "M"),
        (("valley",), "V"),
        (("cut",), "C"),
        (("border", "boundary", "outline", "edge"), "B"),
        (("flat", "aux"), "F"),
    ):
        if any(w in low for w in words):
            return letter
    return None


def _by_aci(aci: int) -> str | None:
    if aci == 1 or 10 <= aci <= 39:
        return "M"
    if aci == 5 or 140 <= aci <= 199:
        return "V"
    if aci == 3 or 60 <= aci <= 129:
        return "C"
    if aci in (7, 8, 9) or 250 <= aci <= 255:
        return "B"
    return None


def _by_rgb(rgb: tuple[int, int, int]) -> str | None:
    if max(rgb) - min(rgb) <= 16:
        return "B"  # black, white, grey
    channel = int(np.argmax(rgb))
    if sorted(rgb)[-1] - sorted(rgb)[-2] < 32:
        return None  # no dominant channel (e.g. yellow, magenta)
    return "MCV"[channel]


def _classify(entity, doc) -> str | None:
    layer_name = entity.dxf.get("layer", "0")
    letter = _by_layer_name(layer_name)
    if letter:
        return letter
    layer = doc.layers.get(layer_name) if doc.layers.has_entry(layer_name) else None
    if entity.dxf.hasattr("true_color"):
        letter = _by_rgb(entity.rgb)
        if letter:
            return letter
    aci = entity.dxf.get("color", 256)
    if aci not in (0, 256):  # not BYBLOCK / BYLAYER
        letter = _by_aci(aci)
        if letter:
            return letter
    elif layer is not None:
        if layer.dxf.hasattr("true_color"):
            letter = _by_rgb(layer.rgb)
            if letter:
                return letter
        letter = _by_aci(abs(layer.dxf.get("color", 7)))
        if letter:
            return letter
    linetype = str(entity.dxf.get("linetype", "BYLAYER")).upper()
    if linetype in ("BYLAYER", "BYBLOCK") and layer is not None:
        linetype = str(layer.dxf.get("linetype", "CONTINUOUS")).upper()
    if "DASH" in linetype or "HIDDEN" in linetype:
        return "V"
    return None


def _describe(entity) -> str:
    return (
        f"handle {entity.dxf.handle} ({entity.dxftype()}) on layer "
        f"{entity.dxf.get('layer', '0')!r}, colour {entity.dxf.get('color', 256)}"
    )


def _entities(space, depth: int = 0):
    for e in space:
        if e.dxftype() == "INSERT" and depth < 16:
            yield from _entities(e.virtual_entities(), depth + 1)
        else:
            yield e


def read_dxf(path: str | os.PathLike[str]) -> CreasePattern:
    """Read a crease pattern from a DXF file (converted to mm).

    Raises
    ------
    PatternError
        Naming the file and the entities that could not be read or classified.
    """
    import ezdxf
    from ezdxf import path as ezpath

    p = Path(path)
    if not p.is_file():
        raise PatternError(f"{p}: no such file")
    try:
        doc = ezdxf.readfile(str(p))
    except (OSError, ezdxf.DXFError) as exc:
        raise PatternError(f"{p}: not a readable DXF file ({exc})") from None
    scale = _UNITS.get(int(doc.header.get("$INSUNITS", 0)), 1.0)
    segments: list[tuple[tuple[float, float], tuple[float, float], str]] = []
    holes: list[Hole] = []
    unknown: list[str] = []
    for e in _entities(doc.modelspace()):
        kind = e.dxftype()
        if kind not in ("LINE", "LWPOLYLINE", "POLYLINE", "ARC", "CIRCLE", "ELLIPSE", "SPLINE"):
            continue
        layer = str(e.dxf.get("layer", "0")).lower()
        if kind == "CIRCLE" and "hole" in layer:
            c = e.dxf.center
            holes.append(Hole(c.x * scale, c.y * scale, 2 * e.dxf.radius * scale))
            continue
        letter = _classify(e, doc)
        if letter is None:
            unknown.append(_describe(e))
            continue
        if kind == "LINE":
            a, b = e.dxf.start, e.dxf.end
            segments.append(((a.x, a.y), (b.x, b.y), letter))
            continue
        curved = kind in ("ARC", "CIRCLE", "ELLIPSE", "SPLINE") or (
            kind == "LWPOLYLINE" and any(abs(v[4]) > 1e-12 for v in e.get_points("xyseb"))
        )
        if curved and letter not in ("B", "C"):
            name = {"M": "mountain", "V": "valley"}.get(letter, "crease")
            raise PatternError(
                f"{p}: {_describe(e)} is a curved {name} line; creases must be straight "
                "to fold rigidly"
            )
        if curved:
            pts = [(v.x, v.y) for v in ezpath.make_path(e).flattening(0.01 / scale)]
        elif kind == "LWPOLYLINE":
            pts = [(x, y) for x, y in e.get_points("xy")]
            if e.closed:
                pts.append(pts[0])
        else:
            pts = [(v.dxf.location.x, v.dxf.location.y) for v in e.vertices]
            if e.is_closed:
                pts.append(pts[0])
        segments += [(a, b, letter) for a, b in itertools.pairwise(pts) if a != b]
    if unknown:
        listed = "; ".join(unknown[:3]) + (
            f"; and {len(unknown) - 3} more" if len(unknown) > 3 else ""
        )
        raise PatternError(
            f"{p}: {len(unknown)} lines cannot be classified as mountain, valley, cut or "
            f"border by layer, colour or linetype ({listed})"
        )
    if not segments:
        raise PatternError(f"{p}: no crease lines found (no LINE, POLYLINE or ARC entities)")
    coords = np.array([[a, b] for a, b, _ in segments], dtype=float) * scale
    letters = [s[2] for s in segments]
    verts = coords.reshape(-1, 2)
    edges = np.arange(len(verts)).reshape(-1, 2)
    try:
        cp = CreasePattern(verts, edges, letters, metadata={"title": p.stem})
        if "C" in letters:  # ORIPA: cut lines on the sheet's outline are its border
            outline = shapely.union_all(cp.face_polygons())
            boundary = outline.boundary
            mids = (cp.vertices[cp.edges[:, 0]] + cp.vertices[cp.edges[:, 1]]) / 2
            on = shapely.dwithin(shapely.points(mids), boundary, 1e-6 * max(cp.size, 1.0))
            assign = np.where((cp.assignments == "C") & on, "B", cp.assignments)
            if np.any(assign != cp.assignments):
                cp = CreasePattern(
                    cp.vertices, cp.edges, assign, cp.fold_angles, metadata={"title": p.stem}
                )
    except PatternError as exc:
        raise PatternError(f"{p}: {exc}") from None
    return cp.with_holes(holes) if holes else cp
