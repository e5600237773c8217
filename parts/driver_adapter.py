"""The driver adapter of Fig. 7a: a plate gathering the servo plugs beside the controller board."""

from __future__ import annotations

from build123d import Box, Cylinder, Location, Part

from origami_cad.errors import DesignError

__all__ = ["driver_adapter"]


def driver_adapter(
    connectors: int = 4,
    board_width: float = 25.0,
    board_length: float = 45.0,
    thickness: float = 3.0,
    margin: float = 6.0,
    pitch: float = 8.0,
    slot_width: float = 7.8,
    slot_depth: float = 2.8,
    mounting_hole: float = 3.2,
    pocket: float = 1.2,
) -> Part:
    """A plate with a pocket for the controller board, connector slots and mounting holes.

    Parameters
    ----------
    connectors : int
        Number of servo connectors (3-pin plugs, one row), >= 1.
    board_width, board_length : float
        Outline of the controller board, mm (it sits in a pocket ``pocket`` deep).
    thickness : float
        Plate thickness, mm.
    margin : float
        Border around the board and the connector row; mounting holes sit in it, mm.
    pitch : float
        Spacing of the connector slots, mm.
    slot_width, slot_depth : float
        Through-slot of each plug (JST/Dupont 3-pin housing), mm.
    mounting_hole : float
        Diameter of the four corner holes (M3 clearance by default), mm.
    pocket : float
        Depth of the board pocket, mm.
    """
    if connectors < 1:
        raise DesignError(f"connectors must be >= 1, got {connectors}")
    if pocket >= thickness:
        raise DesignError(
            f"pocket ({pocket:g} mm) must be shallower than the plate ({thickness:g})"
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
    part.label = f"driver adapter ({connectors} connectors)"
    return part
