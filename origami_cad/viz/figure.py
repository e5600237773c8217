"""Saving matplotlib figures: laid out, written atomically, no pyplot state.

Figures are plain :class:`matplotlib.figure.Figure` objects: nothing here
selects a backend or registers a figure with pyplot, so importing
:mod:`origami_cad.viz` changes no global state and works without a display
(``Figure.savefig`` renders PNGs with the Agg canvas whatever the backend).
"""

from __future__ import annotations

import contextlib
import os
import struct
import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from origami_cad._fileio import atomic_path

__all__ = ["PNG_COMPRESS_LEVEL", "new_axes", "png_bytes", "png_subplots", "write_png"]

#: zlib level of the PNGs: 3 compresses a 20 x 20 sheet's panels.png within 2 % of the
#: default (6) in about half the time.
PNG_COMPRESS_LEVEL = 3


def new_axes(figsize: tuple[float, float]) -> Axes:
    """The axes of a new stand-alone figure (inches), for plot functions given no ``ax``.

    Save it with ``ax.figure.savefig(...)``; it is never shown by pyplot.
    """
    return Figure(figsize=figsize).subplots()


@contextlib.contextmanager
def png_subplots(
    path: str | os.PathLike[str], *args: Any, dpi: int = 150, **kwargs: Any
) -> Iterator[tuple[Figure, Any]]:
    """A new ``Figure`` and its ``fig.subplots(*args, **kwargs)``, saved to ``path`` on success.

    Parameters
    ----------
    path : path-like
        The PNG to write: the figure is laid out and written to a temporary file
        renamed onto ``path`` when the block ends without an exception.
    dpi : int
        Resolution, dots per inch.
    **kwargs
        ``figsize`` (inches) goes to the figure, everything else to ``Figure.subplots``.
    """
    fig = Figure(figsize=kwargs.pop("figsize", None))
    axes = fig.subplots(*args, **kwargs)
    yield fig, axes
    fig.tight_layout()
    write_png(fig, path, dpi=dpi)


def write_png(fig: Figure, path: str | os.PathLike[str], *, dpi: float = 150) -> Path:
    """Render ``fig`` with Agg at ``dpi`` (dots per inch) and write it as a PNG (atomic).

    The picture ``fig.savefig(path, dpi=dpi)`` draws, encoded by :func:`png_bytes`
    (about three times faster than Pillow's encoder, whose filter search dominates).
    """
    fig.dpi = dpi
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    data = png_bytes(np.asarray(canvas.buffer_rgba()), dpi)
    with atomic_path(path) as tmp:
        Path(tmp).write_bytes(data)
    return Path(path)


def png_bytes(rgba: np.ndarray, dpi: float) -> bytes:
    """A PNG file of an RGBA picture (``(rows, columns, 4)`` bytes), its resolution ``dpi``.

    RGB when every pixel is opaque, else RGBA; 8 bits a channel; rows unfiltered,
    deflated at :data:`PNG_COMPRESS_LEVEL`; a ``Software`` text chunk naming matplotlib.
    """
    rows, cols = rgba.shape[:2]
    pixels = rgba[..., :3] if bool(np.all(rgba[..., 3] == 255)) else rgba
    raw = np.zeros((rows, 1 + cols * pixels.shape[2]), dtype=np.uint8)  # filter 0: none
    raw[:, 1:] = pixels.reshape(rows, -1)
    per_metre = round(dpi / 0.0254)
    colour = 2 if pixels.shape[2] == 3 else 6
    return b"".join(
        [
            b"\x89PNG\r\n\x1a\n",
            _chunk(b"IHDR", struct.pack(">IIBBBBB", cols, rows, 8, colour, 0, 0, 0)),
            _chunk(b"pHYs", struct.pack(">IIB", per_metre, per_metre, 1)),
            _chunk(b"tEXt", _SOFTWARE),
            _chunk(b"IDAT", zlib.compress(raw.tobytes(), PNG_COMPRESS_LEVEL)),
            _chunk(b"IEND", b""),
        ]
    )


#: The text chunk ``savefig`` writes, as it writes it.
_SOFTWARE = (
    f"Software\0Matplotlib version{matplotlib.__version__}, https://matplotlib.org/".encode()
)


def _chunk(kind: bytes, data: bytes) -> bytes:
    """One PNG chunk: length, type, data, CRC-32 of type and data."""
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
