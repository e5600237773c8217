"""The PNGs of ``viz.figure``: encoded here, the pixels Agg draws, read as such.

:func:`~origami_cad.viz.figure.write_png` must write what ``savefig`` writes: the same
pixels at the same size and resolution, opaque pictures as RGB, a transparent one with its
alpha kept; Pillow must read the file back unchanged.
"""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure
from PIL import Image

from origami_cad.viz.figure import png_bytes, write_png


def _figure(facecolor: str) -> Figure:
    fig = Figure(figsize=(3, 2), facecolor=facecolor)
    ax = fig.subplots()
    ax.plot([0, 1, 2], [0, 1, 0], color="#d62728")
    ax.set_title("a title")
    return fig


@pytest.mark.parametrize(("facecolor", "mode"), [("white", "RGB"), ("none", "RGBA")])
def test_write_png_writes_the_pixels_savefig_writes(tmp_path, facecolor, mode):
    fig = _figure(facecolor)
    fig.savefig(tmp_path / "savefig.png", dpi=120, format="png")
    write_png(_figure(facecolor), tmp_path / "mine.png", dpi=120)
    want, got = Image.open(tmp_path / "savefig.png"), Image.open(tmp_path / "mine.png")
    assert got.mode == mode and got.size == want.size == (360, 240)
    assert got.info["dpi"] == pytest.approx(want.info["dpi"])
    assert np.array_equal(np.asarray(got.convert("RGBA")), np.asarray(want.convert("RGBA")))


def test_png_bytes_round_trips_any_pixels(tmp_path):
    rgba = np.random.default_rng(3).integers(0, 256, (17, 23, 4), dtype=np.uint8)
    path = tmp_path / "noise.png"
    path.write_bytes(png_bytes(rgba, 96))
    assert np.array_equal(np.asarray(Image.open(path)), rgba)
    rgba[..., 3] = 255  # opaque: written as RGB
    path.write_bytes(png_bytes(rgba, 96))
    assert np.array_equal(np.asarray(Image.open(path)), rgba[..., :3])
