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


#: The files of a printed sheet (``write_fabrication``, the glTF and the panels' plot), and
#: the pictures ``renders`` adds.
SHEET_FILES = (
    "infills.stl", "midlayers.stl", "shells.stl", "creases.stl", "assembly.step", "print.3mf",
    "pattern_with_holes.fold", "fabrication.json", "panels.png",
)  # fmt: skip
RENDERS = ("assembled.png", "exploded.png", "section.png")


@register
class Fabricate(Command):
    """Dual-material printable structure: four STLs, STEP, 3MF, parts.glb, panels.png, and more.

    The paper's b = 3, h = 2.2, t = 0.4 mm by default; ``bias``, ``theta_max`` or
    ``p_max`` (eq. 6), ``height``, ``thickness``... set them. ``hole`` gives hole
    centres (x, y in mm) that replace the automatic ones. ``renders`` adds assembled,
    exploded and section pictures. ``unit``, ``scale`` and ``width`` size an imported
    pattern. ``slicer`` is the slicer print.3mf is laid out for; ``bed`` (x, y in mm)
    the print bed: a larger sheet is refused before any work (without it, a sheet larger
    than PrusaSlicer's default 200 x 200 mm bed is warned about, as the library does).

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
        Option("bed", "float", "your printer's bed: a larger sheet is refused (without it: a "
               "warning past 200 x 200)", "mm", None, nargs=2, metavar=("X", "Y"), min=0,
               open_min=True, max=1e5),
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
        from origami_cad.fabrication import fabricate, fabrication_numbers, write_fabrication
        from origami_cad.viz.fabrication_plots import save_panels_png
        from origami_cad.viz.gltf import write_parts_glb
        from origami_cad.viz.parts_render import render_fabrication

        params = _params(a)
        loaded, warned = self.load(a, a.design)
        bed = tuple(map(float, a.bed)) if a.bed is not None else None
        fab = fabricate(loaded, params, bed=bed, progress=a.progress)
        label = a.name or Path(a.design).stem
        with self.stage(a, loaded) as stage:
            written = write_fabrication(fab, stage, slicer=a.slicer)
            write_parts_glb(fab, stage / "parts.glb")
            save_panels_png(fab, stage / "panels.png")
            images = [(stage / "parts.glb", f"{label}: the printed parts, PLA white, TPU red")]
            images.append((stage / "panels.png", f"{label}: panels, operation regions and holes"))
            if a.renders:
                images += render_fabrication(loaded.pattern, fab, stage, label)
            files = moved(staged(stage), stage, a.folder)
        summary, numbers = fabrication_numbers(fab, label, written.timings)
        return Outputs(
            files=files,
            images=[(Path(a.folder) / p.name, c) for p, c in images],
            numbers=numbers,
            messages=[
                *warned,
                summary,
                *(f"warning: {w}" for w in fab.warnings),
                wrote(a.folder, files),
            ],
            result=fab,
        )
