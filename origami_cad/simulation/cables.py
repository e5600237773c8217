"""Strings through holes on the panel faces: length, gradient and exact Hessian.

A string runs from its anchor (the TSA's end, fixed in space) through an ordered
list of holes. Each hole moves with its panel: it is a point of the panel's frame
(three nodes and two affine coordinates), and the string reaches it on the top or
the bottom face, half the panel thickness off the mid-surface along the panel's
unit normal. The string slides freely through the holes, so only its total length
matters: the TSA's share (eq. 8 or the onboard model, the same
``TSAParams.consumed`` as the DCQC simulation) over the anchor's free stretch plus
the straight segments between holes plus the thickness crossed where the string
changes face. Units: mm, N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from origami_cad.simulation.mechanics import skew

__all__ = ["SimString", "StringSet", "string_derivatives", "string_length", "string_lengths"]


@dataclass
class SimString:
    """A string in the model: anchor (mm), holes as node triples with affine coordinates.

    The anchor is fixed in space, or mounted on a panel (an onboard TSA): then
    ``anchor_tri``/``anchor_ab`` place it on that panel and ``anchor`` holds
    ``(x, y, height)``, the height above the panel's mid-surface in mm.
    """

    anchor: np.ndarray  # (3,)
    tri: np.ndarray  # (k, 3) node indices of each hole's panel frame
    ab: np.ndarray  # (k, 2) affine coordinates of each hole in that frame
    orient: np.ndarray  # (k,) +1/-1: keeps the frame normal on the top face
    sides: np.ndarray  # (k,) +1 top / -1 bottom: face along which the string reaches hole k
    through: float  # length spent crossing the sheet where the side changes, mm
    free_length: float = math.inf  # L0: the string's length (mm)
    stiffness: float = 0.0  # EA / L0, N/mm
    anchor_tri: np.ndarray | None = None  # (3,) the mounting panel's frame, or None: fixed
    anchor_ab: np.ndarray | None = None  # (2,)
    anchor_orient: float = 1.0

    @property
    def leave_sides(self) -> np.ndarray:
        """Face along which the string leaves each hole (+1 top, -1 bottom)."""
        return np.r_[self.sides[1:], self.sides[-1]]

    @property
    def mounted(self) -> bool:
        """Whether the anchor rides on a panel."""
        return self.anchor_tri is not None

    def frames(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every frame the string's points live in: holes, then the anchor's panel."""
        if not self.mounted:
            return self.tri, self.ab, self.orient
        return (
            np.vstack([self.tri, self.anchor_tri[None]]),
            np.vstack([self.ab, self.anchor_ab[None]]),
            np.r_[self.orient, self.anchor_orient],
        )


@dataclass
class StringSet:
    """The strings of a structure and the TSA that shortens them."""

    strings: list[SimString]
    offset: float  # half the panel thickness, mm
    tsa: object  # TSAParams
    theta: float = 0.0  # TSA rotation, rad
    _packed: tuple | None = None

    def packed(self) -> tuple:
        """The strings' holes and mounts as flat arrays for :func:`string_lengths` (cached;
        the anchors, which the mean-pose placement moves, are read afresh each time).
        """
        if self._packed is None:
            ss = self.strings
            starts = np.cumsum([0] + [len(s.tri) for s in ss]).astype(np.int64)
            mount_tri = np.array(
                [s.anchor_tri if s.mounted else (-1, -1, -1) for s in ss], dtype=np.int64
            ).reshape(-1, 3)
            mount_ab = np.array(
                [s.anchor_ab if s.mounted else (0.0, 0.0) for s in ss], dtype=float
            ).reshape(-1, 2)
            self._packed = (
                np.ascontiguousarray(np.vstack([s.tri for s in ss]), dtype=np.int64),
                np.ascontiguousarray(np.vstack([s.ab for s in ss]), dtype=float),
                np.concatenate([np.asarray(s.orient, float) for s in ss]),
                np.concatenate([np.asarray(s.sides, float) for s in ss]),
                np.concatenate([np.asarray(s.leave_sides, float) for s in ss]),
                starts,
                mount_tri,
                mount_ab,
                np.array([s.anchor_orient for s in ss], dtype=float),
                np.array([s.through for s in ss], dtype=float),
            )
        return self._packed


