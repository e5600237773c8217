"""The panels' solids meshed straight from the faces they were assembled from.

:func:`~origami_cad.fabrication.polymesh.facets_mesh` must give, on every
distinct panel of several sheets (the examples, vanished edges, no hole, two holes in a
panel), a closed mesh, outward, whose vertices are OCC's mesh's (every B-rep vertex
among them, each hole's circle OCC's polygon) and whose volume is OCC's mesh's and
the B-rep's less the chordal error of the holes' polygons; the faces' own volume is the
B-rep's. A panel built by booleans
(holes near its footprints) has no faces kept and is meshed by OCC.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from build123d import Solid
from conftest import closed_mesh, mesh_volume
from helpers_fabrication import SHEETS, distinct_panels
from OCP.BRep import BRep_Tool
from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.TopAbs import TopAbs_VERTEX
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS

from origami_cad.fabrication import FabricationParams, plan_panels
from origami_cad.fabrication.meshing import ANGULAR_TOLERANCE, TOLERANCE, part_meshes, solid_mesh
from origami_cad.fabrication.polyhedra import Cap, Facets, frustum
from origami_cad.fabrication.polymesh import circle_segments, facets_mesh
from origami_cad.fabrication.solids import PART_NAMES, build_parts, panel_build
from origami_cad.pattern.design import load_design, miura_design
from origami_cad.pattern.model import Hole

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
PLANS = {
    "examples/miura_6x4.toml": (load_design(EXAMPLES / "miura_6x4.toml"), FabricationParams()),
    "examples/arm_design.toml": (load_design(EXAMPLES / "arm_design.toml"), FabricationParams()),
    **SHEETS,
}
SEGMENTS = circle_segments(ANGULAR_TOLERANCE)


def _nearest(points: np.ndarray, among: np.ndarray) -> np.ndarray:
    """Each point's distance (mm) to the nearest of ``among``."""
    return np.sqrt(((points[:, None, :] - among[None, :, :]) ** 2).sum(axis=2)).min(axis=1)


def _brep_vertices(solid: Solid) -> np.ndarray:
    out, explorer = [], TopExp_Explorer(solid.wrapped, TopAbs_VERTEX)
    while explorer.More():
        out.append(BRep_Tool.Pnt_s(TopoDS.Vertex(explorer.Current())).Coord())
        explorer.Next()
    return np.array(out)


def _chordal_loss(facets: Facets) -> float:
    """The volume (mm^3) the holes' polygons leave that their cylinders take away."""
    polygon = 0.5 * SEGMENTS * math.sin(2.0 * math.pi / SEGMENTS)
    return sum((math.pi - polygon) * r * r * (z1 - z0) for _, _, r, z0, z1 in facets.walls)


def _check(solid: Solid, facets: Facets, where: str) -> None:
    mesh = facets_mesh(facets, SEGMENTS)
    assert mesh is not None, where
    v, t = mesh
    assert len(np.unique(v, axis=0)) == len(v) and closed_mesh(t), where
    occ_v, occ_t = solid_mesh(Solid(solid.wrapped))
    assert len(v) == len(occ_v) and len(t) == len(occ_t), where  # no point inside a face
    assert _nearest(v, occ_v).max() < 1e-9 and _nearest(occ_v, v).max() < 1e-9, where
    assert _nearest(_brep_vertices(solid), v).max() < 1e-12, where
    assert facets.volume() == pytest.approx(solid.volume, rel=1e-12), where  # exact
    volume, loss = mesh_volume(v, t), _chordal_loss(facets)
    assert volume == pytest.approx(mesh_volume(occ_v, occ_t), rel=1e-9, abs=1e-9), where
    slack = 1e-9 * solid.volume  # rounding
    assert -slack <= volume - solid.volume <= loss * (1 + 1e-6) + slack, where


