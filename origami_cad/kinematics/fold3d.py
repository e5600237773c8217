"""Exact rigid folding of TG tessellations in 3D, in closed form per vertex.

Frame
-----
The flat pattern lies in the plane ``z = 0`` (top face +z); ``p = 0`` gives the
flat pattern exactly. The main crease of copy ``c`` stays in the plane
``y = y_s + 2 c h cos(theta/2)`` (``h`` half the unit width), so the TGs of all
copies lie in parallel planes. A point ``(a, b)`` of the 2D TG (eqs. 2-4) sits
at ``(a, y_c, -b)``: the TG plane is seen from the +y side with the TG's y axis
pointing down -z, which is where a valley fold (FOLD convention: valley
positive, towards the top face) turns the chain in the sense of eq. 2.

Construction
------------
Every panel next to main-crease segment ``k`` is spanned by the segment's unit
direction ``d_k`` and an in-panel perpendicular that tilts out of the TG plane
by ``theta/2`` towards side ``s_k n_k`` (``s_k`` = +1 valley, -1 mountain,
``n_k`` the in-plane normal): ``u_k = cos(theta/2) y + sin(theta/2) s_k n_k``
above the crease, its mirror image ``l_k`` below. The legs at joint ``k`` are
``h (cot(beta_k) d_k + u_k)``; they are shared by both neighbouring panels
exactly because eq. 2 holds, which is what makes the fold rigid. Copy ``c + 1``
is the mirror image of copy ``c`` in the plane of their shared long edge.
"""

from __future__ import annotations

import math

import numpy as np

from origami_cad.errors import PatternError
from origami_cad.kinematics.chain import chain_angles
from origami_cad.pattern.model import CreasePattern
from origami_cad.pattern.tg import TGDesign

__all__ = [
    "face_normals",
    "fold_angles_from_coords",
    "fold_tessellation",
    "fold_tessellation_many",
    "tessellation_vertices",
]


def tessellation_vertices(design: TGDesign, p: float | np.ndarray) -> np.ndarray:
    """3D vertex coordinates of a TG tessellation folded to fold ratio ``p``, mm.

    Parameters
    ----------
    design : TGDesign
        The tessellation.
    p : float or ndarray, shape (P,)
        Fold ratio(s) ``theta / pi`` in [0, 1].

    Returns
    -------
    ndarray, shape (rows + 1, n + 2, 3) for scalar ``p``, or (P, rows + 1, n + 2, 3)
        Vertex ``[r, k]`` is on horizontal line ``r`` (0 = bottom border, odd =
        main creases) at joint ``k`` (0 and n + 1 are the short ends), the same
        order as :func:`origami_cad.pattern.miura.miura_tessellation`.
    """
    scalar = np.ndim(p) == 0
    pv = np.atleast_1d(np.asarray(p, dtype=float))
    if np.any((pv < 0) | (pv > 1)) or not np.all(np.isfinite(pv)):
        raise PatternError(f"fold ratio p must lie in [0, 1], got {pv[(pv < 0) | (pv > 1)][:1]}")
    theta = pv * math.pi
    beta = np.radians(np.asarray(design.shape_angles, dtype=float))
    lengths = np.asarray(design.lengths, dtype=float)
    n = len(lengths) - 1
    h = design.row_height
    rows = 2 * int(design.copies)
    # TG angles (eq. 2, 3); the 3D angle in the x-z plane is their negative
    alpha = -chain_angles(theta, beta, design.entry_flag, design.hypar_base)[0]  # (P, n+1)
    psi = theta / 2.0
    cpsi, spsi = np.cos(psi)[:, None], np.sin(psi)[:, None]
    s = np.where(design.flags == 1, 1.0, -1.0)[None, :]  # +1 valley
    ca, sa = np.cos(alpha), np.sin(alpha)
    zero = np.zeros_like(ca)
    d = np.stack([ca, zero, sa], axis=-1)  # (P, n+1, 3)
    nrm = np.stack([-sa, zero, ca], axis=-1)
    yhat = np.array([0.0, 1.0, 0.0])
    down = -cpsi[..., None] * yhat + (spsi * s)[..., None] * nrm
    # joints on the main crease of copy 0
    x_s, y_s = design.start
    joints = np.zeros((len(pv), n + 2, 3))
    joints[:, 0] = [x_s, y_s, 0.0]
    joints[:, 1:] = joints[:, :1] + np.cumsum(lengths[None, :, None] * d, axis=1)
    # leg vectors to the lower long edge at every joint; the short ends follow
    # the legs of the nearest joint (perpendicular for a single vector)
    cot = np.zeros(n + 2)
    if n:
        cot[1:-1] = 1.0 / np.tan(beta)
        cot[0], cot[-1] = cot[1], cot[-2]
    seg = np.minimum(np.arange(n + 2), n)  # the segment after each joint (last: before)
    leg_down = h * (cot[None, :, None] * d[:, seg] + down[:, seg])
    # copy c is copy 0 translated by c * pitch: the reflection in the shared long
    # edge plane composed with the copy's own mirror symmetry about its TG plane
    pitch = 2.0 * h * cpsi[:, 0]
    out = np.empty((len(pv), rows + 1, n + 2, 3))
    for r in range(rows + 1):
        copy = r // 2
        out[:, r] = joints if r % 2 else joints + leg_down
        out[:, r, :, 1] += (copy * pitch)[:, None]
    return out[0] if scalar else out


