"""Pictures: matplotlib plots of patterns and trajectories, pyvista renders of folded states.

Everything renders headless (matplotlib's Agg backend, pyvista off-screen).
"""

from origami_cad.viz.pattern_plot import plot_pattern, save_pattern_png

__all__ = ["plot_pattern", "save_pattern_png"]
