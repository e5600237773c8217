"""Commands on crease patterns: ``convert``, ``check``, ``pattern``, ``fold``, ``tg``."""

from __future__ import annotations

from pathlib import Path

from origami_cad.commands._base import (
    SIZING,
    Command,
    Option,
    Outputs,
    file_format,
    register,
    wrote,
)
from origami_cad.commands._options import TOLERANCE
from origami_cad.errors import DesignError

__all__ = ["FOLD_SUFFIXES", "MAX_FRAMES", "pattern_numbers"]

FOLD_SUFFIXES = (".fold", ".png", ".gif", ".glb", ".step")
MAX_FRAMES = 10_000  # folded states in one file or animation
_LABELS = Option("labels", "flag", "panel labels on a .png")


def _pattern_suffixes() -> tuple[str, ...]:
    """What a pattern is written as: the registered formats' suffixes, and .png."""
    from origami_cad.pattern.formats import WRITERS

    return (*WRITERS, ".png")


def pattern_numbers(cp) -> list[tuple[str, str]]:
    """The key numbers of a pattern: panels, creases (M / V) and its size in mm."""
    n_m, n_v = int((cp.assignments == "M").sum()), int((cp.assignments == "V").sum())
    width, height = cp.bounds[2] - cp.bounds[0], cp.bounds[3] - cp.bounds[1]
    return [
        ("panels", str(len(cp.faces))),
        ("creases (M / V)", f"{n_m} / {n_v}"),
        ("pattern size", f"{width:.1f} x {height:.1f} mm"),
    ]


def _write_pattern_file(cp, out: Path, labels: bool = False) -> None:
    from origami_cad.pattern import write_pattern
    from origami_cad.viz import save_pattern_png

    fmt = file_format(out, _pattern_suffixes())
    if fmt == ".png":
        save_pattern_png(cp, out, labels=labels)
    else:
        write_pattern(cp, out, fmt=fmt)


@register
class Convert(Command):
    """Read a pattern (.fold/.dxf/.svg/.opx/.cp) and write it as .fold, .dxf, .svg, .opx, .cp or a
    .png picture.

    ``unit``, ``scale`` and ``width`` size an imported pattern and ``tolerance`` joins it
    up.
    """

    NAME, INPUTS, WHAT = "convert", ("source", "output"), "a pattern"
    OPTIONS = (_LABELS, *SIZING)

    def suffixes(self):
        return _pattern_suffixes()

    def outputs(self, a):
        return [a.output], []

    def formats(self, a):  # the output is the second positional argument, not -o
        return [(a.output, self.suffixes(), self.WHAT)]

    def inputs(self, a):
        return [a.source]

    def run(self, a) -> Outputs:
        from origami_cad.pattern import read_pattern, size_warnings

        cp = read_pattern(a.source, **self.size(a))
        _write_pattern_file(cp, Path(a.output), a.labels)
        n = f"{cp.n_vertices} vertices, {cp.n_edges} edges, {len(cp.faces)} panels"
        warned = [f"warning: {w}" for w in size_warnings(cp)]
        return Outputs(
            files=[Path(a.output)], messages=[*warned, wrote(a.output, detail=n)], result=cp
        )


