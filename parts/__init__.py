"""Parametric hardware around the origami, as build123d parts (mm, z up, pattern frame).

Installed as ``origami_cad.parts`` (the folder stays at the top of the repository).
Every part is a build123d ``BasePartObject`` (:class:`TSAModule`, :class:`RingRail`,
:class:`Blocker`, :class:`DriverAdapter`, all :class:`~.base.OrigamiPart`): it builds
at its defaults with no argument, takes ``rotation``, ``align`` and ``mode`` as
build123d's own parts do, adds itself to an active ``BuildPart`` (nothing it builds on
the way leaks into the user's builder), has labelled children and named
``RigidJoint`` s at its mounting features. Every part has a typed parameter
dataclass (units in its field docs) and is listed in
:data:`~origami_cad.parts.registry.PARTS`, from which ``origami-cad part`` and its
``--list`` are generated:

==================  =========================================  =========================
name                builder                                    parameters
==================  =========================================  =========================
``tsa-module``      :func:`.tsa_module.tsa_module`             :class:`TSAModuleParams`
``ring-rail``       :func:`.ring_rail.ring_rail`               :class:`RingRailParams`
``blocker``         :func:`.blocker.blocker`                   :class:`BlockerParams`
``driver-adapter``  :func:`.driver_adapter.driver_adapter`     :class:`DriverAdapterParams`
==================  =========================================  =========================
"""

from .base import OrigamiPart
from .blocker import Blocker, BlockerParams, blocker, blocker_frame
from .driver_adapter import DriverAdapter, DriverAdapterParams, driver_adapter
from .registry import (
    PARTS,
    PartSpec,
    Placement,
    build_part,
    parse_part_options,
    parts_listing,
)
from .ring_rail import RingRail, RingRailParams, ring_anchor_points, ring_rail
from .tsa_module import SERVOS, TSAModule, TSAModuleParams, tsa_module

__all__ = [
    "PARTS",
    "SERVOS",
    "Blocker",
    "BlockerParams",
    "DriverAdapter",
    "DriverAdapterParams",
    "OrigamiPart",
    "PartSpec",
    "Placement",
    "RingRail",
    "RingRailParams",
    "TSAModule",
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
