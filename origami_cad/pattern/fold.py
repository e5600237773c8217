"""FOLD 1.2 reader and writer (``.fold``, JSON).

Writes ``file_spec``, ``file_creator``, ``frame_unit: "mm"``, ``vertices_coords``,
``edges_vertices``, ``edges_assignment``, ``edges_foldAngle`` (degrees, valley
positive) and always ``faces_vertices`` (Origami Simulator refuses files
without it). Holes and panel labels ride along under namespaced keys
``faces_origami_cad:holes`` (per face, a list of ``[x, y, diameter]``) and
``faces_origami_cad:labels``. Folded states go in ``file_frames`` (see
:func:`write_fold` ``frames``).

Reading accepts files of other tools: 2D or 3D coordinates (a 3D file takes
the key frame if it is flat, else the first flat frame, else it is an error),
missing faces (computed), the old key ``edges_foldAngles``, and a missing
``edges_assignment`` (taken from the sign of the fold angles, else ``U``).
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad._fileio import atomic_write
from origami_cad.errors import PatternError
from origami_cad.pattern.model import CreasePattern, Hole

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
    if frames:
        data["file_frames"] = [dict(f) for f in frames]
    return data


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
    data = fold_dict(cp, frames)
    with atomic_write(path, "w", encoding="utf-8") as fh:
        json.dump(data, fh, indent=1)
        fh.write("\n")
    return Path(path)


def _load(path: str | os.PathLike[str]) -> dict[str, Any]:
    p = Path(path)
    if not p.exists():
        raise PatternError(f"{p}: no such file")
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise PatternError(
            f"{p}: not valid JSON (line {exc.lineno}, column {exc.colno}: {exc.msg})"
        ) from None
    except UnicodeDecodeError:
        raise PatternError(f"{p}: not a text file (FOLD is JSON)") from None
    if not isinstance(data, dict):
        raise PatternError(f"{p}: a FOLD file must hold a JSON object, not {type(data).__name__}")
    return data


def _frames(data: dict[str, Any]) -> list[dict[str, Any]]:
    """All frames with inheritance resolved (frame 0 is the key frame)."""
    base = {k: v for k, v in data.items() if k != "file_frames"}
    raw = data.get("file_frames") or []
    out = [base]
    for fr in raw:
        if not isinstance(fr, dict):
            raise PatternError("file_frames must hold JSON objects")
        if fr.get("frame_inherit"):
            parent = int(fr.get("frame_parent", 0))
            if not 0 <= parent < len(out):
                raise PatternError(f"frame_parent {parent} does not exist")
            merged = {**out[parent], **fr}
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
    unit = str(frame.get("frame_unit", "mm")).lower()
    scales = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4, "pt": 25.4 / 72, "unit": 1.0}
    if unit not in scales:
        # FOLD allows "unit" (no physical unit); anything else unknown is kept as mm
        raise PatternError(f"{where}: frame_unit {unit!r} is not supported (mm, cm, m, in, pt)")
    return scales[unit]


def _frame_to_pattern(frame: dict[str, Any], where: str, title: str) -> CreasePattern:
    coords = _key(frame, "vertices_coords", where)
    edges = _key(frame, "edges_vertices", where)
    if not isinstance(edges, list) or len(edges) == 0:
        raise PatternError(f"{where}: 'edges_vertices' is empty; a crease pattern needs edges")
    try:
        verts = np.asarray(coords, dtype=float)
        e = np.asarray(edges, dtype=np.int64)
    except (TypeError, ValueError):
        raise PatternError(f"{where}: vertices_coords/edges_vertices are not numeric") from None
    if verts.ndim != 2 or verts.shape[1] not in (2, 3):
        raise PatternError(f"{where}: vertices_coords must be a list of [x, y] or [x, y, z]")
    if e.ndim != 2 or e.shape[1] != 2:
        raise PatternError(f"{where}: every entry of edges_vertices must be [v1, v2]")
    verts = verts * _unit_scale(frame, where)
    angles = _key(frame, "edges_foldAngle", where, required=False)
    if angles is not None:
        if len(angles) != len(e):
            raise PatternError(
                f"{where}: edges_foldAngle has {len(angles)} entries for {len(e)} edges"
            )
        angles = np.array([np.nan if a is None else float(a) for a in angles])
        if np.any(np.abs(angles[np.isfinite(angles)]) > 180 + 1e-9):
            raise PatternError(f"{where}: edges_foldAngle must lie within [-180, 180] degrees")
    assign = _key(frame, "edges_assignment", where, required=False)
    if assign is None:
        if angles is not None:
            a = np.nan_to_num(angles)
            assign = np.where(a > 0, "V", np.where(a < 0, "M", "U"))
        else:
            assign = "U"
    elif len(assign) != len(e):
        raise PatternError(
            f"{where}: edges_assignment has {len(assign)} entries for {len(e)} edges"
        )
    faces = frame.get("faces_vertices")
    labels = frame.get(_LABELS)
    holes = []
    for face_holes in frame.get(_HOLES) or []:
        for x, y, d in face_holes:
            holes.append(Hole(float(x), float(y), float(d)))
    try:
        cp = CreasePattern(
            verts,
            e,
            assign,
            angles,
            faces=faces,
            face_labels=labels if faces is not None else None,
            holes=holes,
            metadata={"title": title} if title else {},
        )
    except PatternError as exc:
        raise PatternError(f"{where}: {exc}") from None
    return cp


def _is_flat(frame: dict[str, Any]) -> bool:
    c = frame.get("vertices_coords") or []
    if not c or len(c[0]) == 2:
        return True
    z = np.asarray(c, dtype=float)[:, 2]
    return bool(np.ptp(z) <= 1e-9 * max(1.0, float(np.abs(np.asarray(c, float)).max())))


def read_fold(path: str | os.PathLike[str]) -> CreasePattern:
    """Read the crease pattern of a FOLD file.

    The key frame is used when it is flat; otherwise the first flat frame of
    ``file_frames`` (a file holding only a folded form is an error, since its
    crease pattern cannot be recovered without unfolding it).
    """
    data = _load(path)
    frames = _frames(data)
    title = str(data.get("file_title", "") or "")
    for i, frame in enumerate(frames):
        if "vertices_coords" not in frame and i == 0 and len(frames) > 1:
            continue
        where = f"{path}" if i == 0 else f"{path} (file_frames[{i - 1}])"
        if i == 0 and "edges_vertices" not in frame and "edges_foldAngles" not in frame:
            raise PatternError(f"{path}: missing key 'edges_vertices' (the file has no edges)")
        if _is_flat(frame):
            return _frame_to_pattern(frame, where, title)
    raise PatternError(
        f"{path}: no frame is flat: the file holds a folded form only, not a crease pattern"
    )


def read_fold_frames(path: str | os.PathLike[str]) -> list[np.ndarray]:
    """Vertex coordinates (mm, shape (n, 3)) of every frame of a FOLD file, key frame first."""
    data = _load(path)
    out = []
    for frame in _frames(data):
        c = np.asarray(frame.get("vertices_coords", []), dtype=float)
        if c.ndim == 2 and c.shape[1] == 2:
            c = np.column_stack([c, np.zeros(len(c))])
        out.append(c * _unit_scale(frame, str(path)))
    return out
