"""SVG crease patterns in Origami Simulator's colour convention (read and write).

Stroke colour gives the type: black border, red ``#ff0000`` mountain, blue ``#0000ff``
valley, green ``#00ff00`` cut, yellow ``#ffff00`` triangulation facet (``F``),
magenta ``#ff00ff`` undriven hinge (``U``). Stroke opacity scales the target fold
angle: a mountain folds to ``-opacity x 180`` degrees, a valley to ``+opacity x 180``.

Reading takes ``line``, ``polyline``, ``polygon``, ``rect`` and ``path`` elements
(commands M, L, H, V, Z, absolute and relative), with every ``transform`` of the
element and its groups applied and colours and opacities inherited from groups
(``style`` wins over attributes). A curved path command or a stroke colour that is
not one of the six is an error naming the element. Circles with a fill and no
stroke are holes.

Units: with a ``viewBox`` and ``width``/``height`` in absolute units (mm, cm, in,
pt, px at 96 per inch) user units are converted to mm; otherwise one user unit is
one millimetre. SVG's y axis points down: the pattern's y is the SVG's -y, so the
pattern is not mirrored (the writer writes -y, so files round-trip exactly).
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
from origami_cad.errors import PatternError
from origami_cad.pattern.model import CreasePattern, Hole

__all__ = ["read_svg", "write_svg"]

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
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def _fmt(v: float) -> str:
    return repr(round(float(v), 12) + 0.0)


def write_svg(cp: CreasePattern, path: str | os.PathLike[str]) -> Path:
    """Write ``cp`` as an SVG at true size (mm), atomically."""
    x0, y0, x1, y1 = cp.bounds
    w, h = max(x1 - x0, 1e-9), max(y1 - y0, 1e-9)
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{_fmt(w)}mm" '
        f'height="{_fmt(h)}mm" viewBox="{_fmt(x0)} {_fmt(-y1)} {_fmt(w)} {_fmt(h)}">',
    ]
    if cp.title:
        lines.append(f"<title>{cp.title}</title>")
    width = 0.002 * max(w, h)
    for (a, b), letter, angle in zip(cp.edges, cp.assignments, cp.fold_angles, strict=True):
        pa, pb = cp.vertices[a], cp.vertices[b]
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
            f'<circle cx="{_fmt(hole.x)}" cy="{_fmt(-hole.y)}" '
            f'r="{_fmt(hole.diameter / 2)}" fill="#888888" stroke="none"/>'
        )
    lines.append("</svg>")
    with atomic_write(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")
    return Path(path)


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _style(el: ET.Element) -> dict[str, str]:
    out = {k: v for k, v in el.attrib.items()}
    for item in el.attrib.get("style", "").split(";"):
        if ":" in item:
            key, value = item.split(":", 1)
            out[key.strip()] = value.strip()
    return out


def _color(value: str) -> str | None:
    v = value.strip().lower()
    if v in ("none", "transparent", ""):
        return None
    if v in _NAMED:
        return _NAMED[v]
    if re.fullmatch(r"#[0-9a-f]{3}", v):
        return "#" + "".join(c * 2 for c in v[1:])
    if re.fullmatch(r"#[0-9a-f]{6}", v):
        return v
    m = re.fullmatch(r"rgb\(\s*([^,]+),\s*([^,]+),\s*([^)]+)\)", v)
    if m:
        chans = []
        for c in m.groups():
            c = c.strip()
            chans.append(round(float(c[:-1]) * 2.55) if c.endswith("%") else int(float(c)))
        return "#" + "".join(f"{max(0, min(255, c)):02x}" for c in chans)
    return v  # unknown: reported by the caller


def _transform(text: str) -> np.ndarray:
    m = np.eye(3)
    for name, args in re.findall(r"(\w+)\s*\(([^)]*)\)", text or ""):
        a = [float(v) for v in re.findall(_NUMBER, args)]
        t = np.eye(3)
        if name == "matrix" and len(a) == 6:
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
        m = m @ t
    return m


def _path_points(d: str, where: str) -> list[list[tuple[float, float]]]:
    tokens = re.findall(r"[A-Za-z]|" + _NUMBER, d)
    subpaths: list[list[tuple[float, float]]] = []
    current: list[tuple[float, float]] = []
    x = y = 0.0
    start = (0.0, 0.0)
    cmd = None
    i = 0
    while i < len(tokens):
        tok = tokens[i]
        if tok.isalpha():
            cmd = tok
            i += 1
            if cmd in "Zz":
                if current:
                    current.append(start)
                    subpaths.append(current)
                    current = []
                x, y = start
                continue
            if cmd not in "MmLlHhVv":
                raise PatternError(
                    f"{where} uses the curved path command {cmd!r}; crease lines must be straight"
                )
            continue
        if cmd is None:
            raise PatternError(f"{where}: path data must start with a command")
        value = float(tok)
        if cmd in "Mm":
            nx = value + (x if cmd == "m" else 0.0)
            ny = float(tokens[i + 1]) + (y if cmd == "m" else 0.0)
            i += 2
            if current:
                subpaths.append(current)
            current = [(nx, ny)]
            x, y = start = nx, ny
            cmd = "l" if cmd == "m" else "L"  # implicit lineto after a moveto
            continue
        if cmd in "Ll":
            nx = value + (x if cmd == "l" else 0.0)
            ny = float(tokens[i + 1]) + (y if cmd == "l" else 0.0)
            i += 2
        elif cmd in "Hh":
            nx, ny = value + (x if cmd == "h" else 0.0), y
            i += 1
        else:
            nx, ny = x, value + (y if cmd == "v" else 0.0)
            i += 1
        if not current:
            current = [(x, y)]
        current.append((nx, ny))
        x, y = nx, ny
    if current:
        subpaths.append(current)
    return subpaths


def _scale(root: ET.Element, p: Path) -> tuple[float, float]:
    box = [float(v) for v in re.findall(_NUMBER, root.attrib.get("viewBox", ""))]
    result = []
    for k, key in enumerate(("width", "height")):
        m = re.fullmatch(r"\s*(" + _NUMBER + r")\s*([a-z%]*)\s*", root.attrib.get(key, ""))
        if not m or len(box) != 4 or m.group(2) not in _UNIT_MM or _UNIT_MM[m.group(2)] is None:
            result.append(1.0)
            continue
        size_mm = float(m.group(1)) * _UNIT_MM[m.group(2)]
        result.append(size_mm / box[2 + k] if box[2 + k] else 1.0)
    return result[0], result[1]


def read_svg(path: str | os.PathLike[str]) -> CreasePattern:
    """Read a crease pattern from an SVG in Origami Simulator's convention (mm).

    Raises
    ------
    PatternError
        Naming the file and the element with an unknown colour or a curve.
    """
    p = Path(path)
    if not p.is_file():
        raise PatternError(f"{p}: no such file")
    try:
        root = ET.parse(p).getroot()
    except ET.ParseError as exc:
        raise PatternError(f"{p}: not valid XML ({exc})") from None
    if _local(root.tag) != "svg":
        raise PatternError(f"{p}: the root element is <{_local(root.tag)}>, not <svg>")
    sx, sy = _scale(root, p)
    segments: list[tuple[np.ndarray, np.ndarray, str, float]] = []
    holes: list[Hole] = []
    title = ""
    counter = [0]

    def visit(el: ET.Element, matrix: np.ndarray, inherited: dict[str, str], opacity: float):
        tag = _local(el.tag)
        style = {
            **inherited,
            **{k: v for k, v in _style(el).items() if k in ("stroke", "stroke-opacity", "fill")},
        }
        own = _style(el)
        opacity = opacity * float(own.get("opacity", 1.0))
        m = matrix @ _transform(el.attrib.get("transform", ""))
        nonlocal title
        if tag == "title" and el.text and not title:
            title = el.text.strip()
        if tag in ("defs", "clipPath", "mask", "symbol", "metadata", "style"):
            return
        counter[0] += 1
        ident = el.attrib.get("id")
        where = f"{p}: <{tag}{' id=' + ident if ident else ''}> (element {counter[0]})"
        polylines: list[list[tuple[float, float]]] = []
        try:
            if tag == "line":
                polylines = [
                    [
                        (float(el.attrib.get("x1", 0)), float(el.attrib.get("y1", 0))),
                        (float(el.attrib.get("x2", 0)), float(el.attrib.get("y2", 0))),
                    ]
                ]
            elif tag in ("polyline", "polygon"):
                v = [float(t) for t in re.findall(_NUMBER, el.attrib.get("points", ""))]
                pts = list(zip(v[::2], v[1::2], strict=False))
                if tag == "polygon" and pts:
                    pts.append(pts[0])
                polylines = [pts]
            elif tag == "rect":
                x, y = float(el.attrib.get("x", 0)), float(el.attrib.get("y", 0))
                w, h = float(el.attrib.get("width", 0)), float(el.attrib.get("height", 0))
                polylines = [[(x, y), (x + w, y), (x + w, y + h), (x, y + h), (x, y)]]
            elif tag == "path":
                polylines = _path_points(el.attrib.get("d", ""), where)
            elif tag == "circle":
                stroke = _color(style.get("stroke", "none"))
                if stroke is None and _color(style.get("fill", "black")) is not None:
                    c = m @ np.array(
                        [float(el.attrib.get("cx", 0)), float(el.attrib.get("cy", 0)), 1.0]
                    )
                    r = float(el.attrib.get("r", 0)) * math.sqrt(abs(np.linalg.det(m[:2, :2])))
                    holes.append(Hole(c[0] * sx, -c[1] * sy, 2 * r * math.sqrt(sx * sy)))
                    return
        except PatternError:
            raise
        except ValueError:
            raise PatternError(f"{where} has a malformed coordinate") from None
        if polylines:
            stroke = _color(style.get("stroke", "none"))
            if stroke is not None:
                letter = _BY_COLOR.get(stroke)
                if letter is None:
                    raise PatternError(
                        f"{where} has stroke {stroke}, not a crease colour of the Origami "
                        "Simulator convention (black border, red mountain, blue valley, green "
                        "cut, yellow facet, magenta undriven)"
                    )
                alpha = opacity * float(style.get("stroke-opacity", 1.0))
                angle = {"M": -180.0 * alpha, "V": 180.0 * alpha}.get(letter, 0.0)
                for pts in polylines:
                    arr = np.column_stack([np.array(pts, float), np.ones(len(pts))]) @ m.T
                    for a, b in itertools.pairwise(arr):
                        if not np.allclose(a, b):
                            segments.append((a[:2], b[:2], letter, angle))
        for child in el:
            visit(child, m, style, opacity)

    visit(root, np.eye(3), {}, 1.0)
    if not segments:
        raise PatternError(f"{p}: no crease lines found (no stroked line, polyline or path)")
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
            metadata={"title": title or p.stem},
        )
    except PatternError as exc:
        raise PatternError(f"{p}: {exc}") from None
    return cp.with_holes(holes) if holes else cp
