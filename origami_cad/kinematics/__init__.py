"""Kinematics: the TG chain (eqs. 2-4) and exact rigid folding in 3D."""

from origami_cad.kinematics.chain import (
    chain_angles,
    chain_points,
    hypar_alpha0,
    tip_positions,
    turning_angles,
)
from origami_cad.kinematics.fold3d import (
    face_normals,
    fold_angles_from_coords,
    fold_tessellation,
    tessellation_vertices,
)
from origami_cad.kinematics.placement import place_on_table, place_sequence, vector_area

__all__ = [
    "chain_angles",
    "chain_points",
    "face_normals",
    "fold_angles_from_coords",
    "fold_tessellation",
    "hypar_alpha0",
    "place_on_table",
    "place_sequence",
    "tessellation_vertices",
    "tip_positions",
    "turning_angles",
    "vector_area",
]
