"""Robot commands: ``robot`` (the printable robot and its mass) and ``crawl`` (its gait)."""

from __future__ import annotations

import math
import time
from pathlib import Path

from origami_cad._fileio import atomic_write
from origami_cad._toml import json_text
from origami_cad.commands._base import Command, Option, Outputs, moved, register, staged, wrote
from origami_cad.commands.fabrication import SHEET_FILES
from origami_cad.commands.simulation import GIF_FRAMES, MATERIALS, gif_states, robot_materials
from origami_cad.errors import FabricationError, SimulationError

__all__: list[str] = []


def _crawl_command(a) -> str:
    """The ``origami-cad crawl`` command line that reproduces a crawl's outputs."""
    args = ["origami-cad", "crawl", str(a.robot), "-o", str(a.folder), "--cycles", str(a.cycles)]
    args += ["--steps", str(a.steps), *["--reverse"] * bool(a.reverse)]
    args += ["--friction", f"{a.friction:g}"] if a.friction is not None else []
    for flag, value in (("--gait", a.gait), ("--materials", a.materials)):
        args += [flag, str(value)] if value is not None else []
    return " ".join(args)


def _write_crawl(stage: Path, names, spec, result, info: dict, gif_frames: int) -> None:
    """crawl.json, crawl.png, loads.png, crawl.gif and gait_sequence.toml into ``stage``."""
    from origami_cad.crawler.robot import PAPER_CRAWL_MM
    from origami_cad.crawler.walk import gait_sequence, gait_sequence_header
    from origami_cad.drive.sequence import dump_sequence
    from origami_cad.viz.crawl_plots import (
        save_crawl_gait_png,
        save_crawl_loads_png,
        save_crawl_position_png,
    )
    from origami_cad.viz.render3d import render_folding_gif

    legs = [leg.name for leg in spec.legs]
    data = result.to_dict()
    data.update({k: v for k, v in info.items() if k != "command"})
    data["legs"] = legs
    with atomic_write(stage / names[0], "w", encoding="utf-8") as fh:
        fh.write(json_text(data, names[0], SimulationError, indent=1))
    reference = -PAPER_CRAWL_MM if info["reverse"] else PAPER_CRAWL_MM
    save_crawl_position_png(
        result.t, result.body, result.cycle_starts, stage / names[1],
        reference=reference, cycle=spec.cycle,
    )  # fmt: skip
    save_crawl_loads_png(result.t, result.torque, result.tensions, legs, stage / names[2])
    save_crawl_gait_png(
        result.t, result.fold, result.turns, legs, stage / names[5], commanded=result.commanded
    )
    picked = gif_states(len(result.states), gif_frames)
    shown = [result.states[k] for k in picked]
    captions = [
        f"t = {result.t[k]:.1f} s, body moved {result.body[k, 0] - result.body[0, 0]:+.1f} mm"
        for k in picked
    ]
    render_folding_gif(spec.pattern, shown, stage / names[3], view="xz", captions=captions)
    seq = gait_sequence(spec, repeat=info["cycles"], result=result, reverse=info["reverse"])
    header = gait_sequence_header(spec, info["command"])
    with atomic_write(stage / names[4], "w", encoding="utf-8") as fh:
        fh.write(dump_sequence(seq, header=header, layout="gait"))


