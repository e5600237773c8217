"""Creases drawn along the sheet's outline, taken as its border.

Some drawings have no black outline: Origami Simulator's ``Origami_Sphere_16Flaps.svg``
draws its sheet's edge as mountain creases. A crease with a panel on one side only
folds nothing (Origami Simulator gives it no crease spring), so such an edge is border
(``B``), flat; a note counts them. Units: mm.
"""

from __future__ import annotations

import numpy as np

from origami_cad.pattern.model import CreasePattern
from origami_cad.pattern.problems import Problem, Severity

__all__ = ["outline_creases_as_border"]

#: The letters of the creases that turn into border on the outline.
CREASE_LETTERS = ("M", "V", "U", "F", "J")


def outline_creases_as_border(cp: CreasePattern) -> CreasePattern:
    """A copy of ``cp`` (mm) whose creases (mountain, valley, unassigned, facet, join)
    with a panel on one side only are border (``B``, fold angle 0); ``cp`` itself when
    there are none. An ``outline-creases`` note counts them."""
    if not cp.faces:
        return cp
    sides = (cp.edge_faces() >= 0).sum(axis=1)
    outline = np.flatnonzero(np.isin(cp.assignments, CREASE_LETTERS) & (sides == 1))
    if outline.size == 0:
        return cp
    assign = cp.assignments.copy()
    angles = cp.fold_angles.copy()
    assign[outline] = "B"
    angles[outline] = 0.0
    out = CreasePattern(
        cp.vertices,
        cp.edges,
        assign,
        angles,
        metadata=cp.metadata,
        holes=cp.holes,
        tolerance=cp.tolerance,
    )
    note = Problem(
        "outline-creases",
        f"{outline.size} creases with a panel on one side only (the sheet's outline) "
        "taken as border",
        severity=Severity.INFO,
    )
    out.cleanup = cp.cleanup
    out.notes = (*cp.notes, *out.notes, note)
    return out
