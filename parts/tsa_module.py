"""The onboard TSA module: a servo, a twist hub, a string exit guide and a panel mount.

The twist hub's two anchor holes sit at the rotation diameter ``d1`` of the TSA
model (:class:`origami_cad.strings.tsa.TSAParams`): the part reads the same
parameter as the simulation, so the printed hub and eq. 8 agree. Generated for a
named panel of a fabricated pattern, the mount fits inside that panel's outer
face and its holes line up with the holes the fabrication step placed there.

Frame: the module's twist axis runs along ``heading`` (degrees from +x) at the
height of the servo horn, the mount sits on the panel's outer face (z = h).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import shapely
import shapely.affinity
from build123d import (
    Align,
    Box,
    Compound,
    Cylinder,
    Location,
    Mode,
    Part,
    Plane,
    Polyline,
    extrude,
    make_face,
)

from origami_cad._args import Arg
from origami_cad.errors import FabricationError
from origami_cad.fabrication.plan import PanelPlan
from origami_cad.strings.tsa import TSAParams

from .base import OrigamiPart
from .parameters import check_params, resolve_params, spec

__all__ = ["SERVOS", "TSAModule", "TSAModuleParams", "tsa_module"]

#: Servo bodies: (width, length, height) of the case in mm and the horn axis's distance from
#: the front end, from the manufacturer's published drawings.
SERVOS = {
    "XL330": {"body": (20.0, 34.0, 26.0), "horn_offset": 10.0, "horn_diameter": 16.0},
    "XL430": {"body": (28.5, 46.5, 34.0), "horn_offset": 13.5, "horn_diameter": 22.0},
}


def _prism(poly: shapely.Polygon, z0: float, z1: float) -> Part:
    pts = shapely.get_coordinates(poly.exterior)[:-1]
    face = make_face(Polyline(*[(float(x), float(y)) for x, y in pts], close=True))
    solid = extrude(Plane.XY.offset(z0) * face, amount=z1 - z0)
    return solid if isinstance(solid, Part) else Part(solid.wrapped)


#: The least gap between the turning hub and the fixed exit guide, mm: a print's
#: clearance (a finer gap prints fused, and the hub cannot turn).
MIN_GAP = 0.5


@dataclass(frozen=True)
class TSAModuleParams:
    """Parameters of :func:`tsa_module`."""

    servo: str = field(
        default="XL330",
        metadata=spec("", "XL330 or XL430 (published footprints), or any name with body"),
    )
    body: tuple[float, float, float] | None = field(
        default=None, metadata=spec("mm", "width, length, height of another servo's case")
    )
    horn_offset: float | None = field(
        default=None,
        metadata=spec("mm", "horn axis from the case's front end (default: the servo's)"),
    )
    tsa: TSAParams | None = field(
        default=None,
        metadata=spec(
            "", "the TSA model: its d1 places the hub's anchor holes (default TSAParams())"
        ),
    )
    hub_thickness: float = field(default=4.0, metadata=spec("mm", "hub disc thickness", low=0.0))
    anchor_hole: float = field(default=1.2, metadata=spec("mm", "anchor hole diameter", low=0.0))
    guide_distance: float = field(
        default=20.0,
        metadata=spec(
            "mm",
            f"string exit guide's distance from the turning hub (a print's clearance: at "
            f"least {MIN_GAP:g} mm, MIN_GAP)",
            least=MIN_GAP,
        ),
    )
    guide_hole: float = field(
        default=3.0, metadata=spec("mm", "string exit guide's hole diameter", low=0.0)
    )
    mount_thickness: float = field(
        default=3.0, metadata=spec("mm", "thickness of the mount plate", low=0.0)
    )
    mount_margin: float | None = field(
        default=None,
        metadata=spec(
            "mm",
            "on a panel: the mount reaches this far around the servo, hub and guide "
            "(default: on a panel its whole outer face, inset by 1 mm; alone 2 mm)",
            low=0.0,
        ),
    )
    heading: float = field(
        default=0.0, metadata=spec("deg", "direction of the twist axis, from +x")
    )
    centre: tuple[float, float] = field(
        default=(0.0, 0.0), metadata=spec("mm", "where the module stands without a panel")
    )

    def __post_init__(self) -> None:
        check_params(self)


class TSAModule(OrigamiPart):
    """An onboard TSA module (build123d part): children ``servo``, ``hub``, ``guide``, ``mount``.

    Joints (``RigidJoint``):

    * ``mount``: the centre of the mount plate's bottom face, axes of the frame the module
      was built in (on a panel: the pattern's; it meets the panel's ``mount`` joint of
      :meth:`Fabrication.assembly <origami_cad.fabrication.Fabrication.assembly>`);
    * ``hub``: the centre of the twist hub's outer face, z along the twist axis (out of
      the servo), x up.

    Parameters
    ----------
    params : TSAModuleParams, optional
        The parameters (default ``TSAModuleParams()``).
    plan : PanelPlan, optional
        The planned panels of a pattern (``fab.plan`` of a fabrication). With
        ``panel``: the mount is the panel's outer face inset by 1 mm, with holes
        at the panel's holes, placed on the panel (z = h).
    panel : str, optional
        Label of the panel of ``plan`` to mount on.
    rotation, align, mode
        As for build123d's own parts (degrees; ``Align``; ``Mode``).
    **values
        Parameters to change, by name (Python values or text, see
        :class:`TSAModuleParams` for units): ``TSAModule(servo="XL430")``.
    """

    def __init__(
        self,
        params: TSAModuleParams | None = None,
        *,
        plan: PanelPlan | None = None,
        panel: str | None = None,
        rotation: Any = (0, 0, 0),
        align: Align | tuple[Align, Align, Align] | None = None,
        mode: Mode = Mode.ADD,
        **values: Any,
    ):
        Arg("object", types=(PanelPlan,)).check("TSAModule: plan", plan, FabricationError)
        Arg("str").check("TSAModule: panel", panel, FabricationError)
        p = resolve_params(TSAModuleParams, params, values)
        tree, joints = _build(p, plan, panel)
        super().__init__(tree, joints, p, rotation, align, mode)


def tsa_module(
    params: TSAModuleParams | None = None,
    *,
    plan: PanelPlan | None = None,
    panel: str | None = None,
    **values: Any,
) -> TSAModule:
    """An onboard TSA module: :class:`TSAModule` (same parameters)."""
    return TSAModule(params, plan=plan, panel=panel, **values)


def _build(
    p: TSAModuleParams, plan: PanelPlan | None, panel: str | None
) -> tuple[Compound, dict[str, Location]]:
    """The module's tree (servo, hub, guide, mount) and its joints, mm."""
    servo, body, horn_offset = p.servo, p.body, p.horn_offset
    spec = SERVOS.get(servo, {})
    if body is None:
        if not spec:
            raise FabricationError(
                f"unknown servo {servo!r}: give its body=(w, l, h) in mm "
                f"(known: {', '.join(SERVOS)})"
            )
        body = spec["body"]
    if horn_offset is None:
        horn_offset = spec.get("horn_offset", body[0] / 2)
    horn_d = spec.get("horn_diameter", 0.8 * body[0])
    tsa = p.tsa or TSAParams()
    w, length, h = (float(v) for v in body)
    if min(w, length, h) <= 0:
        raise FabricationError(f"servo body dimensions must be > 0 mm, got {body}")
    if not 0 <= horn_offset <= length:
        raise FabricationError(
            f"parameter horn_offset: {horn_offset:g} mm is not on the servo's case, "
            f"{length:g} mm long; it must lie in [0, {length:g}] mm"
        )
    hub_r = max(tsa.d1 / 2 + max(3.0, p.anchor_hole * 2), horn_d / 2)
    wall = min(hub_r, w / 2, 6.0)  # around the guide's hole: its half width, foot, top
    if not p.guide_hole / 2 < wall:
        raise FabricationError(
            f"parameter guide_hole: {p.guide_hole:g} mm is wider than the exit guide "
            f"around it; it must be < {2 * wall:g} mm"
        )
    if panel is not None and plan is None:
        raise FabricationError("panel needs plan (the PanelPlan the panel belongs to)")
    if plan is not None and panel is not None:
        _check_fits(plan, panel, h, length)
    reach = _reach(p, tsa, horn_d, horn_offset, length, h)
    mount, cx, cy, z_base = _mount(p, plan, panel, reach)
    # the servo lies on its side: its height runs along the twist axis (local x, horn face
    # at x = 0), its length across (local y, horn axis horn_offset from the front end)
    z0 = z_base + p.mount_thickness
    servo_box = Box(h, length, w, align=None).moved(Location((-h, -horn_offset, z0)))
    servo_part = servo_box if isinstance(servo_box, Part) else Part(servo_box.wrapped)
    axis_z = z0 + w / 2
    hub, guide = _hub_and_guide(p, tsa, horn_d, z0, axis_z)
    shift = Location((cx, cy, 0), (0, 0, 1), p.heading)
    children = []
    for name, part in (("servo", servo_part), ("hub", hub), ("guide", guide)):
        moved = part.moved(shift)
        moved = moved if isinstance(moved, Part) else Part(moved.wrapped)
        moved.label = name
        children.append(moved)
    children.append(mount)
    assembly = Compound(children=children)
    assembly.label = f"TSA module ({servo})"
    hub_face = Plane(origin=(1.0 + p.hub_thickness, 0.0, axis_z), x_dir=(0, 0, 1), z_dir=(1, 0, 0))
    joints = {
        "mount": Location((cx, cy, z_base)),
        "hub": shift * Location(hub_face),
    }
    return assembly, joints


