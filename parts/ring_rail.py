"""The ring-shaped slide rail of the paper's Fig. 5d, carrying external TSAs around the sheet.

The ring is centred on ``centre`` (pattern coordinates, mm) with its top ``z_top``
above the sheet's bottom face; each carriage slides on the ring, is locked by a
screw, and guides its TSA's strings through an eyelet on the ring's inner edge.
:func:`ring_anchor_points` gives those eyelets in the frame of the route files, so
a routing can be set up from the rail.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from build123d import Box, Compound, Cylinder, Location, Part

from origami_cad.errors import DesignError

__all__ = ["ring_anchor_points", "ring_rail"]


#: Thickness of a carriage's walls, mm; the string eyelet goes through its inner wall.
WALL = 2.0


def ring_anchor_points(
    inner_diameter: float = 140.0,
    angles: Sequence[float] = (45.0, 135.0, 225.0, 315.0),
    centre: Sequence[float] = (0.0, 0.0),
    z_top: float = 20.0,
    height: float = 8.0,
) -> list[list[float]]:
    """Where the strings leave the carriages' eyelets, ``[x, y, z]`` mm (route ``anchor``).

    The eyelet crosses the carriage's inner wall at half the ring's height; the
    point is on the wall's inner face, toward the sheet. Arguments as :func:`ring_rail`.
    """
    r = inner_diameter / 2.0 - WALL
    z = z_top - height / 2.0
    return [
        [centre[0] + r * math.cos(math.radians(a)), centre[1] + r * math.sin(math.radians(a)), z]
        for a in angles
    ]


def ring_rail(
    inner_diameter: float = 140.0,
    width: float = 12.0,
    height: float = 8.0,
    angles: Sequence[float] = (45.0, 135.0, 225.0, 315.0),
    centre: Sequence[float] = (0.0, 0.0),
    z_top: float = 20.0,
    carriage_length: float = 24.0,
    carriage_height: float = 10.0,
    lock_screw: float = 3.2,
    eyelet: float = 2.0,
) -> Compound:
    """The rail (a ring) and its carriages, as an assembly with named children.

    Parameters
    ----------
    inner_diameter : float
        Diameter of the inner circular space, mm (the paper: 140, a 70 mm radius).
    width, height : float
        Radial width and height of the ring, mm.
    angles : sequence of float
        Angular positions of the carriages, degrees.
    centre : (float, float)
        Centre of the ring in pattern coordinates, mm.
    z_top : float
        Height of the ring's top above the sheet's bottom face, mm.
    carriage_length, carriage_height : float
        Size of each carriage along the ring and above it, mm.
    lock_screw, eyelet : float
        Diameters of each carriage's lock-screw hole and string eyelet, mm.
    """
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