@njit(cache=True)
def _lengths_kernel(
    x, tri, ab, orient, sides, leave, starts, mount_tri, mount_ab, mount_orient, anchors, e
):
    """Each string's anchor stretch ``x_dis`` and the rest of its route (k,), mm."""
    k = len(starts) - 1
    x_dis = np.zeros(k)
    rest = np.zeros(k)
    arrive = np.zeros(3)
    prev = np.zeros(3)
    for si in range(k):
        anchor = anchors[si].copy()
        if mount_tri[si, 0] >= 0:
            c, nh = _frame_point(x, mount_tri[si], mount_ab[si], mount_orient[si])
            anchor = c + anchors[si, 2] * nh
        for h in range(starts[si], starts[si + 1]):
            c, nh = _frame_point(x, tri[h], ab[h], orient[h])
            arrive = c + e * sides[h] * nh
            if h == starts[si]:
                d = arrive - anchor
                x_dis[si] = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            else:
                d = arrive - prev
                rest[si] += math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            prev = c + e * leave[h] * nh
    return x_dis, rest


@njit(cache=True, inline="always")
def _frame_point(x, t, ab, orient):
    """A frame's point ``ab`` and its unit top normal in ``x``."""
    v0 = x[t[0]]
    e1 = x[t[1]] - v0
    e2 = x[t[2]] - v0
    n = np.empty(3)
    n[0] = e1[1] * e2[2] - e1[2] * e2[1]
    n[1] = e1[2] * e2[0] - e1[0] * e2[2]
    n[2] = e1[0] * e2[1] - e1[1] * e2[0]
    n *= orient / math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
    return v0 + ab[0] * e1 + ab[1] * e2, n


def string_lengths(x: np.ndarray, strings: StringSet) -> tuple[np.ndarray, np.ndarray]:
    """Every string's demanded length (incl. the TSA's share) and ``x_dis``, (k,) each, mm.

    The same as :func:`string_length` string by string, compiled over all strings.
    """
    if not strings.strings:
        return np.zeros(0), np.zeros(0)
    tri, ab, orient, sides, leave, starts, mtri, mab, morient, through = strings.packed()
    anchors = np.array([s.anchor for s in strings.strings], dtype=float)
    x_dis, rest = _lengths_kernel(
        np.ascontiguousarray(x, dtype=float),
        tri,
        ab,
        orient,
        sides,
        leave,
        starts,
        mtri,
        mab,
        morient,
        anchors,
        float(strings.offset),
    )
    return np.asarray(
        strings.tsa.consumed(strings.theta, x_dis), dtype=float
    ) + rest + through, x_dis


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (k, 3) arrays (np.cross costs more on small arrays)."""
    return np.column_stack(
        [
            a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1],
            a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
            a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0],
        ]
    )


def _frames(x: np.ndarray, tri: np.ndarray, ab: np.ndarray, orient: np.ndarray):
    v0, v1, v2 = x[tri[:, 0]], x[tri[:, 1]], x[tri[:, 2]]
    e1, e2 = v1 - v0, v2 - v0
    n = _cross(e1, e2) * orient[:, None]
    norm = np.linalg.norm(n, axis=1)
    centre = v0 + ab[:, :1] * e1 + ab[:, 1:] * e2
    return e1, e2, n, norm, centre


def _points(x: np.ndarray, s: SimString, e: float):
    """Frames, and the string's points: arrive and leave at each hole, then the anchor."""
    tri, ab, orient = s.frames()
    e1, e2, n, norm, centre = _frames(x, tri, ab, orient)
    nh = n / norm[:, None]
    k = len(s.tri)
    arrive = centre[:k] + e * s.sides[:, None] * nh[:k]
    leave = centre[:k] + e * s.leave_sides[:, None] * nh[:k]
    anchor = centre[k] + s.anchor[2] * nh[k] if s.mounted else s.anchor
    return (tri, ab, orient, e1, e2, n, norm), arrive, leave, anchor


