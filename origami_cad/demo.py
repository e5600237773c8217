"""The main job: reproduce the paper's figures end to end into one HTML report.

``origami-cad demo -o out/`` (what ``make demo`` runs) runs each step below,
writes its files into ``out/<step>/`` and the report to ``out/index.html``.
Each step uses the same public functions and example files a user would.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

from origami_cad import __version__
from origami_cad.viz.report import StepReport, write_report

__all__ = ["STEPS", "run_demo"]

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _rel(path: Path, root: Path) -> str:
    return path.relative_to(root).as_posix()


def step_fig2(out: Path, root: Path, quick: bool) -> StepReport:
    """Fig. 2: a TG of five vectors becomes a crease pattern and folds to p = 0, 0.5, 0.98."""
    import numpy as np

    from origami_cad.kinematics.folding import fold_design, fold_sequence
    from origami_cad.pattern import folded_frame, write_fold, write_pattern
    from origami_cad.pattern.design import load_design
    from origami_cad.viz import save_pattern_png
    from origami_cad.viz.render3d import render_folded, render_folding_gif
    from origami_cad.viz.tg_plot import save_tg_png

    design = load_design(EXAMPLES / "fig2_tg.toml")
    cp, tg = design.pattern, design.tg
    rep = StepReport("fig2", "Fig. 2 - from a transition graph to a folded tessellation")
    rep.summary = (
        "Five transition vectors drawn at p = 0.5 (unit width 36 mm, three copies) give the "
        "shape angles of eq. 1; the tessellation then folds rigidly and exactly (eqs. 2-3)."
    )
    files = [out / "pattern.png", out / "pattern.fold", out / "pattern.svg", out / "pattern.dxf"]
    save_pattern_png(cp, files[0], labels=True)
    for f in files[1:]:
        write_pattern(cp, f)
    save_tg_png(tg, out / "tg.png")
    rep.images += [
        (_rel(files[0], root), "Crease pattern (mountain red, valley blue dashed)"),
        (_rel(out / "tg.png", root), "TG chain at several p and the path of T_e"),
    ]
    for p in (0.0, 0.5, 0.98):
        state = fold_design(design, p)
        img = out / f"folded_p{round(p * 100):02d}.png"
        render_folded(cp, state.coords, img, title=f"p = {p:g}", view=(1, -2, 1.5))
        rep.images.append((_rel(img, root), f"Folded at p = {p:g}"))
        files.append(img)
    ratios = np.linspace(0, 0.98, 12 if quick else 40)
    states = fold_sequence(design, ratios)
    render_folding_gif(cp, [s.coords for s in states], out / "folding.gif", view=(1, -2, 1.5))
    write_fold(
        cp,
        out / "folding.fold",
        frames=[folded_frame(s.coords, s.fold_angles, f"p = {s.p:.3f}") for s in states],
    )
    rep.images.append((_rel(out / "folding.gif", root), "Folding from p = 0 to 0.98"))
    files += [out / "tg.png", out / "folding.gif", out / "folding.fold"]
    rep.numbers += [
        ("shape angles beta_1..beta_4 (eq. 1)", ", ".join(f"{b:.2f} deg" for b in tg.shape_angles)),
        ("panels", str(len(cp.faces))),
        (
            "creases (M / V)",
            f"{int((cp.assignments == 'M').sum())} / {int((cp.assignments == 'V').sum())}",
        ),
        (
            "pattern size",
            f"{cp.bounds[2] - cp.bounds[0]:.1f} x {cp.bounds[3] - cp.bounds[1]:.1f} mm",
        ),
    ]
    rep.files = [_rel(f, root) for f in files]
    return rep


def step_fig3(out: Path, root: Path, quick: bool) -> StepReport:
    """Fig. 3: ten CMA-ES runs design a robotic arm around warning and prohibited areas."""
    import dataclasses
    import time

    from origami_cad.design import design_arm, load_task, write_design_outputs
    from origami_cad.pattern.design import load_design
    from origami_cad.viz import save_pattern_png

    task, settings = load_task(EXAMPLES / "arm_task.toml")
    if quick:
        settings = dataclasses.replace(settings, runs=4, max_generations=60)
    t0 = time.perf_counter()
    results = design_arm(task, settings)
    seconds = time.perf_counter() - t0
    paths = write_design_outputs(results, task, settings, out, seconds=seconds)
    winner = load_design(paths["best"])
    save_pattern_png(winner.pattern, out / "best_pattern.png", labels=True)
    best = results[0]
    rep = StepReport("fig3", "Fig. 3 - computational design of an origami robotic arm")
    rep.summary = (
        "T_s = (0, 0); the tip must pass P_start = (250, 0) when flat and P_end = (50, 133.3) "
        "when folded, never touch the prohibited area (x >= 150, y >= 40) and stay out of "
        "the warning area (x >= 140, y >= 30). Fitness: eq. 5 with alpha = 120; the winner "
        "must also be buildable at a 36 mm unit width."
    )
    rep.images += [
        (_rel(paths["trajectories"], root), "Top designs: chains and the path of T_e"),
        (_rel(paths["convergence"], root), "Best fitness per generation, one line per run"),
        (_rel(out / "best_pattern.png", root), "The winner's crease pattern"),
    ]
    rep.numbers += [
        ("runs x generations", f"{settings.runs} x {settings.max_generations}"),
        ("search time", f"{seconds:.1f} s"),
        ("best fitness (max 60)", f"{best.fitness:.3f} (run {best.run}, EF_0 = {best.entry_flag})"),
        ("|T_e(0) - P_start|", f"{best.terms.d_start:.3g} mm"),
        ("|T_e(pi) - P_end|", f"{best.terms.d_end:.3g} mm"),
        ("improper states N", str(best.terms.improper_states)),
        ("lengths l_0..l_n", ", ".join(f"{v:.1f}" for v in best.lengths) + " mm"),
        ("shape angles", ", ".join(f"{v:.1f}" for v in best.shape_angles) + " deg"),
    ]
    rep.files = [_rel(p, root) for p in [*paths.values(), out / "best_pattern.png"]]
    return rep


def _fabricate_into(design, folder: Path, root: Path, rep: StepReport, name: str) -> None:
    from origami_cad._fileio import atomic_directory
    from origami_cad.fabrication import fabricate, write_fabrication
    from origami_cad.viz.fabrication_plots import save_panels_png
    from origami_cad.viz.parts_render import render_parts

    fab = fabricate(design)
    with atomic_directory(folder) as tmp:
        write_fabrication(fab, tmp)
        save_panels_png(fab, tmp / "panels.png")
    stls = {n: folder / f"{n}.stl" for n in ("infills", "midlayers", "shells", "creases")}
    render_parts(stls, folder / "assembled.png", title=f"{name}: assembled")
    render_parts(stls, folder / "exploded.png", mode="exploded", title=f"{name}: the four STLs")
    # a section perpendicular to the first main crease, through its middle
    cp = design.pattern
    main = [e for e in range(cp.n_edges) if cp.assignments[e] in "MV"]
    a, b = cp.vertices[cp.edges[main[0]]]
    mid = (a + b) / 2
    direction = (b - a) / max(float(((b - a) ** 2).sum()) ** 0.5, 1e-12)
    render_parts(
        stls,
        folder / "section.png",
        mode="section",
        section_origin=(float(mid[0]), float(mid[1]), fab.params.height / 2),
        section_normal=(float(direction[0]), float(direction[1]), 0.0),
        title=f"{name}: section across a crease (Fig. 4e)",
    )
    report = fab.report()
    rep.images += [
        (_rel(folder / "panels.png", root), f"{name}: panels, operation regions and holes"),
        (_rel(folder / "assembled.png", root), f"{name}: assembled parts"),
        (_rel(folder / "exploded.png", root), f"{name}: exploded parts"),
        (_rel(folder / "section.png", root), f"{name}: section across a crease"),
    ]
    vols = ", ".join(f"{n} {v['volume_mm3'] / 1000:.2f} cm3" for n, v in report["parts"].items())
    rep.numbers += [
        (f"{name}: panels / holes", f"{report['panels']} / {len(fab.holes)}"),
        (
            f"{name}: theta_max, p_max (eq. 6)",
            f"{report['theta_max_deg']:.1f} deg, {100 * report['p_max']:.1f} %",
        ),
        (f"{name}: volumes", vols),
        (f"{name}: mass estimate", f"{report['total_mass_g']:.1f} g"),
    ]
    if fab.limits.p_max_kinematic is not None:
        rep.numbers.append(
            (
                f"{name}: p_max of the folded structure (legs first)",
                f"{100 * fab.limits.p_max_kinematic:.1f} %",
            )
        )
    rep.numbers.append((f"{name}: build + export time", f"{sum(fab.timings.values()):.1f} s"))
    rep.files += [_rel(p, root) for p in sorted(folder.iterdir())]


def step_fig4(out: Path, root: Path, quick: bool) -> StepReport:
    """Fig. 4: the arm winner and the 6 x 4 Miura as dual-material printable parts."""
    from origami_cad.pattern.design import load_design

    rep = StepReport("fig4", "Fig. 4 - dual-material printable structures")
    rep.summary = (
        "Each panel is two exact B-rep halves (PLA infill wrapped in a TPU shell) with "
        "chamfers of eq. 6, joined by a PLA mid-layer in a continuous TPU crease sheet. "
        "Exported as four STL files, one STEP assembly and a 3MF whose PLA parts are on "
        "extruder 1 and TPU parts on extruder 2 (PrusaSlicer and Bambu/Orca)."
    )
    _fabricate_into(
        load_design(EXAMPLES / "miura_6x4.toml"), out / "miura", root, rep, "6 x 4 Miura"
    )
    winner = root / "fig3" / "best.toml"
    if winner.exists():
        _fabricate_into(load_design(winner), out / "arm", root, rep, "arm winner")
    return rep


def step_fig5(out: Path, root: Path, quick: bool) -> StepReport:
    """Fig. 5: a ring TSA folds the 6 x 4 Miura through DCQC-routed strings."""
    from origami_cad.pattern.design import load_design
    from origami_cad.strings import load_route, simulate_dcqc
    from origami_cad.viz.strings_plots import write_route_outputs

    design = load_design(EXAMPLES / "miura_6x4.toml")
    route = load_route(EXAMPLES / "miura_route.toml", design.pattern)
    result = simulate_dcqc(design, route)
    write_route_outputs(design.pattern, route, result, out)
    rep = StepReport("fig5", "Fig. 5 - folding by a twisted string actuator (DCQC)")
    rep.summary = (
        "One ring TSA twists four strings that reach the sheet from guides on a ring of 70 mm "
        "radius and thread through panel holes on the side where each crease closes (above "
        "valleys, below mountains). Each quasi-static step turns the TSA by 2 deg (eq. 8) and "
        "finds the smallest fold ratio at which every string fits its length (eq. 7)."
    )
    rep.images += [
        (_rel(out / "route.png", root), "Routing (solid above, dashed below the sheet)"),
        (_rel(out / "dcqc.png", root), "Fold ratio against TSA turns"),
        (_rel(out / "route_folded.png", root), "Final state with the strings"),
    ]
    rep.numbers += [
        ("strings / quasi-static steps", f"{len(route.strings)} / {len(result.steps) - 1}"),
        ("final fold ratio p", f"{result.final['p']:.3f} after {result.final['turns']:.2f} turns"),
        ("why it stops", result.reason),
        ("DCQC side-rule violations", str(len(result.violations))),
        ("segments cutting through panels", str(len(result.cutting))),
    ]
    rep.files = [
        _rel(out / n, root) for n in ("dcqc.json", "route.png", "dcqc.png", "route_folded.png")
    ]
    return rep


def step_fig6(out: Path, root: Path, quick: bool) -> StepReport:
    """Fig. 6: the boat-like pattern read from DXF: panels, holes, parts, TSA folding."""
    import json

    import numpy as np

    from origami_cad._fileio import atomic_write
    from origami_cad.fabrication.export import export_part
    from origami_cad.pattern import read_pattern
    from origami_cad.pattern.design import Design
    from origami_cad.simulation import simulate
    from origami_cad.strings import load_route
    from origami_cad.viz import save_pattern_png
    from origami_cad.viz.render3d import render_folded, render_folding_gif
    from origami_cad.viz.strings_plots import save_route_png

    cp = read_pattern(EXAMPLES / "data" / "boat.dxf")
    design = Design(cp, None, "file")
    rep = StepReport("fig6", "Fig. 6 - a boat-like structure from a DXF file")
    rep.summary = (
        "A 165.6 x 96.6 mm crease pattern drawn in CAD is read from DXF, checked, turned into "
        "printable parts with one hole per panel, fitted with an onboard TSA module, and folded "
        "by that TSA's strings in the bar-and-hinge simulation (any pattern, no kinematic "
        "model needed) until its creases reach eq. 6's limit."
    )
    out.mkdir(parents=True, exist_ok=True)
    save_pattern_png(cp, out / "pattern.png", labels=True)
    _fabricate_into(design, out / "parts", root, rep, "boat")
    route = load_route(EXAMPLES / "boat_route.toml", cp)
    save_route_png(cp, route, out / "route.png")
    steps = 24 if quick else 100
    result = simulate(cp, route, steps=steps)
    with atomic_write(out / "simulation.json", "w", encoding="utf-8") as fh:
        json.dump(result.to_dict(), fh)
    render_folded(
        cp,
        result.states[-1],
        out / "folded.png",
        title=f"after {result.steps[-1]['turns']:.1f} TSA turns",
        view=(1, -1.5, 1),
    )
    every = max(1, len(result.states) // 30)
    render_folding_gif(
        cp, [*result.states[::every], result.states[-1]], out / "folding.gif", view=(1, -1.5, 1)
    )
    from origami_cad.fabrication import plan_panels
    from origami_cad.parts import tsa_module

    module = tsa_module(plan=plan_panels(design), panel="f0")
    export_part(module, out, "tsa_module")
    keel = int(np.flatnonzero(cp.edge_mask("V"))[0])
    last = result.steps[-1]
    rep.images = [
        (_rel(out / "pattern.png", root), "The pattern read from examples/data/boat.dxf"),
        (_rel(out / "route.png", root), "Strings from the TSA module on panel f0"),
        (_rel(out / "folded.png", root), "Folded by the TSA (bar-and-hinge simulation)"),
        (_rel(out / "folding.gif", root), "The folding as the TSA turns"),
        *rep.images,
    ]
    rep.numbers = [
        (
            "pattern",
            f"{cp.n_vertices} vertices, {cp.n_edges} edges, {len(cp.faces)} panels, "
            f"{cp.bounds[2] - cp.bounds[0]:.1f} x {cp.bounds[3] - cp.bounds[1]:.1f} mm",
        ),
        (
            "check",
            "no errors" if not [p for p in cp.check() if p.severity == "error"] else "errors",
        ),
        ("simulated steps", str(len(result.steps))),
        ("final TSA turns", f"{last['turns']:.1f}"),
        ("keel fold angle at the end", f"{last['fold_angles_deg'][keel]:.1f} deg"),
        ("string tensions at the end", ", ".join(f"{t:.2f} N" for t in last["tensions_N"])),
        ("why it stops", result.reason),
        *rep.numbers,
    ]
    rep.files += [
        _rel(out / n, root)
        for n in (
            "pattern.png",
            "route.png",
            "folded.png",
            "folding.gif",
            "simulation.json",
            "tsa_module.step",
            "tsa_module.stl",
        )
    ]
    return rep


def step_fig7(out: Path, root: Path, quick: bool) -> StepReport:
    """Fig. 7: the crawler's four-TSA gait cycle run against emulated servos (dry run)."""
    from origami_cad.drive import DynamixelBus, DynamixelEmulator
    from origami_cad.drive.sequence import load_sequence, run_sequence
    from origami_cad.viz.drive_plots import save_drive_png

    seq = load_sequence(EXAMPLES / "crawler_gait.toml")
    speed = 32.0 if quick else 8.0
    limits = {t.dxl_id: t.max_turns for t in seq.tsas}
    out.mkdir(parents=True, exist_ok=True)
    with (
        DynamixelEmulator(seq.ids, time_scale=speed) as emu,
        DynamixelBus(
            emu.port,
            1_000_000,
            seq.ids,
            max_turns=limits,
            current_limit_ma=seq.current_limit,
            profile_velocity=0,
        ) as bus,
    ):
        rows = run_sequence(seq, bus, out / "crawler_log.csv", time_scale=speed)
    names = {t.dxl_id: t.name for t in seq.tsas}
    save_drive_png(rows, out / "crawler_turns.png", names)
    lag = max(abs(r["target_turns"] - r["measured_turns"]) for r in rows)
    rep = StepReport("fig7", "Fig. 7 - the crawler's gait on four TSAs (dry run)")
    rep.summary = (
        "Four onboard TSAs (servo IDs 1-4) run the 32 s cycle of get ready, step forward, "
        "crawl and relax, from fold-ratio keyframes turned into motor turns through each "
        "TSA's model. The servos are emulated: real Dynamixel Protocol 2.0 packets go through "
        "dynamixel_sdk over a pseudo-terminal; every command and reading is in the CSV log."
    )
    rep.images.append(
        (
            _rel(out / "crawler_turns.png", root),
            "Commanded (dashed) and measured (solid) turns and current per TSA",
        )
    )
    rep.numbers += [
        ("cycle / readings", f"{seq.cycle:g} s / {len(rows)}"),
        ("dry-run time acceleration", f"{speed:g} x"),
        ("largest lag of a servo behind its command", f"{lag:.3f} turns"),
        ("maximum commanded twist", f"{max(r['target_turns'] for r in rows):.2f} turns"),
    ]
    rep.files = [_rel(out / "crawler_log.csv", root), _rel(out / "crawler_turns.png", root)]
    return rep


