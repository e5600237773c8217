"""Simulation commands: ``simulate`` (bar-and-hinge), ``arm-scene`` (Fig. 8), ``mjcf``."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

from origami_cad._fileio import atomic_write
from origami_cad._toml import json_text
from origami_cad.commands._base import SIZING, Command, Option, Outputs, register, wrote
from origami_cad.commands.pull import MATERIALS, materials_of, robot_materials
from origami_cad.errors import DesignError, SimulationError

__all__ = ["GIF_FRAMES", "MATERIALS", "gif_states", "robot_materials"]

GIF_FRAMES = 30  # frames of a simulation's animation
#: The share of ``simulate``'s ``--time-limit`` kept for writing its files (the animation
#: shows fewer states when even that is short: a frame costs about one folded.png)
_WRITE_SHARE = 0.25
_GIF = Option("gif_frames", "int", "frames of the animation", default=GIF_FRAMES, min=1,
              max=1000, flag="")  # fmt: skip


def gif_states(states: int, frames: int) -> list[int]:
    """The states a GIF of about ``frames`` frames shows: evenly spaced, and the last."""
    every = max(1, states // max(frames, 1))
    return [*range(0, states, every), states - 1]


def _blocker(text: str) -> tuple[int, float]:
    """``--blocker EDGE:DEGREES`` (60 degrees when only the edge is given)."""
    edge, _, angle = text.partition(":")
    if not edge.strip().isdigit():
        raise ValueError(f"expected EDGE:DEGREES, got {text!r}")
    try:
        degrees = float(angle or "60")
    except ValueError:
        raise ValueError(f"expected EDGE:DEGREES, got {text!r}") from None
    if not (math.isfinite(degrees) and 0 < degrees <= 180):
        raise ValueError(f"expected EDGE:DEGREES with DEGREES in (0, 180], got {text!r}")
    return int(edge), degrees


def _write_simulation(stage: Path, names, cp, spec, result, gif_frames: int, deadline) -> list:
    """The simulation's files into ``stage``; the animation shows fewer states when the
    :func:`time.monotonic` ``deadline`` (s) leaves too little time for ``gif_frames``
    (then a note says so: the notes are returned)."""
    from origami_cad.pattern import folded_frame, write_fold
    from origami_cad.strings.dcqc_result import StopReason
    from origami_cad.viz.render3d import render_folded, render_folding_gif
    from origami_cad.viz.strings_plots import save_route_png

    titles = [f"theta_s = {math.degrees(t):.0f} deg" for t in result.theta]
    if result.stop is StopReason.TIME_LIMIT:  # the last state says the folding stopped early
        titles[-1] += f"; stopped early: {result.reason}"
    frames = [folded_frame(*f) for f in zip(result.states, result.fold_angles, titles, strict=True)]
    write_fold(cp, stage / names[0], frames=frames)
    with atomic_write(stage / names[1], "w", encoding="utf-8") as fh:
        fh.write(json_text(result.to_dict(), names[1], SimulationError, indent=1))
    view, started = (1, -1.5, 1), time.monotonic()
    title = f"after {result.turns[-1]:.1f} TSA turns"
    render_folded(cp, result.states[-1], stage / names[3], title=title, view=view)
    save_route_png(cp, spec, stage / names[4])
    affordable = (deadline - time.monotonic()) / max(time.monotonic() - started, 1e-3)
    picked = gif_states(len(result.states), max(min(gif_frames, int(affordable) - 1), 1))
    shown = [result.states[k] for k in picked]
    captions = [f"{result.turns[k]:.1f} TSA turns" for k in picked]
    render_folding_gif(cp, shown, stage / names[2], view=view, captions=captions)
    full = len(gif_states(len(result.states), gif_frames))
    notes = [f"warning: the time limit ran out: the files hold the {len(result)} states so far"]
    notes = notes if result.stop is StopReason.TIME_LIMIT else []
    return notes + [f"note: the time limit left the animation {len(picked)} of {full} frames"] * (
        len(picked) < full
    )


@register
class Simulate(Command):
    """Bar-and-hinge folding by strings and TSA (or a test machine's pull): states.fold,
    simulation.json, fold.gif.

    ``route`` is the route file; a design carrying its tendons (a PyGamiX description)
    needs none. ``pull`` (mm) pulls the strings' anchored end as a test machine does, at
    ``rate`` mm/s, instead of the TSA: pull.csv (pull in mm, tension in N...),
    states.fold and simulation.json. ``unit``, ``scale``, ``width`` size an imported pattern.

    From Python, ``params`` is a whole ``SimulationParams`` instead of its keywords,
    and ``gif_frames`` the number of frames of the animation.
    """

    NAME, INPUTS, OUTPUT, PROGRESS = "simulate", ("pattern",), "folder", "simulating"
    ARGS = ("pattern", "route", "folder", "params")
    FILES = ("states.fold", "simulation.json", "fold.gif", "folded.png", "route.png")
    PULL_FILES = ("pull.csv", "states.fold", "simulation.json")
    OPTIONS = (
        Option("route", help="route file (default: the design's own tendons)", nargs="?",
               positional=True, metavar="ROUTE"),
        Option("steps", "int", "equal TSA steps over the route's turns (default: by take-up)",
               min=1, max=100_000),
        Option("blockers", "object", "stop crease EDGE at DEG deg (repeat)", repeat=True,
               parse=_blocker, flag="--blocker", metavar="EDGE:DEG"),
        Option("gravity", "float", "gravity along -z", "mm/s^2", min=-1e6, max=1e6),
        Option("ground", "float", "height of a ground plane", "mm", min=-1e5, max=1e5),
        Option("friction", "float", "Coulomb friction coefficient", min=0, max=100),
        Option("free", "flag", "hold no panel (needs --gravity, --ground)"),
        Option("pull", "float", "pull the strings' end by this much (test machine)", "mm",
               min=0, max=1e4, open_min=True),
        Option("rate", "float", "the pull's speed", "mm/s", default=1000.0 / 60.0, min=0,
               max=1e4, open_min=True),
        Option("pull_step", "float", "pull per state", "mm", default=1.0, min=0, max=1e3,
               open_min=True),
        Option("fixed_panel", help="hold this panel (default: the route's or design's)",
               metavar="PANEL"),
        Option("time_limit", "float", "wall-clock time the command may take, writing included "
               "(then the states so far are written)", "s", default=120.0, min=0, open_min=True,
               max=1e6),
        MATERIALS,
        Option("params", "object", "a SimulationParams instead of its keywords", flag=""),
        _GIF,
        *SIZING,
    )  # fmt: skip

    @classmethod
    def library_defaults(cls) -> dict[str, Any]:
        import dataclasses

        from origami_cad.simulation.model import SimulationParams

        fields = dataclasses.fields(SimulationParams)
        return {f.name: f.default for f in fields if f.default is not dataclasses.MISSING}

    def inputs(self, a):
        return [a.pattern, *([a.route] if a.route else []), *([a.materials] if a.materials else [])]

    def outputs(self, a):
        names = self.PULL_FILES if a.pull is not None else self.FILES
        return [Path(a.folder) / n for n in names], [a.folder]

    def run(self, a) -> Outputs:
        from origami_cad.commands.pull import simulation_setup, write_pull
        from origami_cad.simulation import simulate

        deadline = time.monotonic() + a.time_limit  # the whole command's, writing too
        loaded, warned, cp, spec, params = simulation_setup(self, a)
        if a.pull is not None:
            return write_pull(self, a, loaded, spec, params, warned)
        limits = dict(a.blockers or {}) or None  # the library refuses a blocker off a crease
        left = math.floor(deadline - _WRITE_SHARE * a.time_limit - time.monotonic())  # whole s
        kwargs = {"steps": a.steps, "fold_limits": limits, "free": a.free}
        result = simulate(cp, spec, params, design=loaded, progress=a.progress,
                          fixed_panel=a.fixed_panel, time_limit=max(left, 1), **kwargs)  # fmt: skip
        with self.stage(a, loaded) as stage:
            notes = _write_simulation(stage, self.FILES, cp, spec, result, a.gif_frames, deadline)
        files, last = [Path(a.folder) / n for n in self.FILES], result.tensions[-1]
        tensions = ", ".join(f"{t:.3g}" for t in last)
        return Outputs(
            files=files,
            images=[
                (files[4], "Strings from the TSA through the panel holes"),
                (files[3], "Folded by the TSA (bar-and-hinge simulation)"),
                (files[2], "The folding as the TSA turns"),
            ],
            numbers=[
                ("simulated steps", str(len(result))),
                ("final TSA turns", f"{result.turns[-1]:.1f}"),
                ("string tensions at the end", ", ".join(f"{t:.2f} N" for t in last)),
                ("why it stops", result.reason),
            ],
            messages=[
                *warned,
                f"{len(result)} equilibrium states up to {result.turns[-1]:.2f} TSA turns; "
                f"{result.reason}",
                f"string tensions {tensions} N, TSA torque {result.torque[-1]:.3g} N mm",
                *notes,
                wrote(a.folder, self.FILES),
            ],
            result=result,
        )  # fmt: skip


def _arm_design(cmd: Command, a):
    """The arm's design file, loaded; an arm is a transition-graph design."""
    loaded, _ = cmd.load(a, a.design, sized=False)
    if loaded.tg is None:
        raise DesignError(f"{a.design}: an arm is a transition-graph design")
    return loaded


@register
class ArmScene(Command):
    """The printed arm folded by its strings in its scene (Fig. 8): fig8.png, arm_scene.json.

    The bar-and-hinge simulation (the route's panel thickness and eq. 6 fold
    limits) folds ``design`` by ``route``; each state is placed by its base panels
    and its main crease read as the TG chain, so its tip path is compared with the
    designed one (at the same fold ratio), ``P_start``, ``P_end`` and the task's
    areas. The simulation starts from creases pre-folded by 3 deg, not flat.
    ``steps`` turns the TSA in that many equal steps (default: steps of string taken
    up).

    The pre-folding is :func:`~origami_cad.simulation.simulate`'s.
    """

    NAME, INPUTS, OUTPUT = "arm-scene", ("task", "design", "route"), "folder"
    OPTIONS = (Option("steps", "int", "equal TSA steps (default: by take-up)", min=1, max=100_000),)
    FILES = ("fig8.png", "arm_scene.json")

    def run(self, a) -> Outputs:
        import numpy as np

        from origami_cad.design import arm_scene as scene
        from origami_cad.design import load_task
        from origami_cad.design.arm_route import arm_chain_path
        from origami_cad.simulation.string_models import fold_by_strings
        from origami_cad.strings import load_route
        from origami_cad.viz.design_plots import save_arm_scene_png

        arm_task, _ = load_task(a.task)
        loaded = _arm_design(self, a)
        spec = load_route(a.route, loaded.pattern)
        result = fold_by_strings(loaded, spec, "simulation", steps=a.steps)
        simulated = arm_chain_path(loaded.tg, result.states, np.asarray(result.p, dtype=float))
        p_e, designed = scene.designed_arm_path(
            arm_task, loaded.tg, getattr(spec.fabrication, "bias", None)
        )
        summary = scene.arm_scene_metrics(arm_task, loaded.tg, result, simulated, designed, p_e)
        d_end, turns = summary["final_distance_from_P_end_mm"], summary["tsa_turns"]
        peak = summary["max_tsa_torque_Nmm"]
        title = f"tip {d_end:.1f} mm from P_end after {turns:.1f} TSA turns, "
        with self.stage(a, loaded) as stage:
            title += f"peak torque {peak:.3g} N mm"
            save_arm_scene_png(arm_task, designed, simulated, stage / self.FILES[0], title)
            with atomic_write(stage / self.FILES[1], "w", encoding="utf-8") as fh:
                fh.write(json_text(summary, self.FILES[1], SimulationError, indent=1))
        files = [Path(a.folder) / n for n in self.FILES]
        return Outputs(
            files=files,
            images=[(files[0], "Designed tip path and the printed arm's, folded by its strings")],
            numbers=scene.arm_scene_numbers(summary),
            messages=[
                f"the printed arm's tip ends {d_end:.2f} mm from P_end after {turns:.1f} TSA "
                f"turns (peak torque {peak:.3g} N mm); {result.reason}",
                wrote(a.folder, self.FILES),
            ],
            result=result,
        )


@register
class Mjcf(Command):
    """A MuJoCo model (MJCF) of a design and its routes, or of a robot file: model.xml.

    Panels as bodies, creases as hinges (eq. 6 ranges), strings as tendons through the
    holes, one TSA actuator per string (docs/mujoco.md). Written atomically.
    """

    NAME, INPUTS, OUTPUT = "mjcf", ("source",), "output"
    SUFFIXES, WHAT = (".xml",), "an MJCF model"
    OPTIONS = (
        Option("routes", help="route files (a robot: none)", default=(), nargs="*",
               metavar="ROUTE", positional=True),
        MATERIALS,
    )  # fmt: skip

    def inputs(self, a):
        return [a.source, *(a.routes or ()), *([a.materials] if a.materials else [])]

    def run(self, a) -> Outputs:
        from origami_cad.crawler.mujoco import mjcf_source
        from origami_cad.simulation.mjcf import to_mjcf

        materials = materials_of(a)
        params = None if materials is None else materials.simulation_params()
        xml = to_mjcf(mjcf_source(a.source, list(a.routes or ())), params=params)
        with atomic_write(a.output, "w", encoding="utf-8") as fh:
            fh.write(xml)
        keys = {"panel": 'class="panel"', "hinge": 'type="hinge"', "connect": "<connect "}
        counts = {k: xml.count(v) for k, v in keys.items()} | {"spatial": xml.count("<spatial ")}
        counts["panel"] //= 2  # two printed halves each
        return Outputs(
            files=[Path(a.output)],
            numbers=[
                (
                    "panels / hinges / loop constraints",
                    "{panel} / {hinge} / {connect}".format(**counts),
                ),
                ("strings (tendons, one TSA actuator each)", str(counts["spatial"])),
            ],
            messages=[wrote(a.output)],
        )
