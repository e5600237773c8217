"""The printed sheet as a build123d assembly: panels with their solids, joints, folded states.

:func:`sheet_assembly` (``Fabrication.assembly(ratio)``) gives a ``Compound`` tree::

    sheet                       the pattern's title, or "sheet"
    +-- c0r0s0                  one child per panel, labelled as FOLD's faces_origami_cad:labels
    |   +-- c0r0s0_infill_0     PLA, white
    |   +-- c0r0s0_shell_0      TPU, red
    |   +-- c0r0s0_midlayer_0   PLA
    |   ...
    +-- creases
        +-- crease_strip_0      TPU (folded: c0r0s0_strip_0, the piece on each face)

Solid labels hold no space, dot or bracket, which build123d's ``import_step`` would turn
into underscores: they read back as written.

Every solid carries its material's colour (:data:`MATERIAL_COLORS`).
Each panel carries build123d joints:

* ``mount`` (``RigidJoint``): the centre of its outer face inset by 1 mm, z = h, axes of
  the pattern: where :class:`origami_cad.parts.TSAModule` mounts (its ``mount`` joint);
* ``crease E`` on both panels of crease edge ``E``: a ``RevoluteJoint`` on the panel on the
  crease's left (A), a ``RigidJoint`` on the panel on its right (B). The axis lies on the
  crease at the crease layer's mid-plane, turned so that a positive angle is a valley fold;
  ``joint.fold_angle`` is the crease's fold angle (degrees) in this state, and
  ``A.joints["crease E"].connect_to(B.joints["crease E"], angle=fold_angle)`` leaves B where
  it is;
* ``blocker E`` (``RigidJoint``) on panel A of every crease: where
  :class:`origami_cad.parts.Blocker` (its ``crease`` joint) sits, on the top face for a
  valley, on the bottom face for a mountain.

At ``ratio`` > 0 each panel is its flat solids moved rigidly by the rigid folding of its
face: the pattern's surface is the crease layer's mid-plane (z = h/2), and the folded state
is placed as ``origami-cad fold`` places its FOLD frames (:mod:`origami_cad.kinematics.placement`),
lifted by h/2 so that p = 0 is the printed sheet as built. The crease strips are then
approximated: the crease sheet is cut along the crease lines into one piece per face, each
moved with its face (docs/fabrication.md, "The assembly").
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from build123d import (
    Axis,
    Color,
    Compound,
    Location,
    Plane,
    RevoluteJoint,
    RigidJoint,
    Solid,
)

from origami_cad.errors import FabricationError
from origami_cad.fabrication.panels import sheet_outline
from origami_cad.fabrication.params import FabricationParams
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES, crease_sheet, planar_prism
from origami_cad.pattern.model import CreasePattern

if TYPE_CHECKING:
    from origami_cad.fabrication.build import Fabrication
    from origami_cad.pattern.design import Design

__all__ = [
    "KIND_PARTS",
    "MATERIAL_COLORS",
    "SheetMotion",
    "face_motions",
    "leaf_part",
    "material_color",
    "mount_point",
    "moved_tree",
    "sheet_assembly",
    "sheet_motion",
    "solids_by_part",
]

#: Display colour of each material (sRGB hex): PLA white, TPU red.
MATERIAL_COLORS = {"PLA": "#F2F2F2", "TPU": "#D62728"}
#: The word naming a solid's part in its label (``c0r1s2_shell_1``), and that part.
KIND_PARTS = {"infill": "infills", "midlayer": "midlayers", "shell": "shells", "strip": "creases"}
_PART_KINDS = {v: k for k, v in KIND_PARTS.items()}


def material_color(material: str) -> Color:
    """The display colour of a material (``"PLA"`` or ``"TPU"``) as a build123d colour."""
    hexa = MATERIAL_COLORS[material].lstrip("#")
    return Color(*(int(hexa[i : i + 2], 16) / 255 for i in (0, 2, 4)))


def face_motions(cp: CreasePattern, coords: np.ndarray) -> np.ndarray:
    """The rigid motion of every face from the flat pattern to a folded state.

    Parameters
    ----------
    cp : CreasePattern
        The flat pattern (z = 0), mm.
    coords : ndarray (n, 3)
        Folded vertex coordinates, mm, in ``cp``'s vertex order.

    Returns
    -------
    ndarray (faces, 4, 4)
        Homogeneous transforms (rotation, translation in mm) taking each face's flat
        vertices onto its folded ones, fitted by least squares (Kabsch; exact for a
        rigid folding).
    """
    coords = np.asarray(coords, dtype=float)
    if coords.shape != (cp.n_vertices, 3):
        raise FabricationError(
            f"a state of this pattern has {cp.n_vertices} vertices, got {coords.shape}"
        )
    flat = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    out = np.tile(np.eye(4), (len(cp.faces), 1, 1))
    for k, face in enumerate(cp.faces):
        a, b = flat[face], coords[face]
        ca, cb = a.mean(axis=0), b.mean(axis=0)
        u, _, vt = np.linalg.svd((a - ca).T @ (b - cb))
        d = np.sign(np.linalg.det(vt.T @ u.T)) or 1.0
        rot = vt.T @ np.diag([1.0, 1.0, d]) @ u.T
        out[k, :3, :3] = rot
        out[k, :3, 3] = cb - rot @ ca
    return out


@dataclass(frozen=True)
class SheetMotion:
    """Where each panel of a printed sheet goes at a fold ratio.

    Attributes
    ----------
    ratio : float
        The fold ratio p.
    coords : ndarray (n, 3)
        The folded vertex coordinates as placed on the table (the FOLD frame), mm.
    fold_angles : ndarray (m,)
        Signed fold angle of every edge, degrees (valley positive).
    locations : tuple of Location
        Per face, the motion of its printed solids (mm): the face's motion conjugated by
        the lift to the crease layer's mid-plane, z = h/2.
    """

    ratio: float
    coords: np.ndarray
    fold_angles: np.ndarray
    locations: tuple[Location, ...]


def _location(matrix: np.ndarray, lift: float) -> Location:
    """``q -> R (q - c) + t + c`` with ``c = (0, 0, lift)``, as a build123d Location."""
    rot, t = matrix[:3, :3], matrix[:3, 3]
    c = np.array([0.0, 0.0, lift])
    origin = t + c - rot @ c
    plane = Plane(origin=tuple(origin), x_dir=tuple(rot[:, 0]), z_dir=tuple(rot[:, 2]))
    return Location(plane)


def sheet_motion(
    pattern: CreasePattern,
    params: FabricationParams,
    ratio: float,
    design: Design | None = None,
) -> SheetMotion:
    """Fold ``design`` (default: ``pattern`` by degree-4 propagation) rigidly to ``ratio``.

    The state is placed on the table as ``origami-cad fold`` places it; p = 0 gives
    the identity for every panel.
    """
    from origami_cad.kinematics.folding import fold_design
    from origami_cad.kinematics.placement import place_on_table
    from origami_cad.pattern.design import Design

    if not 0.0 <= ratio <= 1.0:
        raise FabricationError(f"the fold ratio must lie in [0, 1], got {ratio}")
    design = design if design is not None else Design(pattern, None, "file")
    if design.pattern.n_vertices != pattern.n_vertices or len(design.pattern.faces) != len(
        pattern.faces
    ):
        raise FabricationError("the design does not match the fabricated pattern")
    if ratio == 0.0:
        coords = np.column_stack([pattern.vertices, np.zeros(pattern.n_vertices)])
        angles = np.zeros(pattern.n_edges)
        locs = tuple(Location() for _ in pattern.faces)
        return SheetMotion(0.0, coords, angles, locs)
    state = fold_design(design, ratio)
    coords = place_on_table(pattern, state.coords)
    half = params.height / 2.0
    locs = tuple(_location(m, half) for m in face_motions(pattern, coords))
    return SheetMotion(float(ratio), coords, np.asarray(state.fold_angles, float), locs)


def _leaf(solid: Solid, label: str, material: str, loc: Location | None) -> Solid:
    out = Solid(solid.wrapped) if loc is None else Solid(solid.wrapped).moved(loc)
    out.label = label
    out.color = material_color(material)
    return out


def _panel_children(fab: Fabrication, motion: SheetMotion) -> list[Compound]:
    """One compound per panel, holding its infill, shell and mid-layer solids."""
    cp = fab.pattern
    per_face: list[list[Solid]] = [[] for _ in cp.faces]
    counts: list[dict[str, int]] = [{} for _ in cp.faces]
    moving = motion.ratio > 0
    for part in ("infills", "shells", "midlayers"):
        kind = _PART_KINDS[part]
        for solid, face in zip(fab.parts.solids[part], fab.parts.owners[part], strict=True):
            k = counts[face].get(kind, 0)
            counts[face][kind] = k + 1
            label = f"{cp.face_labels[face]}_{kind}_{k}"
            loc = motion.locations[face] if moving else None
            per_face[face].append(_leaf(solid, label, PART_MATERIALS[part], loc))
    panels = []
    for face, solids in enumerate(per_face):
        panel = Compound(children=solids)
        panel.label = cp.face_labels[face]
        panels.append(panel)
    return panels


def _crease_strips(fab: Fabrication, motion: SheetMotion) -> Compound:
    """The crease sheet: as built (flat), or cut per face and moved with each face."""
    material = PART_MATERIALS["creases"]
    flat = fab.parts.solids["creases"]
    if motion.ratio == 0:
        strips = [_leaf(s, f"crease_strip_{k}", material, None) for k, s in enumerate(flat)]
    else:
        cp = fab.pattern
        p = fab.params
        z0, z1 = p.half_height, p.half_height + p.thickness
        sheet = crease_sheet(fab.outlines, sheet_outline(cp))
        strips = []
        for face, poly in enumerate(cp.face_polygons()):
            piece = shapely.intersection(sheet, shapely.Polygon(poly))
            for k, part in enumerate(shapely.get_parts(piece)):
                if part.geom_type != "Polygon" or part.area < 1e-9:
                    continue
                label = f"{cp.face_labels[face]}_strip_{k}"
                strips.append(
                    _leaf(planar_prism(part, z0, z1), label, material, motion.locations[face])
                )
    out = Compound(children=strips)
    out.label = "creases"
    return out


def _crease_frames(cp: CreasePattern) -> list[tuple[int, int, int, np.ndarray, np.ndarray]]:
    """Every crease joining two faces: ``(edge, face A, face B, midpoint, direction)``."""
    ef = cp.edge_faces()
    out = []
    for e in np.flatnonzero(np.isin(cp.assignments, ("M", "V"))).tolist():
        if (ef[e] < 0).any():
            continue
        a, b = cp.vertices[cp.edges[e]]
        out.append((e, int(ef[e][0]), int(ef[e][1]), (a + b) / 2, (b - a) / np.linalg.norm(b - a)))
    return out


def mount_point(fab: Fabrication, face: int) -> tuple[float, float]:
    """Where a TSA module's mount centres on panel ``face``: its outer face inset by 1 mm, mm.

    A panel too small for the inset gives its outer face's centroid.
    """
    outer = shapely.Polygon(fab.outlines[face].outer)
    foot = outer.buffer(-1.0, join_style="mitre")
    foot = foot if not foot.is_empty else outer
    return float(foot.centroid.x), float(foot.centroid.y)


def _add_joints(fab: Fabrication, panels: Sequence[Compound], motion: SheetMotion) -> None:
    """The panels' mount, crease and blocker joints (see the module's docstring)."""
    cp, p = fab.pattern, fab.params
    h, z_hinge = p.height, p.height / 2.0
    z_block = (p.height + p.thickness) / 2.0
    locs = motion.locations
    for face, panel in enumerate(panels):
        x, y = mount_point(fab, face)
        RigidJoint("mount", panel, locs[face] * Location((x, y, h)))
    for e, fa, fb, mid, d in _crease_frames(cp):
        axis_flat = Axis((float(mid[0]), float(mid[1]), z_hinge), (float(-d[0]), float(-d[1]), 0.0))
        axis = axis_flat.located(locs[fa])
        joint = RevoluteJoint(f"crease {e}", panels[fa], axis=axis, angular_range=(-180, 180))
        joint.fold_angle = float(motion.fold_angles[e])
        # the joint's frame at angle 0, pulled back to the flat sheet, moved with panel B
        flat_frame = locs[fa].inverse() * joint.location
        RigidJoint(f"crease {e}", panels[fb], locs[fb] * flat_frame)
        yaw = float(np.degrees(np.arctan2(d[1], d[0]))) - 90.0
        z = z_block if cp.assignments[e] == "V" else h - z_block
        seat = Location((float(mid[0]), float(mid[1]), z), (0, 0, 1), yaw)
        RigidJoint(f"blocker {e}", panels[fa], locs[fa] * seat)


def sheet_assembly(fab: Fabrication, ratio: float = 0.0, design: Design | None = None) -> Compound:
    """The printed sheet as a labelled, coloured ``Compound`` tree with joints, at ``ratio``.

    Parameters
    ----------
    fab : Fabrication
        The fabricated sheet.
    ratio : float
        Fold ratio p in [0, 1] (0: flat, as printed).
    design : Design, optional
        The design to fold (default ``fab.design``, else the pattern folded by degree-4
        propagation).

    Returns
    -------
    Compound
        See the module's docstring; ``sheet.fold_ratio`` is ``ratio``.
    """
    motion = sheet_motion(fab.pattern, fab.params, ratio, design or getattr(fab, "design", None))
    panels = _panel_children(fab, motion)
    _add_joints(fab, panels, motion)
    sheet = Compound(children=[*panels, _crease_strips(fab, motion)])
    sheet.label = fab.pattern.title or "sheet"
    sheet.fold_ratio = float(ratio)
    return sheet


def leaf_part(label: str) -> str | None:
    """The part (``infills``...) a solid of :func:`sheet_assembly` belongs to, from its label."""
    words = label.rsplit("_", 2)
    return KIND_PARTS.get(words[-2]) if len(words) == 3 else None


def solids_by_part(shape: Any) -> dict[str, list[Solid]]:
    """The solids of a sheet assembly (or a tree holding one), by part name, in tree order."""
    out: dict[str, list[Solid]] = {n: [] for n in PART_NAMES}
    stack = [shape]
    while stack:
        node = stack.pop(0)
        children = list(getattr(node, "children", ()) or ())
        if children:
            stack[:0] = children
            continue
        part = leaf_part(node.label or "")
        if part is not None:
            out[part].append(node)
    return out


def moved_tree(shape: Any, loc: Location) -> Any:
    """A copy of a shape or a labelled tree moved by ``loc``, keeping labels and colours.

    Every node of the copy is new (the original tree is left as it was, still attached
    wherever it is), so the copy can be exported or nested on its own.
    """
    children = list(getattr(shape, "children", ()) or ())
    if not children:
        # build123d's ``moved`` deep-copies the node's parent too, hence the whole tree
        # for every leaf (quadratic); the copy here stops at the node, detached
        parent = getattr(shape, "parent", None)
        out = copy.deepcopy(shape, {id(parent): None} if parent is not None else {})
        out.move(loc)
    else:
        out = Compound(children=[moved_tree(c, loc) for c in children])
    out.label = shape.label
    if getattr(shape, "color", None) is not None:
        out.color = shape.color
    return out
