"""The main job: reproduce the paper's figures end to end into one HTML report.

``origami-cad demo -o out/`` (what ``make demo`` runs) runs each step below,
writes its files into ``out/<step>/`` and the report to ``out/index.html``.
Each step uses the same public functions and example files a user would: the
``examples/`` folder, which a wheel installs as ``origami_cad/examples`` (see
:func:`examples_dir`), so the demo runs from an installed package outside the source tree.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import NamedTuple

from origami_cad import __version__
from origami_cad.commands import Command, Option, Outputs, execute, register
from origami_cad.errors import OrigamiCadError, OutputError
from origami_cad.viz.report import StepReport, write_report

__all__ = [
    "GALLERY",
    "GALLERY_RATIOS",
    "GALLERY_WIDTH",
    "STEPS",
    "Demo",
    "Step",
    "examples_dir",
    "gallery",
    "mujoco_frame",
    "run_demo",
    "run_step",
]


def examples_dir() -> Path:
    """The folder of example files the demo reads.

    An installed wheel ships the top-level ``examples/`` as the package data
    ``origami_cad/examples`` (found through :mod:`importlib.resources`); an editable
    install or a source checkout reads ``examples/`` beside the package.

    Raises
    ------
    OrigamiCadError
        When neither folder holds the examples (a broken install).
    """
    packaged = resources.files("origami_cad") / "examples"
    tree = Path(__file__).resolve().parent.parent / "examples"
    for folder in (packaged, tree):
        if isinstance(folder, Path) and (folder / "crawler" / "crawler.toml").is_file():
            return folder
    from origami_cad.errors import OrigamiCadError

    raise OrigamiCadError(
        f"the demo's example files are missing: neither {packaged} (installed package "
        f"data) nor {tree} (source tree) holds crawler/crawler.toml; reinstall origami-cad"
    )


def fig2(out: Path, quick: bool) -> list[Outputs]:
    """Fig. 2: a TG of five vectors becomes a crease pattern and folds to p = 0, 0.5, 0.98."""
    design, view = examples_dir() / "fig2_tg.toml", (1, -2, 1.5)
    names = ("pattern.png", "pattern.fold", "pattern.svg", "pattern.dxf")
    chained = [execute("pattern", design, [out / n for n in names], labels=True)]
    chained.append(execute("tg", design, out / "tg.png"))
    for p in (0.0, 0.5, 0.98):
        img = out / f"folded_p{round(p * 100):02d}.png"
        chained.append(execute("fold", design, img, ratio=p, view=view))
    frames = 12 if quick else 40
    chained.append(
        execute("fold", design, out / "folding.gif", ratio=0.98, frames=frames, view=view)
    )
    chained.append(execute("fold", design, out / "folding.fold", ratio=0.98, frames=frames))
    chained.append(execute("fold", design, out / "folding.glb", ratio=0.98, frames=frames))
    return chained


def fig3(out: Path, quick: bool) -> list[Outputs]:
    """Fig. 3: ten CMA-ES runs design a robotic arm around warning and prohibited areas."""
    budget = {"runs": 4, "max_generations": 60} if quick else {}
    return [execute("design-arm", examples_dir() / "arm_task.toml", out, **budget)]


def fig4(out: Path, quick: bool) -> list[Outputs]:
    """Fig. 4: the arm winner and the 6 x 4 Miura as dual-material printable parts."""
    miura = examples_dir() / "miura_6x4.toml"
    chained = [execute("fabricate", miura, out / "miura", renders=True, name="6 x 4 Miura")]
    winner = out.parent / "fig3" / "best.toml"
    if winner.exists():
        # the arm's sheet is about 250 mm long: printed on a 300 x 300 mm bed
        arm = execute(
            "fabricate", winner, out / "arm", renders=True, name="arm winner", bed=(300, 300)
        )
        chained.append(arm)
    return chained


def fig5(out: Path, quick: bool) -> list[Outputs]:
    """Fig. 5: a ring TSA folds the 6 x 4 Miura through DCQC-routed strings."""
    design, route = examples_dir() / "miura_6x4.toml", examples_dir() / "miura_route.toml"
    return [
        execute("route", design, route, out),
        execute("string-models", design, route, out / "models"),
    ]


def fig6(out: Path, quick: bool) -> list[Outputs]:
    """Fig. 6: the boat-like pattern read from DXF: panels, holes, parts, TSA folding."""
    boat, route = examples_dir() / "data" / "boat.dxf", examples_dir() / "boat_route.toml"
    return [
        execute("check", boat),
        execute("pattern", boat, [out / "pattern.png"], labels=True),
        execute("simulate", boat, route, out, steps=24 if quick else 100),
        execute("fabricate", boat, out / "parts", renders=True, name="boat"),
        execute("part", "tsa-module", out, pattern=boat, panel="f0"),
    ]


def fig7(out: Path, quick: bool) -> list[Outputs]:
    """Fig. 7: the crawler printed with its parts, walking in simulation, and driven (dry run)."""
    robot = examples_dir() / "crawler" / "crawler.toml"
    chained = [execute("robot", robot, out / "robot", renders=True)]
    walk = {"cycles": 1, "steps": 3} if quick else {"cycles": 3, "steps": 6}
    crawl = execute("crawl", robot, out / "crawl", **walk)
    chained.append(crawl)
    # the gait designed by CMA-ES against the hand gait and the paper's 63 mm, over the
    # friction sweep; the demo's budget (docs/crawler.md): the hand gait, then 2 generations
    # of 4 from it at 3 frictions (1.5 min on 2 busy cores), quick: 2 candidates at 0.6
    budget = (
        {"frictions": [0.6], "popsize": 2, "generations": 1, "steps": 2}
        if quick
        else {"popsize": 4, "generations": 2}
    )
    chained.append(execute("design-gait", robot, out / "gait", **budget))
    # the servo logs: examples/crawler_gait.toml is the crawl job's gait_sequence.toml (the
    # model's mappings and the simulated load per servo, which the emulated servos carry);
    # its header says how it was made
    speed = 32.0 if quick else 8.0
    done = execute(
        "drive",
        examples_dir() / "crawler_gait.toml",
        out / "crawler_log.csv",
        dry_run=True,
        speed=speed,
        baudrate=1_000_000,
        plot=out / "crawler_turns.png",
    )
    done.numbers.insert(1, ("dry-run time acceleration", f"{speed:g} x"))
    chained.append(done)
    chained.append(mujoco_frame(robot, out / "mujoco_mid_stride.png"))
    return chained


def mujoco_frame(robot: Path, png: Path) -> Outputs:
    """The crawler exported to MuJoCo (``oc.robot_mjcf``) 11 s into its gait, rendered off-screen.

    Without the ``mujoco`` extra or an off-screen GL context (EGL, OSMesa) the report says
    why instead of showing the frame.
    """
    from origami_cad._fileio import atomic_path

    try:
        from origami_cad.crawler.mujoco import render_gait_frame
        from origami_cad.simulation.mjcf import MjcfError
    except ImportError as exc:
        return Outputs(numbers=[("MuJoCo frame", f"not rendered: {exc}")])
    try:
        with atomic_path(png) as tmp:
            render_gait_frame(robot, tmp)
    except (MjcfError, ImportError) as exc:
        return Outputs(numbers=[("MuJoCo frame", f"not rendered: {exc}")])
    caption = "The crawler in MuJoCo (oc.robot_mjcf), 11 s into its gait: mid-stride"
    return Outputs(files=[png], images=[(png, caption)])


def fig8(out: Path, quick: bool) -> list[Outputs]:
    """Fig. 8: the fig. 3 winner folded by its route's strings, against its designed tip path."""
    import json

    task = examples_dir() / "arm_task.toml"
    design, route = out.parent / "fig3" / "best.toml", out.parent / "fig3" / "route.toml"
    if not (design.exists() and route.exists()):
        design, route = examples_dir() / "arm_design.toml", examples_dir() / "arm_route.toml"
    chained = [execute("arm-scene", task, design, route, out, steps=60 if quick else None)]
    p_e = json.loads((out / "arm_scene.json").read_text())["designed_fold_ratio_end"]
    frames = ["0:0", f"20:{p_e:.4f}", f"30:{p_e:.4f}", "40:0"]
    chained.append(execute("sequence", design, route, out / "arm_fold.toml", keyframes=frames))
    return chained


