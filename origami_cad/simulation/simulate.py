"""String-driven folding of any crease pattern: the continuation loop, its records and stops.

The TSA turns in steps of string taken up (``route.take_up`` mm for the string
that takes most, at most ``route.step`` of rotation), so the slow start of
eq. 8 costs few steps and its fast end stays accurate. After each step the
bar-and-hinge equilibrium is found. The folding ends only for a physical
reason (:class:`~origami_cad.strings.dcqc_result.StopReason`), named in the result:

- the TSA reached its turn limit or, onboard, its maximum helix angle;
- a fold limit (eq. 6 or a blocker) is active while the strings stretch
  instead of folding further;
- a string's tension or the TSA torque passed the route's ``max_tension`` or
  ``max_torque``;
- a jam: the strings stretch instead of folding the sheet (most of the string
  taken up goes into stretch, or a string's or a panel's strain passes its
  threshold), named with the string and the segment that lengthens.

Placement (the same default as the DCQC model): a panel given by the route or
the caller is held; otherwise the sheet keeps its mean pose (its vertex
centroid stays and it does not rotate on average), a sheet free in the middle
of the ring and pulled evenly. The solver holds the panel nearest the centroid
and, in turn, the fixed anchors are placed in that panel's frame so that the
whole state, moved back to the mean pose, has them where the route puts them
(a fixed point, usually in one or two solves per step). ``free=True`` lays the
sheet on the ground instead (gravity and friction hold it).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from origami_cad._args import Arg, brief_value, check_number, checked
from origami_cad.errors import PatternError, SimulationError
from origami_cad.pattern.design import Design
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.cables import (
    SimString,
    StringSet,
    string_length,
    string_lengths,
    update_capstan,
)
from origami_cad.simulation.mechanics import bar_lengths, fold_angles
from origami_cad.simulation.model import SimulationParams, Structure, build_structure
from origami_cad.simulation.paths import fold_ratio_fit, rigid_table
from origami_cad.simulation.solver import Ground, HessianAssembly, solve_equilibrium, total_energy
from origami_cad.strings.dcqc import (
    MAX_STRING_STRAIN,
    segment_names,
    time_limit_stop,
    torque_limit_reason,
    tsa_step,
    turn_limit_stop,
)
from origami_cad.strings.dcqc_result import Jam, StopReason, TurnStates
from origami_cad.strings.route import (
    RouteSpec,
    frame_orientation,
    hole_frames,
    panel_frame,
    rigid_fit,
)

__all__ = ["SimulationResult", "StopRules", "fold_ratio_fit", "rigid_table", "simulate"]

POSE_ROUNDS = 6  # re-placements of the anchors per step at most (mean pose)


@dataclass(repr=False)
class SimulationResult(TurnStates):
    """Equilibrium states as the TSA turns (NumPy columns, one row per state) and the stop.

    ``states`` (S, n, 3) mm; ``theta`` (S,) rad; ``p`` (S,) fold ratio fitted to the
    rigid folding (NaN where the pattern has no one-parameter folding);
    ``tensions`` (S, k) N; ``taut`` (S, k); ``torque`` (S,) N mm; ``fold_angles``
    (S, m) deg of every edge; ``take_up`` (S, k) mm of string the TSA has taken;
    ``stretch`` (S, k) mm; ``energy`` (S,) N mm; ``iterations`` (S,);
    ``converged`` (S,); ``moved`` (S,) largest node displacement in the step, mm;
    ``energies`` the energy after each Newton iteration of each solve.
    """

    states: np.ndarray
    theta: np.ndarray
    p: np.ndarray
    tensions: np.ndarray
    taut: np.ndarray
    torque: np.ndarray
    fold_angles: np.ndarray
    take_up: np.ndarray
    stretch: np.ndarray
    energy: np.ndarray
    iterations: np.ndarray
    converged: np.ndarray
    moved: np.ndarray
    stop: StopReason
    reason: str
    jam: Jam | None = None
    limited_edges: tuple[int, ...] = ()
    notes: list[str] = field(default_factory=list)
    energies: list[list[float]] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """The JSON form (``simulation.json``)."""
        p = np.where(np.isfinite(self.p), self.p, np.nan)
        return {
            "stop": self.stop.value,
            "reason": self.reason,
            "jam": None if self.jam is None else self.jam.to_dict(),
            "limited_edges": list(self.limited_edges),
            "notes": self.notes,
            "states": {
                "turns": self.turns.tolist(),
                "theta_s_deg": np.degrees(self.theta).tolist(),
                "p": [None if math.isnan(v) else v for v in p.tolist()],
                "tensions_N": self.tensions.tolist(),
                "taut": self.taut.tolist(),
                "tsa_torque_Nmm": self.torque.tolist(),
                "take_up_mm": self.take_up.tolist(),
                "stretch_mm": self.stretch.tolist(),
                "energy_Nmm": self.energy.tolist(),
                "iterations": self.iterations.tolist(),
                "converged": self.converged.tolist(),
                "max_displacement_mm": self.moved.tolist(),
                "fold_angles_deg": self.fold_angles.tolist(),
            },
        }


def _strings(cp: CreasePattern, route: RouteSpec, flat: np.ndarray, params) -> StringSet:
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
    strings = StringSet(out, route.thickness / 2.0, route.tsa, friction=params.hole_friction)
    update_capstan(flat, strings)  # the tensions along the strings on the flat sheet
    for s in strings.strings:  # the strings are tight on the flat sheet (eq. 7)
        s.free_length, _ = string_length(flat, s, strings)
        s.stiffness = params.string_axial_stiffness / s.free_length
    return strings


def _distance_to_ring(p: np.ndarray, ring: np.ndarray) -> np.ndarray:
    a, b = ring, np.roll(ring, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
    return np.linalg.norm(a + t[:, None] * ab - p, axis=1)


class _Placement:
    """Keeps the solver's held panel and the route's fixed anchors consistent with the mean pose."""

    def __init__(self, strings: StringSet, flat: np.ndarray, active: bool) -> None:
        self.active = active
        self.flat = flat
        self.world = [None if s.mounted else s.anchor.copy() for s in strings.strings]
        self.strings = strings
        self.rot, self.shift = np.eye(3), np.zeros(3)
        self.history: list[tuple[np.ndarray, np.ndarray]] = []

    def set(self, rot: np.ndarray, shift: np.ndarray) -> float:
        """Put the anchors in the solver's frame for the pose ``world = rot x + shift``."""
        change = 0.0
        for s, a in zip(self.strings.strings, self.world, strict=True):
            if a is not None:
                new = (a - shift) @ rot
                change = max(change, float(np.linalg.norm(new - s.anchor)))
                s.anchor = new
        self.rot, self.shift = rot, shift
        return change

    @property
    def fixed(self) -> np.ndarray:
        return np.array([a is not None for a in self.world], dtype=bool)

    def anchors(self) -> np.ndarray:
        """The fixed anchors in the solver's frame, (k_fixed, 3)."""
        return np.array(
            [
                s.anchor
                for s, a in zip(self.strings.strings, self.world, strict=True)
                if a is not None
            ]
        )

    def put(self, anchors: np.ndarray) -> None:
        it = iter(anchors)
        for s, a in zip(self.strings.strings, self.world, strict=True):
            if a is not None:
                s.anchor = np.array(next(it))

    def lengths(self, x: np.ndarray) -> np.ndarray:
        return string_lengths(x, self.strings)[0]

    def predict(self) -> tuple[np.ndarray, np.ndarray]:
        """The pose extrapolated linearly from the last two accepted poses."""
        if len(self.history) < 2:
            return self.rot, self.shift
        (r0, s0), (r1, s1) = self.history[-2:]
        u, _, vt = np.linalg.svd(r1 @ r0.T @ r1)
        return u @ vt, 2.0 * s1 - s0

    def accept(self) -> None:
        self.history = [*self.history[-1:], (self.rot, self.shift)]

    def to_world(self, x: np.ndarray) -> np.ndarray:
        return x @ self.rot.T + self.shift


