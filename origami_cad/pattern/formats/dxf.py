"""DXF reader and writer (ezdxf).

Writing (:func:`write_dxf`): one LINE per edge on the layers

==============  =========  =========  ==========  ===========
layer           layer ACI  line ACI   linetype    assignment
==============  =========  =========  ==========  ===========
``Mountain``    1          1          CONTINUOUS  M (red)
``Valley``      5          5          DASHED      V (blue)
``Cut``         3          3          CONTINUOUS  C (green)
``Border``      7          3          CONTINUOUS  B (black/white layer, green lines)
``Flat``        8          8          CONTINUOUS  F (grey)
``Unassigned``  9          9          CONTINUOUS  U (light grey)
``Join``        9          9          CONTINUOUS  J
==============  =========  =========  ==========  ===========

Every line carries its own ACI colour (group 62), not BYLAYER: ORIPA's DXF
loader reads only an entity's own colour (1 mountain, 5 valley, 3 cut, anything
else auxiliary) and never its layer, and, like ORIPA's writer, the sheet outline
is drawn in the cut colour (ORIPA's boundary is a cut line). Readers that go by
layer name (ours, most CAD programs) still see ``Border``.
Holes are CIRCLEs on layer ``Holes`` (ACI 4); ``$INSUNITS`` = 4 (mm),
``$MEASUREMENT`` = 1 (metric), the title in ``$PROJECTNAME``.

Reading (:func:`read_dxf`): LINE, LWPOLYLINE and POLYLINE (every segment is an
edge, closed flags honoured, z ignored), in model space and inside block
references (INSERT and MINSERT, nested, with the block transforms; entities on
layer ``0`` inside a block take the layer of the reference, BYBLOCK colours and
linetypes its colour and linetype). ARC, CIRCLE, ELLIPSE, SPLINE and bulged
polyline segments are flattened (chords within 0.01 mm of the curve, or within
1e-6 of the drawing's size if that is larger, so no curve becomes more than a few
thousand chords) for border and cut lines only:
a curved crease cannot fold rigidly, so a curved mountain, valley, flat or
unassigned line is an error naming its handle. A CIRCLE on a layer whose name
contains ``hole`` (``Holes``, ``Hole``) is a :class:`~origami_cad.pattern.Hole`.

Each line is classified, in this order, the first rule that says something
deciding:

1. layer name (any case, substring): ``mountain`` M; ``valley`` V; ``cut``
   (``Cut``, ``Cutting``, ORIPA's ``CutLine``) C; ``border``, ``boundary``,
   ``outline``, ``edge`` B; ``flat``, ``aux`` F; ``unassigned`` U; ``join`` J;
2. colour: the entity's own (true colour if set, else ACI) when it has one,
   otherwise (BYLAYER, or BYBLOCK outside a block) its layer's. ACI 1 or 10-39
   M, 5 or 140-199 V, 3 or 60-129 C, 7, 8, 9 or 250-255 (black, white, greys)
   B; a true colour by its dominant channel (red M, blue V, green C; grey,
   black, white B). An entity's own colour that means nothing (e.g. ACI 2
   yellow) is not overridden by its layer's colour;
3. linetype (the entity's, else its layer's): a dashed one (name containing
   ``DASH`` or ``HIDDEN``, e.g. ``DASHED``, ``DASHEDX2``) is V.

A line that none of the rules classifies is not guessed: the file is rejected
with a message naming the lines (handle, layer, colour). ORIPA draws the sheet's
outline as cut lines, so cut edges on the outer boundary of the sheet (the
exterior of the union of the faces) become border; cut lines inside stay cuts.
``$INSUNITS`` is honoured (inches, feet, cm, m, ... are converted to mm;
unitless files are taken as mm). The title is the file name's stem.

Limits, each a :class:`~origami_cad.errors.PatternError` naming the entity: the
drawing may expand to at most :data:`MAX_ENTITIES` entities through its block
references and MINSERT grids (counted from the block definitions before any is
expanded), give at most :data:`MAX_SEGMENTS` line segments, and lie within
:data:`~origami_cad.pattern.model.MAX_COORDINATE` mm of the origin.

Examples
--------
>>> import tempfile, pathlib
>>> from origami_cad.pattern import miura_pattern
>>> cp = miura_pattern(2, 2, 20.0, 30.0, 60.0)
>>> with tempfile.TemporaryDirectory() as tmp:
...     back = read_dxf(write_dxf(cp, pathlib.Path(tmp) / "miura.dxf"))
>>> back.same_graph(cp), back.title
(True, 'miura')
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import os
from collections import Counter
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad._toml import input_file
from origami_cad.errors import PatternError
from origami_cad.pattern.formats.dxf_write import write_dxf
from origami_cad.pattern.model import (
    MAX_COORDINATE,
    MAX_EDGES,
    CreasePattern,
    Hole,
    Problem,
    Severity,
    printable,
)
from origami_cad.pattern.planar import Tolerance, import_tolerance

__all__ = ["MAX_ENTITIES", "MAX_SEGMENTS", "read_dxf", "write_dxf"]

#: layer-name words (lower case, substrings) and the assignment they mean, in order
_LAYER_WORDS = (
    (("mountain",), "M"),
    (("valley",), "V"),
    (("cut",), "C"),
    (("border", "boundary", "outline", "edge"), "B"),
    (("flat", "aux"), "F"),
    (("unassigned",), "U"),
    (("join",), "J"),
)
_NAMES = {"M": "mountain", "V": "valley", "C": "cut", "B": "border", "F": "flat"}
_NAMES.update(U="unassigned", J="join")

#: $INSUNITS codes ezdxf cannot convert: millimetres per unit
_MM_PER_UNIT = {
    0: 1.0,  # unitless: taken as mm
    8: 25.4e-6,  # microinches
    9: 25.4e-3,  # mils
    21: 1200 / 3937 * 1000,  # US survey feet
    22: 1000 / 39.37,  # US survey inches
    23: 3600 / 3937 * 1000,  # US survey yards
    24: 6336000 / 3937,  # US survey miles
}
_LINEAR = ("LINE", "LWPOLYLINE", "POLYLINE")
_CURVED = ("ARC", "CIRCLE", "ELLIPSE", "SPLINE")
#: chord tolerance of flattened curves, mm (at least; see _FLATTEN_RELATIVE)
_FLATTEN_MM = 0.01
#: chord tolerance relative to the drawing's size: a curve never becomes more than a
#: few thousand chords, however large the drawing (the pattern merges vertices closer
#: than 5e-4 of its size anyway: IMPORT_RELATIVE_TOLERANCE)
_FLATTEN_RELATIVE = 1e-6
#: block nesting deeper than this is taken as a cycle
_MAX_DEPTH = 32
#: most entities a drawing may expand to, block references and MINSERT arrays counted
#: (each takes about 50 us to read: 100,000 take a few seconds)
MAX_ENTITIES = 100_000
#: most line segments read, curves flattened: a pattern's limit of edges
MAX_SEGMENTS = MAX_EDGES


# ------------------------------------------------------------- classification
Colour = tuple[str, Any]  # ("aci", int) or ("rgb", (r, g, b))


def _by_layer_name(name: str) -> str | None:
    low = name.lower()
    for words, letter in _LAYER_WORDS:
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
    first, second = sorted(rgb)[-1:-3:-1]
    if first - second < 32:
        return None  # no dominant channel (yellow, magenta, cyan, ...)
    return "MCV"[int(np.argmax(rgb))]


def _by_colour(colour: Colour) -> str | None:
    kind, value = colour
    return _by_rgb(value) if kind == "rgb" else _by_aci(value)


def _colour_text(colour: Colour | None) -> str:
    if colour is None:
        return "none"
    kind, value = colour
    return "#{:02x}{:02x}{:02x}".format(*value) if kind == "rgb" else str(value)


@dataclass(frozen=True)
class _Block:
    """What entities inside a block reference inherit from it."""

    matrix: Any  # ezdxf Matrix44: block coordinates -> WCS
    layer: str  # for entities on layer "0"
    colour: Colour | None  # for BYBLOCK colours
    linetype: str | None  # for BYBLOCK linetypes
    where: str  # " in block 'NAME' (INSERT 2F)"
    depth: int


@dataclass(frozen=True)
class _Item:
    """An entity with its effective layer, colour and linetype."""

    entity: Any
    block: _Block | None
    layer: str
    own_colour: Colour | None  # the entity's own colour; None: BYLAYER
    layer_colour: Colour
    linetype: str

    @property
    def colour(self) -> Colour:
        return self.own_colour if self.own_colour is not None else self.layer_colour

    def classify(self) -> str | None:
        letter = _by_layer_name(self.layer)
        if letter is None:
            letter = _by_colour(self.colour)
        if letter is None and ("DASH" in self.linetype or "HIDDEN" in self.linetype):
            letter = "V"
        return letter

    def describe(self) -> str:
        where = self.block.where if self.block is not None else ""
        by = "" if self.own_colour is not None else " (by layer)"
        return (
            f"handle {printable(self.entity.dxf.get('handle', '?'))}{where} "
            f"({self.entity.dxftype()}) on layer {printable(self.layer)!r}, "
            f"colour {_colour_text(self.colour)}{by}"
        )


def _layer_props(doc: Any, name: str) -> tuple[Colour, str]:
    """Colour and linetype (upper case) of a layer; white, CONTINUOUS if undefined."""
    layer = doc.layers.get(name) if doc.layers.has_entry(name) else None
    if layer is None:
        return ("aci", 7), "CONTINUOUS"
    rgb = layer.rgb if layer.dxf.hasattr("true_color") else None
    colour: Colour = ("rgb", tuple(rgb)) if rgb is not None else ("aci", abs(layer.dxf.color))
    return colour, str(layer.dxf.get("linetype", "CONTINUOUS")).upper()


def _item(entity: Any, doc: Any, block: _Block | None) -> _Item:
    dxf = entity.dxf
    layer = str(dxf.get("layer", "0"))
    if layer == "0" and block is not None:
        layer = block.layer
    layer_colour, layer_linetype = _layer_props(doc, layer)
    own: Colour | None
    rgb = entity.rgb if dxf.hasattr("true_color") else None
    if rgb is not None:
        own = ("rgb", tuple(rgb))
    else:
        aci = int(dxf.get("color", 256))
        if aci == 0:  # BYBLOCK
            own = block.colour if block is not None else None
        elif aci == 256:  # BYLAYER
            own = None
        else:
            own = ("aci", abs(aci))
    linetype = str(dxf.get("linetype", "BYLAYER")).upper()
    if linetype == "BYBLOCK":
        linetype = (block.linetype if block is not None else None) or "BYLAYER"
    if linetype == "BYLAYER":
        linetype = layer_linetype
    return _Item(entity, block, layer, own, layer_colour, linetype)


def _grid_matrices(entity: Any) -> Iterator[Any]:
    """Matrices (block -> WCS) of an INSERT, one per cell of a MINSERT grid.

    Only the distinct cells (``Insert.mcount``) are visited: a zero spacing
    repeats nothing, whatever the row or column count says.
    """
    from ezdxf.math import Matrix44, Vec3

    base = entity.matrix44()
    if entity.mcount <= 1:
        yield base
        return
    dxf = entity.dxf
    rows = dxf.row_count if dxf.row_spacing else 1
    cols = dxf.column_count if dxf.column_spacing else 1
    ocs = entity.ocs()
    for row in range(rows):
        for col in range(cols):
            offset = Vec3(col * dxf.column_spacing, row * dxf.row_spacing)
            if dxf.rotation:
                offset = offset.rotate_deg(dxf.rotation)
            yield Matrix44.chain(base, Matrix44.translate(*ocs.to_wcs(offset)))


def _insert_text(entity: Any, name: str) -> str:
    kind = "MINSERT" if entity.mcount > 1 or entity.dxf.hasattr("row_count") else "INSERT"
    handle = printable(entity.dxf.get("handle", "?"))
    return f"handle {handle} ({kind} of block {printable(name)!r})"


def _nested_too_deep(entity: Any) -> PatternError:
    return PatternError(
        f"block references nested deeper than {_MAX_DEPTH} levels (a block "
        f"that contains itself?) at handle {printable(entity.dxf.get('handle', '?'))}"
    )


def _expanded_count(
    space: Iterable[Any], memo: dict[str, int], inside: tuple[str, ...] = ()
) -> int:
    """How many entities a layout expands to, block references and MINSERT grids counted.

    Computed from the block definitions alone (each once), so a small file that
    would expand to millions of entities is refused before any is made.
    """
    total = 0
    for entity in space:
        if entity.dxftype() != "INSERT":
            total += 1
            continue
        name = str(entity.dxf.get("name", "?"))
        _check_numbers(entity, lambda e=entity, n=name: _insert_text(e, n))
        layout = entity.block()
        if layout is None:
            continue  # reported by _walk
        if name in inside or len(inside) >= _MAX_DEPTH:
            raise _nested_too_deep(entity)
        if name not in memo:
            memo[name] = _expanded_count(layout, memo, (*inside, name))
        # every reference (each cell of a MINSERT grid) costs work, even of an empty block
        made = max(entity.mcount, 1) * (1 + memo[name])
        total += made
        if total > MAX_ENTITIES:
            grid = f" (a {entity.mcount:,}-cell MINSERT)" if entity.mcount > 1 else ""
            raise PatternError(
                f"the drawing expands to more than {MAX_ENTITIES:,} entities through its "
                f"block references; at handle {printable(entity.dxf.get('handle', '?'))}, "
                f"block {printable(name)!r}{grid} makes {made:,}"
            )
    return total


def _walk(space: Iterable[Any], doc: Any, block: _Block | None = None) -> Iterator[_Item]:
    """Every entity of a layout, entering block references (nested)."""
    from ezdxf.math import Matrix44

    for entity in space:
        if entity.dxftype() != "INSERT":
            yield _item(entity, doc, block)
            continue
        depth = 0 if block is None else block.depth + 1
        if depth > _MAX_DEPTH:
            raise _nested_too_deep(entity)
        ref = _item(entity, doc, block)
        layout = entity.block()
        name = printable(entity.dxf.get("name", "?"))
        handle = printable(entity.dxf.get("handle", "?"))
        if layout is None:
            raise PatternError(
                f"INSERT {handle} refers to block {name!r}, which the file does not define"
            )
        for m in _grid_matrices(entity):
            if block is not None:
                m = Matrix44.chain(m, block.matrix)
            inner = _Block(
                matrix=m,
                layer=ref.layer,
                colour=ref.colour,
                linetype=ref.linetype,
                where=f" in block {name!r} (INSERT {handle})"
                + (block.where if block is not None else ""),
                depth=depth,
            )
            yield from _walk(layout, doc, inner)


# ------------------------------------------------------------------ geometry
#: attributes that must be > 0 (a zero or negative one draws nothing, or a mirror
#: image no CAD program draws)
_POSITIVE = {"CIRCLE": ("radius",), "ARC": ("radius",), "ELLIPSE": ("ratio",)}


def _check_numbers(entity: Any, describe: Any) -> None:
    """PatternError naming the entity (``describe()``) and its attribute when one of its
    numbers is not finite (NaN, inf), a radius or ellipse ratio is not > 0, an INSERT's
    scale is 0 or a MINSERT's row or column count is below 1. Nothing is repaired."""
    kind = entity.dxftype()
    for key, value in entity.dxf.all_existing_dxf_attribs().items():
        numbers = value if isinstance(value, tuple | list) else (value,)
        if any(isinstance(v, float) and not math.isfinite(v) for v in numbers):
            raise PatternError(f"{describe()}: {key} = {printable(str(value), 60)} is not finite")
    for key in _POSITIVE.get(kind, ()):
        if not float(entity.dxf.get(key, 1.0)) > 0:
            raise PatternError(
                f"{describe()}: {key} = {float(entity.dxf.get(key)):g} must be > 0 (a "
                f"{kind} with it draws nothing)"
            )
    if kind == "INSERT":
        dxf = entity.dxf
        for key in ("xscale", "yscale", "zscale"):
            if float(dxf.get(key, 1.0)) == 0:
                raise PatternError(
                    f"{describe()}: {key} = 0 flattens the block (CAD programs refuse a zero scale)"
                )
        for key in ("row_count", "column_count"):
            if int(dxf.get(key, 1)) < 1:
                raise PatternError(
                    f"{describe()}: {key} = {int(dxf.get(key))} must be >= 1 (a MINSERT grid of "
                    "no cells)"
                )


