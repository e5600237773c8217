"""The route planner's search: beam search of strings and string sets, CMA-ES of hole positions.

Lengths mm, ring guide angles deg (see :mod:`origami_cad.strings.plan`). Results do not
depend on the executor: the work is split into :data:`TASKS` tasks, task ``k`` is seeded
``seed + k``, and results are gathered in task order.
"""

from __future__ import annotations

import concurrent.futures as cf
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from origami_cad.errors import StringsError
from origami_cad.parallel import local_pool
from origami_cad.strings.plan_geometry import ring_points
from origami_cad.strings.plan_model import PlanGeometry, PlannedRoute, PlanSettings, RouteScores
from origami_cad.strings.plan_scoring import evaluate_routes, string_curves
from origami_cad.strings.route import BOTTOM, TOP, StringRoute

__all__ = [
    "progress_tick",
    "ranked_routes",
    "run_tasks",
    "search_routes",
    "string_pool",
    "string_sets",
]

TASKS = 8  # the beam search is split into this many tasks, whatever the executor
STALL = 60  # a CMA-ES refinement stops after this many generations without a better route
SET_BEAM = 64  # string sets kept per size at least (a narrow beam may find no compatible set)


@dataclass
class _Strings:
    """A batch of strings: anchor index (C,), hole candidates (C, K), sides (C, K), cost (C,)."""

    anchor: np.ndarray
    holes: np.ndarray
    sides: np.ndarray
    cost: np.ndarray
    depth: np.ndarray

    def take(self, idx) -> _Strings:
        return _Strings(
            *(getattr(self, k)[idx] for k in ("anchor", "holes", "sides", "cost", "depth"))
        )


def _first_side(geom: PlanGeometry) -> int:
    """The side along which a string leaves its anchor: the anchor's side of the sheet."""
    return TOP if geom.placement.height >= 0 else BOTTOM


def _score_strings(geom, settings, s: _Strings, width: int) -> tuple[np.ndarray, RouteScores]:
    """Each string scored alone as a one-string route; cost (C,) and the scores."""
    faces = geom.hole_face[s.holes]
    xy = geom.hole_xy[s.holes]
    x, rest, cuts = string_curves(geom, geom.anchors[s.anchor], faces, xy, s.sides)
    scores = evaluate_routes(geom, settings, x[:, None], rest[:, None], cuts[:, None])
    return scores.cost, scores


def _expand(geom: PlanGeometry, beam: _Strings, next_holes) -> _Strings:
    """Every string of ``beam`` extended by one hole on an adjacent, unvisited panel."""
    out_a, out_h, out_s = [], [], []
    d = int(beam.depth[0]) if len(beam.depth) else 0
    for c in range(len(beam.anchor)):
        seq = beam.holes[c, :d]
        visited = geom.hole_face[seq]
        nxt = next_holes[visited[-1]]
        nxt = nxt[~np.isin(geom.hole_face[nxt], visited)]
        if not len(nxt):
            continue
        k = len(nxt)
        holes = np.repeat(seq[None], k, axis=0)
        out_h.append(np.column_stack([holes, nxt]))
        sides = np.repeat(beam.sides[c, :d][None], k, axis=0)
        out_s.append(np.column_stack([sides, geom.rule[visited[-1], geom.hole_face[nxt]]]))
        out_a.append(np.full(k, beam.anchor[c]))
    if not out_a:
        return _Strings(
            *(np.zeros((0, *sh), dtype=np.int64) for sh in ((), (d + 1,), (d + 1,))),
            np.zeros(0),
            np.zeros(0, dtype=np.int64),
        )
    n = sum(len(a) for a in out_a)
    return _Strings(
        np.concatenate(out_a),
        np.concatenate(out_h),
        np.concatenate(out_s).astype(np.int64),
        np.zeros(n),
        np.full(n, d + 1),
    )