def string_length(x: np.ndarray, s: SimString, strings: StringSet) -> tuple[float, float]:
    """(length demanded by the string incl. the TSA's share, anchor stretch x_dis), mm."""
    _, arrive, leave, anchor = _points(x, s, strings.offset)
    x_dis = float(np.linalg.norm(arrive[0] - anchor))
    rest = float(np.linalg.norm(arrive[1:] - leave[:-1], axis=1).sum()) + s.through
    return float(strings.tsa.consumed(strings.theta, x_dis)) + rest, x_dis


def _exit_jacobians(e1, e2, n, norm, orient, ab, off: np.ndarray) -> np.ndarray:
    """d(point)/d(v0, v1, v2) per frame, (k, 3, 9): offset ``off`` (k,) along the normal."""
    nh = n / norm[:, None]
    proj = (np.eye(3)[None] - nh[:, :, None] * nh[:, None, :]) / norm[:, None, None]
    o = orient[:, None, None]
    # d n = o (d e1 x e2 + e1 x d e2) = o (-[e2]x d e1 + [e1]x d e2)
    dn_de1, dn_de2 = -skew(e2) * o, skew(e1) * o
    eye = np.eye(3)[None]
    d1 = ab[:, 0, None, None] * eye + off[:, None, None] * proj @ dn_de1
    d2 = ab[:, 1, None, None] * eye + off[:, None, None] * proj @ dn_de2
    return np.concatenate([eye - d1 - d2, d1, d2], axis=2)


def _normal_curvature(e1, e2, n, norm, orient, w: np.ndarray) -> np.ndarray:
    """Hessian of ``w . n_hat`` w.r.t. (v0, v1, v2) per frame, (k, 9, 9), for fixed ``w`` (k, 3)."""
    # w . (o m / |m|) with m = e1 x e2: fold the sign into w and use m's own unit vector
    mh = n / norm[:, None] * orient[:, None]
    w = w * orient[:, None]
    wn = np.einsum("ij,ij->i", w, mh)
    u = w - wn[:, None] * mh
    perp = np.eye(3)[None] - mh[:, :, None] * mh[:, None, :]
    h_nn = (
        -(
            wn[:, None, None] * perp
            + mh[:, :, None] * u[:, None, :]
            + u[:, :, None] * mh[:, None, :]
        )
        / (norm**2)[:, None, None]
    )
    grad_n = u / norm[:, None]
    jn = np.concatenate([-skew(e2), skew(e1)], axis=2)  # dm / d(e1, e2), (k, 3, 6)
    h_ee = np.transpose(jn, (0, 2, 1)) @ h_nn @ jn
    sm = skew(grad_n)
    h_ee[:, :3, 3:] -= sm
    h_ee[:, 3:, :3] += sm
    eye = np.eye(3)
    t = np.block([[-eye, eye, np.zeros((3, 3))], [-eye, np.zeros((3, 3)), eye]])  # (6, 9)
    return t.T @ h_ee @ t


