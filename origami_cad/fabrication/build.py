"""Fabricate a crease pattern, second step: build the B-rep solids of a plan, and export them."""

from __future__ import annotations

import dataclasses
import logging
import math
import os
import time
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from origami_cad import __version__
from origami_cad._args import Arg, checked
from origami_cad._display import View3DDisplay
from origami_cad._fileio import atomic_write
from origami_cad._toml import json_text, printable
from origami_cad.errors import FabricationError, OutputError, warn
from origami_cad.fabrication.panels import PanelOutline, sheet_outline
from origami_cad.fabrication.params import DENSITY_G_CM3, FabricationParams
from origami_cad.fabrication.plan import (
    DEFAULT_BED,
    CreaseLimits,
    PanelPlan,
    check_bed,
    check_panel_count,
    plan_panels,
)
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES, Parts, build_parts
from origami_cad.pattern.design import Design
from origami_cad.pattern.model import CreasePattern, Hole

log = logging.getLogger(__name__)

__all__ = [
    "Fabrication",
    "FabricationFiles",
    "build_fabrication",
    "fabricate",
    "fabrication_numbers",
    "write_fabrication",
]


@dataclass(repr=False)
class Fabrication(View3DDisplay):
    """A fabricated structure: its :class:`PanelPlan`, the solids built from it, timings.

    ``parts`` holds build123d solids and stays inside the fabrication stage;
    everything else is plain data. The plan's fields are readable here too
    (``fab.holes`` is ``fab.plan.holes``).

    In a notebook it shows the printed parts in an interactive 3D view (and a PNG);
    :attr:`part` is the flat sheet's assembly, which ocp_vscode's ``show(fab)`` draws
    (it takes the object as it takes a build123d ``BuildPart``: ``_obj``, ``_obj_name``).
    """

    plan: PanelPlan
    parts: Parts
    timings: dict[str, float] = field(default_factory=dict)
    #: the design it was made from, when it came from one (folds it in :meth:`assembly`)
    design: Design | None = None
    #: the slicer ``print.3mf`` is laid out for (``export_3mf``'s ``slicer``)
    slicer: str = "prusa"
    #: the flat sheet's assembly, made on first use of :attr:`part`
    _sheet: Any = field(default=None, init=False, compare=False)

    #: what a build123d builder declares, so that ocp_vscode's ``show`` takes :attr:`part`
    _obj_name = "part"
    _tag = "Fabrication"

    def __repr__(self) -> str:
        """One line: the pattern's title, panels, holes, the parameters (mm), solids, warnings."""
        p, plan = self.params, self.plan
        title = f" {self.pattern.title!r}" if self.pattern.title else ""
        solids = sum(len(v) for v in self.parts.solids.values())
        return (
            f"<Fabrication{title}: {len(plan.outlines)} panels, {len(plan.holes)} holes, "
            f"bias {p.bias:g} mm, height {p.height:g} mm, crease {p.thickness:g} mm, "
            f"{solids} solids, {len(plan.warnings)} warnings>"
        )

    @property
    def part(self) -> Any:
        """The flat printed sheet as a build123d ``Compound`` tree, :meth:`assembly` at
        ratio 0 (made once, then kept); what ``ocp_vscode.show(fab)`` draws."""
        if self._sheet is None:
            self._sheet = self.assembly(0.0)
        return self._sheet

    @property
    def _obj(self) -> Any:
        """The shape a viewer of build123d builders draws (ocp_vscode): :attr:`part`."""
        return self.part

    def assembly(self, ratio: float = 0.0, design: Design | None = None) -> Any:
        """The printed sheet as a build123d ``Compound`` tree with joints, folded to ``ratio``.

        sheet -> one child per panel (labelled as the FOLD's ``faces_origami_cad:labels``)
        holding its infill, shell and mid-layer solids, and ``creases``, the crease strips;
        every solid in its material's colour. See
        :func:`~origami_cad.fabrication.assembly.sheet_assembly` (``ratio`` in [0, 1],
        ``design`` default :attr:`design`).
        """
        from origami_cad.fabrication.assembly import sheet_assembly

        return sheet_assembly(self, ratio, design or self.design)

    @property
    def pattern(self) -> CreasePattern:
        """The crease pattern."""
        return self.plan.pattern

    @property
    def params(self) -> FabricationParams:
        """The fabrication parameters."""
        return self.plan.params

    @property
    def outlines(self) -> tuple[PanelOutline, ...]:
        """Footprints of every panel."""
        return self.plan.outlines

    @property
    def holes(self) -> tuple[Hole, ...]:
        """The string holes, mm (panel of each: ``plan.hole_panels``)."""
        return self.plan.holes

    @property
    def limits(self) -> CreaseLimits:
        """Where the rigid folding brings creases to ``theta_max``."""
        return self.plan.limits

    @property
    def warnings(self) -> tuple[str, ...]:
        """What may print or fold badly."""
        return self.plan.warnings

    @property
    def pattern_with_holes(self) -> CreasePattern:
        """The crease pattern carrying the placed holes (for FOLD files and routing)."""
        return self.plan.pattern_with_holes

    def volumes(self) -> dict[str, float]:
        """Volume of each part, mm^3."""
        return {n: self.parts.volume(n) for n in PART_NAMES}

    def solid_mass(self) -> dict[str, float]:
        """Mass of each part as a solid (its whole volume at its material's density), g."""
        vols = self.volumes()
        return {n: vols[n] / 1000.0 * DENSITY_G_CM3[PART_MATERIALS[n]] for n in PART_NAMES}

    def printed_mass(self) -> dict[str, float]:
        """Mass of each part as printed with the settings ``print.3mf`` carries (perimeters,
        top and bottom layers, infill: :mod:`~origami_cad.fabrication.printmass`), g."""
        from origami_cad.fabrication.meshing import part_meshes
        from origami_cad.fabrication.printmass import printed_mass
        from origami_cad.fabrication.slicer import slicer_settings

        s = slicer_settings(self.params)
        return {
            n: printed_mass({PART_MATERIALS[n]: part_meshes(self.parts, n)}, s)[PART_MATERIALS[n]]
            for n in PART_NAMES
        }

    def _bias_report(self, labels) -> dict[str, Any]:
        """Each panel's inner bias (mm) and the panels without a hole, when some panel was
        too small for the default bias, each panel's shell wall (mm) when some panel got
        a thinner one, and each panel's mid-layer margin (mm) and the panels printed in TPU
        alone when some panel got a narrower margin or no PLA (nothing otherwise: the file
        stays as it was)."""
        out: dict[str, Any] = {}
        if self.plan.biases is not None:
            holed = set(self.plan.hole_panels.tolist())
            out["panel_bias_mm"] = {
                lab: float(b) for lab, b in zip(labels, self.plan.biases, strict=True)
            }
            out["panels_without_hole"] = (
                [lab for i, lab in enumerate(labels) if i not in holed]
                if self.params.holes == "auto"
                else []
            )
        if self.plan.shells is not None:
            out["panel_shell_mm"] = _per_panel(labels, self.plan.shells)
        if self.plan.midlayers is not None:
            out["panel_midlayer_bias_mm"] = _per_panel(labels, self.plan.midlayers)
            out["panels_tpu_only"] = [labels[i] for i in sorted(self.plan.tpu_only)]
        return out

    def report(self) -> dict[str, Any]:
        """The content of ``fabrication.json``: masses in g, ``total_mass_g`` the parts as
        solids, ``printed_mass_g`` as printed with the 3MF's settings (``robot.json``'s)."""
        vols, solid, printed = self.volumes(), self.solid_mass(), self.printed_mass()
        labels = self.pattern.face_labels
        return {
            "origami_cad_version": __version__,
            "parameters": self.params.to_dict(),
            "theta_max_deg": math.degrees(self.params.theta_max),
            "p_max": self.params.p_max,
            "panels": len(self.outlines),
            "parts": {
                n: {
                    "material": PART_MATERIALS[n],
                    "solids": len(self.parts.solids[n]),
                    "volume_mm3": vols[n],
                    "mass_g": solid[n],
                    "printed_mass_g": printed[n],
                }
                for n in PART_NAMES
            },
            "total_mass_g": sum(solid.values()),
            "printed_mass_g": sum(printed.values()),
            "holes": [
                {"panel": labels[i], "x_mm": h.x, "y_mm": h.y, "diameter_mm": h.diameter}
                for h, i in zip(self.holes, self.plan.hole_panels.tolist(), strict=True)
            ],
            **self._bias_report(labels),
            "crease_limits": self.limits.to_dict(),
            "warnings": list(self.warnings),
            "timings_s": self.timings,
        }


