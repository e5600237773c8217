"""The route search command: ``plan-route`` (DCQC-scored beam search and CMA-ES)."""

from __future__ import annotations

import math
import time
from dataclasses import replace
from pathlib import Path

from origami_cad._fileio import atomic_write
from origami_cad._names import one_line
from origami_cad._toml import json_text
from origami_cad.commands._base import SIZING, Command, Option, Outputs, register, wrote
from origami_cad.errors import StringsError
from origami_cad.parallel import open_executor

__all__: list[str] = []

#: The share of ``--time-limit`` kept for writing the files (the plots, routes.json): the
#: fold path, the search and its bar-and-hinge check end that much earlier
_WRITE_SHARE = 0.15


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


def _plan_header(a, planned, geom) -> str:
    """The route file's comment lines: the command line that planned it, and its rank 1."""
    target = f" --target-p {a.target_p:g}" if a.target_p is not None else ""
    strings = f" --strings {a.strings}" if a.strings is not None else ""
    return (
        f"# Planned by: origami-cad plan-route {one_line(a.pattern)} --tsa {one_line(a.tsa)}"
        f"{strings}{target} --seed {a.seed}\n"
        f"# rank 1 of {len(planned)}: {planned[0].turns:.2f} TSA turns to p = "
        f"{geom.target_p:.4f}, peak torque {planned[0].peak_torque:.3g} N mm (DCQC model)"
    )


