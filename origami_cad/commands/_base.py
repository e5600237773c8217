"""The command registry and the skeleton every command shares.

A command is a class registered with :func:`register`: its ``NAME``, its input files
(``INPUTS``), what ``-o`` gives (``OUTPUT``), its ``OPTIONS`` (each an :class:`Option`
with its type, unit, range and help) and a ``run`` method that computes and writes. The
skeleton (:func:`execute`) does the rest, in one place and in this order, before any work:
every option is checked (type, finiteness, range: one line naming the option), the output
files' formats (``SUFFIXES``), and the outputs against the inputs
(:func:`~origami_cad._fileio.check_outputs`). ``run`` then writes a folder through
:meth:`Command.stage` (only the command's own files, all at once at the end) and says so
with :func:`wrote`; an error it raises carries the size notes of the patterns it read by
:meth:`Command.load` (a pattern read at the wrong scale fails far from its reader).

>>> import tempfile, pathlib
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> out = execute("pattern", "examples/miura_6x4.toml", [folder / "cp.fold"])
>>> [p.name for p in out.files], dict(out.numbers)["panels"]
(['cp.fold'], '24')
"""

from __future__ import annotations

import contextlib
import contextvars
import math
import os
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace
from typing import Any, ClassVar

from origami_cad._fileio import atomic_directory, check_outputs
from origami_cad.errors import OptionsError, OrigamiCadError

__all__ = [
    "COMMANDS",
    "SIZING",
    "Command",
    "Option",
    "Outputs",
    "check_suffix",
    "execute",
    "moved",
    "register",
    "sources",
    "staged",
    "wrote",
]

PathLike = str | os.PathLike[str]


@dataclass
class Outputs:
    """What a command wrote and what it found.

    Attributes
    ----------
    files : list of Path
        Every file written, in order.
    images : list of (Path, str)
        The pictures among them (.png, .gif, and .glb 3D views), with a caption.
    numbers : list of (str, str)
        Key results, name and value with its unit.
    messages : list of str
        Lines for the user: summary and warnings.
    result : object
        The library result the files were made from (a ``DCQCResult``,
        ``Fabrication``, list of ``ArmDesign``...), or ``None``.
    status : int
        0, or 1 when the command ran but its answer is negative (a pattern with
        errors, a routing that never folds).
    """

    files: list[Path] = field(default_factory=list)
    images: list[tuple[Path, str]] = field(default_factory=list)
    numbers: list[tuple[str, str]] = field(default_factory=list)
    messages: list[str] = field(default_factory=list)
    result: Any = None
    status: int = 0

    def extend(self, other: Outputs) -> Outputs:
        """Add another command's outputs to these (for chained commands); returns ``self``.

        A number two commands both report (the same name and value: a pattern's size,
        read by each) is kept once.
        """
        self.files += other.files
        self.images += other.images
        self.numbers += [n for n in other.numbers if n not in self.numbers]
        self.messages += other.messages
        return self


# ----------------------------------------------------------------------------- options

_KINDS = ("float", "int", "str", "flag", "object")


def _describe_range(opt: Option) -> str:
    """``a finite number in [0, 1]``, ``an integer in 1..4096``..."""
    if opt.kind == "int":
        lo = "" if opt.min is None else f"{opt.min:g}"
        hi = "" if opt.max is None else f"{opt.max:g}"
        return "an integer" + (f" in {lo}..{hi}" if lo or hi else "")
    text = "a finite number"
    if opt.min is None and opt.max is None:
        return text
    left = "(" if opt.open_min else "["
    lo = "-inf" if opt.min is None else f"{opt.min:g}"
    hi = "inf" if opt.max is None else f"{opt.max:g}"
    return f"{text} in {left}{lo}, {hi}{')' if opt.max is None else ']'}"


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
    choices : tuple, optional
        The allowed values.
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
    choices: tuple | None = None
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
        if self.choices is not None and value not in self.choices:
            raise OptionsError(
                f"{self.shown}: expected one of {', '.join(map(str, self.choices))}, got {value!r}"
            )
        return value

    def _number(self, value: Any) -> float | int:
        expected = f"{self.shown}: expected {_describe_range(self)}, got {_shown(value)}"
        if isinstance(value, bool):
            raise OptionsError(expected)
        try:
            number = float(value) if self.kind == "float" else _integer(value)
        except (TypeError, ValueError, OverflowError):
            raise OptionsError(expected) from None
        if not math.isfinite(number):
            raise OptionsError(expected)
        low = self.min is not None and (number <= self.min if self.open_min else number < self.min)
        if low or (self.max is not None and number > self.max):
            raise OptionsError(expected)
        return number


def _shown(value: Any) -> str:
    return value if isinstance(value, str) else repr(value)


def _integer(value: Any) -> int:
    if isinstance(value, str):
        return int(value.strip())
    if isinstance(value, float) and not value.is_integer():
        raise ValueError(value)
    import operator

    return operator.index(value) if not isinstance(value, float) else int(value)