def _per_panel(labels, values) -> dict[str, float | None]:
    """A value (mm) per panel label; ``None`` for NaN (a panel in TPU alone has no shell wall
    and no mid-layer)."""
    pairs = zip(labels, values, strict=True)
    return {lab: float(v) if math.isfinite(v) else None for lab, v in pairs}


def build_fabrication(
    plan: PanelPlan, progress: Callable[[int, int], None] | None = None
) -> Fabrication:
    """Build the B-rep solids of the four parts of a plan (the second step of fabrication);
    ``progress(panels built, panels)`` is called after each panel."""
    cp = plan.pattern
    t0 = time.perf_counter()
    sheet = sheet_outline(cp)
    outlines = list(plan.outlines)
    parts = build_parts(outlines, plan.holes, plan.hole_panels, plan.params, sheet, progress)
    seconds = time.perf_counter() - t0
    log.info("built the solids of %d panels in %.1f s", len(outlines), seconds)
    return Fabrication(plan, parts, {**plan.timings, "solids": seconds})


@checked(
    FabricationError,
    source=Arg("object", types=(CreasePattern, Design), optional=False),
    params=Arg("object", types=(FabricationParams,)),
    bed=Arg("floats", length=2, min=0.0, open_min=True, max=1e5),
    progress=Arg("callable", length=2),
)
def fabricate(
    source: CreasePattern | Design,
    params: FabricationParams | None = None,
    bed: tuple[float, float] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Fabrication:
    """Plan the panels of a crease pattern (or design) and build its printable solids.

    ``build_fabrication(plan_panels(source, params))``; use :func:`plan_panels`
    alone when no solid is needed (plots, hole positions, part placement). With
    ``bed`` (x, y in mm), a sheet that does not lie flat on it is refused before any
    work (:func:`check_bed`); without, it is only warned about against
    :data:`DEFAULT_BED`. ``progress(panels built, panels)`` is called after each panel.

    What may print or fold badly (``Fabrication.warnings``: panels given a smaller bias,
    a thin infill, creases that reach their limit first) is also said through
    :func:`origami_cad.errors.warn`: a :class:`~origami_cad.errors.OrigamiCadWarning`
    and the ``origami_cad`` logger.

    Raises
    ------
    FabricationError
        The sheet is larger than ``bed``, or has more than
        :data:`~origami_cad.fabrication.plan.MAX_FABRICATED_PANELS` panels.
    PatternError
        Naming the panel or hole that does not fit, or the pattern's defect.
    """
    cp = source.pattern if isinstance(source, Design) else source
    if bed is not None:
        check_bed(cp, bed)
    check_panel_count(cp)
    fab = build_fabrication(plan_panels(source, params, bed or DEFAULT_BED), progress)
    for line in fab.warnings:
        warn(line, stacklevel=2)
    if isinstance(source, Design):  # the printed panels: merged across facet creases
        merged = source.pattern is not fab.pattern
        fab.design = dataclasses.replace(source, pattern=fab.pattern) if merged else source
    return fab


@dataclass(frozen=True)
class FabricationFiles(Mapping):
    """What :func:`write_fabrication` wrote: ``{key: path}`` (``files["3mf"]``, ``files["json"]``,
    one key per part's STL...) and what it measured, ``timings`` (s per export format, in
    the registry's order), and the ``slicer`` ``print.3mf`` is laid out for. The
    :class:`Fabrication` it wrote is left as it was."""

    paths: dict[str, Path]
    timings: dict[str, float]
    slicer: str

    def __getitem__(self, key: str) -> Path:
        return self.paths[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self.paths)

    def __len__(self) -> int:
        return len(self.paths)


@checked(
    FabricationError,
    fab=Arg("object", types=(Fabrication,), optional=False),
    folder=Arg("path", optional=False),
    slicer=Arg("str"),
)
def write_fabrication(
    fab: Fabrication, folder: str | os.PathLike[str], slicer: str | None = None
) -> FabricationFiles:
    """Write the four STLs, ``assembly.step``, ``print.3mf``, ``fabrication.json`` and a FOLD.

    ``slicer`` (``"prusa"``, ``"bambu"`` or ``"orca"``; default :attr:`Fabrication.slicer`)
    is the slicer ``print.3mf`` is laid out for. Each file is written whole or not at all.
    ``fab`` is not changed: the export times (s) go into ``fabrication.json``'s
    ``timings_s`` beside the build's and into the returned :class:`FabricationFiles`.

    Every format is written here, in this process: a forked writer beside the others (tried
    for the STEP) hangs when OCC's thread pool is running in the parent (the child waits for
    workers that were not copied with it).
    """
    from origami_cad.fabrication.exports import WRITERS
    from origami_cad.fabrication.slicer import SLICERS
    from origami_cad.pattern.formats.fold import write_fold

    if slicer is not None and slicer not in SLICERS:
        raise FabricationError(f"slicer must be one of {', '.join(SLICERS)}, got {slicer!r}")
    # the writers read the slicer and the report the timings from a copy: fab stays as given
    written_fab = dataclasses.replace(fab, slicer=slicer or fab.slicer, timings=dict(fab.timings))
    written_fab._sheet = fab._sheet

    out = Path(folder)
    if out.exists() and not out.is_dir():
        raise OutputError(
            f"{printable(str(folder), 300)}: is a file, not a folder to write the fabrication into"
        )
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(
            f"{printable(str(folder), 300)}: cannot make this folder ({exc.strerror})"
        ) from None
    written: dict[str, dict[str, Path]] = {}
    timings: dict[str, float] = {}
    for fmt, write in WRITERS.items():
        written[fmt], timings[fmt] = _timed_write(write, written_fab, out)
    written_fab.timings.update(timings)
    paths = {key: path for fmt in WRITERS for key, path in written[fmt].items()}
    paths["fold"] = write_fold(fab.pattern_with_holes, out / "pattern_with_holes.fold")
    paths["json"] = out / "fabrication.json"
    text = json_text(written_fab.report(), str(paths["json"]), FabricationError, indent=1)
    with atomic_write(paths["json"], "w", encoding="utf-8") as fh:
        fh.write(text)
    return FabricationFiles(paths, timings, written_fab.slicer)


def _timed_write(write, fab: Fabrication, out: Path) -> tuple[dict[str, Path], float]:
    """``write(fab, out)`` and the seconds it took."""
    t0 = time.perf_counter()
    return write(fab, out), time.perf_counter() - t0


def fabrication_numbers(
    fab: Fabrication, name: str = "", exports: Mapping[str, float] | None = None
) -> tuple[str, list[tuple[str, str]]]:
    """What a fabrication tells its user: one summary line (panels, holes, eq. 6's
    ``theta_max`` deg and ``p_max`` %, the mass as printed and as solid, g) and the key
    numbers, each label prefixed by ``name`` (volumes cm3, masses g, the build's time plus
    ``exports``' seconds, e.g. :attr:`FabricationFiles.timings`)."""
    report = fab.report()
    summary = (
        f"{report['panels']} panels, {len(fab.holes)} holes; theta_max = "
        f"{report['theta_max_deg']:.1f} deg, p_max = {100 * report['p_max']:.1f} %; "
        f"mass {report['printed_mass_g']:.1f} g as printed ({report['total_mass_g']:.1f} g solid)"
    )
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
    seconds = sum(fab.timings.values()) + sum((exports or {}).values())
    numbers.append((f"{name}: build + export time", f"{seconds:.1f} s"))
    return summary, numbers
