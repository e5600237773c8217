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
import os
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace
from typing import Any, ClassVar

from origami_cad._fileio import atomic_directory, check_outputs
from origami_cad.commands._options import SIZING, Option
from origami_cad.commands._outputs import (
    FOLDER_HELP,
    Outputs,
    check_suffix,
    file_format,
    moved,
    one_output,
    sources,
    staged,
    wrote,
)
from origami_cad.errors import OptionsError, OrigamiCadError

__all__ = [
    "COMMANDS",
    "FOLDER_HELP",
    "SIZING",
    "Command",
    "Option",
    "Outputs",
    "check_suffix",
    "execute",
    "file_format",
    "moved",
    "register",
    "sources",
    "staged",
    "wrote",
]

PathLike = str | os.PathLike[str]


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
    FILES : tuple of str
        A folder command's files (names in its folder), checked against the inputs and
        the files they name before any work; a name that depends on the input (a
        robot's ``tsa_module_<leg>.stl``) is checked when the files are put in place.
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
    FILES: ClassVar[tuple[str, ...]] = ()
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

    @classmethod
    def default(cls, name: str) -> Any:
        """The value option ``name`` has when not given: its own default, else the
        library's (:meth:`library_defaults`); ``None`` when it has neither (or no such option).

        >>> COMMANDS["fold"].default("ratio"), COMMANDS["fabricate"].default("height")
        (0.5, 2.2)
        """
        opt = next((o for o in cls.OPTIONS if o.name == name), None)
        if opt is not None and opt.default is not None:
            return opt.default
        return cls.library_defaults().get(name)

    def inputs(self, a: SimpleNamespace) -> list:
        """The files the command reads, which no output may replace."""
        return [getattr(a, n) for n in self.INPUTS if getattr(a, n) is not None]

    def outputs(self, a: SimpleNamespace) -> tuple[list, list]:
        """``(files, folders)`` the command writes, checked against the inputs first."""
        if self.OUTPUT == "folder":
            return [Path(a.folder) / n for n in self.FILES], [a.folder]
        if self.OUTPUT == "outputs":
            return list(a.outputs), []
        return ([a.output] if self.OUTPUT == "output" else []), []

    def suffixes(self) -> tuple[str, ...]:
        """The extensions an output file may have (``()``: any)."""
        return self.SUFFIXES

    def formats(self, a: SimpleNamespace) -> list[tuple[Any, tuple[str, ...], str]]:
        """``(file, extensions, what)`` of each output whose extension gives its format:
        by default the files of ``-o`` and :meth:`suffixes`."""
        allowed = self.suffixes()
        given = {"output": [getattr(a, "output", None)], "outputs": getattr(a, "outputs", [])}
        return (
            [(path, allowed, self.WHAT) for path in given.get(self.OUTPUT, [])] if allowed else []
        )

    def prepare(self, a: SimpleNamespace) -> None:
        """The checks before any work: the outputs' formats, then against the inputs."""
        for path, allowed, what in self.formats(a):
            check_suffix(path, allowed, what)
        files, folders = self.outputs(a)
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

    @staticmethod
    def size(a: SimpleNamespace) -> dict[str, Any]:
        """The ``unit``/``scale``/``width``/``tolerance`` options (:data:`SIZING`) as
        ``read_pattern``'s keywords (``None``: not given)."""
        return {o.name: getattr(a, o.name, None) for o in SIZING}

    def load(self, a: SimpleNamespace, path: PathLike, sized: bool = True):
        """``(Design, warnings)``: a design or pattern file, an imported pattern sized by
        the ``unit``/``scale``/``width`` options (``sized``; else only joined up by
        ``tolerance``); the warnings name an implausible size, and an error the command
        raises later carries them as notes."""
        from origami_cad.pattern import size_warnings
        from origami_cad.pattern.design import load_pattern_source

        joined = {"tolerance": getattr(a, "tolerance", None)}  # commands that only join up
        loaded = load_pattern_source(path, **(self.size(a) if sized else joined))
        warned = size_warnings(loaded.pattern)
        notes = _SIZE_NOTES.get()
        if notes is not None:
            notes += [f"note: {w}" for w in warned]
        return loaded, [f"warning: {w}" for w in warned]


def _bind(cls: type[Command], args: tuple, kwargs: dict) -> SimpleNamespace:
    """The command's arguments: positional ones, options (checked), defaults."""
    names = [*cls.INPUTS, *([cls.OUTPUT] if cls.OUTPUT else [])]
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
    if cls.OUTPUT == "outputs" and isinstance(values.get("outputs"), str | os.PathLike):
        values["outputs"] = [values["outputs"]]  # one file, from Python
    for name in (cls.OUTPUT, *(o.name for o in cls.OPTIONS if o.flag == "--output")):
        if name not in (None, "outputs") and isinstance(values.get(name), list):
            values[name] = one_output(cls.NAME, cls.OUTPUT == "output", values[name])
    for opt in cls.OPTIONS:
        given = values.get(opt.name)
        if given is None and opt.required:
            raise OptionsError(f"{opt.shown}: required")
        default = False if opt.kind == "flag" and opt.default is None else opt.default
        values[opt.name] = default if given is None else opt.check(given)
    values.setdefault("progress", None)
    values.setdefault("echo", print)
    values.setdefault("extra", [])
    return SimpleNamespace(**values)


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