def _is_curved(e: Any) -> bool:
    """Whether an entity has curved parts (arcs, splines, bulged polyline segments)."""
    kind = e.dxftype()
    if kind == "LWPOLYLINE":
        return any(abs(b) > 0 for (b,) in e.get_points("b"))
    if kind == "POLYLINE":
        return e.is_2d_polyline and any(abs(v.dxf.get("bulge", 0)) > 0 for v in e.vertices)
    return kind in _CURVED


def _flat_pieces(e: Any, flatten: float) -> Iterator[list[Any]]:
    """Vertex chains (Vec3, block or WCS coordinates) of an entity, curves flattened."""
    kind = e.dxftype()
    if kind == "LINE":
        yield [e.dxf.start, e.dxf.end]
    elif kind in ("LWPOLYLINE", "POLYLINE"):
        for piece in e.virtual_entities():  # LINE and ARC entities, in WCS
            yield from _flat_pieces(piece, flatten)
    else:  # ARC, CIRCLE, ELLIPSE, SPLINE: points on the curve itself, chords within flatten
        yield list(e.flattening(flatten))


def _points(item: _Item, flatten: float) -> list[list[tuple[float, float]]]:
    """Vertex chains of an entity in WCS drawing units (z dropped, once checked finite;
    curves flattened).

    ``flatten`` is the largest distance (drawing units) between a curve and its chords.
    """
    m = item.block.matrix if item.block is not None else None
    if m is not None and item.entity.dxftype() != "LINE":
        # flatten in block coordinates, finer by the block's largest stretch (the 2x2
        # matrix's largest singular value, in closed form: this runs per entity)
        ux, uy = m.transform_direction((1, 0, 0)), m.transform_direction((0, 1, 0))
        a, b, c, d = ux.x, ux.y, uy.x, uy.y
        total = a * a + b * b + c * c + d * d
        det = a * d - b * c
        stretch = math.sqrt(
            max(0.5 * (total + math.sqrt(max(total * total - 4 * det * det, 0))), 0)
        )
        flatten /= max(stretch, 1e-300) if math.isfinite(stretch) else math.inf
    try:
        chains = list(_flat_pieces(item.entity, flatten))
    except Exception as exc:  # ezdxf's geometry code raises anything on degenerate input
        raise PatternError(f"{item.describe()}: cannot read its geometry ({_why(exc)})") from None
    if m is not None:
        chains = [list(m.transform_vertices(chain)) for chain in chains]
    if not all(math.isfinite(v.z) for chain in chains for v in chain):  # z is dropped: check
        raise PatternError(f"{item.describe()}: a vertex's z is not finite (NaN or infinite)")
    return [[(float(v.x), float(v.y)) for v in chain] for chain in chains]