@register
class PlanRoute(Command):
    """Search string routes by the DCQC principle: route.toml, routes.json and plots.

    Beam search over hole sequences (sides by the M/V rule), then CMA-ES over hole
    positions in the panels' operation regions, scored on the fast DCQC model and
    ranked by TSA turns, peak torque and load share; the best ``verify`` routes are
    folded by the bar-and-hinge simulator. ``--tsa ring`` puts the guides on a ring
    (126 mm in radius, 10 mm above the sheet); ``onboard:PANEL`` mounts the TSA on
    that panel. Without ``--strings``, the fewest strings whose best
    route reaches the target are planned (1, 2, ...), and the count is said.
    ``--budget TURNS[,NMM]``: the TSA's turns and peak torque (N mm) to stay within
    (default 40 turns). routes.json, routes.png and
    routes_turns.png go next to route.toml. ``--scheduler`` runs the search on a Dask
    cluster. ``unit``, ``scale`` and ``width`` size an imported pattern.
    """

    NAME, INPUTS, OUTPUT, PROGRESS = "plan-route", ("pattern",), "output", "candidates"
    SUFFIXES, WHAT = (".toml",), "the route"
    OPTIONS = (
        Option("tsa", help="ring (the TSA on a ring above the sheet), or onboard:PANEL (on "
               "that panel)", default="ring", parse=lambda t: _tsa_placement(t, 126.0, 10.0) and t,
               metavar="ring|onboard:PANEL"),
        Option("strings", "int", "strings the TSA twists (default: the fewest that reach the "
               "target)", min=1, max=16, metavar="N"),
        Option("target_p", "float", "fold ratio to reach (default: the eq. 6 limit)", min=0,
               open_min=True, max=1, metavar="P"),
        Option("candidates", "int", "beam width of the search", default=128, min=1, max=4096,
               metavar="N"),
        Option("budget", help="the TSA's turns, and peak torque in N mm, to stay within "
               "(default 40 turns)", metavar="TURNS[,NMM]", parse=lambda t: _plan_budget(t) and t),
        Option("seed", "int", "random seed of the search", default=0, min=0, max=2**32 - 1,
               metavar="N"),
        Option("scheduler", help="address of a Dask scheduler to search on (default: a "
               "local process pool)", metavar="ADDR"),
        Option("ring_radius", "float", "radius of the ring TSA's guides", "mm", 126.0, min=0,
               open_min=True, max=1e4, flag=""),
        Option("ring_height", "float", "height of the ring above the sheet", "mm", 10.0,
               min=0, max=1e4, flag=""),
        Option("time_limit", "float", "wall-clock time the command may take, writing included "
               "(then the best found is kept)", "s", default=120.0, min=0, open_min=True,
               max=1e6),
        Option("verify", "int", "routes folded by the bar-and-hinge simulator", default=2,
               min=0, max=100, flag=""),
        *SIZING,
    )  # fmt: skip
    NAMES = ("routes.json", "routes.png", "routes_turns.png")

    def outputs(self, a):
        folder = Path(a.output).parent
        return [folder / n for n in (Path(a.output).name, *self.NAMES)], []

    def run(self, a) -> Outputs:
        from origami_cad.strings.plan import plan_messages, plan_numbers, truncated_geometry

        # the whole command's time: the computing ends early enough to write the files
        deadline = time.time() + (1.0 - _WRITE_SHARE) * a.time_limit
        placement = _tsa_placement(a.tsa, a.ring_radius, a.ring_height)
        loaded, warned = self.load(a, a.pattern)
        t0, cpu0 = time.perf_counter(), time.process_time()
        loaded, geom, planned = self.search(a, loaded, placement, deadline)
        seconds = time.perf_counter() - t0
        geom = truncated_geometry(geom, len(planned[0].p))  # a default target out of reach
        files, _ = self.outputs(a)
        with self.stage(a, loaded, folder=files[0].parent) as stage:
            planned = self.write(a, loaded, geom, planned, stage, (seconds, deadline))
        return Outputs(
            files=files,
            images=[(files[2], "The best planned routes"), (files[3], "p against TSA turns")],
            numbers=plan_numbers(planned, geom, seconds, time.process_time() - cpu0),
            messages=[
                *warned,
                *plan_messages(planned, geom, a.strings is None, loaded, a.target_p is None),
                wrote(files[0].parent, files),
            ],
            result=planned,
        )  # fmt: skip

    def search(self, a, loaded, placement, deadline: float):
        """``(design with its fold path, the search's geometry, the planned routes)``, all
        by ``deadline`` (a :func:`time.time`, s), else a refusal saying the time ran out."""
        from origami_cad.simulation.paths import with_fold_path
        from origami_cad.strings.plan import PlanSettings, plan_geometry, plan_routes

        start = time.time()
        loaded = with_fold_path(loaded, deadline=time.monotonic() + deadline - start)
        settings = PlanSettings() if a.budget is None else _plan_budget(a.budget)
        settings = replace(settings, time_limit=a.time_limit, deadline=deadline)
        geom = plan_geometry(loaded, placement, target_p=a.target_p, settings=settings)
        if time.time() > deadline:  # the search could not end in time: no search at all
            raise StringsError(
                f"the time limit of {a.time_limit:g} s ran out before the route search "
                f"(folding the pattern and placing its holes took {time.time() - start:.0f} "
                "s): a longer --time-limit searches"
            )
        with open_executor(a.scheduler) as executor:
            planned = plan_routes(
                loaded, placement, a.strings, target_p=a.target_p, candidates=a.candidates,
                seed=a.seed, executor=executor, progress=a.progress, geometry=geom,
                check=max(a.verify, 1), settings=settings,
            )  # fmt: skip
        return loaded, geom, planned

    def write(self, a, loaded, geom, planned, stage: Path, times: tuple) -> list:
        """route.toml, routes.json and the two plots into ``stage``; the routes, verified.

        ``times``: the search's seconds, and the :func:`time.time` (s) the bar-and-hinge
        check of the routes ends by."""
        from origami_cad.simulation.verify import verify_planned
        from origami_cad.strings.plan import plan_data, route_spec
        from origami_cad.strings.route import dump_route
        from origami_cad.viz.plan_plots import save_planned_routes_png, save_planned_turns_png

        names, (seconds, deadline) = [f.name for f in self.outputs(a)[0]], times
        spec = route_spec(geom, planned[0])
        text = dump_route(spec, loaded.pattern, header=_plan_header(a, planned, geom))
        (stage / names[0]).write_text(text, encoding="utf-8")
        planned = verify_planned(
            loaded, geom, planned, a.verify, first=stage / names[0], deadline=deadline
        )
        with atomic_write(stage / names[1], "w", encoding="utf-8") as fh:
            fh.write(json_text(plan_data(geom, planned, seconds), names[1], StringsError, indent=1))
        save_planned_routes_png(loaded.pattern, planned, stage / names[2])
        save_planned_turns_png(planned, stage / names[3])
        return planned
