"""The names of the package, each imported on first use (origami_cad._lazy.attach_stub)."""

from origami_cad.design import ArmTask, design_arm, load_task
from origami_cad.fabrication import (
    Fabrication,
    FabricationParams,
    fabricate,
    plan_panels,
    write_fabrication,
)
from origami_cad.fabrication.exports.step import export_step_tree
from origami_cad.kinematics.folding import FoldedState, fold_design, fold_sequence
from origami_cad.kinematics.placement import place_on_table
from origami_cad.parts import Blocker, DriverAdapter, RingRail, TSAModule
from origami_cad.pattern.design import Design, load_design, miura_design, tg_design
from origami_cad.pattern.formats.fold import write_fold
from origami_cad.pattern.io import read_pattern, write_pattern
from origami_cad.pattern.model import CreasePattern
from origami_cad.pattern.tg import TGDesign
from origami_cad.simulation import SimulationParams, simulate
from origami_cad.simulation.calibrate import Calibration, calibrate
from origami_cad.simulation.folder import fold, fold_states
from origami_cad.simulation.mjcf import to_mjcf
from origami_cad.simulation.paths import with_fold_path
from origami_cad.strings import RouteSpec, TSAParams, load_route, simulate_dcqc
from origami_cad.strings.plan import plan_routes
from origami_cad.viz.pyvista_mesh import display_mode, show, to_pyvista
