"""Friction where a string passes through a hole: the capstan law.

A string sliding around a hole's edge loses tension by the capstan (Euler-Eytelwein)
law: ``T_out = T_in exp(-mu phi)`` going away from the pulled end, ``phi`` the angle it
wraps there (rad) and ``mu`` the string-on-hole friction coefficient. At hole ``k`` the
string arrives along ``d_in``, crosses the sheet along ``c`` (from its arriving exit
to its leaving one) where it changes face, and leaves along ``d_out``; it wraps
``angle(d_in, c) + angle(c, d_out)``, or ``angle(d_in, d_out)`` where it stays on one
face. Both string models (the bar-and-hinge simulation and the DCQC model) keep the
strings' lengths as they are (friction does not change what the string's length
allows) and weigh the force of each segment by its tension relative to the pulled end
(its weight), so the pulled end needs more tension for the same fold. The weights
are taken from the last state (bar-and-hinge) or the rigid folding at each fold ratio
(DCQC). ``mu = 0`` gives weights of exactly 1 (no friction).
"""

from __future__ import annotations

import numpy as np

from origami_cad.strings.route import anchor_points, hole_exits

__all__ = ["capstan_rate", "capstan_weights", "wrap_angles"]


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The angle between vectors ``a`` and ``b`` (..., 3), rad; 0 where one is zero."""
    cross = np.linalg.norm(np.cross(a, b), axis=-1)
    return np.arctan2(cross, np.einsum("...i,...i->...", a, b))


def wrap_angles(anchor: np.ndarray, arrive: np.ndarray, leave: np.ndarray) -> np.ndarray:
    """The angle the string wraps at each hole but the last, (..., k - 1) rad.

    ``anchor`` (..., 3) mm is where the string comes from (the pulled end's side),
    ``arrive`` and ``leave`` (..., k, 3) mm its exits at each hole (equal where it
    stays on one face).
    """
    arrive, leave = np.asarray(arrive, float), np.asarray(leave, float)
    before = np.concatenate([np.asarray(anchor, float)[..., None, :], leave[..., :-1, :]], -2)
    d_in = arrive[..., :-1, :] - before[..., :-1, :]
    d_out = arrive[..., 1:, :] - leave[..., :-1, :]
    c = leave[..., :-1, :] - arrive[..., :-1, :]
    through = np.linalg.norm(c, axis=-1) > 1e-9
    bent = _angle(d_in, c) + _angle(c, d_out)
    return np.where(through, bent, _angle(d_in, d_out))


def capstan_weights(
    anchor: np.ndarray, arrive: np.ndarray, leave: np.ndarray, mu: float
) -> np.ndarray:
    """Each segment's tension over the pulled end's, (..., k): 1 for the anchor's segment,
    then ``exp(-mu * the angle wrapped before it)`` (``mu`` dimensionless, >= 0)."""
    phi = wrap_angles(anchor, arrive, leave)
    lead = np.zeros((*phi.shape[:-1], 1))
    return np.exp(-mu * np.concatenate([lead, np.cumsum(phi, axis=-1)], axis=-1))


def capstan_rate(cp, coords, route, frames, segs, ratios, mu: float) -> np.ndarray:
    """The DCQC model's routed length's rate by the fold ratio, friction weighed, (strings, G).

    ``coords`` (G, n, 3) mm are the folded states at fold ratios ``ratios`` (G,),
    ``segs`` each string's segment lengths there (G, k_i) mm. Each hole-to-hole
    segment's rate counts by its capstan weight at that fold ratio
    (:func:`capstan_weights`), mm per unit fold ratio: what the TSA's end feels. The
    kinematics (the strings' lengths) are not weighed: friction changes the tensions.
    """
    out = np.empty((len(segs), len(ratios)))
    for i, (s, f, seg) in enumerate(zip(route.strings, frames, segs, strict=True)):
        arrive, leave, _ = hole_exits(cp, coords, s, route.thickness, f)
        anchor = anchor_points(cp, coords, s, route.thickness)
        w = capstan_weights(anchor, arrive, leave, mu)  # (G, k)
        out[i] = (w[:, 1:] * np.gradient(seg[:, 1:], ratios, axis=0)).sum(axis=1)
    return out
