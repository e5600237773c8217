"""Computational design of origami robotic arms (the paper's section III-B).

>>> from origami_cad.design import ArmTask, SearchSettings
>>> task = ArmTask(points=[[250.0, 0.0], [50.0, 133.3]], vectors=6)
>>> task.dimension
11
"""

from origami_cad.design.arm import ArmSearch, choose_arm_winner, design_arm
from origami_cad.design.fitness import (
    INFEASIBLE_COST,
    FitnessResult,
    FitnessTerms,
    arm_fitness,
    sample_angles,
)
from origami_cad.design.limits import panel_bias_violations
from origami_cad.design.search import (
    ArmDesign,
    decode,
    decode_bias,
    rank_designs,
    run_one,
    ties,
)
from origami_cad.design.task import ArmTask, SearchSettings, load_task, task_to_dict
from origami_cad.kinematics.limits import crease_fold_limit, leg_fold_angles, reachable_fold_angle

__all__ = [
    "INFEASIBLE_COST",
    "ArmDesign",
    "ArmSearch",
    "ArmTask",
    "FitnessResult",
    "FitnessTerms",
    "SearchSettings",
    "arm_fitness",
    "choose_arm_winner",
    "crease_fold_limit",
    "decode",
    "decode_bias",
    "design_arm",
    "leg_fold_angles",
    "load_task",
    "panel_bias_violations",
    "rank_designs",
    "reachable_fold_angle",
    "run_one",
    "sample_angles",
    "task_to_dict",
    "ties",
]
