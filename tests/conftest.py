"""Shared fixtures: the examples folder, small patterns, an emulated servo bus, and a
helper that says what a picture shows."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.fixture(scope="session")
def examples() -> Path:
    """The repository's examples folder (design, task, route and sequence files)."""
    return EXAMPLES


@pytest.fixture
def small_miura_toml(tmp_path) -> Path:
    """A 2 x 2-panel Miura design file (20 x 25 mm panels, 65 deg), fast to fabricate."""
    path = tmp_path / "small_miura.toml"
    path.write_text(
        '[pattern]\nkind = "miura"\nrows = 2\ncolumns = 2\npanel_length = 20.0\n'
        "panel_width = 25.0\nsector_angle = 65.0\n"
    )
    return path


@pytest.fixture
def emulator():
    """An emulated Dynamixel bus with servos 1 and 2 on a pseudo-terminal."""
    from origami_cad.drive import DynamixelEmulator

    with DynamixelEmulator([1, 2], time_scale=8.0) as emu:
        yield emu


def ink(path: Path, background: float = 0.97) -> tuple[float, tuple[int, int, int, int]]:
    """What a picture shows: the fraction of pixels that are not background (white), and
    the bounding box (left, top, right, bottom) of those pixels, in pixels."""
    from PIL import Image

    image = np.asarray(Image.open(path).convert("L"), dtype=float) / 255.0
    drawn = image < background
    rows, cols = np.flatnonzero(drawn.any(axis=1)), np.flatnonzero(drawn.any(axis=0))
    if not rows.size:
        return 0.0, (0, 0, 0, 0)
    return float(drawn.mean()), (int(cols[0]), int(rows[0]), int(cols[-1]), int(rows[-1]))
