"""The ``origami-cad`` command, generated from the registry of :mod:`origami_cad.commands`.

Each registered command becomes a subcommand: its inputs, ``-o`` and its options as
declared there; this module only parses the text and hands it to
:func:`origami_cad.commands.execute`, which checks every option before any work.

Exit codes (``docs/outputs.md``): 0 success; 1 a negative answer (``check``, ``route``); 2 bad
input, one line ``origami-cad: error: ...``; 3 an internal error; 130 and 143 interrupted.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import importlib
import inspect
import os
import re
import signal
import sys
import threading
from collections.abc import Sequence
from typing import Any, NoReturn

from origami_cad import __version__, demo  # noqa: F401  (demo registers its command)
from origami_cad._fileio import Interrupted, handle_signals, interrupted, written
from origami_cad._names import one_line
from origami_cad.commands import COMMANDS, FOLDER_HELP, Command, Option, Outputs, execute
from origami_cad.errors import OrigamiCadError

__all__ = ["build_parser", "main"]


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``origami-cad: error: ...`` and exit code 2."""

    def error(self, message: str) -> NoReturn:
        _error(message.removeprefix("argument "))
        raise SystemExit(2)


def _display(name: str, *args):
    """A display of :mod:`origami_cad.viz.console`, imported only when a command runs."""
    return getattr(importlib.import_module("origami_cad.viz.console"), name)(*args)


def _progress(cls: type[Command]):
    """The live display of a long command and the callable it reports to, or ``(None, None)``."""
    if cls.PROGRESS is None:
        return None, None
    if cls.PROGRESS == "servo_table":
        return _display("servo_table")
    return _display("progress_bar", cls.PROGRESS)


def _call(args: argparse.Namespace) -> Outputs:
    """Run the command with the arguments given (the others keep their defaults)."""
    cls = COMMANDS[args.command]
    given = {k: v for k, v in vars(args).items() if v is not None and k in args.names}
    # by keyword where the command orders its arguments itself (ARGS), else in order
    order = [] if cls.ARGS is not None else args.positional
    positional = [given.pop(n) for n in order if n in given]
    display, progress = _progress(cls)
    echo = {"echo": lambda line: print(line, flush=True)}
    extra = {"extra": args.extra} if cls.EXTRA else {}
    with display or contextlib.nullcontext():
        return execute(cls, *positional, **given, **extra, progress=progress, **echo)


class _DefaultsHelp(argparse.HelpFormatter):
    """Help that asks for an option's default (the library's, when the option has none)
    only when the help is shown: building the parser imports no stage."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        default = getattr(action, "shown_default", None)
        if default is None:
            return action.help
        value = default()
        return action.help if value in (None, False, ()) else f"{action.help} (default {value})"


class _Once(argparse.Action):
    """Store an option's value(s), refusing the option given a second time: which of two
    values was meant? (argparse keeps the last silently.)"""

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        if getattr(namespace, self.dest, None) is not None:
            parser.error(f"{option_string or self.dest} is given twice; give it once")
        setattr(namespace, self.dest, values)


class _FlagOnce(argparse.Action):
    """A flag (``store_true``, or ``store_false`` with ``const=False``) given once."""

    def __init__(self, option_strings, dest, const=True, **kwargs) -> None:
        super().__init__(option_strings, dest, nargs=0, const=const, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        if getattr(namespace, self.dest, None) is not None:
            parser.error(f"{option_string or self.dest} is given twice; give it once")
        setattr(namespace, self.dest, self.const)


def _add_option(p: argparse.ArgumentParser, cls: type[Command], opt: Option) -> str:
    """Add one option to a command's parser; its dest."""
    text = opt.help + (f", {opt.unit}" if opt.unit else "")
    kwargs: dict[str, Any] = {"help": text, "default": None}
    if opt.kind == "flag":
        kwargs |= {"action": _FlagOnce, "const": not opt.dest_negated}
    else:
        kwargs["action"] = "append" if opt.repeat else _Once
        kwargs |= {"nargs": opt.nargs} if opt.nargs is not None else {}
        kwargs |= {"metavar": opt.metavar} if opt.metavar is not None else {}
        kwargs |= {"required": True} if opt.required and not opt.positional else {}
    if opt.positional:
        action = p.add_argument(opt.name, **kwargs)
    else:
        flags = [*([opt.short] if opt.short else []), opt.shown]
        action = p.add_argument(*flags, dest=opt.name, **kwargs)
    if opt.kind != "flag":  # its default, from the library when None: asked for by --help
        action.shown_default = functools.partial(cls.default, opt.name)
    return opt.name


