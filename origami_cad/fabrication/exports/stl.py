"""STL export of the printed parts: one binary STL per part, and the meshes behind every export.

The meshes (:func:`solid_mesh`) are OCC's tessellation of each solid, welded within the
solid only; the 3MF and the glb files are made of the same meshes.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from build123d import Solid, export_stl

from origami_cad._fileio import atomic_path
from origami_cad.fabrication.solids import PART_NAMES, Parts

__all__ = [
    "ANGULAR_TOLERANCE",
    "TOLERANCE",
    "WRITERS",
    "export_stls",
    "part_meshes",
    "parts_tessellation",
    "read_binary_stl",
    "solid_mesh",
    "write_stl",
]

#: Tessellation of the exports: chordal tolerance (mm) and angular tolerance (rad).
TOLERANCE, ANGULAR_TOLERANCE = 0.01, 0.1


def export_stls(parts: Parts, folder: str | os.PathLike[str]) -> dict[str, Path]:
    """Write ``<part>.stl`` (binary, assembly position) for each of the four parts."""
    out = {}
    for name in PART_NAMES:
        path = write_stl(parts.compound(name), Path(folder) / f"{name}.stl")
        out[name] = path
    return out


def read_binary_stl(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (welded, mm) and triangles of a binary STL file."""
    raw = Path(path).read_bytes()
    count = int(np.frombuffer(raw, dtype="<u4", count=1, offset=80)[0])
    record = np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    data = np.frombuffer(raw, dtype=record, count=count, offset=84)
    corners = data["v"].reshape(-1, 3).astype(float)
    verts, inverse = np.unique(corners, axis=0, return_inverse=True)
    return verts, inverse.reshape(-1, 3)


def solid_mesh(solid: Solid) -> tuple[np.ndarray, np.ndarray]:
    """One solid meshed by OCC: vertices (mm) welded within the solid, triangles.

    Vertices are welded only inside one solid, never across solids: neighbouring
    shell chamfers meet on a line, and welding them would join four triangles on one
    edge. Triangles that collapse in the weld are dropped.
    """
    points, triangles = solid.tessellate(TOLERANCE, ANGULAR_TOLERANCE)
    v = np.array([(p.X, p.Y, p.Z) for p in points], dtype=float).reshape(-1, 3)
    t = np.array(triangles, dtype=np.int64).reshape(-1, 3)
    key = np.round(v / 1e-6).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    t = inverse.reshape(-1)[t]
    t = t[(t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 2] != t[:, 0])]
    return v[first], t


def part_meshes(parts: Parts, name: str) -> list[tuple[np.ndarray, np.ndarray]]:
    """The meshes of every solid of a part (see :func:`solid_mesh`)."""
    return [solid_mesh(s) for s in parts.solids[name]]


def parts_tessellation(parts: Parts) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each part as one plain mesh: vertices (mm, assembly position) and triangles.

    The solids of a part are stacked (:func:`part_meshes`, no vertex shared between
    solids); this is what other stages draw, as NumPy arrays rather than build123d
    shapes.
    """
    out = {}
    for name in PART_NAMES:
        verts, tris, offset = [np.zeros((0, 3))], [np.zeros((0, 3), dtype=np.int64)], 0
        for v, t in part_meshes(parts, name):
            verts.append(v)
            tris.append(t + offset)
            offset += len(v)
        out[name] = (np.vstack(verts), np.vstack(tris))
    return out


def write_stl(shape, path: str | os.PathLike[str]) -> Path:
    """Write one binary STL of a shape or assembly (atomic), at the exports' tolerance."""
    with atomic_path(path) as tmp:
        ok = export_stl(
            shape,
            str(tmp),
            tolerance=TOLERANCE,
            angular_tolerance=ANGULAR_TOLERANCE,
            ascii_format=False,
        )
        if ok is False:
            raise OSError(f"{path}: the STL writer failed")
    return Path(path)


def _write_fabrication_stls(fab, folder: Path) -> dict[str, Path]:
    return export_stls(fab.parts, folder)


#: What ``write_fabrication`` writes of this format: ``{format: writer(fab, folder)}``.
WRITERS = {"stl": _write_fabrication_stls}