@dataclass(frozen=True)
class StopRules:
    """When :func:`simulate` stops, besides the TSA's turn and helix limits.

    Parameters
    ----------
    tension_cap : float
        Stop when a string's tension exceeds it, N.
    jam_ratio, jam_steps : float, int
        A jam (or, with a fold limit active, the fold limit): over ``jam_steps``
        steps a taut string stretched by more than ``jam_ratio`` of the string the
        TSA took up.
    max_string_strain, max_bar_strain : float
        A jam also when a string's strain or a panel bar's strain passes these.
    max_dp : float
        The take-up per step shrinks (to 1/20 at least) so that the fold ratio changes
        by about this much at most between states.
    max_states : int
        Safety cap on the number of states.
    time_limit : float
        Stop (:attr:`StopReason.TIME_LIMIT`) once the folding has taken this many seconds
        of wall-clock time, keeping the states found so far.
    """

    tension_cap: float
    jam_ratio: float = 0.8
    jam_steps: int = 3
    max_string_strain: float = MAX_STRING_STRAIN
    max_bar_strain: float = 0.01
    max_dp: float = 0.01
    max_states: int = 5000
    time_limit: float = math.inf


@checked(
    SimulationError,
    cp=Arg("object", types=(CreasePattern,), optional=False),
    route=Arg("object", types=(RouteSpec,), optional=False),
    params=Arg("object", types=(SimulationParams,)),
    design=Arg("object", types=(Design,)),
    steps=Arg("int", min=1, max=100_000),
    fixed_panel=Arg("str"),
    prefold=Arg(min=0.0, max=90.0, optional=False),
    tension_limit=Arg(min=0.0, open_min=True, max=1e6),
    jam_ratio=Arg(min=0.0, open_min=True, max=1.0, inf_ok=True, optional=False),
    jam_steps=Arg("int", min=1, max=10_000, optional=False),
    max_string_strain=Arg(min=0.0, open_min=True, max=1.0, inf_ok=True, optional=False),
    max_bar_strain=Arg(min=0.0, open_min=True, max=1.0, inf_ok=True, optional=False),
    max_dp=Arg(min=1e-4, max=1.0, optional=False),
    max_states=Arg("int", min=1, max=1_000_000, optional=False),
    time_limit=Arg(min=0.0, open_min=True, inf_ok=True),
    progress=Arg("callable", length=2),
    free=Arg("bool", optional=False),
)
def simulate(
    cp: CreasePattern,
    route: RouteSpec,
    params: SimulationParams | None = None,
    *,
    design: Design | None = None,
    steps: int | None = None,
    fixed_panel: str | None = None,
    fold_limits: dict[int, float] | None = None,
    prefold: float = 3.0,
    tension_limit: float | None = None,
    jam_ratio: float = StopRules.jam_ratio,
    jam_steps: int = StopRules.jam_steps,
    max_string_strain: float = StopRules.max_string_strain,
    max_bar_strain: float = StopRules.max_bar_strain,
    max_dp: float = StopRules.max_dp,
    max_states: int = StopRules.max_states,
    progress: Callable[[int, int], None] | None = None,
    free: bool = False,
    time_limit: float | None = None,
) -> SimulationResult:
    """Turn the route's TSA and find the equilibrium after each step, until a physical stop.

    Parameters
    ----------
    cp : CreasePattern
        Any pattern (mm).
    route : RouteSpec
        TSA, strings through holes, take-up per step, turn, tension and torque limits.
    params : SimulationParams
        Materials and loads (default: from the route's ``[fabrication]``, else the
        default printed sheet).
    design : Design, optional
        The pattern's design, to fit each state's fold ratio ``p`` to the same rigid
        folding as the DCQC model (``Design(cp, None, "file")`` for the degree-4
        folder); without it ``p`` is NaN (fitting costs a hundred rigid folds).
    steps : int, optional
        Turn the TSA in exactly this many equal steps up to ``route.max_turns``
        instead of steps of string taken up (benchmarks, animations).
    fixed_panel : str, optional
        Panel held in place (default: the route's ``fixed_panel``; without one the
        sheet keeps its mean pose).
    fold_limits : dict, optional
        ``{edge: degrees}``: fold limits of particular creases (blockers).
    prefold : float
        The flat sheet is a bifurcation point (it can fold into several branches);
        the creases rest this many degrees folded in the sense of their assignments,
        as a printed sheet pre-folded by hand does, so that the strings fold it along
        its assigned branch. The strings are tight on the flat sheet (eq. 7) and
        slack by what the pre-fold saves, deg.
    tension_limit, jam_ratio, jam_steps, max_string_strain, max_bar_strain, max_dp, max_states
        The stops and step control of :class:`StopRules` (``tension_limit`` N, its
        ``tension_cap``; default: the route's ``max_tension``).
    progress : callable, optional
        Called as ``progress(state, estimated states)`` after each equilibrium.
    free : bool
        Hold no panel: the structure lies on the ground plane, held there by gravity
        and friction (a walking structure). Needs ``params.gravity > 0`` and
        ``params.ground``.
    time_limit : float, optional
        Seconds of wall-clock time the folding may take, set-up included, checked in each
        Newton iteration too (default: no limit); then it stops with the equilibria found
        so far (:attr:`StopReason.TIME_LIMIT`, said by the result).
    """
    fold_limits = _checked_limits(cp, fold_limits)
    _check_design(cp, design)
    params = _default_params(route, params, free)
    cap = route.max_tension if tension_limit is None else tension_limit
    rules = StopRules(
        cap, jam_ratio, jam_steps, max_string_strain, max_bar_strain, max_dp, max_states,
        math.inf if time_limit is None else float(time_limit),
    )  # fmt: skip
    deadline = time.monotonic() + rules.time_limit  # the set-up counts too
    held = fixed_panel or route.fixed_panel
    limits, note = _route_limits(route, design, fold_limits)
    run = _start(cp, route, params, held, limits, prefold, free, design, deadline)
    run.notes += [note] if note else []
    rows, stop = _fold(run, route, rules, steps, progress)
    run.notes.append(stop.reason)
    return _result(rows, stop, run.notes)


