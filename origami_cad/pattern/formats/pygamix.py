"""PyGamiX's JSON designs (read only): system descriptions and editable designs, mm.

PyGamiX (the software release of the paper this project implements) keeps a design
in one of two JSON forms, both read here as they are:

- a **system description** (``descriptionData/*.json``): ``kps`` (2-D key points),
  ``lines`` (segments, each two points), ``line_features[i]["type"]`` per line,
  ``units`` (the panels' polygons), ``contributions[u]`` (the weights of panel
  ``u``'s corners whose weighted sum is its hole), ``P_candidators`` (``points``,
  3-D anchors, and ``connections``: the panel an anchor rides on, or -1 for an
  anchor fixed off the sheet), ``strings`` (per tendon the lists ``type`` - ``"A"``
  an anchor, ``"B"`` a panel -, ``id`` - the anchor's index into ``P_candidators``
  or the panel's index - and ``reverse`` - -1 the tendon runs below the sheet,
  +1 above) and ``fix`` (the panels held);
- an **editable design** (``packedImport/*.json``): ``origami``, a list of pieces
  placed at ``tsp``; a ``"dxf"`` piece holds ``data.kps``, ``data.lines`` and
  ``data.lines_type``; its panels' holes are ``util.hole_axis`` (``[point, panel,
  enabled]``), its hole size ``setting.hole_size``; strings, anchors and fixed
  panels as above. A ``"kl"`` piece is a transition graph, ``data`` a list of
  ``[length, angle]`` (mm, radians), that PyGamiX draws as ``setting.copy_time``
  Miura rows of ``setting.unit_width`` mm upwards from ``tsp``, the first segment's
  crease a valley when ``setting.entry_flag`` is 1, else a mountain; it is drawn
  here as PyGamiX draws it (:mod:`.pygamix_kl`: the joints, their legs clipped where
  they cross, the rows' ends at 1.57 rad), its panels numbered in PyGamiX's order.
  A design of ``"kl"`` pieces only may leave a panel out of ``util.hole_axis``: its
  hole is then ``contributions[u]`` times the panel's corners (their mean without
  weights). As in PyGamiX, ``add_width`` true starts the piece's rows
  ``copy_time * unit_width`` above ``tsp``, and ``setting.enable_connection`` true
  lengthens its first and last segments by ``setting.con_left_length`` and
  ``con_right_length`` (the connection flaps; their extra holes are not read). A
  turn of 180 degrees and pieces of other types are refused, naming them.

Line types: 0 valley, 1 mountain, 2 border, 3 cut, 6 facet (``F``); 4 (a hole's
outline) and 5 (a hinge hole) are refused, naming the line. A panel's first hole
becomes its :class:`~origami_cad.pattern.model.Hole`. The tendons, anchors and
fixed panels travel in ``metadata["tendons"]`` (plain data, panels as face indices
of the pattern, points in mm at the pattern's size ``metadata["tendons"]["size"]``);
:func:`origami_cad.strings.tendons.route_from_pattern` turns them into a route. A
``.json`` file in the FOLD format is read as FOLD.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad._toml import check_finite, printable
from origami_cad.errors import PatternError
from origami_cad.pattern.formats.pygamix_kl import KLRows, kl_rows
from origami_cad.pattern.model import CreasePattern, Hole

__all__ = ["LINE_TYPES", "read_pygamix"]

#: PyGamiX line type -> FOLD assignment (None: refused, with the reason).
LINE_TYPES: dict[int, str | None] = {0: "V", 1: "M", 2: "B", 3: "C", 4: None, 5: None, 6: "F"}
_REFUSED = {4: "a hole's outline", 5: "a hinge hole"}
#: Hole diameter when the file gives none, mm.
DEFAULT_HOLE_DIAMETER = 2.0
_MAX_ITEMS = 200_000
#: Most rows (``setting.copy_time``) of a generated piece.
_MAX_COPIES = 1000


def _fail(where: str, what: str) -> PatternError:
    return PatternError(f"{where}: {what}")


def _number(v: Any, where: str, key: str) -> float:
    if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
        raise _fail(where, f"{key}: {printable(repr(v), 40)} is not a finite number")
    return float(v)


def _points(items: Any, where: str, key: str, dims: tuple[int, ...] = (2, 3)) -> np.ndarray:
    if not isinstance(items, list) or len(items) > _MAX_ITEMS:
        raise _fail(where, f"{key} must be a list (of at most {_MAX_ITEMS} points)")
    out = []
    for i, p in enumerate(items):
        if not isinstance(p, list) or len(p) not in dims:
            sizes = " or ".join(map(str, dims))
            raise _fail(where, f"{key}[{i}] must be a point of {sizes} numbers")
        out.append([_number(v, where, f"{key}[{i}]") for v in p[:2]])
    return np.array(out, dtype=float).reshape(-1, 2)


def _index(v: Any, where: str, key: str, n: int, low: int = 0) -> int:
    if isinstance(v, bool) or not isinstance(v, int) or not low <= v < n:
        raise _fail(where, f"{key}: {printable(repr(v), 40)} is not an index in [{low}, {n})")
    return int(v)


def _lines(data: dict, where: str, lines_key: str, types: list[int]) -> tuple[np.ndarray, list]:
    lines = data.get(lines_key)
    if not isinstance(lines, list) or not lines or len(lines) > _MAX_ITEMS:
        raise _fail(where, f"{lines_key} must be a non-empty list of segments")
    if len(types) != len(lines):
        raise _fail(where, f"{len(types)} line types for {len(lines)} lines")
    ends = np.zeros((len(lines), 2, 2))
    for i, seg in enumerate(lines):
        if not isinstance(seg, list) or len(seg) != 2:
            raise _fail(where, f"{lines_key}[{i}] must be two points")
        ends[i] = _points(seg, where, f"{lines_key}[{i}]")
    letters = []
    for i, t in enumerate(types):
        if isinstance(t, bool) or t not in LINE_TYPES:
            raise _fail(where, f"line {i}: unknown line type {printable(repr(t), 20)} (0-6)")
        if LINE_TYPES[t] is None:
            raise _fail(where, f"line {i} is {_REFUSED[t]} (type {t}), which is not supported")
        letters.append(LINE_TYPES[t])
    return ends, letters


def _types(features: Any, where: str) -> list[int]:
    if not isinstance(features, list):
        raise _fail(where, "line_features must be a list")
    out = []
    for i, f in enumerate(features):
        if not isinstance(f, dict) or "type" not in f:
            raise _fail(where, f"line_features[{i}] has no type")
        out.append(f["type"])
    return out


def _pattern(ends: np.ndarray, letters: list[str], where: str) -> CreasePattern:
    verts = ends.reshape(-1, 2)
    edges = np.arange(len(verts)).reshape(-1, 2)
    try:  # PyGamiX's points coincide to its own rounding (1e-7 mm): merge within 1e-4 mm
        return CreasePattern(verts, edges, letters, tolerance=1e-4)
    except PatternError as exc:
        raise _fail(where, str(exc)) from None


def _description(data: dict, where: str) -> tuple[CreasePattern, np.ndarray, np.ndarray, float]:
    """The pattern, each panel's face, each panel's hole (P, 2) mm, the hole diameter."""
    ends, letters = _lines(data, where, "lines", _types(data.get("line_features"), where))
    cp = _pattern(ends, letters, where)
    units = data.get("units")
    if not isinstance(units, list):
        raise _fail(where, "units must be a list of panel polygons")
    weights = data.get("contributions")
    if not isinstance(weights, list) or len(weights) != len(units):
        raise _fail(where, f"contributions must hold one list per panel ({len(units)})")
    holes = np.zeros((len(units), 2))
    centres = np.zeros((len(units), 2))
    for u, poly in enumerate(units):
        corners = _points(poly, where, f"units[{u}]")
        w = weights[u]
        if not isinstance(w, list) or len(w) != len(corners):
            raise _fail(where, f"contributions[{u}] must hold one weight per corner of panel {u}")
        wv = np.array([_number(v, where, f"contributions[{u}]") for v in w])
        holes[u] = wv @ corners if wv.sum() > 0 else corners.mean(axis=0)
        centres[u] = corners.mean(axis=0)
    return cp, _faces(cp, centres, where), holes, DEFAULT_HOLE_DIAMETER


def _kl_piece(piece: dict, k: int, setting: dict, where: str) -> KLRows:
    """A ``"kl"`` piece drawn as PyGamiX draws it (:mod:`.pygamix_kl`), mm."""
    key = f"origami[{k}]"
    entries = piece.get("data")
    if not isinstance(entries, list) or not entries or len(entries) > _MAX_ITEMS:
        raise _fail(where, f"{key}.data must be a non-empty list of [length, angle]")
    rows = []
    for i, e in enumerate(entries):
        if not isinstance(e, list) or len(e) != 2:
            raise _fail(where, f"{key}.data[{i}] must be [length, angle] (mm, radians)")
        length, angle = (_number(v, where, f"{key}.data[{i}]") for v in e)
        if length <= 0:
            raise _fail(where, f"{key}.data[{i}]: the length must be > 0 mm")
        if rows and abs(math.cos((angle - rows[-1][1]) / 2)) < 1e-9:
            raise _fail(where, f"{key}.data[{i}] turns by 180 degrees, which is not supported")
        rows.append([length, angle])
    tsp = _points([piece.get("tsp", [0, 0])], where, f"{key}.tsp")[0]
    width = _number(setting.get("unit_width"), where, "setting.unit_width")
    copies = setting.get("copy_time", 1)
    flag = setting.get("entry_flag", 0)
    if width <= 0:
        raise _fail(where, "setting.unit_width must be > 0 mm")
    _index(copies, where, "setting.copy_time", _MAX_COPIES + 1, low=1)
    _index(flag, where, "setting.entry_flag", 2)
    if len(rows) * copies > _MAX_ITEMS:
        raise _fail(where, f"{key}: more than {_MAX_ITEMS} segments in all rows")
    if _flag(piece.get("add_width", False), where, f"{key}.add_width"):
        tsp = tsp + np.array([0.0, copies * width])  # PyGamiX starts such a piece above its rows
    if _flag(setting.get("enable_connection", False), where, "setting.enable_connection"):
        # connection flaps: the first and last segments longer, at their own angles
        left = _number(setting.get("con_left_length"), where, "setting.con_left_length")
        right = _number(setting.get("con_right_length"), where, "setting.con_right_length")
        if left < 0 or right < 0:
            raise _fail(where, "setting.con_left_length and con_right_length must be >= 0 mm")
        rows = [[left, rows[0][1]], *rows, [right, rows[-1][1]]]
    return kl_rows(rows, (float(tsp[0]), float(tsp[1])), width, copies, flag == 1)


def _flag(v: Any, where: str, key: str) -> bool:
    if not isinstance(v, bool):
        raise _fail(where, f"{key}: {printable(repr(v), 20)} is neither true nor false")
    return v


def _pieces(data: dict, where: str) -> tuple[CreasePattern, np.ndarray | None]:
    """The pattern of all pieces; the panels' corners when all are generated, else None."""
    pieces = data.get("origami")
    if not isinstance(pieces, list) or not pieces:
        raise _fail(where, "origami must be a non-empty list of pieces")
    setting = data.get("setting") or {}
    if not isinstance(setting, dict):
        raise _fail(where, "setting must be an object")
    all_ends, all_letters, panels = [], [], []
    for k, piece in enumerate(pieces):
        kind = piece.get("type") if isinstance(piece, dict) else None
        if kind == "kl":
            rows = _kl_piece(piece, k, setting, where)
            all_ends.append(rows.ends)
            all_letters += rows.letters
            panels.append(rows.panels)
            continue
        if kind != "dxf":
            raise _fail(
                where,
                f"origami[{k}] is a {printable(repr(kind), 20)} piece, which is not supported "
                "(only 'dxf' and 'kl' pieces are read)",
            )
        body = piece.get("data")
        if not isinstance(body, dict) or not isinstance(body.get("lines_type"), list):
            raise _fail(where, f"origami[{k}].data must hold lines and lines_type")
        ends, letters = _lines(body, where, "lines", body["lines_type"])
        shift = _points([piece.get("tsp", [0, 0])], where, f"origami[{k}].tsp")[0]
        all_ends.append(ends + shift)
        all_letters += letters
    cp = _pattern(np.concatenate(all_ends), all_letters, where)
    return cp, np.concatenate(panels) if len(panels) == len(pieces) else None


