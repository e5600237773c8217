"""Blockers (the paper's Fig. 7a): clips that stop a crease's fold at a set angle.

The blocker sits on the outer face of one panel (``A``) across the crease. Its stop
face is the plane that the other panel's (``B``) outer face reaches when the crease
has folded by ``angle``: rotating ``B`` about the crease axis (on the crease layer
surface, where eq. 6's chamfers hinge) leaves a gap below the angle and brings ``B``'s
outer face flat against the stop face at it.
"""

from __future__ import annotations

import math

import numpy as np
from build123d import Location, Part, Plane, Polyline, extrude, make_face

from origami_cad.errors import DesignError

__all__ = ["blocker", "blocker_frame"]


def blocker_frame(fab, crease: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, int, int]:
    """Frame of a crease of a fabricated pattern.

    Returns ``(start, direction, across, face_a, face_b)``: the crease's start
    point and unit direction (mm, in the pattern), the unit vector pointing into
    panel ``B`` (the face on the crease's right), and the two face indices.
    """
    cp = fab.pattern
    if not 0 <= crease < cp.n_edges or cp.assignments[crease] not in ("M", "V"):
        raise DesignError(f"edge {crease} is not a mountain or valley crease of the pattern")
    ef = cp.edge_faces()[crease]
    if (ef < 0).any():
        raise DesignError(f"crease {crease} does not join two panels")
    a, b = cp.vertices[cp.edges[crease]]
    direction = (b - a) / np.linalg.norm(b - a)
    across = np.array([direction[1], -direction[0]])  # right of the edge: face column 1
    return a, direction, across, int(ef[0]), int(ef[1])


def blocker(
    fab=None,
    crease: int | None = None,
    angle: float = 60.0,
    length: float = 10.0,
    reach: float = 5.0,
    base: float = 6.0,
    clearance: float = 0.0,
    bias: float = 3.0,
    height: float = 2.2,
    thickness: float = 0.4,
) -> Part:
    """A blocker stopping a valley crease at ``angle`` degrees.

    Parameters
    ----------
    fab : Fabrication, optional
        A fabricated pattern; with ``crease`` the blocker is placed on that crease
        (its panel ``A`` is the face on the crease's left) in the pattern frame, and
        its ``bias``, ``height`` and ``thickness`` are taken from it.
    crease : int, optional
        Edge index of a valley crease of ``fab.pattern``.
    angle : float
        Fold angle at which the crease stops, degrees (0 < angle < eq. 6's theta_max).
    length : float
        Length of the blocker along the crease, mm.
    reach : float
        How far past panel B's chamfer the stop face meets B's outer face, mm.
    base : float
        Length of the foot bonded to panel A's outer face, mm.
    clearance : float
        Gap left at the stop angle, mm (0: contact).
    bias, height, thickness : float
        ``b``, ``h``, ``t`` of the panels, mm, when no ``fab`` is given: the
        blocker is then built for a crease along +y through the origin, panel
        ``B`` on the +x side.
    """
    if fab is not None:
        bias, height, thickness = fab.params.bias, fab.params.height, fab.params.thickness
        theta_max = math.degrees(fab.params.theta_max)
    else:
        theta_max = math.degrees(2 * math.atan(2 * bias / (height - thickness)))
    if not 0 < angle < min(theta_max, 180.0):
        raise DesignError(f"angle must lie in (0, {theta_max:.1f}) deg (theta_max), got {angle}")
    rho = math.radians(angle)
    z_c = (height + thickness) / 2  # hinge: the crease layer's upper surface
    d = height - z_c + clearance  # distance of the outer face from the hinge

    def u_at(z: float) -> float:
        # B's outer face at the stop: the plane z = h turned by rho about the hinge
        return (math.cos(rho) * (z - z_c) - d) / math.sin(rho)

    # the stop face must cover B's outer face from its chamfer edge (u = b) to b + reach
    far_u, far_z = bias + reach, height - z_c
    top = z_c + far_u * math.sin(rho) + far_z * math.cos(rho) + 1.0
    u0, u_top = u_at(height), u_at(top)
    section = [(u0 - base, height), (u0, height), (u_top, top), (u0 - base, top)]
    face = make_face(Polyline(*[(u, z) for u, z in section], close=True))
    # section in the (u, z) plane, extruded along the crease (y)
    solid = extrude(Plane.XZ * face, amount=-length)
    part = solid if isinstance(solid, Part) else Part(solid.wrapped)
    if fab is not None and crease is not None:
        start, direction, _, _, _ = blocker_frame(fab, crease)
        mid = (
            start
            + direction
            * (np.linalg.norm(fab.pattern.vertices[fab.pattern.edges[crease, 1]] - start) - length)
            / 2
        )
        yaw = math.degrees(math.atan2(direction[1], direction[0])) - 90.0
        part = part.moved(Location((float(mid[0]), float(mid[1]), 0.0), (0, 0, 1), yaw))
    part.label = f"blocker {angle:g} deg"
    return part
