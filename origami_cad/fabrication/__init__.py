"""Fabrication: dual-material printable structures as exact B-rep solids (section III-C, IV-A).

Two steps: :func:`plan_panels` plans the panels as plain data (footprints, holes,
crease limits), :func:`build_fabrication` builds the solids of a plan;
:func:`fabricate` does both.

The names are imported on first use, so that the plain-data modules (``params``,
``panels``, ``plan``) load without build123d: ``origami-cad --help`` and the commands
that build no solid start without OCP.

>>> from origami_cad.fabrication import FabricationParams
>>> round(FabricationParams(bias=3, height=2.2, thickness=0.4).p_max, 3)
0.814
"""

from __future__ import annotations

import importlib

#: ``typing.TYPE_CHECKING`` without importing typing (true for type checkers only)
TYPE_CHECKING = False

#: Each public name and the module it comes from.
_NAMES = {
    "Fabrication": "build",
    "build_fabrication": "build",
    "fabricate": "build",
    "write_fabrication": "build",
    "PanelOutline": "panels",
    "offset_ring": "panels",
    "panel_outlines": "panels",
    "plan_holes": "panels",
    "DENSITY_G_CM3": "params",
    "FabricationParams": "params",
    "bias_for_p_max": "params",
    "bias_for_theta_max": "params",
    "fabrication_params": "params",
    "theta_max": "params",
    "DEFAULT_BED": "plan",
    "CreaseLimits": "plan",
    "LimitStatus": "plan",
    "PanelPlan": "plan",
    "check_bed": "plan",
    "check_panel_count": "plan",
    "crease_limits": "plan",
    "largest_bias": "plan",
    "plan_panels": "plan",
}

#: The same names as ``_NAMES``'s keys.
__all__ = [
    "DEFAULT_BED",
    "DENSITY_G_CM3",
    "CreaseLimits",
    "Fabrication",
    "FabricationParams",
    "LimitStatus",
    "PanelOutline",
    "PanelPlan",
    "bias_for_p_max",
    "bias_for_theta_max",
    "build_fabrication",
    "check_bed",
    "check_panel_count",
    "crease_limits",
    "fabricate",
    "fabrication_params",
    "largest_bias",
    "offset_ring",
    "panel_outlines",
    "plan_holes",
    "plan_panels",
    "theta_max",
    "write_fabrication",
]

if TYPE_CHECKING:  # for type checkers; at run time: __getattr__
    from origami_cad.fabrication.build import (
        Fabrication,
        build_fabrication,
        fabricate,
        write_fabrication,
    )
    from origami_cad.fabrication.panels import (
        PanelOutline,
        offset_ring,
        panel_outlines,
        plan_holes,
    )
    from origami_cad.fabrication.params import (
        DENSITY_G_CM3,
        FabricationParams,
        bias_for_p_max,
        bias_for_theta_max,
        fabrication_params,
        theta_max,
    )
    from origami_cad.fabrication.plan import (
        DEFAULT_BED,
        CreaseLimits,
        LimitStatus,
        PanelPlan,
        check_bed,
        check_panel_count,
        crease_limits,
        largest_bias,
        plan_panels,
    )


def __getattr__(name: str) -> object:
    module = _NAMES.get(name)
    if module is None:
        raise AttributeError(f"module 'origami_cad.fabrication' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"origami_cad.fabrication.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
