"""The ``origami-cad`` command, generated from the registry of :mod:`origami_cad.commands`.

Each registered command becomes a subcommand: its inputs, ``-o`` and its options as
declared there; this module only parses the text and hands it to
:func:`origami_cad.commands.execute`, which checks every option before any work.

Exit codes (``docs/outputs.md``): 0 success; 1 a negative answer (``check``, ``route``); 2 bad
input, one line ``origami-cad: error: ...``; 3 an internal error; 130 and 143 interrupted.

Diagnostics go to stderr: warnings (the library's, through the ``origami_cad`` logger, and
the command's) as ``origami-cad: warning: ...``, progress bars on a terminal only.
``--quiet`` shows errors only, ``--verbose`` the library's info lines too, ``--debug``
everything and the traceback of an internal error (exit 3); the environment variable
``ORIGAMI_CAD_LOG`` (``quiet``, ``warning``, ``info`` or ``debug``) sets the same
when no flag is given.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import importlib
import inspect
import logging
import os
import re
import signal
import sys
import threading
import traceback
import warnings
from collections.abc import Sequence
from typing import Any, NoReturn

from origami_cad import __version__, demo  # noqa: F401  (demo registers its command)
from origami_cad._names import one_line
from origami_cad._signals import Interrupted, handle_signals, interrupted, written
from origami_cad.commands import (
    COMMANDS,
    FOLDER_HELP,
    Command,
    Option,
    Outputs,
    execute,
    register,
)
from origami_cad.errors import OrigamiCadError, OrigamiCadWarning

__all__ = ["build_parser", "main"]


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``origami-cad: error: ...`` and exit code 2."""

    def error(self, message: str) -> NoReturn:
        _error(message.removeprefix("argument "))
        raise SystemExit(2)


def _display(name: str, *args):
    """A display of :mod:`origami_cad.viz.console`, imported only when a command runs."""
    return getattr(importlib.import_module("origami_cad.viz.console"), name)(*args)


#: The environment variable that sets how much the command line says (``LEVELS``).
LOG_ENV = "ORIGAMI_CAD_LOG"
#: Its values and the flags', as logging levels (``quiet``: errors only).
LEVELS = {"quiet": logging.ERROR, "warning": logging.WARNING, "info": logging.INFO,
          "debug": logging.DEBUG}  # fmt: skip
_DIAGNOSTICS = (
    ("-q", "--quiet", "say nothing but errors (no summary, warnings or progress)"),
    (None, "--verbose", "also say what the library does (its info lines)"),
    (None, "--debug", "say everything, and show the traceback of an internal error"),
)


def _add_diagnostics(p: argparse.ArgumentParser, taken: set[str], top: bool) -> None:
    """``--quiet``, ``--verbose``, ``--debug`` (those a command does not use itself),
    before or after the command's name."""
    for short, flag, text in _DIAGNOSTICS:
        if flag in taken:
            continue  # check's own --verbose (it also lists what was normalised)
        names = [n for n in (short, flag) if n and n not in taken]
        default = False if top else argparse.SUPPRESS  # a subcommand keeps the top's value
        dest = "log_" + flag.lstrip("-")
        p.add_argument(*names, dest=dest, action="store_true", default=default, help=text)


def log_level(args: argparse.Namespace) -> int:
    """The logging level of a run: ``--debug``, ``--verbose``, ``--quiet``, else
    :data:`LOG_ENV`, else warnings."""
    for flag, name in (("log_debug", "debug"), ("log_verbose", "info"), ("log_quiet", "quiet")):
        if getattr(args, flag, False):
            return LEVELS[name]
    env = os.environ.get(LOG_ENV, "").strip().lower()
    return LEVELS.get(env, logging.WARNING)


class _Stderr(logging.Handler):
    """The ``origami_cad`` logger's lines on stderr, in the command's words; remembers the
    warnings said, so that a command's copy of one is not said twice."""

    def __init__(self, cls: type[Command]) -> None:
        super().__init__()
        self.cls, self.said = cls, set()

    def emit(self, record: logging.LogRecord) -> None:
        text = record.getMessage()
        self.said.add(text)
        level = record.levelname.lower()
        print(f"origami-cad: {level}: {one_line(command_words(text, self.cls))}", file=sys.stderr)


