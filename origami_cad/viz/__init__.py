"""Pictures: matplotlib plots of patterns and trajectories, pyvista renders of folded states.

Everything renders headless and changes no global state: plots are stand-alone matplotlib
``Figure`` objects (no pyplot, no backend selection), renders come from pyvista plotters
created off-screen.
"""

from origami_cad.viz.pattern_plot import plot_pattern, save_pattern_png

__all__ = ["plot_pattern", "save_pattern_png"]
