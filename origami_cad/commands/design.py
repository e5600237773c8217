"""The arm design command: ``design-arm`` (CMA-ES, eq. 5)."""

from __future__ import annotations

import time
from pathlib import Path

from origami_cad._fileio import atomic_write
from origami_cad._toml import json_text
from origami_cad.commands._base import Command, Option, Outputs, moved, register, wrote
from origami_cad.errors import DesignError
from origami_cad.parallel import open_executor

__all__: list[str] = []

# the task file's limits (origami_cad.design.task; not imported here: --help stays fast)
MAX_RUNS, MAX_GENERATIONS = 10_000, 1_000_000


def _best_design_toml(design, task, copies: int = 3) -> str:
    """The winner as a design file (``kind = "transition-graph"``) that every command reads.

    Its comments state the fold range the printed arm reaches and the ``fabricate``
    command that builds it with the fabrication parameters it was designed for.
    """
    from origami_cad.pattern.design import dump_design

    terms, p_e = design.terms, design.fold_ratio_end
    if task.fold_limit is not None:
        fab = f"# designed for creases that fold up to {task.fold_limit:g} deg (fold_limit)\n"
        build = "origami-cad fabricate best.toml -o fab" + (
            f" --theta-max {task.fold_limit:g}" if task.fold_limit < 180 else ""
        )
    else:
        fab = (
            f"# designed for b = {design.bias:.4g} mm, h = {task.height:g} mm, t = "
            f"{task.thickness:g} mm: every crease stops at {terms.crease_limit:.1f} deg (eq. 6)"
            f"{' (b co-designed)' if task.codesign else ''}\n"
        )
        build = (
            f"origami-cad fabricate best.toml -o fab --bias {design.bias:.4g} "
            f"--height {task.height:g} --thickness {task.thickness:g}"
        )
    return (
        f"# Best arm design of run {design.run}: fitness {design.fitness:.4f} (eq. 5)\n"
        f"# T_e(0) is {terms.d_start:.3f} mm from P_start; at p = {p_e:.4f}, the end of the "
        f"fold range the printed arm reaches, T_e is {terms.d_end:.3f} mm from P_end; "
        f"{terms.improper_states} improper states\n"
        f"{fab}"
        f"# build it with: {build}\n"
    ) + dump_design(design.tg(task, task.unit_width or 36.0, copies), digits=6)


def _write_arm_files(search, task, settings, seconds: float, stage: Path) -> list[Path]:
    """results.json, best.toml, the plots and route.toml of an arm search into ``stage``."""
    from origami_cad.pattern.design import load_design
    from origami_cad.viz import save_pattern_png
    from origami_cad.viz.design_plots import save_convergence_png, save_trajectories_png

    files = [stage / n for n in ("results.json", "best.toml", "trajectories.png")]
    files += [stage / "convergence.png", stage / "best_pattern.png"]
    if search.strings.route is not None:  # else results.json says why it has none
        files.append(stage / "route.toml")
        with atomic_write(files[-1], "w", encoding="utf-8") as fh:
            fh.write(search.strings.text)
    with atomic_write(files[0], "w", encoding="utf-8") as fh:
        fh.write(
            json_text(search.to_dict(task, settings, seconds), files[0].name, DesignError, indent=1)
        )
    with atomic_write(files[1], "w", encoding="utf-8") as fh:
        fh.write(_best_design_toml(search.winner, task))
    designs = list(search)
    save_trajectories_png(designs, task, files[2])
    save_convergence_png(designs, files[3])
    save_pattern_png(load_design(files[1]).pattern, files[4], labels=True)
    return files


