"""The two string foldings whose states the solver must keep (within 1e-6 mm), and the
writer of their recorded states, ``tests/data/solver_states.npz``.

Run as ``python tests/solver_cases.py`` to record them afresh (only when a change of the
states is intended and explained).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from origami_cad.pattern.design import load_design, miura_design
from origami_cad.simulation import simulate
from origami_cad.strings import TOP, TSAParams
from origami_cad.strings.route import RouteSpec, StringRoute, auto_holes, side_rule

HERE = Path(__file__).resolve().parent
BASELINE = HERE / "data" / "solver_states.npz"
#: which states are recorded: every tenth and the last
EVERY = 10


def _row_string(cp, labels: list[str], tsa: TSAParams, step: float, turns: float) -> RouteSpec:
    """A string from above the first panel through the centre holes of ``labels``."""
    auto = auto_holes(cp, 2.0)
    faces = tuple(cp.face_index(label) for label in labels)
    hx, hy = auto[labels[0]]
    sides = [TOP] + [side_rule(cp, faces[k - 1], faces[k]) or TOP for k in range(1, len(faces))]
    string = StringRoute(
        (hx, hy, 8.0), faces, tuple(auto[lb] for lb in labels), tuple(sides), tuple(labels)
    )
    return RouteSpec(tsa, (string,), 2.2, math.radians(step), turns, fixed_panel=labels[0])


def miura_6x4():
    """The 6 x 4 example Miura folded by a string along its second row, 40 steps."""
    cp = load_design(HERE.parent / "examples" / "miura_6x4.toml").pattern
    tsa = TSAParams(model="onboard", length=120.0, radius=0.6, max_helix_angle=75.0)
    route = _row_string(cp, [f"c1r0s{k}" for k in range(6)], tsa, 60.0, 23.0)
    return simulate(cp, route, steps=40)


def miura_10x10():
    """The 10 x 10-panel Miura of the benchmark folded by its string, 100 steps."""
    cp = miura_design(10, 10, 15.0, 15.0, 60.0).pattern
    tsa = TSAParams(model="onboard", length=150.0, radius=0.6, max_helix_angle=75.0)
    route = _row_string(cp, [f"c2r0s{k}" for k in range(10)], tsa, 60.0, 20.0)
    return simulate(cp, route, steps=100)


CASES = {"miura_6x4": miura_6x4, "miura_10x10": miura_10x10}


def recorded(states: np.ndarray) -> np.ndarray:
    """The recorded subset of a result's ``states`` (S, n, 3): every tenth and the last."""
    keep = sorted({*range(0, len(states), EVERY), len(states) - 1})
    return states[keep]


def main() -> int:
    arrays = {}
    for name, case in CASES.items():
        result = case()
        arrays[name] = recorded(result.states)
        arrays[f"{name}_count"] = np.array(len(result.states))
        print(name, len(result.states), "states", result.reason)
    np.savez_compressed(BASELINE, **arrays)
    print("wrote", BASELINE)
    return 0


if __name__ == "__main__":
    sys.exit(main())
