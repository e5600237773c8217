"""Exact B-rep solids of the four printed parts, built with build123d.

Each panel half is a polyhedron whose faces are planes (outer face, chamfers of
eq. 6, vertical free sides), built face by face from the footprints of
:mod:`origami_cad.fabrication.panels`, with no lofts and no sheet-wide boolean. A
panel's solids with their holes are assembled from their faces too
(:mod:`origami_cad.fabrication.polyhedra`), which keeps their faces as plain data for
the exports' meshes; only a panel whose holes come near its footprints is built with
booleans (shell = half minus infill, and the holes).
The crease sheet is one planar face with a hole per mid-layer, extruded once.

build123d objects never leave ``origami_cad.fabrication``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely
from build123d import Compound, Face, Plane, Shell, Solid, Vector, Wire
from OCP.BRep import BRep_Builder
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakePolygon
from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
from OCP.Geom import Geom_Plane
from OCP.gp import gp_Dir, gp_Pln, gp_Pnt, gp_Trsf, gp_Vec
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS, TopoDS_Face

from origami_cad.errors import PatternError
from origami_cad.fabrication.panels import PanelOutline, shell_of
from origami_cad.fabrication.params import FabricationParams
from origami_cad.fabrication.polyhedra import Facets, fast_panel_build
from origami_cad.pattern.model import Hole

__all__ = [
    "PART_MATERIALS",
    "PART_NAMES",
    "Parts",
    "boolean_panel_solids",
    "build_parts",
    "crease_sheet",
    "half_solid",
    "moved_copy",
    "panel_build",
    "panel_solids",
    "planar_prism",
    "prism_rings",
]

#: The four parts, in the order of the exports.
PART_NAMES = ("infills", "midlayers", "shells", "creases")
#: Material of each part.
PART_MATERIALS = {"infills": "PLA", "midlayers": "PLA", "shells": "TPU", "creases": "TPU"}


@dataclass
class Parts:
    """The solids of each part (lists of build123d ``Solid``), mm.

    ``panel_copies`` and ``copy_of`` describe the solids as :func:`build_parts` built
    them (``built``); the exports' meshes (``mesh_cache``) follow ``copy_of`` only for a
    solid that is still the one built there, and a part's meshes are made afresh when
    its list of solids changes.
    """

    solids: dict[str, list[Solid]] = field(default_factory=lambda: {n: [] for n in PART_NAMES})
    halves: list[tuple[Solid, Solid]] = field(default_factory=list)  # (lower, upper) per panel
    #: face index of the panel of each solid of ``infills``, ``midlayers``, ``shells``
    owners: dict[str, list[int]] = field(default_factory=lambda: {n: [] for n in PART_NAMES})
    #: per panel (in ``halves``' order): ``None`` if built, or ``(earlier panel, motion)``
    #: when its solids are copies of that panel's moved by a 3 x 3 plane motion (mm)
    panel_copies: list[tuple[int, np.ndarray] | None] = field(default_factory=list)
    #: per solid of each part: ``None`` if built, or ``(earlier solid, motion)`` of the
    #: same part that it is a moved copy of (``panel_copies``, solid by solid)
    copy_of: dict[str, list[tuple[int, np.ndarray] | None]] = field(
        default_factory=lambda: {n: [] for n in PART_NAMES}
    )
    #: the solids as added, position by position (what ``copy_of`` describes)
    built: dict[str, list[Solid]] = field(default_factory=lambda: {n: [] for n in PART_NAMES})
    #: per solid of each part, as built: ``(polygon, z0, z1)`` when it is that polygon's
    #: :func:`planar_prism` (meshed from the polygon: ``meshing.prism_mesh``), else ``None``
    prisms: dict[str, list[tuple[shapely.Polygon, float, float] | None]] = field(
        default_factory=dict
    )
    #: per solid of each part, as built: its faces as data when it was assembled from
    #: them (:mod:`~origami_cad.fabrication.polyhedra`; meshed from them:
    #: ``polymesh.facets_mesh``), else ``None``
    facets: dict[str, list[Facets | None]] = field(default_factory=dict)
    #: the meshes of each part's solids, once tessellated (``meshing.part_meshes``)
    mesh_cache: dict[str, Any] = field(default_factory=dict, repr=False)

    def __repr__(self) -> str:
        """One line: the number of solids of each part."""
        counts = ", ".join(f"{name} {len(solids)}" for name, solids in self.solids.items())
        return f"<Parts: solids {counts}>"

    def add(
        self,
        name: str,
        solids: list[Solid],
        face: int,
        copy_of: list | None = None,
        facets: list[Facets] | None = None,
    ) -> None:
        """Append ``solids`` to part ``name``, as solids of panel (face index) ``face``.

        ``copy_of`` (one per solid): ``(earlier solid of the part, motion)`` for a moved
        copy; ``facets`` (one per solid): the faces each was assembled from.
        """
        self.facets.setdefault(name, [None] * len(self.solids[name]))
        self.facets[name] += facets if facets is not None else [None] * len(solids)
        self.solids[name] += solids
        self.owners[name] += [face] * len(solids)
        self.copy_of.setdefault(name, [])
        self.copy_of[name] += copy_of if copy_of is not None else [None] * len(solids)
        self.built.setdefault(name, [])
        self.built[name] += solids

    def compound(self, name: str) -> Compound:
        return Compound(self.solids[name])

    def source(self, name: str, k: int) -> tuple[int, np.ndarray] | None:
        """``(earlier solid, motion)`` when solid ``k`` of part ``name`` is, as built, a moved
        copy of that earlier solid (both still the solids built there), else ``None``."""
        solids, copies = self.solids[name], self.copy_of.get(name, [])
        built = self.built.get(name, [])
        src = copies[k] if k < len(copies) else None
        if src is None or k >= len(built) or built[k] is not solids[k]:
            return None
        return src if built[src[0]] is solids[src[0]] else None

    def prism(self, name: str, k: int) -> tuple[shapely.Polygon, float, float] | None:
        """``(polygon, z0, z1)`` when solid ``k`` of part ``name`` is, as built, that
        polygon's :func:`planar_prism`, else ``None``."""
        return self._as_built(self.prisms, name, k)

    def faces_of(self, name: str, k: int) -> Facets | None:
        """The faces solid ``k`` of part ``name`` was assembled from (plain data), when it
        is still the solid built there, else ``None``."""
        return self._as_built(self.facets, name, k)

    def _as_built(self, table: dict[str, list], name: str, k: int) -> Any:
        """``table[name][k]`` when solid ``k`` is still the one built there, else ``None``."""
        rows, built = table.get(name, []), self.built.get(name, [])
        if k >= len(rows) or k >= len(built) or built[k] is not self.solids[name][k]:
            return None
        return rows[k]

    def volume(self, name: str) -> float:
        """The part's volume, mm^3: a moved copy's is its prototype's (computed once), a
        solid assembled from its faces has theirs (``Facets.volume``), a prism its
        polygon's area times its height; others OCC's."""
        volumes: list[float] = []
        for k, solid in enumerate(self.solids[name]):
            src, facets, prism = self.source(name, k), self.faces_of(name, k), self.prism(name, k)
            if src is not None:
                volumes.append(volumes[src[0]])
            elif facets is not None:
                volumes.append(facets.volume())
            elif prism is not None:
                volumes.append(prism[0].area * (prism[2] - prism[1]))
            else:
                volumes.append(solid.volume)
        return float(sum(volumes))