def _why(exc: BaseException) -> str:
    if isinstance(exc, RecursionError):
        return "a degenerate curve"
    return printable(str(exc) or type(exc).__name__, 120)


def _box(item: _Item) -> np.ndarray:
    """Corners (WCS drawing units, x and y) of a curved entity's bounding box."""
    from ezdxf import bbox

    try:
        ext = bbox.extents([item.entity], fast=True)
    except Exception as exc:  # ezdxf's geometry code raises anything on degenerate input
        raise PatternError(f"{item.describe()}: cannot read its geometry ({_why(exc)})") from None
    if not ext.has_data:
        return np.zeros((1, 2))
    (x0, y0, z0), (x1, y1, z1) = ext.extmin, ext.extmax
    corners = [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]
    if item.block is not None:
        corners = list(item.block.matrix.transform_vertices(corners))
    return np.array([(float(v[0]), float(v[1])) for v in corners])


def _hole(item: _Item, scale: float) -> Hole:
    e = item.entity
    ocs = e.ocs()
    centre = ocs.to_wcs(e.dxf.center)
    r = float(e.dxf.radius)
    ux, uy = ocs.ux * r, ocs.uy * r
    if item.block is not None:
        m = item.block.matrix
        centre = m.transform(centre)
        ux, uy = m.transform_direction(ux), m.transform_direction(uy)
    rx, ry = ux.vec2.magnitude, uy.vec2.magnitude
    if abs(rx - ry) > 1e-9 * max(rx, ry):
        raise PatternError(
            f"{item.describe()}: the hole is distorted into an ellipse "
            "(non-uniform scaling or tilt); holes must be circles"
        )
    try:
        return Hole(float(centre.x) * scale, float(centre.y) * scale, 2 * rx * scale)
    except PatternError as exc:
        raise PatternError(f"{item.describe()}: {exc}") from None


