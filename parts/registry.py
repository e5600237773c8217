"""The registry of parts: name, builder, typed parameters, and what each part is placed on.

:func:`build_part` builds a part from its name and parameters given as text
(the command line) or Python values; :func:`parts_listing` is the text of
``origami-cad part --list``, generated from the parameter dataclasses.

>>> part = build_part("driver-adapter", {"connectors": "3"})
>>> part.label
'driver adapter (3 connectors)'
>>> parse_part_options(["--horn-offset", "12", "--servo", "XL430"])
{'horn_offset': '12', 'servo': 'XL430'}
"""

from __future__ import annotations

import enum
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from origami_cad._args import brief_value
from origami_cad.errors import FabricationError
from origami_cad.fabrication.plan import PanelPlan, plan_panels
from origami_cad.pattern.design import Design, load_pattern_source
from origami_cad.pattern.model import CreasePattern

from .blocker import BlockerParams, blocker
from .driver_adapter import DriverAdapterParams, driver_adapter
from .parameters import param_info, resolve_params
from .ring_rail import RingRailParams, ring_rail
from .tsa_module import TSAModuleParams, tsa_module

__all__ = [
    "PARTS",
    "PartSpec",
    "Placement",
    "build_part",
    "parse_part_options",
    "parts_listing",
]


class Placement(enum.Enum):
    """What a part can be placed on, given a pattern."""

    #: Free-standing: built in its own frame, never on a pattern.
    NONE = "nothing"
    #: A panel of the planned pattern (by label): the TSA module's mount.
    PANEL = "a fabricated panel"
    #: A crease of the planned pattern (by edge index): the blocker.
    CREASE = "a crease"


@dataclass(frozen=True)
class PartSpec:
    """One part of the library.

    Attributes
    ----------
    name : str
        The name on the command line (``tsa-module``).
    builder : callable
        ``builder(params, ...)`` returning a build123d shape.
    params : type
        The parameter dataclass (fields with types, units and docs).
    placement : Placement
        What the part can be placed on, given a pattern.
    summary : str
        One line saying what the part is.
    """

    name: str
    builder: Callable[..., Any]
    params: type
    placement: Placement
    summary: str


#: The parts, by name.
PARTS: dict[str, PartSpec] = {
    spec.name: spec
    for spec in (
        PartSpec(
            "tsa-module",
            tsa_module,
            TSAModuleParams,
            Placement.PANEL,
            "onboard TSA module: servo, twist hub, string exit guide, mount",
        ),
        PartSpec(
            "ring-rail",
            ring_rail,
            RingRailParams,
            Placement.NONE,
            "ring slide rail with TSA carriages (Fig. 5d)",
        ),
        PartSpec(
            "blocker",
            blocker,
            BlockerParams,
            Placement.CREASE,
            "clip that stops a valley crease at an angle (Fig. 7a)",
        ),
        PartSpec(
            "driver-adapter",
            driver_adapter,
            DriverAdapterParams,
            Placement.NONE,
            "plate gathering the servo plugs beside the controller board (Fig. 7a)",
        ),
    )
}


def _spec(name: str) -> PartSpec:
    if not isinstance(name, str) or name not in PARTS:
        raise FabricationError(f"unknown part {brief_value(name)} (known: {', '.join(PARTS)})")
    return PARTS[name]


def parse_part_options(tokens: Sequence[str]) -> dict[str, str]:
    """``["--horn-offset", "12", ...]`` to ``{"horn_offset": "12", ...}`` (values unconverted)."""
    out = {}
    if isinstance(tokens, str | bytes) or not hasattr(tokens, "__iter__"):
        raise FabricationError(f"expected a list of --name value tokens, got {brief_value(tokens)}")
    items = list(tokens)
    if not all(isinstance(t, str) for t in items):
        raise FabricationError(f"expected --name value pairs as text, got {brief_value(items)}")
    while items:
        key = items.pop(0)
        if not key.startswith("--") or not items:
            raise FabricationError(f"expected --name value pairs after the part name, got {key!r}")
        name = key[2:].replace("-", "_")
        if name in out:
            raise FabricationError(f"{key} is given twice; give each part parameter once")
        out[name] = items.pop(0)
    return out