def _kl_holes(
    first: dict[int, np.ndarray], data: dict, panels: np.ndarray, where: str
) -> np.ndarray:
    """Each generated panel's hole: its ``util.hole_axis`` point, else the weighted sum of
    its corners (``contributions``), else their mean, mm."""
    n = len(panels)
    beyond = [u for u in first if u >= n]
    if beyond:
        raise _fail(where, f"util.hole_axis places a hole on panel {beyond[0]} of {n}")
    weights = data.get("contributions")
    holes = np.zeros((n, 2))
    for u in range(n):
        if u in first:
            holes[u] = first[u]
            continue
        w = weights[u] if isinstance(weights, list) and len(weights) == n else None
        if isinstance(w, list) and len(w) == 4:
            wv = np.array([_number(v, where, f"contributions[{u}]") for v in w])
            holes[u] = wv @ panels[u] if wv.sum() > 0 else panels[u].mean(axis=0)
        else:
            holes[u] = panels[u].mean(axis=0)
    return holes


def _editable(data: dict, where: str) -> tuple[CreasePattern, np.ndarray, np.ndarray, float]:
    cp, panels = _pieces(data, where)
    axis = (data.get("util") or {}).get("hole_axis", [])
    if not isinstance(axis, list):
        raise _fail(where, "util.hole_axis must be a list")
    first: dict[int, np.ndarray] = {}
    for i, entry in enumerate(axis):
        if not isinstance(entry, list) or len(entry) < 2:
            raise _fail(where, f"util.hole_axis[{i}] must be [point, panel, enabled]")
        point = _points([entry[0]], where, f"util.hole_axis[{i}]")[0]
        panel = _index(entry[1], where, f"util.hole_axis[{i}] panel", _MAX_ITEMS)
        first.setdefault(panel, point)
    if panels is not None:
        holes = _kl_holes(first, data, panels, where)
    else:
        n = max(first, default=-1) + 1
        missing = [u for u in range(n) if u not in first]
        if missing:
            raise _fail(where, f"util.hole_axis places no hole on panel {missing[0]}")
        holes = np.array([first[u] for u in range(n)]).reshape(-1, 2)
    size = (data.get("setting") or {}).get("hole_size", DEFAULT_HOLE_DIAMETER)
    diameter = _number(size, where, "setting.hole_size")
    if diameter <= 0:
        raise _fail(where, "setting.hole_size must be > 0 mm")
    return cp, _faces(cp, holes, where), holes, diameter


