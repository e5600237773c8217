"""DXF crease patterns written: layers Mountain, Valley (dashed), Cut, Border, Flat,
Unassigned, Join and Holes, in millimetres (``$INSUNITS`` = 4), every LINE also with its
own ACI colour (1 mountain, 5 valley, 3 cut and border: ORIPA reads the colours, not the
layers). :mod:`origami_cad.pattern.formats.dxf` reads them back and registers the format.
"""

from __future__ import annotations

import os
from pathlib import Path

from origami_cad._fileio import atomic_path
from origami_cad.pattern.model import CreasePattern

__all__ = ["write_dxf"]

#: assignment -> (layer, ACI colour, linetype) written by :func:`write_dxf`
_LAYERS = {
    "M": ("Mountain", 1, "CONTINUOUS"),
    "V": ("Valley", 5, "DASHED"),
    "C": ("Cut", 3, "CONTINUOUS"),
    "B": ("Border", 7, "CONTINUOUS"),
    "F": ("Flat", 8, "CONTINUOUS"),
    "U": ("Unassigned", 9, "CONTINUOUS"),
    "J": ("Join", 9, "CONTINUOUS"),
}
_HOLE_LAYER = ("Holes", 4)
#: assignment -> the ACI colour of each LINE (ORIPA reads these, not the layers')
_LINE_ACI = {"M": 1, "V": 5, "C": 3, "B": 3, "F": 8, "U": 9, "J": 9}


def _dxf_text(text: str, limit: int = 255) -> str:
    """``text`` safe as one DXF string value: a line break would start a new group
    (injecting entities), so control characters become spaces; lone surrogates,
    which no encoding holds, become U+FFFD; at most ``limit`` characters."""
    out = []
    for c in str(text)[:limit]:
        code = ord(c)
        out.append(" " if code < 32 or code == 127 else "\ufffd" if 0xD800 <= code < 0xE000 else c)
    return "".join(out)


def write_dxf(cp: CreasePattern, path: str | os.PathLike[str]) -> Path:
    """Write a crease pattern as a DXF file (R2010, millimetres), atomically.

    Parameters
    ----------
    cp : CreasePattern
        The pattern; coordinates in mm.
    path : path-like
        Output ``.dxf`` file; replaced only once it is completely written.

    Returns
    -------
    Path
        ``path``.

    Notes
    -----
    Fold angles are not stored (DXF has no place for them): reading the file
    back gives the default +-180 degrees for mountains and valleys.
    """
    import ezdxf

    doc = ezdxf.new("R2010", setup=True)  # setup: standard linetypes incl. DASHED
    doc.header["$INSUNITS"] = 4
    doc.header["$MEASUREMENT"] = 1
    if cp.title:
        doc.header["$PROJECTNAME"] = _dxf_text(cp.title)
    for name, color, linetype in dict.fromkeys(_LAYERS.values()):
        doc.layers.add(name, color=color, linetype=linetype)
    doc.layers.add(_HOLE_LAYER[0], color=_HOLE_LAYER[1])
    msp = doc.modelspace()
    for (a, b), letter in zip(cp.edges.tolist(), cp.assignments.tolist(), strict=True):
        xa, ya = cp.vertices[a]
        xb, yb = cp.vertices[b]
        msp.add_line(
            (float(xa), float(ya)),
            (float(xb), float(yb)),
            dxfattribs={"layer": _LAYERS[letter][0], "color": _LINE_ACI[letter]},
        )
    for h in cp.holes:
        attribs = {"layer": _HOLE_LAYER[0], "color": _HOLE_LAYER[1]}
        msp.add_circle((h.x, h.y), h.diameter / 2, dxfattribs=attribs)
    x0, y0, x1, y1 = cp.bounds
    doc.set_modelspace_vport(
        height=1.1 * max(y1 - y0, (x1 - x0) * 0.75, 1.0), center=((x0 + x1) / 2, (y0 + y1) / 2)
    )
    with atomic_path(path) as tmp:
        doc.saveas(tmp)
    return Path(path)
