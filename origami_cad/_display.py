"""How the curated objects show themselves in a notebook: IPython's ``_repr_*_`` hooks.

Jupyter (and IPython, VS Code's notebooks, ...) asks an object for its ``_repr_svg_``,
``_repr_html_`` and ``_repr_png_`` and shows the richest answer. A crease pattern and a
design answer with the pattern's plot as SVG (:class:`PatternDisplay`); a folded state and
a fabrication with the report's interactive WebGL view of their glb, inline, and a PNG
for clients that run no JavaScript (:class:`View3DDisplay`).

The pictures are drawn by :mod:`origami_cad.viz.notebook`, imported when an object is
first displayed and never when a stage is imported (as the package's names are imported
on first use), so ``import origami_cad`` and the stages load no matplotlib, pyvista or
viewer. This is the one module of the base that reaches a stage, and only that way.
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["PatternDisplay", "View3DDisplay"]

#: The module that draws what the hooks show (imported on first display).
RENDERER = "origami_cad.viz.notebook"


def _renderer() -> Any:
    return importlib.import_module(RENDERER)


class PatternDisplay:
    """``_repr_svg_``: the flat crease pattern, as ``origami-cad pattern -o cp.svg`` draws it."""

    __slots__ = ()

    def _repr_svg_(self) -> str:
        """The pattern's plot (mm axes, mountain red, valley blue dashed) as SVG text."""
        return _renderer().pattern_svg(self)


class View3DDisplay:
    """``_repr_html_`` (an interactive WebGL view) and ``_repr_png_`` (a still picture)."""

    __slots__ = ()

    def _repr_html_(self) -> str | None:
        """A ``<figure>`` with the glb of this object and the offline WebGL viewer.

        ``None`` (IPython then shows another form) when there is nothing to draw, e.g. a
        folded state made without its pattern.
        """
        return _renderer().view_html(self)

    def _repr_png_(self) -> bytes | None:
        """A still picture, PNG bytes: a pyvista render, or matplotlib's without pyvista."""
        return _renderer().view_png(self)
