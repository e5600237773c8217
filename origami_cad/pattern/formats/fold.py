"""FOLD 1.2 reader and writer (``.fold``, JSON).

Writes ``file_spec``, ``file_creator``, ``frame_unit: "mm"``, ``vertices_coords``,
``edges_vertices``, ``edges_assignment``, ``edges_foldAngle`` (degrees, valley
positive) and always ``faces_vertices`` (Origami Simulator refuses files
without it). Holes and panel labels ride along under namespaced keys
``faces_origami_cad:holes`` (per face, a list of ``[x, y, diameter]``) and
``faces_origami_cad:labels``. Folded states go in ``file_frames`` (see
:func:`write_fold` ``frames``).

Reading accepts files of other tools: 2D or 3D coordinates (a 3D file takes
the key frame if it is flat, else the first flat frame, else the first folded form
with faces, unfolded: :mod:`origami_cad.pattern.unfold`),
missing faces (computed), the old key ``edges_foldAngles``, and a missing
``edges_assignment`` (taken from the sign of the fold angles, else ``U``).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad._args import Arg, brief_value, checked
from origami_cad._fileio import atomic_write
from origami_cad._toml import check_finite, input_file, parse_file
from origami_cad.errors import PatternError
from origami_cad.pattern.model import (
    MAX_COORDINATE,
    MAX_EDGES,
    MAX_VERTICES,
    CreasePattern,
    Hole,
    Problem,
    Severity,
    default_fold_angles,
    printable,
)
from origami_cad.pattern.planar import Tolerance, import_tolerance

__all__ = [
    "FoldFrame",
    "fold_dict",
    "folded_frame",
    "read_fold",
    "read_fold_frames",
    "write_fold",
]

NAMESPACE = "origami_cad"
_HOLES = f"faces_{NAMESPACE}:holes"
_LABELS = f"faces_{NAMESPACE}:labels"


def _version() -> str:
    from origami_cad import __version__

    return __version__


class FoldFrame(dict):
    """A folded state to store in ``file_frames``: a dict of FOLD frame keys.

    Build one with :func:`folded_frame`; any FOLD frame keys are allowed.
    """


def folded_frame(
    coords: np.ndarray, fold_angles_deg: np.ndarray | None = None, title: str = ""
) -> FoldFrame:
    """A ``foldedForm`` frame with 3D vertex coordinates (mm) and fold angles (degrees).

    The frame has the same vertex and edge indexing as the key frame and
    inherits its edges and faces (``frame_inherit``).
    """
    coords = np.asarray(coords, dtype=float)
    frame = FoldFrame(
        frame_classes=["foldedForm"],
        frame_attributes=["3D"],
        frame_parent=0,
        frame_inherit=True,
        frame_unit="mm",
        vertices_coords=_round(coords).tolist(),
    )
    if title:
        frame["frame_title"] = title
    if fold_angles_deg is not None:
        frame["edges_foldAngle"] = _round(np.asarray(fold_angles_deg, float)).tolist()
    return frame


def _round(a: np.ndarray) -> np.ndarray:
    # 12 significant digits keep 1e-9 mm on patterns up to a metre and stay readable
    return np.round(a, 12) + 0.0


def fold_dict(cp: CreasePattern, frames: Sequence[dict[str, Any]] = ()) -> dict[str, Any]:
    """The FOLD object (a JSON-ready dict) of a crease pattern and optional folded frames."""
    data: dict[str, Any] = {
        "file_spec": 1.2,
        "file_creator": f"origami_cad {_version()}",
        "file_classes": ["singleModel"] if not frames else ["animation"],
    }
    if cp.title:
        data["file_title"] = cp.title
    data.update(
        {
            "frame_classes": ["creasePattern"],
            "frame_attributes": ["2D"],
            "frame_unit": "mm",
            "vertices_coords": _round(cp.vertices).tolist(),
            "edges_vertices": cp.edges.tolist(),
            "edges_assignment": cp.assignments.tolist(),
            "edges_foldAngle": _round(cp.fold_angles).tolist(),
            "faces_vertices": [f.tolist() for f in cp.faces],
        }
    )
    if any(lbl != f"f{i}" for i, lbl in enumerate(cp.face_labels)):
        data[_LABELS] = list(cp.face_labels)
    if cp.holes:
        per_face: list[list[list[float]]] = [[] for _ in cp.faces]
        for h in cp.holes:
            f = cp.face_of_point(h.x, h.y)
            if f < 0:
                raise PatternError(f"hole at ({h.x:g}, {h.y:g}) mm is not on any panel")
            per_face[f].append([h.x, h.y, h.diameter])
        data[_HOLES] = per_face
    if isinstance(frames, str | bytes | Mapping) or not hasattr(frames, "__iter__"):
        raise PatternError(f"frames must be a list of dicts (FOLD frames), got {frames!r:.60}")
    frames = list(frames)
    if not all(isinstance(f, Mapping) for f in frames):
        raise PatternError("frames must be a list of dicts (FOLD frames)")
    if frames:
        data["file_frames"] = [dict(f) for f in frames]
    return data


@checked(
    PatternError,
    cp=Arg("object", types=(CreasePattern,), optional=False),
    path=Arg("path", optional=False),
)
def write_fold(
    cp: CreasePattern, path: str | os.PathLike[str], frames: Sequence[dict[str, Any]] = ()
) -> Path:
    """Write ``cp`` (and optional folded frames) to a FOLD file atomically.

    Parameters
    ----------
    cp : CreasePattern
        The crease pattern (the key frame, 2D, mm).
    path : path-like
        Output ``.fold`` file.
    frames : sequence of dict
        Extra frames for ``file_frames`` (e.g. from :func:`folded_frame`).
    """
    if not isinstance(frames, list | tuple) or not all(isinstance(f, dict) for f in frames):
        raise PatternError(
            f"write_fold: frames: expected a list of dicts, got {brief_value(frames)}"
        )
    data = fold_dict(cp, frames)
    try:  # FOLD is JSON: no NaN or infinity, which no reader (ours included) accepts
        text = json.dumps(data, indent=1, allow_nan=False)
    except ValueError:
        raise PatternError(
            f"{path}: a frame holds NaN or an infinite number; FOLD (JSON) cannot hold it"
        ) from None
    except TypeError as exc:
        raise PatternError(f"{path}: a frame holds a value FOLD cannot hold ({exc})") from None
    with atomic_write(path, "w", encoding="utf-8") as fh:
        fh.write(text + "\n")
    return Path(path)


class _DuplicateKey(Exception):
    """A JSON object names one key twice, with different values."""


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """The object of ``pairs``; :class:`_DuplicateKey` when a key comes twice with
    different values (JSON keeps the last silently; which one is meant?)."""
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out and out[key] != value:
            raise _DuplicateKey(key)
        out[key] = value
    return out


def _load(path: str | os.PathLike[str]) -> dict[str, Any]:
    try:
        return _load_unique(path)
    except _DuplicateKey as exc:
        _, name = input_file(path, PatternError)
        raise PatternError(
            f"{name}: the key {printable(str(exc.args[0]), 80)!r} is given twice in one JSON "
            "object, with different values (which one is meant?)"
        ) from None


def _load_unique(path: str | os.PathLike[str]) -> dict[str, Any]:
    data, name = parse_file(
        path,
        lambda p: json.loads(p.read_text(encoding="utf-8"), object_pairs_hook=_unique_keys),
        fmt="JSON",
        error=PatternError,
        not_text="not a text file (FOLD is JSON)",
        too_deep="JSON nested too deeply to read",
    )
    if not isinstance(data, dict):
        raise PatternError(
            f"{name}: a FOLD file must hold a JSON object, not {type(data).__name__}"
        )
    check_finite(data, name, PatternError)  # NaN, 1e999: even in a key not read
    return data


def _json_type(value: Any) -> str:
    if value is None:
        return "null"
    return {bool: "a boolean", int: "a number", float: "a number", str: "a string"}.get(
        type(value), "an array" if isinstance(value, list) else "an object"
    )


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _list(frame: dict[str, Any], key: str, where: str) -> list[Any]:
    value = frame[key]
    if not isinstance(value, list):
        raise PatternError(f"{where}: {key!r} must be an array, not {_json_type(value)}")
    return value


def _index(v: Any, key: str, k: int, where: str) -> int:
    """A vertex index: a whole JSON number (``3`` or ``3.0``), never a boolean."""
    if isinstance(v, bool) or not isinstance(v, int | float):
        raise PatternError(f"{where}: {key}[{k}] holds {_json_type(v)}, not a vertex index")
    if isinstance(v, float) and not (math.isfinite(v) and v.is_integer()):
        raise PatternError(f"{where}: {key}[{k}] holds {v!r}, not a whole vertex index")
    return int(v)


def _coords(frame: dict[str, Any], where: str, scale: float) -> np.ndarray:
    """``vertices_coords`` checked: [x, y] or [x, y, z] numbers, finite, bounded (mm)."""
    raw = _list(frame, "vertices_coords", where)
    if len(raw) > MAX_VERTICES:
        raise PatternError(
            f"{where}: vertices_coords has {len(raw):,} vertices, more than the limit of "
            f"{MAX_VERTICES:,} (MAX_VERTICES)"
        )
    dims = None
    for k, c in enumerate(raw):
        if not isinstance(c, list) or len(c) not in (2, 3):
            raise PatternError(
                f"{where}: vertices_coords[{k}] must be [x, y] or [x, y, z], got "
                f"{_json_type(c) if not isinstance(c, list) else f'{len(c)} values'}"
            )
        if dims is None:
            dims = len(c)
        elif len(c) != dims:
            raise PatternError(
                f"{where}: vertices_coords[{k}] has {len(c)} coordinates, the first vertex {dims}"
            )
        for v in c:
            if not _is_number(v) or not math.isfinite(v):
                shown = repr(v) if _is_number(v) else _json_type(v)
                raise PatternError(
                    f"{where}: vertices_coords[{k}] holds {shown}, not a finite number"
                )
    if not raw:
        return np.zeros((0, 2))
    with np.errstate(over="ignore"):  # an overflow is infinite: refused just below
        verts = np.asarray(raw, dtype=float) * scale
    big = np.abs(verts) > MAX_COORDINATE
    if big.any():
        k = int(np.flatnonzero(big.any(axis=1))[0])
        raise PatternError(
            f"{where}: vertices_coords[{k}] lies farther than {MAX_COORDINATE:g} mm from the "
            "origin; coordinates are limited to that magnitude"
        )
    return verts


def _index_rows(
    frame: dict[str, Any], key: str, where: str, n_vertices: int, width: int | None
) -> list[list[int]]:
    """Rows of vertex indices (``edges_vertices``: 2 each; ``faces_vertices``: any)."""
    rows = []
    given = _list(frame, key, where)
    if len(given) > MAX_EDGES:
        what = "edges" if key == "edges_vertices" else "faces"
        raise PatternError(
            f"{where}: {key} has {len(given):,} {what}, more than the limit of {MAX_EDGES:,} "
            "(MAX_EDGES)"
        )
    for k, row in enumerate(given):
        if not isinstance(row, list) or (width is not None and len(row) != width):
            raise PatternError(
                f"{where}: {key}[{k}] must be an array of {width or 'the'} vertex indices"
            )
        idx = [_index(v, key, k, where) for v in row]
        if any(not 0 <= i < n_vertices for i in idx):
            raise PatternError(
                f"{where}: {key}[{k}] = {idx} refers to vertex "
                f"{next(i for i in idx if not 0 <= i < n_vertices)}, which does not exist "
                f"(there are {n_vertices} vertices)"
            )
        rows.append(idx)
    return rows


def _parent(fr: dict[str, Any], n_before: int, k: int) -> int:
    parent = fr.get("frame_parent", 0)
    if isinstance(parent, bool) or not isinstance(parent, int | float):
        raise PatternError(f"file_frames[{k}]: frame_parent holds {_json_type(parent)}")
    if isinstance(parent, float) and not (math.isfinite(parent) and parent.is_integer()):
        raise PatternError(f"file_frames[{k}]: frame_parent {parent!r} is not a frame index")
    parent = int(parent)
    if not 0 <= parent < n_before:
        raise PatternError(f"file_frames[{k}]: frame_parent {parent} does not exist")
    return parent


def _frames(data: dict[str, Any]) -> list[dict[str, Any]]:
    """All frames with inheritance resolved (frame 0 is the key frame)."""
    base = {k: v for k, v in data.items() if k != "file_frames"}
    raw = data.get("file_frames")
    if raw is None:
        raw = []
    if not isinstance(raw, list):
        raise PatternError(f"file_frames must be an array of frames, not {_json_type(raw)}")
    out = [base]
    for k, fr in enumerate(raw):
        if not isinstance(fr, dict):
            raise PatternError(f"file_frames[{k}] must be a JSON object, not {_json_type(fr)}")
        inherit = fr.get("frame_inherit", False)
        if not isinstance(inherit, bool):
            raise PatternError(
                f"file_frames[{k}]: frame_inherit must be true or false, not {_json_type(inherit)}"
            )
        if inherit:
            merged = {**out[_parent(fr, len(out), k)], **fr}
        else:
            merged = dict(fr)
        out.append(merged)
    return out


def _key(frame: dict[str, Any], name: str, where: str, required: bool = True) -> Any:
    if name in frame:
        return frame[name]
    if name == "edges_foldAngle" and "edges_foldAngles" in frame:
        return frame["edges_foldAngles"]
    if required:
        raise PatternError(f"{where}: missing key {name!r}")
    return None


def _unit_scale(frame: dict[str, Any], where: str) -> float:
    unit = frame.get("frame_unit", "mm")
    if not isinstance(unit, str):
        raise PatternError(f"{where}: frame_unit must be a string, not {_json_type(unit)}")
    unit = unit.lower()
    scales = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4, "pt": 25.4 / 72, "unit": 1.0}
    if unit not in scales:
        # FOLD allows "unit" (no physical unit); anything else unknown is kept as mm
        raise PatternError(f"{where}: frame_unit {unit!r} is not supported (mm, cm, m, in, pt)")
    return scales[unit]


def _fold_angles(frame: dict[str, Any], where: str, m: int) -> np.ndarray | None:
    key = "edges_foldAngle" if "edges_foldAngle" in frame else "edges_foldAngles"
    if key not in frame:
        return None
    raw = _list(frame, key, where)
    if len(raw) != m:
        raise PatternError(f"{where}: {key} has {len(raw)} entries for {m} edges")
    out = np.full(m, np.nan)
    for k, a in enumerate(raw):
        if a is None:
            continue
        if not _is_number(a) or not math.isfinite(a) or abs(a) > 180 + 1e-9:
            shown = repr(a) if _is_number(a) else _json_type(a)
            raise PatternError(
                f"{where}: {key}[{k}] holds {shown}; fold angles are numbers within "
                "[-180, 180] degrees (or null)"
            )
        out[k] = float(a)
    return out


def _assignments(frame: dict[str, Any], where: str, m: int) -> list[str] | None:
    if "edges_assignment" not in frame:
        return None
    raw = _list(frame, "edges_assignment", where)
    if len(raw) != m:
        raise PatternError(f"{where}: edges_assignment has {len(raw)} entries for {m} edges")
    for k, a in enumerate(raw):
        if not isinstance(a, str):
            raise PatternError(
                f"{where}: edges_assignment[{k}] holds {_json_type(a)}, not a letter "
                "(M V B F U C J)"
            )
    return raw


def _check_signs(frame: dict[str, Any], where: str, assign: list[str], angles: np.ndarray) -> None:
    """PatternError naming the edge whose fold angle has the sign of the other fold
    (FOLD: a mountain folds to a negative angle, a valley to a positive one), or that
    folds a border or flat crease (``B``, ``F``: angle 0)."""
    key = "edges_foldAngle" if "edges_foldAngle" in frame else "edges_foldAngles"
    letters = np.asarray([str(a).upper() for a in assign])
    flat = np.isin(letters, ("B", "F")) & (np.abs(angles) > 1e-6)  # nan: not given
    wrong = ((letters == "M") & (angles > 0)) | ((letters == "V") & (angles < 0)) | flat
    if wrong.any():
        k = int(np.flatnonzero(wrong)[0])
        fold, sign = {"M": ("mountain", "negative"), "V": ("valley", "positive")}.get(
            letters[k], ("border" if letters[k] == "B" else "flat crease", "zero")
        )
        more = f" (and {int(wrong.sum()) - 1} more edges)" if wrong.sum() > 1 else ""
        raise PatternError(
            f"{where}: edge {k}: {key}[{k}] = {angles[k]:g} contradicts edges_assignment[{k}] = "
            f"{printable(str(assign[k]), 8)!r}: a {fold} folds to a {sign} angle{more}"
        )


def _holes(frame: dict[str, Any], where: str) -> list[Hole]:
    if frame.get(_HOLES) is None:
        return []
    holes = []
    for k, face_holes in enumerate(_list(frame, _HOLES, where)):
        if not isinstance(face_holes, list):
            raise PatternError(f"{where}: {_HOLES}[{k}] must be an array of [x, y, diameter]")
        for h in face_holes:
            if not (isinstance(h, list) and len(h) == 3 and all(map(_is_number, h))):
                raise PatternError(
                    f"{where}: {_HOLES}[{k}] holds {_json_type(h)}, not [x, y, diameter]"
                )
            x, y, dia = (float(v) for v in h)
            if not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE for v in (x, y, dia)):
                raise PatternError(f"{where}: {_HOLES}[{k}]: {h!r} is not a finite hole")
            try:
                holes.append(Hole(x, y, dia))
            except PatternError as exc:
                raise PatternError(f"{where}: {_HOLES}[{k}]: {exc}") from None
    return holes


def _labels(frame: dict[str, Any], where: str) -> list[str] | None:
    if frame.get(_LABELS) is None:
        return None
    raw = _list(frame, _LABELS, where)
    for k, lbl in enumerate(raw):
        if not isinstance(lbl, str):
            raise PatternError(f"{where}: {_LABELS}[{k}] holds {_json_type(lbl)}, not a string")
    if len(set(raw)) != len(raw):
        dup = next(lbl for lbl in raw if raw.count(lbl) > 1)
        raise PatternError(f"{where}: {_LABELS}: the label {dup!r} is used twice")
    return raw


def _frame_to_pattern(
    frame: dict[str, Any], where: str, title: str, verts: np.ndarray, tolerance: Tolerance = None
) -> CreasePattern:
    if "edges_vertices" not in frame:
        raise PatternError(f"{where}: missing key 'edges_vertices'")
    e = _index_rows(frame, "edges_vertices", where, len(verts), 2)
    if len(e) == 0:
        raise PatternError(f"{where}: 'edges_vertices' is empty; a crease pattern needs edges")
    angles = _fold_angles(frame, where, len(e))
    assign = _assignments(frame, where, len(e))
    if assign is not None and angles is not None:
        _check_signs(frame, where, assign, angles)
    if assign is None:
        if angles is not None:
            a = np.nan_to_num(angles)
            assign = np.where(a > 0, "V", np.where(a < 0, "M", "U"))
        else:
            assign = "U"
    if angles is not None:  # a null angle: the letter's (+-180 for V/M, else 0)
        letters = np.asarray([str(x).upper() for x in np.broadcast_to(assign, len(e))])
        angles = np.where(np.isnan(angles), default_fold_angles(letters), angles)
    faces = None
    if frame.get("faces_vertices") is not None:
        faces = _index_rows(frame, "faces_vertices", where, len(verts), None)
    labels = _labels(frame, where)
    holes = _holes(frame, where)
    try:
        cp = CreasePattern(
            verts,
            np.asarray(e, dtype=np.int64),
            assign,
            angles,
            faces=faces,
            face_labels=labels if faces is not None else None,
            holes=holes,
            metadata={"title": title} if title else {},
            tolerance=import_tolerance(tolerance),
        )
    except PatternError as exc:
        raise PatternError(f"{where}: {exc}") from None
    return cp


def _is_flat(verts: np.ndarray) -> bool:
    if verts.shape[1] == 2 or len(verts) == 0:
        return True
    z = verts[:, 2]
    return bool(np.ptp(z) <= 1e-9 * max(1.0, float(np.abs(verts).max())))


def read_fold(
    path: str | os.PathLike[str], mm_per_unit: float | None = None, tolerance: Tolerance = None
) -> CreasePattern:
    """Read the crease pattern of a FOLD file.

    ``mm_per_unit`` (millimetres per coordinate unit) replaces what the frame's
    ``frame_unit`` declares (default: the declared unit; mm when none, one mm per
    unit for ``"unit"``); ``metadata["source_unit"]`` says which was used. Vertices
    within ``tolerance`` mm merge (default
    :func:`~origami_cad.pattern.planar.import_tolerance`).

    The key frame is used when it is flat (and not declared a ``foldedForm``);
    otherwise the first such frame of ``file_frames``; otherwise the first folded
    form with ``faces_vertices`` is unfolded, its faces laid flat across their
    shared creases (:func:`origami_cad.pattern.unfold.unfold_faces`), which keeps
    every length; its fold angles become the pattern's. A form that does not
    unfold flat (stretched, torn) is an error naming the vertex.

    Every field used is checked for its JSON type, shape and range (finite
    coordinates within :data:`~origami_cad.pattern.model.MAX_COORDINATE` mm,
    whole vertex indices that exist, fold angles within [-180, 180] degrees);
    a wrong one is a :class:`PatternError` naming the file, frame and key.
    """
    data = _load(path)
    name = printable(str(path), 300)
    try:
        frames = _frames(data)
    except PatternError as exc:
        raise PatternError(f"{name}: {exc}") from None
    title = data.get("file_title", "")
    if title is None:
        title = ""
    if not isinstance(title, str):
        raise PatternError(f"{name}: file_title must be a string, not {_json_type(title)}")
    forms = []
    for i, frame in enumerate(frames):
        if "vertices_coords" not in frame and i == 0 and len(frames) > 1:
            continue
        where = f"{name}" if i == 0 else f"{name} (file_frames[{i - 1}])"
        if i == 0 and "edges_vertices" not in frame and "edges_foldAngles" not in frame:
            raise PatternError(f"{name}: missing key 'edges_vertices' (the file has no edges)")
        _key(frame, "vertices_coords", where)
        scale = _unit_scale(frame, where) if mm_per_unit is None else float(mm_per_unit)
        verts = _coords(frame, where, scale)
        unit = "mm (no frame_unit)"
        if "frame_unit" in frame:
            unit = f"frame_unit {frame['frame_unit']!r}"
        if mm_per_unit is not None:
            unit = f"{scale:g} mm per unit (given)"
        if _is_flat(verts) and not _is_folded_form(frame):
            cp = _frame_to_pattern(frame, where, title, verts, tolerance)
            return cp.with_metadata(source_unit=printable(unit, 80))
        if frame.get("faces_vertices") is not None and "edges_vertices" in frame:
            forms.append((frame, where, verts, unit))
    if not forms:
        raise PatternError(
            f"{name}: no frame is flat and no folded form has faces_vertices to unfold: "
            "the file holds no crease pattern"
        )
    frame, where, verts, unit = forms[0]
    cp = _unfolded_pattern(frame, where, title, verts, tolerance)
    return cp.with_metadata(source_unit=printable(unit, 80))


def _is_folded_form(frame: dict[str, Any]) -> bool:
    """Whether the frame says it is a folded state (``frame_classes`` ``foldedForm``)
    and not also a crease pattern: a form folded flat is flat but no crease pattern."""
    classes = frame.get("frame_classes")
    if not isinstance(classes, list):
        return False
    return "foldedForm" in classes and "creasePattern" not in classes


def _unfolded_pattern(
    frame: dict[str, Any], where: str, title: str, verts: np.ndarray, tolerance: Tolerance = None
) -> CreasePattern:
    """The crease pattern of a folded-form frame, its faces laid flat (:mod:`.unfold`).

    The form's fold angles become the pattern's (unless the file gives its own) and,
    without ``edges_assignment``, its assignments: B on edges of one face, V or M by
    the angle's sign, F where the faces are coplanar, U where the geometry cannot tell
    (folded flat). Faces listed clockwise seen from the top (their valleys measure
    negative) are laid out mirrored, so that the pattern is seen from its top.
    """
    from origami_cad.pattern.unfold import (
        counter_clockwise,
        faces_per_edge,
        fold_angles_of_form,
        unfold_faces,
    )

    faces = _index_rows(frame, "faces_vertices", where, len(verts), None)
    edges = np.asarray(_index_rows(frame, "edges_vertices", where, len(verts), 2), dtype=int)
    try:
        flat = unfold_faces(verts, faces)
    except PatternError as exc:
        raise PatternError(f"{where}: {exc}") from None
    measured = fold_angles_of_form(verts, faces, edges.reshape(-1, 2))
    assign = _assignments(frame, where, len(edges))
    sides = faces_per_edge(faces, edges)
    if assign is None:
        assign = np.where(
            sides < 2,
            "B",
            np.where(
                np.isnan(measured),
                "U",
                np.where(measured > 1e-6, "V", np.where(measured < -1e-6, "M", "F")),
            ),
        ).tolist()
    sense = np.array([{"V": 1.0, "M": -1.0}.get(a, 0.0) for a in assign])
    known = np.isfinite(measured) & (sense != 0) & (np.abs(measured) > 1e-6)
    if known.any() and np.sum(np.sign(measured[known]) != sense[known]) > known.sum() / 2:
        flat[:, 0] *= -1.0  # seen from below: mirror, and the measured senses turn over
        measured = -measured
    faces = counter_clockwise(flat, faces)  # seen from the top
    flat_folded = np.isnan(measured) & (sense != 0) & (sides == 2)
    measured[flat_folded] = 180.0 * sense[flat_folded]
    measured[np.sign(measured) != sense] = np.nan  # only angles that agree with the letters
    given = {"edges_assignment": list(assign), "faces_vertices": faces}
    if "edges_foldAngle" not in frame and "edges_foldAngles" not in frame:
        given["edges_foldAngle"] = [None if np.isnan(a) else float(a) for a in measured]
    cp = _frame_to_pattern({**frame, **given}, where, title, flat, tolerance)
    note = Problem(
        "unfolded",
        f"{where}: the file holds a folded form only; its {len(faces)} faces were laid "
        "flat to recover the crease pattern",
        severity=Severity.INFO,
    )
    out = cp.with_metadata(unfolded=True)
    out.notes = (*cp.notes, note)
    return out


def read_fold_frames(path: str | os.PathLike[str]) -> list[np.ndarray]:
    """Vertex coordinates (mm, shape (n, 3)) of every frame of a FOLD file, key frame first."""
    data = _load(path)
    name = printable(str(path), 300)
    out = []
    try:
        frames = _frames(data)
    except PatternError as exc:
        raise PatternError(f"{name}: {exc}") from None
    for i, frame in enumerate(frames):
        where = f"{name}" if i == 0 else f"{name} (file_frames[{i - 1}])"
        scale = _unit_scale(frame, where)
        if "vertices_coords" not in frame:
            out.append(np.asarray([], dtype=float) * scale)
            continue
        c = _coords(frame, where, scale)
        if c.shape[1] == 2:
            c = np.column_stack([c, np.zeros(len(c))])
        out.append(c)
    return out


# the registry entries of this format, merged by :mod:`origami_cad.pattern.formats`:
# a reader is ``read(path, mm_per_unit) -> CreasePattern``, a writer ``write(cp, path) -> Path``
readers = {".fold": read_fold}
writers = {".fold": write_fold}
