"""SVG crease patterns in Origami Simulator's colour convention (read and write).

Stroke colour gives the type: black border, red ``#ff0000`` mountain, blue ``#0000ff``
valley, green ``#00ff00`` cut, yellow ``#ffff00`` triangulation facet (``F``),
magenta ``#ff00ff`` undriven hinge (``U``). Stroke opacity scales the target fold
angle: a mountain folds to ``-opacity x 180`` degrees, a valley to ``+opacity x 180``.

Reading takes ``line``, ``polyline``, ``polygon``, ``rect`` and ``path`` elements
(every path command, absolute and relative: curves are cut into straight segments, as
Origami Simulator cuts them, :mod:`~origami_cad.pattern.formats.svgpath`), with every
``transform`` of the element and its groups applied and colours and opacities inherited
from groups (in CSS's cascade: attributes, then the rules of ``<style>`` elements, as
Illustrator's default export writes them, :mod:`~origami_cad.pattern.formats.svgcss`, then
``style``). A stroke colour that is not one of the six is an error naming the element.
Circles with a fill and no stroke are holes; a stroked circle or ellipse is not a crease
line (Origami Simulator reads only the five elements above): it is left out, with a
warning naming it. Every number, transform, colour and opacity is checked: junk in
path data, a transform with the wrong number of arguments, an opacity outside
[0, 1] (it would scale a fold past 180 degrees) or a non-finite or huge
coordinate is an error naming the element (its ``id`` with control characters
escaped). The writer escapes the title (``&``, ``<``, control characters).

Units: with a ``viewBox`` and ``width``/``height`` in absolute units (mm, cm, in,
pt, px at 96 per inch) user units are converted to mm; otherwise one user unit is
one millimetre. SVG's y axis points down: the pattern's y is the SVG's -y, so the
pattern is not mirrored (the writer writes -y, so files round-trip within 1e-12 of
the pattern's size).

The writer gives ``width`` and ``height`` in mm and draws in user units at
:func:`units_per_mm` units per mm: 1, or 10, 100, ... when the pattern has
features under 4 mm, because Origami Simulator reads user units only and merges
vertices closer than 3 of them (its ``vertTol``).
"""

from __future__ import annotations

import itertools
import math
import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from origami_cad._fileio import atomic_write
from origami_cad._names import xml_text
from origami_cad._toml import input_file
from origami_cad.errors import PatternError
from origami_cad.pattern.formats.svgcss import StyleSheet, style_sheet
from origami_cad.pattern.formats.svgpath import NUMBER as _NUMBER
from origami_cad.pattern.formats.svgpath import path_points, svg_number
from origami_cad.pattern.formats.xmlparse import parse_bounded
from origami_cad.pattern.model import (
    MAX_COORDINATE,
    MAX_EDGES,
    CreasePattern,
    Hole,
    Problem,
    Severity,
    printable,
)
from origami_cad.pattern.outline import outline_creases_as_border
from origami_cad.pattern.planar import Tolerance, import_tolerance

__all__ = [
    "MAX_DEPTH",
    "MAX_ELEMENTS",
    "MIN_FEATURE_UNITS",
    "OS_MERGE_UNITS",
    "read_svg",
    "units_per_mm",
    "write_svg",
]

COLORS = {
    "B": "#000000",
    "M": "#ff0000",
    "V": "#0000ff",
    "C": "#00ff00",
    "F": "#ffff00",
    "U": "#ff00ff",
    "J": "#ff00ff",
}
_BY_COLOR = {
    "#000000": "B",
    "#ff0000": "M",
    "#0000ff": "V",
    "#00ff00": "C",
    "#ffff00": "F",
    "#ff00ff": "U",
}
_NAMED = {
    "black": "#000000",
    "red": "#ff0000",
    "blue": "#0000ff",
    "lime": "#00ff00",
    "yellow": "#ffff00",
    "magenta": "#ff00ff",
    "fuchsia": "#ff00ff",
}
_UNIT_MM = {
    "mm": 1.0,
    "cm": 10.0,
    "in": 25.4,
    "pt": 25.4 / 72,
    "pc": 25.4 / 6,
    "px": 25.4 / 96,
    "": None,
}


