"""Strings: twisted string actuators, routing through panel holes, DCQC folding (section IV-B)."""

from origami_cad.strings.dcqc import fold_limit, simulate_dcqc
from origami_cad.strings.dcqc_result import DCQCResult, FoldLimit, Jam, StopReason
from origami_cad.strings.route import (
    BOTTOM,
    TOP,
    RouteSpec,
    StringRoute,
    hole_exits,
    load_route,
    side_rule,
    string_lengths,
)
from origami_cad.strings.tsa import (
    TSAParams,
    onboard_angle,
    onboard_compliant_length,
    onboard_contraction,
    onboard_transmission,
    ring_length,
    ring_length_derivatives,
)

__all__ = [
    "BOTTOM",
    "TOP",
    "DCQCResult",
    "FoldLimit",
    "Jam",
    "RouteSpec",
    "StopReason",
    "StringRoute",
    "TSAParams",
    "fold_limit",
    "hole_exits",
    "load_route",
    "onboard_angle",
    "onboard_compliant_length",
    "onboard_contraction",
    "onboard_transmission",
    "ring_length",
    "ring_length_derivatives",
    "side_rule",
    "simulate_dcqc",
    "string_lengths",
]
