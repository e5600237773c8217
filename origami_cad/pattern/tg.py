"""Transition graphs (TG) and the shape angles of their crease patterns (eq. 1).

A TG is a chain of transition vectors ``v_i = (l_i, alpha_i, EF_i)`` starting at
``T_s``: ``l_i`` is the length of main-crease segment ``i`` (mm), ``alpha_i`` its
absolute angle in the folded state, and ``EF_i`` its entry flag (1 valley,
0 mountain; flags alternate). Joint ``i`` (``i = 1 .. n``) joins ``v_{i-1}`` and
``v_i``; its shape angle ``beta_i`` is the angle of the zigzag legs to the main
crease in the flat pattern.

Index convention
----------------
The paper writes eq. 1 with ``EF_i`` and eq. 2 with ``EF_{i-1}``; the two are
inverse to each other only when both flags name the vector *before* the joint
(eq. 1 counts joints from the vector that enters them). This module uses that
reading everywhere: ``beta_i`` depends on ``Delta alpha_i = alpha_i - alpha_{i-1}``
and on ``EF_{i-1}``, so that designing a TG at fold ratio ``p`` with eq. 1 and
folding it to ``p`` with eq. 2 gives back the drawn TG.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from origami_cad._args import Arg, check_fields, check_numbers, checked
from origami_cad.errors import PatternError
from origami_cad.pattern.miura import miura_tessellation
from origami_cad.pattern.model import CreasePattern

__all__ = [
    "DEFAULT_MIN_TURN",
    "TGDesign",
    "design_from_vectors",
    "entry_flags",
    "shape_angles_eq1",
    "tg_pattern",
]

#: Smallest allowed angle between a leg and the main crease, degrees.
DEFAULT_MIN_TURN = 5.0


def entry_flags(entry_flag: int, count: int) -> np.ndarray:
    """``EF_0 .. EF_{count-1}``: the flags alternate from ``EF_0``."""
    return (entry_flag + np.arange(count)) % 2


def shape_angles_eq1(delta_alpha: np.ndarray, flags_before: np.ndarray, p: float) -> np.ndarray:
    """Eq. 1: shape angles ``beta_i`` from the TG drawn at fold ratio ``p``.

    ``beta = arctan(tan(|da|/2) / sin(p pi / 2))`` when
    ``(da >= 0 and EF = 0) or (da < 0 and EF = 1)``, else ``pi`` minus it.

    Parameters
    ----------
    delta_alpha : ndarray
        ``Delta alpha_i = alpha_i - alpha_{i-1}``, radians, in (-pi, pi).
    flags_before : ndarray of int
        ``EF`` of the vector before each joint (see the module notes).
    p : float
        Fold ratio ``theta / pi`` at which the TG is drawn, in (0, 1].

    Returns
    -------
    ndarray
        ``beta_i``, radians, in [0, pi].
    """
    if not 0.0 < p <= 1.0:
        raise PatternError(f"fold_ratio must lie in (0, 1] to design from a drawn TG, got {p}")
    da = np.asarray(delta_alpha, dtype=float)
    ef = np.asarray(flags_before)
    base = np.arctan(np.tan(np.abs(da) / 2.0) / math.sin(p * math.pi / 2.0))
    first = ((da >= 0) & (ef == 0)) | ((da < 0) & (ef == 1))
    return np.where(first, base, math.pi - base)


#: What a :class:`TGDesign`'s scalar fields must be (its lists: finite numbers).
_TG_FIELDS = {
    "entry_flag": Arg("int", choices=(0, 1), optional=False),
    "unit_width": Arg(min=0.0, open_min=True, max=1e5, optional=False),
    "copies": Arg("int", min=1, max=1000, optional=False),
    "hypar_base": Arg("bool", optional=False),
}


@dataclass(frozen=True)
class TGDesign:
    """The design variables of a TG tessellation (what the arm optimiser produces).

    Parameters
    ----------
    lengths : tuple of float
        ``l_0 .. l_n``, mm, measured along the main crease.
    shape_angles : tuple of float
        ``beta_1 .. beta_n``, degrees, in (0, 180).
    entry_flag : int
        ``EF_0``: 1 valley, 0 mountain.
    unit_width : float
        Width of one minimum tessellation unit (two panel rows), mm.
    copies : int
        Units stacked across the width.
    start : tuple of float
        ``T_s`` in the flat pattern and in the TG plane, mm.
    hypar_base : bool
        ``v_0`` is attached to a half hypar unit: ``alpha_0`` follows eq. 3.
    notes : tuple of str
        What the designer reported (e.g. merged small turns).
    """

    lengths: tuple[float, ...]
    shape_angles: tuple[float, ...]
    entry_flag: int = 1
    unit_width: float = 36.0
    copies: int = 3
    start: tuple[float, float] = (0.0, 0.0)
    hypar_base: bool = False
    notes: tuple[str, ...] = field(default=(), compare=False)

    def __post_init__(self) -> None:
        for name, length in (("lengths", None), ("shape_angles", None), ("start", 2)):
            value = check_numbers(
                f"TGDesign: {name}", getattr(self, name), length=length, error=PatternError
            )
            object.__setattr__(self, name, value)
        check_fields(self, PatternError, _TG_FIELDS)
        if len(self.lengths) < 1:
            raise PatternError("a TG needs at least one transition vector")
        if len(self.shape_angles) != len(self.lengths) - 1:
            raise PatternError(
                f"{len(self.lengths)} lengths need {len(self.lengths) - 1} shape angles, "
                f"got {len(self.shape_angles)}"
            )
        for k, v in enumerate(self.lengths):
            if not (math.isfinite(v) and v > 0):
                raise PatternError(f"lengths[{k}] (l_{k}) must be > 0 mm, got {v}")
        for k, b in enumerate(self.shape_angles):
            if not 0.0 < b < 180.0:
                raise PatternError(
                    f"shape_angles[{k}] (beta_{k + 1}) must lie in (0, 180) deg, got {b}"
                )
        if self.entry_flag not in (0, 1):
            raise PatternError(f"entry_flag must be 0 or 1, got {self.entry_flag}")
        if not self.unit_width > 0:
            raise PatternError(f"unit_width must be > 0 mm, got {self.unit_width}")
        if int(self.copies) != self.copies or self.copies < 1:
            raise PatternError(f"copies must be a whole number >= 1, got {self.copies}")

    @property
    def n_vectors(self) -> int:
        return len(self.lengths)

    @property
    def flags(self) -> np.ndarray:
        """``EF_0 .. EF_n``."""
        return entry_flags(self.entry_flag, self.n_vectors)

    @property
    def row_height(self) -> float:
        """Half the unit width, mm."""
        return self.unit_width / 2.0


@checked(
    PatternError,
    fold_ratio=Arg(min=0.0, open_min=True, max=1.0, optional=False),
    entry_flag=Arg("int", choices=(0, 1), optional=False),
    unit_width=Arg(min=0.0, open_min=True, max=1e5, optional=False),
    copies=Arg("int", min=1, max=1000, optional=False),
    min_turn=Arg(min=0.0, open_min=True, max=90.0, optional=False),
)
def design_from_vectors(
    vectors: Sequence[Sequence[float]],
    fold_ratio: float,
    entry_flag: int = 1,
    *,
    unit_width: float = 36.0,
    copies: int = 3,
    start: Sequence[float] = (0.0, 0.0),
    hypar_base: bool = False,
    min_turn: float = DEFAULT_MIN_TURN,
    merge_small_turns: bool = False,
) -> TGDesign:
    """A TG design from transition vectors drawn in their folded shape (eq. 1).

    Parameters
    ----------
    vectors : sequence of (length, angle)
        ``[l_i, alpha_i]``: length in mm and absolute angle in degrees.
    fold_ratio : float
        ``p`` at which the vectors are drawn, in (0, 1].
    entry_flag : int
        ``EF_0`` (1 valley, 0 mountain).
    unit_width, copies, start, hypar_base
        See :class:`TGDesign` (mm).
    min_turn : float
        Smallest angle between legs and main crease, degrees: a turn whose
        ``beta`` or ``180 - beta`` falls below it is an error naming the vector.
    merge_small_turns : bool
        Instead of an error, merge the two vectors around such a turn into one
        (their vector sum) and report the realised heading error in ``notes``.

    Raises
    ------
    PatternError
        Names the vector whose turn is too small or whose values are invalid.
    """
    vec = _checked_vectors(vectors, min_turn)
    # work on complex numbers: one per vector, merging adds them
    items = [
        complex(length * math.cos(math.radians(a)), length * math.sin(math.radians(a)))
        for length, a in vec
    ]
    items, beta, notes = _resolve_small_turns(
        items, fold_ratio, entry_flag, min_turn, merge_small_turns
    )
    lengths = tuple(float(abs(z)) for z in items)
    return TGDesign(
        lengths=lengths,
        shape_angles=tuple(float(v) for v in np.degrees(beta)),
        entry_flag=entry_flag,
        unit_width=unit_width,
        copies=copies,
        start=(float(start[0]), float(start[1])),
        hypar_base=hypar_base,
        notes=tuple(notes),
    )


def _checked_vectors(vectors: Sequence[Sequence[float]], min_turn: float) -> np.ndarray:
    """``vectors`` as an ``(n, 2)`` array of ``[length_mm, angle_deg]``, once valid.

    ``min_turn`` (degrees) is checked too; PatternError naming the first bad value.
    """
    try:
        vec = np.asarray(vectors, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise PatternError(
            "vectors must be a list of [length_mm, angle_deg] pairs of numbers"
        ) from None
    if vec.ndim != 2 or vec.shape[1] != 2 or len(vec) < 1:
        raise PatternError("vectors must be a list of [length_mm, angle_deg] pairs")
    for k, (length, ang) in enumerate(vec):
        if not (math.isfinite(length) and length > 0):
            raise PatternError(f"vectors[{k}]: length must be > 0 mm, got {length}")
        if not math.isfinite(ang):
            raise PatternError(f"vectors[{k}]: angle must be a finite number of degrees")
    if not 0.0 < min_turn < 90.0:
        raise PatternError(f"min_turn must lie in (0, 90) deg, got {min_turn}")
    return vec


def _resolve_small_turns(
    items: list[complex],
    fold_ratio: float,
    entry_flag: int,
    min_turn: float,
    merge: bool,
) -> tuple[list[complex], np.ndarray, list[str]]:
    """``(items, beta, notes)`` once no turn gives a shape angle within ``min_turn``
    degrees of the main crease.

    ``items`` are the vectors as complex numbers (mm); ``beta`` the shape angles
    (eq. 1), radians. Without ``merge`` the first such turn is a PatternError;
    with it the two vectors around it become their sum, noted in ``notes``.
    """
    items = list(items)
    names = [str(k) for k in range(len(items))]
    notes: list[str] = []
    limit = math.radians(min_turn)
    while True:
        ang = np.angle(np.array(items))
        da = np.angle(np.exp(1j * np.diff(ang)))  # wrapped to (-pi, pi]
        flags = entry_flags(entry_flag, len(items))
        beta = shape_angles_eq1(da, flags[:-1], fold_ratio) if len(da) else np.zeros(0)
        small = np.flatnonzero((beta < limit) | (beta > math.pi - limit))
        if not small.size:
            return items, beta, notes
        j = int(small[0]) + 1  # joint between vector j-1 and j
        if not merge:
            raise PatternError(
                f"vectors[{names[j]}]: the turn of {math.degrees(da[j - 1]):.3g} deg from "
                f"vectors[{names[j - 1]}] gives a shape angle of "
                f"{math.degrees(beta[j - 1]):.3g} deg, within {min_turn:g} deg of the main "
                f"crease (set merge_small_turns = true to merge the two vectors)"
            )
        merged = items[j - 1] + items[j]
        err = max(
            abs(math.degrees(np.angle(items[j - 1] / merged))),
            abs(math.degrees(np.angle(items[j] / merged))),
        )
        notes.append(
            f"merged vectors[{names[j - 1]}] and vectors[{names[j]}] (turn "
            f"{math.degrees(da[j - 1]):.3g} deg): realised heading error {err:.3g} deg"
        )
        items[j - 1 : j + 1] = [merged]
        names[j - 1 : j + 1] = [f"{names[j - 1]}+{names[j]}"]


def tg_pattern(design: TGDesign, title: str = "") -> CreasePattern:
    """The crease pattern of a TG design (Miura-based tessellation).

    The main crease of copy 0 starts at ``T_s`` and runs along +x; copies stack
    in +y. Panels are labelled ``c{copy}r{row}s{segment}``.
    """
    return miura_tessellation(
        design.lengths,
        design.shape_angles,
        design.entry_flag,
        design.row_height,
        2 * int(design.copies),
        start=design.start,
        title=title or f"TG tessellation, {design.n_vectors} vectors x {design.copies} copies",
    )