@register
class Crawl(Command):
    """Walk a legged robot through its gait in simulation: crawl.json, .png plots, crawl.gif.

    The robot file (``examples/crawler/crawler.toml``) gives the pattern, one onboard
    TSA route per leg, blockers, masses and the gait as fold ratios; each keyframe is
    turned into TSA turns through the model and the robot lies free on the ground
    (gravity, Coulomb ``friction``, default the robot file's). ``cycles`` gait cycles
    of ``steps`` quasi-static steps between keyframes; ``reverse`` plays the gait
    backwards. Writes the body's path and per-TSA torque and tensions
    (``crawl.json``), the body's position against time (``crawl.png``), torques and
    tensions (``loads.png``), the legs' fold angles and TSA twist (``gait.png``), the
    crawl seen from the side (``crawl.gif``) and the gait as a sequence for ``drive``
    (``gait_sequence.toml``: string-model mappings, simulated loads for ``--dry-run``).
    ``gait``: walk a gait file's keyframes (``design-gait``'s ``gait.toml``) instead.
    """

    NAME, INPUTS, OUTPUT = "crawl", ("robot",), "folder"
    FILES = ("crawl.json", "crawl.png", "loads.png", "crawl.gif", "gait_sequence.toml", "gait.png")
    OPTIONS = (
        Option("cycles", "int", "gait cycles to simulate", default=2, min=1, max=100),
        Option("steps", "int", "quasi-static steps between keyframes", default=6, min=1,
               max=1000),
        Option("reverse", "flag", "play the gait backwards"),
        Option("friction", "float", "Coulomb coefficient (robot file's)", min=0, max=100),
        Option("gait", help="gait file (design-gait's gait.toml) instead of the robot's",
               metavar="GAIT.toml"),
        Option("gif_frames", "int", "frames of the animation", default=GIF_FRAMES, min=1,
               max=1000, flag=""), MATERIALS,
    )  # fmt: skip

    def inputs(self, a) -> list:  # the gait and materials files too: no output replaces them
        return [a.robot, *(x for x in (a.gait, a.materials) if x is not None)]

    def run(self, a) -> Outputs:
        from origami_cad.crawler.robot import PAPER_CRAWL_MM
        from origami_cad.crawler.walk import simulate_gait, walking_robot

        spec = walking_robot(a.robot, a.gait)
        start = time.perf_counter()
        result = simulate_gait(
            spec, cycles=a.cycles, steps=a.steps, reverse=a.reverse, friction=a.friction,
            progress=a.progress, params=robot_materials(a, spec),
        )  # fmt: skip
        seconds = time.perf_counter() - start
        per = result.displacement_per_cycle()
        info = {
            "robot": str(a.robot), "cycles": a.cycles, "reverse": a.reverse,
            "cycle_s": spec.cycle, "paper_mm_per_cycle": PAPER_CRAWL_MM,
            "simulation_s": seconds, "command": _crawl_command(a),
        }  # fmt: skip
        with self.stage(a, spec.pattern_path, *(leg.route_path for leg in spec.legs)) as stage:
            _write_crawl(stage, self.FILES, spec, result, info, a.gif_frames)
        files = [Path(a.folder) / n for n in self.FILES]
        mean = float(per.mean()) if per.size else math.nan
        return Outputs(
            files=files,
            images=[
                (files[5], "The gait: leg fold angles (simulated and keyframed) and TSA twist"),
                (files[1], "Body position against time (paper: 63 mm per 32 s cycle)"),
                (files[2], "TSA torque and string tension per leg"),
                (files[3], "The crawl seen from the side"),
            ],
            numbers=result.numbers(seconds),
            messages=[
                f"{a.cycles} gait cycle(s), {len(result.t)} states in {seconds:.1f} s: "
                f"{mean:.1f} mm per cycle (the paper's crawler: {PAPER_CRAWL_MM:g} mm)",
                *([f"stopped: {result.reason}"] if result.stop is not None else []),
                *(f"note: {n}" for n in result.notes),
                wrote(a.folder, self.FILES),
            ],
            result=result,
        )


