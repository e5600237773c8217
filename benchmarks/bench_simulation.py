"""Simulation: a Miura folded by a string in 100 actuation steps; cost against pattern size.

441, 1,681 (the issue's figure, goal < 2 s CPU) and 10,201 nodes (the largest timed once:
about a minute of CPU); the cost exponent against the node count up to 10,201 nodes
(goal <= 1.2), by CPU time beside wall time.
"""

from __future__ import annotations

import math
import time

from origami_cad.pattern.design import miura_design
from origami_cad.simulation import simulate
from origami_cad.simulation.factor import pardiso_available
from origami_cad.strings import TOP, TSAParams
from origami_cad.strings.route import RouteSpec, StringRoute, auto_holes


def _run(n: int, steps: int = 100) -> tuple[float, float, int, int]:
    """Fold an ``n/2 x n/2``-cell Miura: (wall s, CPU s, nodes, states)."""
    design = miura_design(n, n, 15.0, 15.0, 60.0)
    cp = design.pattern
    row = f"c{n // 4}r0s"
    labels = [f"{row}{k}" for k in range(n)]
    auto = auto_holes(cp, 2.0)
    faces = tuple(cp.face_index(label) for label in labels)
    hx, hy = auto[labels[0]]
    from origami_cad.strings.route import side_rule

    sides = [TOP] + [side_rule(cp, faces[k - 1], faces[k]) or TOP for k in range(1, n)]
    string = StringRoute(
        (hx, hy, 8.0), faces, tuple(auto[lb] for lb in labels), tuple(sides), tuple(labels)
    )
    tsa = TSAParams(model="onboard", length=150.0, radius=0.6, max_helix_angle=75.0)
    route = RouteSpec(tsa, (string,), 2.2, math.radians(60), 20.0, fixed_panel=labels[0])
    t0, c0 = time.perf_counter(), time.process_time()
    result = simulate(cp, route, steps=steps)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return wall, cpu, cp.n_vertices, len(result)


def run() -> list[tuple[str, float, str]]:
    # the machine is shared: CPU time (process_time) beside wall time, the better of two runs
    _run(6, 3)  # load the compiled kernels
    out = [
        (
            "MKL's PARDISO installed (1: large patterns use it; 0: band/SuperLU)",
            float(pardiso_available()),
            "pip install origami-cad[mkl]",
        )
    ]
    times = {}
    for n in (10, 20, 40, 100):
        runs = [_run(n) for _ in range(1 if n == 100 else 2)]
        wall = min(r[0] for r in runs)
        cpu = min(r[1] for r in runs)
        _, _, nodes, steps = runs[0]
        times[n] = (wall, cpu, nodes)
        # the "20 x 20 Miura (1,681 nodes)": 20 x 20 unit cells, 40 x 40 panels
        target = "(wall: shared machine)" if n == 40 else ""
        what = f"{n // 2} x {n // 2} Miura cells ({nodes} nodes), {steps} states: wall s"
        out.append((what, wall, target))
        out.append(("  CPU s (process_time)", cpu, "goal < 2 s CPU" if n == 40 else ""))
        out.append(("  node-steps per second (wall)", nodes * steps / wall, ""))
        out.append(("  node-steps per CPU second", nodes * steps / cpu, ""))
    (w1, c1, n1), (w2, c2, n2) = times[20], times[40]
    k = math.log(n2 / n1)
    out.append(("cost ~ nodes^k between 441 and 1,681 nodes (wall): k", math.log(w2 / w1) / k, ""))
    out.append(
        (
            "cost ~ nodes^k between 441 and 1,681 nodes (CPU): k",
            math.log(c2 / c1) / k,
            "goal <= 1.2",
        )
    )
    (w3, c3, n3) = times[100]
    k = math.log(n3 / n2)
    out.append(
        ("cost ~ nodes^k between 1,681 and 10,201 nodes (wall): k", math.log(w3 / w2) / k, "")
    )
    out.append(
        (
            "cost ~ nodes^k between 1,681 and 10,201 nodes (CPU): k",
            math.log(c3 / c2) / k,
            "goal <= 1.2",
        )
    )
    return out
