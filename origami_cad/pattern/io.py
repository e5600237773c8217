"""Format dispatch: read and write crease patterns by file extension.

=========  ==================  ======================================
extension  module              notes
=========  ==================  ======================================
``.fold``  :mod:`.fold`        FOLD 1.2 (JSON), lossless
``.dxf``   :mod:`.dxf`         layers Mountain/Valley/Cut/Border, mm
``.svg``   :mod:`.svg`         Origami Simulator colour convention
=========  ==================  ======================================

PNG pictures of a pattern are drawn by :func:`origami_cad.viz.plot_pattern`.
"""

from __future__ import annotations

import os
from pathlib import Path

from origami_cad._toml import input_file, printable
from origami_cad.errors import PatternError
from origami_cad.pattern.model import CreasePattern

__all__ = ["READ_FORMATS", "WRITE_FORMATS", "read_pattern", "write_pattern"]

READ_FORMATS = (".fold", ".dxf", ".svg")
WRITE_FORMATS = (".fold", ".dxf", ".svg")


def read_pattern(path: str | os.PathLike[str]) -> CreasePattern:
    """Read a crease pattern from a ``.fold``, ``.dxf`` or ``.svg`` file (mm).

    Raises
    ------
    PatternError
        If the file does not exist, has another extension, or is malformed; the
        message names the file and what is wrong.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in READ_FORMATS:
        raise PatternError(
            f"{printable(str(p), 300)}: unknown crease-pattern format "
            f"{suffix or '(no extension)'!r} (readable: {', '.join(READ_FORMATS)})"
        )
    p, _ = input_file(p, PatternError)
    if suffix == ".fold":
        from origami_cad.pattern.fold import read_fold

        return read_fold(p)
    if suffix == ".dxf":
        from origami_cad.pattern.dxf import read_dxf

        return read_dxf(p)
    from origami_cad.pattern.svg import read_svg

    return read_svg(p)


def write_pattern(cp: CreasePattern, path: str | os.PathLike[str]) -> Path:
    """Write ``cp`` to ``path``; the format follows the extension. Atomic."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix == ".fold":
        from origami_cad.pattern.fold import write_fold

        return write_fold(cp, p)
    if suffix == ".dxf":
        from origami_cad.pattern.dxf import write_dxf

        return write_dxf(cp, p)
    if suffix == ".svg":
        from origami_cad.pattern.svg import write_svg

        return write_svg(cp, p)
    raise PatternError(
        f"{p}: cannot write crease patterns as {suffix or '(no extension)'!r} "
        f"(writable: {', '.join(WRITE_FORMATS)}; .png through origami_cad.viz)"
    )