def _check_design(cp: CreasePattern, design: Design | None) -> None:
    """A :class:`SimulationError` when ``design`` is the design of another pattern."""
    if design is not None and design.pattern.edges.shape != cp.edges.shape:
        raise SimulationError(
            f"simulate: design: its pattern has {design.pattern.n_edges} edges, cp "
            f"{cp.n_edges}: the design of another pattern"
        )


def _checked_limits(cp: CreasePattern, fold_limits: Any) -> dict[int, float] | None:
    """``{edge: degrees}`` checked: mountain or valley creases of ``cp``, limits in (0, 180]."""
    if fold_limits is None:
        return None
    if not isinstance(fold_limits, dict):
        raise SimulationError(
            f"simulate: fold_limits: expected {{edge: degrees}}, got {brief_value(fold_limits)}"
        )
    out = {}
    for key, value in fold_limits.items():
        edge = check_number(
            "simulate: fold_limits edge",
            key,
            kind="int",
            low=0,
            high=cp.n_edges - 1,
            error=SimulationError,
        )
        if cp.assignments[edge] not in ("M", "V"):
            raise SimulationError(
                f"simulate: fold_limits: edge {edge} is not a mountain or valley crease"
            )
        out[edge] = check_number(
            f"simulate: fold_limits[{edge}]",
            value,
            low=0.0,
            open_min=True,
            high=180.0,
            error=SimulationError,
        )
    return out


