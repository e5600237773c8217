"""Typed part parameters: dataclass fields with units, and their coercion from text or values.

Every part's parameters are a frozen dataclass whose fields carry :func:`spec`
metadata (unit, one-line doc, optional lower bound).
:func:`resolve_params` builds one from keyword values given as Python values or
as command-line text, converting each to its field's declared type:

>>> from dataclasses import dataclass, field
>>> @dataclass(frozen=True)
... class Demo:
...     width: float = field(default=10.0, metadata=spec("mm", "plate width", low=0.0))
...     offset: float | None = field(default=None, metadata=spec("mm", "default: width / 2"))
...     angles: tuple[float, ...] = field(default=(0.0, 90.0), metadata=spec("deg", "holes"))
>>> resolve_params(Demo, None, {"offset": "12", "angles": "0, 45, 90"})
Demo(width=10.0, offset=12.0, angles=(0.0, 45.0, 90.0))
>>> resolve_params(Demo, None, {"width": "-1"})
Traceback (most recent call last):
...
origami_cad.errors.FabricationError: parameter width: must be > 0 mm, got -1.0
"""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from collections.abc import Iterable, Mapping
from typing import Any, TypeVar

from origami_cad._args import brief_value
from origami_cad.errors import FabricationError

__all__ = ["ParamInfo", "check_params", "param_info", "resolve_params", "spec"]

P = TypeVar("P")

#: The stated bounds of every part parameter, checked before any solid is built (a part
#: of 1e300 mm, or of a million connectors, fails deep in the B-rep kernel or never ends):
#: a length at most :data:`MAX_LENGTH` mm from zero, an angle at most :data:`MAX_ANGLE`
#: degrees, a count at most :data:`MAX_COUNT`, a list of at most :data:`MAX_ITEMS` numbers.
MAX_LENGTH = 10_000.0
MAX_ANGLE = 360.0
MAX_COUNT = 64
MAX_ITEMS = 64
#: The least size of a part's length or angle that must be positive (mm or degrees): a
#: finer one (1e-300 mm) is no solid the B-rep kernel can build.
MIN_SIZE = 1e-3
_BOUNDS = {"mm": MAX_LENGTH, "deg": MAX_ANGLE}


def spec(unit: str, doc: str, *, low: float | None = None) -> dict[str, Any]:
    """Metadata of a part parameter: ``field(default=..., metadata=spec(unit, doc))``.

    Parameters
    ----------
    unit : str
        ``"mm"``, ``"deg"``, ``""`` (a count or a name)...
    doc : str
        One line saying what the parameter is.
    low : float, optional
        Values must be greater than this (numbers and each number of a tuple).
    """
    return {"unit": unit, "doc": doc, "low": low}


@dataclasses.dataclass(frozen=True)
class ParamInfo:
    """What a part parameter is: its name, type, default, unit and meaning."""

    name: str
    type: Any
    default: Any
    unit: str
    doc: str
    low: float | None

    @property
    def type_name(self) -> str:
        """The type as written in the listing: ``FLOAT``, ``FLOAT or none``, ``FLOAT,...``."""
        base, optional = _unwrap_optional(self.type)
        if typing.get_origin(base) is tuple:
            args = typing.get_args(base)
            one = args[0].__name__.upper()
            name = f"{one},..." if args[-1] is Ellipsis else ",".join([one] * len(args))
        else:
            name = getattr(base, "__name__", str(base)).upper()
        return f"{name} or none" if optional else name

    @property
    def text(self) -> bool:
        """Whether it can be given as text (on the command line)."""
        base, _ = _unwrap_optional(self.type)
        return base in (float, int, str) or typing.get_origin(base) is tuple


def param_info(cls: type) -> list[ParamInfo]:
    """The parameters of a parameter dataclass, in declaration order."""
    hints = typing.get_type_hints(cls)
    return [
        ParamInfo(
            f.name,
            hints[f.name],
            f.default,
            f.metadata.get("unit", ""),
            f.metadata.get("doc", ""),
            f.metadata.get("low"),
        )
        for f in dataclasses.fields(cls)
    ]


def resolve_params(cls: type[P], params: P | None, values: Mapping[str, Any]) -> P:
    """``params`` (default ``cls()``) with ``values`` replaced, each converted to its type.

    Values may be Python values or text (``"12"``, ``"0,45,90"``, ``"none"``).
    Raises :class:`FabricationError` naming the parameter when a name is unknown or a
    value has the wrong type or is out of range.
    """
    base = params if params is not None else cls()
    if not isinstance(base, cls):
        raise FabricationError(f"expected {cls.__name__} parameters, got {type(base).__name__}")
    infos = {i.name: i for i in param_info(cls)}
    changes = {}
    for name, value in values.items():
        if name not in infos:
            raise FabricationError(f"unknown parameter {name!r} (known: {', '.join(infos)})")
        changes[name] = _coerce(infos[name], value)
    return dataclasses.replace(base, **changes)