def _arm_numbers(search, settings, seconds: float) -> list[tuple[str, str]]:
    """The key numbers of an arm design: the winner, its fold range and its strings."""
    best, strings = search.winner, search.strings
    t = best.terms
    folded = (
        f"to p = {strings.result.p[-1]:.4f} in {strings.result.turns[-1]:.1f} TSA turns "
        f"({strings.result.stop})"
        if strings.error is None
        else f"not simulated: {strings.error}"
    )
    return [
        ("runs x generations", f"{settings.runs} x {settings.max_generations}"),
        ("search time", f"{seconds:.1f} s"),
        ("best fitness (max 60)", f"{best.fitness:.3f} (run {best.run}, EF_0 = {best.entry_flag})"),
        ("runs tied for the best (eq. 5 within 1e-3)", search.tie_line()),
        ("|T_e(0) - P_start|", f"{t.d_start:.3g} mm"),
        ("fold range the printed arm reaches", f"p = 0 .. {best.fold_ratio_end:.4f}"),
        ("|T_e(p_e) - P_end| at its end", f"{t.d_end:.3g} mm"),
        ("crease limit (eq. 6)", f"{t.crease_limit:.1f} deg at b = {best.bias:.3g} mm"),
        ("improper states N", str(t.improper_states)),
        ("lengths l_0..l_n", ", ".join(f"{v:.1f}" for v in best.lengths) + " mm"),
        ("shape angles", ", ".join(f"{v:.1f}" for v in best.shape_angles) + " deg"),
        ("route.toml: its strings fold the arm (DCQC)", folded),
    ]


@register
class DesignArm(Command):
    """CMA-ES arm design (eq. 5): results.json, best.toml and plots into ``folder``.

    The fitness is evaluated over the fold range the printed arm reaches (the
    task's ``[fabrication]`` b, h, t of eq. 6, or its limit in degrees); best.toml's
    comments give that range and the ``fabricate`` command that builds the winner
    with its fabrication parameters. ``runs``, ``seed`` and ``max_generations``
    override the task's ``[search]`` table; ``scheduler`` runs the runs on a Dask
    cluster (results identical to the local process pool).
    """

    NAME, INPUTS, OUTPUT, PROGRESS = "design-arm", ("task",), "folder", "CMA-ES generations"
    FILES = ("results.json", "best.toml", "trajectories.png", "convergence.png")
    FILES += ("best_pattern.png", "route.toml")
    OPTIONS = (
        Option(
            "runs",
            "int",
            "independent CMA-ES runs (default: the task's [search] runs)",
            min=1,
            max=MAX_RUNS,
            metavar="N",
        ),
        Option(
            "seed",
            "int",
            "seed of the first run (default: the task's [search] seed)",
            min=0,
            max=2**32 - 1,
            metavar="N",
        ),
        Option(
            "max_generations",
            "int",
            "CMA-ES generations per run at most (default: the task's [search] value)",
            min=1,
            max=MAX_GENERATIONS,
            metavar="N",
        ),
        Option(
            "scheduler",
            help="address of a Dask scheduler to run the runs on (default: a local process pool)",
            metavar="ADDR",
        ),
    )

    def run(self, a) -> Outputs:
        import dataclasses
        import warnings

        from origami_cad.design import design_arm, load_task
        from origami_cad.errors import DesignWarning

        arm_task, settings = load_task(a.task)
        given = {k: getattr(a, k) for k in ("runs", "seed", "max_generations")}
        settings = dataclasses.replace(
            settings, **{k: v for k, v in given.items() if v is not None}
        )
        t0 = time.perf_counter()
        with open_executor(a.scheduler) as executor, warnings.catch_warnings():
            warnings.simplefilter("ignore", DesignWarning)  # on stderr below, as one line
            search = design_arm(arm_task, settings, executor=executor, progress=a.progress)
        seconds = time.perf_counter() - t0
        if search.winner is None:
            raise DesignError(
                f"{a.task}: no feasible design: every run's chain touched a prohibited area; "
                "relax the obstacles or the length range"
            )
        with self.stage(a) as stage:
            written = _write_arm_files(search, arm_task, settings, seconds, stage)
            files = moved(written, stage, a.folder)
        captions = ["Top designs: chains and the path of T_e"]
        captions += ["Best fitness per generation, one line per run", "The winner's crease pattern"]
        messages = [
            search.summary(settings.runs, seconds),
            f"tied for the best: {search.tie_line()}",
        ]
        messages += [f"refused: run {run}: {why}" for run, why in search.refused.items()]
        return Outputs(
            files=files,
            images=list(zip(files[2:5], captions, strict=True)),
            numbers=_arm_numbers(search, settings, seconds),
            messages=[*messages, *map(wrote, files)],
            warnings=[w for w in [search.shortfall()] if w is not None],
            result=search,
        )
