"""The gait design command: ``design-gait`` (CMA-ES over a legged robot's gait)."""

from __future__ import annotations

import time
from pathlib import Path

from origami_cad._fileio import atomic_write
from origami_cad._toml import json_text
from origami_cad.commands._base import Command, Option, Outputs, register, wrote
from origami_cad.commands.simulation import GIF_FRAMES, gif_states
from origami_cad.errors import DesignError
from origami_cad.parallel import open_executor

__all__: list[str] = []

FILES = ("gait.toml", "results.json", "convergence.png", "gait.png", "friction.png", "gait.gif")
#: With ``--design``: the designed crawler, its robot file walking the designed gait.
ROBOT_FILES = (
    "crawler.toml",
    "crawler.fold",
    *(f"route_{k}.toml" for k in ("fl", "fr", "rl", "rr")),
)

#: The options that are ``GaitSettings`` fields.
SETTINGS = ("runs", "popsize", "generations", "seed", "steps", "cycle", "mix", "frictions")
SETTINGS += ("targets",)


def _command_line(a) -> str:
    """The ``origami-cad design-gait`` command line that reproduces the search."""
    args = ["origami-cad", "design-gait", str(a.robot), "-o", str(a.folder)]
    for name in ("runs", "popsize", "generations", "seed", "steps", "cycle"):
        if getattr(a, name) is not None:
            args += [f"--{name}", f"{getattr(a, name):g}"]
    for name in ("frictions", "targets"):
        if getattr(a, name) is not None:
            args += [f"--{name}", *(f"{f:g}" for f in getattr(a, name))]
    args += ["--design", a.design] if a.design is not None else []
    return " ".join([*args, *(["--mix", a.mix] if a.mix else [])])


def _write(stage: Path, robot, design, walked, report: dict, gif_frames: int) -> None:
    """gait.toml, results.json, the plots and the side-view GIF into ``stage``."""
    import numpy as np

    from origami_cad.crawler.gait_files import gait_header
    from origami_cad.crawler.robot import PAPER_CRAWL_MM
    from origami_cad.crawler.walk import gait_sequence, gait_sequence_header
    from origami_cad.drive.sequence import dump_sequence
    from origami_cad.viz import crawl_plots as plots
    from origami_cad.viz.render3d import render_folding_gif

    best_robot, result = walked
    header = gait_header(design, report["command"])
    header += gait_sequence_header(best_robot, report["command"])
    with atomic_write(stage / FILES[0], "w", encoding="utf-8") as fh:
        fh.write(dump_sequence(gait_sequence(best_robot, result=result), header=header,
                               layout="gait"))  # fmt: skip
    with atomic_write(stage / FILES[1], "w", encoding="utf-8") as fh:
        fh.write(json_text(report, FILES[1], DesignError, indent=1))
    cands = design.candidates
    plots.save_gait_convergence_png(
        np.array([c.generation for c in cands]), np.array([c.score for c in cands]),
        design.history, stage / FILES[2], hand=design.hand_score,
    )  # fmt: skip
    legs = [leg.name for leg in robot.legs]
    best = (best_robot.gait_t, best_robot.gait_p)
    plots.save_gait_keyframes_png(best, (robot.gait_t, robot.gait_p), legs, stage / FILES[3])
    mus = [t.friction for t in design.best.terms]
    plots.save_gait_vs_hand_png(
        mus, [t.forward for t in design.best.terms], [t.forward for t in design.hand],
        stage / FILES[4], reference=PAPER_CRAWL_MM, drift=[t.drift for t in design.best.terms],
    )  # fmt: skip
    picked = gif_states(len(result.states), gif_frames)
    captions = [f"t = {result.t[k]:.1f} s, {result.body[k, 0] - result.body[0, 0]:+.1f} mm"
                for k in picked]  # fmt: skip
    shown = [result.states[k] for k in picked]
    render_folding_gif(best_robot.pattern, shown, stage / FILES[5], view="xz", captions=captions)


def _numbers(design, seconds: float) -> list[tuple[str, str]]:
    from origami_cad.crawler.robot import PAPER_CRAWL_MM

    rows = [("search", f"{len(design.candidates)} candidates in {seconds:.0f} s")]
    for best, hand in zip(design.best.terms, design.hand, strict=True):
        rows.append((
            f"friction {best.friction:g}: forward (hand gait; paper {PAPER_CRAWL_MM:g} mm)",
            f"{best.forward:.1f} mm ({hand.forward:.1f} mm), drift {best.drift:+.1f} mm, "
            f"yaw {best.yaw:+.1f} deg",
        ))  # fmt: skip
    hits = sorted({h for t in design.best.terms for h in t.hits})
    return [*rows, ("limits hit by the best gait", "; ".join(hits) or "none")]


