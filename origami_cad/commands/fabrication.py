"""The fabrication command: ``fabricate`` (the dual-material printable structure)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from origami_cad.commands._base import (
    SIZING,
    Command,
    Option,
    Outputs,
    moved,
    register,
    staged,
    wrote,
)
from origami_cad.errors import OptionsError

__all__: list[str] = []

_MM = {"kind": "float", "unit": "mm", "min": 0.0, "max": 1000.0}

#: The options that are fields of ``FabricationParams`` (or give its bias, eq. 6).
PARAM_OPTIONS = (
    Option("bias", help="inner bias b", **_MM),
    Option("theta_max", "float", "largest fold angle of the creases (gives b, eq. 6)", "deg",
           min=0, open_min=True, max=180),
    Option("p_max", "float", "largest fold ratio in (0, 1] (gives b, eq. 6)", min=0,
           open_min=True, max=1, metavar="P"),
    Option("height", help="panel height h", open_min=True, **_MM),
    Option("thickness", help="crease layer t", open_min=True, **_MM),
    Option("shell", help="shell wall s", **_MM),
    Option("midlayer_bias", help="mid-layer inset m", **_MM),
    Option("border_margin", help="border inset", **_MM),
    Option("hole_diameter", help="hole diameter", open_min=True, **_MM),
    Option("holes", help="string holes: placed on every panel (auto), the pattern's own "
           "(pattern) or none", choices=("auto", "pattern", "none")),
)  # fmt: skip


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


def _fabrication_numbers(fab, name: str, exports: dict[str, float]) -> list[tuple[str, str]]:
    report = fab.report()
    vols = ", ".join(f"{n} {v['volume_mm3'] / 1000:.2f} cm3" for n, v in report["parts"].items())
    limits = f"{report['theta_max_deg']:.1f} deg, {100 * report['p_max']:.1f} %"
    numbers = [
        (f"{name}: panels / holes", f"{report['panels']} / {len(fab.holes)}"),
        (f"{name}: theta_max, p_max (eq. 6)", limits),
        (f"{name}: volumes", vols),
        (f"{name}: mass estimate", f"{report['total_mass_g']:.1f} g"),  # as solid
        (f"{name}: mass as printed (the 3MF's settings)", f"{report['printed_mass_g']:.1f} g"),
    ]
    if fab.limits.p_max_kinematic is not None:
        kinematic = f"{100 * fab.limits.p_max_kinematic:.1f} %"
        numbers.append((f"{name}: p_max of the folded structure (legs first)", kinematic))
    seconds = sum(fab.timings.values()) + sum(exports.values())
    numbers.append((f"{name}: build + export time", f"{seconds:.1f} s"))
    return numbers


def _params(a):
    """The command's ``FabricationParams``: given whole, or from its keywords (eq. 6)."""
    from origami_cad.fabrication import fabrication_params

    fields = {o.name: getattr(a, o.name) for o in PARAM_OPTIONS}
    if a.hole:
        fields["holes"] = [tuple(map(float, h)) for h in a.hole]
    if a.params is None:
        return fabrication_params(**fields)
    if any(v is not None for v in fields.values()):
        raise OptionsError("give either fabrication parameters or their keywords, not both")
    return a.params


def _summary(fab) -> str:
    report = fab.report()
    return (
        f"{report['panels']} panels, {len(fab.holes)} holes; theta_max = "
        f"{report['theta_max_deg']:.1f} deg, p_max = {100 * report['p_max']:.1f} %; "
        f"mass {report['printed_mass_g']:.1f} g as printed ({report['total_mass_g']:.1f} g solid)"
    )


#: The files of a printed sheet (``write_fabrication``, the glTF and the panels' plot), and
#: the pictures ``renders`` adds.
SHEET_FILES = (
    "infills.stl", "midlayers.stl", "shells.stl", "creases.stl", "assembly.step", "print.3mf",
    "pattern_with_holes.fold", "fabrication.json", "panels.png",
)  # fmt: skip
RENDERS = ("assembled.png", "exploded.png", "section.png")


@register
class Fabricate(Command):
    """Dual-material printable structure: four STLs, STEP, 3MF, parts.glb, fabrication.json...

    The paper's b = 3, h = 2.2, t = 0.4 mm by default; ``bias``, ``theta_max`` or
    ``p_max`` (eq. 6), ``height``, ``thickness``... set them. ``hole`` gives hole
    centres (x, y in mm) that replace the automatic ones. ``renders`` adds assembled,
    exploded and section pictures. ``unit``, ``scale`` and ``width`` size an imported
    pattern. ``slicer`` is the slicer print.3mf is laid out for; ``bed`` (x, y in mm)
    the print bed: a larger sheet is refused before any work.

    From Python, ``params`` is a whole ``FabricationParams`` instead of its keywords
    (:func:`~origami_cad.fabrication.fabrication_params`), and ``name`` prefixes the
    key numbers (for reports holding several structures).
    """

    NAME, INPUTS, OUTPUT, ARGS = "fabricate", ("design",), "folder", ("design", "folder", "params")
    PROGRESS = "panels built"
    FILES = (*SHEET_FILES, "parts.glb", *RENDERS)
    OPTIONS = (
        *PARAM_OPTIONS,
        Option("hole", "float", "a hole at X Y; repeat", "mm", nargs=2, repeat=True,
               metavar=("X", "Y"), min=-1e5, max=1e5),
        Option("renders", "flag", "also render the assembled parts"),
        Option("slicer", help="the slicer print.3mf is laid out for", default="prusa",
               choices=("prusa", "bambu", "orca")),
        Option("bed", "float", "print bed: a larger sheet is refused", "mm", (200.0, 200.0),
               nargs=2, metavar=("X", "Y"), min=0, open_min=True, max=1e5),
        *SIZING,
        Option("params", "object", "a FabricationParams instead of its keywords", flag=""),
        Option("name", help="prefix of the key numbers", default="", flag=""),
    )  # fmt: skip

    @classmethod
    def library_defaults(cls) -> dict[str, Any]:
        import dataclasses

        from origami_cad.fabrication.params import FabricationParams

        fields = dataclasses.fields(FabricationParams)
        return {f.name: f.default for f in fields if f.default is not dataclasses.MISSING}

    def run(self, a) -> Outputs:
        from origami_cad.fabrication import fabricate, write_fabrication
        from origami_cad.viz.fabrication_plots import save_panels_png
        from origami_cad.viz.gltf import write_parts_glb

        params = _params(a)
        loaded, warned = self.load(a, a.design)
        fab = fabricate(loaded, params, bed=tuple(map(float, a.bed)), progress=a.progress)
        label = a.name or Path(a.design).stem
        with self.stage(a, loaded) as stage:
            written = write_fabrication(fab, stage, slicer=a.slicer)
            write_parts_glb(fab, stage / "parts.glb")
            save_panels_png(fab, stage / "panels.png")
            images = [(stage / "parts.glb", f"{label}: the printed parts, PLA white, TPU red")]
            images.append((stage / "panels.png", f"{label}: panels, operation regions and holes"))
            if a.renders:
                images += _render_fabrication(loaded.pattern, fab, stage, label)
            files = moved(staged(stage), stage, a.folder)
        return Outputs(
            files=files,
            images=[(Path(a.folder) / p.name, c) for p, c in images],
            numbers=_fabrication_numbers(fab, label, written.timings),
            messages=[
                *warned,
                _summary(fab),
                *(f"warning: {w}" for w in fab.warnings),
                wrote(a.folder, files),
            ],
            result=fab,
        )
