"""ORIPA's plain-text ``.cp`` crease patterns: read and written.

A ``.cp`` file is the text format ORIPA, Orihime and Rabbit Ear read and write: one line
per crease, five numbers separated by blanks, ``type x0 y0 x1 y1``. The line types are
ORIPA's, read as :mod:`.opx` reads them (:data:`~origami_cad.pattern.formats.opx.ORIPA_TYPES`):

=====  ================  ==================================================
type   ORIPA             here
=====  ================  ==================================================
1      cut line          ``C``; those on the sheet's outer boundary ``B``
2      mountain          ``M``
3      valley            ``V``
4      unassigned        ``U``
other  auxiliary line    ``F`` (flat), as ORIPA reads any other type
=====  ================  ==================================================

As in ``.opx``, y points down the screen: the reader turns it up. The file has no unit:
one unit is read as one millimetre unless ``mm_per_unit`` says otherwise. The writer
writes ``B`` and ``C`` as type 1, ``F`` as 0 (auxiliary); fold angles other than
+-180 degrees, holes and ``J`` (join) edges have no place in the format: a ``J`` edge is
refused, naming it.

A line that does not hold five numbers, a number that is not finite or lies farther than
:data:`~origami_cad.pattern.model.MAX_COORDINATE` mm from the origin, more than
:data:`~origami_cad.pattern.model.MAX_EDGES` lines, or a file with no crease line is a
:class:`~origami_cad.errors.PatternError` naming the file and the line.
"""

from __future__ import annotations

import os
from pathlib import Path

from origami_cad._fileio import atomic_write
from origami_cad._toml import input_file, printable
from origami_cad.errors import PatternError
from origami_cad.pattern.formats.opx import ORIPA_TYPES, oripa_pattern, refuse_joins
from origami_cad.pattern.model import MAX_COORDINATE, MAX_EDGES, CreasePattern
from origami_cad.pattern.planar import Tolerance

__all__ = ["read_cp", "write_cp"]

#: The type code each assignment is written as (``F``: ORIPA's auxiliary line).
_WRITE_TYPES = {"F": 0, "B": 1, "C": 1, "M": 2, "V": 3, "U": 4}


def _lines(p: Path, name: str) -> list[tuple[float, float, float, float, str]]:
    """``(x0, y0, x1, y1, letter)`` of each line of the file, checked."""
    out = []
    try:
        with open(p, encoding="utf-8") as fh:
            for number, text in enumerate(fh, 1):
                words = text.split()
                if not words:
                    continue
                where = f"{name}: line {number}"
                if len(out) >= MAX_EDGES:
                    raise PatternError(f"{name}: more than the limit of {MAX_EDGES:,} lines")
                if len(words) != 5:
                    shown = printable(text.strip(), 60)
                    raise PatternError(f"{where}: expected 'type x0 y0 x1 y1', got {shown!r}")
                try:
                    kind = int(words[0])
                    x0, y0, x1, y1 = (float(w) for w in words[1:])
                except ValueError:
                    shown = printable(text.strip(), 60)
                    raise PatternError(f"{where}: {shown!r} is not five numbers") from None
                if not all(abs(v) <= MAX_COORDINATE for v in (x0, y0, x1, y1)):
                    raise PatternError(
                        f"{where}: a coordinate is not finite or farther than "
                        f"{MAX_COORDINATE:g} from the origin"
                    )
                letter = ORIPA_TYPES.get(kind) if kind in (1, 2, 3, 4) else "F"
                out.append((x0, y0, x1, y1, letter))
    except UnicodeDecodeError:
        raise PatternError(f"{name}: not a text file") from None
    except OSError as exc:
        raise PatternError(f"{name}: cannot be read ({exc.strerror or exc})") from None
    return out


def read_cp(
    path: str | os.PathLike[str],
    mm_per_unit: float | None = None,
    tolerance: Tolerance = None,
) -> CreasePattern:
    """Read an ORIPA ``.cp`` crease pattern (see the module notes), in mm.

    Parameters
    ----------
    path : path-like
        The ``.cp`` file.
    mm_per_unit : float, optional
        Millimetres per unit of the file (default 1).
    tolerance : float, optional
        Lines whose ends lie this close (mm) meet there (default
        :func:`~origami_cad.pattern.planar.import_tolerance`).

    Raises
    ------
    PatternError
        Naming the file, and the line, for a line that is not five numbers, a
        coordinate that is not finite, too many lines, or no crease line at all.
    """
    p, name = input_file(path, PatternError)
    kept = [ln for ln in _lines(p, name) if ln[:2] != ln[2:4]]
    if not kept:
        raise PatternError(f"{name}: no crease lines found (a .cp line is 'type x0 y0 x1 y1')")
    scale = 1.0 if mm_per_unit is None else float(mm_per_unit)
    unit = "1 mm per unit (the file has no unit)"
    if mm_per_unit is not None:
        unit = f"{scale:g} mm per unit (given)"
    metadata = {"title": p.stem, "source_unit": unit}
    letters = [ln[4] for ln in kept]
    return oripa_pattern([ln[:4] for ln in kept], letters, name, metadata, scale, tolerance)


def write_cp(cp: CreasePattern, path: str | os.PathLike[str]) -> Path:
    """Write ``cp`` as an ORIPA ``.cp`` file (mm as units, y turned down), atomically.

    A ``J`` (join) edge, which the format has no type for, is a PatternError naming it.
    """
    refuse_joins(cp, path, ".cp")
    rows = []
    for (a, b), letter in zip(cp.edges, cp.assignments, strict=True):
        (x0, y0), (x1, y1) = cp.vertices[a], cp.vertices[b]
        coords = (float(x0), 0.0 - float(y0), float(x1), 0.0 - float(y1))
        rows.append(" ".join([str(_WRITE_TYPES[str(letter)]), *map(repr, coords)]))
    with atomic_write(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(rows) + "\n")
    return Path(path)


# the registry entries of this format, merged by :mod:`origami_cad.pattern.formats`
readers = {".cp": read_cp}
writers = {".cp": write_cp}
