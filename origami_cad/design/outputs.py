"""Files written by an arm design: results.json, best.toml (a design file)."""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from pathlib import Path

from origami_cad import __version__
from origami_cad._fileio import atomic_write
from origami_cad.design.search import ArmDesign
from origami_cad.design.task import ArmTask, SearchSettings, task_to_dict
from origami_cad.errors import DesignError

__all__ = ["best_design_toml", "write_design_outputs"]


def best_design_toml(
    design: ArmDesign, task: ArmTask, unit_width: float = 36.0, copies: int = 3
) -> str:
    """The winner as a design file (``kind = "transition-graph"``) that every command reads."""
    lengths = ", ".join(f"{v:.6f}" for v in design.lengths)
    angles = ", ".join(f"{v:.6f}" for v in design.shape_angles)
    return (
        f"# Best arm design of run {design.run}: fitness {design.fitness:.4f} (eq. 5)\n"
        f"# T_e(0) is {design.terms.d_start:.3f} mm from P_start, T_e(pi) "
        f"{design.terms.d_end:.3f} mm from P_end, {design.terms.improper_states} "
        "improper states\n"
        "[pattern]\n"
        'kind = "transition-graph"\n'
        f"unit_width = {task.unit_width or unit_width}   # mm\n"
        f"copies = {copies}\n"
        f"entry_flag = {design.entry_flag}\n"
        f"start = [{task.start[0]}, {task.start[1]}]\n"
        f"lengths = [{lengths}]   # mm\n"
        f"shape_angles = [{angles}]   # deg\n"
        f"hypar_base = {'true' if task.hypar_base else 'false'}\n"
    )


def write_design_outputs(
    results: Sequence[ArmDesign],
    task: ArmTask,
    settings: SearchSettings,
    out_dir: str | os.PathLike[str],
    *,
    seconds: float | None = None,
) -> dict[str, Path]:
    """Write results.json, best.toml, trajectories.png and convergence.png into ``out_dir``."""
    if not results:
        raise DesignError(
            "no feasible design: every run's chain touched a prohibited area; relax the "
            "obstacles or the length range"
        )
    from origami_cad.viz.design_plots import save_convergence_png, save_trajectories_png

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    data = {
        "origami_cad_version": __version__,
        "task": task_to_dict(task, settings),
        "seconds": seconds,
        "designs": [r.to_dict() for r in results],
    }
    paths = {
        "results": out / "results.json",
        "best": out / "best.toml",
        "trajectories": out / "trajectories.png",
        "convergence": out / "convergence.png",
    }
    with atomic_write(paths["results"], "w", encoding="utf-8") as fh:
        json.dump(data, fh, indent=1)
    with atomic_write(paths["best"], "w", encoding="utf-8") as fh:
        fh.write(best_design_toml(results[0], task))
    save_trajectories_png(results, task, paths["trajectories"])
    save_convergence_png(results, paths["convergence"])
    return paths