def _faces(cp: CreasePattern, points: np.ndarray, where: str) -> np.ndarray:
    faces = cp.faces_of_points(points) if len(points) else np.zeros(0, dtype=int)
    bad = np.flatnonzero(faces < 0)
    if bad.size:
        x, y = points[bad[0]]
        raise _fail(where, f"panel {bad[0]} (at ({x:.4g}, {y:.4g}) mm) lies on no face")
    return np.asarray(faces, dtype=int)


def _tendons(data: dict, where: str, faces: np.ndarray, holes: np.ndarray) -> dict[str, Any]:
    """The strings, anchors and fixed panels as plain data (faces of the pattern, mm)."""
    n_panels = len(faces)
    cand = data.get("P_candidators") or {"points": [], "connections": []}
    if not isinstance(cand, dict):
        raise _fail(where, "P_candidators must be an object with points and connections")
    anchors = cand.get("points", [])
    conns = cand.get("connections", [])
    if not isinstance(anchors, list) or not isinstance(conns, list) or len(anchors) != len(conns):
        raise _fail(where, "P_candidators: one connection per point")
    points = []
    for i, p in enumerate(anchors):
        if not isinstance(p, list) or len(p) != 3:
            raise _fail(where, f"P_candidators.points[{i}] must be a 3-D point")
        xyz = [_number(v, where, f"P_candidators.points[{i}]") for v in p]
        panel = _index(conns[i], where, f"P_candidators.connections[{i}]", n_panels, low=-1)
        points.append({"point": xyz, "face": -1 if panel < 0 else int(faces[panel])})
    strings = data.get("strings") or {"type": [], "id": [], "reverse": []}
    if not isinstance(strings, dict):
        raise _fail(where, "strings must be an object with type, id and reverse lists")
    kinds, ids, sides = (strings.get(k, []) for k in ("type", "id", "reverse"))
    if not all(isinstance(v, list) for v in (kinds, ids, sides)) or not (
        len(kinds) == len(ids) == len(sides)
    ):
        raise _fail(where, "strings: type, id and reverse must be lists of the same length")
    out = []
    for s, (kk, ii, rr) in enumerate(zip(kinds, ids, sides, strict=True)):
        if not all(isinstance(v, list) for v in (kk, ii, rr)) or not len(kk) == len(ii) == len(rr):
            raise _fail(where, f"strings[{s}]: type, id and reverse differ in length")
        stops = []
        for j, (k, i, r) in enumerate(zip(kk, ii, rr, strict=True)):
            key = f"strings[{s}][{j}]"
            if r not in (-1, 1) or isinstance(r, bool):
                raise _fail(where, f"{key}: reverse must be -1 (below) or 1 (above)")
            if k == "A":
                stops.append(("anchor", _index(i, where, key, len(points)), int(r)))
            elif k == "B":
                u = _index(i, where, key, n_panels)
                stops.append(("panel", int(faces[u]), int(r), holes[u].tolist()))
            else:
                raise _fail(where, f"{key}: type {printable(repr(k), 10)} is neither 'A' nor 'B'")
        out.append(stops)
    fixed = data.get("fix", [])
    if not isinstance(fixed, list):
        raise _fail(where, "fix must be a list of panels")
    fix = [int(faces[_index(u, where, f"fix[{j}]", n_panels)]) for j, u in enumerate(fixed)]
    return {"anchors": points, "strings": out, "fixed": fix}