def plain_text(doc: str) -> str:
    """A docstring's reST markup as a terminal shows it: roles by their last name, no
    double backquotes.

    >>> plain_text("keywords of :func:`~origami_cad.fabrication.fabrication_params`, ``bias``")
    'keywords of fabrication_params(), bias'
    """
    doc = re.sub(r":(?:func|meth):`~?(?:[\w.]*\.)?(\w+)`", r"\1()", doc)
    doc = re.sub(r":\w+:`~?(?:[\w.]*\.)?(\w+)`", r"\1", doc)
    return doc.replace("``", "")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``origami-cad``: one subcommand per registered command."""
    parser = _Parser(
        prog="origami-cad",
        description="Design, fold, fabricate and drive string-driven origami robots. "
        "Lengths are in millimetres and angles in degrees.",
    )
    parser.add_argument("--version", action="version", version=f"origami-cad {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, cls in COMMANDS.items():
        if cls.HIDDEN:
            continue
        doc = plain_text(inspect.cleandoc(cls.__doc__ or "")).split("\n\n")
        text = {"help": doc[0].splitlines()[0], "description": "\n\n".join(doc[:2])}
        p = sub.add_parser(name, formatter_class=_DefaultsHelp, **text)
        for arg in cls.INPUTS:
            p.add_argument(arg)
        names = list(cls.INPUTS)
        if cls.OUTPUT:
            many = {"action": "append" if cls.OUTPUT == "outputs" else _Once}
            what = FOLDER_HELP if cls.OUTPUT == "folder" else "output file (format by extension)"
            p.add_argument("-o", "--output", dest=cls.OUTPUT, required=True, help=what, **many)
            names.append(cls.OUTPUT)
        positional = [*names, *(o.name for o in cls.OPTIONS if o.positional)]
        names += [_add_option(p, cls, o) for o in cls.OPTIONS if o.flag != ""]
        p.set_defaults(names=names, positional=positional)
    return parser


@functools.lru_cache(maxsize=4)
def _parser(commands: tuple[str, ...]) -> argparse.ArgumentParser:
    """The parser of the registered ``commands`` (built once: argparse is slow to build)."""
    return build_parser()


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script; returns the exit code."""
    try:
        parser = _parser(tuple(COMMANDS))
        args, extra = parser.parse_known_args(argv)
        if extra and not COMMANDS[args.command].EXTRA:
            parser.error(f"unrecognized arguments: {' '.join(extra)}")
    except SystemExit as exc:  # argparse's usage errors: exit code 2, returned like the rest
        if exc.code in (0, None):
            raise  # --help, --version
        return int(exc.code)
    except KeyboardInterrupt:  # Ctrl-C while the arguments were read: nothing was written
        return _interrupted()
    except Exception as exc:  # a Ctrl-C inside an extension's import surfaces as its error
        if _caused_by_interrupt(exc):
            return _interrupted()
        raise
    args.extra = extra  # the part's own --name value parameters
    main_thread = threading.current_thread() is threading.main_thread()
    # argv None: the console script, which exits next (a caller passing argv goes on)
    with handle_signals(exiting=argv is None) if main_thread else contextlib.nullcontext():
        return _run(args)


def _run(args: argparse.Namespace) -> int:
    """Run the job; every failure becomes one line on stderr and an exit code."""
    try:
        outputs = _call(args)
        if interrupted():  # an interrupt a library swallowed: the outputs were not written
            raise Interrupted(interrupted())
        shown = sys.stderr if _into_stdout(outputs.files) else sys.stdout
        for line in outputs.messages:
            print(line, file=shown)
        for line in outputs.warnings:
            print(f"origami-cad: warning: {one_line(line)}", file=sys.stderr)
        return outputs.status
    except OrigamiCadError as exc:  # with its notes (a pattern's implausible size)
        _error("; ".join([str(exc), *getattr(exc, "__notes__", ())]))
        return 2
    except KeyboardInterrupt:
        return _interrupted()
    except BrokenPipeError:  # output piped into a program that stopped reading (| head)
        sys.stderr.close()
        return 0
    except (RecursionError, MemoryError) as exc:  # hostile input: too deep or too large
        deep = isinstance(exc, RecursionError)
        _error("the input is nested too deeply to read" if deep else "out of memory for this input")
        return 2
    except OSError as exc:  # the file system said no: missing file, full disk, bad name...
        _error(f"{exc.filename}: {exc.strerror}" if exc.filename else str(exc.strerror or exc))
        return 2
    except Exception as exc:  # the last line of defence: one line, never a traceback
        if interrupted() or _caused_by_interrupt(exc):  # it surfaced as another error (import)
            return _interrupted()
        _error(
            f"internal error ({type(exc).__name__}: {exc}); this is a bug in origami-cad "
            f"{__version__}, please report it with the command and its input files"
        )
        return 3


def _into_stdout(files) -> bool:
    """Whether one of ``files`` is the standard output (``-o /dev/stdout``): the
    messages then go to stderr, and the output holds its data alone."""
    try:
        out = os.fstat(sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        return False
    for f in files:
        with contextlib.suppress(OSError):
            if os.path.samestat(os.stat(f), out):
                return True
    return False


def _caused_by_interrupt(exc: BaseException) -> bool:
    """Whether ``exc`` was raised by a Ctrl-C (a ``KeyboardInterrupt`` among its causes)."""
    seen: set[int] = set()
    cause: BaseException | None = exc
    while cause is not None and id(cause) not in seen:
        if isinstance(cause, KeyboardInterrupt):
            return True
        seen.add(id(cause))
        cause = cause.__cause__ or cause.__context__
    return False


def _interrupted() -> int:
    """Say the command was interrupted, naming the outputs it had put in place whole."""
    signum = interrupted() or signal.SIGINT
    word = "terminated" if signum == signal.SIGTERM else "interrupted"
    done = written()
    if done:
        word += f" after writing {', '.join(map(one_line, done))} in full"
    print(f"origami-cad: {word}; nothing more was written", file=sys.stderr)
    return 128 + signum


def _error(message: str) -> None:
    """Print one error line; control characters of user-supplied names are escaped."""
    print(f"origami-cad: error: {one_line(message)}", file=sys.stderr)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
