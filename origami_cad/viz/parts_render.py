"""Renders of the printed parts from their STL files: assembled, exploded, section (Fig. 4)."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from origami_cad._fileio import atomic_path
from origami_cad.viz.render3d import import_pyvista, offscreen_plotter

__all__ = ["PART_COLORS", "fabrication_section", "render_fabrication", "render_parts"]

#: Display colour of each part: PLA white/cream, TPU red.
PART_COLORS = {
    "infills": "#f4f1e8",
    "midlayers": "#e8dfc8",
    "shells": "#d62728",
    "creases": "#ff9896",
}
_EXPLODE = {"infills": 0.0, "midlayers": 1.0, "creases": 2.0, "shells": 3.0}


def render_parts(
    stls: Mapping[str, str | os.PathLike[str]],
    path: str | os.PathLike[str],
    *,
    mode: str = "assembled",
    section_origin: Sequence[float] | None = None,
    section_normal: Sequence[float] | None = None,
    window_size: tuple[int, int] = (1000, 700),
    title: str = "",
    labels: Mapping[str, str] | None = None,
    colors: Mapping[str, str] | None = None,
) -> Path:
    """Render the part STLs to a PNG (off-screen).

    Parameters
    ----------
    stls : mapping
        Part name (``infills``, ``midlayers``, ``shells``, ``creases``) to STL path.
    path : path-like
        Output PNG (atomic write).
    mode : str
        ``assembled``; ``exploded`` (parts spread along z); or ``section``: every part
        cut by the plane through ``section_origin`` (mm) with ``section_normal``, the
        cut outlined in black, seen along the normal (choose a plane perpendicular to
        a crease for the paper's Fig. 4e).
    labels : mapping, optional
        The legend's label of each part (default: its name); parts sharing a label
        (four TSA modules) share one legend entry.
    colors : mapping, optional
        Colour (sRGB hex) of parts not in :data:`PART_COLORS` (default grey).
    """
    pv = import_pyvista()

    meshes = {name: pv.read(str(p)) for name, p in stls.items()}
    size = max(np.ptp(np.asarray(m.bounds).reshape(3, 2), axis=1).max() for m in meshes.values())
    legend: dict[str, str] = {}
    with offscreen_plotter(window_size) as plotter:
        for name, mesh in meshes.items():
            if mode == "exploded":
                mesh = mesh.translate((0, 0, _EXPLODE.get(name, 0.0) * 0.08 * size), inplace=False)
            elif mode == "section":
                if section_origin is None or section_normal is None:
                    raise ValueError("a section needs section_origin and section_normal")
                plane = {"normal": tuple(section_normal), "origin": tuple(section_origin)}
                cut = mesh.slice(**plane)
                mesh = mesh.clip(**plane)
                if cut.n_points:
                    plotter.add_mesh(cut, color="black", line_width=3)
                if mesh.n_points == 0:
                    continue
            colour = PART_COLORS.get(name) or (colors or {}).get(name, "#cccccc")
            label = (labels or {}).get(name, name)
            if label not in legend:
                legend[label] = colour
            plotter.add_mesh(mesh, color=colour, show_edges=False, ambient=0.3, specular=0.2)
        if mode == "section":
            n = np.asarray(section_normal, float)
            plotter.view_vector(tuple(n / np.linalg.norm(n)), viewup=(0, 0, 1))
            plotter.enable_parallel_projection()
            plotter.reset_camera()
            plotter.camera.zoom(6.0)
            plotter.camera.focal_point = tuple(section_origin)
        else:
            plotter.view_isometric()
            plotter.reset_camera()
        # entries are written in their parts' colours, from near white to dark grey: a
        # mid-grey box, in the corner
        plotter.add_legend(
            [[label, colour] for label, colour in legend.items()],
            bcolor="#a0a0a0",
            face="rectangle",
            size=(0.17, min(0.035 * len(legend), 0.3)),
            loc="upper right",
        )
        if title:
            plotter.add_text(title, font_size=10, color="black")
        with atomic_path(path) as tmp:
            plotter.screenshot(str(tmp))
    return Path(path)


def fabrication_section(cp, height: float) -> dict:
    """The section :func:`render_parts` cuts to show a crease (Fig. 4e): perpendicular to
    ``cp``'s first main crease, through its middle, at half the panels' ``height`` (mm)."""
    main = [e for e in range(cp.n_edges) if cp.assignments[e] in "MV"]
    a, b = cp.vertices[cp.edges[main[0]]]
    mid = (a + b) / 2
    direction = (b - a) / max(float(((b - a) ** 2).sum()) ** 0.5, 1e-12)
    return {
        "mode": "section",
        "section_origin": (float(mid[0]), float(mid[1]), height / 2),
        "section_normal": (float(direction[0]), float(direction[1]), 0.0),
    }


def render_fabrication(
    cp, fab, folder: str | os.PathLike[str], name: str
) -> list[tuple[Path, str]]:
    """``assembled.png``, ``exploded.png`` and ``section.png`` of a fabrication's four
    STLs, already written into ``folder``; each picture's path and caption (``name`` first)."""
    out = Path(folder)
    stls = {n: out / f"{n}.stl" for n in ("infills", "midlayers", "shells", "creases")}
    shots = [
        (out / "assembled.png", {}, f"{name}: assembled"),
        (out / "exploded.png", {"mode": "exploded"}, f"{name}: the four STLs"),
        (out / "section.png", fabrication_section(cp, fab.params.height),
         f"{name}: section across a crease (Fig. 4e)"),
    ]  # fmt: skip
    for path, kwargs, title in shots:
        render_parts(stls, path, title=title, **kwargs)
    return [(p, t) for p, _, t in shots]
