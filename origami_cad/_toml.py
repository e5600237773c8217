"""Strict reading of the package's TOML input files, and the writing of them.

Every file format of the package (designs, arm tasks, routes, sequences) is a
TOML file read through :class:`Table`, so unknown keys, missing keys, wrong
types and out-of-range values all give the same kind of message, naming the
file, the table and the key. :func:`parse_file` reads any input file (TOML, the
FOLD format's JSON) with the same messages for a file that cannot be read.
:func:`toml_value` and :func:`toml_table` write the values and tables of those files
(each format's writer sits next to its reader and uses them).
"""

from __future__ import annotations

import json
import math
import os
import tomllib
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from origami_cad.errors import DesignError

__all__ = [
    "MAX_INTEGER",
    "MAX_MAGNITUDE",
    "Table",
    "check_finite",
    "finite_toml",
    "input_file",
    "json_text",
    "load_toml",
    "parse_file",
    "printable",
    "toml_table",
    "toml_value",
]

_MISSING = object()
#: Largest magnitude of any number in an input file (mm, degrees, seconds, ...): no
#: physical quantity of the package comes near it, and larger ones overflow later.
MAX_MAGNITUDE = 1e9
#: Largest magnitude of any integer in an input file (exact as a float).
MAX_INTEGER = 2**53


def printable(text: str, limit: int = 80) -> str:
    r"""``text`` safe to put in a one-line message: control characters escaped, long text cut.

    >>> printable("a\nb")
    'a\\nb'
    """
    text = str(text)
    if len(text) > limit:
        text = text[:limit] + "..."
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def input_file(
    path: str | os.PathLike[str], error: type[Exception] = DesignError
) -> tuple[Path, str]:
    """An input file that exists and is a regular file: ``(path, name for messages)``.

    A missing file, a folder, a device or FIFO (which could block or never end), or
    a name the file system refuses (too long, a NUL byte) is ``error`` naming it.
    """
    p = Path(path)
    name = printable(str(p), 300)
    try:
        if p.is_file():
            return p, name
        exists = p.exists()
    except (OSError, ValueError) as exc:
        raise error(f"{name}: cannot be read ({getattr(exc, 'strerror', None) or exc})") from None
    raise error(f"{name}: {'not a regular file' if exists else 'no such file'}")


def parse_file(
    path: str | os.PathLike[str],
    parse: Callable[[Path], Any],
    *,
    fmt: str,
    error: type[Exception] = DesignError,
    not_text: str = "not a text file",
    too_deep: str | None = None,
) -> tuple[Any, str]:
    """``parse(path)`` of an input file, and its name for messages.

    Every way the reading can fail is ``error`` naming the file: not a regular
    file (see :func:`input_file`), not UTF-8 text (``not_text``), nested too
    deeply (``too_deep``, default ``not valid <fmt> (nested too deeply)``), a
    syntax error or a value Python cannot convert (``not valid <fmt> (...)``,
    with line and column for JSON), or an OS error.
    """
    p, name = input_file(path, error)
    try:
        return parse(p), name
    except UnicodeDecodeError:
        raise error(f"{name}: {not_text}") from None
    except RecursionError:
        raise error(f"{name}: {too_deep or f'not valid {fmt} (nested too deeply)'}") from None
    except ValueError as exc:  # a syntax error, or e.g. an integer with too many digits
        detail = (
            f"line {exc.lineno}, column {exc.colno}: {exc.msg}"
            if isinstance(exc, json.JSONDecodeError)
            else exc
        )
        raise error(f"{name}: not valid {fmt} ({detail})") from None
    except OSError as exc:
        raise error(f"{name}: cannot be read ({exc.strerror or exc})") from None


def _read_toml(path: Path) -> dict[str, Any]:
    with open(path, "rb") as fh:
        return tomllib.load(fh)


def load_toml(path: str | os.PathLike[str], error: type[Exception] = DesignError) -> dict[str, Any]:
    """Parse a TOML file; ``error`` (default :class:`DesignError`) naming the file on a problem."""
    too_deep = "not valid TOML (arrays or tables nested too deeply)"
    return parse_file(path, _read_toml, error=error, fmt="TOML", too_deep=too_deep)[0]


