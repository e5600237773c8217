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
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from origami_cad.simulation.mechanics import skew

__all__ = [
    "SimString",
    "StringSet",
    "string_derivatives",
    "string_hessian_pattern",
    "string_length",
    "string_lengths",
    "update_capstan",
]


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
    weights: np.ndarray | None = None  # (k,) capstan weight of the segment reaching hole h
    cache: dict = field(default_factory=dict, repr=False, compare=False)

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
    friction: float = 0.0  # string-on-hole friction coefficient (capstan law)
    _packed: tuple | None = None

    def packed(self) -> tuple:
        """The strings' holes and mounts as flat arrays for :func:`string_lengths` (cached;
        the anchors, which the mean-pose placement moves, are read afresh each time).
        """
        key = tuple((id(s), len(s.tri), s.mounted) for s in self.strings)
        if self._packed is None or self._packed[0] != key:
            ss = self.strings
            starts = np.cumsum([0] + [len(s.tri) for s in ss]).astype(np.int64)
            mount_tri = np.array(
                [s.anchor_tri if s.mounted else (-1, -1, -1) for s in ss], dtype=np.int64
            ).reshape(-1, 3)
            mount_ab = np.array(
                [s.anchor_ab if s.mounted else (0.0, 0.0) for s in ss], dtype=float
            ).reshape(-1, 2)
            self._packed = (
                key,
                (
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
                ),
            )
        return self._packed[1]


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
            _, _, n, norm, c = _frame(x, mount_tri[si], mount_ab[si], mount_orient[si])
            anchor = c + anchors[si, 2] * n / norm
        for h in range(starts[si], starts[si + 1]):
            _, _, n, norm, c = _frame(x, tri[h], ab[h], orient[h])
            nh = n / norm
            arrive = c + e * sides[h] * nh
            if h == starts[si]:
                d = arrive - anchor
                x_dis[si] = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            else:
                d = arrive - prev
                rest[si] += math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            prev = c + e * leave[h] * nh
    return x_dis, rest


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


def update_capstan(x: np.ndarray, strings: StringSet) -> None:
    """Set every string's capstan weights from the state ``x`` (n, 3) mm (friction > 0).

    The weights are held while the solver finds the next equilibrium (lagged by one
    state). They weigh each segment's force in :func:`string_derivatives` (the
    tension at the pulled end times the weight), not the string's length: friction
    changes the forces, not what the length allows. Without friction they stay 1.
    """
    if strings.friction <= 0:
        return
    from origami_cad.strings.friction import capstan_weights

    for s in strings.strings:
        _, arrive, leave, anchor = _points(x, s, strings.offset)
        s.weights = capstan_weights(anchor, arrive, leave, strings.friction)


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


def _topology(s: SimString, e: float):
    """A string's frames, the nodes they use, each frame's local dofs and the points'
    normal offsets (arrive, leave), cached on the string: they depend on the route only
    (its holes and its mount; a fixed anchor's place, which the mean pose moves, is not
    among them).
    """
    mount = (tuple(int(v) for v in s.anchor_tri), float(s.anchor[2])) if s.mounted else ()
    key = ("topology", e, len(s.tri), mount)  # what the arrays below depend on
    if key not in s.cache:
        tri, ab, orient = s.frames()
        k, nf = len(s.tri), len(tri)
        nodes, inverse = np.unique(tri.ravel(), return_inverse=True)
        dofs = (3 * inverse.reshape(nf, 3)[:, :, None] + np.arange(3)).reshape(nf, 9)
        off_a = np.r_[e * np.asarray(s.sides, float), [s.anchor[2]] * (nf - k)]
        off_l = np.r_[e * np.asarray(s.leave_sides, float), [0.0] * (nf - k)]
        s.cache[key] = (
            np.ascontiguousarray(tri, dtype=np.int64),
            np.ascontiguousarray(ab, dtype=float),
            np.ascontiguousarray(orient, dtype=float),
            nodes,
            np.ascontiguousarray(dofs, dtype=np.int64),
            off_a,
            off_l,
        )
    return s.cache[key]


