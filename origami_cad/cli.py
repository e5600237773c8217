"""The ``origami-cad`` command. Thin: it parses arguments and calls the library.

Bad input prints one line ``origami-cad: error: ...`` and exits with code 2;
``origami-cad check`` exits with 1 when the pattern has errors.
"""

from __future__ import annotations

import argparse
import inspect
import sys
from collections.abc import Sequence
from pathlib import Path

from origami_cad import __version__
from origami_cad.errors import DesignError, OrigamiCadError

__all__ = ["build_parser", "main"]


def _cmd_convert(args: argparse.Namespace) -> int:
    from origami_cad.pattern import read_pattern

    cp = read_pattern(args.input)
    out = Path(args.output)
    _write_pattern_any(cp, out, labels=args.labels)
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


def _write_pattern_any(cp, out: Path, labels: bool = False) -> None:
    from origami_cad.pattern import write_pattern
    from origami_cad.viz import save_pattern_png

    if out.suffix.lower() == ".png":
        save_pattern_png(cp, out, labels=labels)
    else:
        write_pattern(cp, out)


def _cmd_pattern(args: argparse.Namespace) -> int:
    from origami_cad.pattern.design import load_pattern_source

    design = load_pattern_source(args.design)
    cp = design.pattern
    for out in args.output:
        _write_pattern_any(cp, Path(out), labels=args.labels)
        print(f"wrote {out}")
    for note in design.tg.notes if design.tg else ():
        print(f"note: {note}")
    print(repr(cp))
    return 0


def _cmd_fold(args: argparse.Namespace) -> int:
    import numpy as np

    from origami_cad.kinematics.folding import fold_sequence
    from origami_cad.pattern import folded_frame, write_fold
    from origami_cad.pattern.design import load_pattern_source
    from origami_cad.viz.render3d import render_folded, render_folding_gif

    if not 0.0 <= args.ratio <= 1.0:
        raise DesignError(f"--ratio must lie in [0, 1], got {args.ratio}")
    if args.frames < 1:
        raise DesignError(f"--frames must be >= 1, got {args.frames}")
    out = Path(args.output)
    suffix = out.suffix.lower()
    if suffix not in (".fold", ".png", ".gif"):
        raise DesignError(f"{out}: the folded state is written as .fold, .png or .gif")
    design = load_pattern_source(args.design)
    frames = args.frames if args.frames > 1 or suffix != ".gif" else 30
    ratios = np.linspace(0.0, args.ratio, frames) if frames > 1 else [args.ratio]
    states = fold_sequence(design, ratios)
    cp = design.pattern
    if suffix == ".fold":
        write_fold(
            cp,
            out,
            frames=[folded_frame(s.coords, s.fold_angles, f"p = {s.p:.4g}") for s in states],
        )
    elif suffix == ".png":
        render_folded(cp, states[-1].coords, out, title=f"p = {args.ratio:g}")
    else:
        render_folding_gif(cp, [s.coords for s in states], out)
    print(
        f"wrote {out} ({len(states)} state{'s' if len(states) > 1 else ''}, p up to {args.ratio:g})"
    )
    return 0


def _cmd_tg(args: argparse.Namespace) -> int:
    from origami_cad.pattern.design import load_design
    from origami_cad.viz.tg_plot import save_tg_png

    design = load_design(args.design)
    if design.tg is None:
        raise DesignError(f"{args.design}: kind {design.kind!r} has no transition graph")
    save_tg_png(design.tg, args.output)
    print(f"wrote {args.output}")
    return 0


