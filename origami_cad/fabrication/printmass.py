"""The printed mass of solids from the print settings the 3MF carries, not their volume.

A slicer prints a solid as walls (``perimeters`` loops of ``extrusion_width`` around its
sides), solid skins (``top_solid_layers`` and ``bottom_solid_layers`` layers of
``layer_height`` under and over its upward and downward faces) and sparse infill
(``fill_density``) inside. :func:`print_volume` estimates that volume for one solid from
its volume and surface areas, :func:`mesh_print_areas` measures those on a triangle mesh,
and :func:`printed_mass` adds up the grams per material with
:data:`~origami_cad.fabrication.params.DENSITY_G_CM3`. The settings are
:func:`~origami_cad.fabrication.slicer.slicer_settings`, the ones ``print.3mf``
carries, so the estimate and the 3MF cannot disagree (docs/fabrication.md, "Printed mass").
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from origami_cad.fabrication.meshing import solid_mesh
from origami_cad.fabrication.params import DENSITY_G_CM3
from origami_cad.fabrication.slicer import slicer_settings

__all__ = ["mesh_print_areas", "print_volume", "printed_mass", "sheet_print_mass"]


def mesh_print_areas(verts: np.ndarray, tris: np.ndarray) -> dict[str, float]:
    """Volume and surface areas of a closed, outward-oriented triangle mesh (mm).

    Each triangle of area ``A`` and unit normal ``n`` adds ``A * hypot(nx, ny)`` to
    ``side_mm2`` (its area seen from the side: perimeter length times height),
    ``A * nz`` to ``top_mm2`` when it faces up and ``A * -nz`` to ``bottom_mm2`` when it
    faces down (its footprint). A chamfer counts in both, as a slicer gives it walls and
    skins.

    Returns
    -------
    dict
        ``volume_mm3``, ``side_mm2``, ``top_mm2``, ``bottom_mm2``.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[x, y, z] for x in (0, 10) for y in (0, 20) for z in (0, 2.0)])
    >>> t = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
    ...               [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    >>> {k: round(x, 6) for k, x in mesh_print_areas(v, t).items()}
    {'volume_mm3': 400.0, 'side_mm2': 120.0, 'top_mm2': 200.0, 'bottom_mm2': 200.0}
    """
    verts, tris = np.asarray(verts, dtype=float), np.asarray(tris, dtype=np.int64)
    a, b, c = (verts[tris[:, k]] for k in range(3))
    cross = np.cross(b - a, c - a)  # 2 A n
    volume = float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
    return {
        "volume_mm3": abs(volume),
        "side_mm2": float(np.hypot(cross[:, 0], cross[:, 1]).sum() / 2.0),
        "top_mm2": float(np.clip(cross[:, 2], 0, None).sum() / 2.0),
        "bottom_mm2": float(np.clip(-cross[:, 2], 0, None).sum() / 2.0),
    }


def print_volume(
    volume_mm3: float,
    side_mm2: float,
    top_mm2: float,
    bottom_mm2: float,
    settings: Mapping[str, Any] | None = None,
) -> float:
    """The volume of plastic a slicer lays down for one solid, mm^3.

    ``shell = perimeters * bead * side_mm2
    + layer_height * (top_solid_layers * top_mm2 + bottom_solid_layers * bottom_mm2)``,
    at most the solid's volume, where ``bead = extrusion_width - layer_height (1 - pi / 4)``
    is the width of a wall's bead of plastic (a rectangle with round sides, as Slic3r's
    flow model lays it), and the walls' part within the skin layers (the fraction
    ``layer_height (top + bottom) / thickness`` of the walls, ``thickness = volume /
    footprint``) counted once, as skin; the rest is filled at ``fill_density``
    (``printed = shell + fill_density * (volume - shell)``). Walls and skins overlapping
    at the edges are counted twice, and a slicer's gaps and overlaps are not modelled:
    within 10 % of PrusaSlicer on the crawler's sheet (docs/fabrication.md).

    Parameters
    ----------
    volume_mm3 : float
        The solid's volume, mm^3.
    side_mm2, top_mm2, bottom_mm2 : float
        Its area seen from the side, and its upward and downward footprints, mm^2
        (:func:`mesh_print_areas`).
    settings : dict, optional
        The print settings (:func:`~origami_cad.fabrication.slicer.slicer_settings`,
        default those of the default parameters): ``perimeters``, ``extrusion_width``
        (mm), ``layer_height`` (mm), ``top_solid_layers``, ``bottom_solid_layers``,
        ``fill_density`` (a fraction in [0, 1]).

    Returns
    -------
    float
        The printed volume, mm^3 (multiply by g/cm^3 / 1000 for grams).

    Examples
    --------
    A 10 x 20 x 2 mm plate, 2 walls of 0.45 mm, 3 + 3 skins of 0.1 mm, 20 % infill:

    >>> s = {"perimeters": 2, "extrusion_width": 0.45, "layer_height": 0.1,
    ...      "top_solid_layers": 3, "bottom_solid_layers": 3, "fill_density": 0.2}
    >>> round(print_volume(400.0, 120.0, 200.0, 200.0, s), 3)
    233.596
    """
    s = slicer_settings() if settings is None else settings
    h = s["layer_height"]
    # a bead's cross-section: a rectangle with round sides (Slic3r's flow), (w - h) h + pi h^2 / 4
    bead = s["extrusion_width"] - h * (1.0 - math.pi / 4.0)
    walls = s["perimeters"] * bead * side_mm2
    skins = s["layer_height"] * (
        s["top_solid_layers"] * top_mm2 + s["bottom_solid_layers"] * bottom_mm2
    )
    # the walls' share within the skin layers is skin already: counted once
    thickness = volume_mm3 / max(top_mm2, bottom_mm2, 1e-12)
    skin_h = h * (s["top_solid_layers"] + s["bottom_solid_layers"])
    shell = min(volume_mm3, walls * (1.0 - min(1.0, skin_h / thickness)) + skins)
    return shell + s["fill_density"] * (volume_mm3 - shell)


def printed_mass(
    solids: Mapping[str, Iterable[Any]], settings: Mapping[str, Any] | None = None
) -> dict[str, float]:
    """The printed mass of each material's solids under the print settings, g.

    Parameters
    ----------
    solids : dict of str to iterable
        Per material (a key of :data:`~origami_cad.fabrication.params.DENSITY_G_CM3`:
        ``"PLA"``, ``"TPU"``), its solids: build123d ``Solid`` objects (meshed as the
        3MF meshes them) or meshes ``(vertices mm, triangles)``, each closed and
        outward-oriented. Each solid is printed as its own object: its walls and skins
        are its own (the 3MF asks for ``interface_shells``, solid layers between
        materials).
    settings : dict, optional
        The print settings (:func:`print_volume`); default
        :func:`~origami_cad.fabrication.slicer.slicer_settings` ``()``.

    Returns
    -------
    dict of str to float
        Grams per material, in the order given; nothing is written.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[x, y, z] for x in (0, 10) for y in (0, 20) for z in (0, 2.0)])
    >>> t = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
    ...               [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    >>> s = {"perimeters": 2, "extrusion_width": 0.45, "layer_height": 0.1,
    ...      "top_solid_layers": 3, "bottom_solid_layers": 3, "fill_density": 0.2}
    >>> {k: round(g, 4) for k, g in printed_mass({"PLA": [(v, t)]}, s).items()}
    {'PLA': 0.2897}
    """
    s = slicer_settings() if settings is None else settings
    out = {}
    for material, items in solids.items():
        mm3 = 0.0
        for item in items:
            mesh = item if isinstance(item, tuple) else solid_mesh(item)
            areas = mesh_print_areas(*mesh)
            mm3 += print_volume(
                areas["volume_mm3"], areas["side_mm2"], areas["top_mm2"], areas["bottom_mm2"], s
            )
        out[material] = mm3 / 1000.0 * DENSITY_G_CM3[material]
    return out


def sheet_print_mass(fab: Any, settings: Mapping[str, Any] | None = None) -> dict[str, float]:
    """A fabricated sheet's printed mass per material, g (:func:`printed_mass`).

    ``fab`` is a :class:`~origami_cad.fabrication.build.Fabrication`; its parts are meshed
    as ``print.3mf`` meshes them (shared with the exports); ``settings`` default to
    ``slicer_settings(fab.params)``, those ``write_fabrication``'s 3MF carries.
    """
    from origami_cad.fabrication.meshing import part_meshes
    from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES

    s = slicer_settings(fab.params) if settings is None else settings
    out: dict[str, float] = {}
    for name in PART_NAMES:
        material = PART_MATERIALS[name]
        grams = printed_mass({material: part_meshes(fab.parts, name)}, s)[material]
        out[material] = out.get(material, 0.0) + grams
    return out
