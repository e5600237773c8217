"""ORIPA's ``.opx`` crease patterns: read and written.

An ``.opx`` file is the XML that Java's ``XMLEncoder`` writes of ORIPA's ``oripa.DataSet``:
an array of ``oripa.OriLineProxy`` objects, each a line from ``(x0, y0)`` to ``(x1, y1)``
with an integer ``type``, and the pattern's ``title``, ``editorName``,
``originalAuthorName``, ``reference`` and ``memo``. ``XMLEncoder`` leaves out a property
that has its default value, so a missing coordinate or type is 0.

=====  ================  =======================================================
type   ORIPA             here
=====  ================  =======================================================
0      auxiliary line    ``F`` (flat), as ORIPA's own FOLD export maps it
1      cut line          ``C``; those on the sheet's outer boundary ``B`` (ORIPA
                         draws the paper's outline as cut lines)
2      mountain          ``M``
3      valley            ``V``
4      unassigned        ``U``
9      cut-model line    left out (an outline ORIPA draws for its cut model, not
                         part of the crease pattern), with a note
=====  ================  =======================================================

ORIPA's y axis points down the screen (its DXF export turns it over): the reader turns
it up, so the pattern is seen as ORIPA shows it. Its files carry no unit: one unit is
read as one millimetre (ORIPA's default paper is 400 units wide), unless ``mm_per_unit``
says otherwise.

The writer writes what ORIPA 1.x reads back (``B`` and ``C`` as cut lines, ``F`` as
auxiliary lines); fold angles other than +-180 degrees, holes and ``J`` (join) edges
have no place in the format: a pattern with ``J`` edges is refused, naming one.

The reader refuses a document type declaration (``<!DOCTYPE``, ``<!ENTITY``: entity
expansion attacks; ``XMLEncoder`` never writes one), elements nested deeper than
:data:`MAX_DEPTH` or more than :data:`MAX_ELEMENTS` of them, and a number that is not
finite, each with a PatternError naming the file and the line.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from origami_cad._fileio import atomic_write
from origami_cad._names import xml_text
from origami_cad._toml import input_file, printable
from origami_cad.errors import PatternError
from origami_cad.pattern.formats.xmlparse import parse_bounded
from origami_cad.pattern.model import (
    MAX_COORDINATE,
    MAX_EDGES,
    CreasePattern,
    Problem,
    Severity,
)
from origami_cad.pattern.planar import Tolerance, import_tolerance

__all__ = [
    "MAX_DEPTH", "MAX_ELEMENTS", "ORIPA_TYPES", "oripa_pattern", "read_opx", "refuse_joins",
    "write_opx",
]  # fmt: skip

#: ORIPA's line type codes (``OriLine.Type``) and the assignment each is read as
#: (None: left out).
ORIPA_TYPES = {0: "F", 1: "C", 2: "M", 3: "V", 4: "U", 9: None}
#: The type code each assignment is written as.
_WRITE_TYPES = {"F": 0, "B": 1, "C": 1, "M": 2, "V": 3, "U": 4}
#: Deepest nesting of elements read (``XMLEncoder`` writes 8 levels).
MAX_DEPTH = 64
#: Most elements read (about 17 per line).
MAX_ELEMENTS = 20 * MAX_EDGES
_FIELDS = ("x0", "y0", "x1", "y1", "type")
_TEXTS = ("title", "editorName", "originalAuthorName", "reference", "memo")


def _parse(p: Path, name: str) -> ET.Element:
    """The root element of ``p``, within the limits and with no declarations."""
    return parse_bounded(p, name, MAX_DEPTH, MAX_ELEMENTS, declarations=False)


def _value(void: ET.Element, where: str) -> str:
    """The text of the one value element (``<int>``, ``<double>``, ``<string>``) of a
    ``<void property=...>``."""
    kids = list(void)
    if len(kids) != 1:
        raise PatternError(f"{where}: expected one value, found {len(kids)} elements")
    return kids[0].text or ""


def _line(obj: ET.Element, k: int, name: str) -> tuple[float, float, float, float, int]:
    """``(x0, y0, x1, y1, type)`` of one ``oripa.OriLineProxy`` (0 where left out)."""
    where = f"{name}: line {k}"
    got: dict[str, float] = {}
    for void in obj.findall("void"):
        prop = void.get("property")
        if prop not in _FIELDS:
            continue
        text = _value(void, f"{where}, {prop}")
        try:
            got[prop] = int(text) if prop == "type" else float(text)
        except ValueError:
            shown = printable(text, 40)
            raise PatternError(f"{where}: {prop} {shown!r} is not a number") from None
        if prop != "type" and not abs(got[prop]) <= MAX_COORDINATE:
            raise PatternError(
                f"{where}: {prop} = {got[prop]:g} is not finite or farther than "
                f"{MAX_COORDINATE:g} from the origin"
            )
    kind = int(got.get("type", 0))
    if kind not in ORIPA_TYPES:
        raise PatternError(
            f"{where}: type {kind} is not an ORIPA line type ({', '.join(map(str, ORIPA_TYPES))})"
        )
    return got.get("x0", 0.0), got.get("y0", 0.0), got.get("x1", 0.0), got.get("y1", 0.0), kind


def _dataset(root: ET.Element, name: str) -> ET.Element:
    """The ``oripa.DataSet`` object of the document."""
    if root.tag != "java":
        raise PatternError(
            f"{name}: the root element is <{printable(root.tag, 40)}>, not <java> "
            "(an ORIPA .opx file is Java XMLEncoder output)"
        )
    found = [o for o in root.findall("object") if o.get("class") == "oripa.DataSet"]
    if not found:
        raise PatternError(f'{name}: no <object class="oripa.DataSet"> (not an ORIPA file)')
    return found[0]


def _texts(data: ET.Element) -> dict[str, str]:
    """The DataSet's text fields (title, ...) as ``XMLEncoder`` writes public fields:
    ``<void method="getField"><string>NAME</string><void method="set"><object
    idref=.../><string>VALUE</string></void></void>`` (or as a ``property``)."""
    texts = {}
    for void in data.iter("void"):
        if void.get("method") == "getField":
            kids, setter = list(void), void.find("void[@method='set']")
            key = kids[0].text if kids and kids[0].tag == "string" else None
            values = [] if setter is None else setter.findall("string")
            text = values[-1].text if values else None
        else:
            key = void.get("property")
            text = void[0].text if len(void) == 1 and void[0].tag == "string" else None
        if key in _TEXTS and text:
            texts[key] = printable(text, 300)
    return texts


def oripa_pattern(
    segments: list,
    letters: list[str],
    name: str,
    metadata: dict,
    scale: float = 1.0,
    tolerance: Tolerance = None,
) -> CreasePattern:
    """The pattern of ORIPA's lines (``.opx`` and ``.cp``): ``segments`` ``(x0, y0, x1, y1)``
    in ORIPA units (y down the screen), ``letters`` their assignments; scaled by ``scale``
    mm per unit, y turned up, outline cuts read as border. A PatternError names ``name``."""
    coords = np.array(segments, dtype=float).reshape(-1, 2) * scale
    coords[:, 1] = 0.0 - coords[:, 1]  # ORIPA's y points down the screen (no -0.0)
    try:
        return CreasePattern(
            coords,
            np.arange(len(coords)).reshape(-1, 2),
            letters,
            metadata=metadata,
            tolerance=import_tolerance(tolerance),
        ).with_outline_cuts_as_border()
    except PatternError as exc:
        raise PatternError(f"{name}: {exc}") from None


def refuse_joins(cp: CreasePattern, path: str | os.PathLike[str], fmt: str) -> None:
    """A PatternError naming the first ``J`` (join) edge, which ORIPA's formats have no
    line type for."""
    joins = np.flatnonzero(cp.assignments == "J")
    if joins.size:
        raise PatternError(
            f"{printable(str(path), 300)}: edge {int(joins[0])} is a join (J) edge, which "
            f"{fmt} has no line type for; write .fold to keep it"
        )


def read_opx(
    path: str | os.PathLike[str],
    mm_per_unit: float | None = None,
    tolerance: Tolerance = None,
) -> CreasePattern:
    """Read an ORIPA ``.opx`` crease pattern (see the module notes), in mm.

    Parameters
    ----------
    path : path-like
        The ``.opx`` file.
    mm_per_unit : float, optional
        Millimetres per ORIPA unit (default 1).
    tolerance : float, optional
        Lines whose ends lie this close (mm) meet there (default
        :func:`~origami_cad.pattern.planar.import_tolerance`).

    Raises
    ------
    PatternError
        Naming the file, and the line, for malformed XML, a document type
        declaration, a line type ORIPA does not have, a coordinate that is not a
        finite number, or a file with no crease lines.
    """
    p, name = input_file(path, PatternError)
    data = _dataset(_parse(p, name), name)
    proxies = [o for o in data.iter("object") if o.get("class") == "oripa.OriLineProxy"]
    if len(proxies) > MAX_EDGES:
        raise PatternError(f"{name}: {len(proxies):,} lines, more than the limit of {MAX_EDGES:,}")
    lines = [_line(o, k, name) for k, o in enumerate(proxies)]
    scale = 1.0 if mm_per_unit is None else float(mm_per_unit)
    kept = [ln for ln in lines if ORIPA_TYPES[ln[4]] is not None and ln[:2] != ln[2:4]]
    if not kept:
        raise PatternError(f"{name}: no crease lines found (no ORIPA line of types 0 to 4)")
    letters = [ORIPA_TYPES[ln[4]] for ln in kept]
    texts = _texts(data)
    unit = "1 mm per ORIPA unit (the file has no unit)"
    if mm_per_unit is not None:
        unit = f"{scale:g} mm per ORIPA unit (given)"
    metadata = {"title": texts.get("title") or p.stem, "source_unit": unit}
    if texts.get("originalAuthorName") or texts.get("editorName"):
        metadata["creator"] = texts.get("originalAuthorName") or texts["editorName"]
    cp = oripa_pattern([ln[:4] for ln in kept], letters, name, metadata, scale, tolerance)
    notes = []
    left = sum(1 for ln in lines if ORIPA_TYPES[ln[4]] is None)
    if left:
        notes.append(
            Problem(
                "cut-model",
                f"{name}: {left} cut-model lines (type 9) left out: not part of the crease pattern",
                severity=Severity.INFO,
            )
        )
    out = cp.with_metadata()
    out.notes = (*cp.notes, *notes)
    return out


def _double(v: float) -> str:
    return f"<double>{float(v)!r}</double>"


def write_opx(cp: CreasePattern, path: str | os.PathLike[str]) -> Path:
    """Write ``cp`` as an ORIPA ``.opx`` file (mm as ORIPA units), atomically.

    ``B`` and ``C`` edges become cut lines, ``F`` auxiliary lines, ``M``, ``V`` and ``U``
    ORIPA's own; y is turned over to ORIPA's (down the screen). A ``J`` (join) edge,
    which ORIPA has no type for, is a PatternError naming it.
    """
    refuse_joins(cp, path, "ORIPA")
    x0, _, x1, _ = cp.bounds
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        '<java version="1.8.0" class="java.beans.XMLDecoder">',
        ' <object class="oripa.DataSet" id="DataSet0">',
        '  <void property="lines">',
        f'   <array class="oripa.OriLineProxy" length="{cp.n_edges}">',
    ]
    for k, ((a, b), letter) in enumerate(zip(cp.edges, cp.assignments, strict=True)):
        pa, pb = cp.vertices[a], cp.vertices[b]
        values = {
            "type": f"<int>{_WRITE_TYPES[str(letter)]}</int>",
            "x0": _double(pa[0]),
            "x1": _double(pb[0]),
            "y0": _double(0.0 - pa[1]),
            "y1": _double(0.0 - pb[1]),
        }
        out.append(f'    <void index="{k}">')
        out.append('     <object class="oripa.OriLineProxy">')
        for prop, value in values.items():
            out.append(f'      <void property="{prop}">{value}</void>')
        out.append("     </object>")
        out.append("    </void>")
    out += ["   </array>", "  </void>"]
    out.append('  <void property="mainVersion"><int>2</int></void>')
    out.append(f'  <void property="paperSize">{_double(max(x1 - x0, 1e-9))}</void>')
    out.append('  <void property="subVersion"><int>1</int></void>')
    if cp.title:
        out += [
            '  <void class="oripa.DataSet" method="getField">',
            "   <string>title</string>",
            '   <void method="set"><object idref="DataSet0"/>'
            f"<string>{xml_text(cp.title)}</string></void>",
            "  </void>",
        ]
    out += [" </object>", "</java>"]
    with atomic_write(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(out) + "\n")
    return Path(path)


# the registry entries of this format, merged by :mod:`origami_cad.pattern.formats`:
# a reader is ``read(path, mm_per_unit, tolerance) -> CreasePattern``, a writer
# ``write(cp, path) -> Path``
readers = {".opx": read_opx}
writers = {".opx": write_opx}