def _mm_per_unit(doc: Any) -> float:
    from ezdxf import units

    code = int(doc.header.get("$INSUNITS", 0))
    if code in _MM_PER_UNIT:
        return _MM_PER_UNIT[code]
    try:
        return float(units.conversion_factor(code, 4))
    except (TypeError, ValueError, IndexError):
        raise PatternError(f"$INSUNITS = {code} is not a known unit code") from None


# ------------------------------------------------------------------- reading
def read_dxf(
    path: str | os.PathLike[str], mm_per_unit: float | None = None, tolerance: Tolerance = None
) -> CreasePattern:
    """Read a crease pattern from a DXF file, converted to millimetres.

    Parameters
    ----------
    path : path-like
        A ``.dxf`` file (any DXF version ezdxf reads; ASCII or binary).
    mm_per_unit : float, optional
        Millimetres per drawing unit, replacing what ``$INSUNITS`` declares
        (default: the declared unit; mm when the file declares none).
    tolerance : float, optional
        Lines whose ends lie this close (mm) meet there (default
        :func:`~origami_cad.pattern.planar.import_tolerance`).

    Returns
    -------
    CreasePattern
        Vertices in mm, edges classified as described in the module
        documentation, holes from circles on a ``Holes`` layer, and
        ``metadata["title"]`` the file name's stem, ``metadata["source_unit"]``
        the unit it was read in. Fold angles are the defaults (+-180 degrees
        for mountains and valleys, 0 otherwise). A file in ORIPA's layers that
        declares no unit gets a ``size`` warning note: ORIPA writes every
        pattern 6 inches wide, whatever its paper size.

    Raises
    ------
    PatternError
        If the file is missing or not a readable DXF, if a line cannot be
        classified as mountain, valley, cut or border, if a crease is curved,
        or if there are no crease lines; the message starts with the path and
        names the entities concerned.
    """
    p, name = input_file(path, PatternError)
    try:
        cp = _read(p, mm_per_unit, tolerance)
    except PatternError as exc:
        raise PatternError(f"{name}: {exc}") from None
    cp.notes = tuple(
        dataclasses.replace(n, message=f"{name}: {n.message}")
        if n.code in ("size", "zero-length")
        else n
        for n in cp.notes
    )
    return cp