def string_derivatives(
    x: np.ndarray, s: SimString, strings: StringSet, hessian: bool = True
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Gradient and exact Hessian of a string's demanded length w.r.t. its nodes.

    Returns ``(nodes, grad, hess)``: the nodes of the string's panels (m,), the
    gradient (m, 3), dimensionless, and the Hessian (3m, 3m), 1/mm, rows
    ``3 node + axis`` in the order of ``nodes`` (None when ``hessian`` is False).
    The Hessian holds the segments' transverse stiffness ``(I - u u^T) / length``,
    the TSA's share of the anchor stretch and the curvature of the points'
    offsets along their panels' normals.
    """
    e = strings.offset
    (tri, ab, orient, e1, e2, n, norm), arrive, leave, anchor = _points(x, s, e)
    k = len(s.tri)
    nf = len(tri)
    offsets_a = np.r_[e * s.sides, [s.anchor[2]] * (nf - k)]
    offsets_l = np.r_[e * s.leave_sides, [0.0] * (nf - k)]
    ja = _exit_jacobians(e1, e2, n, norm, orient, ab, offsets_a)  # arrive (or the anchor)
    jl = _exit_jacobians(e1, e2, n, norm, orient, ab, offsets_l)
    ga = np.zeros((nf, 3))  # d length / d point: arrive at each hole, then the anchor
    gl = np.zeros((nf, 3))
    first = arrive[0] - anchor
    x_dis = float(np.linalg.norm(first))
    _, _, rate, curv = (float(v) for v in strings.tsa.consumed_derivatives(strings.theta, x_dis))
    u0 = first / x_dis
    ga[0] += rate * u0
    if s.mounted:
        ga[k] -= rate * u0
    seg = arrive[1:] - leave[:-1]
    seg_len = np.linalg.norm(seg, axis=1)
    unit = seg / seg_len[:, None]
    ga[1:k] += unit
    gl[: k - 1] -= unit
    per_frame = np.einsum("ko,koi->ki", ga, ja) + np.einsum("ko,koi->ki", gl, jl)  # (nf, 9)
    nodes, inverse = np.unique(tri.ravel(), return_inverse=True)
    inverse = inverse.reshape(nf, 3)
    grad = np.zeros((len(nodes), 3))
    np.add.at(grad, inverse.ravel(), per_frame.reshape(-1, 3))
    if not hessian:
        return nodes, grad, None
    m = len(nodes)
    hess = np.zeros((3 * m, 3 * m))
    dofs = (3 * inverse[:, :, None] + np.arange(3)).reshape(nf, 9)  # local dofs of each frame

    def scatter(rows: np.ndarray, cols: np.ndarray, blocks: np.ndarray) -> None:
        np.add.at(hess, (rows[:, :, None], cols[:, None, :]), blocks)

    def pair(jp, jq, dp, dq, hs) -> None:  # a segment between points p and q, (s, 3, 9) each
        jpt, jqt = np.transpose(jp, (0, 2, 1)), np.transpose(jq, (0, 2, 1))
        scatter(dp, dp, jpt @ hs @ jp)
        scatter(dq, dq, jqt @ hs @ jq)
        scatter(dp, dq, -(jpt @ hs @ jq))
        scatter(dq, dp, -(jqt @ hs @ jp))

    # the anchor's stretch: rate' u u^T + rate (I - u u^T) / x_dis (eq. 8's analytic
    # derivatives, TSAParams.consumed_derivatives)
    uu = np.outer(u0, u0)
    h0 = (curv * uu + rate * (np.eye(3) - uu) / x_dis)[None]
    if s.mounted:
        pair(ja[k : k + 1], ja[:1], dofs[k : k + 1], dofs[:1], h0)
    else:
        scatter(dofs[:1], dofs[:1], ja[:1].transpose(0, 2, 1) @ h0 @ ja[:1])
    if k > 1:  # segments leave_k -> arrive_(k+1)
        hs = (np.eye(3)[None] - unit[:, :, None] * unit[:, None, :]) / seg_len[:, None, None]
        pair(jl[: k - 1], ja[1:k], dofs[: k - 1], dofs[1:k], hs)
    # the points' normal offsets curve with their panels
    w = offsets_a[:, None] * ga + offsets_l[:, None] * gl
    scatter(dofs, dofs, _normal_curvature(e1, e2, n, norm, orient, w))
    return nodes, grad, hess
