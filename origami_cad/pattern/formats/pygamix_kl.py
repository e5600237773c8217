"""PyGamiX's generated pieces (``"kl"``): a kinematic line made into Miura rows, mm.

A ``"kl"`` piece of a PyGamiX editable design holds ``data``, a list of entries
``[length, angle]`` (mm, radians): the transition graph of the paper (eq. 1), a chain
of segments each ``length`` long at the absolute ``angle``. PyGamiX draws it as
``copy_time`` identical rows of width ``unit_width`` stacked upwards from the piece's
``tsp`` (its lower-left corner). Within a row:

- the main crease runs along the row's middle, ``unit_width / 2`` above its lower edge;
- between entries ``i`` and ``i + 1`` the line turns by ``d = angle[i+1] - angle[i]``;
  PyGamiX places a Miura joint of sector angle ``a = |atan(tan(d / 2))|`` (drawn flat:
  its folding percent is 0). Its two legs run from the main crease to the row's edges,
  ``(unit_width / 2) / tan(a)`` along x: forward for an *active* joint (the leg's top
  ahead of its feet), backward for a *passive* one. A joint with ``a < 0.1`` rad is no
  joint: its segment's length passes on to the next entry;
- the joints are placed so that a path ``unit_width / 4`` above the row's lower edge
  (the *transition line*) crosses the legs at the entries' cumulated lengths: the
  joint's main-crease point is ``(unit_width / 4) / tan(a)`` ahead of (active) or
  behind (passive) that crossing;
- the entry flag alternates at every joint from ``setting.entry_flag`` (1 valley,
  0 mountain); a joint is active when ``d > 0`` with a mountain flag or ``d < 0`` with
  a valley flag. The main crease after a joint has the joint's flag (valley or
  mountain), an active joint's legs the opposite, a passive joint's legs the same;
  the row's long edges beside a segment are borders on the sheet's outside and the
  opposite of that segment's main crease where two rows meet;
- the row starts and ends with a joint of sector angle 1.57 rad (PyGamiX's
  approximation of 90 degrees, so the ends lean by ``(w / 2) / tan(1.57)``, about
  0.04 mm per 60 mm) whose legs are the sheet's border;
- where the legs of two neighbouring joints would cross, PyGamiX clips them at the
  crossing and joins the clipped ends to the main crease by borders.

The panels are PyGamiX's units, in its order: row by row from ``tsp`` upwards, within
a row segment by segment, the lower panel before the upper one. Each has four corners,
the ends of the legs that bound it, in the order PyGamiX walks its creases (the weights
``contributions[u]`` of an editable design refer to this order): the lower panel from
the previous joint's leg top to this joint's leg top, its foot and the previous foot;
the upper panel from this joint's leg top to the previous top, the previous foot and
this foot. (Where legs are clipped PyGamiX's panel has more corners, at the clips.)

This module only computes; :mod:`.pygamix` reads the file and checks its values.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from itertools import pairwise

import numpy as np

__all__ = ["KL_END_ANGLE", "KL_MIN_TURN", "KLRows", "kl_rows"]

#: The sector angle of the end joints of a row, radians (PyGamiX's 90 degrees).
KL_END_ANGLE = 1.57
#: A turn whose half angle is below this is no joint, radians.
KL_MIN_TURN = 0.1
#: Legs shorter than this along x are drawn vertical, mm.
_FLAT_LEG = 1e-8
#: Lines shorter than this are dropped, mm (PyGamiX's merge distance of points).
_SHORTEST_LINE = 1e-5

# the kinds of a row's long edge beside a joint's segment
_NONE, _BORDER, _SHARED = 0, 1, 2


@dataclass
class _Joint:
    """One Miura joint of a row and the main-crease segment before it (PyGamiX's unit)."""

    x: float  # where the segment before starts (the previous joint's main point), mm
    y: float  # the row's lower edge, mm
    main: float  # the segment's length along x up to this joint's main point, mm
    width: float  # the row's width, mm
    alpha: float  # sector angle, radians
    active: bool
    valley: bool  # the segment's crease: valley (True) or mountain
    border_start: float  # x where the long edges beside the segment start, mm
    legs_border: bool = False  # the end joints: legs are the sheet's border
    up: int = _NONE
    down: int = _NONE
    left: float = 0.0  # where the leg's foot is clipped (0 the edge, 1 the main crease)
    right: float = 1.0  # where the leg's top is clipped
    main_left: float = 0.0
    main_right: float = 1.0
    border_end: float = field(init=False)

    def __post_init__(self) -> None:
        self.dx = (self.width / 2) / math.tan(self.alpha)
        sign = -1.0 if self.active else 1.0
        self.border_end = self.x + self.main + sign * self.dx
        self.border_start = min(self.border_start, self.border_end)

    def next_start(self) -> float:
        """Where the long edges beside the next segment start, mm."""
        return max(self.border_start, self.border_end)

    def leg_dx(self) -> float:
        """The legs' x extent as drawn (0 when nearly vertical), mm."""
        return 0.0 if self.dx < _FLAT_LEG else self.dx

    def upper_leg(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """The upper leg, unclipped: from the main point to the row's upper edge, mm."""
        h, d = self.width / 2, self.leg_dx()
        top = (self.x + self.main, self.y + h)
        foot_x = top[0] - d if self.active else top[0] + d
        return top, (foot_x, self.y + self.width)

    def points(self) -> list[tuple[float, float]]:
        """PyGamiX's key points: main start, main end, leg tops (lower, upper), leg feet
        (lower, upper), long-edge ends (lower, upper), mm."""
        x, y, m, h, d = self.x, self.y, self.main, self.width / 2, self.leg_dx()
        if self.active:
            f = m - (1 - self.main_right) * d
            end = (x, y + h) if f <= 0.0 else (x + f, y + h)
            tx, fx = x + m - (1 - self.right) * d, x + m - d * (1 - self.left)
            ty, fy = self.right * h, self.left * h
        else:
            f = m + self.main_left * d
            end = (x, y + h) if f <= 1e-5 else (x + f, y + h)
            tx, fx = x + m + self.left * d, x + m + d * self.right
            ty, fy = (1 - self.left) * h, (1 - self.right) * h
        edge = self.next_start()
        return [
            (x, y + h),
            end,
            (tx, y + ty),
            (tx, y + 2 * h - ty),
            (fx, y + fy),
            (fx, y + 2 * h - fy),
            (edge, y),
            (edge, y + self.width),
        ]

    def lines(self) -> list[tuple[tuple[float, float], tuple[float, float], str]]:
        """The joint's lines with their FOLD letters (zero-length ones included)."""
        kp = self.points()
        flag, other = ("V", "M") if self.valley else ("M", "V")
        leg = "B" if self.legs_border else (other if self.active else flag)
        out = [(kp[0], kp[1], flag), (kp[1], kp[2], "B"), (kp[1], kp[3], "B")]
        out += [(kp[2], kp[4], leg), (kp[3], kp[5], leg)]
        out += [(kp[4], kp[6], "B"), (kp[5], kp[7], "B")]
        for kind, y in ((self.up, kp[7][1]), (self.down, kp[6][1])):
            if kind != _NONE and self.border_end > self.border_start:
                letter = "B" if kind == _BORDER else other
                out.append(((self.border_end, y), (self.border_start, y), letter))
        return out


def _crossing(c1: tuple, c2: tuple) -> list | None:
    """Where two legs' lines cross, as fractions of their x extents (PyGamiX's rule).

    ``[[0, s1 on c2], [1, e1 on c2], [s2 on c1, 0], [e2 on c1, 1], [X on c1, X on c2]]``,
    or None when they are parallel or cross outside ``c1``'s x extent.
    """
    (x11, y11), (x21, y21) = c1
    (x12, y12), (x22, y22) = c2
    if x21 == x11 or x22 == x12:
        return None  # a vertical leg: refused before (a turn of 180 degrees)
    k1, k2 = (y21 - y11) / (x21 - x11), (y22 - y12) / (x22 - x12)
    if k1 == k2:
        return None
    b1, b2 = y11 - k1 * x11, y12 - k2 * x12
    x0 = (b2 - b1) / (k1 - k2)
    on1 = (x0 - x11) / (x21 - x11)
    if not 0.0 <= on1 <= 1.0:
        return None
    return [
        [0.0, (x11 - x12) / (x22 - x12)],
        [1.0, (x21 - x12) / (x22 - x12)],
        [(x12 - x11) / (x21 - x11), 0.0],
        [(x22 - x11) / (x21 - x11), 1.0],
        [on1, (x0 - x12) / (x22 - x12)],
    ]


def _clip(x: float) -> float:
    return min(max(x, 0.0), 1.0)


def _clip_legs(prev: _Joint, new: _Joint, last: bool) -> None:
    """Clip the legs of two neighbouring joints where they cross (PyGamiX's percents)."""
    if new.active or last:
        p = _crossing(prev.upper_leg(), new.upper_leg())
        if p is None:
            return
        if last or not prev.active:
            prev.right = _clip(p[-1][0])
        else:
            prev.left = _clip(1 - p[-1][0])
        new.left = _clip(1 - p[-1][1])
        return
    p = _crossing(new.upper_leg(), prev.upper_leg())
    if p is None:
        return
    new.main_left = p[2][0]
    if prev.active:
        prev.main_right = 1 - p[0][1]
        prev.right = _clip(1 - p[-1][1])
    else:
        prev.main_left = 1 - p[0][1]
        prev.left = _clip(p[-1][1])
    new.left = _clip(p[-1][0])


def _row(entries: list[list[float]], tsp: tuple[float, float], width: float, valley0: bool,
         edges: tuple[int, int]) -> list[_Joint]:  # fmt: skip
    """One row's joints, from its start joint to its end joint."""
    x0, y0 = tsp
    up, down = edges
    main_x, trans_x, valley = x0, x0, valley0
    start = _Joint(x0, y0, 0.0, width, KL_END_ANGLE, True, valley, x0, True, up, down)
    joints, valley = [start], not valley0
    lengths = [e[0] for e in entries]
    n = len(entries)
    for i in range(n):
        last = i == n - 1
        length = lengths[i]
        if last:
            alpha, active, main = KL_END_ANGLE, True, length - main_x + trans_x
        else:
            turn = math.atan(math.tan((entries[i + 1][1] - entries[i][1]) / 2))
            if abs(turn) < KL_MIN_TURN:
                lengths[i + 1] += length
                continue
            alpha = abs(turn)
            active = (turn > 0) != valley
            lead = (width / 4) / math.tan(alpha)
            main = length - main_x + trans_x + (lead if active else -lead)
        prev = joints[-1]
        new = _Joint(main_x, y0, main, width, alpha, active, valley, prev.next_start(), last, up,
                     down)  # fmt: skip
        prev.border_end = min(prev.border_end, new.border_end)
        _clip_legs(prev, new, last)
        joints.append(new)
        if main > 0.0:
            main_x += main
        if not last:
            trans_x += length
        valley = not valley
    return joints


@dataclass
class KLRows:
    """A ``"kl"`` piece drawn: its lines (mm, FOLD letters) and panels (mm, PyGamiX order)."""

    ends: np.ndarray  # (E, 2, 2) line end points, mm
    letters: list[str]  # each line's FOLD assignment
    panels: np.ndarray  # (P, 4, 2) each panel's corners, mm


def kl_rows(entries: list[list[float]], tsp: tuple[float, float], unit_width: float,
            copy_time: int, valley: bool) -> KLRows:  # fmt: skip
    """Draw a ``"kl"`` piece as PyGamiX does (see the module notes), mm.

    Parameters
    ----------
    entries : list of [float, float]
        ``[length, angle]`` per segment: mm, radians (absolute).
    tsp : (float, float)
        The piece's lower-left corner, mm.
    unit_width : float
        A row's width, mm (> 0).
    copy_time : int
        The number of rows (>= 1).
    valley : bool
        The first segment's entry flag: valley (``setting.entry_flag`` 1) or mountain.
    """
    ends, letters, panels = [], [], []
    for k in range(copy_time):
        up = _BORDER if k == copy_time - 1 else _SHARED
        down = _BORDER if k == 0 else _SHARED
        y = tsp[1] + unit_width * k
        joints = _row([list(e) for e in entries], (tsp[0], y), unit_width, valley, (up, down))
        for j in joints:
            for a, b, letter in j.lines():
                if math.dist(a, b) >= _SHORTEST_LINE:
                    ends.append((a, b))
                    letters.append(letter)
        for a, b in pairwise(joints):
            pa, pb = a.points(), b.points()
            panels.append((pa[2], pb[2], pb[4], pa[4]))  # lower
            panels.append((pb[3], pa[3], pa[5], pb[5]))  # upper
    return KLRows(np.array(ends, dtype=float), letters, np.array(panels, dtype=float))
