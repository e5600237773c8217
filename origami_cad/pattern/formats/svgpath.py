"""SVG path data as polylines: every command, curves cut into straight segments.

``path_points`` reads the ``d`` attribute of a ``<path>``: moveto, lineto (``M L H V``),
closepath (``Z``), cubic and quadratic Béziers (``C S Q T``) and elliptical arcs
(``A``), absolute and relative. A crease is straight, so a curve becomes a polyline, as
Origami Simulator cuts a curve into segments when it imports one: a Bézier into equal
steps of its parameter, enough that no point of the curve lies farther than
:data:`CURVE_TOLERANCE` of the length of its control polygon from the polyline (at most
:data:`MAX_SEGMENTS`); an arc into steps of at most :data:`ARC_STEP_DEG`. Numbers are in
the drawing's user units; anything that is neither a command nor a number is a
:class:`~origami_cad.errors.PatternError` naming the element.
"""

from __future__ import annotations

import math
import re

import numpy as np

from origami_cad.errors import PatternError
from origami_cad.pattern.model import MAX_COORDINATE, printable

__all__ = ["ARC_STEP_DEG", "CURVE_TOLERANCE", "MAX_SEGMENTS", "NUMBER", "path_points", "svg_number"]

#: An SVG number (no unit).
NUMBER = r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"
#: Largest distance of a Bézier curve from its polyline, a fraction of the length of the
#: curve's control polygon (0.5 %: a pleat drawn 60 mm long is off by at most 0.3 mm).
CURVE_TOLERANCE = 0.005
#: Most straight segments one curve becomes.
MAX_SEGMENTS = 64
#: Largest turn of an arc's segment, degrees.
ARC_STEP_DEG = 10.0

#: numbers each path command takes
_PATH_ARGS = {"M": 2, "L": 2, "H": 1, "V": 1, "Z": 0, "C": 6, "S": 4, "Q": 4, "T": 2, "A": 7}
_PATH_TOKEN = re.compile(r"[\s,]*(?:([A-Za-z])|(" + NUMBER + r"))")


def svg_number(text: str, where: str, what: str) -> float:
    """A finite SVG number (no unit), else a :class:`PatternError` naming ``what``."""
    if not re.fullmatch(r"\s*" + NUMBER + r"\s*", text):
        raise PatternError(f"{where}: {what} = {printable(text)!r} is not a number")
    value = float(text)
    if not math.isfinite(value) or abs(value) > MAX_COORDINATE:
        raise PatternError(f"{where}: {what} = {printable(text)!r} is out of range")
    return value


def _path_tokens(d: str, where: str) -> list[str]:
    """Tokens of path data; anything that is neither a command nor a number is an error."""
    tokens = []
    pos = 0
    while pos < len(d):
        m = _PATH_TOKEN.match(d, pos)
        if m is None:
            rest = d[pos:]
            if rest.strip(" \t\r\n\f,"):
                raise PatternError(
                    f"{where}: path data has {printable(rest.lstrip()[:12])!r} at character "
                    f"{pos}, neither a command nor a number"
                )
            break
        tokens.append(m.group(1) or m.group(2))
        pos = m.end()
    return tokens


