"""Quasi-static folding under the DCQC principle (the paper's section IV-B, eqs. 7-8).

In the initial state ``S_0`` (fold ratio ``p0``, strings tight) each string's
length is ``L_0 = l_AB(0) + routed length`` (eq. 7). As the TSA turns by
``theta_s``, its share ``l_AB(theta_s)`` grows (eq. 8, or the onboard model),
so each string demands ``g_i(p) = l_AB,i(theta_s, p) + rest_i(p) - L_0,i <= 0``:
the structure must fold until every string fits. With elastic creases resisting,
the quasi-static state is the *smallest* fold ratio not below the previous one
at which all strings fit; strings that are not binding go slack. When no fold
ratio up to the fold limit satisfies all strings, the previous state is final,
and why is reported: the fold limit is reached, or a string's routed length
cannot shrink any more (it no longer decreases as the pattern folds).

For patterns the kinematics folds with one parameter (TG tessellations,
Miura-ori, degree-4 patterns read from files). The folded sheet is placed with
its vertex centroid where it was flat (a sheet centred on the ring rail,
pulled evenly), or with the route's ``fixed_panel`` held in place; anchors are
fixed in that frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from origami_cad.kinematics.folding import fold_coords
from origami_cad.pattern.design import Design
from origami_cad.strings.route import (
    RouteSpec,
    cutting_segments,
    hole_frames,
    string_lengths,
    string_path,
)

__all__ = ["DCQCResult", "simulate_dcqc"]


@dataclass
class DCQCResult:
    """The sequence of quasi-static states and why the last one is final.

    ``steps`` holds one record per state: ``theta_s_deg``, ``turns``, ``p``,
    ``routed_length_mm`` (per string), ``tsa_length_mm`` (``l_AB`` per string),
    ``binding`` (index of the string that set the fold ratio, or -1).
    """

    steps: list[dict[str, Any]] = field(default_factory=list)
    reason: str = ""
    valid: bool = True
    initial_length_mm: list[float] = field(default_factory=list)
    violations: list[str] = field(default_factory=list)
    cutting: list[str] = field(default_factory=list)
    final_coords: np.ndarray | None = None
    final_strings: list[np.ndarray] = field(default_factory=list)

    @property
    def final(self) -> dict[str, Any]:
        return self.steps[-1]

    @property
    def p(self) -> np.ndarray:
        return np.array([s["p"] for s in self.steps])

    @property
    def turns(self) -> np.ndarray:
        return np.array([s["turns"] for s in self.steps])

    def to_dict(self) -> dict[str, Any]:
        return {
            "valid": self.valid,
            "reason": self.reason,
            "initial_length_mm": self.initial_length_mm,
            "route_violations": self.violations,
            "segments_cutting_panels": self.cutting,
            "steps": self.steps,
            "final": self.final,
        }


def simulate_dcqc(design: Design, route: RouteSpec, grid: int = 801) -> DCQCResult:
    """Simulate the folding that the route's strings and TSA produce, step by step.

    Parameters
    ----------
    design : Design
        A pattern the kinematics folds with one parameter.
    route : RouteSpec
        TSA, strings and settings (step, max turns, ``p0``, fold limit ``p_max``).
    grid : int
        Fold ratios sampled between ``p0`` and ``p_max`` (the exact geometry is
        evaluated there, vectorised); each state is where the linearly
        interpolated demand crosses zero, accurate to about ``1e-6`` in ``p``
        for the default grid.
    """
    cp = design.pattern
    ratios = np.linspace(route.p0, route.p_max, grid)
    centre = np.r_[cp.vertices.mean(axis=0), 0.0]

    held = None if route.fixed_panel is None else cp.faces[cp.face_index(route.fixed_panel)]
    flat3 = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])

    def placed(rs) -> np.ndarray:
        c = fold_coords(design, rs)
        if held is None:  # the sheet sits centred on the rail: its centroid stays put
            return c - c.mean(axis=1, keepdims=True) + centre
        return _hold(c, held, flat3)  # the held panel stays where it is flat

    coords = placed(ratios)
    frames = [hole_frames(cp, s) for s in route.strings]

    def measure(c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        vals = [
            string_lengths(cp, c, s, route.thickness, f)
            for s, f in zip(route.strings, frames, strict=True)
        ]
        return np.stack([v[0] for v in vals]), np.stack([v[1] for v in vals])

    x_dis, rest = measure(coords)  # (strings, grid)
    tsa = route.tsa
    l0 = tsa.consumed(0.0, x_dis[:, 0]) + rest[:, 0]
    result = DCQCResult(initial_length_mm=l0.tolist(), violations=route.violations)

    def record(theta: float, p: float, binding: int) -> None:
        xd = np.array([np.interp(p, ratios, row) for row in x_dis])
        rs = np.array([np.interp(p, ratios, row) for row in rest])
        result.steps.append(
            {
                "theta_s_deg": math.degrees(theta),
                "turns": theta / (2 * math.pi),
                "p": p,
                "routed_length_mm": rs.tolist(),
                "tsa_length_mm": tsa.consumed(theta, xd).tolist(),
                "binding": binding,
            }
        )

    record(0.0, route.p0, -1)
    theta_end = min(route.max_turns * 2 * math.pi, tsa.max_theta())
    n_steps = math.floor(theta_end / route.step + 1e-9)
    p_prev = route.p0
    for step in range(1, n_steps + 1):
        theta = step * route.step
        g = tsa.consumed(theta, x_dis) + rest - l0[:, None]  # (strings, grid)
        worst = g.max(axis=0)
        w_prev = np.interp(p_prev, ratios, worst)
        if w_prev <= 0:  # the strings still fit: nothing moves
            record(theta, p_prev, -1)
            continue
        start_k = int(np.searchsorted(ratios, p_prev, side="right"))
        ok = np.flatnonzero(worst[start_k:] <= 0)
        if not len(ok):
            result.reason = _why(g, max(start_k - 1, 0), ratios, route)
            if step == 1:
                result.valid = False
                result.reason = "the routing never folds the structure: " + result.reason
            break
        k = start_k + int(ok[0])
        # the state: where the (piecewise linear) worst demand crosses zero
        lo = p_prev if k == start_k else float(ratios[k - 1])
        w_lo = w_prev if k == start_k else float(worst[k - 1])
        p = lo + (0.0 - w_lo) / (worst[k] - w_lo) * (ratios[k] - lo)
        record(theta, float(p), int(np.argmax(g[:, k])))
        p_prev = float(p)
    else:
        result.reason = (
            f"the TSA reached its limit ({route.max_turns:g} turns)"
            if tsa.max_theta() > theta_end or tsa.model == "ring"
            else "the strands reached their maximum helix angle"
        )
    # geometry of the final state, and segments cutting through panels along the way
    final = placed([result.final["p"]])[0]
    result.final_coords = final
    result.final_strings = [string_path(cp, final, s, route.thickness) for s in route.strings]
    seen: set[str] = set()
    for p in np.linspace(route.p0, result.final["p"], 6):
        c = placed([p])[0]
        for i, s in enumerate(route.strings):
            for msg in cutting_segments(cp, c, s, route.thickness, i):
                if msg not in seen:
                    seen.add(msg)
                    result.cutting.append(f"{msg} (from p = {p:.3f})")
    return result


def _hold(coords: np.ndarray, ring: np.ndarray, flat: np.ndarray) -> np.ndarray:
    """Move each state rigidly so that the panel ``ring`` is back at its flat place."""
    out = np.empty_like(coords)
    target = flat[ring]
    tc = target.mean(axis=0)
    for k, c in enumerate(coords):
        src = c[ring]
        sc = src.mean(axis=0)
        u, _, vt = np.linalg.svd((src - sc).T @ (target - tc))
        d = np.sign(np.linalg.det(u @ vt))
        rot = u @ np.diag([1.0, 1.0, d]) @ vt
        out[k] = (c - sc) @ rot + tc
    return out


def _why(g: np.ndarray, k_prev: int, ratios: np.ndarray, route: RouteSpec) -> str:
    """Why no fold ratio in ``[p_prev, p_max]`` lets every string fit."""
    worst = g[:, k_prev:].max(axis=0)
    i = int(np.argmin(worst))
    binding = int(np.argmax(g[:, k_prev + i]))
    gi = g[binding, k_prev:]
    if i == len(worst) - 1:
        return (
            f"the fold limit p = {route.p_max:g} is reached (string {binding + 1} would need "
            "more folding)"
        )
    if np.argmin(gi) == 0:
        return (
            f"string {binding + 1}'s length does not decrease as the pattern folds "
            "(check its sides against the DCQC rule)"
        )
    return (
        f"string {binding + 1} cannot shorten enough: folding further (its length is "
        f"shortest at p = {ratios[k_prev + int(np.argmin(gi))]:.3f}) no longer makes up for "
        "the string the TSA takes"
    )
