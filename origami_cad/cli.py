"""The ``origami-cad`` command. It only parses arguments into the jobs of :mod:`origami_cad.jobs`.

Exit codes (``docs/outputs.md``): 0 success; 1 a negative answer (``check``, ``route``); 2 bad
input, one line ``origami-cad: error: ...``; 3 an internal error; 130 and 143 interrupted.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import inspect
import math
import signal
import sys
import threading
from collections.abc import Callable, Sequence
from typing import Any

from origami_cad import __version__, jobs
from origami_cad._fileio import Interrupted, handle_signals, interrupted
from origami_cad._names import one_line
from origami_cad.errors import OptionsError, OrigamiCadError

__all__ = ["build_parser", "main"]


def _finite(text: str) -> float:
    """argparse type: a finite number (NaN and infinities are refused)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


def _ids(text: str) -> list[int]:
    """argparse type: comma-separated servo IDs."""
    if not all(v.strip().isdigit() for v in text.split(",")):
        raise argparse.ArgumentTypeError(f"expected comma-separated IDs, got {text!r}")
    return [int(v) for v in text.split(",")]


def _blocker(text: str) -> tuple[int, float]:
    """argparse type: EDGE:DEGREES (60 degrees when only the edge is given)."""
    edge, _, angle = text.partition(":")
    if not edge.strip().isdigit():
        raise argparse.ArgumentTypeError(f"expected EDGE:DEGREES, got {text!r}")
    return int(edge), _finite(angle or "60")


def _display(name: str, *args):
    """A display of :mod:`origami_cad.viz.console`, imported only when a job runs (fast --help)."""
    return getattr(importlib.import_module("origami_cad.viz.console"), name)(*args)


_BARS = {"design-arm": "CMA-ES generations", "simulate": "simulating", "plan-route": "candidates"}
_PROGRESS = {k: lambda v=v: _display("progress_bar", v) for k, v in _BARS.items()}
_PROGRESS["drive"] = lambda: _display("servo_table")


def _call(args: argparse.Namespace) -> jobs.Outputs:
    """Call the command's job with the arguments named like its parameters."""
    if args.command == "part":
        from origami_cad.parts import parse_part_options, parts_listing

        if args.list or not args.name:
            return jobs.Outputs(messages=[parts_listing()])
        if not args.folder:
            raise OptionsError("give the output folder with -o DIR")
        args.params = parse_part_options(args.params)
    job = _COMMANDS[args.command][0]
    names = inspect.signature(job).parameters
    if any(p.kind == p.VAR_KEYWORD for p in names.values()):  # takes every option of its own
        names = {**names, **dict.fromkeys(args.option_names)}
    kwargs = {n: getattr(args, n) for n in names if getattr(args, n, None) is not None}
    display, progress = _PROGRESS.get(args.command, lambda: (None, None))()
    kwargs |= {"progress": progress} if "progress" in names else {}
    if "echo" in names:
        kwargs["echo"] = lambda line: print(line, flush=True)
    with display or contextlib.nullcontext():
        return job(**kwargs)


def _demo(folder: str = "out", quick: bool = False) -> jobs.Outputs:
    """Reproduce the paper's figures end to end into one HTML report (FOLDER/index.html)."""
    from origami_cad.demo import run_demo

    return jobs.Outputs(files=[run_demo(folder, quick=quick)])


_FOLDER = "output folder; only this command's files are written into it, all else is kept"
_FLAG, _SIZED = {"action": "store_true"}, "convert fold fabricate route simulate plan-route"