def _route_limits(route: RouteSpec, design: Design | None, fold_limits: dict | None):
    """The creases' own limits (deg): the blockers ``fold_limits`` and the route's ``p_max``.

    The route's ``p_max`` limits each crease to its angle in the rigid folding at
    ``p_max`` (the same limit as the DCQC model's); that needs the pattern's folder
    (``design``). Returns ``({edge: degrees} or None, a note or "")``.
    """
    out = {int(k): float(v) for k, v in (fold_limits or {}).items()}
    if route.p_max is None:
        return out or None, ""
    if design is None:
        return out or None, "the route's p_max is not applied: pass design= to fold by it"
    from origami_cad.kinematics.folding import fold_design

    angles = np.abs(fold_design(design, route.p_max).fold_angles)
    for edge in np.flatnonzero(design.pattern.edge_mask("M", "V")):
        if angles[edge] > 1e-6:
            out[int(edge)] = min(out.get(int(edge), math.inf), float(angles[edge]))
    return out, f"the route's p_max = {route.p_max:g} limits each crease to its angle there"


def _default_params(
    route: RouteSpec, params: SimulationParams | None, free: bool
) -> SimulationParams:
    """``params``, else the sheet the route describes (:meth:`SimulationParams.for_route`).

    Raises :class:`SimulationError` when ``free`` but nothing holds the sheet down.
    """
    if params is None:
        params = SimulationParams.for_route(route)
    if free and (params.ground is None or params.gravity <= 0):
        raise SimulationError(
            "a free structure (no panel held) needs gravity > 0 and a ground plane to rest on"
        )
    return params


