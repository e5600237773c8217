"""Parametric hardware around the origami, as build123d parts (mm, z up, pattern frame).

Installed as ``origami_cad.parts`` (the folder stays at the top of the repository).
Every part has a typed parameter dataclass (units in its field docs) and is listed
in :data:`~origami_cad.parts.registry.PARTS`, from which ``origami-cad part`` and
its ``--list`` are generated:

==================  =========================================  =========================
name                builder                                    parameters
==================  =========================================  =========================
``tsa-module``      :func:`.tsa_module.tsa_module`             :class:`TSAModuleParams`
``ring-rail``       :func:`.ring_rail.ring_rail`               :class:`RingRailParams`
``blocker``         :func:`.blocker.blocker`                   :class:`BlockerParams`
``driver-adapter``  :func:`.driver_adapter.driver_adapter`     :class:`DriverAdapterParams`
==================  =========================================  =========================
"""

from .blocker import BlockerParams, blocker, blocker_frame
from .driver_adapter import DriverAdapterParams, driver_adapter
from .registry import (
    PARTS,
    PartSpec,
    Placement,
    build_part,
    parse_part_options,
    parts_listing,
)
from .ring_rail import RingRailParams, ring_anchor_points, ring_rail
from .tsa_module import SERVOS, TSAModuleParams, tsa_module

__all__ = [
    "PARTS",
    "SERVOS",
    "BlockerParams",
    "DriverAdapterParams",
    "PartSpec",
    "Placement",
    "RingRailParams",
    "TSAModuleParams",
    "blocker",
    "blocker_frame",
    "build_part",
    "driver_adapter",
    "parse_part_options",
    "parts_listing",
    "ring_anchor_points",
    "ring_rail",
    "tsa_module",
]