def _prune(geom, s: _Strings, scores: RouteScores, width: int, per_path: int = 2) -> np.ndarray:
    """Indices of the ``width`` best strings that cut no panel, at most ``per_path``
    per (anchor, panel sequence): the beam keeps different paths."""
    order = np.lexsort((np.arange(len(s.cost)), s.cost))
    seen: dict[tuple, int] = {}
    keep = []
    for i in order:
        if scores.why[i] == 1:
            continue
        key = (int(s.anchor[i]), *geom.hole_face[s.holes[i]].tolist())
        if seen.get(key, 0) >= per_path:
            continue
        seen[key] = seen.get(key, 0) + 1
        keep.append(i)
        if len(keep) >= width:
            break
    return np.array(keep, dtype=np.int64)


def _next_holes(geom: PlanGeometry) -> list[np.ndarray]:
    """For each panel, the candidate holes on the panels it shares a DCQC crease with."""
    return [np.flatnonzero(geom.rule[f, geom.hole_face] != 0) for f in range(len(geom.labels))]


def _beam_task(geom: PlanGeometry, settings: PlanSettings, starts: np.ndarray) -> dict:
    """Beam search from ``starts`` (S, 2: anchor, first hole): the valid strings found.

    Returns padded arrays (``holes``, ``sides`` (M, max_holes)), ``anchor``, ``cost``
    and the number of strings evaluated.
    """
    width = settings.candidates
    side0 = _first_side(geom)
    beam = _Strings(
        starts[:, 0].copy(),
        starts[:, 1:2].copy(),
        np.full((len(starts), 1), side0, dtype=np.int64),
        np.zeros(len(starts)),
        np.ones(len(starts), dtype=np.int64),
    )
    nxt = _next_holes(geom)
    found: list[tuple[_Strings, np.ndarray]] = []
    evaluated = 0
    for depth in range(1, settings.max_holes + 1):
        if depth > 1:
            beam = _expand(geom, beam, nxt)
        if not len(beam.anchor):
            break
        beam.cost, scores = _score_strings(geom, settings, beam, width)
        evaluated += len(beam.cost)
        if depth > 1:
            good = np.flatnonzero(scores.valid)
            found.append((beam.take(good), good))
        beam = beam.take(_prune(geom, beam, scores, width))
    pad = settings.max_holes
    out = {"anchor": [], "holes": [], "sides": [], "cost": []}
    for s, _ in found:
        k = s.holes.shape[1]
        out["anchor"].append(s.anchor)
        out["holes"].append(np.pad(s.holes, ((0, 0), (0, pad - k)), mode="edge"))
        out["sides"].append(np.pad(s.sides, ((0, 0), (0, pad - k)), mode="edge"))
        out["cost"].append(s.cost)
    arrays = {
        k: (np.concatenate(v) if v else np.zeros((0, pad) if k in ("holes", "sides") else 0))
        for k, v in out.items()
    }
    order = np.lexsort((np.arange(len(arrays["cost"])), arrays["cost"]))[: 2 * width]
    result = {k: v[order] for k, v in arrays.items()}
    result["evaluated"] = evaluated
    return result


def _pool_curves(geom: PlanGeometry, pool: dict):
    """The pool's strings over the grid: x_dis, rest (P, G), cuts (P,), faces used (P, F)."""
    faces = geom.hole_face[pool["holes"]]
    x, rest, cuts = string_curves(
        geom, geom.anchors[pool["anchor"]], faces, geom.hole_xy[pool["holes"]], pool["sides"]
    )
    used = np.zeros((len(faces), len(geom.labels)), dtype=bool)
    np.put_along_axis(used, faces, True, axis=1)
    if geom.anchor_face >= 0:
        used[:, geom.anchor_face] = False
    return x, rest, cuts, used


def _overlap(route_sets: np.ndarray, sets: np.ndarray) -> np.ndarray:
    """(B, P): whether each route's set (B, X) meets each pool string's set (P, X)."""
    return (route_sets.astype(np.uint8) @ sets.T.astype(np.uint8)).astype(bool)


