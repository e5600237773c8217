"""Pictures: matplotlib plots of patterns and trajectories, pyvista renders of folded states.

:func:`to_pyvista` and :func:`show` are the visual checks from a script (docs/visual-checks.md);
:mod:`origami_cad.viz.gltf` writes glb files, which the report's 3D views show.

Everything renders headless and changes no global state: plots are stand-alone matplotlib
``Figure`` objects (no pyplot, no backend selection), renders come from pyvista plotters
created off-screen. The names are imported on first use, so that the report's writer and
the console display load without matplotlib or pyvista.
"""

from origami_cad._lazy import attach_stub

#: The names of ``__init__.pyi``, each listed once there, imported on first use.
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
