"""Reading and writing crease patterns by file extension, in mm.

The formats (``.fold``, ``.dxf``, ``.svg``, ``.opx``) are registered in
:mod:`origami_cad.pattern.formats`, one module each; here are the entry points, the
units and the size checks shared by all of them.

PNG pictures of a pattern are drawn by :func:`origami_cad.viz.plot_pattern`.
"""

from __future__ import annotations

import inspect
import math
import os
from pathlib import Path

from origami_cad._args import Arg, checked
from origami_cad._toml import input_file, printable
from origami_cad.errors import PatternError
from origami_cad.pattern.formats import READERS, WRITERS, reader, writer
from origami_cad.pattern.model import CreasePattern, Problem, Severity

__all__ = [
    "PLAUSIBLE_SIZE",
    "READ_FORMATS",
    "SIZE_CHECKS",
    "UNITS",
    "WRITE_FORMATS",
    "mm_per_unit",
    "read_pattern",
    "size_warnings",
    "write_pattern",
]

#: the suffixes :func:`read_pattern` and :func:`write_pattern` know (of the registry)
READ_FORMATS = tuple(READERS)
WRITE_FORMATS = tuple(WRITERS)


#: units a file's coordinates may be declared in: millimetres per unit
UNITS = {
    "mm": 1.0,
    "cm": 10.0,
    "m": 1000.0,
    "in": 25.4,
    "ft": 304.8,
    "pt": 25.4 / 72,
    "px": 25.4 / 96,
}
#: a pattern larger or smaller than this across (mm) gets a ``size`` warning note: under
#: 10 mm no printed panel fits its chamfers and holes (FOLD's unitless examples are 1 or 2
#: units across, read as mm)
PLAUSIBLE_SIZE = (10.0, 5000.0)
#: how a user sets the size (named in the warning)
SIZE_HINT = "--unit mm|cm|m|in|ft|pt|px, --scale FACTOR or --width MM"


def mm_per_unit(unit: str | float) -> float:
    """Millimetres per unit of ``unit``: a name of :data:`UNITS` or a number of mm."""
    if isinstance(unit, str) and unit.strip().lower() in UNITS:
        return UNITS[unit.strip().lower()]
    try:
        value = float(unit)
    except (TypeError, ValueError, OverflowError):
        raise PatternError(
            f"unit {printable(str(unit), 40)!r} is not one of {', '.join(UNITS)} "
            "or a number of millimetres"
        ) from None
    if not (math.isfinite(value) and value > 0):
        raise PatternError(f"a unit must be a length > 0 mm, got {value:g}")
    return value


#: The checks of a pattern file's path and of the options sizing and joining it (``scale``,
#: ``width`` mm, ``tolerance`` mm): :func:`read_pattern`'s, and a design file's reader's.
SIZE_CHECKS = {
    "path": Arg("path", optional=False),
    "scale": Arg(min=0.0, open_min=True, max=1e9),
    "width": Arg(min=0.0, open_min=True, max=1e9),
    "tolerance": Arg(min=0.0, max=1e6),
}