def _compatible(geom: PlanGeometry, pool: dict, used, routes: np.ndarray, share: bool):
    """(B, P) which pool strings may join each route: later in the pool; on a ring no guide
    shared and no panel (``share``: no hole) shared, onboard not the same holes."""
    last = routes.max(axis=1)
    ok = np.arange(len(used))[None, :] > last[:, None]
    if geom.placement.kind != "ring":
        same = (pool["holes"][routes][:, :, None, :] == pool["holes"][None, None]).all(axis=-1)
        return ok & ~same.any(axis=1)
    if share:
        holes = np.zeros((len(used), len(geom.hole_face)), dtype=bool)
        np.put_along_axis(holes, pool["holes"], True, axis=1)
        ok &= ~_overlap(holes[routes].any(axis=1), holes)
    else:
        ok &= ~_overlap(used[routes].any(axis=1), used)
    anchors = pool["anchor"]
    return ok & ~(anchors[routes][:, :, None] == anchors[None, None, :]).any(axis=1)


def string_sets(geom, settings, pool: dict, n_strings: int) -> tuple[np.ndarray, int]:
    """Beam search over sets of ``n_strings`` pool strings: the best routes (B, n) and the
    sets evaluated.

    On a ring, strings first keep to panels of their own (each panel pulled by one
    string); when no ``n_strings`` such strings fit together (a small sheet), they may
    share panels through holes of their own. Never two strings through one hole, nor
    (ring) from one guide.

    Raises
    ------
    StringsError
        No ``n_strings`` strings fit together, saying how many do.
    """
    try:
        return _combine(geom, settings, pool, n_strings, share=False)
    except _TooMany as exc:
        if geom.placement.kind != "ring":
            raise StringsError(exc.message) from None
    try:
        return _combine(geom, settings, pool, n_strings, share=True)
    except _TooMany as exc:
        raise StringsError(exc.message) from None


class _TooMany(Exception):
    """No set of the asked size fits together; ``message`` says how many do."""

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.message = message


def _combine(geom, settings, pool: dict, n_strings: int, share: bool):
    """Beam search over sets of ``n_strings`` pool strings: the best routes (B, n), scores."""
    x, rest, cuts, used = _pool_curves(geom, pool)
    width = max(settings.candidates, SET_BEAM)
    routes = np.arange(len(x))[:, None]
    scores = evaluate_routes(geom, settings, x[:, None], rest[:, None], cuts[:, None])
    evaluated = len(routes)
    for size in range(2, n_strings + 1):
        keep = np.lexsort((np.arange(len(routes)), scores.cost))[:width]
        routes = routes[keep]
        ok = _compatible(geom, pool, used, routes, share)
        b, p = np.nonzero(ok)
        if not len(b):
            fewer = "1 string fits" if size == 2 else f"at most {size - 1} strings fit"
            raise _TooMany(
                f"no {n_strings} strings fit together (each needs a hole sequence of its own"
                f"{' and a guide of its own' if geom.placement.kind == 'ring' else ''}): "
                f"{fewer} on this sheet; ask for --strings {size - 1}, or leave --strings out "
                "to plan the fewest that reach the target"
            )
        routes = np.column_stack([routes[b], p])
        parts = []
        for lo in range(0, len(routes), 4096):
            r = routes[lo : lo + 4096]
            parts.append(evaluate_routes(geom, settings, x[r], rest[r], cuts[r]))
        scores = RouteScores(
            *(
                np.concatenate([getattr(s, f) for s in parts])
                for f in RouteScores.__dataclass_fields__
            )
        )
        evaluated += len(routes)
    order = np.lexsort((np.arange(len(routes)), scores.cost))[:width]
    return routes[order], evaluated


def _route_arrays(geom: PlanGeometry, pool: dict, route: np.ndarray) -> dict:
    """A route of pool strings as arrays: ring angles (n,), faces, xy, sides (n, K), counts."""
    holes = pool["holes"][route]
    count = 1 + (np.diff(holes, axis=1) != 0).sum(axis=1)
    return {
        "angle": geom.anchor_angle[pool["anchor"][route]].astype(float),
        "faces": geom.hole_face[holes],
        "xy": geom.hole_xy[holes].astype(float),
        "sides": pool["sides"][route].astype(np.int64),
        "count": count,
    }


