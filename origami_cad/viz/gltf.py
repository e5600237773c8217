"""glTF 2.0 binary (``.glb``) files of folded states and printed parts, from plain arrays.

Blender, three.js viewers and the report's own viewer open them. Coordinates are
origami_cad's (mm, z up) in the meshes; one root node turns them into glTF's
convention (metres, y up) by a scale of 0.001 and a rotation of -90 deg about x,
so that every client shows the structure the right size and the right way up.

Importing this module does not import build123d: the parts are plain arrays.

A folding is one mesh per kind of line (panels as triangles, mountain, valley,
border and cut creases as lines) whose morph targets are the folded states; one
animation plays them through the ``weights`` of each node (linear between two
states). Colours are ``pbrMetallicRoughness`` base colours (linear RGB, as glTF
requires; :func:`srgb_to_linear`).
"""

from __future__ import annotations

import math
import os
import struct
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from origami_cad._fileio import atomic_write
from origami_cad._toml import json_text
from origami_cad.errors import OutputError
from origami_cad.pattern.model import CreasePattern
from origami_cad.pattern.triangles import panel_triangles

__all__ = [
    "CREASE_COLORS",
    "PANEL_COLOR",
    "GlbMesh",
    "folding_meshes",
    "glb_bytes",
    "panel_triangles",
    "parts_meshes",
    "srgb_to_linear",
    "write_glb",
    "write_parts_glb",
]

#: Display colour (sRGB hex) of the panels of a folded state.
PANEL_COLOR = "#F2E6C9"
#: Display colour (sRGB hex) of each kind of line: mountain, valley, border, cut.
CREASE_COLORS = {"M": "#D62728", "V": "#1F4FD6", "B": "#222222", "C": "#2CA02C"}
_CREASE_NAMES = {"M": "mountain", "V": "valley", "B": "border", "C": "cut"}
#: Length of a folding animation, seconds.
FOLDING_SECONDS = 3.0

_FLOAT, _USHORT, _UINT = 5126, 5123, 5125
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963
_LINES, _TRIANGLES = 1, 4


def srgb_to_linear(color: str) -> list[float]:
    """An sRGB hex colour (``"#RRGGBB"``) as linear RGBA in [0, 1] (glTF's base colour)."""
    hexa = color.lstrip("#")
    out = []
    for i in (0, 2, 4):
        c = int(hexa[i : i + 2], 16) / 255
        out.append(c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4)
    return [*out, 1.0]


@dataclass
class GlbMesh:
    """One node of a glb: a mesh of triangles or lines in one colour.

    Attributes
    ----------
    name : str
        Node, mesh and (with ``material``) material name.
    positions : ndarray, shape (n, 3)
        Vertices, mm, z up.
    indices : ndarray, shape (m, 3) or (m, 2)
        Triangles (3 columns) or line segments (2 columns), vertex indices.
    color : str
        sRGB hex display colour.
    material : str
        The material's name (defaults to ``name``).
    targets : list of ndarray (n, 3)
        Morph targets: other positions of the same vertices, mm (a folding's states).
    """

    name: str
    positions: np.ndarray
    indices: np.ndarray
    color: str
    material: str = ""
    targets: list[np.ndarray] = field(default_factory=list)


class _Buffer:
    """The binary chunk and its buffer views and accessors, as they are appended."""

    def __init__(self) -> None:
        self.data = bytearray()
        self.views: list[dict] = []
        self.accessors: list[dict] = []

    def add(self, array: np.ndarray, kind: str, target: int | None = None, bounds=False) -> int:
        """Append ``array`` (float32, uint16 or uint32); the index of its accessor."""
        comp = {np.dtype("float32"): _FLOAT, np.dtype("uint16"): _USHORT}.get(array.dtype, _UINT)
        raw = np.ascontiguousarray(array).tobytes()
        view = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(raw)}
        if target is not None:
            view["target"] = target
        self.data += raw + b"\0" * (-len(raw) % 4)
        self.views.append(view)
        count = len(array) if kind != "SCALAR" else array.size
        acc = {"bufferView": len(self.views) - 1, "componentType": comp, "count": count}
        acc["type"] = kind
        if bounds:
            flat = array.reshape(count, -1)
            acc["min"] = flat.min(axis=0).tolist()
            acc["max"] = flat.max(axis=0).tolist()
        self.accessors.append(acc)
        return len(self.accessors) - 1