def _finite_number(v: Any) -> bool:
    """A TOML integer or float (not a boolean), finite and within :data:`MAX_MAGNITUDE`."""
    return (
        isinstance(v, int | float)
        and not isinstance(v, bool)
        and math.isfinite(v)
        and abs(v) <= MAX_MAGNITUDE
    )


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:60] + "..."


def _type_name(value: Any) -> str:
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string"}.get(
        type(value), f"a {type(value).__name__}"
    )


class Table:
    """One TOML table being read; call :meth:`finish` to reject unknown keys.

    Parameters
    ----------
    data : dict
        The parsed table.
    where : str
        How to name it in messages, e.g. ``"design.toml [pattern]"``.
    error : type
        The exception class of its messages (the reading stage's, e.g.
        :class:`~origami_cad.errors.StringsError` for a route file); its tables share it.
    """

    def __init__(self, data: Any, where: str, error: type[Exception] = DesignError) -> None:
        where = printable(where, 1000)  # a file named with a newline: its messages stay one line
        if not isinstance(data, dict):
            raise error(f"{where}: expected a table, got {_type_name(data)}")
        self.data = data
        self.where = where
        self.error_class = error
        self.used: set[str] = set()

    def has(self, key: str) -> bool:
        return key in self.data

    def _raw(self, key: str, default: Any) -> Any:
        self.used.add(key)
        if key in self.data:
            return self.data[key]
        if default is _MISSING:
            raise self.error_class(f"{self.where}: missing key '{key}'")
        return default

    def error(self, key: str, message: str) -> Exception:
        """An error about ``key`` (to raise)."""
        return self.error_class(f"{self.where}: key '{key}': {message}")

    def number(
        self,
        key: str,
        default: Any = _MISSING,
        *,
        low: float | None = None,
        high: float | None = None,
        low_open: bool = False,
        high_open: bool = False,
    ) -> float:
        """A finite number within ``[low, high]`` (open ends if asked)."""
        value = self._raw(key, default)
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.error(key, f"expected a number, got {_type_name(value)} {_shown(value)}")
        if isinstance(value, int) and abs(value) > MAX_MAGNITUDE:
            raise self.error(key, f"{_shown(value)} is too large (limit {MAX_MAGNITUDE:g})")
        value = float(value)
        if not math.isfinite(value):
            raise self.error(key, f"expected a finite number, got {value}")
        if abs(value) > MAX_MAGNITUDE:
            raise self.error(key, f"{value:g} is too large (limit {MAX_MAGNITUDE:g})")
        bad_low = low is not None and (value <= low if low_open else value < low)
        bad_high = high is not None and (value >= high if high_open else value > high)
        if bad_low or bad_high:
            lo = "(" if low_open else "["
            hi = ")" if high_open else "]"
            span = f"{lo}{'-inf' if low is None else f'{low:g}'}, "
            span += f"{'inf' if high is None else f'{high:g}'}{hi}"
            raise self.error(key, f"{value:g} is out of range {span}")
        return value

    def integer(
        self, key: str, default: Any = _MISSING, *, low: int | None = None, high: int | None = None
    ) -> int:
        """A whole number within ``[low, high]``."""
        value = self._raw(key, default)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(key, f"expected an integer, got {_type_name(value)} {_shown(value)}")
        if abs(value) > MAX_INTEGER:
            raise self.error(key, f"{_shown(value)} is too large (limit 2**53)")
        if (low is not None and value < low) or (high is not None and value > high):
            raise self.error(key, f"{value} is out of range [{low}, {high}]")
        return int(value)

    def boolean(self, key: str, default: Any = _MISSING) -> bool:
        value = self._raw(key, default)
        if not isinstance(value, bool):
            raise self.error(
                key, f"expected true or false, got {_type_name(value)} {_shown(value)}"
            )
        return value

    def string(self, key: str, default: Any = _MISSING, *, choices: tuple[str, ...] = ()) -> str:
        value = self._raw(key, default)
        if not isinstance(value, str):
            raise self.error(key, f"expected a string, got {_type_name(value)} {_shown(value)}")
        if choices and value not in choices:
            raise self.error(key, f"{_shown(value)} is not one of {', '.join(map(repr, choices))}")
        return value

    def numbers(
        self,
        key: str,
        default: Any = _MISSING,
        *,
        length: int | None = None,
        min_length: int = 0,
        check: Callable[[float], bool] | None = None,
        what: str = "",
    ) -> list[float]:
        """A list of numbers (optionally of a given length, each passing ``check``)."""
        value = self._raw(key, default)
        if not isinstance(value, list):
            raise self.error(key, f"expected a list of numbers, got {_type_name(value)}")
        out = []
        for i, v in enumerate(value):
            if not _finite_number(v):
                raise self.error(
                    key,
                    f"item {i} is not a finite number within +-{MAX_MAGNITUDE:g}: {_shown(v)}",
                )
            if check is not None and not check(float(v)):
                raise self.error(key, f"item {i} = {v!r}: {what or 'out of range'}")
            out.append(float(v))
        if length is not None and len(out) != length:
            raise self.error(key, f"expected {length} numbers, got {len(out)}")
        if len(out) < min_length:
            raise self.error(key, f"expected at least {min_length} numbers, got {len(out)}")
        return out

    def point(self, key: str, default: Any = _MISSING, dims: int = 2) -> tuple[float, ...]:
        """A point ``[x, y]`` (or ``dims`` coordinates), mm."""
        return tuple(self.numbers(key, default, length=dims))

    def pairs(self, key: str, default: Any = _MISSING, *, min_length: int = 1) -> list[list[float]]:
        """A list of ``[a, b]`` number pairs."""
        value = self._raw(key, default)
        if not isinstance(value, list) or len(value) < min_length:
            raise self.error(key, f"expected a list of at least {min_length} [a, b] pairs")
        out = []
        for i, item in enumerate(value):
            if not isinstance(item, list) or len(item) != 2 or not all(map(_finite_number, item)):
                raise self.error(
                    key,
                    f"item {i} must be a pair of finite numbers within +-{MAX_MAGNITUDE:g}, "
                    f"got {_shown(item)}",
                )
            out.append([float(item[0]), float(item[1])])
        return out

    def table(self, key: str, default: Any = _MISSING) -> Table:
        return Table(
            self._raw(key, default),
            f"{self.where.rstrip(']')}.{key}]"
            if self.where.endswith("]")
            else f"{self.where} [{key}]",
            self.error_class,
        )

    def finish(self) -> None:
        """Raise on keys that were never read (typos, unsupported options)."""
        unknown = [k for k in self.data if k not in self.used]
        if unknown:
            shown = ", ".join(_shown(k) for k in unknown[:5])
            if len(unknown) > 5:
                shown += f" and {len(unknown) - 5} more"
            raise self.error_class(
                f"{self.where}: unknown key{'s' if len(unknown) > 1 else ''} {shown}"
            )