def _anchor_positions(geom: PlanGeometry, angles: np.ndarray) -> np.ndarray:
    """Anchors (..., G, 3) for ring angles (...) deg, or the onboard TSA's for each."""
    g = len(geom.ratios)
    if geom.placement.kind == "ring":
        pts = ring_points(geom.centre, geom.placement, angles)
        return np.broadcast_to(pts[..., None, :], (*pts.shape[:-1], g, 3))
    return np.broadcast_to(geom.anchors[0], (*np.shape(angles), g, 3))


def _score_arrays(geom, settings, angle, xy, route: dict) -> RouteScores:
    """Scores of P variants of one route: guide angles (P, n) deg and holes (P, n, K, 2)."""
    p, n, k = xy.shape[:3]
    faces = np.broadcast_to(route["faces"], (p, n, k)).reshape(p * n, k)
    sides = np.broadcast_to(route["sides"], (p, n, k)).reshape(p * n, k)
    anchors = _anchor_positions(geom, angle.reshape(-1))
    x, rest, cuts = string_curves(geom, anchors, faces, xy.reshape(p * n, k, 2), sides)
    g = x.shape[-1]
    return evaluate_routes(
        geom, settings, x.reshape(p, n, g), rest.reshape(p, n, g), cuts.reshape(p, n)
    )


def _decode(geom: PlanGeometry, route: dict, genomes: np.ndarray):
    """Guide angles (P, n) deg and holes (P, n, K, 2) mm from genomes: 3 deg and 2 mm steps."""
    n, k = route["faces"].shape
    ring = geom.placement.kind == "ring"
    angle = np.broadcast_to(route["angle"], (len(genomes), n)).copy()
    at = 0
    if ring:
        angle += 3.0 * genomes[:, :n]
        at = n
    xy = np.broadcast_to(route["xy"], (len(genomes), n, k, 2)).copy()
    for i in range(n):
        c = int(route["count"][i])
        move = 2.0 * genomes[:, at : at + 2 * c].reshape(-1, c, 2)
        xy[:, i, :c] += move
        xy[:, i, c:] = xy[:, i, c - 1 : c]
        at += 2 * c
    return angle, xy


def _outside(geom: PlanGeometry, route: dict, xy: np.ndarray, polys: dict) -> np.ndarray:
    """(P,) how many holes of each variant leave their panel's operation region."""
    import shapely

    out = np.zeros(len(xy))
    for i, faces in enumerate(route["faces"]):
        for j in range(int(route["count"][i])):
            f = int(faces[j])
            if f not in polys:
                rings = geom.regions[f]
                polys[f] = shapely.Polygon(rings[0]) if rings else None
            if polys[f] is not None:
                out += ~shapely.contains_xy(polys[f], xy[:, i, j, 0], xy[:, i, j, 1])
    return out


def _refine_task(geom: PlanGeometry, settings: PlanSettings, route: dict, seed: int) -> dict:
    """CMA-ES over one route's hole positions (in their regions) and ring guide angles.

    Seeded with ``seed``; returns the best variant (the route itself if none is better),
    its cost and the number of variants evaluated.
    """
    import cma

    from origami_cad._libm import canonical_eigh

    n = len(route["faces"])
    dim = int(route["count"].sum()) * 2 + (n if geom.placement.kind == "ring" else 0)
    polys: dict = {}

    def cost(genomes: np.ndarray) -> np.ndarray:
        angle, xy = _decode(geom, route, genomes)
        return _score_arrays(geom, settings, angle, xy, route).cost + 1e3 * _outside(
            geom, route, xy, polys
        )

    best_g, best_c = np.zeros(dim), float(cost(np.zeros((1, dim)))[0])
    opts = {"seed": seed + 1, "maxiter": settings.generations, "verbose": -9, "verb_log": 0}
    opts.update(verb_disp=0, popsize=max(8, 4 + int(3 * math.log(dim))), tolfun=1e-6)
    opts["CMA_eigenmethod"] = canonical_eigh  # the same samples whatever the CPU
    es = cma.CMAEvolutionStrategy(np.zeros(dim), 0.5, opts)
    evaluated, since = 1, 0
    while not es.stop() and since < STALL and time.time() < settings.deadline:
        pop = np.asarray(es.ask())
        c = cost(pop)
        evaluated += len(pop)
        es.tell(list(pop), c.tolist())
        k = int(np.argmin(c))
        since += 1
        if c[k] < best_c - 1e-9:
            best_g, best_c, since = pop[k].copy(), float(c[k]), 0
    angle, xy = _decode(geom, route, best_g[None])
    return {**route, "angle": angle[0], "xy": xy[0], "cost": best_c, "evaluated": evaluated}