#: The gallery's patterns: (file under ``examples/gallery/``, the tool that wrote it, title).
GALLERY = (
    ("origami_simulator/miura-ori.svg", "Origami Simulator", "Miura-ori"),
    ("origami_simulator/waterbombBase.svg", "Origami Simulator", "waterbomb base"),
    ("fold/squaretwist.fold", "FOLD's examples", "square twist"),
    ("fold/simple.fold", "FOLD's examples", "simple"),
    ("pygamix/waterbomb.json", "PyGamiX", "waterbomb tessellation"),
    ("pygamix/resch-50.json", "PyGamiX", "Resch tessellation"),
)
#: The fold ratios the gallery shows each pattern at.
GALLERY_RATIOS = (0.3, 0.7)
#: The width every gallery pattern is scaled to, mm.
GALLERY_WIDTH = 150.0


def gallery(out: Path, quick: bool) -> list[Outputs]:
    """Patterns of other tools: each crease pattern beside ``oc.fold`` at two ratios.

    Six files from Origami Simulator, FOLD's examples and PyGamiX
    (``examples/gallery/``, :data:`GALLERY`), each scaled to :data:`GALLERY_WIDTH` mm and
    folded by ``fold`` (the closed form where it applies, else the general solver) at
    :data:`GALLERY_RATIOS`; the images come three to a row: pattern, then each ratio.
    """
    chained = []
    for name, tool, title in GALLERY:
        src, stem = examples_dir() / "gallery" / name, Path(name).stem
        drawn = execute("pattern", src, [out / f"{stem}.png"])
        drawn.images = [(p, f"{title} ({tool}): crease pattern") for p, _ in drawn.images]
        drawn.numbers, folds = [], []
        chained.append(drawn)
        for p in GALLERY_RATIOS:
            png = out / f"{stem}_p{round(p * 100):02d}.png"
            done = execute("fold", src, png, ratio=p, width=GALLERY_WIDTH)
            state = done.result[-1]
            how = f"{state.method}, largest strain {state.strain:.2g} %"
            done.images, done.numbers = [(png, f"{title} folded to p = {p:g} ({how})")], []
            folds.append(f"p = {p:g}: {how}")
            chained.append(done)
        drawn.numbers = [(f"{title} ({tool})", "; ".join(folds))]
    return chained