@dataclass
class _Run:
    """What the continuation loop works on: the structure, its strings and the state ``x``."""

    cp: CreasePattern
    st: Structure
    strings: StringSet
    ground: Ground | None
    assembly: HessianAssembly
    place: _Placement
    table: tuple[np.ndarray, np.ndarray] | None
    notes: list[str]
    x: np.ndarray
    deadline: float = math.inf  # a time.monotonic() time, s

    @property
    def folds(self) -> np.ndarray:
        """The hinges on creases (not panel diagonals), indices into ``st.hinges``."""
        return self.st.folds

    @property
    def limit_edges(self) -> np.ndarray:
        """The pattern edge of each crease hinge."""
        return self.st.hinge_edge[self.st.folds]


@dataclass
class _Stop:
    """Why the folding stopped: the kind, the sentence, the jam and the creases at a limit."""

    kind: StopReason
    reason: str
    jam: Jam | None = None
    limited: tuple[int, ...] = ()


def _start(cp, route, params, held, fold_limits, prefold, free, design, deadline) -> _Run:
    """The structure pre-folded by ``prefold`` degrees and settled, strings slack on it.

    ``held`` is the panel held (None: the mean pose, unless ``free`` or a ground);
    ``deadline`` a :func:`time.monotonic` time (s) the settling stops at.
    """
    mean_pose = not free and held is None and params.ground is None and params.gravity == 0
    st: Structure = build_structure(cp, params, held, fold_limits, free=free)
    notes = list(st.notes)
    if mean_pose:
        notes = ["the sheet keeps its mean pose (free on the ring, pulled evenly)"]
    ground = None
    if params.ground is not None:
        # nodes lie on the mid-surface: the bottom face touches the ground
        contact = params.ground + 0.5 * params.panel_thickness
        ground = Ground(contact, params.ground_stiffness, params.friction, params.slip)
        if free:  # lay the sheet on the ground
            st.x0[:, 2] = contact
    flat = st.x0.copy()
    strings = _strings(cp, route, flat, params)
    # pre-fold toward the assignments so that the strings have a way to go
    sign = np.zeros(len(st.hinges))
    letters = cp.assignments[st.hinge_edge[st.folds]]
    sign[st.folds] = np.where(letters == "M", -1.0, np.where(letters == "V", 1.0, 0.0))
    st.hinge_rest = sign * math.radians(prefold)
    if ground is not None:
        ground.start(st.x0)
    assembly = HessianAssembly(st, strings)  # its pattern and ordering serve every solve
    # from the flat sheet (not its first Newton step whole: from that bifurcation point the
    # whole step may settle on another branch, docs/simulation.md)
    solve = {"ground": ground, "assembly": assembly, "deadline": deadline}
    x, _ = solve_equilibrium(st.x0.copy(), st, None, **solve)
    place = _Placement(strings, flat, mean_pose)
    if ground is not None:
        ground.start(x)
    table = None if design is None else rigid_table(design)
    return _Run(cp, st, strings, ground, assembly, place, table, notes, x, deadline)