def run_tasks(
    executor: cf.Executor | None,
    fn: Callable,
    tasks: Sequence[tuple],
    progress: Callable[[Any], None] | None = None,
) -> list:
    """``fn(*task)`` for every task on ``executor``; results in task order.

    Default: a process pool on this machine (one worker per core, fork where
    available). Any ``concurrent.futures.Executor`` works, e.g. a Dask cluster's
    ``Client.get_executor()``. ``progress(result)`` is called as tasks finish (in
    whatever order they finish); the results never depend on that order.
    """
    own = executor is None
    if own:
        executor = local_pool(len(tasks))
    try:
        futures = [executor.submit(fn, *task) for task in tasks]
        if progress is not None:
            for f in cf.as_completed(futures):
                progress(f.result())
        return [f.result() for f in futures]
    finally:
        if own:
            executor.shutdown(wait=True, cancel_futures=True)


def _starts(geom: PlanGeometry) -> list[np.ndarray]:
    """The (anchor, first hole) pairs, split into :data:`TASKS` contiguous chunks."""
    a, h = np.meshgrid(np.arange(len(geom.anchors)), np.arange(len(geom.hole_face)), indexing="ij")
    pairs = np.column_stack([a.ravel(), h.ravel()])
    return [c for c in np.array_split(pairs, TASKS) if len(c)]


def _merge(results: list[dict]) -> dict:
    pool = {
        k: np.concatenate([r[k] for r in results]) for k in ("anchor", "holes", "sides", "cost")
    }
    order = np.lexsort((np.arange(len(pool["cost"])), pool["cost"]))
    return {k: v[order].astype(np.int64) if k != "cost" else v[order] for k, v in pool.items()}


def progress_tick(progress: Callable[[int, int | None], None] | None) -> Callable[[dict], None]:
    """A callback adding each task's ``evaluated`` count and calling ``progress(total, None)``."""
    counter = [0]

    def tick(result: dict) -> None:
        counter[0] += int(result["evaluated"])
        if progress is not None:
            progress(counter[0], None)

    return tick


def string_pool(geom: PlanGeometry, settings: PlanSettings, executor, tick) -> dict:
    """The beam search of single strings (tasks on ``executor``): the best valid ones, as
    padded arrays (``anchor``, ``holes``, ``sides``, ``cost``), best first.

    Raises
    ------
    StringsError
        No string satisfies DCQC from flat to the target.
    """
    faces = np.unique(geom.hole_face)
    if not (geom.rule[np.ix_(faces, faces)] != 0).any():  # no sequence of two holes at all
        raise StringsError(
            f"no two of the {len(faces)} panels with holes meet at a mountain or valley crease "
            "(a string runs from a panel to a neighbour; the panels between them have no room "
            f"for a {geom.fabrication.hole_diameter:g} mm hole even at the narrowest bias): "
            "no string can be routed on this sheet at this size (larger panels, --width, give "
            "more of them room)"
        )
    found = run_tasks(executor, _beam_task, [(geom, settings, s) for s in _starts(geom)], tick)
    pool = _merge(found)
    if not len(pool["cost"]):  # plan_routes says what else works
        raise StringsError(
            f"no string satisfies DCQC from flat to p = {geom.target_p:.3f}: every hole "
            f"sequence of {len(set(geom.hole_face.tolist()))} panels with holes lengthens or "
            "cuts a panel"
        )
    return {k: v[: max(4 * settings.candidates, 4 * SET_BEAM)] for k, v in pool.items()}