def calibration(out: Path, quick: bool) -> list[Outputs]:
    """PyGamiX's mountain structure on the bench: its three measured runs against the pull
    simulated with the default materials and with the calibrated ones of
    ``examples/pygamix/materials_mountain.toml`` (no fit: two pulls)."""
    from origami_cad._fileio import atomic_path
    from origami_cad.simulation.calibrate import compare_materials
    from origami_cad.simulation.materials import Materials, load_materials
    from origami_cad.viz.calibration_plots import save_fit_png

    folder = examples_dir() / "pygamix"
    runs = sorted((folder / "experiment" / "mountain").glob("*.csv"))
    calibrated = load_materials(folder / "materials_mountain.toml")
    design = folder / "descriptionData" / "f-mountain-big-fix-new.json"
    fit = compare_materials(design, runs, Materials(), calibrated, step=3.0,
                            tendons=(2,))  # fmt: skip
    out.mkdir(parents=True, exist_ok=True)
    png = out / "mountain_fit.png"
    with atomic_path(png) as tmp:
        save_fit_png(fit, tmp, title="PyGamiX's mountain structure, its second tendon pulled")
    caption = (f"Measured force against pull (3 runs) and simulated: default materials "
               f"(NRMSE {fit.error_before:.2f}), calibrated (NRMSE {fit.error:.2f})")  # fmt: skip
    mountain = Outputs(files=[png], images=[(png, caption)], numbers=[
        ("NRMSE before calibration", f"{fit.error_before:.3f}"),
        ("NRMSE after calibration", f"{fit.error:.3f} (goal 0.10)"),
    ])  # fmt: skip
    if quick:
        return [mountain]
    return [
        mountain,
        *(
            predicted(folder, out, calibrated, name, design)
            for name, design in (
                ("diamond", "f-diamond-III-acc.json"),
                ("resch", "f-resch-50.json"),
            )
        ),
    ]