def _fold(run: _Run, route: RouteSpec, rules: StopRules, steps, progress):
    """The continuation loop: states as the TSA turns, until a stop; (rows, :class:`_Stop`)."""
    theta_end = min(route.max_turns * 2 * math.pi, route.tsa.max_theta())
    uniform = None if steps is None else route.max_turns * 2 * math.pi / max(steps, 1)
    rows: dict[str, list] = {}
    previous = None
    theta = 0.0
    window: list[tuple[np.ndarray, np.ndarray]] = []
    held_at_limit = 0
    while True:
        x_new, info = _step_equilibrium(run, theta, previous)
        if info.timed_out and rows:  # an equilibrium cut short is no state: the last one ends
            return rows, _Stop(*time_limit_stop(rules.time_limit, rows["theta"]))
        previous = run.x
        world = run.place.to_world(x_new)
        moved = float(np.max(np.linalg.norm(world - rows["states"][-1], axis=1))) if rows else 0.0
        run.x = x_new
        if run.ground is not None:
            run.ground.start(run.x)
        record, lengths, rho = _record(run, route, theta, info, world, moved)
        for key, value in record.items():
            rows.setdefault(key, []).append(value)
        n = len(rows["theta"])
        if progress is not None:
            progress(n, (steps + 1) if steps is not None else n + 1)
        active = np.abs(rho[run.folds]) >= run.st.hinge_limit[run.folds] - math.radians(0.25)
        held_at_limit = held_at_limit + 1 if active.any() else 0
        window = [*window, (record["take_up"], record["stretch"])][-(rules.jam_steps + 1) :]
        stop = _limit_stop(route, rules, record) or _jam_stop(
            run, route, rules, rows, window, active, held_at_limit
        )
        if stop is None and theta >= theta_end - 1e-12:
            stop = _Stop(*turn_limit_stop(route))
        if stop is None and time.monotonic() > run.deadline:
            stop = _Stop(*time_limit_stop(rules.time_limit, rows["theta"]))
        if stop is not None:
            return rows, stop
        if n >= rules.max_states:
            raise SimulationError(f"no stop after {rules.max_states} states; raise take_up or step")
        dtheta = uniform
        if dtheta is None:
            dtheta = _take_up_step(route, rules, rows, theta, theta_end, lengths)
        theta = min(theta + dtheta, theta_end)


def _step_equilibrium(run: _Run, theta: float, previous: np.ndarray | None):
    """The equilibrium at TSA angle ``theta`` (rad), from ``run.x`` or a secant predictor."""
    st, strings, ground = run.st, run.strings, run.ground
    strings.theta = theta
    update_capstan(run.x, strings)  # friction at the holes, from the last state
    start = run.x
    if previous is not None:  # secant predictor, kept when it starts lower
        guess = 2.0 * run.x - previous
        if total_energy(guess, st, strings, ground) < total_energy(run.x, st, strings, ground):
            start = guess
    return _solve(start, st, strings, ground, run.assembly, run.place, deadline=run.deadline)


def _record(run: _Run, route: RouteSpec, theta: float, info, world, moved: float):
    """The state ``run.x``'s row of the result, its strings' lengths (k, 2) mm, fold angles rad.

    ``world`` is the state in the world frame (n, 3) mm, ``moved`` its largest node
    displacement since the last state, mm.
    """
    x, st, strings, tsa = run.x, run.st, run.strings, route.tsa
    lengths = np.column_stack(string_lengths(x, strings)).reshape(-1, 2)
    rate = np.array([float(tsa.consumed_derivatives(theta, xd)[1]) for xd in lengths[:, 1]])
    taken = np.array(
        [float(tsa.consumed(theta, xd) - tsa.consumed(0.0, xd)) for xd in lengths[:, 1]]
    )
    tensions = np.asarray(info.tensions, dtype=float)
    free_lengths = np.array([s.free_length for s in strings.strings])
    stretch = lengths[:, 0] - free_lengths if len(lengths) else np.zeros(0)
    rho = fold_angles(x, st.hinges)
    angles = np.zeros(run.cp.n_edges)
    angles[run.limit_edges] = rho[run.folds]
    creases = run.cp.edge_mask("M", "V") if run.table is not None else None
    p = fold_ratio_fit(angles, run.table, creases) if run.table is not None else math.nan
    record = {
        "states": world,
        "theta": theta,
        "p": p,
        "tensions": tensions,
        "taut": tensions > 0,
        "torque": float(np.sum(tensions * rate)),
        "fold_angles": np.degrees(angles),
        "take_up": taken,
        "stretch": np.maximum(stretch, 0.0),
        "energy": total_energy(x, st, strings, run.ground),
        "iterations": info.iterations,
        "converged": info.converged,
        "moved": moved,
        "energies": info.energies,
    }
    return record, lengths, rho