def read_pygamix(path: str | os.PathLike[str], mm_per_unit: float | None = None) -> CreasePattern:
    """Read a PyGamiX design (``.json``, system description or editable design), mm.

    ``mm_per_unit`` scales the file's coordinates (PyGamiX draws in mm: default 1).
    The holes become the pattern's :class:`Hole` s, the tendons, anchors and fixed
    panels its ``metadata["tendons"]`` (see the module docstring). A JSON file in
    the FOLD format is read by the FOLD reader. Raises :class:`PatternError` naming
    the file, the key and what is wrong or not supported.
    """
    p = Path(path)
    where = printable(str(p), 300)
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise _fail(where, f"cannot read: {exc}") from None
    try:
        data = json.loads(text)
    except (json.JSONDecodeError, RecursionError) as exc:
        raise _fail(where, f"not valid JSON: {exc}") from None
    check_finite(data, where, PatternError)  # NaN, 1e999: even in a key not read
    if not isinstance(data, dict):
        raise _fail(where, "a PyGamiX design is a JSON object")
    if "vertices_coords" in data or "file_spec" in data or "file_frames" in data:
        from origami_cad.pattern.formats.fold import read_fold

        return read_fold(p, mm_per_unit)
    if "origami" in data:
        cp, faces, holes, diameter = _editable(data, where)
    elif "lines" in data and "line_features" in data:
        cp, faces, holes, diameter = _description(data, where)
    else:
        raise _fail(where, "not a PyGamiX design (origami, or lines and line_features) nor FOLD")
    tendons = _tendons(data, where, faces, holes)
    placed = [Hole(float(x), float(y), diameter) for x, y in holes]
    cp = cp.with_holes(placed).with_metadata(
        tendons={**tendons, "size": cp.size}, creator="PyGamiX", title=p.stem
    )
    if mm_per_unit is not None and mm_per_unit != 1.0:
        cp = cp.scaled(mm_per_unit)
    return cp


readers = {".json": read_pygamix}
writers: dict[str, Any] = {}
