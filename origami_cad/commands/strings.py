"""Commands on string routes: ``route`` (DCQC), ``plan-route`` (route search) and the
demo's ``string-models`` (both string models from one route)."""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

from origami_cad._fileio import atomic_write
from origami_cad._names import one_line
from origami_cad.commands._base import SIZING, Command, Option, Outputs, register, wrote
from origami_cad.errors import StringsError
from origami_cad.parallel import open_executor

__all__: list[str] = []


def _sim_params(spec, **loads):
    """The simulation's materials: from the route's [fabrication] (one source), else defaults."""
    from origami_cad.simulation import SimulationParams

    return SimulationParams.for_route(spec, **loads)


def _route_numbers(spec, result) -> list[tuple[str, str]]:
    p, turns = float(result.p[-1]), float(result.turns[-1])
    return [
        ("strings / quasi-static steps", f"{len(spec.strings)} / {len(result) - 1}"),
        ("final fold ratio p", f"{p:.3f} after {turns:.2f} turns"),
        ("why it stops", result.reason),
        ("DCQC side-rule violations", str(len(result.violations))),
        ("segments cutting through panels", str(len(result.cutting))),
    ]


@register
class Route(Command):
    """DCQC folding by a TSA: dcqc.json, dcqc.png, route.png, route_folded.png into ``folder``.

    ``status`` is 1 when the routing never folds the structure.
    ``unit``, ``scale`` and ``width`` size an imported pattern (``read_pattern``).
    """

    NAME, INPUTS, OUTPUT = "route", ("design", "route"), "folder"
    OPTIONS = SIZING
    FILES = ("dcqc.json", "route.png", "dcqc.png", "route_folded.png")

    def run(self, a) -> Outputs:
        from origami_cad.strings import load_route, simulate_dcqc
        from origami_cad.viz.render3d import render_folded
        from origami_cad.viz.strings_plots import save_dcqc_png, save_route_png

        loaded, warned = self.load(a, a.design)
        cp, names = loaded.pattern, self.FILES
        spec = load_route(a.route, cp)
        result = simulate_dcqc(loaded, spec, **_sim_params(spec).dcqc_stiffness())
        p, turns = float(result.p[-1]), float(result.turns[-1])
        with self.stage(a, loaded) as stage:
            with atomic_write(stage / names[0], "w", encoding="utf-8") as fh:
                json.dump(result.to_dict(), fh, indent=1)
            save_route_png(cp, spec, stage / names[1])
            save_dcqc_png(result, stage / names[2])
            title = f"final p = {p:.3f}"
            render_folded(
                cp, result.final_coords, stage / names[3], strings=result.final_strings,
                title=title,
            )  # fmt: skip
        files = [Path(a.folder) / n for n in names]
        captions = ["Routing (solid above, dashed below the sheet)"]
        captions += ["Fold ratio against TSA turns", "Final state with the strings"]
        state = "final" if result.valid else "INVALID routing"
        return Outputs(
            files=files,
            images=list(zip(files[1:], captions, strict=True)),
            numbers=_route_numbers(spec, result),
            messages=[
                *warned,
                *(f"warning: {v}" for v in result.violations + result.cutting),
                f"{state}: p = {p:.4f} after {turns:.2f} turns; {result.reason}",
                wrote(a.folder, names),
            ],
            result=result,
            status=0 if result.valid else 1,
        )


@register
class StringModels(Command):
    """Both string models from one route file: fig5.png (p, tensions, torque, four stages).

    Also ``simulation.json``; the numbers give where the two p(turns) curves differ.
    """

    NAME, INPUTS, OUTPUT, HIDDEN = "string-models", ("design", "route"), "folder", True

    def run(self, a) -> Outputs:
        import numpy as np

        from origami_cad.simulation import simulate
        from origami_cad.strings import load_route, simulate_dcqc
        from origami_cad.viz.strings_plots import save_fig5_png

        loaded, _ = self.load(a, a.design, sized=False)
        spec = load_route(a.route, loaded.pattern)
        params = _sim_params(spec)
        dcqc = simulate_dcqc(loaded, spec, **params.dcqc_stiffness())
        sim = simulate(loaded.pattern, spec, params, design=loaded)
        gap = np.abs(sim.p - np.interp(sim.turns, dcqc.turns, dcqc.p))
        names = ("fig5.png", "simulation.json")
        with self.stage(a, loaded) as stage:
            save_fig5_png(loaded.pattern, dcqc, sim, stage / names[0])
            with atomic_write(stage / names[1], "w", encoding="utf-8") as fh:
                json.dump(sim.to_dict(), fh)
        files = [Path(a.folder) / n for n in names]
        peak = f"{sim.tensions.max():.1f} N / {sim.torque.max():.2f} N mm"
        end = f"{sim.p[-1]:.3f} after {sim.turns[-1]:.2f} turns"
        return Outputs(
            files=files,
            images=[(files[0], "p against turns in both models; tensions, torque; four stages")],
            numbers=[
                ("simulated states", str(len(sim))),
                ("final fold ratio p (simulation)", end),
                ("largest gap in p(turns) between the models", f"{np.nanmax(gap):.3f}"),
                ("largest string tension / TSA torque", peak),
                ("why the simulation stops", sim.reason),
            ],
            messages=[wrote(a.folder, names)],
            result=(dcqc, sim),
        )  # fmt: skip


