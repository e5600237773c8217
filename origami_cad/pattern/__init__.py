"""Crease patterns: the data model, validation, generators and file formats.

Examples
--------
>>> from origami_cad.pattern import miura_pattern
>>> cp = miura_pattern(rows=4, columns=6, panel_length=20.0, panel_width=30.0, sector_angle=60.0)
>>> [p for p in cp.check() if p.severity == "error"]
[]
"""

from origami_cad.errors import PatternError
from origami_cad.pattern.check import check_pattern
from origami_cad.pattern.formats.fold import folded_frame, read_fold, read_fold_frames, write_fold
from origami_cad.pattern.io import (
    READ_FORMATS,
    UNITS,
    WRITE_FORMATS,
    read_pattern,
    size_warnings,
    write_pattern,
)
from origami_cad.pattern.miura import miura_pattern
from origami_cad.pattern.model import Assignment, CreasePattern, Hole, Problem, Severity

__all__ = [
    "READ_FORMATS",
    "UNITS",
    "WRITE_FORMATS",
    "Assignment",
    "CreasePattern",
    "Hole",
    "PatternError",
    "Problem",
    "Severity",
    "check_pattern",
    "folded_frame",
    "miura_pattern",
    "read_fold",
    "read_fold_frames",
    "read_pattern",
    "size_warnings",
    "write_fold",
    "write_pattern",
]