def check_params(params: Any) -> None:
    """Check and convert every field of a part's parameter dataclass (its
    ``__post_init__``), as :func:`resolve_params` does the values it is given: a
    :class:`FabricationError` names the parameter and the bad value."""
    for info in param_info(type(params)):
        value = _coerce(info, getattr(params, info.name))
        object.__setattr__(params, info.name, value)


def _unwrap_optional(tp: Any) -> tuple[Any, bool]:
    if typing.get_origin(tp) in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(tp) if a is not type(None)]
        if len(args) == 1:
            return args[0], True
    return tp, False


def _coerce(info: ParamInfo, value: Any) -> Any:
    base, optional = _unwrap_optional(info.type)
    if value is None or (optional and isinstance(value, str) and value.lower() == "none"):
        if optional:
            return None
        raise FabricationError(f"parameter {info.name}: a value is required")
    if typing.get_origin(base) is tuple:
        return _coerce_tuple(info, base, value)
    if base in (float, int, str):
        return _scalar(info, base, value)
    if isinstance(value, base):
        return value
    raise FabricationError(
        f"parameter {info.name}: expected a {getattr(base, '__name__', base)}, "
        f"got {brief_value(value)}"
    )


def _coerce_tuple(info: ParamInfo, tp: Any, value: Any) -> tuple:
    args = typing.get_args(tp)
    count = "numbers" if args[-1] is Ellipsis else f"{len(args)} comma-separated numbers"
    expected = f"parameter {info.name}: expected {count}, got {brief_value(value)}"
    if isinstance(value, str):
        items = value.split(",")
    elif isinstance(value, bytes | Mapping) or not isinstance(value, Iterable):
        raise FabricationError(expected)
    else:
        items = list(value)
    if args[-1] is not Ellipsis and len(items) != len(args):
        raise FabricationError(expected)
    if not items:
        raise FabricationError(f"parameter {info.name}: expected at least one value")
    if len(items) > MAX_ITEMS:
        raise FabricationError(
            f"parameter {info.name}: {len(items)} values, at most {MAX_ITEMS} "
            "(parts.parameters.MAX_ITEMS)"
        )
    return tuple(_scalar(info, args[0], v) for v in items)


def _scalar(info: ParamInfo, tp: type, value: Any) -> Any:
    if tp is str:
        if not isinstance(value, str):
            raise FabricationError(
                f"parameter {info.name}: expected text, got {brief_value(value)}"
            )
        return value
    expected = f"parameter {info.name}: expected {'an int' if tp is int else 'a float'}"
    shown = brief_value(value)
    text = isinstance(value, str)
    if (
        isinstance(value, bool)
        or not isinstance(value, str | int | float)
        or (
            text and not value.isascii()  # "\u0663" is 3 to float(): no one types it for one
        )
    ):
        raise FabricationError(f"{expected}, got {shown}")
    try:
        number = tp(value.strip()) if isinstance(value, str) else tp(value)
    except (ValueError, OverflowError):
        raise FabricationError(f"{expected}, got {shown}") from None
    if not math.isfinite(number):
        raise FabricationError(f"parameter {info.name}: expected a finite number, got {shown}")
    if number != value and not isinstance(value, str):
        raise FabricationError(f"{expected}, got {shown}")
    unit = f" {info.unit}" if info.unit else ""
    if info.low is not None and not number > info.low:
        raise FabricationError(
            f"parameter {info.name}: must be > {info.low:g}{unit}, got {number!r}"
        )
    if info.low == 0 and info.unit in _BOUNDS and number < MIN_SIZE:
        raise FabricationError(
            f"parameter {info.name}: at least {MIN_SIZE:g}{unit} "
            f"(parts.parameters.MIN_SIZE), got {number!r}"
        )
    _check_bound(info, tp, number)
    return number


def _check_bound(info: ParamInfo, tp: type, number: float) -> None:
    """The stated bound of the parameter's unit (a count's when it is an integer)."""
    bound = _BOUNDS.get(info.unit, MAX_COUNT if tp is int else None)
    if bound is not None and abs(number) > bound:
        unit = f" {info.unit}" if info.unit else ""
        name = {MAX_LENGTH: "MAX_LENGTH", MAX_ANGLE: "MAX_ANGLE"}.get(bound, "MAX_COUNT")
        raise FabricationError(
            f"parameter {info.name}: at most {bound:g}{unit}{' from zero' if unit else ''} "
            f"(parts.parameters.{name}), got {number!r}"
        )
