"""Fabricate a crease pattern: footprints, holes, solids, checks and every export."""

from __future__ import annotations

import json
import math
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from origami_cad import __version__
from origami_cad._fileio import atomic_write
from origami_cad.errors import PatternError
from origami_cad.fabrication.panels import PanelOutline, panel_outlines, place_holes
from origami_cad.fabrication.params import DENSITY_G_CM3, FabricationParams
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES, Parts, build_parts
from origami_cad.pattern.design import Design
from origami_cad.pattern.model import CreasePattern, Hole

__all__ = ["Fabrication", "crease_limits", "fabricate", "write_fabrication"]


@dataclass
class Fabrication:
    """A fabricated structure: panels, holes, parts and what was measured.

    ``parts`` holds build123d solids and stays inside the fabrication stage;
    everything else is plain data.
    """

    pattern: CreasePattern
    params: FabricationParams
    outlines: list[PanelOutline]
    holes: list[tuple[int, float, float, float]]
    parts: Parts
    warnings: list[str] = field(default_factory=list)
    limits: dict[str, Any] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)

    @property
    def pattern_with_holes(self) -> CreasePattern:
        """The crease pattern carrying the placed holes (for FOLD files and routing)."""
        return self.pattern.with_holes(Hole(x, y, d) for _, x, y, d in self.holes)

    def volumes(self) -> dict[str, float]:
        """Volume of each part, mm^3."""
        return {n: self.parts.volume(n) for n in PART_NAMES}

    def report(self) -> dict[str, Any]:
        """The content of ``fabrication.json``."""
        vols = self.volumes()
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
                    "mass_g": vols[n] / 1000.0 * DENSITY_G_CM3[PART_MATERIALS[n]],
                }
                for n in PART_NAMES
            },
            "total_mass_g": sum(
                vols[n] / 1000.0 * DENSITY_G_CM3[PART_MATERIALS[n]] for n in PART_NAMES
            ),
            "holes": [
                {"panel": self.outlines[i].label, "x_mm": x, "y_mm": y, "diameter_mm": d}
                for i, x, y, d in self.holes
            ],
            "crease_limits": self.limits,
            "warnings": self.warnings,
            "timings_s": self.timings,
        }


def crease_limits(design: Design, params: FabricationParams, samples: int = 101) -> dict[str, Any]:
    """Where the rigid folding of ``design`` brings creases to ``theta_max`` (eq. 6).

    Every crease's fold angle grows with the fold ratio ``p`` at its own rate:
    the legs of a Miura fold faster than its main creases. Returns the fold
    ratio at which each crease reaches ``theta_max``, the structure's
    kinematic ``p_max`` (the first such ratio) and the creases that limit it.
    Empty when the pattern cannot be folded rigidly by the kinematics.

    This does not model collisions between several thick panels around one
    vertex (the paper's multi-layer caveat): creases that reach ``theta_max``
    first are where such collisions start.
    """
    from origami_cad.kinematics.folding import fold_sequence

    ratios = np.linspace(0.0, 1.0, samples)
    try:
        states = fold_sequence(design, ratios)
    except (PatternError, ImportError) as exc:
        return {"foldable": False, "reason": str(exc)}
    cp = design.pattern
    creases = np.flatnonzero(cp.edge_mask("M", "V"))
    angles = np.abs(np.array([s.fold_angles[creases] for s in states]))  # (samples, creases)
    limit = math.degrees(params.theta_max)
    reached = angles >= limit
    first = np.where(reached.any(axis=0), np.argmax(reached, axis=0), -1)
    p_first = np.where(first >= 0, ratios[np.maximum(first, 0)], np.nan)
    # refine by interpolation between samples
    for k in np.flatnonzero(first > 0):
        i = first[k]
        a0, a1 = angles[i - 1, k], angles[i, k]
        p_first[k] = ratios[i - 1] + (limit - a0) / (a1 - a0) * (ratios[i] - ratios[i - 1])
    if np.all(np.isnan(p_first)):
        return {"foldable": True, "p_max_kinematic": 1.0, "limiting_creases": []}
    p_kin = float(np.nanmin(p_first))
    limiting = creases[np.isclose(p_first, p_kin, atol=1e-3)]
    early = creases[p_first < params.p_max - 1e-3]
    mids = (cp.vertices[cp.edges[:, 0]] + cp.vertices[cp.edges[:, 1]]) / 2
    return {
        "foldable": True,
        "p_max_kinematic": p_kin,
        "limiting_creases": [
            {
                "edge": int(e),
                "midpoint_mm": mids[e].round(3).tolist(),
                "assignment": str(cp.assignments[e]),
            }
            for e in limiting[:50]
        ],
        "creases_before_p_max": len(early),
    }


def fabricate(
    source: CreasePattern | Design, params: FabricationParams | None = None
) -> Fabrication:
    """Build the printable structure of a crease pattern (or design).

    Raises
    ------
    PatternError
        Naming the panel or hole that does not fit, or the pattern's defect.
    """
    params = params or FabricationParams()
    design = source if isinstance(source, Design) else Design(source, None, "file")
    cp = design.pattern
    timings = {}
    t0 = time.perf_counter()
    outlines = panel_outlines(cp, params)
    holes = place_holes(cp, outlines, params)
    timings["panels_and_holes"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    sheet = shapely.union_all(cp.face_polygons())
    parts = build_parts(outlines, holes, params, sheet)
    timings["solids"] = time.perf_counter() - t0
    warnings = []
    infill = params.half_height - params.shell
    if infill < 0.2:
        warnings.append(
            f"the infill is only {infill:.2g} mm thick between the shell skin and the crease "
            f"layer (half height {(params.half_height):.2g} mm, shell {params.shell:g} mm): "
            "consider a thinner shell or a taller panel"
        )
    t0 = time.perf_counter()
    limits = crease_limits(design, params) if design.tg is not None else {}
    timings["crease_limits"] = time.perf_counter() - t0
    if limits.get("creases_before_p_max"):
        warnings.append(
            f"{limits['creases_before_p_max']} creases reach theta_max before the main crease "
            f"(structure p_max {limits['p_max_kinematic']:.3f} < eq. 6 p_max "
            f"{params.p_max:.3f})"
        )
    return Fabrication(cp, params, outlines, holes, parts, warnings, limits, timings)


def write_fabrication(fab: Fabrication, folder: str | os.PathLike[str]) -> dict[str, Path]:
    """Write the four STLs, ``assembly.step``, ``print.3mf``, ``fabrication.json`` and a FOLD."""
    from origami_cad.fabrication.export import export_3mf, export_step_assembly, export_stls
    from origami_cad.pattern.fold import write_fold

    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    paths = dict(export_stls(fab.parts, out))
    fab.timings["stl"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    paths["step"] = export_step_assembly(fab.parts, out / "assembly.step")
    fab.timings["step"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    paths["3mf"] = export_3mf(fab.parts, out / "print.3mf", name=fab.pattern.title or "origami")
    fab.timings["3mf"] = time.perf_counter() - t0
    paths["fold"] = write_fold(fab.pattern_with_holes, out / "pattern_with_holes.fold")
    paths["json"] = out / "fabrication.json"
    with atomic_write(paths["json"], "w", encoding="utf-8") as fh:
        json.dump(fab.report(), fh, indent=1)
    return paths