def _non_finite(value: Any, path: str = "") -> tuple[str, float] | None:
    """``(key path, number)`` of the first NaN or infinity in ``value`` (``a.b[2]``), else None."""
    if hasattr(value, "tolist") and not isinstance(value, str | bytes):
        value = value.tolist()  # a NumPy array or scalar
    if isinstance(value, float):
        return None if math.isfinite(value) else (path, value)
    items = (
        ((f"{path}.{k}" if path else str(k), v) for k, v in value.items())
        if isinstance(value, Mapping)
        else ((f"{path}[{k}]", v) for k, v in enumerate(value))
        if isinstance(value, list | tuple)
        else ()
    )
    for here, item in items:
        found = _non_finite(item, here)
        if found is not None:
            return found
    return None


def check_finite(data: Any, where: str, error: type[Exception] = DesignError) -> None:
    """``error`` naming ``where`` and the key path of the first NaN or infinity in ``data``
    (read from JSON: Python's reader takes ``NaN``, ``Infinity`` and ``1e999``, which
    no strict JSON holds), even in a key the reader does not use.

    >>> check_finite({"a": [1.5, float("inf")]}, "x.json")
    Traceback (most recent call last):
    ...
    origami_cad.errors.DesignError: x.json: a[1] is inf, not a finite number (strict JSON has none)
    """
    try:
        bad = _non_finite(data)
    except RecursionError:
        raise error(f"{where}: nested too deeply to read") from None
    if bad is not None:
        raise error(
            f"{where}: {bad[0] or 'the value'} is {bad[1]}, not a finite number "
            "(strict JSON has none)"
        )