def _open_dxf(p: Path):
    """The ezdxf document of ``p``; a PatternError when it cannot be read."""
    import ezdxf

    try:
        return ezdxf.readfile(str(p))
    except Exception as exc:  # ezdxf raises OSError, DXFStructureError, StopIteration, ...
        problem = printable(str(exc) or type(exc).__name__, 200)
        if isinstance(exc, OSError) and str(p) in problem:
            problem = "not a DXF file"
        raise PatternError(f"not a readable DXF file ({problem})") from None


def _classify_entities(doc, scale: float):
    """Pass 1: classify every entity of the model space.

    Straight entities give their chains (drawing units) now, curved ones their
    ``_Item`` (flattened later, as the chord tolerance depends on the drawing's
    size). ``scale`` is millimetres per drawing unit.

    Returns ``(chains, (x0, y0, x1, y1), holes, unknown, skipped)``: the
    ``(letter, chains or item, item)`` list, the bounding box in drawing units, the
    holes (mm), descriptions of unclassifiable entities and counts of skipped
    entity types. Raises PatternError for a curved crease or an entity too far
    from the origin.
    """
    limit = MAX_COORDINATE / scale  # drawing units
    chains: list[tuple[str, list[list[tuple[float, float]]] | _Item, _Item]] = []
    x0 = y0 = math.inf
    x1 = y1 = -math.inf
    holes: list[Hole] = []
    unknown: list[str] = []
    skipped: Counter[str] = Counter()
    for item in _walk(doc.modelspace(), doc):
        e = item.entity
        kind = e.dxftype()
        if kind not in _LINEAR + _CURVED:
            skipped[kind] += 1
            continue
        if kind == "POLYLINE" and not (e.is_2d_polyline or e.is_3d_polyline):
            skipped["POLYLINE (mesh)"] += 1
            continue
        _check_numbers(e, item.describe)
        if kind == "CIRCLE" and "hole" in item.layer.lower():
            holes.append(_hole(item, scale))
            continue
        letter = item.classify()
        if letter is None:
            unknown.append(item.describe())
            continue
        curved = _is_curved(e)
        if letter not in ("B", "C") and curved:
            raise PatternError(
                f"{item.describe()} is a curved {_NAMES[letter]} line; only border and "
                "cut lines may be curved (a curved crease cannot be folded rigidly)"
            )
        if curved:
            box = [tuple(map(float, q)) for q in _box(item)]
            chains.append((letter, item, item))
        else:
            pts = _points(item, _FLATTEN_MM / scale)
            box = [q for chain in pts for q in chain] or [(0.0, 0.0)]
            chains.append((letter, pts, item))
        # plain Python: this runs per entity (abs(nan) <= limit is False too)
        if not all(abs(v) <= limit for q in box for v in q):
            raise PatternError(
                f"{item.describe()} lies farther than {MAX_COORDINATE:g} mm from the origin "
                "(or is not finite); coordinates are limited to that magnitude"
            )
        xs, ys = [q[0] for q in box], [q[1] for q in box]
        x0, x1, y0, y1 = min(x0, *xs), max(x1, *xs), min(y0, *ys), max(y1, *ys)
    return chains, (x0, y0, x1, y1), holes, unknown, skipped


