"""Fabrication: dual-material printable structures as exact B-rep solids (section III-C, IV-A).

Two steps: :func:`plan_panels` plans the panels as plain data (footprints, holes,
crease limits), :func:`build_fabrication` builds the solids of a plan;
:func:`fabricate` does both.

>>> from origami_cad.fabrication import FabricationParams
>>> round(FabricationParams(bias=3, height=2.2, thickness=0.4).p_max, 3)
0.814
"""

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
    crease_limits,
    largest_bias,
    plan_panels,
)

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