STEPS: list[tuple[str, Callable[[Path, Path, bool], StepReport]]] = [
    ("fig2", step_fig2),
    ("fig3", step_fig3),
    ("fig4", step_fig4),
    ("fig5", step_fig5),
    ("fig6", step_fig6),
    ("fig7", step_fig7),
]


def run_demo(out: Path, quick: bool = False, echo: Callable[[str], None] = print) -> Path:
    """Run every step into ``out/<step>/`` and write ``out/index.html``.

    A step that fails is reported in the page (and the run continues); the
    function raises at the end if any step failed, so ``make demo`` fails too.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    reports = []
    t_all = time.perf_counter()
    failed = []
    for key, func in STEPS:
        echo(f"[{key}] {func.__doc__.splitlines()[0]}")
        t0 = time.perf_counter()
        try:
            rep = func(out / key, out, quick)
        except Exception as exc:  # reported in the page, re-raised at the end
            rep = StepReport(key, key, error=f"{type(exc).__name__}: {exc}")
            failed.append(key)
        rep.seconds = time.perf_counter() - t0
        echo(f"[{key}] {'FAILED' if rep.error else 'done'} in {rep.seconds:.1f} s")
        reports.append(rep)
    total = time.perf_counter() - t_all
    index = write_report(
        out / "index.html",
        reports,
        subtitle=f"origami_cad {__version__} - Yang and Li, 'Design and Fabrication of "
        f"String-driven Origami Robots' - total {total:.1f} s" + (" (quick run)" if quick else ""),
    )
    echo(f"report: {index}  (total {total:.1f} s)")
    if failed:
        from origami_cad.errors import OrigamiCadError

        raise OrigamiCadError(f"demo steps failed: {', '.join(failed)} (see {index})")
    return index
