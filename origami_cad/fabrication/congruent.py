"""Panels that are the same shape up to a rigid motion of the plane (plain data).

A Miura's 400 panels are a handful of shapes: every interior panel is one parallelogram
or its mirror image, and the border panels a few more. :func:`congruent_panels` finds,
for each panel, an earlier panel whose footprints and holes its own are, moved by a
rotation about z and a translation (never a reflection: a mirrored panel is its own
shape), so that the solids are built once per shape and copied.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from origami_cad.fabrication.panels import PanelOutline
from origami_cad.pattern.model import Hole

__all__ = ["MATCH_TOLERANCE", "congruent_panels", "panel_points"]

#: Largest distance (mm) between a panel's footprint corners or hole centres and those
#: of the panel it copies, moved; diameters must agree to the same tolerance.
MATCH_TOLERANCE = 1e-7


def panel_points(o: PanelOutline) -> np.ndarray | None:
    """The five footprint rings of a panel, ``(5, k, 2)`` mm; ``None`` if lengths differ."""
    rings = (o.inner, o.outer, o.infill_inner, o.infill_outer, o.midlayer)
    if len({len(r) for r in rings}) != 1:
        return None
    return np.stack([np.asarray(r, dtype=float) for r in rings])


def _key(points: np.ndarray, holes: np.ndarray) -> tuple:
    """Invariants under rigid motion and cyclic shift, rounded: the bucket of a panel."""
    edges = np.roll(points, -1, axis=1) - points
    lengths = np.sort(np.hypot(edges[..., 0], edges[..., 1]), axis=1)
    spread = np.hypot(*(points - points.reshape(-1, 2).mean(0)).reshape(-1, 2).T)
    return (
        points.shape[1],
        len(holes),
        tuple(np.round(lengths.ravel(), 5).tolist()),
        round(float(spread.sum()), 5),
        tuple(np.round(np.sort(holes[:, 2]), 6).tolist()),
    )


def _rigid_fit(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The proper 2D rigid motion (3 x 3 homogeneous) best taking points ``a`` onto ``b``."""
    ca, cb = a.mean(0), b.mean(0)
    h = (a - ca).T @ (b - cb)
    angle = np.arctan2(h[0, 1] - h[1, 0], h[0, 0] + h[1, 1])
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, -s], [s, c]])
    out = np.eye(3)
    out[:2, :2], out[:2, 2] = rot, cb - rot @ ca
    return out


def _apply(m: np.ndarray, xy: np.ndarray) -> np.ndarray:
    return xy @ m[:2, :2].T + m[:2, 2]


def _match(
    ref: tuple[np.ndarray, np.ndarray], own: tuple[np.ndarray, np.ndarray]
) -> np.ndarray | None:
    """The motion taking panel ``ref`` (points, holes) onto ``own``, or ``None``."""
    (pa, ha), (pb, hb) = ref, own
    flat_b = pb.reshape(-1, 2)
    for shift in range(pa.shape[1]):
        flat_a = np.roll(pa, shift, axis=1).reshape(-1, 2)
        m = _rigid_fit(flat_a, flat_b)
        if np.abs(_apply(m, flat_a) - flat_b).max() > MATCH_TOLERANCE:
            continue
        moved = _apply(m, ha[:, :2])
        gap = np.hypot(*(moved[:, None, :] - hb[None, :, :2]).transpose(2, 0, 1))
        nearest = gap.argmin(axis=1) if len(hb) else np.zeros(0, dtype=int)
        same = len(set(nearest.tolist())) == len(hb) and np.all(
            gap[np.arange(len(ha)), nearest] <= MATCH_TOLERANCE
        )
        if same and np.all(np.abs(ha[:, 2] - hb[nearest, 2]) <= MATCH_TOLERANCE):
            return m
    return None


def congruent_panels(
    outlines: Sequence[PanelOutline], holes_of: Sequence[Sequence[Hole]]
) -> list[tuple[int, np.ndarray] | None]:
    """For each panel, ``(earlier panel, motion)`` when it is a moved copy of one, else ``None``.

    Parameters
    ----------
    outlines : sequence of PanelOutline
        The panels' footprints, mm.
    holes_of : sequence of sequences of Hole
        The holes of each panel (same order as ``outlines``), mm.

    Returns
    -------
    list
        ``None`` for a panel built afresh; else the position (in ``outlines``) of a
        panel built afresh and the 3 x 3 homogeneous motion (rotation about z, then a
        translation in mm) taking its footprints and holes onto this panel's, to
        :data:`MATCH_TOLERANCE`.
    """
    buckets: dict[tuple, list[int]] = {}
    data: list[tuple[np.ndarray, np.ndarray] | None] = []
    out: list[tuple[int, np.ndarray] | None] = []
    for k, (o, hs) in enumerate(zip(outlines, holes_of, strict=True)):
        points = panel_points(o)
        holes = np.array([(h.x, h.y, h.diameter) for h in hs], dtype=float).reshape(-1, 3)
        data.append(None if points is None else (points, holes))
        found = None
        if points is not None:
            bucket = buckets.setdefault(_key(points, holes), [])
            for j in bucket:
                m = _match(data[j], data[k])
                if m is not None:
                    found = (j, m)
                    break
            if found is None:
                bucket.append(k)
        out.append(found)
    return out