#: characters XML 1.0 cannot hold, even escaped (control characters, lone surrogates)


def _fmt(v: float) -> str:
    return repr(round(float(v), 12) + 0.0)


#: Elements :func:`read_svg` walks at the most, the copies that ``<use>`` makes included
#: (a file with more is refused while it is parsed).
MAX_ELEMENTS = 1_000_000
#: Deepest nesting of elements :func:`read_svg` reads (the root is at depth 1): libxml2's
#: default limit, so no browser or Inkscape opens a deeper file either.
MAX_DEPTH = 256

#: Origami Simulator merges vertices closer than this many user units (``vertTol``)
OS_MERGE_UNITS = 3.0
#: the writer keeps distinct vertices (and a vertex and a line it is not on) at
#: least this many user units apart: Origami Simulator's tolerance, with a margin
MIN_FEATURE_UNITS = 4.0


def _min_feature(cp: CreasePattern, within: float) -> float:
    """The smallest distance (mm) between two distinct vertices, or between a vertex and
    an edge it is not on, if below ``within`` mm; else ``inf``. O(n log n)."""
    import shapely
    from scipy.spatial import cKDTree

    gaps, _ = cKDTree(cp.vertices).query(cp.vertices, k=2, distance_upper_bound=within)
    best = float(gaps[:, 1].min()) if cp.n_vertices > 1 else math.inf
    lines = shapely.linestrings(cp.vertices[cp.edges])
    points = shapely.points(cp.vertices)
    v, e = shapely.STRtree(lines).query(points, predicate="dwithin", distance=within)
    other = (cp.edges[e, 0] != v) & (cp.edges[e, 1] != v)
    if other.any():
        best = min(best, float(shapely.distance(points[v[other]], lines[e[other]]).min()))
    return best


def units_per_mm(cp: CreasePattern) -> float:
    """User units per millimetre of :func:`write_svg`: 1, or the smallest power of ten
    that keeps every feature of ``cp`` at least :data:`MIN_FEATURE_UNITS` units wide.

    Origami Simulator reads coordinates in user units (it ignores the viewBox and the
    width and height) and merges vertices closer than :data:`OS_MERGE_UNITS` units;
    at 1 unit per mm it would merge the 0.734 mm edges of the paper's Fig. 2.
    Coordinates stay within :data:`~origami_cad.pattern.model.MAX_COORDINATE` units.
    """
    feature = _min_feature(cp, MIN_FEATURE_UNITS)
    if not math.isfinite(feature) or feature <= 0:
        return 1.0
    k = 10.0 ** max(0, math.ceil(math.log10(MIN_FEATURE_UNITS / feature) - 1e-12))
    reach = float(np.abs(cp.vertices).max(initial=1.0))
    while k > 1 and k * reach > MAX_COORDINATE:
        k /= 10
    return k


