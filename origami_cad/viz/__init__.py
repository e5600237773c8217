"""Pictures: matplotlib plots of patterns and trajectories, pyvista renders of folded states.

:func:`to_pyvista` and :func:`show` are the visual checks from a script (docs/visual-checks.md);
:mod:`origami_cad.viz.gltf` writes glb files, which the report's 3D views show.

Everything renders headless and changes no global state: plots are stand-alone matplotlib
``Figure`` objects (no pyplot, no backend selection), renders come from pyvista plotters
created off-screen. The names are imported on first use, so that the report's writer and
the console display load without matplotlib or pyvista.
"""

from __future__ import annotations

import importlib

#: ``typing.TYPE_CHECKING`` without importing typing (true for type checkers only)
TYPE_CHECKING = False

#: Each public name and the module it comes from.
_NAMES = {
    "display_mode": "pyvista_mesh",
    "plot_pattern": "pattern_plot",
    "save_pattern_png": "pattern_plot",
    "show": "pyvista_mesh",
    "to_pyvista": "pyvista_mesh",
}

__all__ = ["display_mode", "plot_pattern", "save_pattern_png", "show", "to_pyvista"]

if TYPE_CHECKING:  # for type checkers; at run time: __getattr__
    from origami_cad.viz.pattern_plot import plot_pattern, save_pattern_png
    from origami_cad.viz.pyvista_mesh import display_mode, show, to_pyvista


def __getattr__(name: str) -> object:
    module = _NAMES.get(name)
    if module is None:
        raise AttributeError(f"module 'origami_cad.viz' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"origami_cad.viz.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