def _distinct(points: list) -> list:
    """``points`` without consecutive repeats (a vanished edge leaves two equal corners)."""
    out = []
    for p in points:
        if not out or max(abs(a - b) for a, b in zip(p, out[-1], strict=True)) > 1e-9:
            out.append(p)
    while len(out) > 1 and max(abs(a - b) for a, b in zip(out[0], out[-1], strict=True)) <= 1e-9:
        out.pop()
    return out


def _face(points: list[tuple[float, float, float]]) -> Face | None:
    """The planar face through ``points``; ``None`` when they collapse to a segment."""
    points = _distinct(points)
    if len(points) < 3:
        return None
    return Face(Wire.make_polygon([Vector(*p) for p in points], close=True))


def half_solid(low: np.ndarray, z_low: float, high: np.ndarray, z_high: float) -> Solid:
    """A polyhedron between two rings with corresponding vertices (CCW, mm).

    ``low`` lies at ``z_low``, ``high`` at ``z_high > z_low``; side faces are the
    planar quadrilaterals between corresponding edges.
    """
    k = len(low)
    lo = [(float(x), float(y), z_low) for x, y in low]
    hi = [(float(x), float(y), z_high) for x, y in high]
    faces = [_face(lo[::-1]), _face(hi)]
    for i in range(k):
        j = (i + 1) % k
        faces.append(_face([lo[i], lo[j], hi[j], hi[i]]))
    solid = Solid(Shell([f for f in faces if f is not None]))
    if not solid.is_valid or solid.volume <= 0:
        raise PatternError("internal error: a panel half is not a valid solid")
    return solid


def _cylinders(holes: Sequence[Hole], z0: float, z1: float) -> list[Solid]:
    return [
        Solid.make_cylinder(h.diameter / 2.0, (z1 - z0) + 2.0, Plane((h.x, h.y, z0 - 1.0)))
        for h in holes
    ]


