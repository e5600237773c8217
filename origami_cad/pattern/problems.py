"""What a check or a clean-up found: :class:`Problem` (with its :class:`Severity`), and
the notes of what :func:`~origami_cad.pattern.planar.normalise` changed
(:func:`cleanup_notes`)."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from origami_cad.pattern.planar import FREE_END_REACH, SNAP_FRACTION, Cleanup

__all__ = ["CLEANUP_CODES", "NEAR_TOLERANCE", "Problem", "Severity", "cleanup_notes"]

#: the codes of the notes :func:`cleanup_notes` writes
CLEANUP_CODES = frozenset({"merged", "normalised", "duplicate-conflict"})


class Severity(StrEnum):
    """How bad a :class:`Problem` is."""

    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


@dataclass(frozen=True)
class Problem:
    """One finding of :meth:`CreasePattern.check` or of normalisation.

    Parameters
    ----------
    code : str
        Short machine-readable kind, e.g. ``"maekawa"``, ``"open-border"``.
    message : str
        What is wrong, naming the vertex, edge or face.
    location : tuple of float or None
        Where, in pattern coordinates (mm).
    severity : Severity
        ``error`` (the pattern cannot be folded or fabricated as is),
        ``warning`` or ``info`` (what normalisation changed).
    """

    code: str
    message: str
    location: tuple[float, float] | None = None
    severity: Severity = Severity.ERROR

    def __str__(self) -> str:
        where = ""
        if self.location is not None:
            where = f" at ({self.location[0]:.4g}, {self.location[1]:.4g}) mm"
        return f"{self.severity.value}: {self.code}{where}: {self.message}"


#: A gap closed larger than this fraction of the tolerance makes the ``merged`` note a
#: warning: the gaps of rounding lie far below the tolerance, a feature near it.
NEAR_TOLERANCE = 0.5
_NEAR = (
    ": gaps this close to the tolerance may be features of the pattern, not rounding; "
    "check them, or set a smaller --tolerance"
)


def _gap(mm: float) -> str:
    return f"{mm:.2g} mm" if mm > 0 else "0 mm"


def cleanup_notes(c: Cleanup) -> list[Problem]:
    """The notes of a :class:`~origami_cad.pattern.planar.Cleanup`: what was merged,
    with the largest gap closed and the tolerance (``merged``: a warning when a gap
    closed is over :data:`NEAR_TOLERANCE` of the tolerance, as a feature of the pattern
    may have been merged), and what else changed (``normalised``); coincident creases
    of different letters are warnings."""
    notes: list[Problem] = []
    tol = f"tolerance {c.tolerance:.2g} mm"
    snap = SNAP_FRACTION * c.tolerance
    for count, gap, within, text in (
        (
            c.merged,
            c.merged_gap,
            c.tolerance,
            "vertices merged with a neighbour closer than the tolerance",
        ),
        (
            c.snapped,
            c.snapped_gap,
            snap,
            f"vertices off an edge by less than {_gap(snap)} put on it",
        ),
        (c.crossings_merged, c.crossing_gap, c.tolerance, "crossing points merged with a vertex"),
        (
            c.reached,
            c.reached_gap,
            FREE_END_REACH * c.tolerance,
            f"free ends of lines put on a line within {_gap(FREE_END_REACH * c.tolerance)} of them",
        ),
    ):
        near = gap > NEAR_TOLERANCE * within
        if count:
            notes.append(
                Problem(
                    "merged",
                    f"{count} {text} (largest gap {_gap(gap)}; {tol})" + (_NEAR if near else ""),
                    severity=Severity.WARNING if near else Severity.INFO,
                )
            )
    for count, text in (
        (c.coincident, "coincident vertices joined (ends of lines at the same point)"),
        (c.zero_length, "zero-length edges dropped"),
        (c.split, "edges split at T-junctions or crossings"),
        (c.crossings, "vertices added where edges cross"),
        (c.duplicates, "duplicate edges dropped"),
        (c.unused, "unused vertices dropped"),
    ):
        if count:
            notes.append(Problem("normalised", f"{count} {text}", severity=Severity.INFO))
    for mid, letter, kept in c.conflicts:
        notes.append(
            Problem(
                "duplicate-conflict",
                f"two coincident edges are {letter} and {kept}; kept {kept}",
                mid,
                Severity.WARNING,
            )
        )
    return notes