# (commands, option, argparse keywords): every option of every command
_OPTIONS: list[tuple[str, str, dict[str, Any]]] = [
    ("convert pattern", "--labels", {**_FLAG, "help": "panel labels on a .png"}),
    ("check", "--angle-tolerance", {"type": _finite, "help": "Kawasaki's theorem, rad"}),
    ("check", "--verbose", {**_FLAG, "help": "also list what was normalised"}),
    (_SIZED, "--unit", {"help": "unit of an imported file: mm, cm, m, in, ft, pt, px or MM"}),
    (_SIZED, "--scale", {"type": _finite, "help": "multiply an imported pattern's size"}),
    (_SIZED, "--width", {"type": _finite, "help": "scale an imported pattern to this width, mm"}),
    ("fold", "--ratio", {"type": _finite, "help": "fold ratio p in [0, 1]"}),
    ("fold", "--frames", {"type": int, "help": "states from p = 0 to --ratio"}),
    ("design-arm", "--runs", {"type": int, "help": "override the task's [search] runs"}),
    ("design-arm plan-route", "--seed", {"type": int, "help": "seed (overrides [search])"}),
    ("design-arm plan-route", "--scheduler", {"metavar": "ADDR", "help": "Dask scheduler"}),
    ("design-arm", "--max-generations", {"type": int, "help": "override [search] value"}),
    ("plan-route", "--tsa", {"help": "ring, or onboard:PANEL (the TSA on that panel)"}),
    ("plan-route", "--strings", {"type": int, "help": "strings the TSA twists"}),
    ("plan-route", "--target-p", {"type": _finite, "help": "fold ratio (default: eq. 6 limit)"}),
    ("plan-route", "--candidates", {"type": int, "help": "beam width of the search"}),
    ("plan-route", "--budget", {"metavar": "TURNS[,NMM]", "help": "turn [and torque] budget"}),
    ("fabricate", "--bias", {"type": _finite, "help": "inner bias b, mm"}),
    ("fabricate", "--theta-max", {"type": _finite, "help": "theta_max, deg (gives b, eq. 6)"}),
    ("fabricate", "--p-max", {"type": _finite, "help": "p_max in [0, 1] (gives b, eq. 6)"}),
    ("fabricate", "--height", {"type": _finite, "help": "panel height h, mm"}),
    ("fabricate", "--thickness", {"type": _finite, "help": "crease layer t, mm"}),
    ("fabricate", "--shell", {"type": _finite, "help": "shell wall s, mm"}),
    ("fabricate", "--midlayer-bias", {"type": _finite, "help": "mid-layer inset m, mm"}),
    ("fabricate", "--border-margin", {"type": _finite, "help": "border inset, mm"}),
    ("fabricate", "--hole-diameter", {"type": _finite, "help": "hole diameter, mm"}),
    ("fabricate", "--holes", {"choices": ("auto", "pattern", "none"), "help": "where holes go"}),
    ("fabricate", "--hole", {"nargs": 2, "type": _finite, "action": "append",
                             "metavar": ("X", "Y"), "help": "a hole at X Y, mm; repeat"}),
    ("fabricate", "--renders", {**_FLAG, "help": "also render the assembled parts"}),
    ("fabricate", "--slicer", {"choices": ("prusa", "bambu", "orca"),
                               "help": "the slicer print.3mf is laid out for"}),
    ("fabricate", "--bed", {"nargs": 2, "type": _finite, "metavar": ("X", "Y"),
                            "help": "print bed, mm: a larger sheet is refused"}),
    ("simulate", "--steps", {"type": int, "help": "actuation steps over the route's turns"}),
    ("simulate", "--blocker", {"action": "append", "metavar": "EDGE:DEG", "type": _blocker,
                               "dest": "blockers", "help": "stop crease EDGE at DEG deg (repeat)"}),
    ("simulate", "--gravity", {"type": _finite, "help": "gravity along -z, mm/s^2"}),
    ("simulate", "--ground", {"type": _finite, "help": "height of a ground plane, mm"}),
    ("simulate", "--friction", {"type": _finite, "help": "Coulomb friction coefficient"}),
    ("simulate", "--free", {**_FLAG, "help": "hold no panel (needs --gravity, --ground)"}),
    ("sequence", "--keyframes", {"nargs": "+", "required": True, "metavar": "T:P[,P...]",
                                 "help": "time s : fold ratio (one per route)"}),
    ("sequence", "--more-routes", {"nargs": "+", "metavar": "ROUTE", "help": "more TSAs"}),
    ("sequence", "--model", {"choices": ("dcqc", "simulation"), "help": "string model"}),
    ("sequence", "--rate", {"type": _finite, "help": "command rate, Hz"}),
    ("sequence", "--repeat", {"type": int, "help": "cycles"}),
    ("sequence", "--points", {"type": int, "help": "mapping points besides the keyframes"}),
    ("sequence", "--fixed-panel", {"help": "hold this panel in every route"}),
    ("arm-scene", "--steps", {"type": int, "help": "equal TSA steps (default: by take-up)"}),
    ("robot", "--ratio", {"type": _finite, "help": "fold ratio p of robot.step"}),
    ("robot", "--no-renders", {"action": "store_false", "dest": "renders", "help": "no render"}),
    ("crawl", "--cycles", {"type": int, "help": "gait cycles to simulate"}),
    ("crawl", "--steps", {"type": int, "help": "quasi-static steps between keyframes"}),
    ("crawl", "--reverse", {**_FLAG, "help": "play the gait backwards"}),
    ("crawl", "--friction", {"type": _finite, "help": "Coulomb coefficient (robot file's)"}),
    ("emulate drive", "--protocol", {"help": "servo bus: a name of origami_cad.drive.BUSES"}),
    ("emulate sequence", "--ids", {"type": _ids, "help": "servo IDs, e.g. 1,2 (one per route)"}),
    ("emulate", "--seconds", {"type": _finite, "help": "0: until Ctrl-C"}),
    ("drive", "--port", {"help": "serial port of the servos"}),
    ("drive", "--baudrate", {"type": int, "help": "bits per second"}),
    ("drive", "--dry-run", {**_FLAG, "help": "start the emulator and drive it"}),
    ("drive", "--speed", {"type": _finite, "help": "dry-run time acceleration"}),
    ("drive", "--load-scale", {"type": _finite, "help": "dry run: loads x this"}),
    ("drive", "--log", {"help": "CSV log, written as it runs"}),
    ("drive", "--plot", {"help": "also a PNG of commanded and measured turns"}),
    ("part", "name", {"nargs": "?", "help": "part name"}),
    ("part", "--list", {**_FLAG, "help": "list the parts and their parameters"}),
    ("part", "--pattern", {"help": "design or pattern file the part is made for"}),
    ("part", "--panel", {"help": "panel label (tsa-module)"}),
    ("part", "--crease", {"type": int, "help": "crease edge index (blocker)"}),
    ("part demo", "--output", {"dest": "folder", "help": _FOLDER}),
    ("demo", "--quick", {**_FLAG, "help": "reduced budget (for tests)"}),
    ("mjcf", "routes", {"nargs": "*", "metavar": "ROUTE", "help": "route files (a robot: none)"}),
]  # fmt: skip


