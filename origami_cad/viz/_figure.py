"""Saving matplotlib figures: laid out, written atomically, always closed."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from typing import Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt

from origami_cad._fileio import atomic_path

__all__ = ["png_subplots"]


@contextlib.contextmanager
def png_subplots(
    path: str | os.PathLike[str], *args: Any, dpi: int = 150, **kwargs: Any
) -> Iterator[tuple[Any, Any]]:
    """``plt.subplots(*args, **kwargs)`` whose figure is saved to ``path`` (PNG) on success.

    The figure is laid out, written to a temporary file renamed onto ``path``, and
    closed whatever happens.
    """
    fig, axes = plt.subplots(*args, **kwargs)
    try:
        yield fig, axes
        fig.tight_layout()
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format="png")
    finally:
        plt.close(fig)