@contextlib.contextmanager
def _diagnostics(args: argparse.Namespace):
    """The run's logging: the library's logger on stderr at the run's level; Python
    warnings of the library shown through it (once, in the command's words)."""
    logger = logging.getLogger("origami_cad")
    handler = _Stderr(COMMANDS[args.command])
    before = (logger.level, logger.propagate)
    logger.setLevel(log_level(args))
    logger.addHandler(handler)
    logger.propagate = False
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", OrigamiCadWarning)  # the logger says them
            yield handler
    finally:
        logger.removeHandler(handler)
        logger.setLevel(before[0])
        logger.propagate = before[1]


def _progress(cls: type[Command], level: int = logging.WARNING):
    """The live display of a long command and the callable it reports to, or ``(None, None)``
    (not on a terminal, nor with ``--quiet``: a pipe or a log file gets no bar)."""
    if cls.PROGRESS is None or level > logging.WARNING or not _on_terminal():
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
    display, progress = _progress(cls, log_level(args))
    echo = {"echo": lambda line: print(line, flush=True)}
    extra = {"extra": args.extra} if cls.EXTRA else {}
    with display or contextlib.nullcontext():
        return execute(cls, *positional, **given, **extra, progress=progress, **echo)


class _DefaultsHelp(argparse.HelpFormatter):
    """Help that asks for an option's default (the library's, when the option has none)
    only when the help is shown: building the parser imports no stage."""

    def _metavar_formatter(self, action: argparse.Action, default_metavar: str):
        lazy = getattr(action, "lazy_choices", None)  # a registry's names, read when shown
        if lazy is not None:
            default_metavar = "{" + ",".join(map(str, lazy())) + "}"
        return super()._metavar_formatter(action, default_metavar)

    def _get_help_string(self, action: argparse.Action) -> str | None:
        text = action.help
        lazy = getattr(action, "lazy_help", None)
        if lazy is not None:
            text = lazy()
        default = getattr(action, "shown_default", None)
        if default is None:
            return text
        shown = shown_value(default())
        return f"{text} (default {shown})" if shown else text


def shown_value(value: Any) -> str:
    """A value as the user types it on the command line (``""``: nothing to show).

    >>> shown_value((200.0, 200.0)), shown_value(1000 / 60), shown_value(True)
    ('200 200', '16.67', '')
    """
    if isinstance(value, bool) or value is None:
        return ""
    if isinstance(value, tuple | list):
        return " ".join(shown_value(v) for v in value)
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


#: The help of an input file, by its name (a command may say more in ``INPUT_HELP``).
INPUT_HELP = {
    "design": "design file (.toml) or crease pattern (.fold, .dxf, .svg, .opx, .json)",
    "source": "crease pattern (.fold, .dxf, .svg, .opx, .json) or design file (.toml)",
    "pattern": "crease pattern (.fold, .dxf, .svg, .opx, .json) or design file (.toml)",
    "route": "route file (.toml): the strings' holes and the TSA",
    "task": "arm task file (.toml): targets, areas and the search's settings",
    "robot": "robot file (.toml), e.g. examples/crawler/crawler.toml",
    "sequence": "sequence file (.toml) of TSA keyframes, as sequence or crawl write it",
    "output": "output file (.fold, .dxf, .svg, .opx or .png: by its extension)",
}


def _metavar(opt: Option) -> Any:
    """What the usage line shows for an option's value: its choices, or its metavar."""
    if callable(opt.choices):
        return None  # the formatter asks for them (lazy_choices)
    if opt.choices is not None:
        return "{" + ",".join(map(str, opt.choices)) + "}"
    if opt.metavar is not None:
        return opt.metavar
    if opt.positional:
        return opt.name.upper()
    return {"mm": "MM", "deg": "DEG"}.get(opt.unit, opt.name.upper().replace("_", "-"))


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
        kwargs["action"] = "append" if opt.repeat or opt.shown == "--output" else _Once
        kwargs |= {"nargs": opt.nargs} if opt.nargs is not None else {}
        kwargs |= {"metavar": _metavar(opt)} if _metavar(opt) is not None else {}
        kwargs |= {"required": True} if opt.required and not opt.positional else {}
    if opt.positional:
        action = p.add_argument(opt.name, **kwargs)
    else:
        flags = [*([opt.short] if opt.short else []), opt.shown]
        action = p.add_argument(*flags, dest=opt.name, **kwargs)
    if callable(opt.choices):
        action.lazy_choices = opt.choices
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


