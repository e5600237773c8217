"""``calibrate``: the model's crease stiffness and hole friction fitted to measured
force-against-pull curves (a test machine's runs, or ``drive``'s logs)."""

from __future__ import annotations

from pathlib import Path

from origami_cad._fileio import atomic_write
from origami_cad._toml import json_text
from origami_cad.commands._base import SIZING, Command, Option, Outputs, register, wrote
from origami_cad.commands.pull import MATERIALS, materials_of
from origami_cad.errors import SimulationError

__all__ = ["Calibrate"]

#: the parameters as the command line names them (the library's names with underscores)
_FIT = ("crease-stiffness", "hole-friction")
_CHOICES = (*_FIT, "crease-softening")


@register
class Calibrate(Command):
    """Fit the materials to measured force-pull runs: materials.toml, calibration.json, fit.png.

    Each RUN is a PyGamiX 4-column bench file (t - 0.1, t, pull mm, force N), a CSV file
    with the header of the pull.csv that simulate --pull writes (pull in mm, tension in
    N), or a drive log (the servo's current through its torque and the ring TSA's eq. 8,
    --x-dis mm from the TSA to the first hole; default: the first tendon's anchor to its
    first hole). The design carries its tendons (a PyGamiX description). --fit names the
    parameters fitted (crease-stiffness, N mm/rad per mm; hole-friction; crease-softening,
    the crease's stiffness factor from 60 deg on); --materials gives the starting values.
    """

    NAME, INPUTS, OUTPUT, PROGRESS = "calibrate", ("design",), "folder", "calibrating"
    ARGS = ("design", "runs", "folder")
    FILES = ("materials.toml", "calibration.json", "fit.png")
    OPTIONS = (
        Option("runs", help="measured runs (CSV)", nargs="+", positional=True, metavar="RUN"),
        Option("fit", help="parameters fitted", nargs="+", choices=_CHOICES, default=_FIT),
        Option("step", "float", "the grid of pulls compared", "mm", default=2.0, min=0.1,
               max=100.0),
        Option("evaluations", "int", "least-squares evaluations at most (a Jacobian and the "
               "coarse start cost more simulations: calibration.json counts them)", default=40,
               min=3, max=1000),
        Option("x_dis", "float", "a drive log's TSA to its first hole", "mm", min=0,
               max=1e4, open_min=True),
        Option("tendons", "int", "pull only these tendons (1-based; default: all)", nargs="+",
               min=1, max=1000),
        MATERIALS,
        *SIZING,
    )  # fmt: skip

    def prepare(self, a) -> None:
        """The fitted parameters by the library's names; then the outputs' checks."""
        a.fit = [name.replace("-", "_") for name in a.fit]
        super().prepare(a)

    def inputs(self, a):
        return [a.design, *a.runs, *([a.materials] if a.materials else [])]

    def run(self, a) -> Outputs:
        from origami_cad.simulation.calibrate import calibrate, design_tendons, load_runs
        from origami_cad.simulation.materials import dump_materials
        from origami_cad.viz.calibration_plots import save_fit_png

        loaded, warned = self.load(a, a.design)
        route = design_tendons(loaded.pattern, a.design)
        runs = load_runs(a.runs, route=route, x_dis=a.x_dis)
        fit = calibrate(loaded.pattern, route, runs, materials_of(a), fit=tuple(a.fit),
                        step=a.step, max_evaluations=a.evaluations,
                        names=[Path(r).name for r in a.runs],
                        tendons=tuple(a.tendons) if a.tendons else None)  # fmt: skip
        header = f"# calibrated by origami-cad calibrate on {len(runs)} runs of {a.design}"
        with self.stage(a, loaded) as stage:
            with atomic_write(stage / self.FILES[0], "w", encoding="utf-8") as fh:
                fh.write(dump_materials(fit.materials, header=header))
            with atomic_write(stage / self.FILES[1], "w", encoding="utf-8") as fh:
                fh.write(json_text(fit.to_dict(), "calibration.json", SimulationError, indent=1))
            save_fit_png(fit, stage / self.FILES[2], title=f"{Path(a.design).name}")
        files = [Path(a.folder) / n for n in self.FILES]
        return Outputs(
            files=files,
            images=[(files[2], "Measured force against pull, simulated before and after")],
            numbers=[
                *((k, f"{v:.4g} +- {fit.sigma[k]:.2g}") for k, v in fit.values.items()),
                ("NRMSE against the runs' mean", f"{fit.error:.3f} (start {fit.error_before:.3f})"),
                ("simulations", str(fit.evaluations)),
            ],
            messages=[*warned, fit.summary(), wrote(a.folder, self.FILES)],
            result=fit,
        )
