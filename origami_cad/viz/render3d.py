"""pyvista renders of folded states, off-screen (no display needed).

Plotters are created with ``off_screen=True``; nothing here sets pyvista's or
VTK's global flags for longer than a render (see :func:`offscreen_plotter`).
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad._fileio import atomic_path
from origami_cad.pattern.model import CreasePattern

__all__ = ["folded_mesh", "offscreen_plotter", "render_folded", "render_folding_gif"]

_PANEL_COLOR = "#f2e6c9"
_CREASE_COLORS = {"M": "#d62728", "V": "#1f4fd6", "B": "#222222", "C": "#2ca02c"}
_STRING_COLOR = "#8e44ad"


def folded_mesh(cp: CreasePattern, coords: np.ndarray):
    """The panels of a folded state as a pyvista ``PolyData`` (polygon faces, mm)."""
    import pyvista as pv

    faces = np.concatenate([np.r_[len(f), f] for f in cp.faces])
    return pv.PolyData(np.asarray(coords, float), faces)


def _add_state(plotter, cp: CreasePattern, coords: np.ndarray, strings=None) -> None:
    import pyvista as pv

    coords = np.asarray(coords, float)
    plotter.add_mesh(folded_mesh(cp, coords), color=_PANEL_COLOR, ambient=0.3, specular=0.2)
    for letter, color in _CREASE_COLORS.items():
        mask = cp.assignments == letter
        if mask.any():
            seg = coords[cp.edges[mask]].reshape(-1, 3)
            width = 2 if letter == "B" else 3
            plotter.add_mesh(pv.line_segments_from_points(seg), color=color, line_width=width)
    for path in strings or ():
        pts = np.asarray(path, float)
        plotter.add_mesh(pv.lines_from_points(pts), color=_STRING_COLOR, line_width=4)


@contextlib.contextmanager
def _quiet_polygon_offset() -> Iterator[None]:
    """For one render: draw lines in front of the polygons they lie on, VTK's logger silent.

    Both are class-wide VTK settings, restored on exit. The polygon offset keeps
    crease lines from z-fighting with their panels; the logger would otherwise
    complain about the missing X server before falling back to off-screen rendering.
    """
    from vtkmodules.vtkCommonCore import vtkLogger
    from vtkmodules.vtkRenderingCore import vtkMapper

    resolve = vtkMapper.GetResolveCoincidentTopology()
    verbosity = vtkLogger.GetCurrentVerbosityCutoff()
    vtkMapper.SetResolveCoincidentTopologyToPolygonOffset()
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    try:
        yield
    finally:
        vtkMapper.SetResolveCoincidentTopology(resolve)
        vtkLogger.SetStderrVerbosity(verbosity)


@contextlib.contextmanager
def offscreen_plotter(window_size: tuple[int, int]) -> Iterator[Any]:
    """A pyvista ``Plotter`` rendering off-screen on a white background, closed on exit.

    Parameters
    ----------
    window_size : (int, int)
        Width and height of the picture, pixels.

    Examples
    --------
    >>> import pyvista as pv
    >>> with offscreen_plotter((64, 48)) as plotter:
    ...     _ = plotter.add_mesh(pv.Sphere())
    ...     image = plotter.screenshot(return_img=True)
    >>> image.shape
    (48, 64, 3)
    """
    import pyvista as pv

    with _quiet_polygon_offset():
        plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
        try:
            plotter.set_background("white")
            yield plotter
        finally:
            plotter.close()


def _set_view(plotter, view: Sequence[float] | str, bounds=None) -> None:
    if isinstance(view, str):
        views = {
            "iso": plotter.view_isometric,
            "xy": plotter.view_xy,
            "xz": plotter.view_xz,
            "yz": plotter.view_yz,
        }
        views[view]()
    else:
        plotter.view_vector(tuple(float(v) for v in view))
    plotter.reset_camera(bounds=bounds)


def render_folded(
    cp: CreasePattern,
    coords: np.ndarray,
    path: str | os.PathLike[str],
    *,
    strings: Sequence[np.ndarray] | None = None,
    window_size: tuple[int, int] = (900, 700),
    view: Sequence[float] | str = "iso",
    title: str = "",
) -> Path:
    """Render a folded state to a PNG: shaded panels, mountain red, valley blue.

    Parameters
    ----------
    cp : CreasePattern
        The pattern (faces and assignments).
    coords : ndarray, shape (n, 3)
        Folded vertex coordinates, mm.
    path : path-like
        Output ``.png`` (written atomically).
    strings : sequence of ndarray (k, 3), optional
        String paths to draw (mm).
    view : str or sequence of float
        ``"iso"``, ``"xy"``, ``"xz"``, ``"yz"`` or a camera direction vector.
    title : str
        Text in the upper-left corner.
    """
    with offscreen_plotter(window_size) as plotter:
        _add_state(plotter, cp, coords, strings)
        _set_view(plotter, view)
        if title:
            plotter.add_text(title, font_size=10, color="black")
        with atomic_path(path) as tmp:
            plotter.screenshot(str(tmp))
    return Path(path)


def render_folding_gif(
    cp: CreasePattern,
    frames: Sequence[np.ndarray],
    path: str | os.PathLike[str],
    *,
    window_size: tuple[int, int] = (640, 480),
    view: Sequence[float] | str = "iso",
    fps: int = 12,
    captions: Sequence[str] | None = None,
) -> Path:
    """Render folded states (coords arrays, mm) to an animated GIF (atomic write).

    The camera is fixed on the bounding box of all frames so the motion shows.
    ``captions``, one per frame, are written in its top-left corner (the state's
    fold ratio, TSA turns or time).
    """
    if not frames:
        raise ValueError("no frames to render")
    if captions is not None and len(captions) != len(frames):
        raise ValueError(f"{len(captions)} captions for {len(frames)} frames")
    import pyvista as pv

    bounds = pv.PolyData(np.concatenate([np.asarray(f, float) for f in frames])).bounds
    with atomic_path(path) as tmp:
        with offscreen_plotter(window_size) as plotter:
            gif, encoded = _gif_writer(plotter, fps)
            for k, coords in enumerate(frames):
                plotter.clear_actors()
                _add_state(plotter, cp, coords)
                if captions is not None:
                    plotter.add_text(captions[k], font_size=10, color="black")
                if k == 0:
                    _set_view(plotter, view, bounds=bounds)
                plotter.write_frame()
            plotter.mwriter = None  # pyvista's close would swallow the writer's errors
            gif.close()
        # the encoded GIF is in memory: a full disk or a quota fails here, loudly
        with open(tmp, "wb") as fh:
            fh.write(encoded.getvalue())
    return Path(path)


def _gif_writer(plotter, fps: int):
    """An imageio GIF writer into memory, as the plotter's movie writer (what
    ``plotter.open_gif`` makes, with its defaults, but never writing a file: an
    error on the disk would only surface in the writer's ``__del__``, ignored)."""
    import io

    import imageio

    buffer = io.BytesIO()
    writer = imageio.get_writer(
        buffer, format=".gif", mode="I", loop=0, palettesize=256,
        subrectangles=False, duration=1000 / fps,
    )  # fmt: skip
    plotter.mwriter = writer
    return writer, buffer
