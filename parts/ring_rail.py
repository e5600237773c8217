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

from build123d import (
    Align,
    Axis,
    Compound,
    Cylinder,
    Edge,
    Face,
    Location,
    Mode,
    Part,
    Plane,
    Solid,
    Vector,
    Wire,
)

from origami_cad.errors import FabricationError

from .base import OrigamiPart
from .parameters import check_params, resolve_params, spec

__all__ = ["CLEARANCE", "WALL", "RingRail", "RingRailParams", "ring_anchor_points", "ring_rail"]


#: Thickness of a carriage's walls, mm; the string eyelet goes through its inner wall.
WALL = 2.0
#: Gap between a carriage and the rail, mm (radially on both sides and above).
CLEARANCE = 0.2


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

    def __post_init__(self) -> None:
        check_params(self)


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


def _sector(r0: float, r1: float, a0: float, a1: float, z0: float, z1: float) -> Solid:
    """The annular sector ``r0 <= r <= r1``, ``a0 <= angle <= a1`` (deg), ``z0 <= z <= z1``.

    Centred on the origin; radii and heights in mm.
    """
    plane = Plane.XY.offset(z0)
    span = a1 - a0  # built from angle 0, away from the circle's seam, then turned to a0
    outer = Edge.make_circle(r1, plane, start_angle=0.0, end_angle=span)
    inner = Edge.make_circle(r0, plane, start_angle=0.0, end_angle=span)
    ends = [
        Edge.make_line(inner.position_at(0), outer.position_at(0)),
        Edge.make_line(outer.position_at(1), inner.position_at(1)),
    ]
    face = Face(Wire([ends[0], outer, ends[1], inner.reversed()]))
    return Solid.extrude(face, Vector(0, 0, z1 - z0)).rotate(Axis.Z, a0)


class RingRail(OrigamiPart):
    """The rail (a ring) and its carriages, a build123d part with named children.

    Children ``rail``, ``carriage 1 (45 deg)``... Each carriage is an arc of the ring's
    own curvature: a top and two curved walls around the rail, ``CLEARANCE`` (mm) from it
    everywhere (radially on both sides and above), so it slides on the printed ring
    without interference. Joints ``seat 1``, ``seat 2``... (``RigidJoint``): where each
    carriage sits, on the ring's top at its mid-radius, x pointing out from the centre,
    z up.

    Parameters
    ----------
    params : RingRailParams, optional
        The parameters (default ``RingRailParams()``; the paper's ring has a 70 mm
        inner radius).
    rotation, align, mode
        As for build123d's own parts (degrees; ``Align``; ``Mode``).
    **values
        Parameters to change, by name (Python values or text, see
        :class:`RingRailParams` for units): ``RingRail(angles=(0, 120, 240))``.
    """

    def __init__(
        self,
        params: RingRailParams | None = None,
        *,
        rotation: Any = (0, 0, 0),
        align: Align | tuple[Align, Align, Align] | None = None,
        mode: Mode = Mode.ADD,
        **values: Any,
    ):
        p = resolve_params(RingRailParams, params, values)
        tree, seats = _build(p)
        super().__init__(tree, seats, p, rotation, align, mode)


def ring_rail(params: RingRailParams | None = None, **values: Any) -> RingRail:
    """The ring rail and its carriages: :class:`RingRail` (same parameters)."""
    return RingRail(params, **values)