# name: (the job, whose docstring is the help; positional arguments, named like the job's
# parameters; the parameter -o gives: None, "output", "outputs" (repeatable) or "folder")
_COMMANDS: dict[str, tuple[Callable[..., jobs.Outputs], tuple[str, ...], str | None]] = {
    "convert": (jobs.run_convert, ("source", "output"), None),
    "check": (jobs.run_check, ("source",), None),
    "pattern": (jobs.run_pattern, ("design",), "outputs"),
    "fold": (jobs.run_fold, ("design",), "output"),
    "tg": (jobs.run_tg, ("design",), "output"),
    "design-arm": (jobs.run_design_arm, ("task",), "folder"),
    "fabricate": (jobs.run_fabricate, ("design",), "folder"),
    "route": (jobs.run_route, ("design", "route"), "folder"),
    "plan-route": (jobs.run_plan_route, ("pattern",), "output"),
    "simulate": (jobs.run_simulate, ("pattern", "route"), "folder"),
    "sequence": (jobs.run_sequence, ("design", "route"), "output"),
    "arm-scene": (jobs.run_arm_scene, ("task", "design", "route"), "folder"),
    "robot": (jobs.run_robot, ("robot",), "folder"),
    "crawl": (jobs.run_crawl, ("robot",), "folder"),
    "mjcf": (jobs.run_mjcf, ("source",), "output"),
    "emulate": (jobs.run_emulate, (), None),
    "drive": (jobs.run_drive, ("sequence",), None),
    "part": (jobs.run_part, (), None),
    "demo": (_demo, (), None),
}


class _Help(argparse.HelpFormatter):
    """Help whose defaults are read from the jobs and their parameter classes, not repeated."""

    def _get_help_string(self, action: argparse.Action) -> str:
        command = getattr(action, "command", None)
        default = jobs.parameter_default(_COMMANDS[command][0], action.dest) if command else None
        hidden = default is None or default is False or default is inspect.Parameter.empty
        return action.help or "" if hidden else f"{action.help or ''} (default {default})"


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``origami-cad`` (one subcommand per job)."""
    parser = argparse.ArgumentParser(
        prog="origami-cad",
        description="Design, fold, fabricate and drive string-driven origami robots. "
        "Lengths are in millimetres and angles in degrees.",
    )
    parser.add_argument("--version", action="version", version=f"origami-cad {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, (job, positional, output) in _COMMANDS.items():
        doc = inspect.cleandoc(job.__doc__ or "").split("\n\n")
        text = {"help": doc[0].splitlines()[0], "description": "\n\n".join(doc[:2])}
        p = sub.add_parser(name, formatter_class=_Help, **text)
        for arg in positional:
            p.add_argument(arg)
        if output:
            many = {"action": "append"} if output == "outputs" else {}
            what = _FOLDER if output == "folder" else "output file (format by extension)"
            p.add_argument("-o", "--output", dest=output, required=True, help=what, **many)
        p.set_defaults(option_names=[])
    for commands, option, kwargs in _OPTIONS:
        for name in commands.split():
            flags = [*{"--output": ["-o"], "--verbose": ["-v"]}.get(option, []), option]
            action = sub.choices[name].add_argument(*flags, **kwargs)
            action.command = name
            sub.choices[name].get_default("option_names").append(action.dest)
    sub.choices["part"].set_defaults(params=[])  # its own --name value pairs, from main()
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script; returns the exit code."""
    parser = build_parser()
    try:
        args, extra = parser.parse_known_args(argv)
        if extra and args.command != "part":
            parser.error(f"unrecognized arguments: {' '.join(extra)}")
    except SystemExit as exc:  # argparse's usage errors: exit code 2, returned like the rest
        if exc.code in (0, None):
            raise  # --help, --version
        return int(exc.code)
    if extra:
        args.params = extra  # the part's own --name value parameters
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
        for line in outputs.messages:
            print(line)
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
        if interrupted():  # the interrupt surfaced as another error (e.g. inside an import)
            return _interrupted()
        _error(
            f"internal error ({type(exc).__name__}: {exc}); this is a bug in origami-cad "
            f"{__version__}, please report it with the command and its input files"
        )
        return 3


def _interrupted() -> int:
    signum = interrupted() or signal.SIGINT
    word = "terminated" if signum == signal.SIGTERM else "interrupted"
    print(f"origami-cad: {word}; nothing more was written", file=sys.stderr)
    return 128 + signum


def _error(message: str) -> None:
    """Print one error line; control characters of user-supplied names are escaped."""
    print(f"origami-cad: error: {one_line(message)}", file=sys.stderr)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
