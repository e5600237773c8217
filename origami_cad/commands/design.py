"""The arm design command: ``design-arm`` (CMA-ES, eq. 5)."""

from __future__ import annotations

import json
import time
from pathlib import Path

from origami_cad._fileio import atomic_write
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


def _route_header(design) -> str:
    """The comment lines of the winner's route.toml: the commands that read it."""
    return (
        "# The string route of best.toml (origami-cad design-arm): one onboard TSA on the\n"
        "# base panel twists two strings that run along the arm, parallel to the transition\n"
        "# vectors, through every panel of one row each; sides by the DCQC rule.\n"
        "#   origami-cad route best.toml route.toml -o route        (DCQC)\n"
        "#   origami-cad simulate best.toml route.toml -o sim       (bar-and-hinge)\n"
        "#   origami-cad arm-scene TASK best.toml route.toml -o fig8 (tip against P_end)\n"
        f"#   origami-cad sequence best.toml route.toml -o arm_fold.toml --keyframes 0:0 "
        f"20:{design.fold_ratio_end:.3f} 30:{design.fold_ratio_end:.3f} 40:0\n"
    )


def _chain_checked(results, task):
    """The designs with the winner first, the winner's strings, and the refused designs.

    Every design's route is built and folded by its strings (DCQC); a design whose route
    cannot be built, or whose strings stop short of its ``p_e``, is refused, with why. The
    winner is the first design in rank order that is not refused: a tied one when any is.
    """
    from origami_cad.design.arm_route import choose_arm_tsa
    from origami_cad.drive.from_model import AT_TOLERANCE

    refused: dict[int, str] = {}
    chosen = {}
    for design in results:
        strings = chosen[design.run] = choose_arm_tsa(design, task, header=_route_header(design))
        if strings.error is not None:
            refused[design.run] = f"its string route cannot be built: {strings.error}"
        elif float(strings.result.p[-1]) < design.fold_ratio_end - AT_TOLERANCE:
            refused[design.run] = (
                f"its strings fold it to p = {float(strings.result.p[-1]):.4f} only "
                f"({strings.result.stop}), short of its fold range's end p_e = "
                f"{design.fold_ratio_end:.4f}"
            )
    winner = next((d for d in results if d.run not in refused), None)
    if winner is None:
        lines = "; ".join(f"run {run}: {why}" for run, why in refused.items())
        raise DesignError(f"every design was refused: {lines}")
    return [winner, *(r for r in results if r is not winner)], chosen[winner.run], refused


def _results_json(results, task, settings, seconds: float, refused) -> dict:
    from origami_cad import __version__
    from origami_cad.design import task_to_dict
    from origami_cad.design.search import FITNESS_TIE, ties

    return {
        "origami_cad_version": __version__,
        "task": task_to_dict(task, settings),
        "seconds": seconds,
        "tie": {
            "rule": "designs within fitness_tolerance of the best tie; of those, the largest "
            "fold range p_e wins (within 1e-6), then the lowest run index; a design whose "
            "route cannot be built or whose strings cannot fold it to p_e is refused and "
            "never wins",
            "fitness_tolerance": FITNESS_TIE,
            "tied_runs": [r.run for r in ties(results)],
            "refused": {str(run): why for run, why in refused.items()},
        },
        "designs": [{**r.to_dict(), "refused": refused.get(r.run)} for r in results],
    }


def _write_arm_files(results, task, settings, seconds: float, stage: Path):
    """results.json, best.toml, the plots and route.toml; returns (files, designs ranked
    with the winner first, the winner's strings, the refused designs)."""
    from origami_cad.pattern.design import load_design
    from origami_cad.viz import save_pattern_png
    from origami_cad.viz.design_plots import save_convergence_png, save_trajectories_png

    files = [stage / n for n in ("results.json", "best.toml", "trajectories.png")]
    files += [stage / "convergence.png", stage / "best_pattern.png", stage / "route.toml"]
    results, strings, refused = _chain_checked(results, task)
    with atomic_write(files[-1], "w", encoding="utf-8") as fh:
        fh.write(strings.text)
    with atomic_write(files[0], "w", encoding="utf-8") as fh:
        json.dump(_results_json(results, task, settings, seconds, refused), fh, indent=1)
    with atomic_write(files[1], "w", encoding="utf-8") as fh:
        fh.write(_best_design_toml(results[0], task))
    save_trajectories_png(results, task, files[2])
    save_convergence_png(results, files[3])
    save_pattern_png(load_design(files[1]).pattern, files[4], labels=True)
    folded = strings.result if strings.error is None else strings.error
    return files, results, folded, refused


