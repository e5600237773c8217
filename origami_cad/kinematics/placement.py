"""Where a folded state is shown: lying on the table, centred on the flat sheet.

The folders keep their own reference where it lies in the flat pattern (a TG
tessellation the start T_s of its first main crease, from which the chain
rises; the degree-4 folder the panel next to its driving crease), so the rest of
the sheet swings up around it: the 6 x 4 Miura folding to p = 0.15 climbs 57 mm
above the table. That frame is what the string models
and the simulation work in; for showing a folded state to a user
(the ``fold`` command's FOLD frames, pictures and animations) it is
moved rigidly, without changing its shape:

1. turned so that the sheet's mean normal (its vector area, the sum over the
   panels of area times unit normal, towards the top face) points up, +z, by the
   smallest rotation that does so. A flat sheet is not turned; a folded Miura
   lies level. When the vector area vanishes (under 1e-6 of the sheet's area, a
   sheet folded flat on edge) the sheet is not turned, or is turned as the
   previous state of a sequence was;
2. moved so that the centroid of its vertices lies above (x, y) the centroid of
   the flat pattern's vertices, and its lowest vertex at z = 0.

At p = 0 the flat pattern is therefore returned as it is.

>>> from origami_cad.pattern.design import miura_design
>>> from origami_cad.kinematics.folding import fold_design
>>> d = miura_design(4, 6, 20.0, 30.0, 60.0)
>>> placed = place_on_table(d.pattern, fold_design(d, 0.15).coords)
>>> float(placed[:, 2].min()), bool(placed[:, 2].max() < 10.0)
(0.0, True)
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from origami_cad._args import Arg, checked
from origami_cad.errors import PatternError
from origami_cad.pattern.model import CreasePattern

__all__ = ["place_on_table", "place_sequence", "vector_area"]

#: below this fraction of the flat sheet's area the vector area gives no direction
_DEGENERATE = 1e-6


def vector_area(cp: CreasePattern, coords: np.ndarray) -> np.ndarray:
    """Sum over the panels of area times unit normal (towards the top face), mm^2, (3,).

    ``coords`` are the folded vertex coordinates (n, 3), mm, in ``cp``'s vertex order.
    """
    rings = np.concatenate(cp.faces)
    counts = np.array([len(f) for f in cp.faces])
    starts = np.r_[0, np.cumsum(counts)[:-1]]
    nxt = np.arange(len(rings)) + 1
    nxt[starts + counts - 1] = starts
    a, b = coords[rings], coords[rings[nxt]]
    return 0.5 * np.cross(a, b).sum(axis=0)


def _turn_up(direction: np.ndarray) -> np.ndarray:
    """The smallest rotation (3 x 3) that turns the unit vector ``direction`` to +z."""
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cross(direction, z)
    s, c = float(np.linalg.norm(axis)), float(direction @ z)
    if s < 1e-15:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])  # upside down: about x
    k = axis / s
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + s * kx + (1 - c) * kx @ kx


def _rotation(cp: CreasePattern, coords: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    area = vector_area(cp, coords)
    size = float(np.linalg.norm(area))
    if size <= _DEGENERATE * float(np.sum(cp.face_areas())):
        return fallback
    return _turn_up(area / size)


def _placed(cp: CreasePattern, coords: np.ndarray, turn: np.ndarray) -> np.ndarray:
    centre = coords.mean(axis=0)
    out = (coords - centre) @ turn.T
    out[:, :2] += cp.vertices.mean(axis=0)
    out[:, 2] -= out[:, 2].min()
    return out


@checked(PatternError, cp=Arg("object", types=(CreasePattern,), optional=False))
def place_on_table(cp: CreasePattern, coords: np.ndarray) -> np.ndarray:
    """A folded state lying on the table (min z = 0), centred on the flat sheet, mm.

    Parameters
    ----------
    cp : CreasePattern
        The flat pattern (its faces and vertex centroid are used).
    coords : ndarray, shape (n, 3)
        Folded vertex coordinates, mm, in ``cp``'s vertex order (any frame).

    Returns
    -------
    ndarray, shape (n, 3)
        The same state moved rigidly: mean normal up, vertex centroid above the
        flat pattern's (x, y), lowest vertex at z = 0 (see the module notes).
    """
    try:
        coords = np.asarray(coords, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise PatternError("place_on_table: coords must be an (n, 3) array of mm") from None
    if coords.shape != (cp.n_vertices, 3) or not np.isfinite(coords).all():
        raise PatternError(
            f"place_on_table: coords must be {cp.n_vertices} finite (x, y, z) points, mm, "
            f"got an array of shape {coords.shape}"
        )
    return _placed(cp, coords, _rotation(cp, coords, np.eye(3)))


def place_sequence(cp: CreasePattern, states: Sequence[np.ndarray]) -> list[np.ndarray]:
    """:func:`place_on_table` of every state; a state with no mean normal (folded flat
    on edge) is turned as the state before it was."""
    turn = np.eye(3)
    out = []
    for coords in states:
        coords = np.asarray(coords, dtype=float)
        turn = _rotation(cp, coords, turn)
        out.append(_placed(cp, coords, turn))
    return out