# ----------------------------------------------------------------------------- plan-route

_PLAN_HINT = "try another TSA place, fewer strings or a smaller --target-p"


def _tsa_placement(tsa: str, ring_radius: float, ring_height: float):
    """``--tsa ring`` or ``onboard:PANEL`` as a :class:`~origami_cad.strings.plan.TSAPlacement`."""
    from origami_cad.strings import TSAParams
    from origami_cad.strings.plan import TSAPlacement

    kind, _, panel = tsa.partition(":")
    if kind not in ("ring", "onboard") or (kind == "onboard") != bool(panel):
        raise ValueError(f"expected 'ring' or 'onboard:PANEL', got {tsa!r}")
    return TSAPlacement(kind, panel or None, ring_radius, ring_height, tsa=TSAParams(model=kind))


def _plan_budget(budget: str):
    """``--budget TURNS[,NMM]`` as the search's settings (budgets of turns and peak torque)."""
    from origami_cad.strings.plan import PlanSettings

    try:
        values = [float(v) for v in budget.split(",")]
    except ValueError:
        values = []
    if not 1 <= len(values) <= 2 or not all(math.isfinite(v) and 0 < v <= 1e6 for v in values):
        raise ValueError(f"expected TURNS or TURNS,NMM (positive), got {budget!r}")
    return PlanSettings(max_turns=values[0], max_torque=values[1] if len(values) > 1 else math.inf)


def _check_tsa(text: str) -> str:
    _tsa_placement(text, 126.0, 10.0)
    return text


def _check_budget(text: str) -> str:
    _plan_budget(text)
    return text


def _plan_header(a, planned, geom) -> str:
    """The route file's comment lines: the command line that planned it, and its rank 1."""
    target = f" --target-p {a.target_p:g}" if a.target_p is not None else ""
    return (
        f"# Planned by: origami-cad plan-route {one_line(a.pattern)} --tsa {one_line(a.tsa)} "
        f"--strings {a.strings}{target} --seed {a.seed}\n"
        f"# rank 1 of {len(planned)}: {planned[0].turns:.2f} TSA turns to p = "
        f"{geom.target_p:.4f}, peak torque {planned[0].peak_torque:.3g} N mm (DCQC model)"
    )


def _plan_numbers(planned, geom, seconds: float, cpu: float) -> list[tuple[str, str]]:
    best = planned[0]
    sim = best.checks.get("simulation")
    checked = (
        "not run"
        if sim is None
        else f"p = {sim['p']:.3f} after {sim['turns']:.1f} turns ({sim['stop']})"
    )
    return [
        ("valid routes ranked", str(len(planned))),
        ("target fold ratio", f"p = {geom.target_p:.4f} (fold limit {geom.limit_p:.4f})"),
        ("best: TSA turns / peak torque", f"{best.turns:.2f} / {best.peak_torque:.3g} N mm"),
        ("best: load share", f"{best.share:.2f}"),
        ("search time", f"{seconds:.1f} s wall, {cpu:.1f} s CPU here"),
        ("bar-and-hinge check of the best", checked),
    ]


def _plan_messages(planned, geom) -> list[str]:
    best = planned[0]
    lines = [
        f"best of {len(planned)} routes: {len(best.strings)} strings, {best.turns:.2f} TSA turns "
        f"to p = {geom.target_p:.4f}, peak torque {best.peak_torque:.3g} N mm"
    ]
    for r in planned:
        sim = r.checks.get("simulation")
        if sim is not None and not sim["reaches_target"]:
            lines.append(
                f"warning: route {r.rank}: the bar-and-hinge simulation stops at p = "
                f"{sim['p']:.3f} ({sim['reason']})"
            )
    return lines


