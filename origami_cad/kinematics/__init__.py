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

__all__ = [
    "chain_angles",
    "chain_points",
    "face_normals",
    "fold_angles_from_coords",
    "fold_tessellation",
    "hypar_alpha0",
    "tessellation_vertices",
    "tip_positions",
    "turning_angles",
]
