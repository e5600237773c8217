"""The driver adapter of Fig. 7a: a plate gathering the servo plugs beside the controller board."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from build123d import Align, Box, Compound, Cylinder, Location, Mode, Part

from origami_cad.errors import FabricationError

from .base import OrigamiPart
from .parameters import check_params, resolve_params, spec

__all__ = ["DriverAdapter", "DriverAdapterParams", "driver_adapter"]


@dataclass(frozen=True)
class DriverAdapterParams:
    """Parameters of :func:`driver_adapter` (mm unless noted)."""

    connectors: int = field(
        default=4, metadata=spec("", "number of servo connectors (3-pin plugs, one row)", low=0)
    )
    board_width: float = field(
        default=25.0, metadata=spec("mm", "width of the controller board", low=0.0)
    )
    board_length: float = field(
        default=45.0, metadata=spec("mm", "length of the controller board", low=0.0)
    )
    thickness: float = field(default=3.0, metadata=spec("mm", "plate thickness", low=0.0))
    margin: float = field(
        default=6.0, metadata=spec("mm", "border around the board and the connector row", low=0.0)
    )
    pitch: float = field(
        default=8.0, metadata=spec("mm", "spacing of the connector slots", low=0.0)
    )
    slot_width: float = field(
        default=7.8, metadata=spec("mm", "through-slot width of each plug housing", low=0.0)
    )
    slot_depth: float = field(
        default=2.8, metadata=spec("mm", "through-slot depth of each plug housing", low=0.0)
    )
    mounting_hole: float = field(
        default=3.2, metadata=spec("mm", "diameter of the four corner holes", low=0.0)
    )
    pocket: float = field(default=1.2, metadata=spec("mm", "depth of the board pocket", low=0.0))

    def __post_init__(self) -> None:
        check_params(self)


class DriverAdapter(OrigamiPart):
    """A plate with a pocket for the controller board, connector slots and mounting holes.

    A build123d part (child ``plate``); joint ``mount`` (``RigidJoint``): the centre of
    the plate's bottom face, z up, y along the plate's long side.

    Parameters
    ----------
    params : DriverAdapterParams, optional
        The parameters (default ``DriverAdapterParams()``).
    rotation, align, mode
        As for build123d's own parts (degrees; ``Align``; ``Mode``).
    **values
        Parameters to change, by name (Python values or text, see
        :class:`DriverAdapterParams` for units): ``DriverAdapter(connectors=6)``.
    """

    def __init__(
        self,
        params: DriverAdapterParams | None = None,
        *,
        rotation: Any = (0, 0, 0),
        align: Align | tuple[Align, Align, Align] | None = None,
        mode: Mode = Mode.ADD,
        **values: Any,
    ):
        p = resolve_params(DriverAdapterParams, params, values)
        tree, mount = _build(p)
        super().__init__(tree, {"mount": mount}, p, rotation, align, mode)


def driver_adapter(params: DriverAdapterParams | None = None, **values: Any) -> DriverAdapter:
    """The driver adapter: :class:`DriverAdapter` (same parameters)."""
    return DriverAdapter(params, **values)


def _build(p: DriverAdapterParams) -> tuple[Compound, Location]:
    """The adapter's tree and its ``mount`` joint, mm."""
    connectors, thickness, pocket, margin = p.connectors, p.thickness, p.pocket, p.margin
    board_width, board_length, pitch = p.board_width, p.board_length, p.pitch
    slot_width, slot_depth, mounting_hole = p.slot_width, p.slot_depth, p.mounting_hole
    if pocket >= thickness:
        raise FabricationError(
            f"pocket ({pocket:g} mm) must be shallower than the plate ({thickness:g})"
        )
    if not slot_depth < pitch:
        raise FabricationError(
            f"parameter slot_depth: {slot_depth:g} mm leaves no wall between slots "
            f"{pitch:g} mm apart (pitch); it must be < {pitch:g} mm"
        )
    if not mounting_hole < margin:
        raise FabricationError(
            f"parameter mounting_hole: {mounting_hole:g} mm does not fit the {margin:g} mm "
            f"border it sits in (margin); it must be < {margin:g} mm"
        )
    row = connectors * pitch
    width = max(board_width, slot_width) + 2 * margin
    length = board_length + row + 3 * margin
    plate = Box(width, length, thickness, align=None)
    pocket_box = Box(board_width, board_length, pocket + 0.01, align=None).moved(
        Location(((width - board_width) / 2, margin, thickness - pocket))
    )
    part = plate - pocket_box
    y0 = 2 * margin + board_length
    for k in range(connectors):
        slot = Box(slot_width, slot_depth, thickness + 2, align=None).moved(
            Location(((width - slot_width) / 2, y0 + k * pitch + (pitch - slot_depth) / 2, -1))
        )
        part = part - slot
    inset = margin / 2
    for x in (inset, width - inset):
        for y in (inset, length - inset):
            part = part - Cylinder(mounting_hole / 2, thickness + 2, align=None).moved(
                Location((x, y, -1))
            )
    if not isinstance(part, Part):
        part = Part(part.wrapped)
    part.label = "plate"
    tree = Compound(children=[part])
    tree.label = f"driver adapter ({connectors} connectors)"
    return tree, Location((width / 2, length / 2, 0.0))
