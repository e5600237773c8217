"""What the curated objects show in a notebook (the ``_repr_*_`` hooks of ``_display.py``).

- a ``CreasePattern`` or ``Design``: the pattern's plot (:func:`~origami_cad.viz.pattern_plot.
  plot_pattern`, mm axes) as SVG;
- a ``FoldedState`` or ``Fabrication``: the report's interactive WebGL view of its glb
  (:mod:`origami_cad.viz.gltf`, ``glb_viewer.js``), inline, and a still PNG: a pyvista
  render (the ``viz`` extra), or matplotlib's 3D axes without it.

Everything is drawn off-screen and changes no global state (no pyplot, no pyvista flag).
"""

from __future__ import annotations

import io
from typing import Any

import numpy as np

from origami_cad.errors import ExtraError
from origami_cad.pattern.model import CreasePattern
from origami_cad.pattern.triangles import panel_triangles
from origami_cad.viz.gltf import CREASE_COLORS, PANEL_COLOR, folding_meshes, glb_bytes
from origami_cad.viz.report import MAX_EMBEDDED_BYTES, view_figure, viewer_script

__all__ = ["PNG_SIZE", "pattern_svg", "view_glb", "view_html", "view_png"]

#: Width and height of the still pictures, pixels.
PNG_SIZE = (800, 600)


def _pattern(obj: Any) -> CreasePattern:
    cp = getattr(obj, "pattern", obj)
    if not isinstance(cp, CreasePattern):
        raise TypeError(f"{type(obj).__name__} has no crease pattern to draw")
    return cp


def pattern_svg(obj: Any) -> str:
    """The plot of a ``CreasePattern`` or ``Design`` (mm; mountain red, valley blue dashed),
    as the text of an SVG picture."""
    from matplotlib.figure import Figure

    from origami_cad.viz.pattern_plot import plot_pattern

    cp = _pattern(obj)
    x0, y0, x1, y1 = cp.bounds
    aspect = float(np.clip((y1 - y0) / max(x1 - x0, 1e-9), 0.3, 1.5))
    fig = Figure(figsize=(6.5, 5.0 * aspect + 0.8))
    plot_pattern(cp, fig.subplots())
    fig.tight_layout()
    out = io.StringIO()
    fig.savefig(out, format="svg", metadata={"Date": None})
    return out.getvalue()


def _is_fabrication(obj: Any) -> bool:
    return hasattr(obj, "parts") and hasattr(obj, "plan")


def view_glb(obj: Any) -> tuple[bytes, str] | None:
    """The glb (bytes, mm, z up) of a ``FoldedState`` (with its pattern) or a
    ``Fabrication`` (its four printed parts), and a caption; ``None`` for a state made
    without its pattern."""
    if _is_fabrication(obj):
        from origami_cad.fabrication.meshing import parts_tessellation
        from origami_cad.viz.gltf import parts_meshes

        title = obj.pattern.title or "fabrication"
        meshes = parts_meshes(parts_tessellation(obj.parts))
        return glb_bytes(meshes), f"{title}: the printed parts (PLA white, TPU red)"
    cp = getattr(obj, "pattern", None)
    if not isinstance(cp, CreasePattern):
        return None
    caption = f"{cp.title or 'folded state'} at p = {obj.p:g} ({obj.method})"
    return glb_bytes(folding_meshes(cp, [np.asarray(obj.coords, float)])), caption


def view_html(obj: Any) -> str | None:
    """An interactive 3D view for a notebook: a ``<figure>`` holding the glb of
    :func:`view_glb` and the offline WebGL viewer (drag to turn, wheel to zoom).

    ``None`` (the notebook then shows the PNG) when there is nothing to draw, or when the
    glb is over :data:`~origami_cad.viz.report.MAX_EMBEDDED_BYTES`.
    """
    found = view_glb(obj)
    if found is None or len(found[0]) > MAX_EMBEDDED_BYTES:
        return None
    glb, caption = found
    script = f"<script>\n{viewer_script()}</script>"
    return f"<div class='oc-notebook'>{view_figure(glb, caption)}{script}</div>"


def view_png(obj: Any) -> bytes | None:
    """A still picture (PNG bytes, :data:`PNG_SIZE`) of a ``FoldedState`` or ``Fabrication``.

    A pyvista render (off-screen) with the ``viz`` extra; without pyvista, matplotlib's
    3D axes draw the same triangles. ``None`` for a state made without its pattern.
    """
    if not _is_fabrication(obj) and not isinstance(getattr(obj, "pattern", None), CreasePattern):
        return None
    try:
        from origami_cad.viz.pyvista_mesh import show

        image = show(obj, mode="offscreen", window_size=PNG_SIZE)
    except ExtraError:
        return _matplotlib_png(obj)
    from origami_cad.viz.figure import png_bytes

    alpha = np.full((*image.shape[:2], 1), 255, dtype=np.uint8)
    return png_bytes(np.concatenate([image[..., :3], alpha], axis=2), 96)


def _matplotlib_png(obj: Any) -> bytes:
    """The triangles of :func:`view_png` on matplotlib's 3D axes (no pyvista), PNG bytes."""
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    from origami_cad.viz.figure import png_bytes

    fig = Figure(figsize=(PNG_SIZE[0] / 100, PNG_SIZE[1] / 100), dpi=100)
    ax = fig.add_subplot(projection="3d")
    if _is_fabrication(obj):
        from origami_cad.fabrication.assembly import MATERIAL_COLORS
        from origami_cad.fabrication.meshing import parts_tessellation
        from origami_cad.fabrication.solids import PART_MATERIALS

        points = []
        for name, (v, t) in parts_tessellation(obj.parts).items():
            color = MATERIAL_COLORS[PART_MATERIALS[name]]
            ax.add_collection3d(Poly3DCollection(v[t], facecolor=color, edgecolor="none"))
            points.append(v)
        pts = np.vstack(points)
    else:
        cp, pts = obj.pattern, np.asarray(obj.coords, float)
        tris = panel_triangles(cp)
        ax.add_collection3d(Poly3DCollection(pts[tris], facecolor=PANEL_COLOR, edgecolor="none"))
        for letter, color in CREASE_COLORS.items():
            edges = cp.edges[cp.assignments == letter]
            if len(edges):
                ax.add_collection3d(Line3DCollection(pts[edges], colors=color, linewidths=1.2))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre, half = (lo + hi) / 2, max(float(np.max(hi - lo)) / 2, 1e-6)
    ax.set(xlim=(centre[0] - half, centre[0] + half), ylim=(centre[1] - half, centre[1] + half))
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_axis_off()
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    return png_bytes(np.asarray(canvas.buffer_rgba()), 100)