#: How many times its panel's largest extent a servo case's narrower side may be.
MAX_OVERHANG = 2.0
#: How many times its panel's largest extent a servo case's longer side may be.
MAX_SPAN = 3.0


def _check_fits(plan: PanelPlan, panel: str, h: float, length: float) -> None:
    """Refuse a servo whose case, lying on its side, is wider than the panel every way (mm).

    A case may overhang its panel (the paper's arm carries an XL330, 26 x 34 mm, on a
    base panel 15.9 mm across), but its narrower side may not exceed
    :data:`MAX_OVERHANG` times the panel's largest extent (its bounding box's diagonal),
    nor its longer side :data:`MAX_SPAN` times.
    """
    x0, y0, x1, y1 = shapely.Polygon(plan.outline(panel).outer).bounds
    extent = math.hypot(x1 - x0, y1 - y0)
    if min(h, length) > MAX_OVERHANG * extent or max(h, length) > MAX_SPAN * extent:
        raise FabricationError(
            f"the servo's case ({h:g} x {length:g} mm lying on its side) is larger than panel "
            f"{panel!r} ({extent:.1f} mm across; a case's sides may be at most "
            f"{MAX_OVERHANG * extent:.1f} and {MAX_SPAN * extent:.1f} mm): mount it on a "
            "larger panel or use a smaller servo"
        )