def string_derivatives(
    x: np.ndarray, s: SimString, strings: StringSet, hessian: bool = True
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Gradient and exact Hessian of a string's demanded length w.r.t. its nodes.

    Returns ``(nodes, grad, hess)``: the nodes of the string's panels (m,), the
    gradient (m, 3), dimensionless, and the Hessian (3m, 3m), 1/mm, rows
    ``3 node + axis`` in the order of ``nodes`` (None when ``hessian`` is False).
    The Hessian holds the segments' transverse stiffness ``(I - u u^T) / length``,
    the TSA's share of the anchor stretch (eq. 8's analytic derivatives,
    ``TSAParams.consumed_derivatives``) and the curvature of the points' offsets
    along their panels' normals; compiled (:func:`_derivatives_kernel`).
    """
    tri, ab, orient, nodes, dofs, off_a, off_l = _topology(s, strings.offset)
    x = np.ascontiguousarray(x, dtype=float)
    k = len(s.tri)
    anchor = np.asarray(s.anchor, dtype=float)
    x_dis = _anchor_stretch(x, tri, ab, orient, off_a, k, s.mounted, anchor)
    _, _, rate, curv = (float(v) for v in strings.tsa.consumed_derivatives(strings.theta, x_dis))
    w = np.ones(k) if s.weights is None else np.asarray(s.weights, dtype=float)
    grad, hess = _derivatives_kernel(
        x, tri, ab, orient, off_a, off_l, k, s.mounted, anchor, rate, curv, dofs, len(nodes), w
    )
    return nodes, grad, (hess if hessian else None)


def string_hessian_pattern(s: SimString) -> tuple[np.ndarray, np.ndarray]:
    """Where the Hessian of :func:`string_derivatives` (without the string's axial
    stiffness ``k g g^T``, which the solver keeps apart) can be non-zero.

    Returns ``(nodes, mask)``: the nodes of the string's panels (m,), as
    :func:`string_derivatives` orders them, and a (3m, 3m) bool mask: each frame with
    itself, each segment's two frames (hole ``j`` and ``j + 1``) and a mounted anchor's
    frame with the first hole's. A string through ``k`` panels so couples only
    neighbouring panels, not all ``k`` of them.
    """
    tri = s.frames()[0]
    k, nf = len(s.tri), len(tri)
    nodes, inverse = np.unique(tri.ravel(), return_inverse=True)
    local = inverse.reshape(nf, 3)
    pairs = [(f, f) for f in range(nf)] + [(j, j + 1) for j in range(k - 1)]
    if s.mounted:
        pairs.append((k, 0))
    node_mask = np.zeros((len(nodes), len(nodes)), dtype=bool)
    for a, b in pairs:
        node_mask[np.ix_(local[a], local[b])] = True
        node_mask[np.ix_(local[b], local[a])] = True
    return nodes, np.kron(node_mask, np.ones((3, 3), dtype=bool))


@njit(cache=True)
def _frame(x, t, ab, orient):
    """A frame's edge vectors, normal (oriented, unnormalised), its norm and the point ``ab``."""
    v0 = x[t[0]]
    e1 = x[t[1]] - v0
    e2 = x[t[2]] - v0
    n = np.empty(3)
    n[0] = e1[1] * e2[2] - e1[2] * e2[1]
    n[1] = e1[2] * e2[0] - e1[0] * e2[2]
    n[2] = e1[0] * e2[1] - e1[1] * e2[0]
    n *= orient
    norm = math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
    return e1, e2, n, norm, v0 + ab[0] * e1 + ab[1] * e2


@njit(cache=True)
def _anchor_stretch(x, tri, ab, orient, off_a, k, mounted, anchor):
    """The distance from the anchor (fixed, or on its panel's frame ``k``) to hole 1, mm."""
    _, _, n, norm, c = _frame(x, tri[0], ab[0], orient[0])
    first = c + off_a[0] * n / norm
    if mounted:
        _, _, n, norm, c = _frame(x, tri[k], ab[k], orient[k])
        a = c + off_a[k] * n / norm
    else:
        a = anchor
    d = first - a
    return math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])


@njit(cache=True)
def _skew(v):
    out = np.zeros((3, 3))
    out[0, 1], out[0, 2] = -v[2], v[1]
    out[1, 0], out[1, 2] = v[2], -v[0]
    out[2, 0], out[2, 1] = -v[1], v[0]
    return out


@njit(cache=True)
def _jacobian(e1, e2, n, norm, orient, ab, off):
    """d(point)/d(v0, v1, v2) of a frame's point offset ``off`` along its normal, (3, 9)."""
    nh = n / norm
    proj = (np.eye(3) - np.outer(nh, nh)) / norm
    d1 = ab[0] * np.eye(3) + off * (proj @ (-_skew(e2) * orient))
    d2 = ab[1] * np.eye(3) + off * (proj @ (_skew(e1) * orient))
    out = np.empty((3, 9))
    out[:, :3] = np.eye(3) - d1 - d2
    out[:, 3:6] = d1
    out[:, 6:] = d2
    return out


