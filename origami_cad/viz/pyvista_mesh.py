"""Visual checks from a script: any result of the pipeline as pyvista meshes, and a viewer.

:func:`to_pyvista` turns a crease pattern, a folded state or simulation frame, the
printed parts of a fabrication, or a route with its strings into a
``pyvista.MultiBlock`` of named blocks; :func:`show` draws one in a window, a
notebook or off-screen. Each block carries its display colour twice, so a test
or a script can read it back: ``block.field_data["color"]`` (sRGB, 3 bytes) and
``block.cell_data["color"]`` (one such row per cell, ready for
``add_mesh(block, scalars="color", rgb=True)``); ``block.field_data["kind"]``
says what it is (``panels``, ``mountain``, ``valley``, ``border``, ``cut``,
``string``, ``part``) and, for printed parts, ``field_data["material"]`` the
material (``PLA`` or ``TPU``). A build123d shape (an assembly of
``Fabrication.assembly``, a part, a user's compound) gives a block per solid leaf.
Lengths are mm.

Nothing changes pyvista's global state: :func:`show` creates its own plotter,
off-screen when there is no display (``pyvista.OFF_SCREEN`` stays untouched).

>>> from origami_cad.pattern.design import miura_design
>>> blocks = to_pyvista(miura_design(2, 3, 30.0, 30.0, 65.0))
>>> blocks.keys()[:3], blocks["panels"].n_cells
(['panels', 'mountain', 'valley'], 6)
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad._args import Arg, brief_value
from origami_cad._fileio import atomic_path
from origami_cad.errors import PatternError
from origami_cad.pattern.model import CreasePattern
from origami_cad.viz.gltf import CREASE_COLORS, PANEL_COLOR
from origami_cad.viz.render3d import import_pyvista

__all__ = ["SHAPE_COLOR", "STRING_COLOR", "display_mode", "show", "to_pyvista"]

#: Display colour (sRGB hex) of the strings of a route.
STRING_COLOR = "#8E44AD"
_LINE_NAMES = {"M": "mountain", "V": "valley", "B": "border", "C": "cut"}


def _rgb(color: str) -> np.ndarray:
    hexa = color.lstrip("#")
    return np.array([int(hexa[i : i + 2], 16) for i in (0, 2, 4)], dtype=np.uint8)


def _paint(mesh, color: str, kind: str, material: str = ""):
    rgb = _rgb(color)
    mesh.field_data["color"] = rgb
    mesh.field_data["kind"] = [kind]
    if material:
        mesh.field_data["material"] = [material]
    mesh.cell_data["color"] = np.tile(rgb, (mesh.n_cells, 1))
    return mesh


def _pattern_of(pattern) -> CreasePattern:
    cp = getattr(pattern, "pattern", pattern)  # a Design, or a CreasePattern
    if not isinstance(cp, CreasePattern):
        raise PatternError(
            "to_pyvista: pattern: give the crease pattern (or design) these coordinates "
            f"belong to, got {brief_value(pattern)}"
        )
    return cp


def _state_blocks(cp: CreasePattern, coords: np.ndarray | None):
    pv = import_pyvista()

    if coords is None:
        coords = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    expected = f"to_pyvista: coords: expected ({cp.n_vertices}, 3) finite coordinates, mm"
    try:
        coords = np.asarray(coords, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise PatternError(f"{expected}, got {brief_value(coords)}") from None
    if coords.shape != (cp.n_vertices, 3) or not np.isfinite(coords).all():
        raise PatternError(f"{expected}, got {brief_value(coords)}")
    blocks = pv.MultiBlock()
    faces = np.concatenate([np.r_[len(f), f] for f in cp.faces]) if cp.faces else []
    blocks["panels"] = _paint(pv.PolyData(coords, faces), PANEL_COLOR, "panels")
    for letter, name in _LINE_NAMES.items():
        edges = cp.edges[cp.assignments == letter]
        if len(edges):
            lines = np.column_stack([np.full(len(edges), 2), edges]).ravel()
            mesh = pv.PolyData(coords, lines=lines).clean(point_merging=False)
            blocks[name] = _paint(mesh, CREASE_COLORS[letter], name)
    return blocks


def _add_strings(blocks, paths: Sequence[np.ndarray]) -> None:
    pv = import_pyvista()

    for k, path in enumerate(paths):
        mesh = pv.lines_from_points(np.asarray(path, dtype=float))
        blocks[f"string {k}"] = _paint(mesh, STRING_COLOR, "string")


def _parts_blocks(fab):
    pv = import_pyvista()

    from origami_cad.fabrication.assembly import MATERIAL_COLORS
    from origami_cad.fabrication.meshing import parts_tessellation
    from origami_cad.fabrication.solids import PART_MATERIALS

    blocks = pv.MultiBlock()
    for name, (v, t) in parts_tessellation(fab.parts).items():
        material = PART_MATERIALS[name]
        faces = np.column_stack([np.full(len(t), 3), t]).ravel()
        mesh = pv.PolyData(v, faces)
        blocks[name] = _paint(mesh, MATERIAL_COLORS[material], "part", material)
    return blocks


#: Display colour (sRGB hex) of a solid of a build123d shape that has no colour of its own.
SHAPE_COLOR = "#B0B0B0"


def _hex(color) -> str:
    r, g, b = (round(255 * float(c)) for c in tuple(color)[:3])
    return f"#{r:02X}{g:02X}{b:02X}"


def _shape_blocks(shape):
    """One block per leaf of a build123d shape or tree, in its (or its nearest ancestor's)
    colour; a leaf of a sheet assembly also names its material."""
    pv = import_pyvista()

    from origami_cad.fabrication.assembly import leaf_part
    from origami_cad.fabrication.meshing import solid_mesh
    from origami_cad.fabrication.solids import PART_MATERIALS

    blocks = pv.MultiBlock()
    stack = [(shape, None)]
    while stack:
        node, inherited = stack.pop(0)
        color = node.color if getattr(node, "color", None) is not None else inherited
        children = list(getattr(node, "children", ()) or ())
        if children:
            stack[:0] = [(c, color) for c in children]
            continue
        meshes = [solid_mesh(s) for s in node.solids()]
        if not meshes:
            continue
        verts, tris, offset = [], [], 0
        for v, t in meshes:
            verts.append(v)
            tris.append(t + offset)
            offset += len(v)
        t = np.vstack(tris)
        mesh = pv.PolyData(np.vstack(verts), np.column_stack([np.full(len(t), 3), t]).ravel())
        part = leaf_part(node.label or "")
        material = PART_MATERIALS[part] if part else ""
        name, k = node.label or f"solid {len(blocks)}", 1
        while name in blocks.keys():
            k += 1
            name = f"{node.label} ({k})"
        blocks[name] = _paint(
            mesh, _hex(color) if color is not None else SHAPE_COLOR, "part", material
        )
    return blocks


def to_pyvista(obj: Any, pattern: Any = None, *, coords: Any = None, frame: int = -1):
    """Pyvista meshes of a pipeline result: a ``pyvista.MultiBlock`` of named blocks.

    Parameters
    ----------
    obj
        One of:

        - a ``CreasePattern`` or ``Design``: the flat sheet (z = 0), or the state
          ``coords`` when given;
        - a ``FoldedState`` (its own pattern, or ``pattern``) or an array (n, 3) of
          vertex coordinates, mm (a simulation frame): that state of ``pattern``;
        - a ``SimulationResult`` or ``DCQCResult``: state ``frame`` of ``pattern``
          (default the last; a DCQC result also draws its final strings);
        - a ``RouteSpec``: ``pattern`` flat (or at ``coords``) with the strings;
        - a ``Fabrication``: the four printed parts coloured by material;
        - a build123d shape or ``Compound`` tree: an assembly
          (``Fabrication.assembly(ratio)``), a part (``TSAModule()``...), a user's
          compound: one block per leaf, named by its label, in its colour.
    pattern : CreasePattern or Design, optional
        The pattern a state, result or route belongs to.
    coords : ndarray (n, 3), optional
        Folded vertex coordinates, mm, for a pattern or a route.
    frame : int
        Which state of a simulation or DCQC result (index; -1 the last).

    Returns
    -------
    pyvista.MultiBlock
        Blocks ``panels`` (polygons), ``mountain``, ``valley``, ``border``, ``cut``
        (lines; only the kinds present), ``string 0``, ``string 1``... (polylines),
        or ``infills``, ``midlayers``, ``shells``, ``creases`` (triangles), or a
        shape's leaves (``c0r0s0 infill 0``, ``servo``...: triangles), each with its
        colour in ``field_data["color"]`` and ``cell_data["color"]``.
    """
    frame = Arg("int", optional=False).check("to_pyvista: frame", frame, PatternError)
    if hasattr(obj, "parts") and hasattr(obj, "plan"):  # a Fabrication
        return _parts_blocks(obj)
    if hasattr(obj, "wrapped") and hasattr(obj, "solids"):  # a build123d shape
        return _shape_blocks(obj)
    if isinstance(obj, CreasePattern) or hasattr(obj, "tg"):  # a pattern or a Design
        return _state_blocks(_pattern_of(obj), coords)
    if pattern is None and isinstance(getattr(obj, "pattern", None), CreasePattern):
        pattern = obj.pattern  # a FoldedState knows the pattern it folds
    cp = _pattern_of(pattern)
    if hasattr(obj, "strings") and hasattr(obj, "tsa"):  # a RouteSpec
        from origami_cad.strings.route import string_path

        blocks = _state_blocks(cp, coords)
        state = blocks["panels"].points
        _add_strings(blocks, [string_path(cp, state, s, obj.thickness) for s in obj.strings])
        return blocks
    states = len(obj.p) if hasattr(obj, "final_strings") else len(getattr(obj, "states", ()))
    if hasattr(obj, "final_strings") or hasattr(obj, "states"):
        Arg("int", min=-states, max=states - 1).check("to_pyvista: frame", frame, PatternError)
    if hasattr(obj, "final_strings"):  # a DCQCResult: its last state has the strings
        from origami_cad.kinematics.folding import fold_design

        if frame in (-1, len(obj.p) - 1) and obj.final_coords is not None:
            blocks = _state_blocks(cp, obj.final_coords)
            _add_strings(blocks, obj.final_strings)
            return blocks
        if not hasattr(pattern, "tg"):
            raise PatternError(
                "to_pyvista: pattern: an earlier DCQC state is refolded from its design: "
                "give the Design"
            )
        return _state_blocks(cp, fold_design(pattern, float(obj.p[frame])).coords)
    if hasattr(obj, "states"):  # a SimulationResult
        return _state_blocks(cp, obj.states[frame])
    return _state_blocks(cp, getattr(obj, "coords", obj))  # a FoldedState or an array


def display_mode() -> str:
    """Where :func:`show` draws: ``"notebook"``, ``"window"`` or ``"offscreen"``.

    A notebook is an IPython kernel; a window needs a display (``DISPLAY`` or
    ``WAYLAND_DISPLAY`` on Linux; always on Windows and macOS).
    """
    shell = sys.modules.get("IPython")
    ip = shell.get_ipython() if shell is not None and hasattr(shell, "get_ipython") else None
    if ip is not None and getattr(ip, "kernel", None) is not None:
        return "notebook"
    if sys.platform in ("win32", "darwin"):
        return "window"
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return "window"
    return "offscreen"


def _add_blocks(plotter, blocks) -> None:
    for name in blocks.keys():
        mesh = blocks[name]
        kind = str(mesh.field_data["kind"][0])
        if kind in ("panels", "part"):
            plotter.add_mesh(
                mesh,
                scalars="color",
                rgb=True,
                preference="cell",
                ambient=0.3,
                specular=0.2,
                label=name,
            )
        else:
            width = 4 if kind == "string" else 2 if kind == "border" else 3
            plotter.add_mesh(
                mesh, scalars="color", rgb=True, preference="cell", line_width=width, label=name
            )


def show(
    obj: Any,
    pattern: Any = None,
    *,
    mode: str | None = None,
    screenshot: str | os.PathLike[str] | None = None,
    window_size: tuple[int, int] = (900, 700),
    **kwargs: Any,
):
    """Draw :func:`to_pyvista` of ``obj``: a window, a notebook widget, or off-screen.

    Parameters
    ----------
    obj, pattern, **kwargs
        As for :func:`to_pyvista` (``coords``, ``frame``).
    mode : str, optional
        ``"window"``, ``"notebook"`` or ``"offscreen"``; default :func:`display_mode`.
    screenshot : path-like, optional
        Also write the picture to this PNG (off-screen, or when the window closes).
    window_size : (int, int)
        Width and height, pixels.

    Returns
    -------
    ndarray or object
        Off-screen: the picture (height, width, 3) uint8. In a notebook: pyvista's
        viewer (an interactive widget with ``trame`` installed, else a static
        picture). In a window: ``None`` once it is closed.
    """
    from origami_cad.viz.render3d import offscreen_plotter

    blocks = to_pyvista(obj, pattern, **kwargs)
    mode = mode or display_mode()
    if mode not in ("window", "notebook", "offscreen"):
        raise ValueError(f"mode must be 'window', 'notebook' or 'offscreen', got {mode!r}")
    if mode == "offscreen":
        with offscreen_plotter(window_size) as plotter:
            _add_blocks(plotter, blocks)
            plotter.view_isometric()
            plotter.reset_camera()
            image = plotter.screenshot(return_img=True)
            if screenshot:
                with atomic_path(screenshot) as tmp:
                    plotter.screenshot(str(tmp))
        return image
    pv = import_pyvista()

    # a notebook's picture or widget is drawn off-screen, by the kernel
    notebook = mode == "notebook"
    plotter = pv.Plotter(window_size=list(window_size), notebook=notebook, off_screen=notebook)
    plotter.set_background("white")
    _add_blocks(plotter, blocks)
    plotter.view_isometric()
    if mode == "notebook":
        return plotter.show(return_viewer=True)
    shot = str(Path(screenshot)) if screenshot else None
    plotter.show(screenshot=shot)
    return None