def _reach(
    p: TSAModuleParams, tsa: TSAParams, horn_d: float, horn_offset: float, length: float, h: float
) -> tuple[float, float, float, float]:
    """The servo, hub and guide's footprint in the module's frame: (x0, y0, x1, y1), mm."""
    hub_r = max(tsa.d1 / 2 + max(3.0, p.anchor_hole * 2), horn_d / 2)
    gx = 1.0 + p.hub_thickness + p.guide_distance
    return (-h, min(-horn_offset, -hub_r), gx + 3.0, max(length - horn_offset, hub_r))


def _mount(
    p: TSAModuleParams,
    plan: PanelPlan | None,
    panel: str | None,
    reach: tuple[float, float, float, float],
) -> tuple[Part, float, float, float]:
    """The mount plate and where the module stands: ``(mount, cx, cy, z_base)``, mm.

    On a planned panel: the panel's outer face inset by 1 mm with the panel's holes, at
    z = h (with ``mount_margin``: only the part of it within that margin of the module's
    ``reach``, its footprint); otherwise the footprint of the servo, hub and guide grown by
    ``mount_margin`` (default 2 mm), turned to the heading, around ``p.centre``: the servo
    and the guide stand on it.
    """
    z_base = 0.0
    holes: list[tuple[float, float, float]] = []
    if plan is not None:
        if panel is None:
            raise FabricationError("give the panel label to mount the TSA module on")
        outline = plan.outline(panel)
        foot = shapely.Polygon(outline.outer).buffer(-1.0, join_style="mitre")
        holes = [(h.x, h.y, h.diameter) for h in plan.holes_of(outline.index)]
        z_base = plan.params.height
        cx, cy = foot.centroid.x, foot.centroid.y
        if p.mount_margin is not None:
            foot = foot.intersection(_footprint(p, reach, p.mount_margin, cx, cy))
            if not isinstance(foot, shapely.Polygon) or foot.is_empty:
                raise FabricationError(f"the TSA module's mount does not fit panel {panel!r}")
    else:
        cx, cy = p.centre
        margin = 2.0 if p.mount_margin is None else p.mount_margin
        foot = _footprint(p, reach, margin, cx, cy)
    mount = _prism(foot, z_base, z_base + p.mount_thickness)
    for x, y, d in holes:
        mount = mount - Cylinder(d / 2, p.mount_thickness + 2, align=None).moved(
            Location((x, y, z_base - 1))
        )
    mount = mount if isinstance(mount, Part) else Part(mount.wrapped)
    mount.label = "mount"
    return mount, cx, cy, z_base