def _limit_stop(route: RouteSpec, rules: StopRules, record: dict) -> _Stop | None:
    """A string's tension over ``rules.tension_cap`` or the TSA's torque over the route's."""
    tensions = record["tensions"]
    if len(tensions) and tensions.max() > rules.tension_cap:
        i = int(np.argmax(tensions))
        return _Stop(
            StopReason.TENSION_LIMIT,
            f"string {i + 1}'s tension {tensions[i]:.3g} N exceeds the route's limit of "
            f"{rules.tension_cap:g} N",
        )
    reason = torque_limit_reason(route, record["torque"])
    return None if reason is None else _Stop(StopReason.TORQUE_LIMIT, reason)


def _jam_stop(run, route, rules, rows, window, active, held_at_limit) -> _Stop | None:
    """A jam, or the fold limit when creases are at theirs: strings stretch, not fold.

    ``window`` holds the last (take-up, stretch) pairs (mm), ``active`` which crease
    hinges are at their limit, ``held_at_limit`` for how many states some have been.
    """
    tensions, stretch = rows["tensions"][-1], rows["stretch"][-1]
    free_lengths = np.array([s.free_length for s in run.strings.strings])
    culprit = _stalled(window, rules.jam_ratio, rules.jam_steps, 1e-3 * free_lengths)
    strain = stretch / free_lengths
    if culprit is None and len(strain) and strain.max() > rules.max_string_strain:
        culprit = int(np.argmax(strain))
    length, _ = bar_lengths(run.x, run.st.bars)
    bar_strain = float(np.max(np.abs(length - run.st.bar_rest) / run.st.bar_rest))
    if culprit is None and bar_strain > rules.max_bar_strain and len(tensions):
        culprit = int(np.argmax(tensions))
    if culprit is None and held_at_limit > rules.jam_steps:
        culprit = int(np.argmax(tensions)) if len(tensions) else 0
    if culprit is None:
        return None
    if active.any():
        limited = tuple(int(e) for e in np.unique(run.limit_edges[active]))
        return _Stop(
            StopReason.FOLD_LIMIT,
            f"fold limit reached on crease{'s' if len(limited) > 1 else ''} "
            f"{', '.join(map(str, limited[:8]))}: the strings stretch instead of "
            "folding further",
            limited=limited,
        )
    p = rows["p"][-1]
    segment = _lengthening_segment(run.cp, route, rows["states"], culprit)
    jam = Jam(culprit, segment, p, float(stretch[culprit]))
    return _Stop(
        StopReason.JAM,
        f"jam: string {culprit + 1} stretches ({stretch[culprit]:.3g} mm, "
        f"strain {100 * strain[culprit]:.2g} %) instead of folding the sheet"
        f"{'' if math.isnan(p) else f' at p = {p:.3f}'}; {jam.hint()}",
        jam=jam,
    )


def _take_up_step(route, rules: StopRules, rows, theta, theta_end, lengths) -> float:
    """The next TSA step, rad: ``route.take_up`` mm of string, less where ``p`` moves fast.

    The take-up shrinks (to 1/20 at least) so that the fold ratio changes by about
    ``rules.max_dp`` at most; at most ``route.step`` and never past ``theta_end``.
    """
    ds = route.take_up
    p = rows["p"][-1]
    if len(rows["p"]) > 1 and np.isfinite(p) and np.isfinite(rows["p"][-2]):
        gained = float(np.max(rows["take_up"][-1] - rows["take_up"][-2], initial=0.0))
        speed = abs(p - rows["p"][-2]) / gained if gained > 0 else 0.0
        if speed * ds > rules.max_dp:  # fold at most max_dp per step
            ds = max(rules.max_dp / speed, route.take_up / 20.0)
    return tsa_step(route.tsa, theta, lengths[:, 1], ds, min(route.step, theta_end - theta))


def _result(rows: dict[str, list], stop: _Stop, notes: list[str]) -> SimulationResult:
    """The rows of every state as NumPy columns, with the stop."""
    s = len(rows["theta"])
    return SimulationResult(
        states=np.array(rows["states"]),
        theta=np.array(rows["theta"]),
        p=np.array(rows["p"]),
        tensions=np.array(rows["tensions"]).reshape(s, -1),
        taut=np.array(rows["taut"], dtype=bool).reshape(s, -1),
        torque=np.array(rows["torque"]),
        fold_angles=np.array(rows["fold_angles"]),
        take_up=np.array(rows["take_up"]).reshape(s, -1),
        stretch=np.array(rows["stretch"]).reshape(s, -1),
        energy=np.array(rows["energy"]),
        iterations=np.array(rows["iterations"]),
        converged=np.array(rows["converged"], dtype=bool),
        moved=np.array(rows["moved"]),
        stop=stop.kind,
        reason=stop.reason,
        jam=stop.jam,
        limited_edges=stop.limited,
        notes=notes,
        energies=rows["energies"],
    )