@register
class Check(Command):
    """Validate a pattern or design (any input fold takes); exit status 1 when it has
    errors. Writes nothing.

    It says what the import merged (vertices, vertices put on an edge, crossing points:
    how many, the largest gap closed and the tolerance). ``angle_tolerance`` is the
    least tolerance of Kawasaki's theorem, degrees (more where the file's coordinates
    were rounded; the defect is how far a vertex's even sectors miss 180 deg); a vertex
    that cannot fold flat is a warning, as it still folds in 3D.
    ``unit``, ``scale``, ``width`` and ``tolerance`` size and join up an imported pattern.
    The result (``Outputs.result``) is the list of problems found.
    """

    NAME, INPUTS = "check", ("source",)
    OPTIONS = (
        Option("angle_tolerance", "float", "Kawasaki's defect, at least", "deg", 0.01, min=0,
               max=5),
        Option("verbose", "flag", "also list what was normalised", short="-v"),
        *SIZING,
    )  # fmt: skip

    def run(self, a) -> Outputs:
        import math

        from origami_cad.pattern import Severity

        cp = self.load(a, a.source)[0].pattern  # its size warning is one of its notes
        problems = cp.check(angle_tolerance=math.radians(a.angle_tolerance))
        shown = [p for p in problems if p.severity != Severity.INFO or a.verbose]
        merged = [p for p in problems if p.code == "merged" and p not in shown]
        lines = [f"{a.source}: {cp!r}", *(f"  {p}" for p in merged + shown)]
        errors = sum(p.severity == Severity.ERROR for p in problems)
        warnings = sum(p.severity == Severity.WARNING for p in problems)
        lines.append(f"{errors} errors, {warnings} warnings")
        numbers = [("check", f"{errors} errors, {warnings} warnings"), *pattern_numbers(cp)]
        c = cp.cleanup
        if c.merged or c.snapped or c.crossings_merged:
            gap = max(c.merged_gap, c.snapped_gap, c.crossing_gap)
            numbers.append(("merged", f"{c.merged + c.snapped + c.crossings_merged} "
                            f"(largest gap {gap:.2g} mm)"))  # fmt: skip
        status = 1 if errors else 0
        return Outputs(messages=lines, numbers=numbers, result=problems, status=status)


@register
class Pattern(Command):
    """Compute a design file's crease pattern; write it to each of ``outputs`` (by extension)."""

    NAME, INPUTS, OUTPUT, WHAT = "pattern", ("design",), "outputs", "a pattern"
    OPTIONS = (_LABELS, TOLERANCE)

    def suffixes(self):
        return _pattern_suffixes()

    def run(self, a) -> Outputs:
        loaded, warned = self.load(a, a.design, sized=False)
        cp = loaded.pattern
        result = Outputs(result=loaded, numbers=pattern_numbers(cp), messages=warned)
        for out in map(Path, a.outputs):
            _write_pattern_file(cp, out, a.labels)
            result.files.append(out)
            result.messages.append(wrote(out))
            if out.suffix.lower() == ".png":
                result.images.append((out, "Crease pattern (mountain red, valley blue dashed)"))
        result.messages += [f"note: {n}" for n in (loaded.tg.notes if loaded.tg else ())]
        result.messages.append(repr(cp))
        if loaded.tg is not None:
            betas = ", ".join(f"{b:.2f} deg" for b in loaded.tg.shape_angles)
            n = len(loaded.tg.shape_angles)
            result.numbers.insert(0, (f"shape angles beta_1..beta_{n} (eq. 1)", betas))
        return result


def _write_folded(loaded, states, out: Path, ratio: float, view) -> None:
    """The folded states as ``out``'s format (.fold, .png, .step, .glb or .gif)."""
    import numpy as np

    from origami_cad.pattern import folded_frame, write_fold
    from origami_cad.viz.render3d import render_folded, render_folding_gif

    # the pattern folded: a cut pattern's general fold has its cuts open
    cp, suffix = states[-1].pattern or loaded.pattern, file_format(out, FOLD_SUFFIXES)
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


@register
class Fold(Command):
    """Fold from p = 0 to ``ratio``; write each ``outputs`` file: .fold frames, a .png
    of the end, .gif, .glb, or a .step of the printed structure folded at ``ratio`` (the
    default fabrication parameters with the pattern's own string holes; closed form only).

    ``method``: ``auto`` folds in closed form where it applies, else by the general
    solver, whose largest edge strain is reported (a warning when large); ``closed-form``
    or ``general`` ask for one. ``frames`` states are written (1: only ``ratio``; a .gif or
    .glb of 1 frame gets 30), each lying on the table, centred on the flat sheet; a .glb
    holds them as morph targets played by an animation. ``unit``, ``scale`` and
    ``width`` size an imported pattern.

    From Python, ``view`` is the camera of the renders: ``"iso"``, ``"xy"``... or a
    direction. The .step is ``Fabrication.assembly``; the general solver is
    :mod:`origami_cad.simulation.folder` (the strain limit:
    :data:`~origami_cad.simulation.folder.STRAIN_LIMIT` percent); the placement
    :mod:`origami_cad.kinematics.placement`, the .glb :mod:`origami_cad.viz.gltf`.
    """

    NAME, INPUTS, OUTPUT = "fold", ("design",), "outputs"
    SUFFIXES, WHAT = FOLD_SUFFIXES, "the folded state"
    OPTIONS = (
        Option("ratio", "float", "fold ratio p in [0, 1]", default=0.5, min=0, max=1),
        Option("frames", "int", "states from p = 0 to --ratio", default=1, min=1, max=MAX_FRAMES),
        Option("view", help="camera of the renders", default="iso", flag="", parse=str),
        Option(
            "method",
            help="auto: the closed form where it applies, else the general solver",
            default="auto",
            choices=("auto", "closed-form", "general"),
        ),
        *SIZING,
    )

    def run(self, a) -> Outputs:
        from origami_cad.simulation.folder import fold_notes, placed_fold_states

        outs, ratio = [Path(o) for o in a.outputs], a.ratio
        loaded, warned = self.load(a, a.design)
        kinds = [file_format(out, FOLD_SUFFIXES) for out in outs]
        animated = any(k in (".gif", ".glb") for k in kinds)
        frames = a.frames if a.frames > 1 or not animated else 30
        states, strained = placed_fold_states(loaded, ratio, frames, a.method.replace("-", " "))
        strained = [f"warning: {m}" for m in strained]
        method, strain = states[-1].method, max(s.strain for s in states)
        how = method if method == "closed form" else f"{method}, largest strain {strain:.3g} %"
        end = states[-1].fold_angles if ratio > 0 else None
        result = Outputs(
            files=outs,
            messages=[*warned, *strained, *fold_notes(states[-1].pattern, end, method)],
            numbers=[("fold method", method), ("largest edge strain", f"{strain:.3g} %")],
            result=states,
        )
        for out, kind in zip(outs, kinds, strict=True):
            # one state asked for: a still picture or file holds only it, an animation 30
            shown = states if a.frames > 1 or kind in (".gif", ".glb") else states[-1:]
            _write_folded(loaded, shown, out, ratio, a.view)
            plural = "s" if len(shown) > 1 else ""
            detail = f"{len(shown)} state{plural}, p up to {ratio:g}; {how}"
            result.messages.append(wrote(out, detail=detail))
            if kind not in (".fold", ".step"):
                still = f"Folded at p = {ratio:g}" if kind == ".png" else None
                result.images.append((out, still or f"Folding from p = 0 to {ratio:g}"))
        return result


@register
class TG(Command):
    """Plot a design's TG chain at p = 0, 0.25, 0.5, 0.75, 1 and the path of T_e (.png)."""

    NAME, INPUTS, OUTPUT = "tg", ("design",), "output"
    SUFFIXES, WHAT = (".png",), "the TG plot"

    def run(self, a) -> Outputs:
        from origami_cad.pattern.design import load_design
        from origami_cad.viz.tg_plot import save_tg_png

        loaded = load_design(a.design)
        if loaded.tg is None:
            raise DesignError(f"{a.design}: kind {loaded.kind!r} has no transition graph")
        save_tg_png(loaded.tg, a.output)
        out = Path(a.output)
        caption = "TG chain at several p and the path of T_e"
        return Outputs(files=[out], images=[(out, caption)], messages=[wrote(out)])