def _footprint(
    p: TSAModuleParams,
    reach: tuple[float, float, float, float],
    margin: float,
    cx: float,
    cy: float,
) -> shapely.Polygon:
    """The module's reach grown by ``margin`` (mm), turned to the heading, at ``(cx, cy)``."""
    x0, y0, x1, y1 = reach
    box = shapely.box(x0 - margin, y0 - margin, x1 + margin, y1 + margin)
    return shapely.affinity.translate(shapely.affinity.rotate(box, p.heading, (0, 0)), cx, cy)


def _hub_and_guide(
    p: TSAModuleParams, tsa: TSAParams, horn_d: float, z0: float, axis_z: float
) -> tuple[Part, Part]:
    """The twist hub (anchor holes at the TSA's ``d1``) and the string exit guide, local frame."""
    front = 0.0
    hub_r = max(tsa.d1 / 2 + max(3.0, p.anchor_hole * 2), horn_d / 2)
    hub = Cylinder(hub_r, p.hub_thickness, align=None).moved(
        Location((front + 1.0, 0, axis_z), (0, 1, 0), 90)
    )
    for sign in (1, -1):  # the two anchor holes at the rotation diameter d1
        hub = hub - Cylinder(p.anchor_hole / 2, p.hub_thickness + 2, align=None).moved(
            Location((front, sign * tsa.d1 / 2, axis_z), (0, 1, 0), 90)
        )
    hub = hub if isinstance(hub, Part) else Part(hub.wrapped)
    gx = front + 1.0 + p.hub_thickness + p.guide_distance
    guide_h = axis_z - z0 + 6.0
    guide = Box(3.0, 2 * hub_r, guide_h, align=None).moved(Location((gx, -hub_r, z0)))
    guide = guide - Cylinder(p.guide_hole / 2, 6.0, align=None).moved(
        Location((gx - 1.0, 0, axis_z), (0, 1, 0), 90)
    )
    guide = guide if isinstance(guide, Part) else Part(guide.wrapped)
    return hub, guide