def ranked_routes(
    geom, settings, pool: dict, routes: np.ndarray, seed: int, executor, tick, refine: int
) -> list[PlannedRoute]:
    """The string sets ``routes`` (B, n) ranked, the best ``refine`` of them refined by
    CMA-ES first (task ``k`` seeded ``seed + k``); invalid ones dropped."""
    arrays = [_route_arrays(geom, pool, r) for r in routes[: settings.keep]]
    tasks = [(geom, settings, arrays[k], seed + k) for k in range(min(refine, len(arrays)))]
    refined = run_tasks(executor, _refine_task, tasks, tick) if tasks else []
    return _ranked(geom, settings, refined, arrays[len(refined) :])


def search_routes(
    geom, settings, n_strings: int, seed: int, executor, progress
) -> list[PlannedRoute]:
    """Beam search of strings (tasks on ``executor``), string sets, CMA-ES of the best."""
    tick = progress_tick(progress)
    pool = string_pool(geom, settings, executor, tick)
    routes, evaluated = string_sets(geom, settings, pool, n_strings)
    tick({"evaluated": evaluated})
    return ranked_routes(geom, settings, pool, routes, seed, executor, tick, settings.refine)


def _strings_of(geom: PlanGeometry, route: dict) -> tuple[StringRoute, ...]:
    """The route's strings as :class:`StringRoute` records (the route file's view)."""
    anchors = _anchor_positions(geom, route["angle"])[:, 0]
    out = []
    for i, faces in enumerate(route["faces"]):
        c = int(route["count"][i])
        if geom.placement.kind == "ring":
            anchor, anchor_face = tuple(float(v) for v in anchors[i]), -1
        else:
            anchor = (*geom.anchor_xy, float(geom.placement.height))
            anchor_face = geom.anchor_face
        out.append(
            StringRoute(
                anchor=anchor,
                faces=tuple(int(f) for f in faces[:c]),
                points=tuple((float(x), float(y)) for x, y in route["xy"][i, :c]),
                sides=tuple(int(s) for s in route["sides"][i, :c]),
                names=tuple(geom.labels[int(f)] for f in faces[:c]),
                anchor_face=anchor_face,
            )
        )
    return tuple(out)


def _ranked(geom, settings, refined: list[dict], rest: list[dict]) -> list[PlannedRoute]:
    """Rescore the refined and the other routes, drop the invalid, rank by cost."""
    items = [(r, "cma") for r in refined] + [(r, "beam") for r in rest]
    planned = []
    for k, (route, stage) in enumerate(items):
        angle = np.asarray(route["angle"], dtype=float)[None]
        s = _score_arrays(geom, settings, angle, np.asarray(route["xy"])[None], route)
        if not s.valid[0]:
            continue
        planned.append((float(s.cost[0]), k, route, stage, s))
    planned.sort(key=lambda t: (t[0], t[1]))
    out, seen = [], set()
    for cost, _, route, stage, s in planned:
        key = np.round(np.asarray(route["xy"]), 6).tobytes() + np.round(route["angle"], 6).tobytes()
        if key in seen:
            continue
        seen.add(key)
        out.append(
            PlannedRoute(
                rank=len(out) + 1,
                strings=_strings_of(geom, route),
                turns=float(s.turns[0]),
                peak_torque=float(s.peak_torque[0]),
                share=float(s.share[0]),
                cost=cost,
                p=geom.ratios.copy(),
                curve_turns=s.theta[0] / (2.0 * math.pi),
                torque=s.torque[0],
                stage=stage,
                anchor_angles=tuple(float(a) for a in route["angle"]),
            )
        )
    return out[: settings.keep]
