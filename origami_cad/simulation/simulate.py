"""String-driven folding of any crease pattern: the actuation loop and its records."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from origami_cad.errors import PatternError, SimulationError
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.cables import SimString, StringSet, string_length
from origami_cad.simulation.mechanics import fold_angles
from origami_cad.simulation.model import SimulationParams, Structure, build_structure
from origami_cad.simulation.solver import Ground, _Assembly, solve_equilibrium, total_energy
from origami_cad.strings.route import RouteSpec, frame_orientation, hole_frames, panel_frame

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
        orient = frame_orientation(cp, tri)
        for h, (fi, (px, py)) in enumerate(zip(s.faces, s.points, strict=True)):
            ring = cp.vertices[cp.faces[fi]]
            d = np.min(_distance_to_ring(np.array([px, py]), ring))
            if d < 1e-6 * max(cp.size, 1.0):
                raise PatternError(
                    f"string {k + 1}: hole {s.names[h]} lies on a crease line; move it onto "
                    "the panel"
                )
        sides = np.asarray(s.sides, dtype=float)
        sim = SimString(
            np.asarray(s.anchor, float),
            tri,
            ab,
            orient,
            sides,
            route.thickness * float(np.sum(np.diff(sides) != 0)),
        )
        if s.anchor_face >= 0:  # an onboard TSA: the anchor rides on its panel
            sim.anchor_tri, sim.anchor_ab = panel_frame(cp, s.anchor_face, *s.anchor[:2])
            sim.anchor_orient = float(frame_orientation(cp, sim.anchor_tri))
            sim.anchor = np.array([*s.anchor[:2], s.anchor[2] + route.thickness / 2.0])
        out.append(sim)
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
    free: bool = False,
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
        Stop when, for this many steps, no crease has turned by more than 0.01 deg
        and no node has moved by more than 1e-4 of the pattern's size.
    progress : callable, optional
        Called as ``progress(step, steps)`` after each equilibrium.
    free : bool
        Hold no panel: the structure lies on the ground plane, held there by
        gravity and friction (a walking structure). Needs ``params.gravity > 0``
        and ``params.ground``.
    """
    params = params or SimulationParams()
    if free and (params.ground is None or params.gravity <= 0):
        raise SimulationError(
            "a free structure (no panel held) needs gravity > 0 and a ground plane to rest on"
        )
    st: Structure = build_structure(
        cp, params, fixed_panel or route.fixed_panel, fold_limits, free=free
    )
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
    ground = None
    if params.ground is not None:
        # nodes lie on the mid-surface: the bottom face touches the ground
        contact = params.ground + 0.5 * params.panel_thickness
        ground = Ground(contact, params.ground_stiffness, params.friction, params.slip)
        if free:  # lay the sheet on the ground
            st.x0[:, 2] = contact
        ground.start(st.x0)
    x, _ = solve_equilibrium(st.x0.copy(), st, None, ground=ground)
    st.hinge_rest = np.zeros(len(st.hinges))
    strings = _strings(cp, route, x, params)
    assembly = _Assembly(st, strings)
    if ground is not None:
        ground.start(x)
    n_steps = steps if steps is not None else int(route.max_turns * 2 * math.pi / route.step)
    if steps is not None:
        step_angle = route.max_turns * 2 * math.pi / max(steps, 1)
    else:
        step_angle = route.step
    dtheta = 1e-4
    still = 0
    previous_angles = None
    previous = None
    for k in range(n_steps + 1):
        strings.theta = k * step_angle
        # secant predictor (the equilibrium path is smooth in the TSA angle), kept
        # when it starts lower than the last state (not where panels turn fast)
        start = x
        if previous is not None:
            guess = 2.0 * x - previous
            if total_energy(guess, st, strings, ground) < total_energy(x, st, strings, ground):
                start = guess
        x_new, info = solve_equilibrium(start, st, strings, ground=ground, assembly=assembly)
        previous = x
        moved = float(np.max(np.linalg.norm(x_new - x, axis=1))) if k else 0.0
        x = x_new
        if ground is not None:
            ground.start(x)  # the next step's friction starts from here
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
        rho = fold_angles(x, st.hinges)[folds]
        angles = np.zeros(cp.n_edges)
        angles[st.hinge_edge[folds]] = np.degrees(rho)
        limit_active = bool(np.any(np.abs(rho) >= st.hinge_limit[folds] - st.limit_margin))
        result.steps.append(
            {
                "step": k,
                "theta_s_deg": math.degrees(strings.theta),
                "turns": strings.theta / (2 * math.pi),
                "tensions_N": [float(t) for t in info.tensions],
                "tsa_torque_Nmm": torque,
                "energy_Nmm": total_energy(x, st, strings, ground),
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
        # the fold has stopped when no crease turns by more than 0.01 deg and nothing moves
        turned = (
            math.inf
            if previous_angles is None
            else float(np.max(np.abs(angles - previous_angles), initial=0.0))
        )
        previous_angles = angles
        still = still + 1 if turned < 0.01 and moved < 1e-4 * cp.size else 0
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