def command_words(text: str, cls: type[Command]) -> str:
    """``text`` in the command's command-line words: an option's keyword as its flag
    (``hole_diameter`` -> ``--hole-diameter``, ``holes = 'none'`` -> ``--holes none``)
    and an input as its metavar (````design```` -> ``DESIGN``), where they are marked up
    as literals or are snake_case.

    >>> from origami_cad.commands import COMMANDS
    >>> command_words("use a smaller hole_diameter or holes = 'none'", COMMANDS["fabricate"])
    'use a smaller --hole-diameter or --holes none'
    >>> command_words("in/a.svg: <svg>: width = 'x' is not a length", COMMANDS["fabricate"])
    "in/a.svg: <svg>: width = 'x' is not a length"

    A message led by the argument it is about (``thickness: ...``, or after its owner,
    ``SimulationParams: friction: ...``) is led by the option instead:

    >>> command_words("FabricationParams: thickness: expected a number", COMMANDS["fabricate"])
    '--thickness: expected a number'
    """
    flags = {o.name: o.shown for o in cls.OPTIONS if o.flag != "" and not o.positional}
    names = {o.name: o.name.upper() for o in cls.OPTIONS if o.positional}
    names |= {n: n.upper() for n in cls.INPUTS}
    if cls.OUTPUT:  # as the usage shows it: -o FOLDER, -o FILE
        flags[cls.OUTPUT] = "FOLDER" if cls.OUTPUT == "folder" else "-o"

    def assigned(m: re.Match) -> str:
        return f"{flags[m[1]]} {m[2]}" if m[1] in flags else m[0]

    def word(m: re.Match) -> str:
        name, marked = m[2], bool(m[1])
        if name in flags and (marked or "_" in name):
            return flags[name]
        if name in names and marked:
            return names[name]
        return m[0]

    def argument(m: re.Match) -> str:  # "FabricationParams: thickness: " -> "--thickness: "
        return flags[m[1]] if m[1] in flags else m[0]

    def rewritten(part: str) -> str:
        if _ABOUT_A_FILE.match(part):  # a file's own keys and attributes keep their names
            return part
        part = re.sub(r"^(?:\w+: )?([a-z]\w*)(?=: )", argument, part, count=1)
        part = re.sub(r"(?<![\w-])([a-z]\w*) ?= ?['\"]?([\w.-]+)['\"]?", assigned, part)
        return re.sub(r"(``)?(?<![\w.-])([a-z][a-z0-9_]*)(?![\w-])(?(1)``)", word, part)

    return "; ".join(rewritten(part) for part in text.split("; "))


#: A message (or a part of one) about a file's contents: it begins with the file's path.
_ABOUT_A_FILE = re.compile(r"[^\s:;]*[/\\][^:;]*: |[^\s:;/]+\.[A-Za-z0-9]{1,5}: ")


def _description(cls: type[Command]) -> dict[str, str]:
    """A command's help (its docstring's first line) and description (the first two
    paragraphs), in command-line words."""
    doc = inspect.cleandoc(cls.__doc__ or "")
    parts = plain_text(command_words(doc, cls)).split("\n\n")
    # the 1st sentence: a dot ends it, but not that of "eq.", "Fig." or "Figs." or an ellipsis
    sentence_end = r"(?<!\beq)(?<!\bFig)(?<!\bFigs)(?<!\.\.)\. "
    first = re.split(sentence_end, " ".join(parts[0].split()))[0]
    first = first.removesuffix(".") if not first.endswith("...") else first
    return {"help": first, "description": "\n\n".join(parts[:2])}