def build_part(
    name: str,
    values: Mapping[str, Any] | None = None,
    *,
    pattern: PanelPlan | Design | CreasePattern | str | os.PathLike[str] | None = None,
    panel: str | None = None,
    crease: int | None = None,
    **options: Any,
) -> Any:
    """Build a part of the library from its name and parameters.

    Parameters
    ----------
    name : str
        A key of :data:`PARTS`.
    values : mapping, optional
        Parameters by name (``horn_offset`` or ``horn-offset``), as text or values;
        each is converted to its declared type and checked (see ``part --list``).
    pattern : PanelPlan, Design, CreasePattern or path, optional
        The pattern the part is made for: planned with the default fabrication
        parameters unless it is a plan already (no solid is built).
    panel : str, optional
        Panel label, for a part placed on a panel (``tsa-module``).
    crease : int, optional
        Crease edge index, for a part placed on a crease (``blocker``).
    **options
        Passed to the part's class as they are (``mountain=True`` for a blocker).

    Raises
    ------
    FabricationError
        Naming the part or parameter that is unknown or wrong, or the missing placement.
    """
    spec = _spec(name)
    if values is not None and not isinstance(values, Mapping):
        raise FabricationError(
            f"part {name}: values must be a dict of parameters, got {brief_value(values)}"
        )
    if pattern is not None and not isinstance(
        pattern, PanelPlan | Design | CreasePattern | str | os.PathLike
    ):
        raise FabricationError(f"part {name}: pattern must be a plan, design, pattern or file")
    try:
        params = resolve_params(
            spec.params, None, {k.replace("-", "_"): v for k, v in (values or {}).items()}
        )
    except FabricationError as exc:
        raise FabricationError(f"part {name}: {exc} (see origami-cad part --list)") from None
    if pattern is None:
        if panel is not None or crease is not None:
            raise FabricationError(f"part {name}: --panel and --crease need --pattern")
        return spec.builder(params=params, **options)
    plan = pattern if isinstance(pattern, PanelPlan) else plan_panels(_source(pattern))
    if spec.placement is Placement.PANEL:
        if not panel:
            raise FabricationError(f"part {name}: give the panel label (--panel) with --pattern")
        return spec.builder(params=params, plan=plan, panel=panel, **options)
    if spec.placement is Placement.CREASE:
        if crease is None:
            raise FabricationError(f"part {name}: give the crease edge (--crease) with --pattern")
        return spec.builder(plan=plan, crease=crease, params=params, **options)
    raise FabricationError(f"part {name} is not placed on a pattern: leave out --pattern")


def _source(pattern: Design | CreasePattern | str | os.PathLike[str]) -> Design | CreasePattern:
    if isinstance(pattern, Design | CreasePattern):
        return pattern
    return load_pattern_source(pattern)


def parts_listing() -> str:
    """The text of ``origami-cad part --list``: every part and its parameters, with units."""
    lines = []
    for spec in PARTS.values():
        place = "" if spec.placement is Placement.NONE else f" (placed on {spec.placement.value})"
        lines.append(f"{spec.name}: {spec.summary}{place}")
        for info in param_info(spec.params):
            if not info.text:
                continue
            unit = f" ({info.unit})" if info.unit else ""
            default = "none" if info.default is None else _text(info.default)
            lines.append(
                f"    --{info.name.replace('_', '-')} {info.type_name}{unit}: {info.doc}; "
                f"default {default}"
            )
    return "\n".join(lines)


def _text(value: Any) -> str:
    if isinstance(value, tuple):
        return ",".join(f"{v:g}" for v in value)
    return f"{value:g}" if isinstance(value, float) else str(value)