def _primitive(buf: _Buffer, mesh: GlbMesh, material: int) -> dict:
    pos = np.asarray(mesh.positions, dtype=np.float32).reshape(-1, 3)
    idx = np.asarray(mesh.indices).reshape(len(mesh.indices), -1)
    if idx.size and (idx.min() < 0 or idx.max() >= len(pos)):
        raise ValueError(f"mesh {mesh.name!r}: an index outside its {len(pos)} vertices")
    itype = np.uint16 if len(pos) < 65535 else np.uint32
    prim = {
        "attributes": {"POSITION": buf.add(pos, "VEC3", _ARRAY_BUFFER, bounds=True)},
        "indices": buf.add(idx.astype(itype).ravel(), "SCALAR", _ELEMENT_ARRAY_BUFFER),
        "material": material,
        "mode": _TRIANGLES if idx.shape[1] == 3 else _LINES,
    }
    if mesh.targets:
        prim["targets"] = [
            {"POSITION": buf.add((np.asarray(t, float) - pos).astype(np.float32), "VEC3",
                                 _ARRAY_BUFFER, bounds=True)}
            for t in mesh.targets
        ]  # fmt: skip
    return prim


def glb_bytes(meshes: Sequence[GlbMesh], times: Sequence[float] | None = None) -> bytes:
    """A glb holding ``meshes`` under one root node (mm, z up -> metres, y up).

    With ``times`` (seconds, one per state: the base positions, then each morph
    target), one animation ``folding`` plays the states of every mesh that has
    morph targets: at ``times[k]`` the weight of target ``k - 1`` is 1, the others 0.
    """
    meshes = [m for m in meshes if len(m.indices)]  # glTF has no empty primitive
    buf, materials, gmeshes, nodes = _Buffer(), [], [], []
    names: dict[str, int] = {}
    for m in meshes:
        key = m.material or m.name
        if key not in names:
            names[key] = len(materials)
            materials.append(
                {
                    "name": key,
                    "pbrMetallicRoughness": {
                        "baseColorFactor": srgb_to_linear(m.color),
                        "metallicFactor": 0.0,
                        "roughnessFactor": 0.8,
                    },
                    "doubleSided": True,
                }
            )
        gm = {"name": m.name, "primitives": [_primitive(buf, m, names[key])]}
        if m.targets:
            gm["weights"] = [0.0] * len(m.targets)
        gmeshes.append(gm)
        nodes.append({"name": m.name, "mesh": len(gmeshes) - 1})
    half = math.sqrt(0.5)
    root = {
        "name": "origami_cad (mm, z up)",
        "children": list(range(1, len(nodes) + 1)),
        "rotation": [-half, 0.0, 0.0, half],
        "scale": [0.001, 0.001, 0.001],
    }
    doc = {
        "asset": {"version": "2.0", "generator": "origami_cad"},
        "scene": 0,
        "scenes": [{"name": "origami_cad", "nodes": [0]}],
        "nodes": [root, *nodes],
        "meshes": gmeshes,
        "materials": materials,
    }
    animated = [k for k, m in enumerate(meshes) if m.targets]
    if times is not None and animated:
        doc["animations"] = [_animation(buf, meshes, animated, times)]
    doc |= {"accessors": buf.accessors, "bufferViews": buf.views}
    doc["buffers"] = [{"byteLength": len(buf.data)}]
    text = json_text(doc, "glTF", OutputError, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    body = bytes(buf.data)
    total = 12 + 8 + len(text) + 8 + len(body)
    head = struct.pack("<4sII", b"glTF", 2, total)
    return (
        head
        + struct.pack("<I4s", len(text), b"JSON")
        + text
        + struct.pack("<I4s", len(body), b"BIN\0")
        + body
    )


def _animation(buf: _Buffer, meshes, animated: list[int], times: Sequence[float]) -> dict:
    n_targets = {len(meshes[k].targets) for k in animated}
    if len(n_targets) != 1 or len(times) != next(iter(n_targets)) + 1:
        raise ValueError("every animated mesh needs one morph target per time after the first")
    n = len(times) - 1
    t = np.asarray(times, dtype=np.float32)
    if np.any(np.diff(t) <= 0):
        raise ValueError("animation times must increase")
    weights = np.zeros((n + 1, n), dtype=np.float32)
    weights[np.arange(1, n + 1), np.arange(n)] = 1.0
    t_acc = buf.add(t, "SCALAR", bounds=True)
    w_acc = buf.add(weights.ravel(), "SCALAR")
    samplers = [{"input": t_acc, "output": w_acc, "interpolation": "LINEAR"} for _ in animated]
    channels = [
        {"sampler": s, "target": {"node": k + 1, "path": "weights"}} for s, k in enumerate(animated)
    ]
    return {"name": "folding", "samplers": samplers, "channels": channels}


def write_glb(
    path: str | os.PathLike[str],
    meshes: Sequence[GlbMesh],
    times: Sequence[float] | None = None,
) -> Path:
    """Write :func:`glb_bytes` to ``path`` (atomic)."""
    data = glb_bytes(meshes, times)
    with atomic_write(path, "wb") as fh:
        fh.write(data)
    return Path(path)


def folding_meshes(cp: CreasePattern, states: Sequence[np.ndarray]) -> list[GlbMesh]:
    """The panels and the lines of each kind of a folding; states after the first are targets.

    Parameters
    ----------
    cp : CreasePattern
        The pattern.
    states : sequence of ndarray (n, 3)
        Vertex coordinates of each state, mm (one state: a still folded state).
    """
    if not len(states):
        raise ValueError("no folded state to write")
    frames = [np.asarray(s, float).reshape(cp.n_vertices, 3) for s in states]
    meshes = [GlbMesh("panels", frames[0], panel_triangles(cp), PANEL_COLOR, "paper", frames[1:])]
    for letter, color in CREASE_COLORS.items():
        edges = cp.edges[cp.assignments == letter]
        if len(edges):
            used, inverse = np.unique(edges, return_inverse=True)
            lines = inverse.reshape(-1, 2)
            name = _CREASE_NAMES[letter]
            meshes.append(
                GlbMesh(name, frames[0][used], lines, color, name, [f[used] for f in frames[1:]])
            )
    return meshes


def parts_meshes(meshes: Mapping[str, tuple[np.ndarray, np.ndarray]]) -> list[GlbMesh]:
    """Printed parts, one node each, coloured by material (PLA white, TPU red).

    Parameters
    ----------
    meshes : mapping
        Part name (``infills``, ``midlayers``, ``shells``, ``creases`` or another
        part) to its vertices (mm) and triangles. A part not in the dual-material
        structure is printed in PLA.
    """
    from origami_cad.fabrication.assembly import MATERIAL_COLORS
    from origami_cad.fabrication.solids import PART_MATERIALS

    out = []
    for name, (v, t) in meshes.items():
        material = PART_MATERIALS.get(name, "PLA")
        out.append(GlbMesh(name, v, t, MATERIAL_COLORS[material], material))
    return out


def write_parts_glb(folder, path: str | os.PathLike[str]) -> Path:
    """Write the four printed parts as one glb, coloured by material (``path``, atomic).

    ``folder`` is a :class:`~origami_cad.fabrication.build.Fabrication`: its shared
    meshes (``fabrication.meshing.parts_tessellation``, the STLs' triangles; no file
    read), or a fabrication folder (path-like): its ``infills.stl``, ``midlayers.stl``,
    ``shells.stl`` and ``creases.stl`` as
    :func:`~origami_cad.fabrication.write_fabrication` writes them, in assembly position.
    """
    from origami_cad.fabrication.solids import PART_NAMES

    if isinstance(folder, (str, os.PathLike)):
        from origami_cad.fabrication.exports.stl import read_binary_stl

        meshes = {n: read_binary_stl(Path(folder) / f"{n}.stl") for n in PART_NAMES}
    else:  # a Fabrication: the meshes in memory
        from origami_cad.fabrication.meshing import parts_tessellation

        meshes = parts_tessellation(folder.parts)
    return write_glb(path, parts_meshes(meshes))
