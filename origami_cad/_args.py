"""Argument checks, declared once for the command line and the library alike.

A command's :class:`~origami_cad.commands._options.Option` and a library function's
:class:`Arg` check numbers through the same :func:`check_number` (finite, in range, of
the declared kind), and name the option or the argument with the bad value; the command
line raises :class:`~origami_cad.errors.OptionsError` (exit 2), a library function the
error type of its stage:

>>> from origami_cad.errors import StringsError
>>> @checked(StringsError, max_dp=Arg(min=0, open_min=True, max=1))
... def step(max_dp=0.01):
...     return max_dp
>>> step(0.5)
0.5
>>> step(float("nan"))
Traceback (most recent call last):
...
origami_cad.errors.StringsError: step: max_dp: expected a finite number in (0, 1], got nan
"""

from __future__ import annotations

import functools
import inspect
import math
import operator
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np

from origami_cad.errors import OptionsError, OrigamiCadError

__all__ = [
    "Arg",
    "brief_value",
    "check_fields",
    "check_number",
    "check_numbers",
    "checked",
    "describe_range",
]

F = TypeVar("F", bound=Callable[..., Any])


def describe_range(kind: str, low: float | None, high: float | None, open_min: bool = False) -> str:
    """``a finite number in [0, 1]``, ``an integer in 1..4096``... (what a check expects)."""
    if kind == "int":
        lo = "" if low is None else str(int(low))
        hi = "" if high is None else str(int(high))
        return "an integer" + (f" in {lo}..{hi}" if lo or hi else "")
    text = "a finite number"
    if low is None and high is None:
        return text
    left = "(" if open_min else "["
    lo = "-inf" if low is None else f"{low:g}"
    hi = "inf" if high is None else f"{high:g}"
    return f"{text} in {left}{lo}, {hi}{')' if high is None else ']'}"


def _brief(value: Any) -> str:
    """``value`` in a message: its type, and its text when short."""
    text = brief_value(value)
    kind = type(value).__name__
    return f"{kind} {text}" if len(text) <= 40 else kind


def brief_value(value: Any, limit: int = 60) -> str:
    """``repr(value)`` on one line (an array's rows joined, control characters escaped),
    cut to about ``limit`` characters: a bad value as an error message shows it.

    >>> import numpy as np
    >>> brief_value(np.zeros((2, 2)))
    'array([[0., 0.], [0., 0.]])'
    """
    text = " ".join(repr(value).split())
    return text if len(text) <= limit else text[:limit] + "..."


def _shown(value: Any) -> str:
    if isinstance(value, str) and value.isprintable() and len(value) <= 60:
        return value
    return brief_value(value)


def _takes(func: Callable, count: int) -> bool:
    """Whether ``func`` can be called with ``count`` positional arguments (a callable
    whose signature Python cannot tell, a builtin's, passes)."""
    try:
        sig = inspect.signature(func)
    except (TypeError, ValueError):
        return True
    try:
        sig.bind(*range(count))
    except TypeError:
        return False
    return True


def _signature(func: Callable) -> str:
    try:
        return f" taking {inspect.signature(func)}"
    except (TypeError, ValueError):
        return ""


def _integer(value: Any) -> int:
    if isinstance(value, str):
        return int(value.strip())
    if isinstance(value, float):
        if not value.is_integer():
            raise ValueError(value)
        return int(value)
    return operator.index(value)


def check_number(
    shown: str,
    value: Any,
    *,
    kind: str = "float",
    low: float | None = None,
    high: float | None = None,
    open_min: bool = False,
    error: type[OrigamiCadError] = OptionsError,
) -> float | int:
    """``value`` as a finite ``float`` (or an ``int``) in range, else ``error`` naming ``shown``.

    ``low`` and ``high`` are inclusive (``open_min`` excludes ``low``); text is parsed, a
    ``bool`` is never a number.
    """
    expected = f"{shown}: expected {describe_range(kind, low, high, open_min)}, got {_shown(value)}"
    if isinstance(value, bool) or (isinstance(value, str) and not value.isascii()):
        raise error(expected)  # "\u0663" is 3 to float(): no one types it for a number
    try:
        number = float(value) if kind == "float" else _integer(value)
        finite = math.isfinite(number)
    except (TypeError, ValueError, OverflowError):  # an integer past a float's range too
        raise error(expected) from None
    if not finite:
        raise error(expected)
    too_low = low is not None and (number <= low if open_min else number < low)
    if too_low or (high is not None and number > high):
        raise error(expected)
    return number


def check_numbers(
    shown: str,
    value: Any,
    *,
    length: int | None = None,
    error: type[OrigamiCadError] = OptionsError,
) -> tuple[float, ...]:
    """``value``, a sequence of finite numbers (``length`` of them when given), as a tuple
    of floats; else ``error`` naming ``shown`` and the value (text, a mapping, a scalar,
    a nested list, NaN...).

    >>> check_numbers("start", [0, 1.5], length=2)
    (0.0, 1.5)
    """
    text = brief_value(value)
    count = f"{length} " if length is not None else ""
    expected = f"{shown}: expected a list of {count}finite numbers, got {text}"
    if isinstance(value, str | bytes | Mapping) or not hasattr(value, "__iter__"):
        raise error(expected)
    out = []
    for item in value:
        if isinstance(item, bool | str | bytes):
            raise error(expected)
        try:
            number = float(item)
        except (TypeError, ValueError, OverflowError):
            raise error(expected) from None
        if not math.isfinite(number):
            raise error(expected)
        out.append(number)
    if length is not None and len(out) != length:
        raise error(expected)
    return tuple(out)