def _arm_numbers(best, settings, seconds: float, strings) -> list[tuple[str, str]]:
    """The key numbers of an arm design: the winner, its fold range and its strings."""
    t = best.terms
    folded = (
        f"to p = {strings.p[-1]:.4f} in {strings.turns[-1]:.1f} TSA turns ({strings.stop})"
        if not isinstance(strings, Exception)
        else f"not simulated: {strings}"
    )
    return [
        ("runs x generations", f"{settings.runs} x {settings.max_generations}"),
        ("search time", f"{seconds:.1f} s"),
        ("best fitness (max 60)", f"{best.fitness:.3f} (run {best.run}, EF_0 = {best.entry_flag})"),
        ("|T_e(0) - P_start|", f"{t.d_start:.3g} mm"),
        ("fold range the printed arm reaches", f"p = 0 .. {best.fold_ratio_end:.4f}"),
        ("|T_e(p_e) - P_end| at its end", f"{t.d_end:.3g} mm"),
        ("crease limit (eq. 6)", f"{t.crease_limit:.1f} deg at b = {best.bias:.3g} mm"),
        ("improper states N", str(t.improper_states)),
        ("lengths l_0..l_n", ", ".join(f"{v:.1f}" for v in best.lengths) + " mm"),
        ("shape angles", ", ".join(f"{v:.1f}" for v in best.shape_angles) + " deg"),
        ("route.toml: its strings fold the arm (DCQC)", folded),
    ]


def _tie_line(results, refused: dict[int, str]) -> str:
    """Which runs tie for the best, and how the winner was told apart from them."""
    from origami_cad.design.search import ties

    tied = ties(results)
    if len(tied) < 2:
        return f"none (run {results[0].run} alone)"
    runs = ", ".join(
        f"{r.run} (p_e {r.fold_ratio_end:.4f}{', refused' if r.run in refused else ''})"
        for r in tied
    )
    return f"runs {runs}: run {results[0].run} wins with the largest fold range it can be folded to"


def _summary(best, settings, seconds: float) -> str:
    t = best.terms
    return (
        f"best of {settings.runs} runs: run {best.run}, f = {best.fitness:.4f}, "
        f"|T_e(0) - P_start| = {t.d_start:.3g} mm, |T_e(p_e) - P_end| = "
        f"{t.d_end:.3g} mm at p_e = {best.fold_ratio_end:.4f} (the fold limit), "
        f"N = {t.improper_states} ({seconds:.1f} s)"
    )


@register
class DesignArm(Command):
    """CMA-ES arm design (eq. 5): results.json, best.toml and plots into ``folder``.

    The fitness is evaluated over the fold range the printed arm reaches (the
    task's ``[fabrication]`` b, h, t of eq. 6 or ``fold_limit``); best.toml's
    comments give that range and the ``fabricate`` command that builds the winner
    with its fabrication parameters. ``runs``, ``seed`` and ``max_generations``
    override the task's ``[search]`` table; ``scheduler`` runs the runs on a Dask
    cluster (results identical to the local process pool).
    """

    NAME, INPUTS, OUTPUT, PROGRESS = "design-arm", ("task",), "folder", "CMA-ES generations"
    FILES = ("results.json", "best.toml", "trajectories.png", "convergence.png")
    FILES += ("best_pattern.png", "route.toml")
    OPTIONS = (
        Option("runs", "int", "override the task's [search] runs", min=1, max=MAX_RUNS),
        Option("seed", "int", "seed (overrides [search])", min=0, max=2**32 - 1),
        Option("max_generations", "int", "override [search] value", min=1, max=MAX_GENERATIONS),
        Option("scheduler", help="Dask scheduler", metavar="ADDR"),
    )

    def run(self, a) -> Outputs:
        import dataclasses

        from origami_cad.design import design_arm, load_task

        arm_task, settings = load_task(a.task)
        changes = {k: getattr(a, k) for k in ("runs", "seed", "max_generations")}
        given = {k: v for k, v in changes.items() if v is not None}
        settings = dataclasses.replace(settings, **given)
        t0 = time.perf_counter()
        with open_executor(a.scheduler) as executor:
            results = design_arm(arm_task, settings, executor=executor, progress=a.progress)
        seconds = time.perf_counter() - t0
        if not results:
            raise DesignError(
                f"{a.task}: no feasible design: every run's chain touched a prohibited area; "
                "relax the obstacles or the length range"
            )
        with self.stage(a) as stage:
            written = _write_arm_files(results, arm_task, settings, seconds, stage)
            files = moved(written[0], stage, a.folder)
        _, results, strings, refused = written
        numbers = _arm_numbers(results[0], settings, seconds, strings)
        tied = _tie_line(results, refused)
        numbers.insert(3, ("runs tied for the best (eq. 5 within 1e-3)", tied))
        captions = ["Top designs: chains and the path of T_e"]
        captions += ["Best fitness per generation, one line per run", "The winner's crease pattern"]
        messages = [_summary(results[0], settings, seconds), f"tied for the best: {tied}"]
        messages += [f"refused: run {run}: {why}" for run, why in refused.items()]
        return Outputs(
            files=files,
            images=list(zip(files[2:5], captions, strict=True)),
            numbers=numbers,
            messages=[*messages, *map(wrote, files)],
            result=results,
        )
