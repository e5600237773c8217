"""Commands on string routes: ``route`` (DCQC) and the demo's ``string-models`` (both
string models from one route); the route search ``plan-route`` is in :mod:`.plan_route`."""

from __future__ import annotations

from pathlib import Path

from origami_cad._fileio import atomic_write
from origami_cad._toml import json_text
from origami_cad.commands._base import SIZING, Command, Outputs, register, wrote
from origami_cad.commands.pull import MATERIALS, materials_of
from origami_cad.errors import SimulationError, StringsError

__all__: list[str] = []


def _sim_params(spec, a=None, **loads):
    """The simulation's materials: from the route's [fabrication] (one source), else defaults,
    with the materials file's (``a.materials``) over them."""
    from origami_cad.simulation import SimulationParams

    materials = None if a is None else materials_of(a)
    extra = {} if materials is None else materials.overrides()
    return SimulationParams.for_route(spec, **extra, **loads)


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
    ``unit``, ``scale`` and ``width`` size an imported pattern.
    """

    NAME, INPUTS, OUTPUT = "route", ("design", "route"), "folder"
    OPTIONS = (*SIZING, MATERIALS)
    FILES = ("dcqc.json", "route.png", "dcqc.png", "route_folded.png")

    def inputs(self, a):
        return [a.design, a.route, *([a.materials] if a.materials else [])]

    def run(self, a) -> Outputs:
        from origami_cad.simulation.paths import with_fold_path
        from origami_cad.strings import load_route, simulate_dcqc
        from origami_cad.viz.render3d import render_folded
        from origami_cad.viz.strings_plots import save_dcqc_png, save_route_png

        loaded, warned = self.load(a, a.design)
        cp, names = loaded.pattern, self.FILES
        spec = load_route(a.route, cp)
        loaded = with_fold_path(loaded)
        result = simulate_dcqc(loaded, spec, **_sim_params(spec, a).dcqc_stiffness())
        p, turns = float(result.p[-1]), float(result.turns[-1])
        with self.stage(a, loaded) as stage:
            with atomic_write(stage / names[0], "w", encoding="utf-8") as fh:
                fh.write(json_text(result.to_dict(), names[0], StringsError, indent=1))
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
        from origami_cad.simulation.paths import with_fold_path
        from origami_cad.strings import load_route, simulate_dcqc
        from origami_cad.viz.strings_plots import save_fig5_png

        loaded, _ = self.load(a, a.design, sized=False)
        loaded = with_fold_path(loaded)
        spec = load_route(a.route, loaded.pattern)
        params = _sim_params(spec)
        dcqc = simulate_dcqc(loaded, spec, **params.dcqc_stiffness())
        sim = simulate(loaded.pattern, spec, params, design=loaded)
        gap = np.abs(sim.p - np.interp(sim.turns, dcqc.turns, dcqc.p))
        names = ("fig5.png", "simulation.json")
        with self.stage(a, loaded) as stage:
            save_fig5_png(loaded.pattern, dcqc, sim, stage / names[0])
            with atomic_write(stage / names[1], "w", encoding="utf-8") as fh:
                fh.write(json_text(sim.to_dict(), names[1], SimulationError))
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