def predicted(folder: Path, out: Path, calibrated, name: str, design: str) -> Outputs:
    """Another structure of the same bench, not used in the fit: its runs against its pull
    (every tendon on one crosshead, every 2.5 mm) with the default and the mountain's
    calibrated materials, and the error over the whole pull and its first half."""
    from origami_cad._fileio import atomic_path
    from origami_cad.simulation.calibrate import compare_materials, nrmse
    from origami_cad.simulation.materials import Materials
    from origami_cad.viz.calibration_plots import save_fit_png

    runs = sorted((folder / "experiment" / name).glob("*.csv"))
    fit = compare_materials(folder / "descriptionData" / design, runs, Materials(), calibrated,
                            step=2.5)  # fmt: skip
    mean, half = fit.runs.mean(axis=0), fit.grid <= fit.grid[-1] / 2
    label = "Resch" if name == "resch" else name
    png = out / f"{name}_prediction.png"
    with atomic_path(png) as tmp:
        save_fit_png(fit, tmp, title=f"PyGamiX's {label} structure, predicted (not fitted)")
    first = nrmse(fit.simulated[half], mean[half])
    caption = (
        f"Predicted with the mountain's materials: NRMSE {fit.error:.2f} over the whole "
        f"pull, {first:.2f} over its first half (default materials {fit.error_before:.2f})"
    )
    return Outputs(files=[png], images=[(png, caption)], numbers=[
        (f"{label}: NRMSE predicted, whole pull", f"{fit.error:.3f} (goal 0.25)"),
        (f"{label}: NRMSE predicted, first half", f"{first:.3f} (goal 0.25)"),
    ])  # fmt: skip


class Step(NamedTuple):
    """A section of the report: its key (the sub-folder), title, text and the commands it chains."""

    key: str
    title: str
    summary: str
    run: Callable[[Path, bool], list[Outputs]]
    columns: int = 0  # images per row in the report (0: as many as fit)