#: ``unit``, ``scale`` and ``width``: how an imported pattern (.dxf, .svg) is sized.
SIZING = (
    Option("unit", help="unit of an imported file: mm, cm, m, in, ft, pt, px or MM"),
    Option("scale", "float", "multiply an imported pattern's size", min=0, open_min=True,
           max=1e6),
    Option("width", "float", "scale an imported pattern to this width", "mm", min=0,
           open_min=True, max=1e6),
)  # fmt: skip


# ----------------------------------------------------------------------------- commands

#: Every command, by name, in the order of ``origami-cad --help``.
COMMANDS: dict[str, type[Command]] = {}

_SIZE_NOTES: contextvars.ContextVar[list[str] | None] = contextvars.ContextVar(
    "size_notes", default=None
)


def register(cls: type[Command]) -> type[Command]:
    """Class decorator: add a command to :data:`COMMANDS` (its ``NAME`` must be new)."""
    if cls.NAME in COMMANDS:
        raise ValueError(f"command {cls.NAME!r} is registered twice")
    names = [*cls.INPUTS, *([cls.OUTPUT] if cls.OUTPUT else []), *(o.name for o in cls.OPTIONS)]
    if len(set(names)) != len(names):
        raise ValueError(f"command {cls.NAME!r}: two arguments share a name")
    COMMANDS[cls.NAME] = cls
    return cls


class Command:
    """A command of ``origami-cad``: subclass, set the class attributes, write :meth:`run`.

    Class attributes
    ----------------
    NAME : str
        The command's name (``origami-cad NAME``).
    INPUTS : tuple of str
        Its positional input files, in order (their names are ``run``'s attributes).
    OUTPUT : {None, "output", "outputs", "folder"}
        What ``-o`` gives: one file, a repeatable file, or a folder.
    SUFFIXES : tuple of str
        The extensions an output file may have (checked before any work), and
        ``WHAT`` it is, for the error.
    OPTIONS : tuple of Option
        Every option.
    PROGRESS : str, optional
        The label of the progress bar the command line shows (``"servo_table"``: the
        live servo table).
    HIDDEN : bool
        Not a command of ``origami-cad`` (a step of the demo only).
    ARGS : tuple of str, optional
        The order of :func:`execute`'s positional arguments, when it is not ``INPUTS``,
        then ``OUTPUT``, then the positional options.
    EXTRA : bool
        The command takes options of its own beyond ``OPTIONS`` (``part``: the part's
        ``--name value`` parameters), given to ``run`` as ``a.extra``.

    The first line of the class docstring is the command's help, the first two
    paragraphs its description.
    """

    NAME: ClassVar[str]
    INPUTS: ClassVar[tuple[str, ...]] = ()
    OUTPUT: ClassVar[str | None] = None
    SUFFIXES: ClassVar[tuple[str, ...]] = ()
    WHAT: ClassVar[str] = "the output"
    OPTIONS: ClassVar[tuple[Option, ...]] = ()
    PROGRESS: ClassVar[str | None] = None
    HIDDEN: ClassVar[bool] = False
    EXTRA: ClassVar[bool] = False
    ARGS: ClassVar[tuple[str, ...] | None] = None

    @classmethod
    def library_defaults(cls) -> dict[str, Any]:
        """Defaults of options whose ``default`` is ``None`` (the library's), for the help."""
        return {}

    def inputs(self, a: SimpleNamespace) -> list:
        """The files the command reads, which no output may replace."""
        return [getattr(a, n) for n in self.INPUTS if getattr(a, n) is not None]

    def outputs(self, a: SimpleNamespace) -> tuple[list, list]:
        """``(files, folders)`` the command writes, checked against the inputs first."""
        if self.OUTPUT == "folder":
            return [], [a.folder]
        if self.OUTPUT == "outputs":
            return list(a.outputs), []
        return ([a.output] if self.OUTPUT == "output" else []), []

    def suffixes(self) -> tuple[str, ...]:
        """The extensions an output file may have (``()``: any)."""
        return self.SUFFIXES

    def prepare(self, a: SimpleNamespace) -> None:
        """The checks before any work: the outputs' formats, then against the inputs."""
        files, folders = self.outputs(a)
        allowed = self.suffixes()
        if allowed and self.OUTPUT in ("output", "outputs"):
            for path in files:
                check_suffix(path, allowed, self.WHAT)
        check_outputs(self.inputs(a), files=files, folders=folders)

    def run(self, a: SimpleNamespace) -> Outputs:  # pragma: no cover - abstract
        """Compute and write; ``a`` holds the inputs, the output and every option."""
        raise NotImplementedError

    @contextlib.contextmanager
    def stage(
        self, a: SimpleNamespace, *more: Any, folder: PathLike | None = None
    ) -> Iterator[Path]:
        """The staging folder of ``a.folder`` (or ``folder``): installed all at once when
        the block ends, holding only the command's files.

        ``more`` are further inputs (a loaded ``Design``: the file it was read from) that
        the folder may not replace.
        """
        where = a.folder if folder is None else folder
        with atomic_directory(where, inputs=sources(*self.inputs(a), *more)) as stage:
            yield stage

    def load(self, a: SimpleNamespace, path: PathLike, sized: bool = True):
        """``(Design, warnings)``: a design or pattern file, an imported pattern sized by
        the ``unit``/``scale``/``width`` options; the warnings name an implausible size,
        and an error the command raises later carries them as notes."""
        from origami_cad.pattern import size_warnings
        from origami_cad.pattern.design import load_pattern_source

        size = {k: getattr(a, k, None) for k in ("unit", "scale", "width")} if sized else {}
        loaded = load_pattern_source(path, **size)
        warned = size_warnings(loaded.pattern)
        notes = _SIZE_NOTES.get()
        if notes is not None:
            notes += [f"note: {w}" for w in warned]
        return loaded, [f"warning: {w}" for w in warned]