@checked(PatternError, **SIZE_CHECKS)
def read_pattern(
    path: str | os.PathLike[str],
    *,
    unit: str | float | None = None,
    scale: float | None = None,
    width: float | None = None,
    tolerance: float | None = None,
) -> CreasePattern:
    """Read a crease pattern from a ``.fold``, ``.dxf``, ``.svg`` or ``.opx`` file (mm).

    Parameters
    ----------
    path : path-like
        The file.
    unit : str or float, optional
        The unit of the file's coordinates, replacing the one it declares
        (DXF ``$INSUNITS``, FOLD ``frame_unit``, SVG ``width``/``height`` against
        the ``viewBox``): a name of :data:`UNITS` or millimetres per unit.
        Default: the declared unit, mm when the file declares none.
    scale : float, optional
        Then multiply the size by this factor (> 0).
    width : float, optional
        Instead, scale the pattern so that it is this wide (x extent), mm;
        excludes ``unit`` and ``scale``.
    tolerance : float, optional
        Vertices closer than this merge, and a vertex this close to a line lies on
        it, mm of the pattern returned (once sized by ``scale`` or ``width``).
        Default: :data:`~origami_cad.pattern.planar.IMPORT_RELATIVE_TOLERANCE` of
        the pattern's size, which closes the gaps real exports leave and keeps
        their features. What was merged, and the largest gap closed, is in the
        pattern's ``notes`` (code ``merged``) and ``cleanup``.

    Returns
    -------
    CreasePattern
        In mm. A pattern over 5 m or under 10 mm across (its larger extent)
        carries a ``size`` warning in its ``notes``, naming the unit it was read
        in and the options that set the size (see :func:`size_warnings`).

    Raises
    ------
    PatternError
        If the file does not exist, has another extension, or is malformed, or
        an option is not a length; the message names the file and what is wrong.
    """
    p = Path(path)
    read = reader(p)
    if width is not None and (unit is not None or scale is not None):
        raise PatternError("give the width alone, or the unit and/or the scale, not both")
    for name, value in (("scale", scale), ("width", width), ("tolerance", tolerance)):
        if value is not None and not (math.isfinite(value) and value > 0):
            raise PatternError(f"the {name} must be a number > 0, got {value:g}")
    per_unit = None if unit is None else mm_per_unit(unit)
    p, name = input_file(p, PatternError)
    if tolerance is None:
        cp = read(p, per_unit)
    elif "tolerance" not in inspect.signature(read).parameters:
        raise PatternError(f"{name}: the reader of {p.suffix.lower()} files takes no tolerance")
    else:
        cp = read(p, per_unit, tolerance=_file_tolerance(tolerance, scale, width))
    x0, _, x1, _ = cp.bounds
    if width is not None and not x1 > x0:
        raise PatternError(f"{name}: the pattern has no width to scale to {width:g} mm")
    try:
        if width is not None:
            cp = cp.scaled(width / (x1 - x0))
            cp.notes = tuple(n for n in cp.notes if n.code != "size")  # the size is given
        elif scale is not None:
            cp = cp.scaled(scale)
    except PatternError as exc:
        raise PatternError(f"{name}: {exc}") from None
    return _check_size(cp, name)


def _file_tolerance(tolerance: float, scale: float | None, width: float | None):
    """The reader's tolerance (mm of the file as read) of ``tolerance`` mm of the pattern
    once sized: divided by the scale, or a function of the vertices giving it at the
    width they will be scaled to."""
    if width is not None:

        def at_width(used) -> float:
            across = float(used[:, 0].max() - used[:, 0].min()) if len(used) else 0.0
            return tolerance * across / width if across > 0 else tolerance

        return at_width
    return tolerance / scale if scale is not None else tolerance


def _check_size(cp: CreasePattern, name: str) -> CreasePattern:
    """``cp`` with a ``size`` warning note when it is implausibly large or small."""
    x0, y0, x1, y1 = cp.bounds
    across = max(x1 - x0, y1 - y0)
    low, high = PLAUSIBLE_SIZE
    said = any(n.code == "size" and n.severity == Severity.WARNING for n in cp.notes)
    if low <= across <= high or said:  # in range, or the reader warned already (ORIPA)
        return cp
    read_in = cp.metadata.get("source_unit", "mm")
    what = "over 5 m" if across > high else "under 10 mm"
    note = Problem(
        "size",
        f"{name}: the pattern measures {x1 - x0:.4g} x {y1 - y0:.4g} mm, {what} across "
        f"(read in {read_in}); if that is not its size, set it with {SIZE_HINT}",
        severity=Severity.WARNING,
    )
    out = cp.with_metadata()
    out.notes = (*cp.notes, note)
    return out


def size_warnings(cp: CreasePattern) -> list[str]:
    """The ``size`` warning notes of a pattern read by :func:`read_pattern`, as text."""
    return [n.message for n in cp.notes if n.code == "size" and n.severity == Severity.WARNING]


@checked(
    PatternError,
    cp=Arg("object", types=(CreasePattern,), optional=False),
    path=Arg("path", optional=False),
    fmt=Arg("str"),
)
def write_pattern(
    cp: CreasePattern, path: str | os.PathLike[str], *, fmt: str | None = None
) -> Path:
    """Write ``cp`` to ``path``; the format follows the extension (:data:`.formats.WRITERS`),
    or ``fmt`` (``".fold"``, ``".svg"``, ``".dxf"``) for a name without one (``/dev/stdout``).

    Atomic. :class:`PatternError` for an extension no format writes, naming those that do.
    """
    p = Path(path)
    return writer(p if fmt is None else p.with_name(f"pattern{fmt}"))(cp, p)