def _add_output(p: argparse.ArgumentParser, cls: type[Command]) -> None:
    """``-o``: a folder, or a file (several where the command writes one result in several
    formats; the skeleton refuses a second ``-o`` of any other command)."""
    folder = cls.OUTPUT == "folder"
    action = p.add_argument(
        "-o",
        "--output",
        action="append",
        dest=cls.OUTPUT,
        required=True,
        metavar="FOLDER" if folder else "FILE",
        help=FOLDER_HELP if folder else "output file",
    )
    if not folder:
        action.lazy_help = functools.partial(_output_help, cls)


def _output_help(cls: type[Command]) -> str:
    """The help of a file ``-o``: the formats it is written in (imported when shown)."""
    formats = cls().suffixes()
    text = "output file" + (f" ({', '.join(formats)}: by its extension)" if formats else "")
    return text + ("; repeat -o to write several" if cls.OUTPUT == "outputs" else "")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``origami-cad``: one subcommand per registered command."""
    parser = _Parser(
        prog="origami-cad",
        description="Design, fold, fabricate and drive string-driven origami robots. "
        "Lengths are in millimetres and angles in degrees.",
    )
    parser.add_argument("--version", action="version", version=f"origami-cad {__version__}")
    _add_diagnostics(parser, set(), top=True)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, cls in COMMANDS.items():
        if cls.HIDDEN:
            continue
        p = sub.add_parser(name, formatter_class=_DefaultsHelp, **_description(cls))
        for arg in cls.INPUTS:
            text = getattr(cls, "INPUT_HELP", {}).get(arg, INPUT_HELP.get(arg))
            p.add_argument(arg, metavar=arg.upper(), help=text)
        taken = {f for o in cls.OPTIONS for f in (o.shown, o.short) if f}
        _add_diagnostics(p, taken, top=False)
        names = list(cls.INPUTS)
        if cls.OUTPUT:
            _add_output(p, cls)
            names.append(cls.OUTPUT)
        positional = [*names, *(o.name for o in cls.OPTIONS if o.positional)]
        names += [_add_option(p, cls, o) for o in cls.OPTIONS if o.flag != ""]
        p.set_defaults(names=names, positional=positional)
    return parser


def _words(parser: argparse.ArgumentParser) -> dict[str, tuple[list[str], dict[str, list]]]:
    """Each command's flags and the values of those with choices (``""``: the top level)."""
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    words = {}
    for name, p in [("", parser), *subs.choices.items()]:
        flags, values = [], {}
        for action in p._actions:
            flags += action.option_strings
            lazy = getattr(action, "lazy_choices", None)
            metavar = action.metavar if isinstance(action.metavar, str) else ""
            choices = lazy() if lazy else metavar[1:-1].split(",") if metavar[:1] == "{" else []
            if choices and action.option_strings:
                values[action.option_strings[-1]] = [str(c) for c in choices]
        words[name] = (flags, values)
    return words


def completion_script(shell: str, parser: argparse.ArgumentParser | None = None) -> str:
    """The shell completion of ``origami-cad`` for ``shell`` (``bash``, ``zsh``, ``fish``):
    commands, their flags and the values of flags with choices, files elsewhere."""
    words = _words(parser or build_parser())
    commands = [n for n in words if n]
    if shell == "fish":
        lines = ["complete -c origami-cad -f"]
        for name in commands:
            lines.append(f"complete -c origami-cad -n __fish_use_subcommand -a {name}")
        for name, (flags, values) in words.items():
            cond = f"__fish_seen_subcommand_from {name}" if name else "__fish_use_subcommand"
            for flag in (f for f in flags if f.startswith("--")):
                given = values.get(flag)
                more = f" -x -a '{' '.join(given)}'" if given else ""
                lines.append(f"complete -c origami-cad -n '{cond}' -l {flag[2:]}{more}")
            lines.append(f"complete -c origami-cad -n '{cond}' -F")
        return "\n".join(lines) + "\n"
    cases, values = [], []
    for name, (flags, choices) in words.items():
        label, joined = name or '""', " ".join(flags)
        cases.append(f'        {label}) opts="{joined}" ;;')
        for flag, given in choices.items():
            listed = " ".join(given)
            values.append(f'        {name}:{flag}) values="{listed}" ;;')
    script = _BASH.format(
        commands=" ".join(commands), cases="\n".join(cases), values="\n".join(values)
    )
    zsh = "autoload -U +X compinit && compinit\nautoload -U +X bashcompinit && bashcompinit\n"
    return (zsh if shell == "zsh" else "") + script