def _cut(solid: Solid, tools: list[Solid]) -> list[Solid]:
    """``solid`` less every tool, in one boolean: the solids left."""
    if not tools:
        return [solid]
    result = solid.cut(*tools)
    return list(result.solids()) if hasattr(result, "solids") else [result]


def prism_rings(poly: shapely.Polygon) -> list[list[tuple[float, float]]]:
    """The corners of a polygon's rings as :func:`planar_prism` builds them (exterior first,
    then the holes; no closing point, no repeated corner), mm."""
    return [
        _distinct([(float(x), float(y)) for x, y in shapely.get_coordinates(ring)[:-1]])
        for ring in (poly.exterior, *poly.interiors)
    ]


def planar_prism(poly: shapely.Polygon, z0: float, z1: float) -> Solid:
    """The vertical prism of a polygon (holes kept) between heights ``z0 < z1``, mm.

    The bottom face is made with OCP directly (a plane, its outer ring anticlockwise and
    its holes clockwise seen from above) and swept up (``BRepPrimAPI_MakePrism``): the
    solid build123d's face of the rings, extruded, gives, without its shape fixing.
    """
    brep, face = BRep_Builder(), TopoDS_Face()
    brep.MakeFace(face, Geom_Plane(gp_Pln(gp_Pnt(0.0, 0.0, z0), gp_Dir(0.0, 0.0, 1.0))), 1e-7)
    for k, ring in enumerate(prism_rings(poly)):
        ccw = shapely.LinearRing(ring).is_ccw
        if ccw != (k == 0):  # the exterior anticlockwise, the holes clockwise
            ring = ring[::-1]
        polygon = BRepBuilderAPI_MakePolygon()
        for x, y in ring:
            polygon.Add(gp_Pnt(x, y, z0))
        polygon.Close()
        brep.Add(face, polygon.Wire())
    prism = BRepPrimAPI_MakePrism(face, gp_Vec(0.0, 0.0, z1 - z0)).Shape()
    return Solid(TopoDS.Solid(prism))


def crease_sheet(
    outlines: Sequence[PanelOutline], sheet_outline: shapely.Polygon | shapely.MultiPolygon
):
    """The crease layer's footprint: the sheet less every panel's mid-layer patch, mm (it runs
    through a panel without one)."""
    mids = shapely.union_all([shapely.Polygon(o.midlayer) for o in outlines if o.has_midlayer])
    return shapely.difference(sheet_outline, mids)


def panel_solids(
    o: PanelOutline, holes: Sequence[Hole], params: FabricationParams
) -> dict[str, list[Solid]]:
    """One panel's solids, built: ``halves`` (lower, upper), ``infills``, ``shells``, ``midlayers``.

    Assembled from their faces without booleans
    (:func:`~origami_cad.fabrication.polyhedra.fast_panel_solids`) when the holes are
    clear of the footprints, else :func:`boolean_panel_solids`: the same solids.

    Parameters
    ----------
    o : PanelOutline
        The panel's footprints, mm.
    holes : sequence of Hole
        The panel's string holes, mm.
    params : FabricationParams
        Heights and thicknesses, mm.
    """
    return panel_build(o, holes, params)[0]


def panel_build(
    o: PanelOutline, holes: Sequence[Hole], params: FabricationParams
) -> tuple[dict[str, list[Solid]], dict[str, list[Facets]] | None]:
    """:func:`panel_solids` and, when they were assembled from their faces, those faces
    (:class:`~origami_cad.fabrication.polyhedra.Facets`, per solid), else ``None``."""
    fast = fast_panel_build(o, holes, params)
    return fast if fast is not None else (boolean_panel_solids(o, holes, params), None)


def boolean_panel_solids(
    o: PanelOutline, holes: Sequence[Hole], params: FabricationParams
) -> dict[str, list[Solid]]:
    """:func:`panel_solids` by booleans: each half less its infill and the holes' cylinders.

    Parameters
    ----------
    o : PanelOutline
        The panel's footprints, mm.
    holes : sequence of Hole
        The panel's string holes, mm.
    params : FabricationParams
        Heights and thicknesses, mm.
    """
    h, t, half, s = params.height, params.thickness, params.half_height, shell_of(o, params)
    z_layer_lo, z_layer_hi = half, half + t
    cyl = _cylinders(holes, 0.0, h)
    lower = half_solid(o.outer, 0.0, o.inner, z_layer_lo)
    upper = half_solid(o.inner, z_layer_hi, o.outer, h)
    if not o.has_infill:  # TPU alone: each half is its shell
        shells = _cut(lower, cyl) + _cut(upper, cyl)
        return {"halves": [lower, upper], "infills": [], "shells": shells, "midlayers": []}
    lower_in = half_solid(o.infill_outer, s, o.infill_inner, z_layer_lo)
    upper_in = half_solid(o.infill_inner, z_layer_hi, o.infill_outer, h - s)
    out: dict[str, list[Solid]] = {"halves": [lower, upper], "infills": [], "shells": []}
    for whole, core in ((lower, lower_in), (upper, upper_in)):
        out["infills"] += _cut(core, cyl)
        out["shells"] += _cut(whole, [core, *cyl])
    out["midlayers"] = []
    if o.has_midlayer:
        mid = planar_prism(shapely.Polygon(o.midlayer), z_layer_lo, z_layer_hi)
        out["midlayers"] = _cut(mid, cyl)
    return out