@dataclass(frozen=True)
class Arg:
    """What a library argument must be: ``kind`` (``"float"``, ``"int"``, ``"bool"``,
    ``"str"``, ``"path"``; ``"floats"``, a sequence of ``length`` finite numbers, each in
    range; ``"object"``, an instance of one of ``types``; ``"callable"``, a function such
    as a progress callback), an inclusive range
    (``open_min`` excludes ``min``), ``choices``; ``None`` passes when ``optional``. Units
    are the argument's documented ones (mm, deg, N...)."""

    kind: str = "float"
    min: float | None = None
    max: float | None = None
    open_min: bool = False
    choices: tuple | None = None
    optional: bool = True
    #: ``+inf`` passes: the argument's "never" (a stop rule that is off)
    inf_ok: bool = False
    #: ``"object"``: the classes an argument may be an instance of
    types: tuple = ()
    #: ``"floats"``: how many numbers (None: any number of them); ``"callable"``: how many
    #: positional arguments the function is called with
    length: int | None = None

    def check(self, shown: str, value: Any, error: type[OrigamiCadError]) -> Any:
        """The value, converted; ``error`` naming ``shown`` and the value if it is bad."""
        if value is None:
            if self.optional:
                return None
            raise error(f"{shown}: a value is needed, got None")
        if self.kind in ("float", "int"):
            if self.inf_ok and isinstance(value, float) and value == math.inf:
                return value
            if isinstance(value, str | bytes):  # text is the command line's, parsed there
                raise error(f"{shown}: expected a number, not text, got {brief_value(value)}")
            value = check_number(
                shown,
                value,
                kind=self.kind,
                low=self.min,
                high=self.max,
                open_min=self.open_min,
                error=error,
            )
        elif self.kind == "floats":
            value = check_numbers(shown, value, length=self.length, error=error)
            for v in value:
                check_number(shown, v, low=self.min, high=self.max, open_min=self.open_min,
                             error=error)  # fmt: skip
        elif self.kind == "object":
            if not isinstance(value, self.types):
                names = " or ".join(t.__name__ for t in self.types)
                raise error(f"{shown}: expected a {names}, got {_brief(value)}")
        elif self.kind == "callable":
            if not callable(value):
                raise error(f"{shown}: expected a function, got {_brief(value)}")
            if self.length is not None and not _takes(value, self.length):
                raise error(
                    f"{shown}: expected a function of {self.length} arguments, got "
                    f"{brief_value(value)}{_signature(value)}"
                )
        elif self.kind == "bool":
            if not isinstance(value, bool | np.bool_):
                raise error(f"{shown}: expected True or False, got {brief_value(value)}")
            value = bool(value)
        elif self.kind == "str" and not isinstance(value, str):
            raise error(f"{shown}: expected text, got {brief_value(value)}")
        elif self.kind == "path":
            if not isinstance(value, str | os.PathLike):
                raise error(f"{shown}: expected a file path, got {_brief(value)}")
            text = os.fspath(value)
            if not isinstance(text, str) or not text or "\0" in text:
                raise error(f"{shown}: expected a file path, got {brief_value(value)}")
        if self.choices is not None and value not in self.choices:
            known = ", ".join(map(str, self.choices))
            raise error(f"{shown}: expected one of {known}, got {brief_value(value)}")
        return value


def checked(error: type[OrigamiCadError], **specs: Arg) -> Callable[[F], F]:
    """Check a library function's named arguments on every call, raising ``error``.

    Each keyword names an argument of the decorated function and its :class:`Arg`; the
    function receives the converted values (an ``int`` for ``kind="int"``...).
    """

    def wrap(func: F) -> F:
        sig = inspect.signature(func)
        unknown = set(specs) - set(sig.parameters)
        if unknown:
            raise TypeError(f"{func.__qualname__} has no argument {sorted(unknown)}")

        @functools.wraps(func)
        def inner(*args: Any, **kwargs: Any) -> Any:
            try:
                bound = sig.bind(*args, **kwargs)
            except TypeError as exc:
                raise error(f"{func.__name__}: {exc}") from None
            for name, spec in specs.items():
                if name in bound.arguments:
                    shown = f"{func.__name__}: {name}"
                    bound.arguments[name] = spec.check(shown, bound.arguments[name], error)
            return func(*bound.args, **bound.kwargs)

        return inner  # type: ignore[return-value]

    return wrap


def check_fields(obj: Any, error: type[OrigamiCadError], specs: Mapping[str, Arg]) -> None:
    """Check a frozen dataclass's fields in its ``__post_init__``, storing converted values."""
    owner = type(obj).__name__
    for name, spec in specs.items():
        value = spec.check(f"{owner}: {name}", getattr(obj, name), error)
        object.__setattr__(obj, name, value)