def _bezier(points: np.ndarray) -> list[tuple[float, float]]:
    """A quadratic or cubic Bézier (its 3 or 4 control points, (k, 2)) as the points of
    its polyline after the first."""
    second = points[:-2] - 2.0 * points[1:-1] + points[2:]
    bend = float(np.max(np.hypot(second[:, 0], second[:, 1])))
    length = float(np.sum(np.hypot(*np.diff(points, axis=0).T)))
    degree = len(points) - 1
    # |B''| <= degree (degree - 1) max|second difference|; the chord error <= |B''| / 8 n^2
    need = degree * (degree - 1) * bend / (8.0 * CURVE_TOLERANCE * length) if length > 0 else 0
    n = int(min(MAX_SEGMENTS, max(1, math.ceil(math.sqrt(need)))))
    t = np.linspace(0.0, 1.0, n + 1)[1:, None]
    if degree == 2:
        p0, p1, p2 = points
        out = (1 - t) ** 2 * p0 + 2 * (1 - t) * t * p1 + t**2 * p2
    else:
        p0, p1, p2, p3 = points
        out = (1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * p1 + 3 * (1 - t) * t**2 * p2 + t**3 * p3
    out[-1] = points[-1]  # the end exactly
    return [(float(x), float(y)) for x, y in out]


def _arc(start, rx, ry, phi_deg, large, sweep, end) -> list[tuple[float, float]]:
    """An elliptical arc (SVG's endpoint form) as the points of its polyline after the
    first (SVG 1.1, appendix F.6: out-of-range radii scaled up, zero radii a line)."""
    (x1, y1), (x2, y2) = start, end
    rx, ry = abs(rx), abs(ry)
    if rx == 0 or ry == 0 or (x1, y1) == (x2, y2):
        return [(x2, y2)]
    phi = math.radians(phi_deg)
    c, s = math.cos(phi), math.sin(phi)
    dx, dy = (x1 - x2) / 2.0, (y1 - y2) / 2.0
    xp, yp = c * dx + s * dy, -s * dx + c * dy
    scale = (xp / rx) ** 2 + (yp / ry) ** 2
    if scale > 1:
        rx, ry = rx * math.sqrt(scale), ry * math.sqrt(scale)
    num = rx**2 * ry**2 - rx**2 * yp**2 - ry**2 * xp**2
    den = rx**2 * yp**2 + ry**2 * xp**2
    k = math.sqrt(max(0.0, num / den)) * (-1.0 if large == sweep else 1.0)
    cxp, cyp = k * rx * yp / ry, -k * ry * xp / rx
    cx = c * cxp - s * cyp + (x1 + x2) / 2.0
    cy = s * cxp + c * cyp + (y1 + y2) / 2.0
    theta1 = math.atan2((yp - cyp) / ry, (xp - cxp) / rx)
    theta2 = math.atan2((-yp - cyp) / ry, (-xp - cxp) / rx)
    delta = theta2 - theta1
    if sweep and delta < 0:
        delta += 2 * math.pi
    elif not sweep and delta > 0:
        delta -= 2 * math.pi
    n = max(1, math.ceil(abs(math.degrees(delta)) / ARC_STEP_DEG))
    out = []
    for i in range(1, n + 1):
        a = theta1 + delta * i / n
        ex, ey = rx * math.cos(a), ry * math.sin(a)
        out.append((cx + c * ex - s * ey, cy + s * ex + c * ey))
    out[-1] = (x2, y2)
    return out


def _segment(up: str, rel: bool, vals: list[float], here: tuple[float, float], control):
    """The points one drawing command (``up``: L, H, V, A, C, S, Q or T; ``rel``: its
    lower-case form) adds from ``here``, its end last, and the control point the next
    smooth Bézier reflects (``(kind, point)``, or None after a line or an arc)."""
    x, y = here
    if up in "LHV":
        if up == "L":
            nx, ny = vals[0] + (x if rel else 0.0), vals[1] + (y if rel else 0.0)
        elif up == "H":
            nx, ny = vals[0] + (x if rel else 0.0), y
        else:
            nx, ny = x, vals[0] + (y if rel else 0.0)
        return [(nx, ny)], None
    if up == "A":
        nx, ny = vals[5] + (x if rel else 0.0), vals[6] + (y if rel else 0.0)
        return _arc((x, y), vals[0], vals[1], vals[2], vals[3] != 0, vals[4] != 0, (nx, ny)), None
    off = np.array([x, y]) if rel else np.zeros(2)
    given = np.array(vals).reshape(-1, 2) + off
    start = np.array([x, y])
    kind = "C" if up in "CS" else "Q"
    if up in "ST":  # the first control point: the last one's reflection, or here
        first = 2 * start - control[1] if control and control[0] == kind else start
        given = np.vstack([first, given])
    ctrl = np.vstack([start, given])
    return _bezier(ctrl), (kind, ctrl[-2])


def path_points(d: str, where: str) -> list[list[tuple[float, float]]]:
    """The polylines (user units) of SVG path data ``d``; ``where`` names the element in
    the errors."""
    tokens = _path_tokens(d, where)
    subpaths: list[list[tuple[float, float]]] = []
    current: list[tuple[float, float]] = []
    x = y = 0.0
    start = (0.0, 0.0)
    cmd = None
    control = None  # the last Bézier's last control point, and its kind ("C" or "Q")
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
                control = None
                continue
            if cmd.upper() not in _PATH_ARGS:
                raise PatternError(f"{where}: {cmd!r} is not a path command")
            if i >= len(tokens) or tokens[i].isalpha():
                raise PatternError(f"{where}: path command {cmd!r} has no coordinates")
            continue
        if cmd is None:
            raise PatternError(f"{where}: path data must start with a command")
        if cmd in "Zz":
            raise PatternError(f"{where}: path data has a number after {cmd!r}")
        need = _PATH_ARGS[cmd.upper()]
        args = tokens[i : i + need]
        if len(args) < need or any(a.isalpha() for a in args):
            raise PatternError(f"{where}: path command {cmd!r} needs {need} numbers")
        vals = [svg_number(a, where, "path data") for a in args]
        i += need
        rel = cmd.islower()
        up = cmd.upper()
        if up == "M":
            nx, ny = vals[0] + (x if rel else 0.0), vals[1] + (y if rel else 0.0)
            if current:
                subpaths.append(current)
            current = [(nx, ny)]
            x, y = start = nx, ny
            control = None
            cmd = "l" if rel else "L"  # implicit lineto after a moveto
            continue
        if not current:
            current = [(x, y)]
        points, control = _segment(up, rel, vals, (x, y), control)
        current.extend(points)
        x, y = points[-1]
    if current:
        subpaths.append(current)
    return subpaths