@pytest.mark.parametrize("case", sorted(PLANS))
def test_every_distinct_panel_is_meshed_from_its_faces_as_occ_meshes_it(case):
    design, params = PLANS[case]
    plan, panels = distinct_panels(design, params)
    for o, holes in panels:
        solids, faces = panel_build(o, holes, plan.params)
        assert faces is not None and faces.keys() == solids.keys(), (case, o.label)
        for name, built in solids.items():
            for k, (solid, facets) in enumerate(zip(built, faces[name], strict=True)):
                _check(solid, facets, f"{case}: {o.label} {name} {k}")


@pytest.mark.parametrize("angular", [0.05, ANGULAR_TOLERANCE, 0.2])
@pytest.mark.parametrize("diameter", [0.5, 2.0, 7.0, 20.0])
def test_a_circle_has_the_corners_occ_gives_it(angular, diameter):
    square = np.array([[0.0, 0.0], [40.0, 0.0], [40.0, 40.0], [0.0, 40.0]])
    solid, facets = frustum(square, 0.0, square, 3.0, [Hole(20.0, 20.0, diameter)])
    BRepMesh_IncrementalMesh(solid.wrapped, TOLERANCE, True, angular, True)
    v, _ = solid_mesh(solid)
    circle = v[(v[:, 2] == 0.0) & (np.hypot(v[:, 0] - 20.0, v[:, 1] - 20.0) < diameter)]
    assert len(circle) == circle_segments(angular)
    mine, _ = facets_mesh(facets, circle_segments(angular))
    assert _nearest(mine, v).max() < 1e-9 and len(mine) == len(v)


def test_a_face_not_convex_is_left_to_occ_and_a_cap_to_constrained_delaunay():
    ell = [(0.0, 0.0, 0.0), (0.0, 0.0, 2.0), (4.0, 0.0, 2.0), (4.0, 0.0, 1.0), (1.0, 0.0, 1.0)]
    ell += [(1.0, 0.0, 0.0)]  # an L in the plane y = 0, seen from -y anticlockwise
    assert facets_mesh(Facets(polygons=[ell]), SEGMENTS) is None
    outer = [(0.0, 0.0, 1.0), (10.0, 0.0, 1.0), (10.0, 10.0, 1.0), (5.0, 2.0, 1.0)]
    outer += [(0.0, 10.0, 1.0)]  # not convex: the zipper cannot, Delaunay can
    cap = Cap(1.0, True, outer, [], [(2.0, 2.0, 0.5)])
    v, t = facets_mesh(Facets(caps=[cap]), SEGMENTS)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    up = np.cross(b - a, c - a)[:, 2] / 2.0
    hole = shapely.Polygon([p[:2] for p in v[len(outer) :]])
    assert np.all(up > 0) and np.all(v[:, 2] == 1.0) and len(v) == len(outer) + SEGMENTS
    assert up.sum() == pytest.approx(shapely.Polygon(outer).area - hole.area, rel=1e-12)


def test_a_sheet_with_a_hole_near_a_footprint_meshes_that_panel_with_occ():
    plan = plan_panels(miura_design(2, 3, 30.0, 30.0, 65.0), FabricationParams(holes="none"))
    near, clear = plan.outlines[0], plan.outlines[3]
    x, y = near.infill_outer.min(axis=0)
    holes = [Hole(float(x) + 1.0, float(y) + 1.0, 3.0), Hole(*clear.inner.mean(axis=0), 2.0)]
    sheet = shapely.union_all([shapely.Polygon(o.polygon) for o in plan.outlines])
    parts = build_parts(plan.outlines, holes, np.array([0, 3]), plan.params, sheet)
    for name in PART_NAMES:
        for k, (v, t) in enumerate(part_meshes(parts, name)):
            assert closed_mesh(t), (name, k)
            volume = parts.solids[name][k].volume
            assert mesh_volume(v, t) == pytest.approx(volume, rel=2e-3), (name, k)
    for name in ("infills", "shells", "midlayers"):
        for k, owner in enumerate(parts.owners[name]):
            if owner == near.index:  # built by booleans: meshed by OCC
                assert parts.faces_of(name, k) is None, (name, k)
            elif parts.source(name, k) is None:  # assembled from its faces, not a copy
                assert parts.faces_of(name, k) is not None, (name, k)
    assert near.index in parts.owners["shells"] and clear.index in parts.owners["shells"]
