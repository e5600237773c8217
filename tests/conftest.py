"""Shared fixtures: the examples folder, small patterns, an emulated servo bus, and a
helper that says what a picture shows."""

from __future__ import annotations

import io
import signal
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
def python_sigint():
    """SIGINT raises ``KeyboardInterrupt`` during the test (Python's own handler), whatever
    the test run inherited: started in the background (``make test &``, ``nohup``) a
    process ignores SIGINT. The disposition found is restored afterwards."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, signal.SIG_DFL if previous is None else previous)


@pytest.fixture
def emulator():
    """An emulated Dynamixel bus with servos 1 and 2 on a pseudo-terminal."""
    from origami_cad.drive import DynamixelEmulator

    with DynamixelEmulator([1, 2], time_scale=8.0) as emu:
        yield emu


def _gray(picture: Path | bytes) -> np.ndarray:
    """A PNG file (or its bytes) as grey levels in [0, 1], one row per pixel row."""
    from PIL import Image

    source = io.BytesIO(picture) if isinstance(picture, bytes) else picture
    return np.asarray(Image.open(source).convert("L"), dtype=float) / 255.0


def ink(path: Path | bytes, background: float = 0.97) -> tuple[float, tuple[int, int, int, int]]:
    """What a picture shows: the fraction of pixels that are not background (white), and
    the bounding box (left, top, right, bottom) of those pixels, in pixels. ``path`` is
    a PNG file or its bytes."""
    image = _gray(path)
    drawn = image < background
    rows, cols = np.flatnonzero(drawn.any(axis=1)), np.flatnonzero(drawn.any(axis=0))
    if not rows.size:
        return 0.0, (0, 0, 0, 0)
    return float(drawn.mean()), (int(cols[0]), int(rows[0]), int(cols[-1]), int(rows[-1]))


def frame_lines(path: Path | bytes, vertical: bool = False) -> list[int]:
    """The first pixel row (column, if ``vertical``) of each dark line across more than
    half the picture: the spines of plot panels."""
    gray = _gray(path)
    lines = (gray < 0.5).mean(axis=0 if vertical else 1) > 0.5
    return [int(i) for i in np.flatnonzero(np.diff(np.r_[0, lines.astype(int)]) == 1)]


def panel_frames(path: Path | bytes) -> list[tuple[int, int]]:
    """The plot panels of a figure stacked from top to bottom: the pixel rows (top,
    bottom) of each panel's frame (its top and bottom spines, see :func:`frame_lines`)."""
    starts = frame_lines(path)
    return list(zip(starts[::2], starts[1::2], strict=False))


def colour_pixels(path: Path | bytes, colour: str, tol: float = 0.08) -> tuple[np.ndarray, ...]:
    """Where a colour is drawn: the rows and columns of the pixels within ``tol`` of
    ``colour`` (``"#rrggbb"``) in every channel."""
    from PIL import Image

    source = io.BytesIO(path) if isinstance(path, bytes) else path
    rgb = np.asarray(Image.open(source).convert("RGB"), dtype=float) / 255.0
    want = np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)]) / 255.0
    return np.nonzero(np.all(np.abs(rgb - want) < tol, axis=-1))


def gif_motion(path: Path) -> tuple[int, float]:
    """What an animation shows: its number of frames, and the largest fraction of pixels
    whose grey level differs by more than 0.1 from the first frame (0: nothing moves)."""
    import imageio.v3 as iio

    frames = np.asarray(iio.imread(path, index=None, plugin="pillow"), dtype=float) / 255.0
    gray = frames[..., :3].mean(axis=-1) if frames.ndim == 4 else frames
    changed = (np.abs(gray - gray[0]) > 0.1).mean(axis=(1, 2))
    return len(frames), float(changed.max())


def three_hole_string(rng: np.random.Generator):
    """The small string the derivative tests use: anchored at (0, 0, 30) mm, through a hole
    in each of three panel frames of nodes 0..7 (random affine coordinates from ``rng``),
    top, bottom, bottom (so it crosses the sheet once: 2.2 mm)."""
    from origami_cad.simulation.cables import SimString

    return SimString(
        np.array([0.0, 0, 30]),
        np.array([[0, 1, 2], [3, 4, 5], [5, 6, 7]]),
        rng.uniform(0.1, 0.4, (3, 2)),
        np.array([1.0, -1, 1]),
        np.array([1.0, -1, -1]),
        2.2,
    )


def refused(read, path: Path, *fragments: str, error: type[Exception] = Exception) -> str:
    """``read(path)`` fails with ``error`` in one printable line (no escape sequences for the
    terminal) that starts with the file's name and contains every fragment; the message."""
    with pytest.raises(error) as info:
        read(path)
    msg = str(info.value)
    assert msg.startswith(str(path)) and msg.isprintable(), msg
    for f in fragments:
        assert f in msg, (f, msg)
    return msg


#: The files whose tests run longest (minutes each on one worker), started first: with
#: ``--dist loadfile`` a file runs on one worker, so a long file started late is the
#: suite's tail; started first, the short files fill the other worker meanwhile.
LONG_FILES = (
    "test_demo.py",
    "test_search_chains.py",
    "test_fabrication.py",
    "test_output_signals.py",
    "test_fuzz_readers.py",
    "test_output_sets.py",
    "test_mjcf.py",
    "test_crawler.py",
)


def pytest_collection_modifyitems(session, config, items):
    """Start the long files first (the order within a file is kept)."""
    rank = {name: k for k, name in enumerate(LONG_FILES)}
    items.sort(key=lambda item: rank.get(item.path.name, len(LONG_FILES)))


def mesh_volume(v: np.ndarray, t: np.ndarray) -> float:
    """The volume (mm^3) a closed, outward triangle mesh encloses."""
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def closed_mesh(t: np.ndarray) -> bool:
    """Every edge used by exactly two triangles, once in each direction."""
    directed = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    forward = {tuple(e) for e in directed.tolist()}
    return len(forward) == len(directed) and all((b, a) in forward for a, b in forward)


def gait_file_text(robot, *, command=None, **options) -> str:
    """A robot's gait as the sequence file crawl writes (the one writer, its gait layout)."""
    from origami_cad.crawler.walk import gait_sequence, gait_sequence_header
    from origami_cad.drive.sequence import dump_sequence

    header = gait_sequence_header(robot, command)
    return dump_sequence(gait_sequence(robot, **options), header=header, layout="gait")


#: The crawler example: its robot file, pattern and four routes, and the script writing them.
CRAWLER = EXAMPLES / "crawler"
CRAWLER_FILES = (
    "crawler.toml",
    "crawler.fold",
    "route_fl.toml",
    "route_fr.toml",
    "route_rl.toml",
    "route_rr.toml",
)


@pytest.fixture(scope="module")
def robot():
    """The crawler example's robot (examples/crawler/crawler.toml), loaded."""
    from origami_cad.crawler.robot import load_robot

    return load_robot(CRAWLER / "crawler.toml")


def copy_crawler(folder: Path, *, leave_out: tuple[str, ...] = ()) -> Path:
    """The crawler example's files copied into ``folder``, but for those in ``leave_out``
    (the test writes its own); the copy's robot file."""
    for name in CRAWLER_FILES:
        if name not in leave_out:
            (folder / name).write_bytes((CRAWLER / name).read_bytes())
    return folder / "crawler.toml"


def make_crawler_script():
    """``examples/crawler/make_crawler.py`` as a module: its design numbers, its ``main``."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_crawler", CRAWLER / "make_crawler.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod
