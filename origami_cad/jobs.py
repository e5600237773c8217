"""One function per command: each computes and writes everything its command produces.

``origami-cad COMMAND`` only parses its arguments into the matching ``run_*``
function, and ``origami-cad demo`` (:mod:`origami_cad.demo`) only chains these
functions and writes the report, so a command and its step of the demo always
write the same files. Each job calls the same public functions a user calls.

Every job follows the output rules of ``docs/outputs.md``: outputs are checked
against the inputs before any work (:func:`~origami_cad._fileio.check_outputs`),
a folder receives only the job's own files, all at once at the end
(:func:`~origami_cad._fileio.atomic_directory`), and a single file is replaced
atomically. A job returns an :class:`Outputs` record of what it wrote and found.

>>> import tempfile, pathlib
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> out = run_pattern("examples/miura_6x4.toml", [folder / "cp.fold"])
>>> [p.name for p in out.files], dict(out.numbers)["panels"]
(['cp.fold'], '24')
"""

from __future__ import annotations

import contextvars
import functools
import json
import math
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from origami_cad._fileio import (
    atomic_directory,
    atomic_path,
    atomic_write,
    check_outputs,
    finishing,
)
from origami_cad._names import one_line
from origami_cad.errors import (
    DesignError,
    DriveError,
    OptionsError,
    OrigamiCadError,
    SimulationError,
    StringsError,
)
from origami_cad.parallel import open_executor

__all__ = [
    "Outputs",
    "fabrication_params",
    "parameter_default",
    "run_arm_scene",
    "run_check",
    "run_convert",
    "run_crawl",
    "run_design_arm",
    "run_drive",
    "run_emulate",
    "run_fabricate",
    "run_fold",
    "run_mjcf",
    "run_part",
    "run_pattern",
    "run_plan_route",
    "run_robot",
    "run_route",
    "run_sequence",
    "run_simulate",
    "run_tg",
]

PathLike = str | os.PathLike[str]
FOLD_SUFFIXES = (".fold", ".png", ".gif", ".glb", ".step")
MAX_FRAMES = 10_000  # folded states in one file or animation
GIF_FRAMES = 30  # frames of a simulation's animation


@dataclass
class Outputs:
    """What a job wrote and what it found.

    Attributes
    ----------
    files : list of Path
        Every file written, in order.
    images : list of (Path, str)
        The pictures among them (.png, .gif, and .glb 3D views), with a caption.
    numbers : list of (str, str)
        Key results, name and value with its unit.
    messages : list of str
        Lines for the user: summary and warnings.
    result : object
        The library result the files were made from (a ``DCQCResult``,
        ``Fabrication``, list of ``ArmDesign``...), or ``None``.
    status : int
        0, or 1 when the job ran but its answer is negative (a pattern with
        errors, a routing that never folds).
    """

    files: list[Path] = field(default_factory=list)
    images: list[tuple[Path, str]] = field(default_factory=list)
    numbers: list[tuple[str, str]] = field(default_factory=list)
    messages: list[str] = field(default_factory=list)
    result: Any = None
    status: int = 0

    def extend(self, other: Outputs) -> Outputs:
        """Add another job's outputs to these (for chained jobs); returns ``self``.

        A number two jobs both report (the same name and value: a pattern's size, read
        by each) is kept once.
        """
        self.files += other.files
        self.images += other.images
        self.numbers += [n for n in other.numbers if n not in self.numbers]
        self.messages += other.messages
        return self


# the parameter classes whose fields a job also takes as keywords
_KEYWORD_PARAMS = {
    "run_fabricate": ("origami_cad.fabrication.params", "FabricationParams"),
    "run_simulate": ("origami_cad.simulation.model", "SimulationParams"),
}


def parameter_default(job: Callable, name: str) -> Any:
    """The default of a job's parameter ``name``, from its signature or its parameter class.

    ``None`` when the parameter has no default (or is not the job's).

    >>> parameter_default(run_fold, "ratio"), parameter_default(run_fabricate, "height")
    (0.5, 2.2)
    """
    import dataclasses
    import importlib
    import inspect

    param = inspect.signature(job).parameters.get(name)
    if param is not None and param.default not in (None, param.empty):
        return param.default
    if job.__name__ not in _KEYWORD_PARAMS:
        return None
    module, cls = _KEYWORD_PARAMS[job.__name__]
    fields = dataclasses.fields(getattr(importlib.import_module(module), cls))
    found = {f.name: f.default for f in fields if f.default is not dataclasses.MISSING}
    return found.get(name)


def _is_stream(path: PathLike) -> bool:
    """A device or pipe (``/dev/stdout``, a FIFO): written into, whatever its name."""
    import stat

    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return stat.S_ISCHR(mode) or stat.S_ISFIFO(mode)


def _check_suffix(path: PathLike, allowed: Sequence[str], what: str) -> None:
    if len(allowed) == 1 and _is_stream(path):
        return  # one possible format: a device or pipe needs no extension
    if Path(os.path.realpath(path)).suffix.lower() not in allowed:  # a link: its file's name
        raise OptionsError(f"{path}: {what} is written as {', '.join(allowed)} (by its extension)")


def _pattern_suffixes() -> tuple[str, ...]:
    """What a pattern is written as: the registered formats' suffixes, and .png."""
    from origami_cad.pattern.formats import WRITERS

    return (*WRITERS, ".png")


def _sources(*items) -> list:
    """Input paths, and the file a design was read from, that no output may replace."""
    return [s for s in (getattr(i, "source", i) for i in items) if s is not None]


def _moved(files: Sequence[Path], stage: Path, folder: PathLike) -> list[Path]:
    """Where the files written into ``stage`` are once in ``folder``."""
    return [Path(folder) / Path(f).relative_to(stage) for f in files]


def _pattern_numbers(cp) -> list[tuple[str, str]]:
    n_m, n_v = int((cp.assignments == "M").sum()), int((cp.assignments == "V").sum())
    return [
        ("panels", str(len(cp.faces))),
        ("creases (M / V)", f"{n_m} / {n_v}"),
        (
            "pattern size",
            f"{cp.bounds[2] - cp.bounds[0]:.1f} x {cp.bounds[3] - cp.bounds[1]:.1f} mm",
        ),
    ]


def _write_pattern_file(cp, out: Path, labels: bool = False) -> None:
    from origami_cad.pattern import write_pattern
    from origami_cad.viz import save_pattern_png

    if out.suffix.lower() == ".png":
        save_pattern_png(cp, out, labels=labels)
    else:
        write_pattern(cp, out)


_SIZE_NOTES: contextvars.ContextVar[list[str] | None] = contextvars.ContextVar(
    "size_notes", default=None
)


def _size_noted(job: Callable) -> Callable:
    """Decorate a job that reads patterns by :func:`_sized_source`: an error it raises
    carries (``add_note``) the size warnings of the patterns read, since a pattern read
    at the wrong scale (1 mm across) fails far from the reader, where nothing says why."""

    @functools.wraps(job)
    def wrapper(*args, **kwargs):
        token = _SIZE_NOTES.set([])
        try:
            return job(*args, **kwargs)
        except OrigamiCadError as exc:
            for note in _SIZE_NOTES.get() or ():
                exc.add_note(note)
            raise
        finally:
            _SIZE_NOTES.reset(token)

    return wrapper


def _sized_source(design: PathLike, unit=None, scale=None, width=None):
    """``(Design, warnings)``: a design or pattern file, an imported pattern sized by
    ``unit``/``scale``/``width``; the warnings name an implausible size."""
    from origami_cad.pattern import size_warnings
    from origami_cad.pattern.design import load_pattern_source

    loaded = load_pattern_source(design, unit=unit, scale=scale, width=width)
    warned = size_warnings(loaded.pattern)
    notes = _SIZE_NOTES.get()
    if notes is not None:
        notes += [f"note: {w}" for w in warned]
    return loaded, [f"warning: {w}" for w in warned]


# --------------------------------------------------------------------------- patterns


def run_convert(
    source: PathLike,
    output: PathLike,
    *,
    labels: bool = False,
    unit: str | None = None,
    scale: float | None = None,
    width: float | None = None,
) -> Outputs:
    """Read a pattern (.fold/.dxf/.svg) and write it as .fold, .dxf, .svg or a .png picture.

    ``unit``, ``scale`` and ``width`` size an imported pattern (``read_pattern``).
    """
    from origami_cad.pattern import read_pattern, size_warnings

    _check_suffix(output, _pattern_suffixes(), "a pattern")
    check_outputs([source], files=[output])
    cp = read_pattern(source, unit=unit, scale=scale, width=width)
    _write_pattern_file(cp, Path(output), labels)
    msg = f"wrote {output} ({cp.n_vertices} vertices, {cp.n_edges} edges, {len(cp.faces)} panels)"
    warned = [f"warning: {w}" for w in size_warnings(cp)]
    return Outputs(files=[Path(output)], messages=[*warned, msg], result=cp)


def run_check(source: PathLike, *, angle_tolerance: float = 1e-6, verbose: bool = False) -> Outputs:
    """Validate a pattern; ``status`` is 1 when it has errors. Writes nothing.

    ``angle_tolerance`` is the tolerance of Kawasaki's theorem, radians.
    """
    from origami_cad.pattern import Severity, read_pattern

    cp = read_pattern(source)
    problems = cp.check(angle_tolerance=angle_tolerance)
    lines = [f"{source}: {cp!r}"]
    lines += [f"  {p}" for p in problems if p.severity != Severity.INFO or verbose]
    errors = sum(p.severity == Severity.ERROR for p in problems)
    warnings = sum(p.severity == Severity.WARNING for p in problems)
    lines.append(f"{errors} errors, {warnings} warnings")
    numbers = [("check", f"{errors} errors, {warnings} warnings"), *_pattern_numbers(cp)]
    return Outputs(messages=lines, numbers=numbers, result=problems, status=1 if errors else 0)


@_size_noted
def run_pattern(design: PathLike, outputs: Sequence[PathLike], *, labels: bool = False) -> Outputs:
    """Compute a design file's crease pattern; write it to each of ``outputs`` (by extension)."""
    for out in outputs:
        _check_suffix(out, _pattern_suffixes(), "a pattern")
    check_outputs([design], files=outputs)
    loaded, warned = _sized_source(design)
    cp = loaded.pattern
    result = Outputs(result=loaded, numbers=_pattern_numbers(cp), messages=warned)
    for out in map(Path, outputs):
        _write_pattern_file(cp, out, labels)
        result.files.append(out)
        result.messages.append(f"wrote {out}")
        if out.suffix.lower() == ".png":
            result.images.append((out, "Crease pattern (mountain red, valley blue dashed)"))
    result.messages += [f"note: {n}" for n in (loaded.tg.notes if loaded.tg else ())]
    result.messages.append(repr(cp))
    if loaded.tg is not None:
        betas = ", ".join(f"{b:.2f} deg" for b in loaded.tg.shape_angles)
        n = len(loaded.tg.shape_angles)
        result.numbers.insert(0, (f"shape angles beta_1..beta_{n} (eq. 1)", betas))
    return result


@_size_noted
def run_fold(
    design: PathLike,
    output: PathLike,
    *,
    ratio: float = 0.5,
    frames: int = 1,
    view: Sequence[float] | str = "iso",
    unit: str | None = None,
    scale: float | None = None,
    width: float | None = None,
) -> Outputs:
    """Fold rigidly from p = 0 to ``ratio``; write .fold frames, a .png of the end, .gif, .glb
    or a .step of the printed structure folded at ``ratio`` (``Fabrication.assembly``; the
    default fabrication parameters, with the pattern's own string holes).

    ``frames`` states are written (1: only ``ratio``; a .gif or .glb of 1 frame gets 30),
    each lying on the table, centred on the flat sheet
    (:mod:`origami_cad.kinematics.placement`); a .glb holds them as morph targets played
    by an animation (:mod:`origami_cad.viz.gltf`).
    ``view`` is the camera of the renders: ``"iso"``, ``"xy"``... or a direction.
    ``unit``, ``scale`` and ``width`` size an imported pattern (``read_pattern``).
    """
    import dataclasses

    import numpy as np

    from origami_cad.kinematics.folding import fold_sequence
    from origami_cad.kinematics.placement import place_sequence
    from origami_cad.pattern import folded_frame, write_fold
    from origami_cad.viz.render3d import render_folded, render_folding_gif

    if not 0.0 <= ratio <= 1.0:
        raise OptionsError(f"the fold ratio must lie in [0, 1], got {ratio}")
    if not 1 <= frames <= MAX_FRAMES:
        raise OptionsError(f"the number of frames must lie in 1..{MAX_FRAMES}, got {frames}")
    out = Path(output)
    suffix = out.suffix.lower()
    _check_suffix(out, FOLD_SUFFIXES, "the folded state")
    check_outputs([design], files=[out])
    loaded, warned = _sized_source(design, unit, scale, width)
    frames = frames if frames > 1 or suffix not in (".gif", ".glb") else 30
    states = fold_sequence(loaded, np.linspace(0.0, ratio, frames) if frames > 1 else [ratio])
    cp = loaded.pattern
    placed = place_sequence(cp, [s.coords for s in states])
    states = [dataclasses.replace(s, coords=c) for s, c in zip(states, placed, strict=True)]
    if suffix == ".fold":
        labelled = [folded_frame(s.coords, s.fold_angles, f"p = {s.p:.4g}") for s in states]
        write_fold(cp, out, frames=labelled)
    elif suffix == ".png":
        render_folded(cp, states[-1].coords, out, title=f"p = {ratio:g}", view=view)
    elif suffix == ".step":
        from origami_cad.fabrication import FabricationParams, fabricate
        from origami_cad.fabrication.exports.step import export_step_tree

        fab = fabricate(loaded, FabricationParams(holes="pattern"))
        export_step_tree(fab.assembly(ratio), out)
    elif suffix == ".glb":
        from origami_cad.viz.gltf import FOLDING_SECONDS, folding_meshes, write_glb

        meshes = folding_meshes(cp, [s.coords for s in states])
        write_glb(out, meshes, times=np.linspace(0.0, FOLDING_SECONDS, len(states)))
    else:
        captions = [f"p = {s.p:.3f}" for s in states]
        render_folding_gif(cp, [s.coords for s in states], out, view=view, captions=captions)
    caption = f"Folded at p = {ratio:g}" if suffix == ".png" else f"Folding from p = 0 to {ratio:g}"
    plural = "s" if len(states) > 1 else ""
    return Outputs(
        files=[out],
        images=[(out, caption)] if suffix not in (".fold", ".step") else [],
        messages=[
            *warned,
            *_flat_creases_note(cp, states[-1].fold_angles if ratio > 0 else None),
            f"wrote {out} ({len(states)} state{plural}, p up to {ratio:g})",
        ],
        result=states,
    )


def _flat_creases_note(cp, fold_angles) -> list[str]:
    """A note when some mountain and valley creases do not fold at all (degrees given)."""
    import numpy as np

    if fold_angles is None:
        return []
    creases = cp.edge_mask("M", "V")
    flat = creases & (np.abs(np.asarray(fold_angles)) < 1e-6)
    if not flat.any():
        return []
    return [
        f"note: {int(flat.sum())} of the {int(creases.sum())} creases stay flat: their straight "
        "crease lines fold independently of the driving crease (as a map's lines fold one at "
        "a time), which a one-parameter rigid folding leaves flat; the bar-and-hinge "
        "simulation (simulate) folds them together"
    ]


def run_tg(design: PathLike, output: PathLike) -> Outputs:
    """Plot a design's TG chain at p = 0, 0.25, 0.5, 0.75, 1 and the path of T_e (.png)."""
    from origami_cad.pattern.design import load_design
    from origami_cad.viz.tg_plot import save_tg_png

    _check_suffix(output, (".png",), "the TG plot")
    check_outputs([design], files=[output])
    loaded = load_design(design)
    if loaded.tg is None:
        raise DesignError(f"{design}: kind {loaded.kind!r} has no transition graph")
    save_tg_png(loaded.tg, output)
    caption = "TG chain at several p and the path of T_e"
    return Outputs(
        files=[Path(output)], images=[(Path(output), caption)], messages=[f"wrote {output}"]
    )


# --------------------------------------------------------------------------- arm design


def _best_design_toml(design, task, copies: int = 3) -> str:
    """The winner as a design file (``kind = "transition-graph"``) that every command reads.

    Its comments state the fold range the printed arm reaches and the ``fabricate``
    command that builds it with the fabrication parameters it was designed for.
    """
    from origami_cad.pattern.design import dump_design

    terms = design.terms
    p_e = design.fold_ratio_end
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


#: Strand lengths (mm) tried for the arm's onboard TSA, shortest first.
ARM_TSA_LENGTHS = (150.0, 225.0, 340.0, 500.0, 750.0)


def _write_arm_route(design, task, path: Path):
    """Write the winner's route.toml; the shortest TSA whose strings fold the whole range.

    Returns the DCQC result of the route written (the strings fold the arm until the
    printed sheet's fold limit, or the longest TSA tried stops first), or the error that
    kept the route from being simulated (e.g. a panel too small for its hole).
    """
    from origami_cad.errors import OrigamiCadError
    from origami_cad.pattern.design import Design
    from origami_cad.pattern.tg import tg_pattern
    from origami_cad.strings import load_route, simulate_dcqc

    tg = design.tg(task, task.unit_width or 36.0)
    loaded = Design(tg_pattern(tg), tg, "transition-graph")
    result = None
    for length in ARM_TSA_LENGTHS:
        with atomic_write(path, "w", encoding="utf-8") as fh:
            fh.write(_arm_route_text(design, task, length))
        try:
            result = simulate_dcqc(loaded, load_route(path, loaded.pattern))
        except OrigamiCadError as exc:
            return exc
        if str(result.stop) not in ("helix_limit", "turn_limit"):
            break
    return result


def _arm_route_text(design, task, tsa_length: float = 150.0) -> str:
    """The winner's string route: one onboard TSA on its base panel (route.toml)."""
    from origami_cad.design.arm_route import arm_route_toml
    from origami_cad.fabrication import bias_for_theta_max

    bias = design.bias
    if task.fold_limit is not None:
        limit = math.radians(task.fold_limit)
        bias = (
            None
            if task.fold_limit >= 180
            else bias_for_theta_max(limit, task.height, task.thickness)
        )
    header = (
        "# The string route of best.toml (origami-cad design-arm): one onboard TSA on the\n"
        "# base panel twists two strings that run along the arm, parallel to the transition\n"
        "# vectors, through every panel of one row each; sides by the DCQC rule.\n"
        "#   origami-cad route best.toml route.toml -o route        (DCQC)\n"
        "#   origami-cad simulate best.toml route.toml -o sim       (bar-and-hinge)\n"
        "#   origami-cad arm-scene TASK best.toml route.toml -o fig8 (tip against P_end)\n"
        f"#   origami-cad sequence best.toml route.toml -o arm_fold.toml --keyframes 0:0 "
        f"20:{design.fold_ratio_end:.3f} 30:{design.fold_ratio_end:.3f} 40:0\n"
    )
    return arm_route_toml(
        design.tg(task, task.unit_width or 36.0),
        bias=bias,
        height=task.height,
        thickness=task.thickness,
        tsa_length=tsa_length,
        header=header,
    )


def _write_arm_files(results, task, settings, seconds: float, stage: Path):
    """results.json, best.toml, the plots and route.toml; returns (files, designs, the route's
    DCQC): ``designs`` ranked with the winner first (the first tied design whose strings fold
    it, see :func:`_chain_checked`)."""
    from origami_cad import __version__
    from origami_cad.design import task_to_dict
    from origami_cad.design.search import FITNESS_TIE, ties
    from origami_cad.pattern.design import load_design
    from origami_cad.viz import save_pattern_png
    from origami_cad.viz.design_plots import save_convergence_png, save_trajectories_png

    files = [stage / n for n in ("results.json", "best.toml", "trajectories.png")]
    files += [stage / "convergence.png", stage / "best_pattern.png", stage / "route.toml"]
    results, strings, refused = _chain_checked(results, task, files[-1])
    data = {
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
    with atomic_write(files[0], "w", encoding="utf-8") as fh:
        json.dump(data, fh, indent=1)
    with atomic_write(files[1], "w", encoding="utf-8") as fh:
        fh.write(_best_design_toml(results[0], task))
    save_trajectories_png(results, task, files[2])
    save_convergence_png(results, files[3])
    save_pattern_png(load_design(files[1]).pattern, files[4], labels=True)
    return files, results, strings, refused


def _chain_checked(results, task, route: Path):
    """The designs with the winner first, and the winner's route written to ``route``.

    Every design's route is built and folded by its strings (DCQC); a design whose route
    cannot be built, or whose strings stop short of its ``p_e``, is refused, with why. The
    winner is the first design in rank order that is not refused: a tied one when any is.

    Returns (designs, the winner's DCQC result, {run: reason} of the refused).
    """
    from origami_cad.drive.from_model import AT_TOLERANCE

    refused: dict[int, str] = {}
    for design in results:
        strings = _write_arm_route(design, task, route)
        if isinstance(strings, Exception):
            why = str(strings).replace(str(route), route.name)  # not the staged path
            refused[design.run] = f"its string route cannot be built: {why}"
        elif float(strings.p[-1]) < design.fold_ratio_end - AT_TOLERANCE:
            refused[design.run] = (
                f"its strings fold it to p = {float(strings.p[-1]):.4f} only ({strings.stop}), "
                f"short of its fold range's end p_e = {design.fold_ratio_end:.4f}"
            )
    winner = next((d for d in results if d.run not in refused), None)
    if winner is None:
        lines = "; ".join(f"run {run}: {why}" for run, why in refused.items())
        raise DesignError(f"every design was refused: {lines}")
    strings = _write_arm_route(winner, task, route)
    return [winner, *(r for r in results if r is not winner)], strings, refused


def _arm_numbers(best, settings, seconds: float, strings) -> list[tuple[str, str]]:
    """The key numbers of an arm design: the winner, its fold range and its strings."""
    t = best.terms
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
        (
            "route.toml: its strings fold the arm (DCQC)",
            f"to p = {strings.p[-1]:.4f} in {strings.turns[-1]:.1f} TSA turns ({strings.stop})"
            if not isinstance(strings, Exception)
            else f"not simulated: {strings}",
        ),
    ]


def run_design_arm(
    task: PathLike,
    folder: PathLike,
    *,
    runs: int | None = None,
    seed: int | None = None,
    max_generations: int | None = None,
    scheduler: str | None = None,
    progress: Callable[[int, int, float], None] | None = None,
) -> Outputs:
    """CMA-ES arm design (eq. 5): results.json, best.toml and plots into ``folder``.

    The fitness is evaluated over the fold range the printed arm reaches (the
    task's ``[fabrication]`` b, h, t of eq. 6 or ``fold_limit``); best.toml's
    comments give that range and the ``fabricate`` command that builds the winner
    with its fabrication parameters. ``runs``, ``seed`` and ``max_generations``
    override the task's ``[search]`` table; ``scheduler`` runs the runs on a Dask
    cluster (results identical to the local process pool).
    """
    import dataclasses

    from origami_cad.design import design_arm, load_task

    check_outputs([task], folders=[folder])
    arm_task, settings = load_task(task)
    changes = {"runs": runs, "seed": seed, "max_generations": max_generations}
    for name, value in changes.items():
        if value is not None and value < (0 if name == "seed" else 1):
            raise OptionsError(f"{name} must be >= {0 if name == 'seed' else 1}, got {value}")
    settings = dataclasses.replace(settings, **{k: v for k, v in changes.items() if v is not None})
    t0 = time.perf_counter()
    with open_executor(scheduler) as executor:
        results = design_arm(arm_task, settings, executor=executor, progress=progress)
    seconds = time.perf_counter() - t0
    if not results:
        raise DesignError(
            f"{task}: no feasible design: every run's chain touched a prohibited area; relax "
            "the obstacles or the length range"
        )
    with atomic_directory(folder, inputs=[task]) as stage:
        staged, results, strings, refused = _write_arm_files(
            results, arm_task, settings, seconds, stage
        )
        files = _moved(staged, stage, folder)
    best, t = results[0], results[0].terms
    numbers = _arm_numbers(best, settings, seconds, strings)
    tied = _tie_line(results, refused)
    numbers.insert(3, ("runs tied for the best (eq. 5 within 1e-3)", tied))
    summary = (
        f"best of {settings.runs} runs: run {best.run}, f = {best.fitness:.4f}, "
        f"|T_e(0) - P_start| = {t.d_start:.3g} mm, |T_e(p_e) - P_end| = "
        f"{t.d_end:.3g} mm at p_e = {best.fold_ratio_end:.4f} (the fold limit), "
        f"N = {t.improper_states} ({seconds:.1f} s)"
    )
    captions = ["Top designs: chains and the path of T_e"]
    captions += ["Best fitness per generation, one line per run", "The winner's crease pattern"]
    return Outputs(
        files=files,
        images=list(zip(files[2:5], captions, strict=True)),
        numbers=numbers,
        messages=[
            summary,
            f"tied for the best: {tied}",
            *(f"refused: run {run}: {why}" for run, why in refused.items()),
            *(f"wrote {p}" for p in files),
        ],
        result=results,
    )


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


# --------------------------------------------------------------------------- fabrication


def fabrication_params(
    *, bias: float | None = None, theta_max: float | None = None, p_max: float | None = None, **kw
):
    """``FabricationParams`` from at most one of bias (mm), theta_max (deg) or p_max (eq. 6).

    Other keywords are ``FabricationParams`` fields; ``None`` values keep their defaults.
    """
    from origami_cad.fabrication import FabricationParams, bias_for_p_max, bias_for_theta_max

    given = [v is not None for v in (bias, theta_max, p_max)]
    if sum(given) > 1:
        raise OptionsError("give only one of the bias, theta_max and p_max")
    kw = {k: v for k, v in kw.items() if v is not None}
    height = kw.get("height", FabricationParams.height)
    thickness = kw.get("thickness", FabricationParams.thickness)
    if theta_max is not None:
        bias = bias_for_theta_max(math.radians(theta_max), height, thickness)
    elif p_max is not None:
        bias = bias_for_p_max(p_max, height, thickness)
    if bias is not None:
        kw["bias"] = bias
    return FabricationParams(**kw)


def _section_args(cp, fab) -> dict[str, Any]:
    """A section perpendicular to the first main crease, through its middle (Fig. 4e)."""
    main = [e for e in range(cp.n_edges) if cp.assignments[e] in "MV"]
    a, b = cp.vertices[cp.edges[main[0]]]
    mid = (a + b) / 2
    direction = (b - a) / max(float(((b - a) ** 2).sum()) ** 0.5, 1e-12)
    return {
        "mode": "section",
        "section_origin": (float(mid[0]), float(mid[1]), fab.params.height / 2),
        "section_normal": (float(direction[0]), float(direction[1]), 0.0),
    }


def _render_fabrication(cp, fab, stage: Path, name: str) -> list[tuple[Path, str]]:
    from origami_cad.viz.parts_render import render_parts

    stls = {n: stage / f"{n}.stl" for n in ("infills", "midlayers", "shells", "creases")}
    shots = [
        (stage / "assembled.png", {}, f"{name}: assembled"),
        (stage / "exploded.png", {"mode": "exploded"}, f"{name}: the four STLs"),
        (
            stage / "section.png",
            _section_args(cp, fab),
            f"{name}: section across a crease (Fig. 4e)",
        ),
    ]
    for path, kwargs, title in shots:
        render_parts(stls, path, title=title, **kwargs)
    return [(p, t) for p, _, t in shots]


def _fabrication_numbers(fab, name: str) -> list[tuple[str, str]]:
    report = fab.report()
    vols = ", ".join(f"{n} {v['volume_mm3'] / 1000:.2f} cm3" for n, v in report["parts"].items())
    limits = f"{report['theta_max_deg']:.1f} deg, {100 * report['p_max']:.1f} %"
    numbers = [
        (f"{name}: panels / holes", f"{report['panels']} / {len(fab.holes)}"),
        (f"{name}: theta_max, p_max (eq. 6)", limits),
        (f"{name}: volumes", vols),
        (f"{name}: mass estimate", f"{report['total_mass_g']:.1f} g"),
    ]
    if fab.limits.p_max_kinematic is not None:
        kinematic = f"{100 * fab.limits.p_max_kinematic:.1f} %"
        numbers.append((f"{name}: p_max of the folded structure (legs first)", kinematic))
    numbers.append((f"{name}: build + export time", f"{sum(fab.timings.values()):.1f} s"))
    return numbers


@_size_noted
def run_fabricate(
    design: PathLike,
    folder: PathLike,
    params=None,
    *,
    renders: bool = False,
    name: str = "",
    hole: Sequence[Sequence[float]] | None = None,
    unit: str | None = None,
    scale: float | None = None,
    width: float | None = None,
    slicer: str = "prusa",
    bed: Sequence[float] = (200.0, 200.0),
    **overrides: Any,
) -> Outputs:
    """Dual-material printable structure: four STLs, STEP, 3MF, parts.glb, fabrication.json...

    ``params`` is a ``FabricationParams`` (default: the paper's b = 3, h = 2.2,
    t = 0.4 mm); instead, keywords of :func:`fabrication_params` (``bias``,
    ``theta_max``, ``height``...) may be given. ``hole`` lists hole centres
    (x, y in mm) that replace the automatic ones. ``renders`` adds assembled,
    exploded and section pictures; ``name`` prefixes the key numbers (for
    reports holding several structures).
    ``unit``, ``scale`` and ``width`` size an imported pattern (``read_pattern``).
    ``slicer`` (prusa, bambu or orca) is the slicer print.3mf is laid out for;
    ``bed`` (x, y in mm) the print bed: a larger sheet is refused before any work.
    """
    from origami_cad.fabrication import fabricate, write_fabrication
    from origami_cad.viz.fabrication_plots import save_panels_png
    from origami_cad.viz.gltf import write_parts_glb

    check_outputs([design], folders=[folder])
    if hole:
        overrides["holes"] = [tuple(map(float, h)) for h in hole]
    if params is None:
        params = fabrication_params(**overrides)
    elif any(v is not None for v in overrides.values()):
        raise OptionsError("give either fabrication parameters or their keywords, not both")
    loaded, warned = _sized_source(design, unit, scale, width)
    fab = fabricate(loaded, params, bed=tuple(map(float, bed)))
    label = name or Path(design).stem
    with atomic_directory(folder, inputs=_sources(design, loaded)) as stage:
        write_fabrication(fab, stage, slicer=slicer)
        write_parts_glb(stage, stage / "parts.glb")
        save_panels_png(fab, stage / "panels.png")
        images = [(stage / "parts.glb", f"{label}: the printed parts, PLA white, TPU red")]
        images.append((stage / "panels.png", f"{label}: panels, operation regions and holes"))
        if renders:
            images += _render_fabrication(loaded.pattern, fab, stage, label)
        staged = sorted(p for p in stage.iterdir() if not p.name.startswith("."))
    report = fab.report()
    summary = (
        f"{report['panels']} panels, {len(fab.holes)} holes; theta_max = "
        f"{report['theta_max_deg']:.1f} deg, p_max = {100 * report['p_max']:.1f} %; "
        f"mass {report['total_mass_g']:.1f} g"
    )
    files = _moved(staged, stage, folder)
    return Outputs(
        files=files,
        images=[(Path(folder) / p.name, c) for p, c in images],
        numbers=_fabrication_numbers(fab, label),
        messages=[
            *warned,
            summary,
            *(f"warning: {w}" for w in fab.warnings),
            f"wrote {folder}/: " + " ".join(p.name for p in files),
        ],
        result=fab,
    )


def run_part(
    name: str,
    folder: PathLike,
    params: dict[str, Any] | None = None,
    *,
    pattern: PathLike | None = None,
    panel: str | None = None,
    crease: int | None = None,
) -> Outputs:
    """Build a parametric part (``origami_cad.parts``) and write NAME.step and NAME.stl.

    ``params`` are the part's own parameters (mm, degrees), as values or as the
    text of ``--name value`` options. With ``pattern``, a ``tsa-module`` is fitted
    to ``panel`` and a ``blocker`` to ``crease``.
    """
    from origami_cad.fabrication.export import export_part
    from origami_cad.parts import build_part

    inputs = [pattern] if pattern else []
    check_outputs(inputs, folders=[folder])
    part = build_part(name, params, pattern=pattern, panel=panel, crease=crease)
    with atomic_directory(folder, inputs=inputs) as stage:
        files = _moved(export_part(part, stage, name), stage, folder)
    volume = f"{part.volume / 1000:.2f} cm3"
    return Outputs(
        files=files,
        numbers=[(f"{name}: volume", volume)],
        messages=[f"{name}: volume {volume}; wrote " + ", ".join(map(str, files))],
    )


# --------------------------------------------------------------------------- strings


@_size_noted
def run_route(
    design: PathLike,
    route: PathLike,
    folder: PathLike,
    *,
    unit: str | None = None,
    scale: float | None = None,
    width: float | None = None,
) -> Outputs:
    """DCQC folding by a TSA: dcqc.json, dcqc.png, route.png, route_folded.png into ``folder``.

    ``status`` is 1 when the routing never folds the structure.
    ``unit``, ``scale`` and ``width`` size an imported pattern (``read_pattern``).
    """
    from origami_cad.strings import load_route, simulate_dcqc
    from origami_cad.viz.render3d import render_folded
    from origami_cad.viz.strings_plots import save_dcqc_png, save_route_png

    check_outputs([design, route], folders=[folder])
    loaded, warned = _sized_source(design, unit, scale, width)
    cp = loaded.pattern
    spec = load_route(route, cp)
    result = simulate_dcqc(loaded, spec, **_sim_params(spec).dcqc_stiffness())
    names = ("dcqc.json", "route.png", "dcqc.png", "route_folded.png")
    with atomic_directory(folder, inputs=_sources(design, route, loaded)) as stage:
        with atomic_write(stage / names[0], "w", encoding="utf-8") as fh:
            json.dump(result.to_dict(), fh, indent=1)
        save_route_png(cp, spec, stage / names[1])
        save_dcqc_png(result, stage / names[2])
        p, turns = float(result.p[-1]), float(result.turns[-1])
        render_folded(
            cp,
            result.final_coords,
            stage / names[3],
            strings=result.final_strings,
            title=f"final p = {p:.3f}",
        )
    files = [Path(folder) / n for n in names]
    captions = ["Routing (solid above, dashed below the sheet)", "Fold ratio against TSA turns"]
    captions.append("Final state with the strings")
    state = "final" if result.valid else "INVALID routing"
    return Outputs(
        files=files,
        images=list(zip(files[1:], captions, strict=True)),
        numbers=[
            ("strings / quasi-static steps", f"{len(spec.strings)} / {len(result) - 1}"),
            ("final fold ratio p", f"{p:.3f} after {turns:.2f} turns"),
            ("why it stops", result.reason),
            ("DCQC side-rule violations", str(len(result.violations))),
            ("segments cutting through panels", str(len(result.cutting))),
        ],
        messages=[
            *warned,
            *(f"warning: {v}" for v in result.violations + result.cutting),
            f"{state}: p = {p:.4f} after {turns:.2f} turns; {result.reason}",
            f"wrote {folder}/: " + " ".join(names),
        ],
        result=result,
        status=0 if result.valid else 1,
    )


def _sim_params(spec, **loads):
    """The simulation's materials: from the route's [fabrication] (one source), else defaults."""
    from origami_cad.simulation import SimulationParams

    return SimulationParams.for_route(spec, **loads)


def run_string_models(design: PathLike, route: PathLike, folder: PathLike) -> Outputs:
    """Both string models from one route file: fig5.png (p, tensions, torque, four stages).

    Also ``simulation.json``; the numbers give where the two p(turns) curves differ.
    """
    import numpy as np

    from origami_cad.pattern.design import load_pattern_source
    from origami_cad.simulation import simulate
    from origami_cad.strings import load_route, simulate_dcqc
    from origami_cad.viz.strings_plots import save_fig5_png

    check_outputs([design, route], folders=[folder])
    loaded = load_pattern_source(design)
    spec = load_route(route, loaded.pattern)
    params = _sim_params(spec)
    dcqc = simulate_dcqc(loaded, spec, **params.dcqc_stiffness())
    sim = simulate(loaded.pattern, spec, params, design=loaded)
    gap = np.abs(sim.p - np.interp(sim.turns, dcqc.turns, dcqc.p))
    names = ("fig5.png", "simulation.json")
    with atomic_directory(folder, inputs=_sources(design, route, loaded)) as stage:
        save_fig5_png(loaded.pattern, dcqc, sim, stage / names[0])
        with atomic_write(stage / names[1], "w", encoding="utf-8") as fh:
            json.dump(sim.to_dict(), fh)
    files = [Path(folder) / n for n in names]
    return Outputs(
        files=files,
        images=[(files[0], "p against turns in both models; tensions, torque; four stages")],
        numbers=[
            ("simulated states", str(len(sim))),
            ("final fold ratio p (simulation)", f"{sim.p[-1]:.3f} after {sim.turns[-1]:.2f} turns"),
            ("largest gap in p(turns) between the models", f"{np.nanmax(gap):.3f}"),
            (
                "largest string tension / TSA torque",
                f"{sim.tensions.max():.1f} N / {sim.torque.max():.2f} N mm",
            ),
            ("why the simulation stops", sim.reason),
        ],
        messages=[f"wrote {folder}/: " + " ".join(names)],
        result=(dcqc, sim),
    )


def _tsa_placement(tsa: str, ring_radius: float, ring_height: float):
    """``ring`` or ``onboard:PANEL`` as a :class:`~origami_cad.strings.plan.TSAPlacement`."""
    from origami_cad.strings import TSAParams
    from origami_cad.strings.plan import TSAPlacement

    kind, _, panel = tsa.partition(":")
    if kind not in ("ring", "onboard") or (kind == "onboard") != bool(panel):
        raise OptionsError(f"--tsa must be 'ring' or 'onboard:PANEL', got {tsa!r}")
    return TSAPlacement(kind, panel or None, ring_radius, ring_height, tsa=TSAParams(model=kind))


def _verify_planned(loaded, geom, planned, route_file: Path, verify: int) -> list:
    """The best ``verify`` routes folded by the bar-and-hinge simulator (the first from
    the written route file, read back as ``route``/``simulate`` read it)."""
    import dataclasses

    from origami_cad.simulation.verify import verify_route
    from origami_cad.strings import load_route
    from origami_cad.strings.plan import route_spec

    out = []
    for k, r in enumerate(planned):
        if k < verify:
            spec = load_route(route_file, loaded.pattern) if k == 0 else route_spec(geom, r)
            r = dataclasses.replace(
                r, checks={**r.checks, "simulation": verify_route(loaded, spec, steps=30)}
            )
        out.append(r)
    return out


@_size_noted
def run_plan_route(
    pattern: PathLike,
    output: PathLike,
    *,
    tsa: str = "ring",
    strings: int = 4,
    target_p: float | None = None,
    candidates: int = 128,
    seed: int = 0,
    ring_radius: float = 126.0,
    ring_height: float = 10.0,
    verify: int = 2,
    budget: str | None = None,
    scheduler: str | None = None,
    unit: str | None = None,
    scale: float | None = None,
    width: float | None = None,
    progress: Callable[..., None] | None = None,
) -> Outputs:
    """Search string routes by the DCQC principle: route.toml, routes.json and plots.

    Beam search over hole sequences (sides by the M/V rule), then CMA-ES over hole
    positions in the panels' operation regions, scored on the fast DCQC model and
    ranked by TSA turns, peak torque and load share; the best ``verify`` routes are
    folded by the bar-and-hinge simulator. ``--tsa ring`` puts the guides on a ring
    of ``ring_radius`` mm, ``ring_height`` mm above the sheet; ``onboard:PANEL``
    mounts the TSA on that panel. ``--budget TURNS[,NMM]``: the TSA's turns and peak
    torque (N mm) to stay within (default 40 turns). routes.json, routes.png and
    routes_turns.png go next to route.toml. ``--scheduler`` runs the search on a Dask
    cluster. ``unit``, ``scale`` and ``width`` size an imported pattern (``read_pattern``).
    """
    from origami_cad.strings.plan import plan_geometry, plan_routes, route_toml
    from origami_cad.viz.plan_plots import save_planned_routes_png, save_planned_turns_png

    _check_suffix(output, (".toml",), "the route")
    folder = Path(output).parent
    names = (Path(output).name, "routes.json", "routes.png", "routes_turns.png")
    check_outputs([pattern], files=[folder / n for n in names])
    placement = _tsa_placement(tsa, ring_radius, ring_height)
    loaded, warned = _sized_source(pattern, unit, scale, width)
    t0, cpu0 = time.perf_counter(), time.process_time()
    settings = _plan_budget(budget)
    geom = plan_geometry(loaded, placement, target_p=target_p, settings=settings)
    with open_executor(scheduler) as executor:
        planned = plan_routes(
            loaded, placement, strings, target_p=target_p, candidates=candidates, seed=seed,
            executor=executor, progress=progress, geometry=geom, check=max(verify, 1),
            settings=settings,
        )  # fmt: skip
    seconds = time.perf_counter() - t0
    if not planned:
        raise StringsError(f"{pattern}: no route satisfies DCQC to the target; {_PLAN_HINT}")
    header = (
        f"# Planned by: origami-cad plan-route {one_line(pattern)} --tsa {one_line(tsa)} "
        f"--strings {strings}"
        f"{f' --target-p {target_p:g}' if target_p is not None else ''} --seed {seed}\n"
        f"# rank 1 of {len(planned)}: {planned[0].turns:.2f} TSA turns to p = "
        f"{geom.target_p:.4f}, peak torque {planned[0].peak_torque:.3g} N mm (DCQC model)"
    )
    with atomic_directory(folder, inputs=_sources(pattern, loaded)) as stage:
        (stage / names[0]).write_text(route_toml(geom, planned[0], header), encoding="utf-8")
        planned = _verify_planned(loaded, geom, planned, stage / names[0], verify)
        with atomic_write(stage / names[1], "w", encoding="utf-8") as fh:
            json.dump(_routes_json(geom, planned, seconds), fh, indent=1)
        save_planned_routes_png(loaded.pattern, planned, stage / names[2])
        save_planned_turns_png(planned, stage / names[3])
    files = [folder / n for n in names]
    return Outputs(
        files=files,
        images=[(files[2], "The best planned routes"), (files[3], "p against TSA turns")],
        numbers=_plan_numbers(planned, geom, seconds, time.process_time() - cpu0),
        messages=[*warned, *_plan_messages(planned, geom), f"wrote {' '.join(map(str, files))}"],
        result=planned,
    )


_PLAN_HINT = "try another TSA place, fewer strings or a smaller --target-p"


def _plan_budget(budget: str | None):
    """``TURNS[,NMM]`` as the search's settings (budgets of TSA turns and peak torque)."""
    from origami_cad.strings.plan import PlanSettings

    if budget is None:
        return PlanSettings()
    try:
        values = [float(v) for v in budget.split(",")]
    except ValueError:
        values = []
    if not 1 <= len(values) <= 2 or not all(math.isfinite(v) and v > 0 for v in values):
        raise OptionsError(f"--budget: expected TURNS or TURNS,NMM (positive), got {budget!r}")
    return PlanSettings(max_turns=values[0], max_torque=values[1] if len(values) > 1 else math.inf)


def _routes_json(geom, planned, seconds: float) -> dict:
    return {
        "target_p": geom.target_p,
        "fold_limit_p": geom.limit_p,
        "tsa": geom.placement.kind,
        "search_seconds": seconds,
        "routes": [r.to_dict() for r in planned],
    }


def _plan_numbers(planned, geom, seconds: float, cpu: float) -> list[tuple[str, str]]:
    best = planned[0]
    sim = best.checks.get("simulation")
    return [
        ("valid routes ranked", str(len(planned))),
        ("target fold ratio", f"p = {geom.target_p:.4f} (fold limit {geom.limit_p:.4f})"),
        ("best: TSA turns / peak torque", f"{best.turns:.2f} / {best.peak_torque:.3g} N mm"),
        ("best: load share", f"{best.share:.2f}"),
        ("search time", f"{seconds:.1f} s wall, {cpu:.1f} s CPU here"),
        (
            "bar-and-hinge check of the best",
            "not run"
            if sim is None
            else f"p = {sim['p']:.3f} after {sim['turns']:.1f} turns ({sim['stop']})",
        ),
    ]


def _plan_messages(planned, geom) -> list[str]:
    best = planned[0]
    lines = [
        f"best of {len(planned)} routes: {len(best.strings)} strings, {best.turns:.2f} TSA turns "
        f"to p = {geom.target_p:.4f}, peak torque {best.peak_torque:.3g} N mm"
    ]
    for r in planned:
        sim = r.checks.get("simulation")
        if sim is not None and not sim["reaches_target"]:
            lines.append(
                f"warning: route {r.rank}: the bar-and-hinge simulation stops at p = "
                f"{sim['p']:.3f} ({sim['reason']})"
            )
    return lines


# --------------------------------------------------------------------------- simulation


def _blocker_limits(cp, blockers, source: PathLike) -> dict[int, float]:
    limits = {}
    for edge, degrees in dict(blockers or {}).items():
        if not 0 <= edge < cp.n_edges or cp.assignments[edge] not in ("M", "V", "F"):
            raise OptionsError(f"blocker on edge {edge}: not a crease of {source}")
        if not (math.isfinite(degrees) and 0 < degrees <= 180):
            raise OptionsError(f"blocker on edge {edge}: the angle must lie in (0, 180] degrees")
        limits[int(edge)] = float(degrees)
    return limits


def _gif_states(states: int, frames: int) -> list[int]:
    """The states a GIF of about ``frames`` frames shows: evenly spaced, and the last."""
    every = max(1, states // max(frames, 1))
    return [*range(0, states, every), states - 1]


def _write_simulation(stage: Path, names, cp, spec, result, gif_frames: int) -> None:
    from origami_cad.pattern import folded_frame, write_fold
    from origami_cad.viz.render3d import render_folded, render_folding_gif
    from origami_cad.viz.strings_plots import save_route_png

    frames = [
        folded_frame(x, a, f"theta_s = {math.degrees(t):.0f} deg")
        for x, a, t in zip(result.states, result.fold_angles, result.theta, strict=True)
    ]
    write_fold(cp, stage / names[0], frames=frames)
    with atomic_write(stage / names[1], "w", encoding="utf-8") as fh:
        json.dump(result.to_dict(), fh, indent=1)
    picked = _gif_states(len(result.states), gif_frames)
    shown = [result.states[k] for k in picked]
    captions = [f"{result.turns[k]:.1f} TSA turns" for k in picked]
    view = (1, -1.5, 1)
    render_folding_gif(cp, shown, stage / names[2], view=view, captions=captions)
    title = f"after {result.turns[-1]:.1f} TSA turns"
    render_folded(cp, result.states[-1], stage / names[3], title=title, view=view)
    save_route_png(cp, spec, stage / names[4])


@_size_noted
def run_simulate(
    pattern: PathLike,
    route: PathLike,
    folder: PathLike,
    params=None,
    *,
    steps: int | None = None,
    blockers: dict[int, float] | Sequence[tuple[int, float]] | None = None,
    free: bool = False,
    gravity: float | None = None,
    ground: float | None = None,
    friction: float | None = None,
    gif_frames: int = GIF_FRAMES,
    progress: Callable[[int, int], None] | None = None,
    unit: str | None = None,
    scale: float | None = None,
    width: float | None = None,
) -> Outputs:
    """Bar-and-hinge folding by strings and TSA: states.fold, simulation.json, fold.gif, folded.png.

    ``params`` is a ``SimulationParams``, or give ``gravity`` (mm/s^2, along -z),
    ``ground`` (height of a ground plane, mm) and ``friction`` (Coulomb
    coefficient). ``blockers`` maps crease index to its limit in degrees;
    ``free`` holds no panel (a robot lying on the ground); ``gif_frames`` is
    the number of frames of the animation.
    ``unit``, ``scale`` and ``width`` size an imported pattern (``read_pattern``).
    """
    from origami_cad.simulation import simulate
    from origami_cad.strings import load_route

    if steps is not None and not 1 <= steps <= 100_000:
        raise OptionsError(f"the number of steps must lie in 1..100000, got {steps}")
    names = ("states.fold", "simulation.json", "fold.gif", "folded.png", "route.png")
    check_outputs([pattern, route], files=[Path(folder) / n for n in names], folders=[folder])
    if friction is not None and friction < 0:
        raise SimulationError(f"the friction coefficient must be >= 0, got {friction:g}")
    given = {"gravity": gravity, "ground": ground, "friction": friction}
    loaded, warned = _sized_source(pattern, unit, scale, width)
    cp = loaded.pattern
    spec = load_route(route, cp)
    if params is None:
        params = _sim_params(spec, **{k: v for k, v in given.items() if v is not None})
    limits = _blocker_limits(cp, blockers, pattern)
    kwargs = {"steps": steps, "fold_limits": limits or None, "progress": progress, "free": free}
    result = simulate(cp, spec, params, design=loaded, **kwargs)
    with atomic_directory(folder, inputs=_sources(pattern, route, loaded)) as stage:
        _write_simulation(stage, names, cp, spec, result, gif_frames)
    files = [Path(folder) / n for n in names]
    tensions = ", ".join(f"{t:.3g}" for t in result.tensions[-1])
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
            ("string tensions at the end", ", ".join(f"{t:.2f} N" for t in result.tensions[-1])),
            ("why it stops", result.reason),
        ],
        messages=[
            *warned,
            f"{len(result)} equilibrium states up to {result.turns[-1]:.2f} TSA turns; "
            f"{result.reason}",
            f"string tensions {tensions} N, TSA torque {result.torque[-1]:.3g} N mm",
            f"wrote {folder}/: " + " ".join(names),
        ],
        result=result,
    )


# --------------------------------------------------------------------------- sequences

SEQUENCE_MODELS = ("dcqc", "simulation")


def _string_model(loaded, spec, model: str, steps: int | None = None, fixed_panel=None):
    """Fold ``loaded`` by the route ``spec``: a DCQCResult or a bar-and-hinge SimulationResult."""
    import dataclasses

    from origami_cad.simulation import SimulationParams, simulate
    from origami_cad.strings import simulate_dcqc

    if fixed_panel is not None:
        if fixed_panel not in loaded.pattern.face_labels:
            raise OptionsError(f"fixed panel: no panel labelled {fixed_panel!r}")
        spec = dataclasses.replace(spec, fixed_panel=fixed_panel)
    params = SimulationParams.for_route(spec)
    if model == "dcqc":
        return simulate_dcqc(loaded, spec, **params.dcqc_stiffness())
    return simulate(loaded.pattern, spec, params, design=loaded, steps=steps)


def _sequence_header(design, routes, output, model, fixed_panel, ids, keyframes) -> str:
    """The comment lines of a generated sequence file: where it comes from, how to remake it."""
    route = routes[0]
    argv = " ".join(
        [
            "origami-cad sequence",
            str(design),
            str(route),
            "-o",
            str(output),
            *(f"--more-routes {r}" for r in routes[1:]),
            f"--model {model}",
            *([f"--fixed-panel {fixed_panel}"] if fixed_panel else []),
            "--ids " + ",".join(map(str, ids)),
            "--keyframes",
            *map(str, keyframes),
        ]
    )
    header = (
        f"# Generated from the {model} model of {one_line(design)} folded by its strings, "
        "not typed by\n"
        f"# hand: each TSA's mapping is the fold ratio its route's strings reach against the\n"
        "# contraction of its onboard TSA (every keyframe's fold ratio included), so drive\n"
        "# commands the turns the model needed. Regenerate with:\n"
        f"#   {one_line(argv)}\n"
    )
    return header


def _check_sequence_options(output, model: str, points: int, rate: float, repeat: int) -> None:
    """Clear errors for the options of ``sequence`` (before any model runs)."""
    _check_suffix(output, (".toml",), "a sequence")
    if model not in SEQUENCE_MODELS:
        raise OptionsError(f"model must be one of {', '.join(SEQUENCE_MODELS)}, got {model!r}")
    if not 2 <= points <= 1000:
        raise OptionsError(f"points must lie in 2..1000, got {points}")
    if not (math.isfinite(rate) and 0 < rate <= 1000):
        raise OptionsError(f"rate must lie in (0, 1000] Hz, got {rate:g}")
    if not 1 <= repeat <= 1_000_000:
        raise OptionsError(f"repeat must lie in 1..1000000, got {repeat}")


def _route_tsa(loaded, path, model: str, fixed_panel, servo: int, at, points: int):
    """Fold ``loaded`` by one route: its TSA entry of the sequence, its numbers, the model result.

    ``at`` are the keyframes' fold ratios for this TSA; the mapping samples the
    model's fold curve at ``points`` even fold ratios and at each of them.
    """
    import numpy as np

    from origami_cad.drive.from_model import (
        fold_curve,
        model_mapping,
        state_fold_ratios,
        turns_at,
    )
    from origami_cad.strings import load_route

    spec = load_route(path, loaded.pattern)
    result = _string_model(loaded, spec, model, fixed_panel=fixed_panel)
    where = f"{path} ({model})"
    creases = np.flatnonzero(loaded.pattern.edge_mask("M", "V"))
    ratios = state_fold_ratios(result.p, result.fold_angles, creases)
    mapping = model_mapping(ratios, result.turns, spec.tsa, at, points, where)
    p, turns = fold_curve(ratios, result.turns)
    torque = np.asarray(result.torque, dtype=float)
    peak = float(np.nanmax(torque)) if np.isfinite(torque).any() else float("nan")
    tsa = {
        "id": servo,
        "name": Path(path).stem.removesuffix("_route").removeprefix("route_"),
        "tsa": spec.tsa,
        "mapping": mapping,
        "comment": (
            f"servo {servo}: {Path(path).name}, {model} model: p = {p[0]:.3f} .. "
            f"{p[-1]:.3f} in {turns[-1]:.2f} turns ({result.reason})"
        ),
    }
    need = ", ".join(f"{v:.2f}" for v in turns_at(p, turns, at))
    numbers = [
        (f"servo {servo}: fold range of its strings", f"p = {p[0]:.3f} .. {p[-1]:.3f}"),
        (f"servo {servo}: turns at the keyframes", need),
        (f"servo {servo}: largest TSA torque", f"{peak:.3g} N mm"),
    ]
    return tsa, numbers, result


def run_sequence(
    design: PathLike,
    route: PathLike,
    output: PathLike,
    *,
    keyframes: Sequence[str],
    more_routes: Sequence[PathLike] | None = None,
    model: str = "dcqc",
    ids: Sequence[int] | None = None,
    rate: float = 10.0,
    repeat: int = 1,
    points: int = 21,
    fixed_panel: str | None = None,
) -> Outputs:
    """Fold-ratio keyframes to TSA turns through a string model: the sequence file ``drive`` runs.

    Each route (``route``, then ``more_routes``: one onboard TSA each, servo IDs
    ``ids``, default 1, 2, ...) folds ``design`` in the DCQC model (``model =
    "dcqc"``) or the bar-and-hinge simulation (``"simulation"``); the fold ratio
    it reaches against the TSA's turns becomes that TSA's mapping (fold ratio to
    contraction of the onboard TSA model, every keyframe's fold ratio included),
    so ``drive`` commands the turns the model needed. ``keyframes`` are
    ``TIME:P`` or ``TIME:P1,P2,...`` (s, fold ratios, one per route). A pattern
    without a one-parameter folding is measured by its most folded crease
    (``max |fold angle| / 180``). ``fixed_panel`` holds that panel in every route
    (e.g. a robot's body while one leg folds), instead of each route's own setting.
    """
    from origami_cad.drive.from_model import parse_keyframes, sequence_toml
    from origami_cad.drive.sequence import load_sequence
    from origami_cad.pattern.design import load_pattern_source

    routes = [route, *(more_routes or [])]
    check_outputs([design, *routes], files=[output])
    _check_sequence_options(output, model, points, rate, repeat)
    ids = list(ids) if ids else list(range(1, len(routes) + 1))
    if len(ids) != len(routes):
        raise DriveError(f"{len(ids)} servo IDs for {len(routes)} routes")
    frames = parse_keyframes(keyframes, len(routes))
    loaded = load_pattern_source(design)
    tsas, numbers, results = [], [], []
    for k, path in enumerate(routes):
        at = [values[k] for _, values in frames]
        tsa, more, result = _route_tsa(loaded, path, model, fixed_panel, ids[k], at, points)
        tsas.append(tsa)
        numbers += more
        results.append(result)
    header = _sequence_header(design, routes, output, model, fixed_panel, ids, keyframes)
    text = sequence_toml(tsas, frames, rate=rate, repeat=repeat, header=header)
    with atomic_path(output) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
        load_sequence(tmp)  # drive reads it: every keyframe reachable within the TSA's twist
    return Outputs(
        files=[Path(output)],
        numbers=numbers,
        messages=[f"{len(tsas)} TSA(s), {len(frames)} keyframes; wrote {output}"],
        result=results,
    )


def _designed_arm_path(arm_task, tg, spec):
    """The designed chain over the printed arm's fold range: (p_e, joints (S, n + 2, 2) mm).

    The range ends where eq. 6's limit (at the route's bias, else the task's) stops
    the first crease, legs included.
    """
    import numpy as np

    from origami_cad.design import reachable_fold_angle
    from origami_cad.kinematics.chain import chain_points

    beta = np.radians(np.asarray(tg.shape_angles, dtype=float))[None, :]
    bias = spec.fabrication.bias if spec.fabrication is not None else arm_task.bias
    limit = arm_task.crease_limit(bias if arm_task.fold_limit is None else None)
    p_e = float(reachable_fold_angle(beta, limit)[0] / math.pi)
    designed = chain_points(
        np.linspace(0.0, p_e * math.pi, arm_task.samples),
        tg.lengths,
        beta,
        tg.entry_flag,
        tg.hypar_base,
        tg.start,
    )[0]
    return p_e, designed


def _arm_scene_summary(arm_task, tg, result, simulated, designed, p_e) -> dict[str, Any]:
    """arm_scene.json: the simulated tip against P_end, the designed path and the areas."""
    import numpy as np

    from origami_cad.design.fitness import area_edges
    from origami_cad.design.predicates import touches_area
    from origami_cad.kinematics.chain import chain_points

    ratios = np.asarray(result.p, dtype=float)
    beta = np.radians(np.asarray(tg.shape_angles, dtype=float))[None, :]
    tips = simulated[:, -1]
    d_end = np.linalg.norm(tips - arm_task.points[-1], axis=1)
    known = np.isfinite(ratios)
    rigid = chain_points(  # the designed tip at each state's fold ratio
        ratios[known] * math.pi, tg.lengths, beta, tg.entry_flag, tg.hypar_base, tg.start
    )[0, :, -1]
    deviation = float(np.linalg.norm(tips[known] - rigid, axis=1).max()) if known.any() else 0.0
    z = simulated[..., 0] + 1j * simulated[..., 1]
    hits = np.zeros(len(z), dtype=bool)
    for edges in area_edges(arm_task.prohibited):
        hits |= touches_area(z, edges)
    torque = np.asarray(result.torque, dtype=float)
    return {
        "designed_fold_ratio_end": p_e,
        "simulated_fold_ratio_end": float(np.nanmax(ratios)) if np.isfinite(ratios).any() else None,
        "final_tip_mm": tips[-1].tolist(),
        "final_distance_from_P_end_mm": float(d_end[-1]),
        "closest_distance_from_P_end_mm": float(d_end.min()),
        "first_state_fold_ratio": float(ratios[0]),
        "max_distance_from_designed_tip_mm": deviation,
        "states_touching_prohibited_area": int(hits.sum()),
        "tsa_turns": float(result.turns[-1]),
        "max_tsa_torque_Nmm": float(np.nanmax(torque))
        if np.isfinite(torque).any()
        else float("nan"),
        "stop": str(result.stop),
        "reason": result.reason,
        "simulated_tip_mm": tips.tolist(),
        "designed_tip_mm": designed[:, -1].tolist(),
    }


def _arm_scene_numbers(summary: dict[str, Any]) -> list[tuple[str, str]]:
    """The key numbers of ``arm-scene`` from its summary."""
    return [
        ("designed fold range", f"p = 0 .. {summary['designed_fold_ratio_end']:.3f}"),
        (
            "simulated tip: distance from P_end at the end",
            f"{summary['final_distance_from_P_end_mm']:.2f} mm",
        ),
        (
            "simulated tip: largest distance from the designed tip",
            f"{summary['max_distance_from_designed_tip_mm']:.2f} mm",
        ),
        ("states touching the prohibited area", str(summary["states_touching_prohibited_area"])),
        ("TSA turns to fold it", f"{summary['tsa_turns']:.1f}"),
        ("largest TSA torque", f"{summary['max_tsa_torque_Nmm']:.3g} N mm"),
        ("why the folding stops", summary["reason"]),
    ]


def run_arm_scene(
    task: PathLike,
    design: PathLike,
    route: PathLike,
    folder: PathLike,
    *,
    steps: int | None = None,
) -> Outputs:
    """The printed arm folded by its strings in its scene (Fig. 8): fig8.png, arm_scene.json.

    The bar-and-hinge simulation (the route's panel thickness and eq. 6 fold
    limits) folds ``design`` by ``route``; each state is placed by its base panels
    and its main crease read as the TG chain, so its tip path is compared with the
    designed one (at the same fold ratio), ``P_start``, ``P_end`` and the task's
    areas. The simulation starts from creases pre-folded by 3 deg (see
    :func:`~origami_cad.simulation.simulate`), not flat. ``steps`` turns the
    TSA in that many equal steps (default: steps of string taken up).
    """
    import numpy as np

    from origami_cad.design import load_task
    from origami_cad.design.arm_route import arm_chain_path
    from origami_cad.pattern.design import load_pattern_source
    from origami_cad.strings import load_route
    from origami_cad.viz.design_plots import save_arm_scene_png

    check_outputs([task, design, route], folders=[folder])
    arm_task, _ = load_task(task)
    loaded = load_pattern_source(design)
    if loaded.tg is None:
        raise DesignError(f"{design}: an arm is a transition-graph design")
    spec = load_route(route, loaded.pattern)
    result = _string_model(loaded, spec, "simulation", steps)
    simulated = arm_chain_path(loaded.tg, result.states, np.asarray(result.p, dtype=float))
    p_e, designed = _designed_arm_path(arm_task, loaded.tg, spec)
    summary = _arm_scene_summary(arm_task, loaded.tg, result, simulated, designed, p_e)
    d_end, turns = summary["final_distance_from_P_end_mm"], summary["tsa_turns"]
    peak = summary["max_tsa_torque_Nmm"]
    names = ("fig8.png", "arm_scene.json")
    with atomic_directory(folder, inputs=_sources(task, design, route, loaded)) as stage:
        title = (
            f"tip {d_end:.1f} mm from P_end after {turns:.1f} TSA turns, "
            f"peak torque {peak:.3g} N mm"
        )
        save_arm_scene_png(arm_task, designed, simulated, stage / names[0], title)
        with atomic_write(stage / names[1], "w", encoding="utf-8") as fh:
            json.dump(summary, fh, indent=1)
    files = [Path(folder) / n for n in names]
    return Outputs(
        files=files,
        images=[(files[0], "Designed tip path and the printed arm's, folded by its strings")],
        numbers=_arm_scene_numbers(summary),
        messages=[
            f"the printed arm's tip ends {d_end:.2f} mm from P_end after {turns:.1f} TSA "
            f"turns (peak torque {peak:.3g} N mm); {result.reason}",
            f"wrote {folder}/: " + " ".join(names),
        ],
        result=result,
    )


# --------------------------------------------------------------------------- robots

PAPER_CRAWL_MM = 63.0  # the paper's crawler: mm forward per 32 s gait cycle on a PVC mat
PAPER_CRAWLER_G = 361.45  # the paper's crawler's weight, g


def _check_crawl_options(cycles: int, steps: int, friction: float | None) -> None:
    if not 1 <= cycles <= 100:
        raise OptionsError(f"the number of cycles must lie in 1..100, got {cycles}")
    if not 1 <= steps <= 1000:
        raise OptionsError(f"the steps between keyframes must lie in 1..1000, got {steps}")
    if friction is not None and not friction >= 0:
        raise SimulationError(f"the friction coefficient must be >= 0, got {friction:g}")


def _crawl_command(robot, folder, cycles, steps, reverse, friction) -> str:
    """The ``origami-cad crawl`` command line that reproduces a crawl job's outputs."""
    args = ["origami-cad", "crawl", str(robot), "-o", str(folder)]
    args += ["--cycles", str(cycles), "--steps", str(steps)]
    args += ["--reverse"] * bool(reverse)
    args += ["--friction", f"{friction:g}"] if friction is not None else []
    return " ".join(args)


def _write_crawl(stage: Path, names, spec, result, info: dict, gif_frames: int) -> None:
    """crawl.json, crawl.png, loads.png, crawl.gif and gait_sequence.toml into ``stage``."""
    from origami_cad.simulation.crawler import gait_sequence_text
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
        json.dump(data, fh, indent=1)
    reference = -PAPER_CRAWL_MM if info["reverse"] else PAPER_CRAWL_MM
    save_crawl_position_png(
        result.t, result.body, result.cycle_starts, stage / names[1],
        reference=reference, cycle=spec.cycle,
    )  # fmt: skip
    save_crawl_loads_png(result.t, result.torque, result.tensions, legs, stage / names[2])
    save_crawl_gait_png(
        result.t, result.fold, result.turns, legs, stage / names[5], commanded=result.commanded
    )
    picked = _gif_states(len(result.states), gif_frames)
    shown = [result.states[k] for k in picked]
    captions = [
        f"t = {result.t[k]:.1f} s, body moved {result.body[k, 0] - result.body[0, 0]:+.1f} mm"
        for k in picked
    ]
    render_folding_gif(spec.pattern, shown, stage / names[3], view="xz", captions=captions)
    text = gait_sequence_text(
        spec, repeat=info["cycles"], result=result, reverse=info["reverse"],
        command=info["command"],
    )  # fmt: skip
    with atomic_write(stage / names[4], "w", encoding="utf-8") as fh:
        fh.write(text)


def _crawl_numbers(result, seconds: float) -> list[tuple[str, str]]:
    per = result.displacement_per_cycle()
    mean = float(per.mean()) if per.size else math.nan
    return [
        ("displacement per cycle", ", ".join(f"{d:.1f} mm" for d in per) or "none complete"),
        ("mean per cycle (paper: 63 mm)", f"{mean:.1f} mm"),
        ("total displacement", f"{result.body[-1, 0] - result.body[0, 0]:.1f} mm"),
        ("lateral drift", f"{result.body[-1, 1] - result.body[0, 1]:.1f} mm"),
        ("largest TSA torque", f"{result.torque.max():.1f} N mm"),
        ("largest string tension", f"{result.tensions.max():.1f} N"),
        ("largest blocked fold", f"{result.blocked.max():.1f} deg"),
        ("simulated mass", f"{result.mass_g:.0f} g"),
        ("simulation time", f"{seconds:.1f} s"),
        ("how the gait ended", result.reason),
    ]


def run_crawl(
    robot: PathLike,
    folder: PathLike,
    *,
    cycles: int = 2,
    steps: int = 6,
    reverse: bool = False,
    friction: float | None = None,
    gif_frames: int = GIF_FRAMES,
    progress: Callable[[int, int], None] | None = None,
) -> Outputs:
    """Walk a legged robot through its gait in simulation: crawl.json, .png plots, crawl.gif.

    The robot file (``examples/crawler/crawler.toml``) gives the pattern, one onboard
    TSA route per leg, blockers, masses and the gait as fold ratios; each keyframe is
    turned into TSA turns through the model and the robot lies free on the ground
    (gravity, Coulomb ``friction``, default the robot file's). ``cycles`` gait cycles
    of ``steps`` quasi-static steps between keyframes; ``reverse`` plays the gait
    backwards. Writes the body's path and per-TSA torque and tensions
    (``crawl.json``), the body's position against time (``crawl.png``), torques and
    tensions (``loads.png``), the legs' fold angles and TSA twist (``gait.png``), the
    crawl seen from the side (``crawl.gif``) and the
    gait as a sequence for ``drive`` (``gait_sequence.toml``: mappings from the string
    model, and each servo's simulated load, which ``drive --dry-run`` applies).
    """
    from origami_cad.simulation.crawler import load_robot, simulate_gait

    _check_crawl_options(cycles, steps, friction)
    check_outputs([robot], folders=[folder])
    spec = load_robot(robot)
    start = time.perf_counter()
    result = simulate_gait(
        spec, cycles=cycles, steps=steps, reverse=reverse, friction=friction, progress=progress
    )
    seconds = time.perf_counter() - start
    per = result.displacement_per_cycle()
    names = ("crawl.json", "crawl.png", "loads.png", "crawl.gif", "gait_sequence.toml", "gait.png")
    info = {
        "robot": str(robot),
        "cycles": cycles,
        "reverse": reverse,
        "cycle_s": spec.cycle,
        "paper_mm_per_cycle": PAPER_CRAWL_MM,
        "simulation_s": seconds,
        "command": _crawl_command(robot, folder, cycles, steps, reverse, friction),
    }
    inputs = [robot, spec.pattern_path, *(leg.route_path for leg in spec.legs)]
    with atomic_directory(folder, inputs=inputs) as stage:
        _write_crawl(stage, names, spec, result, info, gif_frames)
    files = [Path(folder) / n for n in names]
    mean = float(per.mean()) if per.size else math.nan
    return Outputs(
        files=files,
        images=[
            (files[5], "The gait: leg fold angles (simulated and keyframed) and TSA twist"),
            (files[1], "Body position against time (paper: 63 mm per 32 s cycle)"),
            (files[2], "TSA torque and string tension per leg"),
            (files[3], "The crawl seen from the side"),
        ],
        numbers=_crawl_numbers(result, seconds),
        messages=[
            f"{cycles} gait cycle(s), {len(result.t)} states in {seconds:.1f} s: "
            f"{mean:.1f} mm per cycle (the paper's crawler: {PAPER_CRAWL_MM:g} mm)",
            *([f"stopped: {result.reason}"] if result.stop is not None else []),
            *(f"note: {n}" for n in result.notes),
            f"wrote {folder}/: " + " ".join(names),
        ],
        result=result,
    )


def _mass_budget(spec, fab, report: dict) -> dict[str, Any]:
    """The robot's mass: the printed sheet, its printed parts and the bought parts, g."""
    sheet = fab.report()["total_mass_g"]
    printed = sum(v["mass_g"] for v in report.values() if v["kind"] != "structure")
    bought = sum(m.grams for m in spec.masses)
    total = sheet + printed + bought
    return {
        "sheet_g": sheet,
        "printed_parts_g": printed,
        "bought_parts_g": {m.name: m.grams for m in spec.masses},
        "total_g": total,
        "paper_g": PAPER_CRAWLER_G,
        "difference_percent": 100.0 * (total - PAPER_CRAWLER_G) / PAPER_CRAWLER_G,
    }


def _write_robot(stage: Path, robot, fab, assembly, data: dict, renders: bool) -> list:
    """The sheet's files, the parts' STLs, robot.step, robot.json and the pictures; images."""
    from origami_cad.fabrication import write_fabrication
    from origami_cad.parts.robot import write_robot_step, write_robot_stls
    from origami_cad.viz.fabrication_plots import save_panels_png

    write_fabrication(fab, stage)
    save_panels_png(fab, stage / "panels.png")
    stls = write_robot_stls(assembly, stage)
    write_robot_step(assembly, stage / "robot.step", label=Path(robot).stem)
    with atomic_write(stage / "robot.json", "w", encoding="utf-8") as fh:
        json.dump(data, fh, indent=1)
    images = [(stage / "panels.png", "The robot's sheet: panels, regions and string holes")]
    if renders:
        from origami_cad.viz.parts_render import render_parts

        every = {n: stage / f"{n}.stl" for n in ("infills", "midlayers", "shells", "creases")}
        every.update(stls)
        from origami_cad.parts.robot import display_color

        kinds = {n: assembly.kinds[n] for n in stls}
        render_parts(
            every,
            stage / "robot.png",
            title=f"{Path(robot).stem}: printed robot",
            labels={
                n: k.replace("-", " ") + "s" * (list(kinds.values()).count(k) > 1)
                for n, k in kinds.items()
            },
            colors={n: display_color(assembly, n) for n in stls},
        )
        images.insert(0, (stage / "robot.png", "The printed robot with its parts in place"))
    return images


def run_robot(
    robot: PathLike, folder: PathLike, *, renders: bool = True, ratio: float = 0.0
) -> Outputs:
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
    from origami_cad.fabrication import FabricationParams, fabricate
    from origami_cad.parts.robot import robot_assembly, robot_overlaps, robot_report
    from origami_cad.simulation.crawler import load_robot, robot_placements

    if not 0.0 <= ratio <= 1.0:
        raise OptionsError(f"the fold ratio must lie in [0, 1], got {ratio}")
    check_outputs([robot], folders=[folder])
    spec = load_robot(robot)
    fab = fabricate(spec.pattern, FabricationParams(holes=spec.holes or "auto"))
    assembly = robot_assembly(fab, **robot_placements(spec), ratio=ratio)
    report = robot_report(assembly)
    overlaps = robot_overlaps(assembly)
    budget = _mass_budget(spec, fab, report)
    data = {
        "robot": str(robot),
        "mass_budget": budget,
        "solids": report,
        "interpenetrating_mm3": {f"{a} / {b}": v for (a, b), v in overlaps.items()},
    }
    inputs = [robot, spec.pattern_path, *(leg.route_path for leg in spec.legs)]
    with atomic_directory(folder, inputs=inputs) as stage:
        images = _write_robot(stage, robot, fab, assembly, data, renders)
        staged = sorted(p for p in stage.iterdir() if not p.name.startswith("."))
    files = _moved(staged, stage, folder)
    kinds = [v["kind"] for v in report.values()]
    sheet, printed, total = budget["sheet_g"], budget["printed_parts_g"], budget["total_g"]
    bought = sum(budget["bought_parts_g"].values())
    return Outputs(
        files=files,
        images=[(Path(folder) / p.name, c) for p, c in images],
        numbers=[
            ("sheet mass", f"{sheet:.1f} g"),
            ("printed parts", f"{printed:.1f} g"),
            ("bought parts (servos, driver module)", f"{bought:.1f} g"),
            (
                "mass estimate (paper: 361.45 g)",
                f"{total:.0f} g ({budget['difference_percent']:+.0f} %)",
            ),
            (
                "parts",
                f"{kinds.count('tsa-module')} TSA modules, {kinds.count('blocker')} blockers, "
                f"{kinds.count('driver-adapter')} driver adapter",
            ),
            ("interpenetrating pairs", str(len(overlaps))),
        ],
        messages=[
            f"mass estimate {total:.0f} g against the paper's {PAPER_CRAWLER_G:g} g "
            f"(sheet {sheet:.0f} g, printed parts {printed:.0f} g, bought {bought:.0f} g)",
            *(f"warning: {a} and {b} share {v:.1f} mm^3" for (a, b), v in overlaps.items()),
            *(f"warning: {w}" for w in fab.warnings),
            f"wrote {folder}/: " + " ".join(p.name for p in files),
        ],
        result=assembly,
    )


# --------------------------------------------------------------------------- hardware


def run_emulate(
    ids: Sequence[int] = (1,),
    *,
    protocol: str = "dynamixel",
    seconds: float = 0.0,
    echo: Callable[[str], None] = print,
) -> Outputs:
    """Emulate servos on a pseudo-terminal until Ctrl-C, or for ``seconds`` (0: forever)."""
    from origami_cad.drive import open_emulator

    if len(set(ids)) != len(ids) or not ids or any(not 0 <= i <= 252 for i in ids):
        raise DriveError(f"servo IDs must be distinct and in 0..252, got {list(ids)}")
    if not (math.isfinite(seconds) and seconds >= 0):
        raise OptionsError(f"the duration must be a finite number of seconds >= 0, got {seconds}")
    emu = open_emulator(protocol, list(ids))
    with emu:
        echo(f"{protocol} emulator with servos {list(ids)} on {emu.port}")
        echo(f"connect with --port {emu.port}; Ctrl-C to stop")
        deadline = time.monotonic() + seconds if seconds else None
        while deadline is None or time.monotonic() < deadline:
            time.sleep(0.1)
    return Outputs()


def _open_bus(stack, seq, port, protocol: str, baudrate: int, emulate: dict | None, log=None):
    """The servo bus of a sequence: on ``port``, or on a new emulator given ``emulate``
    (``time_scale`` and ``load_scale``: its servos carry the sequence's loads). If it
    cannot be opened (an absent servo), the CSV ``log`` says why."""
    from origami_cad.drive.sequence import log_not_started

    try:
        return _start_bus(stack, seq, port, protocol, baudrate, emulate)
    except BaseException as exc:
        log_not_started(log, seq, exc)
        raise


def _start_bus(stack, seq, port, protocol: str, baudrate: int, emulate: dict | None):
    from origami_cad.drive import open_bus, open_emulator

    limits = {t.dxl_id: t.max_turns for t in seq.tsas}
    if emulate is not None:
        loads = seq.loads(emulate["load_scale"])
        emu = open_emulator(protocol, seq.ids, time_scale=emulate["time_scale"], loads=loads)
        port = stack.enter_context(emu).port
    bus = open_bus(
        protocol,
        port,
        baudrate,
        seq.ids,
        max_turns=limits,
        current_limit_ma=seq.current_limit,
        emulated=emulate is not None,
    )
    return stack.enter_context(bus)


def _drive_stopped(exc: BaseException, plot, names: dict[int, str], done=None) -> BaseException:
    """After a run stopped early: the ``plot`` of its readings (``done``: all of them, when
    only the shutdown failed), so log and plot stay one set; and the error to raise (a
    stall names the TSA, not only its servo ID)."""
    from origami_cad.drive import StallError
    from origami_cad.drive.sequence import DriveLog
    from origami_cad.viz.drive_plots import save_drive_png

    ran = done or getattr(exc, "drive_log", None) or getattr(exc.__cause__, "drive_log", None)
    if plot:  # no readings yet (stopped while the bus opened): an empty plot, as the log
        with finishing():
            save_drive_png(ran or DriveLog.empty(list(names), 0), plot, names)
    if isinstance(exc, StallError) and names.get(exc.servo):
        return StallError(f"{names[exc.servo]}: {exc}", exc.servo)
    return exc


def run_drive(
    sequence: PathLike,
    log: PathLike = "drive_log.csv",
    *,
    port: str | None = None,
    dry_run: bool = False,
    speed: float = 8.0,
    load_scale: float = 1.0,
    protocol: str = "dynamixel",
    baudrate: int = 57600,
    plot: PathLike | None = None,
    progress: Callable | None = None,
) -> Outputs:
    """Run a TSA sequence on servos at ``port`` (or an emulator: ``dry_run``), CSV ``log``.

    ``speed`` is the time acceleration of a dry run; its emulated Dynamixel servos carry
    each TSA's ``load`` (the torque a simulation predicts, N mm) times ``load_scale``, so
    a load past a servo's stall torque or the sequence's ``current_limit`` stops that
    servo by name. ``plot`` adds a PNG of the commanded and measured turns. Torque goes
    off on exit, error and Ctrl-C.
    """
    import contextlib

    import numpy as np

    from origami_cad.drive.sequence import check_time_scale, load_sequence, run_sequence
    from origami_cad.viz.drive_plots import save_drive_png

    if plot is not None:
        _check_suffix(plot, (".png",), "the drive plot")
    check_outputs([sequence], files=[p for p in (log, plot) if p])
    if dry_run:
        speed = check_time_scale(speed, "speed")
        if not (math.isfinite(load_scale) and 0 <= load_scale <= 1e6):
            raise DriveError(f"the load scale must be a number in [0, 1e6], got {load_scale}")
    seq = load_sequence(sequence)
    if not dry_run and not port:
        raise DriveError("give the servos' port, or use a dry run on the emulator")
    scale = speed if dry_run else 1.0
    emulate = {"time_scale": scale, "load_scale": load_scale} if dry_run else None
    names, done = {t.dxl_id: t.name for t in seq.tsas}, None
    try:
        with contextlib.ExitStack() as stack:
            bus = _open_bus(stack, seq, port, protocol, baudrate, emulate, log)
            done = run_sequence(seq, bus, log, time_scale=scale, progress=progress)
    except BaseException as exc:  # the plot shows what ran; a stall names the TSA
        raise _drive_stopped(exc, plot, names, done) from exc.__cause__
    files = [Path(log)]
    if plot:
        with finishing():  # the log is complete: its plot follows, even past a Ctrl-C
            save_drive_png(done, plot, names)
        files.append(Path(plot))
    # the largest lag is where a command jumps (to the first keyframe, a gait's step);
    # how closely the servos follow shows in the lag of 95 % of the readings
    lag, typical = float(done.lag.max()), float(np.percentile(done.lag, 95))
    caption = "Commanded (dashed) and measured (solid) turns and current per TSA"
    loads = seq.loads(load_scale if dry_run else 1.0)
    peak = ", ".join(f"{names[i]} {c.peak:.1f}" for i, c in loads.items())
    return Outputs(
        files=files,
        images=[(Path(plot), caption)] if plot else [],
        numbers=[
            ("cycle / readings", f"{seq.cycle:g} s / {done.target.size}"),
            (
                "lag of the servos behind their commands: 95 % of readings / largest",
                f"{typical:.3f} / {lag:.3f} turns",
            ),
            ("maximum commanded twist", f"{done.target.max():.2f} turns"),
            *([("peak load per servo (N mm)", peak)] if loads else []),
            ("largest current", f"{abs(done.current).max():.0f} mA"),
        ],
        messages=[
            f"ran {seq.repeat} x {seq.cycle:g} s on servos {seq.ids}"
            f"{' (dry run)' if dry_run else ''}: {done.target.size} readings, "
            f"lag {typical:.3f} turns (95 % of readings), {lag:.3f} at most",
            *(f"wrote {p}" for p in files),
        ],
        result=done,
    )


def run_mjcf(source: PathLike, routes: Sequence[PathLike] = (), output: PathLike = "") -> Outputs:
    """A MuJoCo model (MJCF) of a design and its routes, or of a robot file: model.xml.

    Panels as bodies, creases as hinges (eq. 6 ranges), strings as tendons through the
    holes, one TSA actuator per string (docs/mujoco.md). Written atomically.
    """
    from origami_cad.simulation.mjcf import to_mjcf

    routes = list(routes or ())
    check_outputs([source, *routes], files=[output])
    _check_suffix(output, (".xml",), "an MJCF model")
    xml = to_mjcf(source, routes)
    with atomic_write(output, "w", encoding="utf-8") as fh:
        fh.write(xml)
    keys = {"panel": 'class="panel"', "hinge": 'type="hinge"', "connect": "<connect "}
    counts = {k: xml.count(v) for k, v in keys.items()} | {"spatial": xml.count("<spatial ")}
    counts["panel"] //= 2  # two printed halves each
    return Outputs(
        files=[Path(output)],
        numbers=[
            (
                "panels / hinges / loop constraints",
                "{panel} / {hinge} / {connect}".format(**counts),
            ),
            ("strings (tendons, one TSA actuator each)", str(counts["spatial"])),
        ],
        messages=[f"wrote {output}"],
    )
