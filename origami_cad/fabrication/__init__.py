"""Fabrication: dual-material printable structures as exact B-rep solids (section III-C, IV-A).

>>> from origami_cad.fabrication import FabricationParams
>>> round(FabricationParams(bias=3, height=2.2, thickness=0.4).p_max, 3)
0.814
"""

from origami_cad.fabrication.build import Fabrication, crease_limits, fabricate, write_fabrication
from origami_cad.fabrication.panels import PanelOutline, offset_ring, panel_outlines, place_holes
from origami_cad.fabrication.params import (
    DENSITY_G_CM3,
    FabricationParams,
    bias_for_theta_max,
    theta_max,
)

__all__ = [
    "DENSITY_G_CM3",
    "Fabrication",
    "FabricationParams",
    "PanelOutline",
    "bias_for_theta_max",
    "crease_limits",
    "fabricate",
    "offset_ring",
    "panel_outlines",
    "place_holes",
    "theta_max",
    "write_fabrication",
]