_BASH = """# origami-cad completion: eval "$(origami-cad completion bash)"
_origami_cad() {{
    local cur prev cmd word opts values
    cur="${{COMP_WORDS[COMP_CWORD]}}"
    prev="${{COMP_WORDS[COMP_CWORD-1]}}"
    cmd=""
    for word in "${{COMP_WORDS[@]:1:COMP_CWORD-1}}"; do
        case "$word" in -*) ;; *) cmd="$word"; break ;; esac
    done
    case "$cmd" in
{cases}
        *) opts="" ;;
    esac
    values=""
    case "$cmd:$prev" in
{values}
    esac
    if [[ -n "$values" ]]; then
        COMPREPLY=($(compgen -W "$values" -- "$cur"))
    elif [[ -z "$cmd" && "$cur" != -* ]]; then
        COMPREPLY=($(compgen -W "{commands}" -- "$cur"))
    elif [[ "$cur" == -* ]]; then
        COMPREPLY=($(compgen -W "$opts" -- "$cur"))
    else
        COMPREPLY=($(compgen -f -- "$cur"))
    fi
}}
complete -o filenames -o bashdefault -F _origami_cad origami-cad
"""


@register
class Completion(Command):
    """Print the shell completion script of origami-cad (bash, zsh or fish).

    Install it with one command: ``eval "$(origami-cad completion bash)"`` in ~/.bashrc,
    ``eval "$(origami-cad completion zsh)"`` in ~/.zshrc, or ``origami-cad completion
    fish > ~/.config/fish/completions/origami-cad.fish``.
    """

    NAME = "completion"
    OPTIONS = (
        Option("shell", help="the shell", choices=("bash", "zsh", "fish"), positional=True,
               required=True),
    )  # fmt: skip

    def run(self, a) -> Outputs:
        return Outputs(messages=[completion_script(a.shell).rstrip("\n")])


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
    with _diagnostics(args) as said:
        return _said(args, said)


def _show(outputs: Outputs, said: _Stderr) -> None:
    """The summary on stdout (stderr when the output is stdout), the warnings on stderr:
    the command's, and its lines starting ``warning:``, each once."""
    level = logging.getLogger("origami_cad").level
    shown = sys.stderr if _into_stdout(outputs.files) else sys.stdout
    warned = [m.removeprefix("warning: ") for m in outputs.messages if m.startswith("warning: ")]
    for line in outputs.messages if level <= logging.WARNING else ():
        if not line.startswith("warning: "):
            print(line, file=shown)
    for line in dict.fromkeys([*warned, *outputs.warnings]):
        if line not in said.said and level <= logging.WARNING:
            said.emit(logging.makeLogRecord({"msg": line, "levelname": "WARNING"}))


def _said(args: argparse.Namespace, said: _Stderr) -> int:
    cls = COMMANDS[args.command]
    try:
        outputs = _call(args)
        if interrupted():  # an interrupt a library swallowed: the outputs were not written
            raise Interrupted(interrupted())
        _show(outputs, said)
        return outputs.status
    except OrigamiCadError as exc:  # with its notes (a pattern's implausible size)
        _error(command_words("; ".join([str(exc), *getattr(exc, "__notes__", ())]), cls))
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
        if log_level(args) <= logging.DEBUG:
            traceback.print_exc(file=sys.stderr)
        _error(
            f"internal error ({type(exc).__name__}: {exc}); this is a bug in origami-cad "
            f"{__version__}, please report it with the command and its input files"
        )
        return 3


def _on_terminal() -> bool:
    """Whether stderr, where progress goes, is a terminal."""
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


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
