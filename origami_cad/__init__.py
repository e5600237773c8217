"""origami_cad: from an origami robot idea to printed, string-driven hardware.

Stages (data flows one way, each may import only the ones above it):
``pattern`` -> ``kinematics`` -> ``design`` -> ``fabrication`` -> ``strings``
-> ``simulation`` -> ``drive`` -> ``viz``.

``import origami_cad as oc`` gives the names a script of the paper's pipeline needs
(:data:`__all__`, docs/api.md): patterns and designs, folding, arm design, fabrication
and its assembly, string routes and DCQC, simulation, route planning, the build123d
parts and ``show``. They are imported on first use, so ``import origami_cad`` stays
light (it loads no build123d, NumPy or pyvista).
"""

from __future__ import annotations

import importlib

#: ``typing.TYPE_CHECKING`` without importing typing (true for type checkers only)
TYPE_CHECKING = False

__version__ = "0.1.0"

#: Each name of the curated API and the module it comes from.
_API = {
    # patterns and designs (mm, degrees)
    "CreasePattern": "origami_cad.pattern.model",
    "read_pattern": "origami_cad.pattern.io",
    "write_pattern": "origami_cad.pattern.io",
    "write_fold": "origami_cad.pattern.formats.fold",
    "Design": "origami_cad.pattern.design",
    "load_design": "origami_cad.pattern.design",
    "miura_design": "origami_cad.pattern.design",
    "tg_design": "origami_cad.pattern.design",
    "TGDesign": "origami_cad.pattern.tg",
    # folding
    "FoldedState": "origami_cad.kinematics.folding",
    "fold_design": "origami_cad.kinematics.folding",
    "fold_sequence": "origami_cad.kinematics.folding",
    "fold": "origami_cad.simulation.folder",
    "fold_states": "origami_cad.simulation.folder",
    "with_fold_path": "origami_cad.simulation.paths",
    "place_on_table": "origami_cad.kinematics.placement",
    # arm design (eq. 5, CMA-ES)
    "ArmTask": "origami_cad.design",
    "load_task": "origami_cad.design",
    "design_arm": "origami_cad.design",
    # fabrication, its assembly and exports
    "Fabrication": "origami_cad.fabrication",
    "FabricationParams": "origami_cad.fabrication",
    "fabricate": "origami_cad.fabrication",
    "plan_panels": "origami_cad.fabrication",
    "write_fabrication": "origami_cad.fabrication",
    "export_step_tree": "origami_cad.fabrication.exports.step",
    # strings: routes, TSA, DCQC, route planning
    "RouteSpec": "origami_cad.strings",
    "TSAParams": "origami_cad.strings",
    "load_route": "origami_cad.strings",
    "simulate_dcqc": "origami_cad.strings",
    "plan_routes": "origami_cad.strings.plan",
    # simulation
    "SimulationParams": "origami_cad.simulation",
    "simulate": "origami_cad.simulation",
    "to_mjcf": "origami_cad.simulation.mjcf",
    # the build123d parts
    "TSAModule": "origami_cad.parts",
    "RingRail": "origami_cad.parts",
    "Blocker": "origami_cad.parts",
    "DriverAdapter": "origami_cad.parts",
    # visual checks
    "show": "origami_cad.viz.pyvista_mesh",
    "to_pyvista": "origami_cad.viz.pyvista_mesh",
    "display_mode": "origami_cad.viz.pyvista_mesh",
}

#: The curated API: the same names as ``_API``'s keys (a test checks it).
__all__ = [
    "ArmTask",
    "Blocker",
    "CreasePattern",
    "Design",
    "DriverAdapter",
    "Fabrication",
    "FabricationParams",
    "FoldedState",
    "RingRail",
    "RouteSpec",
    "SimulationParams",
    "TGDesign",
    "TSAModule",
    "TSAParams",
    "__version__",
    "design_arm",
    "display_mode",
    "export_step_tree",
    "fabricate",
    "fold",
    "fold_design",
    "fold_sequence",
    "fold_states",
    "load_design",
    "load_route",
    "load_task",
    "miura_design",
    "place_on_table",
    "plan_panels",
    "plan_routes",
    "read_pattern",
    "show",
    "simulate",
    "simulate_dcqc",
    "tg_design",
    "to_mjcf",
    "to_pyvista",
    "with_fold_path",
    "write_fabrication",
    "write_fold",
    "write_pattern",
]

if TYPE_CHECKING:  # for type checkers and the docs' name check; at run time: __getattr__
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
    from origami_cad.simulation.folder import fold, fold_states
    from origami_cad.simulation.mjcf import to_mjcf
    from origami_cad.simulation.paths import with_fold_path
    from origami_cad.strings import RouteSpec, TSAParams, load_route, simulate_dcqc
    from origami_cad.strings.plan import plan_routes
    from origami_cad.viz.pyvista_mesh import display_mode, show, to_pyvista


def __getattr__(name: str) -> object:
    """Import a name of the curated API on first use (PEP 562)."""
    module = _API.get(name)
    if module is None:
        raise AttributeError(f"module 'origami_cad' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