def _bind(cls: type[Command], args: tuple, kwargs: dict) -> SimpleNamespace:
    """The command's arguments: positional ones, options (checked), defaults."""
    names = [*cls.INPUTS, *([_dest(cls.OUTPUT)] if cls.OUTPUT else [])]
    names += [o.name for o in cls.OPTIONS if o.positional]
    names = list(cls.ARGS) if cls.ARGS is not None else names
    if len(args) > len(names):
        raise TypeError(f"{cls.NAME}: {len(args)} positional arguments, at most {len(names)}")
    values = dict(zip(names, args, strict=False))
    options = {o.name: o for o in cls.OPTIONS}
    for key, value in kwargs.items():
        if key in values:
            raise TypeError(f"{cls.NAME}: {key} given twice")
        if key not in options and key not in names and key not in ("progress", "echo", "extra"):
            raise TypeError(f"{cls.NAME}: no option {key!r}")
        values[key] = value
    for name in names:
        if name not in values and name not in options:
            raise TypeError(f"{cls.NAME}: missing {name}")
    for opt in cls.OPTIONS:
        given = values.get(opt.name)
        if given is None and opt.required:
            raise OptionsError(f"{opt.shown}: required")
        values[opt.name] = opt.default if given is None else opt.check(given)
    values.setdefault("progress", None)
    values.setdefault("echo", print)
    values.setdefault("extra", [])
    return SimpleNamespace(**values)


def _dest(output: str) -> str:
    return {"output": "output", "outputs": "outputs", "folder": "folder"}[output]


def execute(command: str | type[Command], *args: Any, **kwargs: Any) -> Outputs:
    """Run a command as ``origami-cad`` does: check every option, the outputs, then run.

    Parameters
    ----------
    command : str or Command subclass
        The command's name (``"fold"``) or class.
    *args
        Its input files, then its output (a file, a list of files or a folder), in order.
    **kwargs
        Its options by keyword (``ratio=0.5``), in their units (mm, degrees); also
        ``progress`` (a callable the long commands report to) and ``echo`` (where
        ``emulate`` prints).

    Returns
    -------
    Outputs
        What the command wrote and found.

    Raises
    ------
    OptionsError
        A bad option (one line naming it), before any work.
    OrigamiCadError
        Bad input, with the size notes of the patterns read.
    """
    cls = COMMANDS[command] if isinstance(command, str) else command
    a = _bind(cls, args, kwargs)
    cmd = cls()
    token = _SIZE_NOTES.set([])
    try:
        cmd.prepare(a)
        return cmd.run(a)
    except OrigamiCadError as exc:
        for note in _SIZE_NOTES.get() or ():
            exc.add_note(note)
        raise
    finally:
        _SIZE_NOTES.reset(token)


# ----------------------------------------------------------------------------- helpers


def _is_stream(path: PathLike) -> bool:
    """A device or pipe (``/dev/stdout``, a FIFO): written into, whatever its name."""
    import stat

    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return stat.S_ISCHR(mode) or stat.S_ISFIFO(mode)


def check_suffix(path: PathLike, allowed: Sequence[str], what: str) -> None:
    """Refuse an output file whose extension is not one of ``allowed`` (``OptionsError``)."""
    if len(allowed) == 1 and _is_stream(path):
        return  # one possible format: a device or pipe needs no extension
    if Path(os.path.realpath(path)).suffix.lower() not in allowed:  # a link: its file's name
        raise OptionsError(f"{path}: {what} is written as {', '.join(allowed)} (by its extension)")


def sources(*items: Any) -> list:
    """Input paths, and the file a design was read from, that no output may replace."""
    return [s for s in (getattr(i, "source", i) for i in items) if s is not None]


def moved(files: Sequence[Path], stage: Path, folder: PathLike) -> list[Path]:
    """Where the files written into ``stage`` are once in ``folder``."""
    return [Path(folder) / Path(f).relative_to(stage) for f in files]


def staged(stage: Path) -> list[Path]:
    """The files written into ``stage`` (sorted), not the skeleton's own."""
    return sorted(p for p in stage.iterdir() if not p.name.startswith("."))


def wrote(folder: PathLike, names: Sequence[Any]) -> str:
    """The line saying what a command wrote into ``folder``: ``wrote FOLDER/: a b c``."""
    return f"wrote {folder}/: " + " ".join(Path(n).name for n in names)