def _plain(value: Any) -> Any:
    """A NumPy array or scalar as plain Python (``json.dumps``'s ``default``)."""
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"Object of type {type(value).__name__} is not JSON serializable")


def json_text(data: Any, where: str, error: type[Exception] = DesignError, **options: Any) -> str:
    """``data`` as strict JSON text (``options`` of ``json.dumps``: ``indent``...).

    JSON has no NaN or infinity, and no strict reader (a browser, ``jq``, the package's
    own) accepts them: one in ``data`` is ``error`` naming ``where`` and its key path;
    so is a value JSON cannot hold.

    >>> json_text({"a": [1.5, 2]}, "x.json")
    '{"a": [1.5, 2]}'
    >>> json_text({"a": [1.5, float("nan")]}, "x.json")
    Traceback (most recent call last):
    ...
    origami_cad.errors.DesignError: x.json: a[1] is nan; JSON holds finite numbers only
    """
    bad = _non_finite(data)
    if bad is not None:
        raise error(f"{where}: {bad[0] or 'the value'} is {bad[1]}; JSON holds finite numbers only")
    try:
        return json.dumps(data, allow_nan=False, default=_plain, **options)
    except (TypeError, ValueError, OverflowError) as exc:
        raise error(f"{where}: a value JSON cannot hold ({exc})") from None


def finite_toml(text: str, where: str, error: type[Exception] = DesignError) -> str:
    r"""``text``, a TOML file a writer made, once read back holding finite numbers only.

    TOML spells ``nan`` and ``inf``, which the package's readers refuse: a writer that
    met one (a NaN fold limit, an infinite length) is ``error`` naming ``where`` and the
    key path, before anything is written.

    >>> finite_toml("[a]\nb = [1.0, nan]\n", "x.toml")
    Traceback (most recent call last):
    ...
    origami_cad.errors.DesignError: x.toml: a.b[1] is nan; the file holds finite numbers only
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:  # a writer's bug, named rather than written
        raise error(f"{where}: the text written is not valid TOML ({exc})") from None
    bad = _non_finite(data)
    if bad is not None:
        raise error(f"{where}: {bad[0]} is {bad[1]}; the file holds finite numbers only")
    return text


def toml_value(value: Any, digits: int | None = None) -> str:
    """``value`` as TOML: a boolean, integer, float, string or (nested) list of them.

    Floats are written exactly (``repr``: read back, they are the same number), or with
    ``digits`` decimals; NumPy scalars and arrays count as floats and lists.

    >>> toml_value([1, 2.5, "a\\b", True]), toml_value((1 / 3, 2.0), digits=3)
    ('[1, 2.5, "a\\\\b", true]', '[0.333, 2.000]')
    """
    if hasattr(value, "tolist"):  # NumPy array or scalar
        value = value.tolist()
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):  # TOML's spelling; finite_toml refuses the file
            return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
        return repr(value) if digits is None else f"{value:.{digits}f}"
    if isinstance(value, str):
        # a TOML basic string: JSON's escapes are TOML's, and DEL must be escaped too
        return json.dumps(value, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(value, list | tuple):
        return "[" + ", ".join(toml_value(v, digits) for v in value) + "]"
    raise TypeError(f"no TOML form for {type(value).__name__}")


def toml_table(
    name: str | None,
    items: Mapping[str, Any],
    *,
    array: bool = False,
    comments: Mapping[str, str] | None = None,
    digits: Mapping[str, int] | None = None,
) -> list[str]:
    """The lines of one TOML table ``[name]`` (``[[name]]`` with ``array``); None values
    are left out, ``comments`` follow their key's value, ``digits`` rounds a key's floats.

    A NaN or infinity is spelled as TOML spells it (``nan``, ``inf``): the writer ends in
    :func:`finite_toml`, which refuses the file naming the key, with its stage's error.

    >>> toml_table("route", {"max_turns": 20.0, "p_max": None}, comments={"max_turns": "turns"})
    ['[route]', 'max_turns = 20.0   # turns']
    """
    lines = [] if name is None else [f"[[{name}]]" if array else f"[{name}]"]
    for key, value in items.items():
        if value is None:
            continue
        line = f"{key} = {toml_value(value, (digits or {}).get(key))}"
        note = (comments or {}).get(key)
        lines.append(f"{line}   # {note}" if note else line)
    return lines
