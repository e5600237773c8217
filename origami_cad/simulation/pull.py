"""A tendon pulled by a test machine: the strings' actuated end moves by a prescribed length.

Beside the TSA (which twists its strings), a tensile test machine pulls the strings'
end at the anchor straight, at a constant rate (PyGamiX's bench: 1000 mm/min). The
pull is quasi-static: each state is the bar-and-hinge equilibrium (the same model as
:func:`~origami_cad.simulation.simulate`) with every string's anchored end drawn in
by ``pull`` mm; the rate only dates the states (``time = pull / rate``). The force
the machine measures is the sum of the strings' tensions at that end, N.
"""

from __future__ import annotations

import dataclasses
import io
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from origami_cad.errors import SimulationError
from origami_cad.pattern.design import Design
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.model import SimulationParams
from origami_cad.simulation.simulate import SimulationResult, simulate
from origami_cad.strings.route import RouteSpec

__all__ = ["BENCH_RATE", "LinearPull", "PullResult", "simulate_pull"]

#: PyGamiX's bench: the test machine pulls at 1000 mm/min, mm/s.
BENCH_RATE = 1000.0 / 60.0


@dataclass(frozen=True)
class LinearPull:
    """The test machine as the strings' actuator: ``theta`` is the pull, mm (not an angle).

    Its share of a string's length is the anchor's free stretch ``x_dis`` plus the
    pull: the string is drawn in through the anchor by ``theta`` mm. It has the
    interface of :class:`~origami_cad.strings.tsa.TSAParams` that the string models use.
    """

    model: str = "pull"

    def consumed(self, theta: Any, x_dis: Any) -> np.ndarray:
        """String taken between the anchor and the first hole, mm: ``x_dis + theta``."""
        return np.asarray(x_dis, dtype=float) + theta

    def consumed_derivatives(self, theta: Any, x_dis: Any):
        """``(length, d/dpull, d/dx_dis, d2/dx_dis2)``: mm, 1, 1 and 0 (1/mm)."""
        x = np.asarray(x_dis, dtype=float)
        one = np.ones_like(x)
        return x + theta, one, one, np.zeros_like(x)

    def max_theta(self) -> float:
        """No limit of its own, mm."""
        return math.inf


@dataclass
class PullResult:
    """The pull's states: ``pull`` (S,) mm, ``time`` (S,) s, ``tension`` (S,) N at the
    actuated end (every string's, summed), and the simulation (states, fold angles,
    each string's tension ``result.tensions`` (S, k) N)."""

    pull: np.ndarray
    time: np.ndarray
    tension: np.ndarray
    result: SimulationResult
    rate: float

    def __len__(self) -> int:
        return len(self.pull)

    def to_csv(self) -> str:
        """``pull.csv``: a header, then ``pull_mm,tension_N,time_s,string_1_N,...`` per state."""
        k = self.result.tensions.shape[1]
        out = io.StringIO()
        names = ["pull_mm", "tension_N", "time_s", *(f"string_{i + 1}_N" for i in range(k))]
        out.write(",".join(names) + "\n")
        for s in range(len(self)):
            row = [self.pull[s], self.tension[s], self.time[s], *self.result.tensions[s]]
            out.write(",".join(f"{v:.6g}" for v in row) + "\n")
        return out.getvalue()

    def to_dict(self) -> dict[str, Any]:
        """The JSON form: the pull's columns and the simulation's (``simulation.json``)."""
        return {
            "rate_mm_per_s": self.rate,
            "pull_mm": self.pull.tolist(),
            "tension_N": self.tension.tolist(),
            "peak_tension_N": float(self.tension.max(initial=0.0)),
            "simulation": _pull_states(self.result.to_dict(), self.pull),
        }


def _pull_states(sim: dict[str, Any], pull: np.ndarray) -> dict[str, Any]:
    """The simulation's JSON with its states labelled by the pull (mm), not by a TSA's
    turns, twist or torque (the machine has none)."""
    states = sim["states"]
    for key in ("turns", "theta_s_deg", "tsa_torque_Nmm"):
        states.pop(key, None)
    sim["states"] = {"pull_mm": pull.tolist(), **states}
    return sim


def simulate_pull(
    cp: CreasePattern,
    route: RouteSpec,
    pull: float,
    params: SimulationParams | None = None,
    *,
    rate: float = BENCH_RATE,
    step: float = 1.0,
    design: Design | None = None,
    fixed_panel: str | None = None,
    prefold: float = 3.0,
    progress: Callable[[int, int], None] | None = None,
) -> PullResult:
    """Pull the route's strings at their anchors by ``pull`` mm, as a test machine does.

    Parameters
    ----------
    cp, route
        The pattern and its strings (mm); the route's TSA is replaced by the machine.
        Every string is pulled by the same length (one crosshead).
    pull : float
        The crosshead's travel, mm (> 0).
    params : SimulationParams, optional
        Materials and loads (default: the route's sheet, :meth:`SimulationParams.for_route`).
    rate : float
        The crosshead's speed, mm/s (dates the states; the model is quasi-static).
    step : float
        Pull per state, mm (the states are ``ceil(pull / step) + 1``).
    design, fixed_panel, prefold, progress
        As :func:`~origami_cad.simulation.simulate` (``fixed_panel`` a panel label;
        default the route's, from the design's fixed panels).

    Returns
    -------
    PullResult
        Force against pull; raises :class:`SimulationError` for a bad pull, rate or step.
    """
    for name, value in (("pull", pull), ("rate", rate), ("step", step)):
        if not (math.isfinite(value) and value > 0):
            raise SimulationError(f"the {name} must be a finite number > 0, got {value!r}")
    steps = max(1, math.ceil(pull / step))
    machine = dataclasses.replace(route, tsa=LinearPull(), max_turns=pull / (2.0 * math.pi))
    result = simulate(
        cp,
        machine,
        params or SimulationParams.for_route(route),
        design=design,
        steps=steps,
        fixed_panel=fixed_panel,
        prefold=prefold,
        # the machine pulls on whatever the sheet does: only its travel ends the test
        jam_ratio=math.inf,
        max_string_strain=math.inf,
        max_bar_strain=math.inf,
        tension_limit=1e6,  # N: no stop by tension (the test machine's own limit)
        progress=progress,
    )
    result.reason = f"the machine pulled {pull:g} mm"
    result.notes[-1] = result.reason
    travel = np.asarray(result.theta, dtype=float)  # the pull, mm
    return PullResult(travel, travel / rate, result.tensions.sum(axis=1), result, rate)
