"""Pictures: matplotlib plots of patterns and trajectories, pyvista renders of folded states.

:func:`to_pyvista` and :func:`show` are the visual checks from a script (docs/visual-checks.md);
:mod:`origami_cad.viz.gltf` writes glb files, which the report's 3D views show.

Everything renders headless and changes no global state: plots are stand-alone matplotlib
``Figure`` objects (no pyplot, no backend selection), renders come from pyvista plotters
created off-screen.
"""

from origami_cad.viz.pattern_plot import plot_pattern, save_pattern_png
from origami_cad.viz.pyvista_mesh import display_mode, show, to_pyvista

__all__ = ["display_mode", "plot_pattern", "save_pattern_png", "show", "to_pyvista"]