def _cmd_design_arm(args: argparse.Namespace) -> int:
    import dataclasses
    import time

    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn

    from origami_cad.design import design_arm, load_task, write_design_outputs

    task, settings = load_task(args.task)
    changes = {
        k: v
        for k, v in (
            ("runs", args.runs),
            ("seed", args.seed),
            ("max_generations", args.max_generations),
        )
        if v is not None
    }
    settings = dataclasses.replace(settings, **changes)
    t0 = time.perf_counter()
    with Progress(
        TextColumn("run {task.fields[run]:>2}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("best f = {task.fields[best]}"),
        transient=False,
    ) as bar:
        ids = [
            bar.add_task("", total=settings.max_generations, run=r, best="-")
            for r in range(settings.runs)
        ]

        def progress(run: int, generation: int, best: float) -> None:
            bar.update(ids[run], completed=generation, best=f"{best:.3f}")

        results = design_arm(task, settings, progress=progress)
        for i in ids:
            bar.update(i, total=bar.tasks[i].completed or 1)
    seconds = time.perf_counter() - t0
    paths = write_design_outputs(results, task, settings, args.output, seconds=seconds)
    best = results[0]
    print(
        f"best of {settings.runs} runs: run {best.run}, f = {best.fitness:.4f}, "
        f"|T_e(0) - P_start| = {best.terms['d_start_mm']:.3g} mm, "
        f"|T_e(pi) - P_end| = {best.terms['d_end_mm']:.3g} mm, N = "
        f"{best.terms['improper_states']} ({seconds:.1f} s)"
    )
    for path in paths.values():
        print(f"wrote {path}")
    return 0


def _cmd_fabricate(args: argparse.Namespace) -> int:
    import math

    from origami_cad._fileio import atomic_directory
    from origami_cad.fabrication import (
        FabricationParams,
        bias_for_theta_max,
        fabricate,
        write_fabrication,
    )
    from origami_cad.pattern.design import load_pattern_source
    from origami_cad.viz.fabrication_plots import save_panels_png

    holes: object = args.holes
    if args.hole:
        holes = [tuple(p) for p in args.hole]
    bias = args.bias
    given = [v is not None for v in (args.bias, args.theta_max, args.p_max)]
    if sum(given) > 1:
        raise DesignError("give only one of --bias, --theta-max and --p-max")
    if args.theta_max is not None:
        bias = bias_for_theta_max(math.radians(args.theta_max), args.height, args.thickness)
    elif args.p_max is not None:
        bias = bias_for_theta_max(args.p_max * math.pi, args.height, args.thickness)
    params = FabricationParams(
        bias=3.0 if bias is None else bias,
        height=args.height,
        thickness=args.thickness,
        shell=args.shell,
        midlayer_bias=args.midlayer_bias,
        border_margin=args.border_margin,
        hole_diameter=args.hole_diameter,
        holes=holes,
    )
    design = load_pattern_source(args.design)
    fab = fabricate(design, params)
    with atomic_directory(args.output) as tmp:
        write_fabrication(fab, tmp)
        save_panels_png(fab, tmp / "panels.png")
    report = fab.report()
    print(
        f"{report['panels']} panels, {len(fab.holes)} holes; theta_max = "
        f"{report['theta_max_deg']:.1f} deg, p_max = {100 * report['p_max']:.1f} %; "
        f"mass {report['total_mass_g']:.1f} g"
    )
    for w in fab.warnings:
        print(f"warning: {w}")
    print(
        f"wrote {args.output}/: infills.stl midlayers.stl shells.stl creases.stl "
        "assembly.step print.3mf fabrication.json panels.png"
    )
    return 0


def _cmd_route(args: argparse.Namespace) -> int:

    from origami_cad._fileio import atomic_directory
    from origami_cad.pattern.design import load_pattern_source
    from origami_cad.strings import load_route, simulate_dcqc
    from origami_cad.viz.strings_plots import write_route_outputs

    design = load_pattern_source(args.design)
    route = load_route(args.route, design.pattern)
    result = simulate_dcqc(design, route)
    with atomic_directory(args.output) as tmp:
        write_route_outputs(design.pattern, route, result, tmp)
    for v in result.violations + result.cutting:
        print(f"warning: {v}")
    state = "final" if result.valid else "INVALID routing"
    print(
        f"{state}: p = {result.final['p']:.4f} after {result.final['turns']:.2f} turns; "
        f"{result.reason}"
    )
    print(f"wrote {args.output}/: dcqc.json dcqc.png route.png route_folded.png")
    return 0 if result.valid else 1


def _parse_ids(text: str) -> list[int]:
    try:
        ids = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise DesignError(f"--ids must be comma-separated servo IDs, got {text!r}") from None
    if not ids or any(not 0 <= i <= 252 for i in ids):
        raise DesignError(f"--ids must be servo IDs in 0..252, got {text!r}")
    return ids


def _cmd_emulate(args: argparse.Namespace) -> int:
    import time

    from origami_cad.drive import DynamixelEmulator, SerialEmulator

    ids = _parse_ids(args.ids)
    emu = DynamixelEmulator(ids) if args.protocol == "dynamixel" else SerialEmulator(ids)
    with emu:
        print(f"{args.protocol} emulator with servos {ids} on {emu.port}", flush=True)
        print("connect with --port " + emu.port + "; Ctrl-C to stop", flush=True)
        deadline = time.monotonic() + args.seconds if args.seconds else None
        while deadline is None or time.monotonic() < deadline:
            time.sleep(0.1)
    return 0


def _cmd_drive(args: argparse.Namespace) -> int:
    import contextlib

    from rich.live import Live
    from rich.table import Table as RichTable

    from origami_cad.drive import DynamixelBus, DynamixelEmulator, SerialBus, SerialEmulator
    from origami_cad.drive.sequence import check_time_scale, load_sequence, run_sequence
    from origami_cad.viz.drive_plots import save_drive_png

    seq = load_sequence(args.sequence)
    if not args.dry_run and not args.port:
        raise DesignError("give --port PORT, or --dry-run to use the emulator")
    scale = check_time_scale(args.speed, "--speed") if args.dry_run else 1.0
    with contextlib.ExitStack() as stack:
        port = args.port
        if args.dry_run:
            emu = (
                DynamixelEmulator(seq.ids, time_scale=scale)
                if args.protocol == "dynamixel"
                else SerialEmulator(seq.ids)
            )
            port = stack.enter_context(emu).port
        limits = {t.dxl_id: t.max_turns for t in seq.tsas}
        if args.protocol == "dynamixel":
            bus = DynamixelBus(
                port,
                args.baudrate,
                seq.ids,
                max_turns=limits,
                current_limit_ma=seq.current_limit,
                profile_velocity=0,
            )
        else:
            bus = SerialBus(
                port, args.baudrate, seq.ids, max_turns=limits, current_limit_ma=seq.current_limit
            )
        stack.enter_context(bus)
        names = {t.dxl_id: t.name for t in seq.tsas}

        def table(t: float, targets, state) -> RichTable:
            tab = RichTable(title=f"t = {t:6.2f} s of {seq.cycle * seq.repeat:g} s")
            for col in ("servo", "target turns", "measured turns", "current mA"):
                tab.add_column(col, justify="right")
            for i in seq.ids:
                tab.add_row(
                    f"{i} {names[i]}",
                    f"{targets[i]:.3f}",
                    f"{state[i][0]:.3f}",
                    f"{state[i][1]:.0f}",
                )
            return tab

        with Live(refresh_per_second=8, transient=True) as live:
            rows = run_sequence(
                seq,
                bus,
                args.log,
                time_scale=scale,
                progress=lambda t, tg, st: live.update(table(t, tg, st)),
            )
    if args.plot:
        save_drive_png(rows, args.plot, names)
    lag = max(abs(r["target_turns"] - r["measured_turns"]) for r in rows)
    print(
        f"ran {seq.repeat} x {seq.cycle:g} s on servos {seq.ids}"
        f"{' (dry run)' if args.dry_run else ''}: {len(rows)} readings, largest lag "
        f"{lag:.3f} turns"
    )
    for path in (args.log, args.plot):
        if path:
            print(f"wrote {path}")
    return 0


def _part_params(func) -> dict[str, inspect.Parameter]:
    skip = {"fab", "panel", "crease", "tsa", "body", "centre", "angles"}
    return {n: p for n, p in inspect.signature(func).parameters.items() if n not in skip}


def _cmd_part(args: argparse.Namespace) -> int:
    from parts import PARTS

    if args.list or not args.name:
        for name, func in PARTS.items():
            doc = (func.__doc__ or "").strip().splitlines()[0]
            print(f"{name}: {doc}")
            for pname, p in _part_params(func).items():
                print(f"    --{pname.replace('_', '-')} (default {p.default!r})")
        return 0
    if args.name not in PARTS:
        raise DesignError(f"unknown part {args.name!r} (known: {', '.join(PARTS)})")
    if not args.output:
        raise DesignError("give the output folder with -o DIR")
    func = PARTS[args.name]
    known = _part_params(func)
    kwargs: dict = {}
    extra = list(args.params)
    while extra:
        key = extra.pop(0)
        if not key.startswith("--") or not extra:
            raise DesignError(f"expected --name value pairs after the part name, got {key!r}")
        name = key[2:].replace("-", "_")
        value = extra.pop(0)
        if name not in known:
            raise DesignError(
                f"part {args.name} has no parameter --{key[2:]} (see origami-cad part --list)"
            )
        default = known[name].default
        try:
            kwargs[name] = type(default)(value) if default is not None else value
        except ValueError:
            raise DesignError(
                f"--{key[2:]}: expected a {type(default).__name__}, got {value!r}"
            ) from None
    if args.pattern:
        from origami_cad.fabrication import fabricate
        from origami_cad.pattern.design import load_pattern_source

        fab = fabricate(load_pattern_source(args.pattern))
        if args.name == "blocker":
            if args.crease is None:
                raise DesignError("the blocker needs --crease EDGE with --pattern")
            kwargs.update(fab=fab, crease=args.crease)
        elif args.name == "tsa-module":
            if not args.panel:
                raise DesignError("the TSA module needs --panel LABEL with --pattern")
            kwargs.update(fab=fab, panel=args.panel)
    part = func(**kwargs)
    from origami_cad.fabrication.export import export_part

    paths = export_part(part, Path(args.output), args.name)
    print(
        f"{args.name}: volume {part.volume / 1000:.2f} cm3; wrote "
        + ", ".join(str(p) for p in paths)
    )
    return 0


def _cmd_simulate(args: argparse.Namespace) -> int:
    import json

    from rich.progress import Progress

    from origami_cad._fileio import atomic_directory
    from origami_cad.pattern import folded_frame, write_fold
    from origami_cad.pattern.design import load_pattern_source
    from origami_cad.simulation import SimulationParams, simulate
    from origami_cad.strings import load_route
    from origami_cad.viz.render3d import render_folding_gif

    if args.steps is not None and args.steps < 1:
        raise DesignError(f"--steps must be >= 1, got {args.steps}")
    design = load_pattern_source(args.pattern)
    cp = design.pattern
    route = load_route(args.route, cp)
    limits = {}
    for item in args.blocker or []:
        edge, _, angle = item.partition(":")
        try:
            limits[int(edge)] = float(angle or 60.0)
        except ValueError:
            raise DesignError(f"--blocker expects EDGE:DEGREES, got {item!r}") from None
    if args.friction < 0:
        raise DesignError(f"--friction must be >= 0, got {args.friction:g}")
    params = SimulationParams(gravity=args.gravity, ground=args.ground, friction=args.friction)
    with Progress(transient=True) as bar:
        task = bar.add_task("simulating", total=None)
        result = simulate(
            cp,
            route,
            params,
            steps=args.steps,
            fold_limits=limits or None,
            progress=lambda k, n: bar.update(task, completed=k, total=n),
            free=args.free,
        )
    with atomic_directory(args.output) as tmp:
        frames = [
            folded_frame(x, s["fold_angles_deg"], f"theta_s = {s['theta_s_deg']:.0f} deg")
            for x, s in zip(result.states, result.steps, strict=True)
        ]
        write_fold(cp, tmp / "states.fold", frames=frames)
        with open(tmp / "simulation.json", "w", encoding="utf-8") as fh:
            json.dump(result.to_dict(), fh, indent=1)
        every = max(1, len(result.states) // 40)
        render_folding_gif(cp, [*result.states[::every], result.states[-1]], tmp / "fold.gif")
    last = result.steps[-1]
    print(
        f"{len(result.steps)} equilibrium states up to {last['turns']:.2f} TSA turns; "
        f"{result.reason}"
    )
    print(
        f"string tensions {', '.join(f'{t:.3g}' for t in last['tensions_N'])} N, "
        f"TSA torque {last['tsa_torque_Nmm']:.3g} N mm"
    )
    print(f"wrote {args.output}/: states.fold simulation.json fold.gif")
    return 0


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
        "pattern",
        help="compute the crease pattern of a design file (TG, Miura) and write it",
        description="Compute the crease pattern of a design file (.toml: kind "
        "transition-graph, miura or file) and write it as .fold, .dxf, .svg or .png.",
    )
    p.add_argument("design", help="design file (.toml) or pattern file")
    p.add_argument(
        "-o",
        "--output",
        action="append",
        required=True,
        help="output file(s), .fold/.dxf/.svg/.png; repeat for several",
    )
    p.add_argument("--labels", action="store_true", help="write panel labels on a .png")
    p.set_defaults(func=_cmd_pattern)

    p = sub.add_parser(
        "fold",
        help="fold a design or pattern rigidly to a fold ratio (FOLD frames, PNG, GIF)",
        description="Fold a design (.toml) or a degree-4 pattern (.fold/.dxf/.svg) rigidly. "
        ".fold: the flat pattern plus folded frames (file_frames, 3D mm, fold angles in "
        "degrees); .png: a render of the final state; .gif: an animation from p = 0.",
    )
    p.add_argument("design", help="design file (.toml) or pattern file")
    p.add_argument("--ratio", type=float, default=0.5, help="fold ratio p = theta/pi in [0, 1]")
    p.add_argument(
        "--frames",
        type=int,
        default=1,
        help="number of states from p = 0 to --ratio (default 1: only --ratio; 30 for a .gif)",
    )
    p.add_argument("-o", "--output", required=True, help="folded.fold, folded.png or folded.gif")
    p.set_defaults(func=_cmd_fold)

    p = sub.add_parser(
        "tg",
        help="plot the transition graph of a design at several fold ratios",
        description="Plot the TG chain at p = 0, 0.25, 0.5, 0.75, 1 and the path of T_e.",
    )
    p.add_argument("design", help="design file (.toml) of kind transition-graph or miura")
    p.add_argument("-o", "--output", required=True, help="output .png")
    p.set_defaults(func=_cmd_tg)

    p = sub.add_parser(
        "design-arm",
        help="search origami robotic arms with CMA-ES (eq. 5), ten independent runs",
        description="Design an origami robotic arm whose tip passes the task's points in "
        "order while it folds from p = 0 to 1, avoiding obstacles. Writes results.json, "
        "best.toml (a design file), trajectories.png and convergence.png.",
    )
    p.add_argument("task", help="arm task file (.toml, see examples/arm_task.toml)")
    p.add_argument("-o", "--output", required=True, help="output folder")
    p.add_argument("--runs", type=int, help="override [search] runs")
    p.add_argument("--seed", type=int, help="override [search] seed")
    p.add_argument("--max-generations", type=int, help="override [search] max_generations")
    p.set_defaults(func=_cmd_design_arm)

    p = sub.add_parser(
        "fabricate",
        help="dual-material printable structure: four STLs, a STEP assembly and a 3MF",
        description="Build the wrapping-based structure of a design or pattern (PLA infills "
        "and mid-layers, TPU shells and creases) as exact B-rep solids and write infills.stl, "
        "midlayers.stl, shells.stl, creases.stl, assembly.step, print.3mf (PLA on extruder 1, "
        "TPU on extruder 2), fabrication.json and panels.png into OUT. Lengths in mm.",
    )
    p.add_argument("design", help="design file (.toml) or pattern file (.fold/.dxf/.svg)")
    p.add_argument("-o", "--output", required=True, help="output folder (replaced atomically)")
    p.add_argument("--bias", type=float, help="inner bias b, mm (default 3)")
    p.add_argument("--theta-max", type=float, help="target theta_max in degrees (gives b, eq. 6)")
    p.add_argument("--p-max", type=float, help="target p_max in [0, 1] (gives b, eq. 6)")
    p.add_argument("--height", type=float, default=2.2, help="panel height h, mm (default 2.2)")
    p.add_argument(
        "--thickness",
        type=float,
        default=0.4,
        help="crease/mid-layer thickness t, mm (default 0.4)",
    )
    p.add_argument("--shell", type=float, default=0.8, help="shell wall s, mm (default 0.8)")
    p.add_argument(
        "--midlayer-bias", type=float, default=0.5, help="extra mid-layer inset m, mm (default 0.5)"
    )
    p.add_argument(
        "--border-margin",
        type=float,
        default=0.0,
        help="inset from border and cut edges, mm (default 0)",
    )
    p.add_argument("--hole-diameter", type=float, default=2.0, help="hole diameter, mm")
    p.add_argument(
        "--holes",
        choices=("auto", "pattern", "none"),
        default="auto",
        help="auto: one per panel at its pole of inaccessibility; pattern: the "
        "pattern's own holes; none",
    )
    p.add_argument(
        "--hole",
        nargs=2,
        type=float,
        action="append",
        metavar=("X", "Y"),
        help="a hole at X Y (mm); repeat; replaces --holes",
    )
    p.set_defaults(func=_cmd_fabricate)

    p = sub.add_parser(
        "route",
        help="route strings through panel holes and simulate the DCQC folding a TSA produces",
        description="Thread the route file's strings through panel holes (DCQC side rule), "
        "turn the TSA step by step and solve the quasi-static fold ratio. Writes dcqc.json, "
        "dcqc.png (p against turns), route.png and route_folded.png. Exit code 1 when the "
        "routing never folds the structure.",
    )
    p.add_argument("design", help="design file (.toml) or pattern file")
    p.add_argument("route", help="route file (.toml, see examples/miura_route.toml)")
    p.add_argument("-o", "--output", required=True, help="output folder (replaced atomically)")
    p.set_defaults(func=_cmd_route)

    p = sub.add_parser(
        "emulate",
        help="emulate servos on a pseudo-terminal (Dynamixel Protocol 2.0 or the serial protocol)",
        description="Open a pseudo-terminal, print its path and answer as real servos would, "
        "until Ctrl-C (or --seconds).",
    )
    p.add_argument("--protocol", choices=("dynamixel", "serial"), default="dynamixel")
    p.add_argument("--ids", default="1", help="comma-separated servo IDs, e.g. 1,2,3,4")
    p.add_argument("--seconds", type=float, default=0.0, help="stop after this long (0: never)")
    p.set_defaults(func=_cmd_emulate)

    p = sub.add_parser(
        "drive",
        help="run a TSA motion sequence on servos (or the emulator with --dry-run)",
        description="Run SEQUENCE.toml: keyframes of fold ratio, contraction or turns per TSA, "
        "interpolated, with a live display of targets, positions and currents, every command "
        "and reading logged to CSV. Torque goes off on exit, error and Ctrl-C.",
    )
    p.add_argument("sequence", help="sequence file (.toml, see examples/crawler_gait.toml)")
    p.add_argument("--port", help="serial port of the servos")
    p.add_argument("--protocol", choices=("dynamixel", "serial"), default="dynamixel")
    p.add_argument("--baudrate", type=int, default=57600)
    p.add_argument("--dry-run", action="store_true", help="start the emulator and drive it")
    p.add_argument(
        "--speed", type=float, default=8.0, help="time acceleration of a dry run (default 8)"
    )
    p.add_argument("--log", default="drive_log.csv", help="CSV log (default drive_log.csv)")
    p.add_argument("--plot", help="also save a PNG of commanded and measured turns")
    p.set_defaults(func=_cmd_drive)

    p = sub.add_parser(
        "part",
        help="parametric hardware: tsa-module, ring-rail, blocker, driver-adapter (STEP + STL)",
        description="Build a parametric part and write NAME.step and NAME.stl into OUT. "
        "Parameters as --name value (see --list). --pattern with --panel places a TSA "
        "module's mount on a fabricated panel; --pattern with --crease places a blocker.",
    )
    p.add_argument("name", nargs="?", help="part name")
    p.add_argument("-o", "--output", help="output folder")
    p.add_argument("--list", action="store_true", help="list the parts and their parameters")
    p.add_argument("--pattern", help="design or pattern file the part is made for")
    p.add_argument("--panel", help="panel label (tsa-module)")
    p.add_argument("--crease", type=int, help="crease edge index (blocker)")
    p.set_defaults(func=_cmd_part, params=[])

    p = sub.add_parser(
        "simulate",
        help="fold any pattern by its strings and TSA (bar-and-hinge, quasi-static)",
        description="Simulate the string-driven folding of any crease pattern: bars and hinges "
        "(TPU creases, PLA panels), strings through holes shortened by the TSA, fold limits, "
        "gravity and ground. Writes states.fold (every equilibrium state, for Origami "
        "Simulator or Rabbit Ear), simulation.json (per step: TSA angle, string tensions, TSA "
        "torque, every crease's fold angle, energy) and fold.gif.",
    )
    p.add_argument("pattern", help="design file (.toml) or pattern file (.fold/.dxf/.svg)")
    p.add_argument("route", help="route file (.toml): TSA and strings")
    p.add_argument("-o", "--output", required=True, help="output folder (replaced atomically)")
    p.add_argument("--steps", type=int, help="actuation steps over the route's max_turns")
    p.add_argument(
        "--blocker",
        action="append",
        metavar="EDGE:DEG",
        help="a blocker stopping crease EDGE at DEG degrees (repeat)",
    )
    p.add_argument("--gravity", type=float, default=0.0, help="gravity along -z, mm/s^2")
    p.add_argument("--ground", type=float, default=None, help="height of a ground plane, mm")
    p.add_argument(
        "--friction", type=float, default=0.5, help="Coulomb friction on the ground (default 0.5)"
    )
    p.add_argument(
        "--free",
        action="store_true",
        help="hold no panel: the structure rests on the ground (needs --gravity and --ground); "
        "give anchor_panel in the route for a TSA riding on the structure",
    )
    p.set_defaults(func=_cmd_simulate)

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
    args, extra = parser.parse_known_args(argv)
    if extra:
        if args.command != "part":
            parser.error(f"unrecognized arguments: {' '.join(extra)}")
        args.params = extra  # the part's own --name value parameters
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
    except BrokenPipeError:  # output piped into a program that stopped reading (| head)
        sys.stderr.close()
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