def _flatten_chains(chains, flatten: float):
    """Pass 2: ``(segments, letters, dropped)`` of the chains, curves flattened in
    entity order.

    ``flatten`` is the chord tolerance in drawing units. Zero-length segments
    are left out and their entities listed in ``dropped`` (description -> True
    when the entity drew nothing else); PatternError past MAX_SEGMENTS.
    """
    segments: list[tuple[float, float, float, float]] = []
    letters: list[str] = []
    dropped: dict[str, bool] = {}
    for letter, got, item in chains:
        pts = _points(got, flatten) if isinstance(got, _Item) else got
        drawn = zero = 0
        for chain in pts:
            for a, b in itertools.pairwise(chain):
                if a != b:
                    segments.append((*a, *b))
                    letters.append(letter)
                    drawn += 1
                else:
                    zero += 1
        if zero or not drawn:
            dropped[item.describe()] = not drawn
        if len(segments) > MAX_SEGMENTS:
            raise PatternError(
                f"more than {MAX_SEGMENTS:,} line segments (curves flattened); the drawing "
                "is too large to read as a crease pattern"
            )
    return segments, letters, dropped


def _dropped_notes(dropped: dict[str, bool]) -> list[Problem]:
    """Notes naming the entities whose zero-length segments were left out: a warning for
    those that drew nothing else (a zero-length mountain line), info for the rest."""
    notes = []
    for empty, severity, what in (
        (True, Severity.WARNING, "drawing nothing but zero-length lines, left out"),
        (False, Severity.INFO, "with zero-length segments, which were left out"),
    ):
        named = [d for d, e in dropped.items() if e is empty]
        if named:
            count = f"{len(named)} {'entity' if len(named) == 1 else 'entities'}"
            more = f"; and {len(named) - 3} more" if len(named) > 3 else ""
            text = f"{count} {what}: {'; '.join(named[:3])}{more}"
            notes.append(Problem("zero-length", text, severity=severity))
    return notes


