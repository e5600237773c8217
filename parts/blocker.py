"""Blockers (the paper's Fig. 7a): clips that stop a crease's fold at a set angle.

The blocker sits on the outer face of one panel (``A``) across the crease. Its stop
face is the plane that the other panel's (``B``) outer face reaches when the crease
has folded by ``angle``: rotating ``B`` about the crease axis (on the crease layer
surface, where eq. 6's chamfers hinge) leaves a gap below the angle and brings ``B``'s
outer face flat against the stop face at it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from build123d import Align, Compound, Location, Mode, Part, Plane, Polyline, extrude, make_face

from origami_cad._args import Arg
from origami_cad.errors import FabricationError
from origami_cad.fabrication.params import FabricationParams, theta_max
from origami_cad.fabrication.plan import PanelPlan
from origami_cad.pattern.model import CreasePattern

from .base import OrigamiPart
from .parameters import check_params, resolve_params, spec

__all__ = ["Blocker", "BlockerParams", "blocker", "blocker_frame"]


@dataclass(frozen=True)
class BlockerParams:
    """Parameters of :func:`blocker`; ``bias``, ``height``, ``thickness`` apply without a plan."""

    angle: float = field(
        default=60.0, metadata=spec("deg", "fold angle at which the crease stops", low=0.0)
    )
    length: float = field(default=10.0, metadata=spec("mm", "length along the crease", low=0.0))
    reach: float = field(
        default=5.0,
        metadata=spec("mm", "how far past panel B's chamfer the stop face reaches", low=0.0),
    )
    base: float = field(
        default=6.0, metadata=spec("mm", "length of the foot bonded to panel A", low=0.0)
    )
    clearance: float = field(
        default=0.0, metadata=spec("mm", "gap left at the stop angle (0: contact)", least=0.0)
    )
    bias: float = field(
        default=FabricationParams.bias, metadata=spec("mm", "b of the panels", low=0.0)
    )
    height: float = field(
        default=FabricationParams.height, metadata=spec("mm", "h of the panels", low=0.0)
    )
    thickness: float = field(
        default=FabricationParams.thickness, metadata=spec("mm", "t of the panels", low=0.0)
    )

    def __post_init__(self) -> None:
        check_params(self)


def blocker_frame(
    pattern: CreasePattern, crease: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int, int]:
    """Frame of a crease of a pattern.

    Returns ``(start, direction, across, face_a, face_b)``: the crease's start
    point and unit direction (mm, in the pattern), the unit vector pointing into
    panel ``B`` (the face on the crease's right), and the two face indices.
    """
    cp = Arg("object", types=(CreasePattern,), optional=False).check(
        "blocker_frame: pattern", pattern, FabricationError
    )
    if isinstance(crease, bool) or not isinstance(crease, int | np.integer):
        raise FabricationError(f"crease must be an edge index (an integer), got {crease!r}")
    if not 0 <= crease < cp.n_edges or cp.assignments[crease] not in ("M", "V"):
        raise FabricationError(f"edge {crease} is not a mountain or valley crease of the pattern")
    ef = cp.edge_faces()[crease]
    if (ef < 0).any():
        raise FabricationError(f"crease {crease} does not join two panels")
    a, b = cp.vertices[cp.edges[crease]]
    direction = (b - a) / np.linalg.norm(b - a)
    across = np.array([direction[1], -direction[0]])  # right of the edge: face column 1
    return a, direction, across, int(ef[0]), int(ef[1])


class Blocker(OrigamiPart):
    """A blocker stopping a valley crease at ``angle`` degrees (build123d part).

    Joint ``crease`` (``RigidJoint``): on the crease axis, at its middle, on the crease
    layer's upper surface (the hinge, z = (h + t) / 2; mirrored: z = (h - t) / 2), x across
    the crease, y along it. It meets the ``blocker E`` joint of crease ``E`` of
    :meth:`Fabrication.assembly <origami_cad.fabrication.Fabrication.assembly>`.

    Parameters
    ----------
    plan : PanelPlan, optional
        The planned panels of a pattern (``fab.plan`` of a fabrication); with
        ``crease`` the blocker is placed on that crease (its panel ``A`` is the
        face on the crease's left) in the pattern frame, and the plan's ``bias``,
        ``height`` and ``thickness`` replace those of ``params``.
    crease : int, optional
        Edge index of a valley crease of ``plan.pattern``.
    params : BlockerParams, optional
        The parameters (default ``BlockerParams()``); without a plan the blocker
        is built for a crease along +y through the origin, panel ``B`` on the +x side.
    mountain : bool
        Mirror it about the sheet's mid-plane z = h/2, onto the bottom face: the
        blocker of a mountain crease (a mountain fold is a valley seen from below).
    rotation, align, mode
        As for build123d's own parts (degrees; ``Align``; ``Mode``).
    **values
        Parameters to change, by name: ``Blocker(plan, 3, angle=45)``.
    """

    def __init__(
        self,
        plan: PanelPlan | None = None,
        crease: int | None = None,
        params: BlockerParams | None = None,
        *,
        mountain: bool = False,
        rotation: Any = (0, 0, 0),
        align: Align | tuple[Align, Align, Align] | None = None,
        mode: Mode = Mode.ADD,
        **values: Any,
    ):
        Arg("object", types=(PanelPlan,)).check("Blocker: plan", plan, FabricationError)
        mountain = Arg("bool", optional=False).check(
            "Blocker: mountain", mountain, FabricationError
        )
        p = resolve_params(BlockerParams, params, values)
        if plan is not None:
            fp = plan.params
            p = resolve_params(
                BlockerParams, p, {"bias": fp.bias, "height": fp.height, "thickness": fp.thickness}
            )
        part, seat = _build(p, plan, crease, mountain)
        tree = Compound(children=[part])
        tree.label = part.label
        super().__init__(tree, {"crease": seat}, p, rotation, align, mode)


def blocker(
    plan: PanelPlan | None = None,
    crease: int | None = None,
    params: BlockerParams | None = None,
    *,
    mountain: bool = False,
    **values: Any,
) -> Blocker:
    """A blocker stopping a valley crease at ``angle`` degrees: :class:`Blocker`."""
    return Blocker(plan, crease, params, mountain=mountain, **values)


def _build(
    p: BlockerParams, plan: PanelPlan | None, crease: int | None, mountain: bool
) -> tuple[Part, Location]:
    """The blocker's solid and its ``crease`` joint, mm."""
    angle, length, reach, base, clearance = p.angle, p.length, p.reach, p.base, p.clearance
    bias, height, thickness = p.bias, p.height, p.thickness
    if plan is None and crease is not None:
        raise FabricationError("crease needs plan (the PanelPlan of the pattern it is on)")
    if plan is not None and crease is None:
        raise FabricationError("plan needs crease (the edge index of the crease to stop)")
    if not thickness < height:
        raise FabricationError(
            f"parameter thickness: {thickness:g} mm is not thinner than the panels "
            f"{height:g} mm high (height); it must be < {height:g} mm"
        )
    limit = math.degrees(theta_max(bias, height, thickness))
    if not 0 < angle < min(limit, 180.0):
        raise FabricationError(f"angle must lie in (0, {limit:.1f}) deg (theta_max), got {angle}")
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
    seat = Location((0.0, length / 2, z_c))
    if mountain:
        part = Part(part.mirror(Plane.XY.offset(height / 2.0)).wrapped)
        seat = Location((0.0, length / 2, height - z_c))
    if plan is not None and crease is not None:
        start, direction, _, _, _ = blocker_frame(plan.pattern, crease)
        end = plan.pattern.vertices[plan.pattern.edges[crease, 1]]
        mid = start + direction * (np.linalg.norm(end - start) - length) / 2
        yaw = math.degrees(math.atan2(direction[1], direction[0])) - 90.0
        place = Location((float(mid[0]), float(mid[1]), 0.0), (0, 0, 1), yaw)
        part, seat = part.moved(place), place * seat
    part.label = f"blocker {angle:g} deg"
    return part, seat