@register
class DesignGait(Command):
    """CMA-ES gait design of a legged robot: gait.toml, results.json, plots and gait.gif.

    Searches a four-stroke wave gait (each leg pair's fold range, left-right trims,
    dwells) within the blockers, the servo's speed and stall torque and the strings'
    tension limit, over one ``cycle``; each candidate is walked in simulation as
    ``crawl`` does at every friction of ``frictions`` and scored by its forward
    displacement per cycle less its drift, yaw, foot slip and limits hit, combined by
    ``mix`` (their mean, the worst friction, the average of the two, or the worst
    shortfall against ``targets``, mm per cycle per friction). The search
    starts from the robot file's own gait, which stays a candidate: the best is never
    worse. ``gait.toml`` is a sequence for ``drive`` whose keyframes ``crawl --gait``
    reads; ``results.json`` holds every candidate and what limits the stride;
    ``scheduler`` runs the simulations on Dask. ``design`` searches the crawler's design
    genes too (leg length with the body shortened to keep the paper's 340 mm, string
    holes, blocker, crease thickness; docs/crawler.md) and writes the designed crawler's
    ``crawler.toml`` (walking the designed gait), ``crawler.fold`` and routes.
    """

    NAME, INPUTS, OUTPUT, PROGRESS = "design-gait", ("robot",), "folder", "gait candidates"
    OPTIONS = (
        Option("frictions", "float", "Coulomb coefficients scored", min=0, max=100, nargs="+"),
        Option("mix", "str", "how frictions combine",
               choices=("mean", "worst", "worst+mean", "shortfall")),
        Option("targets", "float", "shortfall's target per friction (default 45 63 45 at "
               "0.4 0.6 0.8)", "mm", min=0, max=1000, nargs="+"),
        Option("cycle", "float", "gait cycle", "s", min=1, max=3600),
        Option("runs", "int", "independent CMA-ES runs", min=1, max=100),
        Option("popsize", "int", "CMA-ES population", min=2, max=1000),
        Option("generations", "int", "CMA-ES generations", min=1, max=10_000),
        Option("seed", "int", "seed of run 0 (run k: seed + k)", min=0, max=2**32 - 1),
        Option("steps", "int", "quasi-static steps between keyframes", min=1, max=100),
        Option("design", "str", "search the crawler's design too: 'default' or "
               "gene=low:high,... (docs/crawler.md, design search)", metavar="BOUNDS"),
        Option("scheduler", help="address of a Dask scheduler to simulate on (default: a "
               "local process pool)", metavar="ADDR"),
        Option("gif_frames", "int", "frames of the animation", default=GIF_FRAMES, min=1,
               max=1000, flag=""),
    )  # fmt: skip

    @classmethod
    def library_defaults(cls) -> dict:
        """The search's defaults (``GaitSettings``), for the help."""
        import dataclasses

        from origami_cad.crawler.gait import GaitSettings

        fields = dataclasses.asdict(GaitSettings())
        return {o.name: fields[o.name] for o in cls.OPTIONS if o.name in fields}

    def run(self, a) -> Outputs:
        from origami_cad.crawler import gait_files as lib
        from origami_cad.crawler.design import write_crawler
        from origami_cad.crawler.robot import PAPER_CRAWL_MM, load_robot
        from origami_cad.crawler.walk import simulate_gait

        robot = load_robot(a.robot)
        settings = lib.gait_settings(robot, **{k: getattr(a, k) for k in SETTINGS})
        command = _command_line(a)
        start = time.perf_counter()
        with open_executor(a.scheduler) as executor:
            design, search = lib.search_gait(robot, settings, a.design, executor, a.progress)
        seconds = time.perf_counter() - start
        lib.check_within_limits(design, str(a.robot))
        best_robot = search.robot() if search else design.robot(robot)
        result = simulate_gait(best_robot, cycles=settings.cycles, steps=settings.steps)
        walker = best_robot if search else robot
        report = lib.gait_report(walker, design, seconds, command, search)
        with self.stage(a, robot.pattern_path, *(leg.route_path for leg in robot.legs)) as stage:
            _write(stage, robot, design, (best_robot, result), report, a.gif_frames)
            if search is not None:
                write_crawler(search.files(lib.crawler_gait_header(design, command)), stage)
        files = [Path(a.folder) / n for n in FILES + (ROBOT_FILES if search else ())]
        return Outputs(
            files=files,
            images=[
                (files[4], "Forward per cycle against friction: designed, hand, the paper"),
                (files[2], "Score per generation"),
                (files[3], "Each leg's fold angle: the designed and the hand gait"),
                (files[5], "The designed gait seen from the side"),
            ],
            numbers=_numbers(design, seconds),
            messages=[
                "designed gait: "
                + ", ".join(f"{t.forward:.1f} mm at {t.friction:g}" for t in design.best.terms)
                + f" per cycle (paper {PAPER_CRAWL_MM:g} mm), {seconds:.0f} s",
                wrote(a.folder, FILES + (ROBOT_FILES if search is not None else ())),
            ],
            result=design,
        )
