"""STL export of the printed parts: one binary STL per part (serialised only).

The meshes are :mod:`origami_cad.fabrication.meshing`'s (``part_meshes``), the same the
3MF and the glb files are made of.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from build123d import export_stl

from origami_cad._fileio import atomic_path
from origami_cad.fabrication.meshing import (
    ANGULAR_TOLERANCE,
    TOLERANCE,
    part_meshes,
    stack_meshes,
    weld_float32,
)
from origami_cad.fabrication.solids import PART_NAMES, Parts

__all__ = ["WRITERS", "export_stls", "read_binary_stl", "write_mesh_stl", "write_stl"]


def export_stls(parts: Parts, folder: str | os.PathLike[str]) -> dict[str, Path]:
    """Write ``<part>.stl`` (binary, assembly position) for each of the four parts.

    Each file holds the part's meshes (:func:`part_meshes`: tessellated once, shared
    with the other exports), every solid its own closed shell.
    """
    out = {}
    for name in PART_NAMES:
        out[name] = write_mesh_stl(
            stack_meshes(part_meshes(parts, name)), Path(folder) / f"{name}.stl"
        )
    return out


def write_mesh_stl(mesh: tuple[np.ndarray, np.ndarray], path: str | os.PathLike[str]) -> Path:
    """Write a mesh (vertices in mm, triangles) as one binary STL (atomic), unit normals."""
    v, t = mesh
    record = np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    data = np.empty(len(t), dtype=record)
    data["attr"] = 0
    data["v"] = corners = np.asarray(v, dtype=np.float32)[t]  # the normals of what is written
    a, b = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    normal = data["normal"]
    normal[:, 0] = a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]
    normal[:, 1] = a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]
    normal[:, 2] = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    length = np.sqrt(np.einsum("ij,ij->i", normal, normal))
    normal /= np.where(length > 0, length, np.float32(1.0))[:, None]
    header = b"binary STL written by origami_cad".ljust(80, b"\0")  # NUL-ended for admesh
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(header + np.array([len(t)], dtype="<u4").tobytes())
        fh.write(memoryview(data).cast("B"))
    return Path(path)


def read_binary_stl(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (welded, mm) and triangles of a binary STL file."""
    raw = Path(path).read_bytes()
    count = int(np.frombuffer(raw, dtype="<u4", count=1, offset=80)[0])
    record = np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    data = np.frombuffer(raw, dtype=record, count=count, offset=84)
    verts, inverse = weld_float32(data["v"].reshape(-1, 3))
    return verts, inverse.reshape(-1, 3)


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
