"""plan-route: candidate routes scored per second by the fast DCQC model, and planning Fig. 5."""

from __future__ import annotations

import resource
import time
from pathlib import Path

import numpy as np

from origami_cad.pattern.design import load_design
from origami_cad.strings import load_route, simulate_dcqc
from origami_cad.strings.plan import (
    DEFAULT_CREASE_STIFFNESS,
    PlanSettings,
    TSAPlacement,
    evaluate_routes,
    plan_geometry,
    plan_routes,
    string_curves,
)

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def random_routes(geom, count: int, n_strings: int, holes: int, rng) -> tuple:
    """``count`` routes of ``n_strings`` random walks of ``holes`` holes along the panels
    that share a DCQC crease: anchors (C, G, 3), faces, xy, sides (C, K) for C strings."""
    c = count * n_strings
    cand = [np.flatnonzero(geom.rule[f, geom.hole_face] != 0) for f in range(len(geom.labels))]
    seq = np.empty((c, holes), dtype=np.int64)
    seq[:, 0] = rng.integers(0, len(geom.hole_face), c)
    for k in range(1, holes):
        for i in range(c):
            nxt = cand[geom.hole_face[seq[i, k - 1]]]
            seq[i, k] = nxt[rng.integers(0, len(nxt))] if len(nxt) else seq[i, k - 1]
    faces = geom.hole_face[seq]
    sides = np.ones((c, holes), dtype=np.int64)
    sides[:, 1:] = np.where(geom.rule[faces[:, :-1], faces[:, 1:]] < 0, -1, 1)
    anchors = geom.anchors[rng.integers(0, len(geom.anchors), c)]
    return anchors, faces, geom.hole_xy[seq], sides


def run() -> list[tuple[str, float, str]]:
    design = load_design(EXAMPLES / "miura_6x4.toml")
    settings = PlanSettings()
    geom = plan_geometry(design, TSAPlacement("ring"), settings=settings)
    rng = np.random.default_rng(0)
    count, n = 4096, 4
    anchors, faces, xy, sides = random_routes(geom, count, n, 4, rng)
    c0, t0 = time.process_time(), time.perf_counter()
    for lo in range(0, count * n, 4096):
        sl = slice(lo, lo + 4096)
        x, rest, cuts = string_curves(geom, anchors[sl], faces[sl], xy[sl], sides[sl])
        g = x.shape[-1]
        evaluate_routes(
            geom, settings, x.reshape(-1, n, g), rest.reshape(-1, n, g), cuts.reshape(-1, n)
        )
    cpu, wall = time.process_time() - c0, time.perf_counter() - t0
    example = load_route(EXAMPLES / "miura_route.toml", design.pattern)
    hand = simulate_dcqc(design, example, crease_stiffness=DEFAULT_CREASE_STIFFNESS)
    turns, torque = float(hand.turns[-1]), float(np.nanmax(hand.torque))
    budget = PlanSettings(max_turns=0.99 * turns, max_torque=0.98 * torque)
    seen = [0]
    c1, t1, k1 = time.process_time(), time.perf_counter(), _children()
    planned = plan_routes(
        design, TSAPlacement("ring"), 4, settings=budget, progress=lambda k, _: seen.append(k)
    )
    plan_wall = time.perf_counter() - t1
    plan_cpu = time.process_time() - c1 + _children() - k1
    full = planned[0].checks["dcqc"]
    return [
        ("4-string Miura routes scored per CPU second (one core)", count / cpu, ""),
        ("  the same on 2 cores (independent tasks)", 2 * count / cpu, "target >= 1,000/s"),
        ("  wall-clock rate on this (shared) machine, routes/s", count / wall, ""),
        ("plan Fig. 5 (4 strings, ring, the example's budgets), wall s", plan_wall, "< 60 s"),
        ("  CPU s, this process and the pool's workers", plan_cpu, "(2 workers)"),
        ("  candidates scored by the search", float(max(seen)), ""),
        (f"  best route's turns, full DCQC model (example {turns:.2f})", full["turns"], ""),
        (f"  its peak torque, N mm (example {torque:.3f})", full["peak_torque_Nmm"], ""),
    ]


def _children() -> float:
    """CPU seconds of finished child processes (the process pool's workers)."""
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    return use.ru_utime + use.ru_stime
