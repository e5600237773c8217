"""Bar-and-hinge folding of any crease pattern, driven by strings and TSAs (quasi-static).

A headless, Python counterpart of Origami Simulator's model (Schenk and Guest; Liu and
Paulino; Ghassaei), with strings through holes, TSAs, thickness-aware fold limits
(eq. 6, blockers), gravity and a ground plane with Coulomb friction, free structures and
TSAs riding on a panel.
"""

from origami_cad.simulation.mechanics import bar_lengths, fold_angles, hinge_gradients
from origami_cad.simulation.model import SimulationParams, Structure, build_structure
from origami_cad.simulation.simulate import SimulationResult, simulate
from origami_cad.simulation.solver import Ground, solve_equilibrium, total_energy

__all__ = [
    "Ground",
    "SimulationParams",
    "SimulationResult",
    "Structure",
    "bar_lengths",
    "build_structure",
    "fold_angles",
    "hinge_gradients",
    "simulate",
    "solve_equilibrium",
    "total_energy",
]
