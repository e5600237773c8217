"""The panels of an MJCF model from the printed solids: visual meshes, mass and inertia.

Each panel's solids come from :func:`~origami_cad.fabrication.fabricate` (its PLA infills
and mid-layer, its TPU shells, ``Parts.owners`` naming the panel), with the holes cut
where the strings run. The crease sheet (TPU) is split along the creases: the part of a
strip over a panel's face goes to that panel. Mass, centre of mass and inertia are
OCC's exact volume integrals of the B-rep solids (``BRepGProp``) at the materials'
densities (``fabrication.params.DENSITY_G_CM3``), plus the robot's point masses. Units:
mm and g here; :mod:`~origami_cad.simulation.mjcf` converts to SI.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely

from origami_cad.fabrication import fabricate
from origami_cad.fabrication.params import DENSITY_G_CM3, FabricationParams
from origami_cad.fabrication.solids import PART_MATERIALS, crease_sheet, planar_prism

__all__ = ["MESH_TOLERANCE", "MassProps", "PanelSolids", "panel_solids", "solid_props"]

#: Tessellation of the visual meshes: chordal (mm) and angular (rad) tolerance, coarser
#: than the STL exports' (0.01 mm, 0.1 rad) and four times faster; the mass properties
#: do not depend on it (they integrate the B-rep).
MESH_TOLERANCE = (0.05, 0.3)


@dataclass(frozen=True)
class MassProps:
    """Mass (g), centre of mass (mm) and inertia about it (g mm^2, 3 x 3)."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray

    def __add__(self, other: MassProps) -> MassProps:
        """The combined body (parallel-axis theorem)."""
        m = self.mass + other.mass
        com = (self.mass * self.com + other.mass * other.com) / m
        total = np.zeros((3, 3))
        for p in (self, other):
            d = p.com - com
            total += p.inertia + p.mass * (d @ d * np.eye(3) - np.outer(d, d))
        return MassProps(m, com, total)

    @staticmethod
    def point(grams: float, at) -> MassProps:
        """A point mass (g) at ``at`` (mm)."""
        return MassProps(float(grams), np.asarray(at, dtype=float), np.zeros((3, 3)))


def solid_props(solid, density: float) -> MassProps:
    """Exact mass properties of a build123d solid (mm) at ``density`` g/cm^3 (OCC)."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(solid.wrapped, props)
    rho = density * 1e-3  # g/mm^3
    c = props.CentreOfMass()
    matrix = props.MatrixOfInertia()  # about the centre of mass, unit density
    inertia = np.array([[matrix.Value(i, j) for j in (1, 2, 3)] for i in (1, 2, 3)])
    return MassProps(props.Mass() * rho, np.array([c.X(), c.Y(), c.Z()]), inertia * rho)


@dataclass
class PanelSolids:
    """One panel's printed solids: meshes by material and the panel's mass properties.

    ``meshes`` are ``(material, vertices (mm), triangles)``; ``props`` sums them and the
    panel's share of the crease sheet (mesh included as ``"TPU"``). z = 0 is the sheet's
    mid-plane (the fabrication's z = h / 2).
    """

    meshes: list[tuple[str, np.ndarray, np.ndarray]] = field(default_factory=list)
    props: MassProps | None = None

    def add(self, material: str, solid, z_shift: float) -> None:
        """Add a solid (mm) of ``material`` ("PLA" or "TPU"), lowered by ``z_shift`` mm."""
        verts, tris = _mesh(solid)
        self.meshes.append((material, verts - [0.0, 0.0, z_shift], tris))
        p = solid_props(solid, DENSITY_G_CM3[material])
        p = MassProps(p.mass, p.com - [0.0, 0.0, z_shift], p.inertia)
        self.props = p if self.props is None else self.props + p


def panel_solids(source, params: FabricationParams) -> tuple[dict[int, PanelSolids], float]:
    """Each panel's printed solids (face index -> :class:`PanelSolids`) and the sheet's
    mass as solids, g (``fabrication.json``'s ``total_mass_g``, for checks).

    ``source`` is the pattern or design :func:`fabricate` takes.
    """
    fab = fabricate(source, params)
    cp, parts, half = fab.pattern, fab.parts, params.height / 2.0
    out = {f: PanelSolids() for f in range(len(cp.faces))}
    for name in ("infills", "midlayers", "shells"):
        for solid, face in zip(parts.solids[name], parts.owners[name], strict=True):
            out[face].add(PART_MATERIALS[name], solid, half)
    sheet = crease_sheet(list(fab.outlines), shapely.union_all(cp.face_polygons()))
    z0, z1 = params.half_height, params.half_height + params.thickness
    for face, poly in enumerate(cp.face_polygons()):
        share = shapely.intersection(sheet, poly)
        for piece in shapely.get_parts(share):
            if isinstance(piece, shapely.Polygon) and piece.area > 1e-6:
                out[face].add(PART_MATERIALS["creases"], planar_prism(piece, z0, z1), half)
    return out, float(sum(fab.solid_mass().values()))


def _mesh(solid) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (mm, welded at 1e-6 mm) and triangles of a solid at :data:`MESH_TOLERANCE`."""
    points, triangles = solid.tessellate(*MESH_TOLERANCE)
    v = np.array([(p.X, p.Y, p.Z) for p in points], dtype=float).reshape(-1, 3)
    _, first, inverse = np.unique(
        np.round(v / 1e-6).astype(np.int64), axis=0, return_index=True, return_inverse=True
    )
    t = inverse.reshape(-1)[np.asarray(triangles, dtype=np.int64).reshape(-1, 3)]
    keep = (t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 2] != t[:, 0])
    return v[first], t[keep]
