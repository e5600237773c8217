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
>>> resolve_params(Demo, None, {"width": "-1e-9"})  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
origami_cad.errors.FabricationError: parameter width (mm): expected ... in [0.001, 10000], got -1e-9
"""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from collections.abc import Iterable, Mapping
from typing import Any, TypeVar

from origami_cad._args import brief_value, check_number
from origami_cad.errors import FabricationError

__all__ = [
    "ParamInfo",
    "check_params",
    "param_info",
    "param_range",
    "resolve_params",
    "spec",
]

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


def spec(
    unit: str, doc: str, *, low: float | None = None, least: float | None = None
) -> dict[str, Any]:
    """Metadata of a part parameter: ``field(default=..., metadata=spec(unit, doc))``.

    Parameters
    ----------
    unit : str
        ``"mm"``, ``"deg"``, ``""`` (a count or a name)...
    doc : str
        One line saying what the parameter is.
    low : float, optional
        Values must be greater than this (numbers and each number of a tuple).
    least : float, optional
        Values must be at least this (``0`` for a gap that may close).
    """
    return {"unit": unit, "doc": doc, "low": low, "least": least}


@dataclasses.dataclass(frozen=True)
class ParamInfo:
    """What a part parameter is: its name, type, default, unit and meaning."""

    name: str
    type: Any
    default: Any
    unit: str
    doc: str
    low: float | None
    least: float | None = None

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
            f.metadata.get("least"),
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
    """One value of a parameter through the checks the commands' options use
    (:func:`origami_cad._args.check_number`): finite, of its kind, in its stated range."""
    if tp is str:
        if not isinstance(value, str):
            raise FabricationError(
                f"parameter {info.name}: expected text, got {brief_value(value)}"
            )
        return value
    low, high, open_min = param_range(info, tp)
    unit = f" ({info.unit})" if info.unit else ""
    return check_number(
        f"parameter {info.name}{unit}",
        value,
        kind="int" if tp is int else "float",
        low=low,
        high=high,
        open_min=open_min,
        error=FabricationError,
    )


def param_range(info: ParamInfo, tp: type = float) -> tuple[float | None, float | None, bool]:
    """``(low, high, open_min)``: the range a parameter's numbers are checked in, in its
    unit. A length at most :data:`MAX_LENGTH` mm from zero, an angle :data:`MAX_ANGLE`
    degrees, a count :data:`MAX_COUNT`; at least the field's ``least``, above its ``low`` (at least
    :data:`MIN_SIZE` for a positive length or angle).

    >>> from dataclasses import dataclass, field
    >>> @dataclass(frozen=True)
    ... class Demo:
    ...     width: float = field(default=10.0, metadata=spec("mm", "plate width", low=0.0))
    >>> param_range(param_info(Demo)[0])
    (0.001, 10000.0, False)
    """
    high = _BOUNDS.get(info.unit, float(MAX_COUNT) if tp is int else None)
    if info.least is not None:
        return info.least, high, False
    if info.low is None:
        return (None if high is None else -high), high, False
    if info.low == 0 and info.unit in _BOUNDS:
        return MIN_SIZE, high, False
    if tp is int:  # a count above ``low``: its least whole value, said as such
        return float(math.floor(info.low) + 1), high, False
    return info.low, high, True