def moved_copy(solid: Solid, motion: np.ndarray) -> Solid:
    """``solid`` moved by a plane motion: the same shape (geometry shared) at a new location.

    ``motion`` is 3 x 3 homogeneous: a rotation about z and a translation in x, y (mm).
    The copy is ``solid``'s shape under another ``TopLoc_Location`` (no geometry copied:
    a copy's faces are its prototype's, meshed once).
    """
    return Solid(solid.wrapped.Moved(motion_location(motion)))


def motion_location(motion: np.ndarray) -> TopLoc_Location:
    """The ``TopLoc_Location`` of a 3 x 3 plane motion (rotation about z, translation in x,
    y; mm), as :func:`moved_copy` and the STEP instances place a copy."""
    m = np.asarray(motion, dtype=float)
    trsf = gp_Trsf()
    trsf.SetValues(m[0, 0], m[0, 1], 0.0, m[0, 2], m[1, 0], m[1, 1], 0.0, m[1, 2], 0, 0, 1, 0)
    return TopLoc_Location(trsf)


def build_parts(
    outlines: Sequence[PanelOutline],
    holes: Sequence[Hole],
    hole_panels: np.ndarray,
    params: FabricationParams,
    sheet_outline: shapely.Polygon | shapely.MultiPolygon,
    progress: Callable[[int, int], None] | None = None,
) -> Parts:
    """Build the four parts: infills, mid-layers, shells (per panel) and the crease sheet.

    Each distinct panel shape is built once: a panel that is an earlier one moved
    rigidly (:func:`~origami_cad.fabrication.congruent.congruent_panels`) gets copies of
    its solids, moved (:func:`moved_copy`); ``Parts.copies`` records which.

    Parameters
    ----------
    outlines : sequence of PanelOutline
        Footprints of the panels.
    holes : sequence of Hole
        String holes, mm; ``hole_panels[k]`` is the panel (face index) of ``holes[k]``.
    params : FabricationParams
        Heights and thicknesses, mm.
    sheet_outline : shapely geometry
        The whole sheet (union of the panels), for the crease sheet.
    progress : callable, optional
        Called as ``progress(panels built, panels)`` after each panel.
    """
    from origami_cad.fabrication.congruent import congruent_panels

    parts = Parts()
    by_panel: dict[int, list[Hole]] = {}
    for hole, fi in zip(holes, np.asarray(hole_panels).tolist(), strict=True):
        by_panel.setdefault(fi, []).append(hole)
    holes_of = [by_panel.get(o.index, []) for o in outlines]
    built: list[dict[str, list[Solid]]] = []
    starts: list[dict[str, int]] = []
    for o, own, same in zip(outlines, holes_of, congruent_panels(outlines, holes_of), strict=True):
        faces = None
        if same is None:
            solids, faces = panel_build(o, own, params)
        else:
            solids = {n: [moved_copy(x, same[1]) for x in v] for n, v in built[same[0]].items()}
        built.append(solids)
        starts.append({n: len(parts.solids[n]) for n in PART_NAMES})
        parts.halves.append(tuple(solids["halves"]))
        parts.panel_copies.append(same)
        if progress is not None:
            progress(len(built), len(outlines))
        for name in ("infills", "shells", "midlayers"):
            copies = None
            if same is not None:
                first = starts[same[0]][name]
                copies = [(first + i, same[1]) for i in range(len(solids[name]))]
            parts.add(name, solids[name], o.index, copies, None if faces is None else faces[name])
    z_layer_lo = params.half_height
    sheet = crease_sheet(outlines, sheet_outline)
    z_layer_hi = z_layer_lo + params.thickness
    for poly in shapely.get_parts(sheet):  # no owner: the crease sheet is no panel's
        prism = planar_prism(poly, z_layer_lo, z_layer_hi)
        parts.solids["creases"].append(prism)
        parts.built["creases"].append(prism)
        parts.prisms.setdefault("creases", []).append((poly, z_layer_lo, z_layer_hi))
    return parts
