"""Simulation: a Miura folded by a string in 100 actuation steps; cost against pattern size."""

from __future__ import annotations

import math
import time

from origami_cad.pattern.design import miura_design
from origami_cad.simulation import simulate
from origami_cad.strings import TOP, TSAParams
from origami_cad.strings.route import RouteSpec, StringRoute, _auto_holes


def _run(n: int, steps: int = 100) -> tuple[float, int, int]:
    design = miura_design(n, n, 15.0, 15.0, 60.0)
    cp = design.pattern
    row = f"c{n // 4}r0s"
    labels = [f"{row}{k}" for k in range(n)]
    auto = _auto_holes(cp, 2.0)
    faces = tuple(cp.face_index(label) for label in labels)
    hx, hy = auto[labels[0]]
    from origami_cad.strings.route import side_rule

    sides = [TOP] + [side_rule(cp, faces[k - 1], faces[k]) or TOP for k in range(1, n)]
    string = StringRoute(
        (hx, hy, 8.0), faces, tuple(auto[lb] for lb in labels), tuple(sides), tuple(labels)
    )
    tsa = TSAParams(model="onboard", length=150.0, radius=0.6, max_helix_angle=75.0)
    route = RouteSpec(tsa, (string,), 2.2, math.radians(60), 20.0, fixed_panel=labels[0])
    t0 = time.perf_counter()
    result = simulate(cp, route, steps=steps)
    return time.perf_counter() - t0, cp.n_vertices, len(result)


def run() -> list[tuple[str, float, str]]:
    out = []
    times = {}
    for n in (10, 20, 40):
        seconds, nodes, steps = _run(n)
        times[n] = (seconds, nodes)
        # the "20 x 20 Miura (about 1,700 nodes)": 20 x 20 unit cells, 40 x 40 panels
        target = "target < 30 s" if n == 40 else ""
        what = f"{n // 2} x {n // 2} Miura cells ({nodes} nodes), {steps} steps, s"
        out.append((what, seconds, target))
        out.append(("  node-steps per second", nodes * steps / seconds, ""))
    (t1, n1), (t2, n2) = times[20], times[40]
    out.append(
        ("cost ~ nodes^k between 441 and 1,681 nodes: k", math.log(t2 / t1) / math.log(n2 / n1), "")
    )
    return out
