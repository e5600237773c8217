"""The names of the package, each imported on first use (origami_cad._lazy.attach_stub)."""

from origami_cad.viz.pattern_plot import plot_pattern, save_pattern_png
from origami_cad.viz.pyvista_mesh import display_mode, show, to_pyvista
