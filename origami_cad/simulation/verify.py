"""Checking a planned string route with the bar-and-hinge simulator.

:func:`~origami_cad.strings.plan.plan_routes` ranks routes on the fast DCQC
model; :func:`verify_route` folds the sheet by the route with the full
simulation (:func:`~origami_cad.simulation.simulate`) and says whether it reaches
the route's target fold ratio without a jam.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from origami_cad.pattern.design import Design
from origami_cad.simulation.model import SimulationParams
from origami_cad.simulation.simulate import simulate
from origami_cad.strings.dcqc import fold_limit
from origami_cad.strings.dcqc_result import StopReason
from origami_cad.strings.route import RouteSpec

__all__ = ["verify_planned", "verify_route"]


def verify_route(
    design: Design,
    spec: RouteSpec,
    params: SimulationParams | None = None,
    *,
    steps: int | None = None,
    tolerance: float = 0.03,
    time_limit: float = math.inf,
) -> dict[str, Any]:
    """Fold ``design`` by ``spec`` with the bar-and-hinge model; the figures and a verdict.

    ``params`` default: :meth:`SimulationParams.for_route` (the route's
    ``[fabrication]``, the same fold limit as the DCQC model). ``steps``: equal TSA steps
    up to the route's ``max_turns`` (default: steps of string taken up). The route
    passes when the simulation stops at the fold limit (or its ``p_max``) within
    ``tolerance`` in p of the target and no string jams. ``time_limit``: wall-clock
    seconds the simulation may take (its stop is then ``time_limit``).

    Returns
    -------
    dict
        ``p``, ``turns``, ``peak_torque_Nmm``, ``peak_tension_N``, ``stop``,
        ``reason``, ``target_p`` and ``reaches_target``.
    """
    params = SimulationParams.for_route(spec) if params is None else params
    target = fold_limit(design, spec).p
    result = simulate(
        design.pattern, spec, params, design=design, steps=steps, time_limit=time_limit
    )
    p = float(np.nan_to_num(result.p[-1]))
    reaches = result.stop is not StopReason.JAM and p >= target - tolerance
    return {
        "p": p,
        "turns": float(result.turns[-1]),
        "peak_torque_Nmm": float(np.max(result.torque, initial=0.0)),
        "peak_tension_N": float(np.max(result.tensions, initial=0.0)),
        "stop": result.stop.value,
        "reason": result.reason,
        "target_p": float(target),
        "reaches_target": bool(reaches),
    }


def verify_planned(
    loaded: Design, geometry, planned: list, count: int, *, first=None, deadline=math.inf
) -> list:
    """The planned routes with the best ``count`` folded by the bar-and-hinge simulator.

    Parameters
    ----------
    loaded : Design
        The pattern the routes thread.
    geometry : PlanGeometry
        The search's geometry (``plan_geometry``), which gives each route's spec.
    planned : list of PlannedRoute
        The ranked routes (``plan_routes``).
    count : int
        How many of the best are simulated (30 steps each).
    first : path-like, optional
        The route file the best was written to: it is read back as ``route`` and
        ``simulate`` read it, so the check is of the file (nothing is written).
    deadline : float, optional
        A ``time.time()`` (s): each simulation stops there (its stop ``time_limit``, the
        whole seconds left), and the routes left with less than a second are not simulated.

    Returns
    -------
    list of PlannedRoute
        The same routes; the simulated ones with ``checks["simulation"]``
        (:func:`verify_route`'s record).
    """
    import dataclasses

    from origami_cad.strings import load_route
    from origami_cad.strings.plan import route_spec

    out = []
    for k, r in enumerate(planned):
        left = math.floor(deadline - time.time())  # whole seconds: its stop names them
        if k < count and left >= 1:
            read = k == 0 and first is not None
            spec = load_route(first, loaded.pattern) if read else route_spec(geometry, r)
            sim = verify_route(loaded, spec, steps=30, time_limit=left)
            r = dataclasses.replace(r, checks={**r.checks, "simulation": sim})
        out.append(r)
    return out