STEPS: list[Step] = [
    Step("fig2", "Fig. 2 - from a transition graph to a folded tessellation",
         "Five transition vectors drawn at p = 0.5 (unit width 36 mm, three copies) give the "
         "shape angles of eq. 1; the tessellation then folds rigidly and exactly (eqs. 2-3).",
         fig2),
    Step("fig3", "Fig. 3 - computational design of an origami robotic arm",
         "T_s = (0, 0); the tip must pass P_start = (250, 0) when flat and P_end = (50, 133.3) "
         "when folded, never touch the prohibited area (x >= 150, y >= 40) and stay out of "
         "the warning area (x >= 140, y >= 30). Fitness: eq. 5 with alpha = 120, evaluated "
         "over the fold range the printed arm reaches: b = 3, h = 2.2, t = 0.4 mm stop every "
         "crease at 146.6 deg (eq. 6), and the legs, folding faster than the main crease, get "
         "there first; T_e must meet P_end at that range's end. The winner must also be "
         "buildable at a 36 mm unit width.",
         fig3),
    Step("fig4", "Fig. 4 - dual-material printable structures",
         "Each panel is two exact B-rep halves (PLA infill wrapped in a TPU shell) with "
         "chamfers of eq. 6, joined by a PLA mid-layer in a continuous TPU crease sheet. "
         "Exported as four STL files, one STEP assembly and a 3MF whose PLA parts are on "
         "extruder 1 and TPU parts on extruder 2 (PrusaSlicer and Bambu/Orca).",
         fig4),
    Step("fig5", "Fig. 5 - folding by a twisted string actuator (DCQC and simulation)",
         "One ring TSA twists four strings that reach the sheet from guides on a ring rail and "
         "thread through panel holes on the side where each crease closes (above valleys, below "
         "mountains). Each quasi-static step takes up 0.1 mm of string (eq. 8); the DCQC model "
         "(rigid panels, inextensible strings) and the bar-and-hinge simulation fold the sheet "
         "from the same route file, in its mean pose, up to the printed sheet's fold limit "
         "(eq. 6 on its first crease, a leg).",
         fig5),
    Step("fig6", "Fig. 6 - a boat-like structure from a DXF file",
         "A 165.6 x 96.6 mm crease pattern drawn in CAD is read from DXF, checked, turned into "
         "printable parts with one hole per panel, fitted with an onboard TSA module, and folded "
         "by that TSA's strings in the bar-and-hinge simulation (any pattern, no kinematic "
         "model needed) until its creases reach eq. 6's limit.",
         fig6),
    Step("fig7", "Fig. 7 - the crawling robot: printed, walking in simulation, driven",
         "A crawler drawn for the project (examples/crawler): a body and four legs on mountain "
         "creases, an onboard TSA of four strings on each leg, blockers at 60 deg and the "
         "driver adapter, printed as one sheet with its parts in place. Its 32 s gait (fold "
         "ratios turned into TSA turns through the string model) runs in the bar-and-hinge "
         "simulator with the robot free on the ground (gravity, Coulomb friction 0.6); the "
         "paper's robot moved 63 mm per cycle. gait/ is the gait found by CMA-ES "
         "(design-gait, a demo budget: from the hand gait, which stays a candidate, two "
         "generations of four candidates) against the hand "
         "gait and the paper's 63 mm at frictions 0.4, 0.6 and 0.8 (gait/friction.png); "
         "docs/crawler.md gives the full search's figures. crawl/gait_sequence.toml is "
         "the hand gait as a "
         "drive sequence: mappings from the string model, and each servo's load, the TSA "
         "torque of the simulated crawl. The servo logs: examples/crawler_gait.toml (that "
         "file, made by the crawl job) on four emulated XL330 servos (Dynamixel Protocol "
         "2.0 over a pseudo-terminal), each carrying its simulated load. Last, the same robot "
         "exported to MuJoCo (panels as bodies, creases as hinges, strings as tendons, TSAs "
         "as actuators) and rendered off-screen mid-stride.",
         fig7),
    Step("fig8", "Fig. 8 - the designed arm, printed and folded by its strings",
         "The winner of Fig. 3 with the string route design-arm wrote for it: one onboard TSA "
         "on the base panel twists two strings that run along the arm through every panel of "
         "a row, sides by the DCQC rule. The bar-and-hinge simulation (2.2 mm panels, creases "
         "stopped at eq. 6's 146.6 deg) folds the printed sheet; each state, placed by its "
         "base panels, gives the arm's tip, drawn against the designed tip path, P_start, "
         "P_end and the areas. The sequence file that drives it is made from the DCQC model.",
         fig8),
    Step("gallery", "Gallery - patterns from other tools, folded",
         "Six crease patterns as Origami Simulator, the FOLD format's examples and PyGamiX "
         "wrote them (examples/gallery/, MIT), each scaled to 150 mm wide and folded by "
         "oc.fold at p = 0.3 and 0.7: in closed form where every interior vertex is a "
         "degree-4 vertex of a one-parameter folding, else by the general solver, which "
         "drives every mountain and valley crease toward its target on the bar-and-hinge "
         "model with stiff panels. Each row: the crease pattern, then the two folds.",
         gallery, columns=3),
    Step("calibration", "Measured - PyGamiX's mountain structure on the bench",
         "The paper's authors pulled the tendons of a printed mountain structure on a test "
         "machine at 1000 mm/min (three runs, PyGamiX's repository, MIT). The bar-and-hinge "
         "model pulls the same design's second tendon by the same length, with the default "
         "materials (a linear crease) and with those origami-cad calibrate fitted to the "
         "runs (a crease that softens to 0.32 of its stiffness by 60 deg, hole friction 0.50; "
         "examples/pygamix/materials_mountain.toml). With both tendons on one crosshead the "
         "first folds its strip shut near 65 mm and the model cannot follow the runs. "
         "The same materials then predict the diamond and the Resch structures of the same "
         "bench (not used in the fit): their first half within the goal, the whole pull not "
         "(the hole friction locks the model; docs/calibration.md).",
         calibration),
]  # fmt: skip