def _check_carriages(p: RingRailParams, half: float) -> None:
    """Refuse carriages that cannot be made: holes wider than their walls, overlaps (mm, deg)."""
    if not p.eyelet < min(p.height, p.carriage_length):
        limit = min(p.height, p.carriage_length)
        raise FabricationError(
            f"parameter eyelet: {p.eyelet:g} mm does not fit the carriage's wall beside a ring "
            f"{p.height:g} mm high and a carriage {p.carriage_length:g} mm long; it must be "
            f"< {limit:g} mm"
        )
    if not p.lock_screw < min(p.width, p.carriage_length):
        limit = min(p.width, p.carriage_length)
        raise FabricationError(
            f"parameter lock_screw: {p.lock_screw:g} mm is wider than the {p.width:g} mm ring "
            f"it presses on (width); it must be < {limit:g} mm"
        )
    order = sorted(((a % 360.0, k) for k, a in enumerate(p.angles)))
    for (a, i), (b, j) in zip(order, [*order[1:], (order[0][0] + 360.0, order[0][1])], strict=True):
        if len(order) > 1 and b - a < 2 * half:
            raise FabricationError(
                f"parameter angles: carriages {i + 1} ({p.angles[i]:g} deg) and {j + 1} "
                f"({p.angles[j]:g} deg) overlap; carriages {p.carriage_length:g} mm long "
                f"need at least {2 * half:.1f} deg between them on this ring"
            )


def _build(p: RingRailParams) -> tuple[Compound, dict[str, Location]]:
    """The rail's tree and its carriage seats, mm."""
    inner_diameter, width, height, angles = p.inner_diameter, p.width, p.height, p.angles
    centre, z_top, carriage_length = p.centre, p.z_top, p.carriage_length
    carriage_height, lock_screw, eyelet = p.carriage_height, p.lock_screw, p.eyelet
    if not inner_diameter > 0 or not width > 0 or not height > 0:
        raise FabricationError("inner_diameter, width and height must be > 0 mm")
    if not len(angles):
        raise FabricationError("at least one carriage angle is needed")
    r_in = inner_diameter / 2.0
    r_out = r_in + width
    if r_in - WALL <= 0:
        raise FabricationError(f"inner_diameter must exceed {2 * WALL:g} mm (the carriage walls)")
    cx, cy = float(centre[0]), float(centre[1])
    z0 = z_top - height
    ring = Cylinder(r_out, height, align=None) - Cylinder(r_in, height, align=None)
    ring = ring.moved(Location((cx, cy, z0)))
    ring.label = "rail"
    children = [ring]
    r_mid = (r_in + r_out) / 2.0
    half = math.degrees(carriage_length / 2.0 / r_mid)  # half the carriage's arc, deg
    if not half < 90.0:
        raise FabricationError(
            f"carriage_length {carriage_length:g} mm is too long for a ring of "
            f"inner diameter {inner_diameter:g} mm"
        )
    _check_carriages(p, half)
    top = z0 + carriage_height + WALL
    for k, a in enumerate(angles):
        # a U-shaped arc straddling the ring, hanging a wall inside it with the eyelet
        outer = _sector(r_in - WALL, r_out + WALL, a - half, a + half, z0, top)
        slot = _sector(
            r_in - CLEARANCE,
            r_out + CLEARANCE,
            a - half - 1,
            a + half + 1,
            z0 - 1,
            z0 + height + CLEARANCE,
        )
        ca, sa = math.cos(math.radians(a)), math.sin(math.radians(a))
        screw = Cylinder(lock_screw / 2, top - z0, align=None).moved(
            Location((r_mid * ca, r_mid * sa, z0 + height - 1))
        )
        # the eyelet: radial, through the inner wall at half the ring's height
        eye = Cylinder(eyelet / 2, 2 * WALL, align=None).moved(
            Location(
                ((r_in - 1.5 * WALL) * ca, (r_in - 1.5 * WALL) * sa, z0 + height / 2),
                (-sa, ca, 0),
                90,
            )
        )
        body = (outer - slot - screw - eye).moved(Location((cx, cy, 0)))
        body = Part(Compound(body.solids()).wrapped)
        body.label = f"carriage {k + 1} ({a:g} deg)"
        children.append(body)
    assembly = Compound(children=children)
    assembly.label = "ring rail"
    seats = {
        f"seat {k + 1}": Location((cx, cy, z_top), (0, 0, 1), a) * Location((r_mid, 0.0, 0.0))
        for k, a in enumerate(angles)
    }
    return assembly, seats