@njit(cache=True)
def _curvature(e1, e2, n, norm, orient, w):
    """Hessian of ``w . n_hat`` w.r.t. (v0, v1, v2) of a frame, (9, 9), for fixed ``w`` (3,)."""
    mh = n / norm * orient  # m / |m| with m = e1 x e2: fold the sign into w
    w = w * orient
    wn = w @ mh
    u = w - wn * mh
    h_nn = -(wn * (np.eye(3) - np.outer(mh, mh)) + np.outer(mh, u) + np.outer(u, mh)) / (
        norm * norm
    )
    jn = np.empty((3, 6))
    jn[:, :3] = -_skew(e2)
    jn[:, 3:] = _skew(e1)
    h_ee = jn.T @ h_nn @ jn
    sm = _skew(u / norm)
    h_ee[:3, 3:] -= sm
    h_ee[3:, :3] += sm
    t = np.zeros((6, 9))  # (e1, e2) = T (v0, v1, v2)
    for i in range(3):
        t[i, i], t[i, 3 + i] = -1.0, 1.0
        t[3 + i, i], t[3 + i, 6 + i] = -1.0, 1.0
    return t.T @ h_ee @ t


@njit(cache=True)
def _add_pair(hess, jp, jq, dp, dq, hs):
    """A segment between points p and q: its Hessian ``hs`` (3, 3) through their Jacobians."""
    for a, ja, b, jb, sign in ((dp, jp, dp, jp, 1.0), (dq, jq, dq, jq, 1.0)):
        block = ja.T @ hs @ jb
        for i in range(9):
            for j in range(9):
                hess[a[i], b[j]] += sign * block[i, j]
    cross = jp.T @ hs @ jq
    for i in range(9):
        for j in range(9):
            hess[dp[i], dq[j]] -= cross[i, j]
            hess[dq[j], dp[i]] -= cross[i, j]


@njit(cache=True)
def _derivatives_kernel(
    x, tri, ab, orient, off_a, off_l, k, mounted, anchor, rate, curv, dofs, m, w
):
    """Gradient (m, 3) and Hessian (3m, 3m) of one string's demanded length (see
    :func:`string_derivatives`); ``rate`` and ``curv`` are the TSA share's first and
    second derivatives by the anchor stretch, ``w`` (k,) the segments' capstan weights.
    """
    nf = len(tri)
    ja = np.empty((nf, 3, 9))
    jl = np.empty((nf, 3, 9))
    arrive = np.empty((nf, 3))
    leave = np.empty((nf, 3))
    frames = []
    for f in range(nf):
        e1, e2, n, norm, c = _frame(x, tri[f], ab[f], orient[f])
        frames.append((e1, e2, n, norm))
        arrive[f] = c + off_a[f] * n / norm
        leave[f] = c + off_l[f] * n / norm
        ja[f] = _jacobian(e1, e2, n, norm, orient[f], ab[f], off_a[f])
        jl[f] = _jacobian(e1, e2, n, norm, orient[f], ab[f], off_l[f])
    ga = np.zeros((nf, 3))
    gl = np.zeros((nf, 3))
    a = arrive[k] if mounted else anchor
    first = arrive[0] - a
    x_dis = math.sqrt(first @ first)
    u0 = first / x_dis
    ga[0] += rate * u0
    if mounted:
        ga[k] -= rate * u0
    hess = np.zeros((3 * m, 3 * m))
    h0 = curv * np.outer(u0, u0) + rate * (np.eye(3) - np.outer(u0, u0)) / x_dis
    if mounted:
        _add_pair(hess, ja[k], ja[0], dofs[k], dofs[0], h0)
    else:
        block = ja[0].T @ h0 @ ja[0]
        for i in range(9):
            for j in range(9):
                hess[dofs[0, i], dofs[0, j]] += block[i, j]
    for j in range(k - 1):  # segments leave_j -> arrive_(j+1)
        seg = arrive[j + 1] - leave[j]
        length = math.sqrt(seg @ seg)
        unit = seg / length
        ga[j + 1] += w[j + 1] * unit
        gl[j] -= w[j + 1] * unit
        hs = w[j + 1] * (np.eye(3) - np.outer(unit, unit)) / length
        _add_pair(hess, jl[j], ja[j + 1], dofs[j], dofs[j + 1], hs)
    grad = np.zeros(3 * m)
    for f in range(nf):
        per = ga[f] @ ja[f] + gl[f] @ jl[f]
        e1, e2, n, norm = frames[f]
        w = off_a[f] * ga[f] + off_l[f] * gl[f]  # the offsets curve with their panels
        block = _curvature(e1, e2, n, norm, orient[f], w)
        for i in range(9):
            grad[dofs[f, i]] += per[i]
            for j in range(9):
                hess[dofs[f, i], dofs[f, j]] += block[i, j]
    return grad.reshape(m, 3), hess