def _error_line(exc: Exception) -> str:
    """What the report says of a failed step: the message of a user-facing error, else
    the exception's public type and message."""
    if isinstance(exc, OrigamiCadError):
        return str(exc)
    kind = next(c.__name__ for c in type(exc).__mro__ if not c.__name__.startswith("_"))
    return f"{kind}: {exc}"


def run_step(step: Step, root: Path, quick: bool = False) -> StepReport:
    """Run one step into ``root/<key>/``; its report section, or the error it ended with."""
    t0 = time.perf_counter()
    try:
        done = Outputs()
        for out in step.run(root / step.key, quick):
            done.extend(out)
        rep = StepReport(step.key, step.title, summary=step.summary, numbers=done.numbers)
        rep.columns = step.columns
        shown = [(p.relative_to(root).as_posix(), caption) for p, caption in done.images]
        rep.images = [(p, c) for p, c in shown if not p.endswith(".glb")]
        rep.views = [(p, c) for p, c in shown if p.endswith(".glb")]
        rep.files = [p.relative_to(root).as_posix() for p in dict.fromkeys(done.files)]
    except Exception as exc:  # reported in the page; run_demo raises at the end
        rep = StepReport(step.key, step.title, error=_error_line(exc))
    rep.seconds = time.perf_counter() - t0
    return rep


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
    for step in STEPS:
        echo(f"[{step.key}] {step.run.__doc__.splitlines()[0]}")
        rep = run_step(step, out, quick)
        if rep.error:
            failed.append(step.key)
        echo(f"[{step.key}] {'FAILED' if rep.error else 'done'} in {rep.seconds:.1f} s")
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


@register
class Demo(Command):
    """Reproduce the paper's figures end to end into one HTML report (FOLDER/index.html)."""

    NAME = "demo"
    OPTIONS = (
        Option("folder", help="output folder; only this command's files are written into it, "
               "all else is kept", default="out", flag="--output", short="-o"),
        Option("quick", "flag", "reduced budget (for tests)"),
    )  # fmt: skip

    def prepare(self, a) -> None:
        """Refuse an output folder among the demo's inputs (``examples/`` or inside it)."""
        super().prepare(a)
        examples = examples_dir().resolve()
        out = Path(os.path.realpath(a.folder))
        if out == examples or examples in out.parents:
            raise OutputError(
                f"{a.folder}: the demo reads its inputs from {examples}; "
                "choose an output folder outside it"
            )

    def run(self, a) -> Outputs:
        return Outputs(files=[run_demo(a.folder, quick=a.quick)])
