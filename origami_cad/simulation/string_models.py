"""A pattern folded by a route in either string model: the DCQC model or bar-and-hinge."""

from __future__ import annotations

import dataclasses

from origami_cad.errors import StringsError
from origami_cad.pattern.design import Design
from origami_cad.simulation.model import SimulationParams
from origami_cad.simulation.simulate import simulate
from origami_cad.strings.route import RouteSpec

__all__ = ["STRING_MODELS", "fold_by_strings"]

#: The string models: ``"dcqc"`` (:func:`~origami_cad.strings.simulate_dcqc`) and
#: ``"simulation"`` (:func:`~origami_cad.simulation.simulate`).
STRING_MODELS = ("dcqc", "simulation")


def fold_by_strings(
    loaded: Design,
    spec: RouteSpec,
    model: str = "dcqc",
    *,
    steps: int | None = None,
    fixed_panel: str | None = None,
):
    """Fold ``loaded`` by the route ``spec`` in one string model; writes nothing.

    Parameters
    ----------
    loaded : Design
        The pattern (and its TG, when it has one).
    spec : RouteSpec
        The route; its ``[fabrication]`` gives the materials and fold limits of both
        models (``SimulationParams.for_route``).
    model : {"dcqc", "simulation"}
        The string model.
    steps : int, optional
        The simulation's equal TSA steps (default: steps of string taken up).
    fixed_panel : str, optional
        Hold this panel (its label) instead of the route's own ``fixed_panel``.

    Returns
    -------
    DCQCResult or SimulationResult
        Columnar: ``p (S,)``, ``turns (S,)``, ``fold_angles (S, m)`` rad, ``torque (S,)``
        N mm, why it stopped.

    Raises
    ------
    StringsError
        An unknown model or panel label.
    """
    from origami_cad.strings import simulate_dcqc

    if model not in STRING_MODELS:
        raise StringsError(f"model must be one of {', '.join(STRING_MODELS)}, got {model!r}")
    if fixed_panel is not None:
        if fixed_panel not in loaded.pattern.face_labels:
            raise StringsError(f"fixed panel: no panel labelled {fixed_panel!r}")
        spec = dataclasses.replace(spec, fixed_panel=fixed_panel)
    params = SimulationParams.for_route(spec)
    if model == "dcqc":
        return simulate_dcqc(loaded, spec, **params.dcqc_stiffness())
    return simulate(loaded.pattern, spec, params, design=loaded, steps=steps)
