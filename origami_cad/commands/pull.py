"""``simulate``'s set-up (the route from a file or from the design, the materials) and its
test-machine pull (``--pull``): pull.csv, states.fold, simulation.json."""

from __future__ import annotations

import time
from pathlib import Path
from types import SimpleNamespace

from origami_cad._fileio import atomic_write
from origami_cad._toml import json_text
from origami_cad.commands._base import Command, Option, Outputs, wrote
from origami_cad.errors import OptionsError, SimulationError, StringsError

__all__ = ["MATERIALS", "materials_of", "robot_materials", "simulation_setup", "write_pull"]

#: The ``--materials FILE`` option of the commands that simulate.
MATERIALS = Option("materials", help="materials file (materials.toml)", metavar="FILE")


def materials_of(a: SimpleNamespace):
    """The materials file ``a.materials`` read (``Materials``), or None when not given."""
    if getattr(a, "materials", None) is None:
        return None
    from origami_cad.simulation.materials import load_materials

    return load_materials(a.materials)


def robot_materials(a: SimpleNamespace, robot):
    """A robot's simulation parameters with the materials file ``a.materials`` (None: the
    robot's own, :func:`~origami_cad.crawler.walk.robot_params`)."""
    materials = materials_of(a)
    if materials is None:
        return None
    from origami_cad.crawler.walk import robot_params

    return robot_params(robot, **materials.overrides())


def simulation_setup(cmd: Command, a: SimpleNamespace):
    """``(design, warnings, pattern, route, params)`` of ``simulate``'s arguments.

    The route is the route file, else the tendons the design carries (a PyGamiX
    description); the parameters are ``a.params``, else the materials file's (or the
    route's sheet) with the options' loads.
    """
    from origami_cad.simulation import SimulationParams
    from origami_cad.simulation.paths import with_fold_path
    from origami_cad.strings import load_route
    from origami_cad.strings.route import route_from_pattern

    loaded, warned = cmd.load(a, a.pattern)
    cp = loaded.pattern
    if a.route is not None:
        spec = load_route(a.route, cp)
    else:
        spec = route_from_pattern(cp)
        if spec is None:
            raise StringsError(
                f"{a.pattern}: the design carries no tendons; give a route file (ROUTE)"
            )
    if a.fixed_panel is not None and a.fixed_panel not in cp.face_labels:
        raise OptionsError(f"--fixed-panel: no panel labelled {a.fixed_panel!r} in {a.pattern}")
    # the fold ratio p of each state, and the route's p_max, within the command's time limit
    loaded = with_fold_path(loaded, deadline=time.monotonic() + a.time_limit)
    given = {k: getattr(a, k) for k in ("gravity", "ground", "friction")}
    loads = {k: v for k, v in given.items() if v is not None}
    if a.params is not None:
        return loaded, warned, cp, spec, a.params
    materials = materials_of(a)
    if materials is not None:
        params = SimulationParams.for_route(spec, **materials.overrides(), **loads)
    else:
        params = SimulationParams.for_route(spec, **loads)
    return loaded, warned, cp, spec, params


def write_pull(cmd: Command, a: SimpleNamespace, loaded, spec, params, warned) -> Outputs:
    """Pull the strings by ``a.pull`` mm and write the pull's files."""
    from origami_cad.pattern import folded_frame, write_fold
    from origami_cad.simulation.pull import simulate_pull

    cp = loaded.pattern
    run = simulate_pull(
        cp,
        spec,
        a.pull,
        params,
        rate=a.rate,
        step=a.pull_step,
        fixed_panel=a.fixed_panel,
        progress=a.progress,
    )
    sim = run.result
    frames = [
        folded_frame(x, f, f"pull = {p:.2f} mm")
        for x, f, p in zip(sim.states, sim.fold_angles, run.pull, strict=True)
    ]
    names = cmd.PULL_FILES
    with cmd.stage(a, loaded) as stage:
        with atomic_write(stage / names[0], "w", encoding="utf-8") as fh:
            fh.write(run.to_csv())
        write_fold(cp, stage / names[1], frames=frames)
        with atomic_write(stage / names[2], "w", encoding="utf-8") as fh:
            fh.write(json_text(run.to_dict(), names[2], SimulationError, indent=1))
    peak = int(run.tension.argmax())
    return Outputs(
        files=[Path(a.folder) / n for n in names],
        numbers=[
            ("states", str(len(run))),
            ("peak tension", f"{run.tension[peak]:.3g} N at {run.pull[peak]:.3g} mm"),
            ("tension at the end", f"{run.tension[-1]:.3g} N at {run.pull[-1]:.3g} mm"),
        ],
        messages=[
            *warned,
            f"{len(run)} states pulled to {run.pull[-1]:.3g} mm at {run.rate:.3g} mm/s; peak "
            f"{run.tension[peak]:.3g} N at {run.pull[peak]:.3g} mm, {run.tension[-1]:.3g} N "
            "at the end",
            wrote(a.folder, names),
        ],
        result=run,
    )