def write_svg(cp: CreasePattern, path: str | os.PathLike[str]) -> Path:
    """Write ``cp`` as an SVG at true size, atomically.

    ``width`` and ``height`` are in mm and the ``viewBox`` in user units, at
    :func:`units_per_mm` units per mm (1 unless the pattern has features under
    4 mm), so a browser, Inkscape and our reader see the true size and Origami
    Simulator, which works in user units and merges vertices closer than 3 of
    them, keeps every vertex.
    """
    k = units_per_mm(cp)
    x0, y0, x1, y1 = cp.bounds
    w, h = max(x1 - x0, 1e-9), max(y1 - y0, 1e-9)
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{_fmt(w)}mm" '
        f'height="{_fmt(h)}mm" viewBox="{_fmt(k * x0)} {_fmt(-k * y1)} {_fmt(k * w)} '
        f'{_fmt(k * h)}">',
    ]
    if cp.title:
        lines.append(f"<title>{xml_text(cp.title)}</title>")
    width = 0.002 * max(w, h) * k
    v = cp.vertices * k
    for (a, b), letter, angle in zip(cp.edges, cp.assignments, cp.fold_angles, strict=True):
        pa, pb = v[a], v[b]
        opacity = ""
        if letter in ("M", "V") and abs(abs(angle) - 180.0) > 1e-9:
            opacity = f' stroke-opacity="{_fmt(abs(angle) / 180.0)}"'
        lines.append(
            f'<line x1="{_fmt(pa[0])}" y1="{_fmt(-pa[1])}" x2="{_fmt(pb[0])}" '
            f'y2="{_fmt(-pb[1])}" stroke="{COLORS[str(letter)]}" stroke-width="{width:.4g}"'
            f"{opacity}/>"
        )
    for hole in cp.holes:
        lines.append(
            f'<circle cx="{_fmt(k * hole.x)}" cy="{_fmt(-k * hole.y)}" '
            f'r="{_fmt(k * hole.diameter / 2)}" fill="#888888" stroke="none"/>'
        )
    lines.append("</svg>")
    with atomic_write(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")
    return Path(path)


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _style(el: ET.Element, sheet: StyleSheet) -> dict[str, str]:
    """``el``'s properties: its attributes, the style sheet's rules, its ``style``."""
    inline = {}
    for item in el.attrib.get("style", "").split(";"):
        if ":" in item:
            key, value = item.split(":", 1)
            inline[key.strip()] = value.strip()
    return sheet.apply(el, dict(el.attrib), inline)


_num = svg_number


def _numbers(text: str, where: str, what: str) -> list[float]:
    """A list of numbers separated by white space and/or commas, nothing else."""
    body = text.strip()
    if not body:
        return []
    if not re.fullmatch(rf"{_NUMBER}(?:(?:\s*,\s*|\s+|(?=[-+.])){_NUMBER})*", body):
        raise PatternError(f"{where}: {what} = {printable(text)!r} is not a list of numbers")
    return [_num(v, where, what) for v in re.findall(_NUMBER, body)]


def _opacity(text: str, where: str, what: str) -> float:
    """An opacity: a number or percentage within [0, 1] (0% .. 100%)."""
    t = text.strip()
    pct = t.endswith("%")
    value = _num(t[:-1] if pct else t, where, what) / (100.0 if pct else 1.0)
    if not 0.0 <= value <= 1.0:
        raise PatternError(
            f"{where}: {what} = {printable(text)!r} is outside [0, 1]; an opacity scales the "
            "fold angle and cannot exceed 1 (180 degrees)"
        )
    return value


def material_color(value: str, where: str = "") -> str | None:
    v = value.strip().lower()
    if v in ("none", "transparent", ""):
        return None
    if v in _NAMED:
        return _NAMED[v]
    if re.fullmatch(r"#[0-9a-f]{3}", v):
        return "#" + "".join(c * 2 for c in v[1:])
    if re.fullmatch(r"#[0-9a-f]{6}", v):
        return v
    parts = v[4:-1].split(",") if v.startswith("rgb(") and v.endswith(")") else []
    if len(parts) == 3:
        chans = []
        for c in parts:
            c = c.strip()
            pct = c.endswith("%")
            x = _num(c[:-1] if pct else c, where, f"colour {printable(value)!r}")
            chans.append(round(x * 2.55) if pct else int(x))
        return "#" + "".join(f"{max(0, min(255, c)):02x}" for c in chans)
    return printable(v)  # unknown: reported by the caller


#: transform name -> allowed argument counts
_TRANSFORM_ARGS = {
    "matrix": (6,),
    "translate": (1, 2),
    "scale": (1, 2),
    "rotate": (1, 3),
    "skewX": (1,),
    "skewY": (1,),
}


def _transform(text: str, where: str = "") -> np.ndarray:
    m = np.eye(3)
    text = text or ""
    pos = 0
    item = re.compile(r"[\s,]*(\w+)\s*\(([^)]*)\)[\s,]*")
    while pos < len(text):
        found = item.match(text, pos)
        if found is None:
            if text[pos:].strip(" \t\r\n,"):
                raise PatternError(
                    f"{where}: transform {printable(text)!r} is malformed at character {pos}"
                )
            break
        pos = found.end()
        name, args = found.groups()
        if name not in _TRANSFORM_ARGS:
            raise PatternError(f"{where}: unknown transform {printable(name)!r}")
        a = _numbers(args, where, f"transform {name}()")
        if len(a) not in _TRANSFORM_ARGS[name]:
            raise PatternError(
                f"{where}: transform {name}() takes "
                f"{' or '.join(map(str, _TRANSFORM_ARGS[name]))} numbers, got {len(a)}"
            )
        t = np.eye(3)
        if name == "matrix":
            t = np.array([[a[0], a[2], a[4]], [a[1], a[3], a[5]], [0, 0, 1]])
        elif name == "translate":
            t[0, 2], t[1, 2] = a[0], (a[1] if len(a) > 1 else 0.0)
        elif name == "scale":
            t[0, 0], t[1, 1] = a[0], (a[1] if len(a) > 1 else a[0])
        elif name == "rotate":
            c, s = math.cos(math.radians(a[0])), math.sin(math.radians(a[0]))
            t = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
            if len(a) == 3:
                to = np.array([[1, 0, a[1]], [0, 1, a[2]], [0, 0, 1]])
                back = np.array([[1, 0, -a[1]], [0, 1, -a[2]], [0, 0, 1]])
                t = to @ t @ back
        elif name == "skewX":
            t[0, 1] = math.tan(math.radians(a[0]))
        elif name == "skewY":
            t[1, 0] = math.tan(math.radians(a[0]))
        with np.errstate(over="ignore", invalid="ignore"):
            m = m @ t
    if not np.all(np.isfinite(m)):
        raise PatternError(f"{where}: transform {printable(text)!r} overflows")
    return m


def _scale(root: ET.Element, name: str) -> tuple[float, float]:
    """mm per user unit in x and y, from the root's ``viewBox`` and ``width``/``height``.

    A ``viewBox`` that is not 4 numbers or has a width or height <= 0 (SVG draws
    nothing then), and a ``width`` or ``height`` that is not a number > 0 with a
    unit of SVG (``mm``, ``cm``, ``in``, ``pt``, ``pc``, ``px``, none, or the
    relative ``%``, ``em``, ``ex``) are PatternErrors naming the attribute. A
    relative or missing size, or no ``viewBox``, gives 1 mm per user unit.
    """
    where = f"{name}: <svg>"
    box = _numbers(root.attrib.get("viewBox", ""), where, "viewBox")
    if box and (len(box) != 4 or box[2] <= 0 or box[3] <= 0):
        raise PatternError(
            f"{where}: viewBox must be 4 numbers: min-x min-y width height, the width and "
            f"height > 0 (got {printable(root.attrib['viewBox'], 60)!r}; SVG draws nothing "
            "in an empty viewBox)"
        )
    result = []
    for k, key in enumerate(("width", "height")):
        text = root.attrib.get(key)
        if text is None:
            result.append(1.0)
            continue
        m = re.fullmatch(r"\s*(" + _NUMBER + r")\s*([a-z%]*)\s*", text)
        if not m or m.group(2) not in (*_UNIT_MM, "%", "em", "ex"):
            raise PatternError(
                f"{where}: {key} = {printable(text, 60)!r} is not a length (a number and "
                "one of the units mm, cm, in, pt, pc, px, %, em, ex)"
            )
        size = _num(m.group(1), where, key)
        if size <= 0:
            raise PatternError(f"{where}: {key} = {size:g} must be > 0")
        if len(box) != 4 or _UNIT_MM.get(m.group(2)) is None:
            result.append(1.0)  # no viewBox or a relative size: 1 user unit = 1 mm
            continue
        result.append(size * _UNIT_MM[m.group(2)] / box[2 + k])
    return result[0], result[1]


def _polylines(el: ET.Element, tag: str, where: str) -> list[list[tuple[float, float]]]:
    """The straight polylines an element draws, in its own user units."""

    def attr(name: str) -> float:
        return _num(el.attrib.get(name, "0"), where, name)

    if tag == "line":
        return [[(attr("x1"), attr("y1")), (attr("x2"), attr("y2"))]]
    if tag in ("polyline", "polygon"):
        v = _numbers(el.attrib.get("points", ""), where, "points")
        if len(v) % 2:
            raise PatternError(f"{where}: points has an odd count of numbers ({len(v)})")
        pts = list(zip(v[::2], v[1::2], strict=True))
        if tag == "polygon" and pts:
            pts.append(pts[0])
        return [pts]
    if tag == "rect":
        x, y, w, h = attr("x"), attr("y"), attr("width"), attr("height")
        if w < 0 or h < 0:
            raise PatternError(f"{where}: a rect's width and height must be >= 0")
        return [[(x, y), (x + w, y), (x + w, y + h), (x, y + h), (x, y)]]
    if tag == "path":
        return path_points(el.attrib.get("d", ""), where)
    return []


def read_svg(
    path: str | os.PathLike[str],
    mm_per_unit: float | None = None,
    tolerance: Tolerance = None,
) -> CreasePattern:
    """Read a crease pattern from an SVG in Origami Simulator's convention (mm).

    Every number, transform, colour and opacity is checked: malformed path
    data, a transform that is not one of SVG's six, an opacity outside [0, 1]
    or a non-finite coordinate is an error naming the element.

    ``mm_per_unit`` (millimetres per user unit) replaces what the root's
    ``viewBox`` and ``width``/``height`` declare (see the module notes);
    ``metadata["source_unit"]`` says which was used. Lines whose ends lie within
    ``tolerance`` mm of each other (or of a line) meet there (default
    :data:`~origami_cad.pattern.planar.IMPORT_RELATIVE_TOLERANCE` of the pattern's
    size; see :func:`~origami_cad.pattern.planar.import_tolerance`).

    Raises
    ------
    PatternError
        Naming the file and the element with an unknown colour, a curve or a
        malformed value.
    """
    p, name = input_file(path, PatternError)
    root = _svg_root(p, name)
    if mm_per_unit is None:
        sx, sy = _scale(root, name)
        unit = f"{sx:.6g} mm per user unit (width, height and viewBox)"
        if (sx, sy) == (1.0, 1.0):
            unit = "mm (1 user unit = 1 mm)"
    else:
        sx = sy = float(mm_per_unit)
        unit = f"{sx:g} mm per user unit (given)"
    sheet = style_sheet(root, name)
    segments, holes, title, dropped, unread = _walk_svg(root, name, sx, sy, sheet)
    if not segments:
        raise PatternError(f"{name}: no crease lines found (no stroked line, polyline or path)")
    coords = np.array([[a, b] for a, b, _, _ in segments], float).reshape(-1, 2)
    coords[:, 0] *= sx
    coords[:, 1] *= -sy
    edges = np.arange(len(coords)).reshape(-1, 2)
    try:
        cp = CreasePattern(
            coords,
            edges,
            [s[2] for s in segments],
            [s[3] for s in segments],
            metadata={"title": title or p.stem, "source_unit": unit},
            tolerance=import_tolerance(tolerance),
        )
    except PatternError as exc:
        raise PatternError(f"{name}: {exc}") from None
    cp = outline_creases_as_border(cp)
    left_out = _dropped_notes(dropped, name) + _sheet_notes(sheet, unread, name)
    cp.notes = (*cp.notes, *left_out)
    return cp.with_holes(holes) if holes else cp


def _dropped_notes(dropped: dict[str, bool], name: str) -> list[Problem]:
    """Notes on the zero-length segments left out: a warning naming the elements that
    drew nothing but them, an info note naming those that drew other lines too."""
    notes = []
    for empty, severity, what in (
        (True, Severity.WARNING, "drawing nothing but zero-length lines, left out"),
        (False, Severity.INFO, "with zero-length segments, which were left out"),
    ):
        named = [w.removeprefix(f"{name}: ") for w, e in dropped.items() if e is empty]
        if named:
            shown = "; ".join(named[:3]) + (
                f"; and {len(named) - 3} more" if len(named) > 3 else ""
            )
            notes.append(
                Problem(
                    "zero-length",
                    f"{name}: {len(named)} element{'' if len(named) == 1 else 's'} {what}: {shown}",
                    severity=severity,
                )
            )
    return notes


def _sheet_notes(sheet: StyleSheet, unread: list[str], name: str) -> list[Problem]:
    """Warnings naming the style rules left out (a browser leaves them out too) and the
    stroked circles and ellipses (not crease lines: Origami Simulator leaves them out)."""
    notes = []
    for items, code, what in (
        (sheet.skipped, "style-rule", "<style> rule(s) not read, left out as a browser does"),
        (unread, "curve-element", "stroked circle(s) or ellipse(s), not crease lines, left out"),
    ):
        if items:
            shown = "; ".join(items[:3]) + ("; ..." if len(items) > 3 else "")
            notes.append(
                Problem(code, f"{name}: {len(items)} {what}: {shown}", severity=Severity.WARNING)
            )
    return notes


def _svg_root(p: Path, name: str) -> ET.Element:
    """The ``<svg>`` root element of file ``p`` (``name`` starts every error), parsed
    within :data:`MAX_DEPTH` and :data:`MAX_ELEMENTS` (:func:`.xmlparse.parse_bounded`)."""
    why = " (libxml2's, so browsers and Inkscape cannot open it either)"
    root = parse_bounded(p, name, MAX_DEPTH, MAX_ELEMENTS, why)
    if _local(root.tag) != "svg":
        raise PatternError(
            f"{name}: the root element is <{printable(_local(root.tag))}>, not <svg>"
        )
    return root


def _walk_svg(
    root: ET.Element, name: str, sx: float, sy: float, sheet: StyleSheet
) -> tuple[
    list[tuple[np.ndarray, np.ndarray, str, float]], list[Hole], str, dict[str, bool], list[str]
]:
    """``(segments, holes, title, dropped, unread)`` of the document below ``root``.

    Depth-first, in document order, without recursion (nesting depth is the
    file's). Segments are ``(a, b, letter, angle)`` in user units (y down),
    angle in degrees; holes in mm; ``sx, sy`` are mm per user unit; ``sheet`` the
    document's style rules; ``dropped`` names the elements with zero-length segments
    (see :func:`_element_segments`), ``unread`` the stroked circles and ellipses left out.
    """
    segments: list[tuple[np.ndarray, np.ndarray, str, float]] = []
    holes: list[Hole] = []
    title = ""
    counter = 0
    dropped: dict[str, bool] = {}
    unread: list[str] = []
    ids = {el.attrib["id"]: el for el in root.iter() if "id" in el.attrib}
    stack: list[tuple[ET.Element, np.ndarray, dict[str, str], float, frozenset]]
    stack = [(root, np.eye(3), {}, 1.0, frozenset())]
    while stack:
        el, matrix, inherited, opacity, using = stack.pop()
        tag = _local(el.tag)
        own = _style(el, sheet)
        style = {
            **inherited,
            **{k: v for k, v in own.items() if k in ("stroke", "stroke-opacity", "fill")},
        }
        if tag == "title" and el.text and not title:
            title = el.text.strip()
        if tag in ("defs", "clipPath", "mask", "symbol", "metadata", "style"):
            continue
        counter += 1
        if counter > MAX_ELEMENTS:
            raise PatternError(
                f"{name}: more than {MAX_ELEMENTS:,} elements (with the copies <use> makes)"
            )
        ident = el.attrib.get("id")
        where = (
            f"{name}: <{printable(tag)}{' id=' + printable(ident) if ident else ''}> "
            f"(element {counter})"
        )
        if tag == "svg" and el is not root:
            _nested_svg(el, where)
        if "opacity" in own:
            opacity = opacity * _opacity(own["opacity"], where, "opacity")
        m = matrix @ _transform(el.attrib.get("transform", ""), where)
        if tag == "use":
            stack.extend(_used(el, ids, where, m, style, opacity, using))
            continue
        hole = _svg_hole(el, tag, where, m, style, sx, sy)
        if hole is not None:
            holes.append(hole)
            continue
        if tag in ("circle", "ellipse") and material_color(style.get("stroke", "none"), where):
            unread.append(where.removeprefix(f"{name}: "))
            continue
        drawn = _element_segments(el, tag, where, m, style, opacity, sx, sy, dropped)
        segments += drawn
        if len(segments) > MAX_EDGES:
            raise PatternError(
                f"{where}: more than {MAX_EDGES:,} line segments (MAX_EDGES), too many for a "
                "crease pattern"
            )
        stack.extend((child, m, style, opacity, using) for child in reversed(el))
    return segments, holes, title, dropped, unread


def _nested_svg(el: ET.Element, where: str) -> None:  # fmt: skip
    """PatternError for a nested ``<svg>`` that sets its own viewport (``viewBox``, ``x``,
    ``y``), which this reader does not apply: an empty ``viewBox`` draws nothing, and a
    valid one, or an offset, would move and scale what it holds."""
    box = _numbers(el.attrib.get("viewBox", ""), where, "viewBox")
    if box and (len(box) != 4 or box[2] <= 0 or box[3] <= 0):
        raise PatternError(
            f"{where}: viewBox must be 4 numbers, width and height > 0 (got "
            f"{printable(el.attrib['viewBox'], 60)!r}; SVG draws nothing then)"
        )
    if box or any(_num(el.attrib.get(k, "0"), where, k) != 0 for k in ("x", "y")):
        raise PatternError(
            f"{where}: a nested <svg> with its own viewBox or x, y is not read "
            "(it would move and scale what it holds); ungroup it first"
        )


def _used(
    el: ET.Element,
    ids: dict[str, ET.Element],
    where: str,
    m: np.ndarray,
    style: dict[str, str],
    opacity: float,
    using: frozenset,
) -> list[tuple[ET.Element, np.ndarray, dict[str, str], float, frozenset]]:
    """What a ``<use>`` draws, as entries of :func:`_walk_svg`'s stack.

    The element its ``href`` (or ``xlink:href``) names, moved by its ``x`` and ``y``
    (user units) after its own transform ``m``, inheriting its style; a ``<symbol>``
    gives its children. ``using`` holds the ids being drawn through ``<use>`` above
    this one: a reference to one of them (a cycle), to an id this file lacks or
    to another file is a PatternError naming the ``<use>``.
    """
    href = el.attrib.get("href", el.attrib.get("{http://www.w3.org/1999/xlink}href", ""))
    key = href[1:] if href.startswith("#") else None
    if key not in ids:
        raise PatternError(f"{where}: href {printable(href)!r} names no element of this file")
    if key in using:
        raise PatternError(f"{where}: #{printable(key)} contains this <use> (a cycle)")
    x = _num(el.attrib.get("x", "0"), where, "x")
    y = _num(el.attrib.get("y", "0"), where, "y")
    moved = m @ np.array([[1.0, 0.0, x], [0.0, 1.0, y], [0.0, 0.0, 1.0]])
    target, inside = ids[key], using | {key}
    shown = list(target) if _local(target.tag) == "symbol" else [target]
    return [(t, moved, style, opacity, inside) for t in reversed(shown)]


def _svg_hole(
    el: ET.Element,
    tag: str,
    where: str,
    m: np.ndarray,
    style: dict[str, str],
    sx: float,
    sy: float,
) -> Hole | None:
    """The hole (mm) of a filled, unstroked ``<circle>``; None for any other element.

    ``m`` is the element's transform, ``sx, sy`` mm per user unit.
    """
    if tag == "circle":
        stroke = material_color(style.get("stroke", "none"), where)
        if stroke is None and material_color(style.get("fill", "black"), where) is not None:
            cx = _num(el.attrib.get("cx", "0"), where, "cx")
            cy = _num(el.attrib.get("cy", "0"), where, "cy")
            r = _num(el.attrib.get("r", "0"), where, "r")
            c = m @ np.array([cx, cy, 1.0])
            r = r * math.sqrt(abs(np.linalg.det(m[:2, :2])))
            try:
                return Hole(c[0] * sx, -c[1] * sy, 2 * r * math.sqrt(sx * sy))
            except PatternError as exc:
                raise PatternError(f"{where}: {exc}") from None
    return None


def _element_segments(
    el: ET.Element,
    tag: str,
    where: str,
    m: np.ndarray,
    style: dict[str, str],
    opacity: float,
    sx: float,
    sy: float,
    dropped: dict[str, bool],
) -> list[tuple[np.ndarray, np.ndarray, str, float]]:
    """The ``(a, b, letter, angle)`` segments of one stroked element (user units).

    The stroke colour gives the letter, the opacities (times the inherited
    ``opacity``) the fold angle in degrees; ``m`` is the element's transform and
    ``sx, sy`` mm per user unit (for the coordinate limit). A transform that
    collapses the plane (``scale(0)``, a singular ``matrix``) is a PatternError
    naming the element; zero-length segments are left out and recorded in
    ``dropped`` (``where`` -> True when the element drew nothing else).
    """
    segments: list[tuple[np.ndarray, np.ndarray, str, float]] = []
    polylines = _polylines(el, tag, where)
    if not polylines:
        return segments
    stroke = material_color(style.get("stroke", "none"), where)
    if stroke is None:
        return segments
    letter = _BY_COLOR.get(stroke)
    if letter is None:
        raise PatternError(
            f"{where} has stroke {stroke}, not a crease colour of the Origami "
            "Simulator convention (black border, red mountain, blue valley, green "
            "cut, yellow facet, magenta undriven)"
        )
    alpha = opacity * _opacity(style.get("stroke-opacity", "1"), where, "stroke-opacity")
    angle = {"M": -180.0 * alpha, "V": 180.0 * alpha}.get(letter, 0.0)
    a, b, c, d = m[0, 0], m[0, 1], m[1, 0], m[1, 1]
    if not abs(a * d - b * c) > 1e-12 * (a * a + b * b + c * c + d * d):
        raise PatternError(
            f"{where}: its transform (with its groups') collapses the plane onto a line or "
            "a point (scale(0) or a singular matrix): its crease lines would vanish"
        )
    zero = 0
    for pts in polylines:
        if not pts:
            continue
        with np.errstate(over="ignore", invalid="ignore"):
            arr = np.column_stack([np.array(pts, float), np.ones(len(pts))]) @ m.T
            mm = arr[:, :2] * (sx, sy)
        if not np.all(np.abs(mm) <= MAX_COORDINATE):
            raise PatternError(
                f"{where}: a point lies farther than {MAX_COORDINATE:g} mm from the "
                "origin (after transforms and units), or is not finite"
            )
        for p, q in itertools.pairwise(arr):
            if np.allclose(p, q):
                zero += 1
            else:
                segments.append((p[:2], q[:2], letter, angle))
    if zero:
        dropped[where] = not segments
    return segments


# the registry entries of this format, merged by :mod:`origami_cad.pattern.formats`:
# a reader is ``read(path, mm_per_unit) -> CreasePattern``, a writer ``write(cp, path) -> Path``
readers = {".svg": read_svg}
writers = {".svg": write_svg}
