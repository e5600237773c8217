"""String-driven folding of any crease pattern: the actuation loop and its records."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from origami_cad.errors import PatternError
from origami_cad.kinematics.fold3d import fold_angles_from_coords
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.mechanics import fold_angles
from origami_cad.simulation.model import SimulationParams, Structure, build_structure
from origami_cad.simulation.solver import (
    SimString,
    StringSet,
    solve_equilibrium,
    string_length,
    total_energy,
)
from origami_cad.strings.route import RouteSpec, hole_frames

__all__ = ["SimulationResult", "simulate"]


@dataclass
class SimulationResult:
    """Equilibrium states as the TSA turns, and why the folding stopped."""

    states: list[np.ndarray] = field(default_factory=list)  # (n, 3) mm
    steps: list[dict[str, Any]] = field(default_factory=list)
    reason: str = ""
    notes: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        return {"reason": self.reason, "notes": self.notes, "steps": self.steps}


def _strings(
    cp: CreasePattern, route: RouteSpec, x: np.ndarray, params: SimulationParams
) -> StringSet:
    out = []
    for k, s in enumerate(route.strings):
        tri, ab = hole_frames(cp, s)
        flat = cp.vertices[tri]
        f1, f2 = flat[:, 1] - flat[:, 0], flat[:, 2] - flat[:, 0]
        orient = np.sign(f1[:, 0] * f2[:, 1] - f1[:, 1] * f2[:, 0])
        for h, (fi, (px, py)) in enumerate(zip(s.faces, s.points, strict=True)):
            ring = cp.vertices[cp.faces[fi]]
            d = np.min(_distance_to_ring(np.array([px, py]), ring))
            if d < 1e-6 * max(cp.size, 1.0):
                raise PatternError(
                    f"string {k + 1}: hole {s.names[h]} lies on a crease line; move it onto "
                    "the panel"
                )
        sides = np.asarray(s.sides, dtype=float)
        out.append(
            SimString(
                np.asarray(s.anchor, float),
                tri,
                ab,
                orient,
                sides,
                route.thickness * float(np.sum(np.diff(sides) != 0)),
            )
        )
    strings = StringSet(out, route.thickness / 2.0, route.tsa)
    for s in strings.strings:
        s.free_length, _ = string_length(x, s, strings)
        s.stiffness = params.string_axial_stiffness / s.free_length
    return strings


def _distance_to_ring(p: np.ndarray, ring: np.ndarray) -> np.ndarray:
    a, b = ring, np.roll(ring, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
    return np.linalg.norm(a + t[:, None] * ab - p, axis=1)


def simulate(
    cp: CreasePattern,
    route: RouteSpec,
    params: SimulationParams | None = None,
    *,
    steps: int | None = None,
    fixed_panel: str | None = None,
    fold_limits: dict[int, float] | None = None,
    prefold: float = 2.0,
    tension_limit: float = math.inf,
    still_steps: int = 3,
    progress: Callable[[int, int], None] | None = None,
) -> SimulationResult:
    """Turn the route's TSA step by step and find the equilibrium at each step.

    Parameters
    ----------
    cp : CreasePattern
        Any pattern (mm).
    route : RouteSpec
        TSA, strings through holes, step and maximum turns.
    params : SimulationParams
        Materials and loads.
    steps : int, optional
        Number of actuation steps (default: as many as ``route.step`` and
        ``route.max_turns`` give).
    fixed_panel : str, optional
        Panel held in place (default: the route's ``fixed_panel``, else the one
        nearest the centroid).
    fold_limits : dict, optional
        ``{edge: degrees}``: fold limits of particular creases (blockers).
    prefold : float
        The flat sheet is a bifurcation point; the creases are first pre-folded by
        this many degrees in the sense of their assignments (strings slack), deg.
    tension_limit : float
        Stop when a string's tension exceeds it, N.
    still_steps : int
        Stop when no crease has turned by more than 0.01 deg for this many steps.
    """
    params = params or SimulationParams()
    st: Structure = build_structure(cp, params, fixed_panel or route.fixed_panel, fold_limits)
    result = SimulationResult(notes=list(st.notes))
    # pre-fold toward the assignments so that the strings have a way to go
    sign = np.zeros(len(st.hinges))
    folds = st.folds
    sign[folds] = np.where(
        cp.assignments[st.hinge_edge[folds]] == "M",
        -1.0,
        np.where(cp.assignments[st.hinge_edge[folds]] == "V", 1.0, 0.0),
    )
    st.hinge_rest = sign * math.radians(prefold)
    x, _ = solve_equilibrium(st.x0.copy(), st, None, ground=params.ground)
    st.hinge_rest = np.zeros(len(st.hinges))
    strings = _strings(cp, route, x, params)
    n_steps = steps if steps is not None else int(route.max_turns * 2 * math.pi / route.step)
    if steps is not None:
        step_angle = route.max_turns * 2 * math.pi / max(steps, 1)
    else:
        step_angle = route.step
    dtheta = 1e-4
    still = 0
    previous_angles = None
    for k in range(n_steps + 1):
        strings.theta = k * step_angle
        x_new, info = solve_equilibrium(x, st, strings, ground=params.ground)
        moved = float(np.max(np.linalg.norm(x_new - x, axis=1))) if k else 0.0
        x = x_new
        result.states.append(x.copy())
        # TSA torque: tension times the string the TSA takes per radian (virtual work)
        torque = 0.0
        for s, tension in zip(strings.strings, info.tensions, strict=True):
            _, x_dis = string_length(x, s, strings)
            rate = (
                float(strings.tsa.consumed(strings.theta + dtheta, x_dis))
                - float(strings.tsa.consumed(strings.theta, x_dis))
            ) / dtheta
            torque += tension * rate
        angles = np.degrees(fold_angles_from_coords(cp, x))
        rho = fold_angles(x, st.hinges)[folds]
        limit_active = bool(np.any(np.abs(rho) >= st.hinge_limit[folds] - st.limit_margin))
        result.steps.append(
            {
                "step": k,
                "theta_s_deg": math.degrees(strings.theta),
                "turns": strings.theta / (2 * math.pi),
                "tensions_N": [float(t) for t in info.tensions],
                "tsa_torque_Nmm": torque,
                "energy_Nmm": total_energy(x, st, strings, ground=params.ground),
                "energy_per_iteration": info.energies,
                "iterations": info.iterations,
                "converged": info.converged,
                "max_displacement_mm": moved,
                "fold_angles_deg": angles.tolist(),
            }
        )
        if progress is not None:
            progress(k, n_steps)
        if max(info.tensions, default=0.0) > tension_limit:
            result.reason = (
                f"string tension {max(info.tensions):.3g} N exceeds the limit of "
                f"{tension_limit:g} N"
            )
            break
        # the fold has stopped when no crease turns by more than 0.01 deg in a step
        turned = (
            math.inf
            if previous_angles is None
            else float(np.max(np.abs(angles - previous_angles), initial=0.0))
        )
        previous_angles = angles
        still = still + 1 if turned < 0.01 else 0
        if still >= still_steps:
            result.reason = (
                "fold limit reached"
                if limit_active
                else "the structure stopped moving: the strings cannot shorten it any further"
            )
            break
    else:
        result.reason = (
            f"the TSA reached its last step ({n_steps * step_angle / (2 * math.pi):.3g} turns)"
        )
    return result
