"""Calibration: one pull of PyGamiX's mountain structure (83.6 mm); a whole fit on its three runs.

The pull as the bench pulls it (2 mm a state, the calibration's grid; goal < 10 s); the
calibration as ``origami-cad calibrate`` runs it by default (crease stiffness and hole
friction, at most 40 simulations; goal < 2 min on 2 cores), and the fit of
``examples/pygamix/materials_mountain.toml`` (the second tendon, the crease's softening
too, a 3 mm grid). The measured runs are the
project's shared data (``../shared/data/pygamix``, see its README); without them the
fit is left out. CPU time beside every wall time.
"""

from __future__ import annotations

from pathlib import Path

from clock import Clock, cpu_row

from origami_cad.pattern import read_pattern
from origami_cad.simulation.calibrate import calibrate, load_runs
from origami_cad.simulation.materials import Materials
from origami_cad.simulation.pull import simulate_pull
from origami_cad.strings.route import route_from_pattern

ROOT = Path(__file__).resolve().parents[1]
MOUNTAIN = ROOT / "tests" / "data" / "pygamix" / "descriptionData" / "f-mountain-big-fix-new.json"
RUNS = ROOT.parent / "shared" / "data" / "pygamix" / "experiment" / "mountain"


def run() -> list[tuple[str, float, str]]:
    cp = read_pattern(MOUNTAIN)
    route = route_from_pattern(cp)
    clock = Clock()
    pull = simulate_pull(cp, route, 83.6, Materials().simulation_params(), step=2.0)
    wall, cpu = clock.lap()
    rows = [
        (f"mountain pull, 83.6 mm in {len(pull) - 1} states: s wall", wall, "goal < 10 s"),
        cpu_row(cpu),
    ]
    files = sorted(RUNS.glob("*.csv"))
    if not files:
        return [*rows, ("calibration: no measured runs at ../shared/data/pygamix", 0.0, "")]
    clock.lap()
    fit = calibrate(cp, route, load_runs(files))
    wall, cpu = clock.lap()
    rows += [
        (f"calibration, {fit.evaluations} simulations: s wall", wall, "goal < 120 s"),
        cpu_row(cpu),
        ("  its NRMSE against the runs' mean", fit.error, "goal < 0.10"),
    ]
    fit = calibrate(cp, route, load_runs(files), Materials(crease_stiffness_given=0.147,
                    hole_friction=0.3, law_angles=(0.0, 60.0), law_factors=(1.0, 0.58)),
                    fit=("crease_stiffness", "hole_friction", "crease_softening"), step=3.0,
                    max_evaluations=25, tendons=(2,))  # fmt: skip
    wall, cpu = clock.lap()
    return [
        *rows,
        (f"tendon 2, softening fitted, {fit.evaluations} simulations: s wall", wall, "< 120 s"),
        cpu_row(cpu),
        ("  its NRMSE against the runs' mean", fit.error, "goal < 0.10"),
    ]