def face_normals(cp: CreasePattern, coords: np.ndarray) -> np.ndarray:
    """Unit normal of every face in 3D (Newell's method), shape (f, 3).

    ``coords`` has shape (n, 3), one row per pattern vertex, mm (or (..., n, 3): several
    states at once, normals (..., f, 3)). Normals point to the side of the sheet's top
    face (+z when flat).
    """
    counts = np.array([len(f) for f in cp.faces])
    flat = np.concatenate(cp.faces)
    starts = np.r_[0, np.cumsum(counts)[:-1]]
    nxt = np.arange(len(flat)) + 1
    nxt[starts + counts - 1] = starts
    a, b = coords[..., flat, :], coords[..., flat[nxt], :]
    terms = np.stack(
        [
            (a[..., 1] - b[..., 1]) * (a[..., 2] + b[..., 2]),
            (a[..., 2] - b[..., 2]) * (a[..., 0] + b[..., 0]),
            (a[..., 0] - b[..., 0]) * (a[..., 1] + b[..., 1]),
        ],
        axis=-1,
    )
    nrm = np.add.reduceat(terms, starts, axis=-2)
    length = np.linalg.norm(nrm, axis=-1, keepdims=True)
    if np.any(length == 0):
        raise PatternError("a panel has zero area in the folded state")
    return nrm / length


def fold_angles_from_coords(cp: CreasePattern, coords: np.ndarray) -> np.ndarray:
    """Signed fold angle of every edge of a folded state, radians.

    Valley positive, mountain negative (FOLD convention); 0 for edges with fewer
    than two faces (border). ``coords`` (n, 3) mm, or (..., n, 3) for several states
    (angles (..., m)).
    """
    normals = face_normals(cp, coords)
    ef = cp.edge_faces()
    both = (ef >= 0).all(axis=1)
    out = np.zeros((*coords.shape[:-2], cp.n_edges))
    e = np.flatnonzero(both)
    n_left, n_right = normals[..., ef[e, 0], :], normals[..., ef[e, 1], :]
    axis = coords[..., cp.edges[e, 1], :] - coords[..., cp.edges[e, 0], :]
    axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
    sin = np.einsum("...ij,...ij->...i", np.cross(n_right, n_left), axis)
    cos = np.einsum("...ij,...ij->...i", n_left, n_right)
    out[..., e] = np.arctan2(sin, cos)
    return out


def fold_tessellation(
    design: TGDesign, cp: CreasePattern, p: float
) -> tuple[np.ndarray, np.ndarray]:
    """Fold the crease pattern ``cp`` of ``design`` to fold ratio ``p``.

    Returns ``(coords, fold_angles)``: vertex coordinates (n, 3) in mm in the
    vertex order of ``cp``, and every edge's fold angle in degrees.
    """
    coords, angles = fold_tessellation_many(design, cp, np.array([float(p)]))
    return coords[0], angles[0]


def fold_tessellation_many(
    design: TGDesign, cp: CreasePattern, ratios: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`fold_tessellation` at many fold ratios at once: (P, n, 3) mm, (P, m) degrees."""
    ratios = np.asarray(ratios, dtype=float).reshape(-1)
    grid = tessellation_vertices(design, np.r_[0.0, ratios])
    flat = grid[0].reshape(-1, 3)[:, :2]
    if len(flat) != cp.n_vertices or not np.allclose(flat, cp.vertices, atol=cp.tolerance):
        raise PatternError("the crease pattern is not the tessellation of this TG design")
    coords = grid[1:].reshape(len(ratios), -1, 3)
    return coords, np.degrees(fold_angles_from_coords(cp, coords))