def _check_found(unknown: list[str], skipped: Counter[str], holes: list[Hole], segments) -> None:
    """PatternError when some lines are unclassifiable or no crease line was found."""
    if unknown:
        shown = "; ".join(unknown[:3])
        if len(unknown) > 3:
            shown += f"; and {len(unknown) - 3} more"
        raise PatternError(
            f"{len(unknown)} lines cannot be classified as mountain/valley/cut/border by "
            f"layer name, colour or linetype ({shown}); put them on a layer named "
            "Mountain, Valley, Cut or Border, or colour them red, blue, green or black"
        )
    if not segments:
        found = ", ".join(f"{n} {k}" for k, n in skipped.most_common()) or "nothing"
        raise PatternError(
            f"no crease lines found (found {found}{' and holes' if holes else ''}; crease "
            "lines are LINE, LWPOLYLINE, POLYLINE, ARC, CIRCLE, ELLIPSE or SPLINE entities)"
        )


def _merge_ends(segments, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """``(coords, edges)``: shared end points of ``segments`` as one vertex.

    Vertices come in order of first appearance, in millimetres (``scale`` is mm
    per drawing unit), so the pattern's notes report only real repairs
    (near-coincident vertices, crossings, ...).
    """
    ends = np.asarray(segments, dtype=float).reshape(-1, 2)
    uniq, first, inverse = np.unique(ends, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return uniq[order] * scale, rank[inverse.reshape(-1)].reshape(-1, 2)


#: the layers ORIPA's DXF writer puts its lines on
_ORIPA_LAYERS = frozenset({"CutLine", "MountainLine", "ValleyLine"})


def _unit_notes(doc: Any, given: float | None) -> tuple[str, list[Problem]]:
    """What unit the drawing was read in (for messages) and a note on ORIPA's size."""
    declared = "$INSUNITS" in doc.header
    code = int(doc.header.get("$INSUNITS", 0))
    if given is not None:
        return f"{given:g} mm per drawing unit (given)", []
    if not declared or code == 0:
        text = "mm (the file declares no unit)"
    else:
        text = f"{_mm_per_unit(doc):g} mm per drawing unit ($INSUNITS = {code})"
    if declared or not any(e.dxf.get("layer") in _ORIPA_LAYERS for e in doc.modelspace()):
        return text, []
    note = Problem(
        "size",
        "the file is in ORIPA's layers and declares no unit: ORIPA writes every pattern "
        "6 inches wide whatever its paper size, so give the size you mean (--width MM)",
        severity=Severity.WARNING,
    )
    return text, [note]


def _read(p: Path, mm_per_unit: float | None = None, tolerance: Tolerance = None) -> CreasePattern:
    """The crease pattern of the DXF file ``p`` (errors without the file name)."""
    doc = _open_dxf(p)
    scale = _mm_per_unit(doc) if mm_per_unit is None else float(mm_per_unit)
    unit_text, unit_notes = _unit_notes(doc, mm_per_unit)
    _expanded_count(doc.modelspace(), {})
    chains, (x0, y0, x1, y1), holes, unknown, skipped = _classify_entities(doc, scale)
    size = math.hypot(x1 - x0, y1 - y0) if x1 >= x0 else 0.0
    flatten = max(_FLATTEN_MM / scale, _FLATTEN_RELATIVE * size)
    segments, letters, dropped = _flatten_chains(chains, flatten)
    _check_found(unknown, skipped, holes, segments)
    coords, edges = _merge_ends(segments, scale)
    title = p.stem
    cp = CreasePattern(
        coords, edges, letters, metadata={"title": title}, tolerance=import_tolerance(tolerance)
    )
    cp = cp.with_outline_cuts_as_border().with_metadata(source_unit=unit_text)
    cp.notes = (*cp.notes, *unit_notes, *_dropped_notes(dropped))
    return cp.with_holes(holes) if holes else cp


# the registry entries of this format, merged by :mod:`origami_cad.pattern.formats`:
# a reader is ``read(path, mm_per_unit) -> CreasePattern``, a writer ``write(cp, path) -> Path``
readers = {".dxf": read_dxf}
writers = {".dxf": write_dxf}