def _solve(x, st, strings, ground, assembly, place: _Placement, rounds=None, deadline=math.inf):
    """One equilibrium; with the mean pose, the anchors consistent with the state's pose.

    The anchors (in the held panel's frame) start from the pose extrapolated from
    the last two states. After the solve the state's pose is fitted; if re-placing
    the anchors for it changes a string's length by more than 1e-4 of the sheet's
    size, they are re-placed and the state solved again, up to ``rounds`` times
    (default :data:`POSE_ROUNDS`), with a secant (Anderson) update since this fixed
    point converges only linearly. The error left does not accumulate (every step
    places the anchors from the states); on the Fig. 5 set-up more rounds change
    the fold ratios by less than the two models differ (docs/simulation.md).
    ``deadline``: a :func:`time.monotonic` time (s) each solve stops at (``info.timed_out``).
    """
    solve = {"ground": ground, "assembly": assembly, "deadline": deadline}
    if place.active:
        place.set(*place.predict())
    x, info = solve_equilibrium(x, st, strings, **solve)
    if not place.active or not place.fixed.any() or info.timed_out:
        return x, info
    tol = 1e-4 * max(float(np.ptp(place.flat, axis=0).max()), 1.0)
    last = None
    for _ in range(POSE_ROUNDS if rounds is None else rounds):
        before = place.lengths(x)
        current = place.anchors()
        place.set(*rigid_fit(x, place.flat))
        target = place.anchors()
        if info.timed_out or np.max(np.abs(place.lengths(x) - before)) < tol:
            break
        if last is not None:  # secant step on the fixed point a = F(a)
            d_res = (target - current) - (last[1] - last[0])
            denom = float(np.sum(d_res * d_res))
            gamma = float(np.sum((target - current) * d_res)) / denom if denom > 0 else 0.0
            if -3.0 < gamma < 0.0:  # accelerate a linear convergence; else plain iteration
                place.put(target - gamma * (target - last[1]))
        last = (current, target)
        x, info = solve_equilibrium(x, st, strings, **solve)
    place.rot, place.shift = rigid_fit(x, place.flat)
    place.accept()
    return x, info


def _stalled(window, ratio: float, count: int, least: np.ndarray) -> int | None:
    """A string the sheet no longer shortens, over the last ``count`` steps, or None.

    Either every taut string stretched by more than ``ratio`` of the string the TSA
    took up (the take-up goes into stretch, not folding), or one string stretched
    by more than twice its take-up (the folding lengthens it: it would have to
    stretch to fold on); in both cases by more than ``least`` (k,) mm over the
    window, so that a string just coming taut is not a jam. Returns the string that
    stretched most.
    """
    if len(window) <= count:
        return None
    taken = window[-1][0] - window[0][0]
    stretched = window[-1][1] - window[0][1]
    taut = (window[-1][1] > 0) & (taken > 1e-9)
    if not taut.any():
        return None
    stalled = bool(np.all(stretched[taut] > ratio * taken[taut])) and bool(
        np.any(stretched[taut] > least[taut])
    )
    lengthened = taut & (stretched > 2.0 * taken) & (stretched > least)
    if not stalled and not lengthened.any():
        return None
    return int(np.argmax(np.where(taut, stretched - taken, -np.inf)))


def _lengthening_segment(cp, route: RouteSpec, states: list[np.ndarray], string: int) -> str:
    """The segment of ``string`` that breaks the DCQC rule, else the one lengthened most.

    Lengthened most since the flat sheet; the same naming as the DCQC model's jam.
    """
    from origami_cad.strings.dcqc import segment_lengths

    s = route.strings[string]
    if s.bad_segments:
        return segment_names(s)[s.bad_segments[0]]
    flat = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    lengths = segment_lengths(cp, np.stack([flat, states[-1]]), s, route.thickness)
    return segment_names(s)[int(np.argmax(lengths[1] - lengths[0]))]
