"""The ring-shaped slide rail of the paper's Fig. 5d, carrying external TSAs around the sheet.

The ring is centred on ``centre`` (pattern coordinates, mm) with its top ``z_top``
above the sheet's bottom face; each carriage slides on the ring, is locked by a
screw, and guides its TSA's strings through an eyelet on the ring's inner edge.
:func:`ring_anchor_points` gives those eyelets in the frame of the route files, so
a routing can be set up from the rail.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from build123d import Box, Compound, Cylinder, Location, Part

from origami_cad.errors import DesignError

from .parameters import resolve_params, spec

__all__ = ["RingRailParams", "ring_anchor_points", "ring_rail"]


#: Thickness of a carriage's walls, mm; the string eyelet goes through its inner wall.
WALL = 2.0


@dataclass(frozen=True)
class RingRailParams:
    """Parameters of :func:`ring_rail`."""

    inner_diameter: float = field(
        default=140.0, metadata=spec("mm", "diameter of the inner circular space", low=0.0)
    )
    width: float = field(default=12.0, metadata=spec("mm", "radial width of the ring", low=0.0))
    height: float = field(default=8.0, metadata=spec("mm", "height of the ring", low=0.0))
    angles: tuple[float, ...] = field(
        default=(45.0, 135.0, 225.0, 315.0),
        metadata=spec("deg", "angular positions of the carriages"),
    )
    centre: tuple[float, float] = field(
        default=(0.0, 0.0), metadata=spec("mm", "centre of the ring (pattern frame)")
    )
    z_top: float = field(
        default=20.0, metadata=spec("mm", "height of the ring's top above the sheet's bottom face")
    )
    carriage_length: float = field(
        default=24.0, metadata=spec("mm", "length of a carriage along the ring", low=0.0)
    )
    carriage_height: float = field(
        default=10.0, metadata=spec("mm", "height of a carriage above the ring", low=0.0)
    )
    lock_screw: float = field(
        default=3.2, metadata=spec("mm", "diameter of each carriage's lock-screw hole", low=0.0)
    )
    eyelet: float = field(
        default=2.0, metadata=spec("mm", "diameter of each carriage's string eyelet", low=0.0)
    )


def ring_anchor_points(params: RingRailParams | None = None, **values: Any) -> list[list[float]]:
    """Where the strings leave the carriages' eyelets, ``[x, y, z]`` mm (route ``anchor``).

    The eyelet crosses the carriage's inner wall at half the ring's height; the
    point is on the wall's inner face, toward the sheet. Parameters as :func:`ring_rail`.
    """
    p = resolve_params(RingRailParams, params, values)
    r = p.inner_diameter / 2.0 - WALL
    z = p.z_top - p.height / 2.0
    cx, cy = p.centre
    return [
        [cx + r * math.cos(math.radians(a)), cy + r * math.sin(math.radians(a)), z]
        for a in p.angles
    ]


def ring_rail(params: RingRailParams | None = None, **values: Any) -> Compound:
    """The rail (a ring) and its carriages, as an assembly with named children.

    Parameters
    ----------
    params : RingRailParams, optional
        The parameters (default ``RingRailParams()``; the paper's ring has a 70 mm
        inner radius).
    **values
        Parameters to change, by name (Python values or text, see
        :class:`RingRailParams` for units): ``ring_rail(angles=(0, 120, 240))``.
    """
    p = resolve_params(RingRailParams, params, values)
    inner_diameter, width, height, angles = p.inner_diameter, p.width, p.height, p.angles
    centre, z_top, carriage_length = p.centre, p.z_top, p.carriage_length
    carriage_height, lock_screw, eyelet = p.carriage_height, p.lock_screw, p.eyelet
    if not inner_diameter > 0 or not width > 0 or not height > 0:
        raise DesignError("inner_diameter, width and height must be > 0 mm")
    if not len(angles):
        raise DesignError("at least one carriage angle is needed")
    r_in = inner_diameter / 2.0
    r_out = r_in + width
    cx, cy = float(centre[0]), float(centre[1])
    z0 = z_top - height
    ring = Cylinder(r_out, height, align=None) - Cylinder(r_in, height, align=None)
    ring = ring.moved(Location((cx, cy, z0)))
    ring.label = "rail"
    children = [ring]
    wall = WALL
    for k, a in enumerate(angles):
        # a U-shaped carriage straddling the ring, hanging a wall inside it with the eyelet
        outer = Box(carriage_length, width + 2 * wall, carriage_height + wall, align=None)
        outer = outer.moved(Location((-carriage_length / 2, -wall, 0)))
        slot = Box(carriage_length + 2, width + 0.4, height + 0.2, align=None)
        slot = slot.moved(Location((-carriage_length / 2 - 1, -0.2, -0.01)))
        shell = outer - slot
        screw = Cylinder(lock_screw / 2, carriage_height + 2 * wall, align=None)
        screw = screw.moved(Location((0, width / 2, height - 1)))
        eye = Cylinder(eyelet / 2, 3 * wall, align=None).moved(
            Location((0, -wall - 1, height / 2), (1, 0, 0), -90)
        )
        body = shell - screw - eye
        # local frame: x along the ring, y radial outward from the inner edge, z up from z0
        yaw = a - 90.0
        ca, sa = math.cos(math.radians(a)), math.sin(math.radians(a))
        body = body.moved(Location((cx + r_in * ca, cy + r_in * sa, z0), (0, 0, 1), yaw))
        if not isinstance(body, Part):
            body = Part(body.wrapped)
        body.label = f"carriage {k + 1} ({a:g} deg)"
        children.append(body)
    assembly = Compound(children=children)
    assembly.label = "ring rail"
    return assembly
