"""The ``origami-cad`` command. Thin: it parses arguments and calls the library.

Bad input prints one line ``origami-cad: error: ...`` and exits with code 2;
``origami-cad check`` exits with 1 when the pattern has errors.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from origami_cad import __version__
from origami_cad.errors import OrigamiCadError

__all__ = ["build_parser", "main"]


def _cmd_convert(args: argparse.Namespace) -> int:
    from origami_cad.pattern import read_pattern, write_pattern
    from origami_cad.viz import save_pattern_png

    cp = read_pattern(args.input)
    out = Path(args.output)
    if out.suffix.lower() == ".png":
        save_pattern_png(cp, out, labels=args.labels)
    else:
        write_pattern(cp, out)
    print(f"wrote {out} ({cp.n_vertices} vertices, {cp.n_edges} edges, {len(cp.faces)} panels)")
    return 0


def _cmd_check(args: argparse.Namespace) -> int:
    from origami_cad.pattern import Severity, read_pattern

    cp = read_pattern(args.input)
    problems = cp.check(angle_tolerance=args.angle_tolerance)
    print(f"{args.input}: {cp!r}")
    for p in problems:
        if p.severity != Severity.INFO or args.verbose:
            print(f"  {p}")
    errors = sum(p.severity == Severity.ERROR for p in problems)
    warnings = sum(p.severity == Severity.WARNING for p in problems)
    print(f"{errors} errors, {warnings} warnings")
    return 1 if errors else 0


def _cmd_demo(args: argparse.Namespace) -> int:
    from origami_cad.demo import run_demo

    run_demo(Path(args.output), quick=args.quick)
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``origami-cad`` (one subcommand per task)."""
    parser = argparse.ArgumentParser(
        prog="origami-cad",
        description="Design, fold, fabricate and drive string-driven origami robots. "
        "Lengths are in millimetres and angles in degrees.",
    )
    parser.add_argument("--version", action="version", version=f"origami-cad {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    p = sub.add_parser(
        "convert",
        help="convert a crease pattern between .fold, .dxf and .svg, or draw it as .png",
        description="Read a crease pattern (.fold, .dxf, .svg) and write it as .fold, .dxf, "
        ".svg or a .png picture. The output format follows the extension.",
    )
    p.add_argument("input", help="input pattern file (.fold, .dxf or .svg)")
    p.add_argument("output", help="output file (.fold, .dxf, .svg or .png)")
    p.add_argument("--labels", action="store_true", help="write panel labels on a .png")
    p.set_defaults(func=_cmd_convert)

    p = sub.add_parser(
        "check",
        help="validate a crease pattern (border, dangling creases, Maekawa, Kawasaki)",
        description="Print every problem of a crease pattern with its location: open or "
        "self-crossing border, dangling creases, non-simple panels, and Maekawa's and "
        "Kawasaki's theorems at interior vertices. Exit code 1 if there are errors.",
    )
    p.add_argument("input", help="pattern file (.fold, .dxf or .svg)")
    p.add_argument(
        "--angle-tolerance",
        type=float,
        default=1e-6,
        help="tolerance of Kawasaki's theorem, radians (default 1e-6)",
    )
    p.add_argument("-v", "--verbose", action="store_true", help="also list what was normalised")
    p.set_defaults(func=_cmd_check)

    p = sub.add_parser(
        "demo",
        help="reproduce the paper's figures end to end into one HTML report",
        description="Run every step of the pipeline on the paper's examples and write "
        "OUT/index.html with pictures, numbers and links to every file.",
    )
    p.add_argument("-o", "--output", default="out", help="output folder (default: out)")
    p.add_argument("--quick", action="store_true", help="reduced budget (for tests)")
    p.set_defaults(func=_cmd_demo)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the console script; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except OrigamiCadError as exc:
        print(f"origami-cad: error: {exc}", file=sys.stderr)
        return 2
    except (FileNotFoundError, IsADirectoryError, PermissionError, NotADirectoryError) as exc:
        name = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        print(f"origami-cad: error: {name}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("origami-cad: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
