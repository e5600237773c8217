"""A command's options, each declared once: :class:`Option` (type, unit, range, help)
and the checks every value passes before any work (one line naming the option)."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from origami_cad._args import check_number
from origami_cad.errors import OptionsError

__all__ = ["SIZING", "TOLERANCE", "Option"]

_KINDS = ("float", "int", "str", "flag", "object")


@dataclass(frozen=True)
class Option:
    """One option of a command, declared once: its name, type, unit, range and help.

    Parameters
    ----------
    name : str
        The keyword of the command (and its ``--flag``: underscores become hyphens).
    kind : {"float", "int", "str", "flag", "object"}
        The value's type; ``"float"`` values are finite, ``"flag"`` is ``store_true``,
        ``"object"`` a Python value given as is (a keyword with no flag).
    help : str
        One line; the unit is appended when given.
    unit : str
        The value's unit (``"mm"``, ``"deg"``, ``"s"``...), or ``""``.
    default : object
        The value when the option is not given (``None``: the library's default).
    min, max : float, optional
        The range (inclusive; ``open_min`` excludes ``min``).
    choices : tuple or callable, optional
        The allowed values, or a function returning them (a registry read when a value
        is checked or the help is shown, not when the parser is built).
    nargs : int or str, optional
        Values per occurrence (2 for ``X Y``, ``"+"``...); each is checked.
    repeat : bool
        The option may be given several times (a list of its values).
    parse : callable, optional
        Text to value, for a structured value (raises ``ValueError`` with the expected form).
    flag : str, optional
        The command-line flag when it is not ``--name``; ``""``: Python only (no flag).
    short : str, optional
        A short flag (``-v``).
    metavar, dest_negated : str, optional
        argparse's metavar; ``dest_negated``: the flag stores ``False`` (``--no-renders``).
    positional : bool
        A positional argument (after the command's inputs).
    required : bool
        The option must be given.
    """

    name: str
    kind: str = "str"
    help: str = ""
    unit: str = ""
    default: Any = None
    min: float | None = None
    max: float | None = None
    open_min: bool = False
    choices: tuple | Callable[[], tuple] | None = None
    nargs: int | str | None = None
    repeat: bool = False
    parse: Callable[[str], Any] | None = None
    flag: str | None = None
    short: str | None = None
    metavar: Any = None
    dest_negated: str | None = None
    positional: bool = False
    required: bool = False

    @property
    def allowed(self) -> tuple | None:
        """The allowed values (:attr:`choices`, called when it is a function), or ``None``."""
        return tuple(self.choices()) if callable(self.choices) else self.choices

    @property
    def shown(self) -> str:
        """How errors name the option: its flag, else its keyword."""
        if self.positional:
            return self.name
        return self.flag or (self.dest_negated or "--" + self.name.replace("_", "-"))

    def check(self, value: Any) -> Any:
        """The value, converted and checked; ``OptionsError`` naming the option if bad."""
        if value is None:
            return value
        if self.kind == "object":  # structured text (the command line) or a Python value
            if self.parse and isinstance(value, str):
                return self._one(value)
            texts = isinstance(value, list) and all(isinstance(v, str) for v in value)
            return [self._one(v) for v in value] if self.parse and texts else value
        if self.kind == "flag":
            if not isinstance(value, bool):
                raise OptionsError(f"{self.shown}: expected True or False, got {value!r}")
            return value
        many = self.repeat or self.nargs not in (None, "?")
        if (many and isinstance(value, (str, bytes))) or not many:
            return self._one(value)
        if not isinstance(value, Sequence) and not hasattr(value, "__iter__"):
            raise OptionsError(f"{self.shown}: expected a list of values, got {value!r}")
        items = list(value)
        if self.repeat and self.nargs not in (None, "?"):
            return [[self._one(v) for v in group] for group in items]
        return [self._one(v) for v in items]

    def _one(self, value: Any) -> Any:
        if self.parse is not None and isinstance(value, str):
            try:
                return self.parse(value)
            except (ValueError, OverflowError) as exc:
                raise OptionsError(f"{self.shown}: {exc}") from None
        if self.kind in ("float", "int"):
            value = self._number(value)
        elif self.kind == "str" and not isinstance(value, (str, os.PathLike)):
            if self.parse is None:
                raise OptionsError(f"{self.shown}: expected text, got {value!r}")
        allowed = self.allowed
        if allowed is not None and value not in allowed:
            raise OptionsError(
                f"{self.shown}: expected one of {', '.join(map(str, allowed))}, got {value!r}"
            )
        return value

    def _number(self, value: Any) -> float | int:
        return check_number(
            self.shown,
            value,
            kind=self.kind,
            low=self.min,
            high=self.max,
            open_min=self.open_min,
        )


#: ``tolerance``: vertices of an imported pattern closer than this merge (mm of the pattern
#: once sized; default: ``IMPORT_RELATIVE_TOLERANCE`` of its size).
TOLERANCE = Option(
    "tolerance",
    "float",
    "imported patterns: vertices closer than this merge (default 1e-4 of the size)",
    "mm",
    min=0,
    open_min=True,
    max=1e6,
)
#: ``unit``, ``scale``, ``width`` and ``tolerance``: how an imported pattern (.fold, .dxf,
#: .svg, .opx) is sized and joined up.
SIZING = (
    Option("unit", help="unit of an imported file's coordinates: mm, cm, m, in, ft, pt or "
           "px, or its length in mm (default: the unit the file declares, else mm)"),
    Option("scale", "float", "multiply an imported pattern's size", min=0, open_min=True,
           max=1e6, metavar="FACTOR"),
    Option("width", "float", "scale an imported pattern to this width", "mm", min=0,
           open_min=True, max=1e6),
    TOLERANCE,
)  # fmt: skip