def _write_plan(a, loaded, geom, planned, stage: Path, names, seconds: float) -> list:
    """route.toml, routes.json and the two plots into ``stage``; the routes, verified."""
    from origami_cad.simulation.verify import verify_planned
    from origami_cad.strings.plan import route_toml
    from origami_cad.viz.plan_plots import save_planned_routes_png, save_planned_turns_png

    text = route_toml(geom, planned[0], _plan_header(a, planned, geom))
    (stage / names[0]).write_text(text, encoding="utf-8")
    planned = verify_planned(loaded, geom, planned, a.verify, first=stage / names[0])
    data = {
        "target_p": geom.target_p,
        "fold_limit_p": geom.limit_p,
        "tsa": geom.placement.kind,
        "search_seconds": seconds,
        "routes": [r.to_dict() for r in planned],
    }
    with atomic_write(stage / names[1], "w", encoding="utf-8") as fh:
        json.dump(data, fh, indent=1)
    save_planned_routes_png(loaded.pattern, planned, stage / names[2])
    save_planned_turns_png(planned, stage / names[3])
    return planned


@register
class PlanRoute(Command):
    """Search string routes by the DCQC principle: route.toml, routes.json and plots.

    Beam search over hole sequences (sides by the M/V rule), then CMA-ES over hole
    positions in the panels' operation regions, scored on the fast DCQC model and
    ranked by TSA turns, peak torque and load share; the best ``verify`` routes are
    folded by the bar-and-hinge simulator. ``--tsa ring`` puts the guides on a ring
    of ``ring_radius`` mm, ``ring_height`` mm above the sheet; ``onboard:PANEL``
    mounts the TSA on that panel. ``--budget TURNS[,NMM]``: the TSA's turns and peak
    torque (N mm) to stay within (default 40 turns). routes.json, routes.png and
    routes_turns.png go next to route.toml. ``--scheduler`` runs the search on a Dask
    cluster. ``unit``, ``scale`` and ``width`` size an imported pattern (``read_pattern``).
    """

    NAME, INPUTS, OUTPUT, PROGRESS = "plan-route", ("pattern",), "output", "candidates"
    SUFFIXES, WHAT = (".toml",), "the route"
    OPTIONS = (
        Option("tsa", help="ring, or onboard:PANEL (the TSA on that panel)", default="ring",
               parse=_check_tsa),
        Option("strings", "int", "strings the TSA twists", default=4, min=1, max=16),
        Option("target_p", "float", "fold ratio (default: eq. 6 limit)", min=0, open_min=True,
               max=1),
        Option("candidates", "int", "beam width of the search", default=128, min=1, max=4096),
        Option("budget", help="turn [and torque] budget", metavar="TURNS[,NMM]",
               parse=_check_budget),
        Option("seed", "int", "seed (overrides [search])", default=0, min=0, max=2**32 - 1),
        Option("scheduler", help="Dask scheduler", metavar="ADDR"),
        Option("ring_radius", "float", "radius of the ring TSA's guides", "mm", 126.0, min=0,
               open_min=True, max=1e4, flag=""),
        Option("ring_height", "float", "height of the ring above the sheet", "mm", 10.0,
               min=0, max=1e4, flag=""),
        Option("verify", "int", "routes folded by the bar-and-hinge simulator", default=2,
               min=0, max=100, flag=""),
        *SIZING,
    )  # fmt: skip
    NAMES = ("routes.json", "routes.png", "routes_turns.png")

    def outputs(self, a):
        folder = Path(a.output).parent
        return [folder / n for n in (Path(a.output).name, *self.NAMES)], []

    def run(self, a) -> Outputs:
        from origami_cad.strings.plan import PlanSettings, plan_geometry, plan_routes

        placement = _tsa_placement(a.tsa, a.ring_radius, a.ring_height)
        loaded, warned = self.load(a, a.pattern)
        t0, cpu0 = time.perf_counter(), time.process_time()
        settings = PlanSettings() if a.budget is None else _plan_budget(a.budget)
        geom = plan_geometry(loaded, placement, target_p=a.target_p, settings=settings)
        with open_executor(a.scheduler) as executor:
            planned = plan_routes(
                loaded, placement, a.strings, target_p=a.target_p, candidates=a.candidates,
                seed=a.seed, executor=executor, progress=a.progress, geometry=geom,
                check=max(a.verify, 1), settings=settings,
            )  # fmt: skip
        seconds = time.perf_counter() - t0
        if not planned:
            raise StringsError(f"{a.pattern}: no route satisfies DCQC to the target; {_PLAN_HINT}")
        files, _ = self.outputs(a)
        names, done = [f.name for f in files], "wrote " + " ".join(map(str, files))
        with self.stage(a, loaded, folder=files[0].parent) as stage:
            planned = _write_plan(a, loaded, geom, planned, stage, names, seconds)
        return Outputs(
            files=files,
            images=[(files[2], "The best planned routes"), (files[3], "p against TSA turns")],
            numbers=_plan_numbers(planned, geom, seconds, time.process_time() - cpu0),
            messages=[*warned, *_plan_messages(planned, geom), done],
            result=planned,
        )  # fmt: skip