def _write_robot(stage: Path, robot, fab, assembly, data: dict, renders: bool) -> list:
    """The sheet's files, the parts' STLs, robot.step, robot.json and the pictures; images."""
    from origami_cad.fabrication import write_fabrication
    from origami_cad.parts.robot import robot_render_style, write_robot_step, write_robot_stls
    from origami_cad.viz.fabrication_plots import save_panels_png
    from origami_cad.viz.parts_render import render_parts

    write_fabrication(fab, stage)
    save_panels_png(fab, stage / "panels.png")
    stls = write_robot_stls(assembly, stage)
    write_robot_step(assembly, stage / "robot.step", label=Path(robot).stem)
    with atomic_write(stage / "robot.json", "w", encoding="utf-8") as fh:
        fh.write(json_text(data, "robot.json", FabricationError, indent=1))
    images = [(stage / "panels.png", "The robot's sheet: panels, regions and string holes")]
    if renders:
        every = {n: stage / f"{n}.stl" for n in ("infills", "midlayers", "shells", "creases")}
        labels, colors = robot_render_style(assembly, list(stls))
        title = f"{Path(robot).stem}: printed robot"
        render_parts({**every, **stls}, stage / "robot.png", title=title, labels=labels,
                     colors=colors)  # fmt: skip
        images.insert(0, (stage / "robot.png", "The printed robot with its parts in place"))
    return images


@register
class Robot(Command):
    """The printable robot: the sheet's STLs, STEP, 3MF and its parts, robot.step, mass budget.

    The robot file (``examples/crawler/crawler.toml``) gives the pattern, the holes its
    strings need, a TSA module per leg, blockers on the leg creases and the driver
    adapter. Writes what ``fabricate`` writes for the sheet (with the robot's holes),
    one STL per added part in place (``tsa_module_*.stl``, ``blocker_*.stl``,
    ``driver_adapter.stl``), ``robot.step`` (every solid named and coloured in place),
    ``robot.json`` (each solid's volume, mass and bounding box, the mass budget with the
    robot file's bought parts, against the paper's 361.45 g) and, with ``renders``,
    ``robot.png``. ``ratio``: the fold ratio of ``robot.step``'s sheet and parts (0: flat);
    the added parts' STLs and ``robot.json``'s boxes follow it, the sheet's own files stay flat.
    """

    NAME, INPUTS, OUTPUT = "robot", ("robot",), "folder"
    FILES = (*SHEET_FILES, "robot.step", "robot.json", "robot.png", "driver_adapter.stl")
    OPTIONS = (
        Option("ratio", "float", "fold ratio p of robot.step", default=0.0, min=0, max=1),
        Option("renders", "flag", "no render", default=True, dest_negated="--no-renders"),
    )

    def run(self, a) -> Outputs:
        from origami_cad.crawler.robot import load_robot, robot_placements
        from origami_cad.fabrication import fabricate
        from origami_cad.parts.robot import (
            PAPER_CRAWLER_G,
            robot_assembly,
            robot_mass_numbers,
            robot_mass_report,
            robot_overlaps,
            robot_report,
        )

        spec = load_robot(a.robot)
        fab = fabricate(spec.pattern, spec.sheet(holes=spec.holes or "auto"))
        assembly = robot_assembly(fab, **robot_placements(spec), ratio=a.ratio)
        report, overlaps = robot_report(assembly), robot_overlaps(assembly)
        bought = [(m.name, m.grams) for m in spec.masses]
        data = robot_mass_report(a.robot, fab, report, overlaps, bought)
        budget = data["mass_budget"]
        with self.stage(a, spec.pattern_path, *(leg.route_path for leg in spec.legs)) as stage:
            images = _write_robot(stage, a.robot, fab, assembly, data, a.renders)
            files = moved(staged(stage), stage, a.folder)
        total, sheet = budget["total_g"], budget["sheet_g"]
        printed, bought_g = budget["printed_parts_g"], sum(budget["bought_parts_g"].values())
        return Outputs(
            files=files,
            images=[(Path(a.folder) / p.name, c) for p, c in images],
            numbers=robot_mass_numbers(data),
            messages=[
                f"mass estimate {total:.0f} g against the paper's {PAPER_CRAWLER_G:g} g "
                f"(sheet {sheet:.0f} g, printed parts {printed:.0f} g, bought {bought_g:.0f} g)",
                *(f"warning: {x} and {y} share {v:.1f} mm^3" for (x, y), v in overlaps.items()),
                *(f"warning: {w}" for w in fab.warnings),
                wrote(a.folder, files),
            ],
            result=assembly,
        )
