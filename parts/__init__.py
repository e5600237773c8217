"""Parametric hardware around the origami, as build123d parts (mm, z up, pattern frame).

======================  ==============================================================
name                    function
======================  ==============================================================
``tsa-module``          :func:`parts.tsa_module.tsa_module`: servo, twist hub, exit guide, mount
``ring-rail``           :func:`parts.ring_rail.ring_rail`: ring slide rail with TSA carriages
``blocker``             :func:`parts.blocker.blocker`: clip that stops a crease at an angle
``driver-adapter``      :func:`parts.driver_adapter.driver_adapter`: plate for servo plugs
======================  ==============================================================
"""

from parts.blocker import blocker
from parts.driver_adapter import driver_adapter
from parts.ring_rail import ring_anchor_points, ring_rail
from parts.tsa_module import SERVOS, tsa_module

#: CLI name of each part and its builder.
PARTS = {
    "tsa-module": tsa_module,
    "ring-rail": ring_rail,
    "blocker": blocker,
    "driver-adapter": driver_adapter,
}

__all__ = [
    "PARTS",
    "SERVOS",
    "blocker",
    "driver_adapter",
    "ring_anchor_points",
    "ring_rail",
    "tsa_module",
]
