"""Old location of :func:`origami_cad.viz.figure.png_subplots`, for callers not yet moved."""

from origami_cad.viz.figure import png_subplots

__all__ = ["png_subplots"]
