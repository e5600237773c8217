"""Computational design of origami arms: eq. 5, constraints, CMA-ES runs, outputs."""

from __future__ import annotations

import concurrent.futures as cf
import json
import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from helpers_exec import InlineExecutor
from matplotlib.image import imread

from origami_cad.cli import main
from origami_cad.design import (
    ArmTask,
    SearchSettings,
    arm_fitness,
    crease_fold_limit,
    decode,
    design_arm,
    leg_fold_angles,
    load_task,
    reachable_fold_angle,
    run_one,
    ties,
)
from origami_cad.design.search import FITNESS_TIE
from origami_cad.errors import DesignError
from origami_cad.kinematics import chain_points, tessellation_vertices
from origami_cad.kinematics.folding import fold_design
from origami_cad.pattern.design import Design, load_design
from origami_cad.pattern.tg import TGDesign, tg_pattern
from origami_cad.viz.design_plots import plot_trajectories

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
PAPER_TASK = EXAMPLES / "arm_task.toml"


def test_eq5_by_hand_for_a_straight_and_a_folding_arm():
    task = ArmTask(
        points=[[250.0, 0.0], [0.0, 100.0]],
        alpha=120.0,
        vectors=3,
        hypar_base=True,
        unit_width=0,
        fold_limit=180.0,  # the paper's range: T_e(pi)
    )
    lengths = np.array([[100.0, 80.0, 70.0]])
    beta = np.radians([[40.0, 140.0]])
    res = arm_fitness(task, lengths, beta, [1])
    # flat: the chain lies along +x (alpha_0 = 0 from eq. 3), 250 mm long
    assert res.d_start[0] == pytest.approx(0.0, abs=1e-9)
    # folded: compare with the chain computed independently
    tip = chain_points(np.array([math.pi]), lengths, beta, 1, True)[0, 0, -1]
    d_end = float(np.linalg.norm(tip - [0.0, 100.0]))
    assert res.d_end[0] == pytest.approx(d_end)
    n = int(res.improper[0])
    expected = 120 / 10 + 480 / (10 + d_end) - 4 * n
    assert res.fitness[0] == pytest.approx(expected)


def _random_designs(task, count, seed):
    x = np.random.default_rng(seed).uniform(size=(count, task.dimension))
    return decode(task, x)


def test_self_intersections_agree_with_shapely_on_random_designs():
    task = ArmTask(
        points=[[250.0, 0.0], [50.0, 133.3]], vectors=6, samples=12, unit_width=0, fold_limit=180
    )
    lengths, beta = _random_designs(task, 150, seed=3)
    flags = np.arange(150) % 2
    res = arm_fitness(task, lengths, beta, flags)
    pts = chain_points(np.linspace(0, math.pi, 12), lengths, beta, flags, True)
    expected = []
    for design in pts:
        count = 0
        for p in design:
            segs = [shapely.LineString(p[k : k + 2]) for k in range(len(p) - 1)]
            count += any(
                segs[a].intersects(segs[b])
                for a in range(len(segs))
                for b in range(a + 2, len(segs))
            )
        expected.append(count)
    assert res.improper.tolist() == expected
    assert 0 < sum(e > 0 for e in expected) < 150  # both kinds of design were tested


def test_warning_area_counts_states_with_the_tip_inside():
    task = ArmTask(points=[[250.0, 0.0], [50.0, 133.3]], vectors=3, samples=19, unit_width=0)
    lengths, beta = np.array([[100.0, 80.0, 70.0]]), np.radians([[40.0, 140.0]])
    tips = arm_fitness(task, lengths, beta, [1]).tips[0]
    area = shapely.box(tips[:, 0].min() - 1, tips[:, 1].min() - 1, 1e4, 1e4)  # every tip
    half = shapely.box(-1e4, -1e4, 1e4, float(np.median(tips[:, 1])))
    base = arm_fitness(task, lengths, beta, [1]).improper[0]
    warned = ArmTask(points=task.points, vectors=3, samples=19, unit_width=0, warning=(area,))
    assert arm_fitness(warned, lengths, beta, [1]).improper[0] == 19
    inside = int(shapely.contains_xy(half, tips[:, 0], tips[:, 1]).sum())
    part = ArmTask(points=task.points, vectors=3, samples=19, unit_width=0, warning=(half,))
    assert arm_fitness(part, lengths, beta, [1]).improper[0] >= max(inside, base)


def test_prohibited_area_agrees_with_shapely_and_is_worse_than_any_feasible():
    box = shapely.Polygon(
        [(150, 40), (400, 40), (400, 400), (150, 400)], [[(200, 100), (300, 100), (300, 200)]]
    )
    task = ArmTask(
        points=[[250.0, 0.0], [50.0, 133.3]],
        vectors=5,
        samples=10,
        unit_width=0,
        prohibited=(box,),
        fold_limit=180.0,
    )
    lengths, beta = _random_designs(task, 120, seed=5)
    res = arm_fitness(task, lengths, beta, np.ones(120, int))
    pts = chain_points(np.linspace(0, math.pi, 10), lengths, beta, 1, True)
    touches = [sum(shapely.LineString(p).intersects(box) for p in d) for d in pts]
    assert res.prohibited_hits.tolist() == touches
    assert 0 < sum(t > 0 for t in touches) < 120
    bad = np.array(touches) > 0
    assert np.all(res.fitness[bad] == -math.inf) and np.all(np.isfinite(res.fitness[~bad]))
    cost = res.cost()
    assert cost[bad].min() > cost[~bad].max()


def test_intermediate_points_are_matched_in_order():
    task = ArmTask(
        points=[[250.0, 0.0], [150.0, -60.0], [60.0, 120.0], [50.0, 133.3]],
        weights=[100.0, 50.0],
        vectors=3,
        unit_width=0,
    )
    lengths = np.array([[100.0, 80.0, 70.0]])
    beta = np.radians([[40.0, 140.0]])
    res = arm_fitness(task, lengths, beta, [1])
    tips = res.tips[0]
    k1, k2 = res.mid_index[0]
    assert k1 <= k2
    assert res.d_mid[0, 0] == pytest.approx(np.linalg.norm(tips - [150, -60], axis=1).min())
    assert res.d_mid[0, 1] == pytest.approx(np.linalg.norm(tips[k1:] - [60, 120], axis=1).min())
    base = ArmTask(points=[[250.0, 0.0], [50.0, 133.3]], vectors=3, unit_width=0)
    plain = arm_fitness(base, lengths, beta, [1]).fitness[0]
    bonus = 100 / (10 + res.d_mid[0, 0]) + 50 / (10 + res.d_mid[0, 1])
    assert res.fitness[0] == pytest.approx(plain + bonus)


def test_unbuildable_crease_pattern_is_infeasible():
    task = ArmTask(points=[[250.0, 0.0], [50.0, 133.3]], vectors=3, unit_width=36.0)
    # 10 mm segment between legs leaning 57 mm apart: the legs would cross
    res = arm_fitness(task, np.array([[100.0, 10.0, 100.0]]), np.radians([[17.0, 163.0]]), [1])
    assert res.leg_violations[0] > 0 and not res.feasible[0]


def test_genome_decoding_covers_both_leanings_and_is_bounded():
    task = ArmTask(vectors=4, length_range=(10.0, 120.0), shape_angle_range=(10.0, 80.0))
    u = np.linspace(0, 1, 101)
    x = np.zeros((101, task.dimension))
    x[:, 4] = u
    lengths, beta = decode(task, x)
    deg = np.degrees(beta[:, 0])
    assert lengths.min() >= 10.0 and lengths.max() <= 120.0
    assert deg[0] == pytest.approx(100.0) and deg[-1] == pytest.approx(80.0)
    assert np.all((deg >= 10 - 1e-9) & (deg <= 80 + 1e-9) | (deg >= 100 - 1e-9) & (deg <= 170))
    # the turn of eq. 2 (EF before = 1) grows monotonically with u
    turn = -np.tan(beta[:, 0])
    assert np.all(np.diff(turn) >= -1e-12) or np.all(np.diff(turn) <= 1e-12)


def test_runs_are_reproducible_and_executor_is_pluggable():
    task, _ = load_task(PAPER_TASK)
    settings = SearchSettings(runs=2, seed=7, max_generations=25)
    a = run_one(task, settings, 1)
    b = run_one(task, settings, 1)
    assert a.lengths == b.lengths and a.history == b.history
    seen = []
    results = design_arm(task, settings, executor=InlineExecutor())
    assert {r.run for r in results} <= {0, 1}
    same = [r for r in results if r.run == 1]
    assert same and same[0].lengths == a.lengths
    with cf.ThreadPoolExecutor(max_workers=1) as pool:
        design_arm(task, settings, executor=pool, progress=lambda *x: seen.append(x))
    assert len(seen) == 50 and all(g >= 1 for _, g, _ in seen)


def test_seed_zero_is_reproducible_too():
    """cma reads a seed of 0 as "from the clock": run 0 of --seed 0 gave a new arm each call."""
    task, _ = load_task(PAPER_TASK)
    settings = SearchSettings(runs=1, seed=0, max_generations=8)
    a, b = run_one(task, settings, 0), run_one(task, settings, 0)
    assert a.history == b.history and a.lengths == b.lengths


def test_paper_task_winner_stays_within_eq6_and_reaches_p_end_in_the_rigid_fold():
    """Fig. 3 with b = 3, h = 2.2, t = 0.4 mm, checked on the folded 3D tessellation."""
    task, _ = load_task(PAPER_TASK)
    assert (task.bias, task.height, task.thickness) == (3.0, 2.2, 0.4)
    limit = 2 * math.degrees(math.atan(2 * 3.0 / (2.2 - 0.4)))  # eq. 6, 146.6 deg
    settings = SearchSettings(runs=10, seed=1, max_generations=300)
    results = design_arm(task, settings)
    best = results[0]
    assert best.terms.d_start <= 2.0
    assert best.terms.improper_states == 0 and best.terms.prohibited_states == 0
    # the runs tied for the best first, by fold range; the others by fitness
    tied = ties(results)
    assert [r.run for r in results[: len(tied)]] == [r.run for r in tied] and tied
    assert [r.fold_ratio_end for r in tied] == sorted(
        (r.fold_ratio_end for r in tied), reverse=True
    )
    rest = [r.fitness for r in results[len(tied) :]]
    top = max(r.fitness for r in tied)
    assert rest == sorted(rest, reverse=True) and all(f < top - FITNESS_TIE for f in rest)
    p_end = best.fold_ratio_end
    assert 0.2 < p_end < 0.82
    # the rigid folding of the winner's real crease pattern, not the formula
    design = winner_design(best, task)
    ratios = np.linspace(0.0, p_end, 101)
    peak = max(np.abs(fold_design(design, float(p)).fold_angles).max() for p in ratios)
    assert peak <= limit + 1e-6
    # the range is the largest: a little further, a crease passes eq. 6's limit
    beyond = np.abs(fold_design(design, min(p_end + 0.01, 1.0)).fold_angles).max()
    assert beyond > limit
    # the tip of the folded 3D main crease (TG point (a, b) sits at (a, y, -b))
    grid = tessellation_vertices(design.tg, p_end)
    tip = np.array([grid[1, -1, 0], -grid[1, -1, 2]])
    assert np.linalg.norm(tip - task.points[-1]) <= 5.0
    flat = tessellation_vertices(design.tg, 0.0)
    assert np.linalg.norm(flat[1, -1, :2] - task.points[0]) <= 2.0
    # independently: the chain never touches the prohibited area over the range
    prohibited = task.prohibited[0]
    pts = chain_points(
        np.linspace(0, math.pi * p_end, 46),
        best.lengths,
        np.radians(best.shape_angles),
        best.entry_flag,
        True,
    )[0]
    assert not any(shapely.LineString(p).intersects(prohibited) for p in pts)


def winner_design(best, task):
    """The winner's tessellation as a Design (what best.toml holds)."""
    tg = best.tg(task)
    return Design(tg_pattern(tg), tg, "transition-graph")


def test_cli_writes_results_and_a_buildable_design_file(tmp_path):
    out = tmp_path / "arm"
    assert (
        main(
            [
                "design-arm",
                str(PAPER_TASK),
                "-o",
                str(out),
                "--runs",
                "2",
                "--max-generations",
                "40",
            ]
        )
        == 0
    )
    data = json.loads((out / "results.json").read_text())
    assert data["task"]["alpha"] == 120.0 and data["origami_cad_version"]
    first = data["designs"][0]
    assert len(first["tip_mm"]) == 46 and len(first["lengths_mm"]) == 6
    assert set(first["terms"]) >= {"d_start_mm", "d_end_mm", "improper_states"}
    design = load_design(out / "best.toml")
    assert design.tg is not None and design.pattern.check() == []
    # the winner's string route: one onboard TSA on the base panel, strings along the rows
    from origami_cad.strings import load_route

    route = load_route(out / "route.toml", design.pattern)
    assert route.tsa.model == "onboard" and len(route.strings) == 2
    assert route.fabrication is not None and route.fabrication.bias == 3.0
    assert "origami-cad sequence" in (out / "route.toml").read_text()
    assert design.tg.lengths == pytest.approx(first["lengths_mm"], abs=1e-5)
    for name in ("trajectories.png", "convergence.png"):
        image = imread(out / name)
        ink = np.any(image[..., :3] < 0.9, axis=-1).mean()  # not white: lines, areas, text
        assert 0.02 < ink < 0.6, (name, ink)


def test_trajectory_plot_shows_the_task_and_the_designs():
    task, _ = load_task(PAPER_TASK)
    best = run_one(task, SearchSettings(runs=1, seed=3, max_generations=10), 0)
    ax = plot_trajectories([best], task)
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    shown = np.vstack([task.points, [task.start], best.tips])
    assert x0 < shown[:, 0].min() and shown[:, 0].max() < x1
    assert y0 < shown[:, 1].min() and shown[:, 1].max() < y1
    (tip_line,) = [line for line in ax.lines if line.get_linestyle() == "--"]
    np.testing.assert_allclose(tip_line.get_xydata(), best.tips)


@pytest.mark.parametrize(
    "change, message",
    [
        (("alpha = 120.0", "alpha = 700.0"), "key 'alpha': 700 is out of range"),
        (("vectors = 6", "vectors = 6\nvectros = 3"), "unknown key 'vectros'"),
        (('entry_flag = "both"', "entry_flag = 2"), "key 'entry_flag'"),
        (("runs = 10", "runs = 0"), "key 'runs': 0 is out of range"),
        (
            ("[[150, 40], [2000, 40], [2000, 2000], [150, 2000]]", "[[150, 40], [2000, 40]]"),
            "key 'polygon'",
        ),
    ],
)
def test_task_errors_name_the_key(tmp_path, change, message):
    text = PAPER_TASK.read_text().replace(*change)
    path = tmp_path / "task.toml"
    path.write_text(text)
    with pytest.raises(DesignError, match=message) as info:
        load_task(path)
    assert "task.toml" in str(info.value)


def test_circle_obstacle(tmp_path):
    text = PAPER_TASK.read_text().replace(
        "polygon = [[150, 40], [2000, 40], [2000, 2000], [150, 2000]]", "circle = [200, 80, 30]"
    )
    path = tmp_path / "task.toml"
    path.write_text(text)
    task, _ = load_task(path)
    assert task.prohibited[0].area == pytest.approx(math.pi * 30**2, rel=1e-3)


def test_predicates_agree_with_shapely_on_random_chains():
    """The one implementation of each predicate of eq. 5, against shapely directly."""
    from origami_cad.design.fitness import area_edges
    from origami_cad.design.predicates import points_inside, self_intersections, touches_area
    from origami_cad.kinematics.chain import chain_joints

    box = shapely.Polygon(
        [(150, 40), (400, 40), (400, 400), (150, 400)], [[(200, 100), (300, 100), (300, 200)]]
    )
    task = ArmTask(points=[[250.0, 0.0], [50.0, 133.3]], vectors=8, samples=20, unit_width=0)
    lengths, beta = _random_designs(task, 200, seed=11)
    z = chain_joints(np.linspace(0, math.pi, 20), lengths, beta, np.arange(200) % 2, True)
    pts = np.stack([z.real, z.imag], axis=-1)  # (designs, samples, joints, 2)
    lines = shapely.linestrings(pts.reshape(-1, pts.shape[2], 2)).reshape(pts.shape[:2])
    edges = area_edges((box,))[0]
    touches = touches_area(z, edges)
    assert np.array_equal(touches, shapely.intersects(lines, box))
    assert 0 < touches.sum() < touches.size  # both outcomes were tested
    tips = pts[:, :, -1]
    inside = points_inside(tips, edges)
    assert np.array_equal(inside, shapely.contains_xy(box, tips[..., 0], tips[..., 1]))
    assert 0 < inside.sum() < inside.size
    crossing = self_intersections(z)
    segs = [
        [shapely.LineString(p[k : k + 2]) for k in range(len(p) - 1)]
        for p in pts[:20].reshape(-1, pts.shape[2], 2)
    ]
    expected = [
        any(s[a].intersects(s[b]) for a in range(len(s)) for b in range(a + 2, len(s)))
        for s in segs
    ]
    assert crossing[:20].reshape(-1).tolist() == expected


def test_terms_are_a_dataclass_and_json_keeps_its_keys():
    task = ArmTask(points=[[250.0, 0.0], [150.0, -60.0], [50.0, 133.3]], weights=[100.0], vectors=3)
    res = arm_fitness(task, np.array([[100.0, 80.0, 70.0]]), np.radians([[40.0, 140.0]]), [1])
    terms = res.terms(0)
    assert terms.d_start == pytest.approx(res.d_start[0]) and terms.d_end == res.d_end[0]
    assert terms.intermediate_sample == (int(res.mid_index[0, 0]),)
    data = json.loads(json.dumps(terms.to_dict()))
    assert data["d_start_mm"] == terms.d_start and data["improper_states"] == terms.improper_states
    assert data["d_intermediate_mm"] == list(terms.d_intermediate)


# ------------------------------------------------------------------ fold limits (eq. 6)


def _fold_to_limit(design, limit_deg):
    """The fold ratio at which the rigid folding first brings a crease to ``limit_deg``."""
    lo, hi = 0.0, 1.0
    for _ in range(40):
        mid = (lo + hi) / 2
        if np.abs(fold_design(design, mid).fold_angles).max() >= limit_deg:
            hi = mid
        else:
            lo = mid
    return lo


@pytest.mark.parametrize("beta, expected", [(70.0, 0.54), (80.0, 0.33), (110.0, 0.54)])
def test_legs_reach_eq6_first_in_the_rigid_folding(beta, expected):
    tg = TGDesign([60.0, 50.0, 40.0, 50.0], [beta] * 3, 1, 36.0, 3)
    design = Design(tg_pattern(tg), tg, "transition-graph")
    limit = crease_fold_limit(3.0, 2.2, 0.4)
    p_rigid = _fold_to_limit(design, math.degrees(limit))
    p_formula = reachable_fold_angle(np.radians([[beta] * 3]), limit)[0] / math.pi
    assert p_rigid == pytest.approx(expected, abs=0.006)
    assert p_formula == pytest.approx(p_rigid, abs=1e-6)
    # and the legs' angle along the way, against the folded tessellation
    for p in (0.1, 0.25, p_rigid):
        angles = np.abs(fold_design(design, p).fold_angles)
        leg = math.degrees(float(leg_fold_angles(p * math.pi, math.radians(beta))))
        assert np.isclose(angles, leg, atol=1e-6).sum() >= 6  # both legs of each joint
        assert angles.max() == pytest.approx(leg, abs=1e-6)


def test_mixed_legs_the_nearest_to_90_deg_stops_the_arm():
    tg = TGDesign([60.0, 50.0, 40.0, 50.0], [30.0, 115.0, 60.0], 0, 36.0, 2)
    design = Design(tg_pattern(tg), tg, "transition-graph")
    limit = math.radians(150.0)
    p_rigid = _fold_to_limit(design, 150.0)
    p_formula = reachable_fold_angle(np.radians([[30.0, 115.0, 60.0]]), limit)[0] / math.pi
    assert p_formula == pytest.approx(p_rigid, abs=1e-6)
    assert p_formula < reachable_fold_angle(np.radians([[30.0, 60.0]]), limit)[0] / math.pi


def test_fitness_is_evaluated_over_the_reachable_range_only():
    lengths, beta = np.array([[100.0, 80.0, 70.0]]), np.radians([[40.0, 140.0]])
    task = ArmTask(points=[[250.0, 0.0], [0.0, 100.0]], vectors=3, unit_width=0)
    res = arm_fitness(task, lengths, beta, [1])
    theta_e = 2 * math.atan(math.cos(math.radians(40)) * 2 * 3.0 / 1.8)  # legs, eq. 6
    assert res.fold_ratio_end[0] == pytest.approx(theta_e / math.pi)
    tip = chain_points(np.array([theta_e]), lengths, beta, 1, True)[0, 0, -1]
    assert res.d_end[0] == pytest.approx(np.linalg.norm(tip - [0.0, 100.0]))
    np.testing.assert_allclose(
        res.tips[0],
        chain_points(np.linspace(0, theta_e, 46), lengths, beta, 1, True)[0, :, -1],
        atol=1e-9,
    )
    # fold_limit instead of b, h, t; 180 deg is the paper's whole range
    same = ArmTask(points=task.points, vectors=3, unit_width=0, fold_limit=math.degrees(2.0))
    assert arm_fitness(same, lengths, beta, [1]).fold_ratio_end[0] == pytest.approx(
        2 * math.atan(math.cos(math.radians(40)) * math.tan(1.0)) / math.pi
    )
    free = ArmTask(points=task.points, vectors=3, unit_width=0, fold_limit=180.0)
    assert arm_fitness(free, lengths, beta, [1]).fold_ratio_end[0] == pytest.approx(1.0)


def test_a_prohibited_area_beyond_the_reachable_range_is_not_hit():
    lengths, beta = np.array([[100.0, 80.0, 70.0]]), np.radians([[75.0, 105.0]])
    full = ArmTask(points=[[250.0, 0.0], [0.0, 100.0]], vectors=3, unit_width=0, fold_limit=180)
    tip_p1 = arm_fitness(full, lengths, beta, [1]).tips[0, -1]
    printed = ArmTask(points=full.points, vectors=3, unit_width=0)
    res = arm_fitness(printed, lengths, beta, [1])
    theta_e = res.fold_ratio_end[0] * math.pi
    # a disc around T_e(pi), 20 mm from every chain the printed arm reaches
    disc = shapely.Point(*tip_p1).buffer(20.0)
    chains = chain_points(np.linspace(0, theta_e, 46), lengths, beta, 1, True)[0]
    assert min(shapely.distance(shapely.LineString(c), disc) for c in chains) > 20.0
    for task in (full, printed):
        hit = ArmTask(
            points=task.points,
            vectors=3,
            unit_width=0,
            fold_limit=task.fold_limit,
            prohibited=(disc,),
        )
        assert arm_fitness(hit, lengths, beta, [1]).feasible[0] == (task is printed)


def test_fabrication_table_is_read_and_checked(tmp_path):
    task, _ = load_task(PAPER_TASK)
    assert task.crease_limit() == pytest.approx(math.radians(146.6015), abs=1e-5)
    text = PAPER_TASK.read_text()
    path = tmp_path / "task.toml"
    path.write_text(text.replace("bias = 3.0", "fold_limit = 150.0"))
    with pytest.raises(DesignError, match="fold_limit or b, h, t"):
        load_task(path)
    path.write_text(
        text.replace("bias = 3.0", "")
        .replace("height = 2.2", "")
        .replace("thickness = 0.4", "fold_limit = 150.0")
    )
    limited, _ = load_task(path)
    assert limited.crease_limit() == pytest.approx(math.radians(150.0))
    for bad, message in [
        (("thickness = 0.4", "thickness = 2.5"), "must exceed the crease thickness"),
        (("bias = 3.0", "bias = -1.0"), "key 'bias'"),
        (("bias = 3.0", "bias = 3.0\nbais = 1.0"), "unknown key 'bais'"),
    ]:
        path.write_text(text.replace(*bad))
        with pytest.raises(DesignError, match=message) as info:
            load_task(path)
        assert "task.toml" in str(info.value)


def test_codesign_reaches_what_the_fixed_structure_cannot_and_the_panels_hold_it():
    from origami_cad.fabrication import FabricationParams, plan_panels

    # the target: a two-vector arm folded back at 78 deg legs, printed with b = 5.5 mm
    make = ArmTask(points=[[220.0, 0.0], [0.0, 0.0]], vectors=2)
    probe = arm_fitness(make, [[110.0, 110.0]], np.radians([[78.0]]), [1], np.array([5.5]))
    assert probe.panel_violations[0] == 0
    target = probe.tips[0, -1]
    settings = SearchSettings(runs=4, seed=1, max_generations=150)
    found = {}
    for codesign in (False, True):
        task = ArmTask(points=[[220.0, 0.0], target], vectors=2, codesign=codesign)
        assert task.dimension == 3 + codesign
        found[codesign] = design_arm(task, settings)[0]
    fixed, co = found[False], found[True]
    assert fixed.bias == 3.0 and 3.0 < co.bias <= 6.0
    # b = 3 mm everywhere: the legs stop the arm before it can fold back that far
    assert fixed.terms.d_start + fixed.terms.d_end > 20.0
    assert co.terms.d_start < 1.0 and co.terms.d_end < 1.0
    # the fabrication stage builds the panels at that bias and finds the same fold range
    design = winner_design(co, task)
    plan = plan_panels(design, FabricationParams(bias=co.bias))
    assert len(plan.outlines) == len(design.pattern.faces)
    assert math.degrees(plan.params.theta_max) == pytest.approx(co.terms.crease_limit)
    assert plan.limits.p_max_kinematic == pytest.approx(co.fold_ratio_end, abs=0.011)
    # a bias the panels cannot hold is infeasible
    thin = arm_fitness(task, [[110.0, 110.0]], np.radians([[78.0]]), [1], np.array([6.6]))
    assert thin.panel_violations[0] > 0 and not thin.feasible[0]


def test_compiled_fitness_tips_match_the_kinematics_chain():
    """The fitness builds its chains in compiled code: the same T_e as eqs. 2-4 of kinematics."""
    from origami_cad.kinematics.chain import chain_joints

    task = ArmTask(points=[[250.0, 0.0], [50.0, 133.3]], vectors=7, samples=15, unit_width=0)
    lengths, beta = _random_designs(task, 60, seed=21)
    flags = np.arange(60) % 2
    res = arm_fitness(task, lengths, beta, flags)
    theta = (res.fold_ratio_end * math.pi)[:, None] * np.linspace(0.0, 1.0, 15)[None, :]
    z = chain_joints(theta, lengths, beta, flags, True, task.start)[:, :, -1]
    assert np.abs(res.tips[..., 0] + 1j * res.tips[..., 1] - z).max() < 1e-9  # mm, rounding
    assert np.allclose(res.d_end, np.abs(z[:, -1] - complex(*task.points[-1])), rtol=0, atol=1e-9)
    assert np.ptp(z.real) > 100  # the chains really fold


def test_infeasible_designs_rank_by_violations_alone():
    """N is counted for feasible designs only; an infeasible design's cost is its violations."""
    box = shapely.box(150, 40, 2000, 2000)
    task = ArmTask(
        points=[[250.0, 0.0], [50.0, 133.3]], vectors=6, samples=20, unit_width=0, prohibited=(box,)
    )
    lengths, beta = _random_designs(task, 200, seed=8)
    res = arm_fitness(task, lengths, beta, np.ones(200, int))
    bad = ~res.feasible
    assert 0 < bad.sum() < 200
    assert np.all(res.improper[bad] == 0) and np.all(np.isneginf(res.fitness[bad]))
    assert np.array_equal(res.cost()[bad], 1.0e4 + res.prohibited_hits[bad])
    free = ArmTask(points=task.points, vectors=6, samples=20, unit_width=0)
    unlimited = arm_fitness(free, lengths, beta, np.ones(200, int))
    good = res.feasible
    assert np.array_equal(res.improper[good], unlimited.improper[good])
    assert np.array_equal(res.fitness[good], unlimited.fitness[good])


def test_unit_box_is_cmas_bound_transformation_on_whole_populations():
    from cma.transformations import BoxConstraintsLinQuadTransformation

    from origami_cad.design.search import UnitBox

    rng = np.random.default_rng(2)
    genotypes = rng.normal(0.5, 1.5, size=(300, 11))  # inside, near and far beyond [0, 1]
    got = UnitBox(11)(genotypes)
    tf = BoxConstraintsLinQuadTransformation([[0.0, 1.0]])
    want = np.array([tf(row.copy()) for row in genotypes])
    assert np.array_equal(got, want)
    assert got.min() >= 0.0 and got.max() <= 1.0
    inside = (genotypes > 0.05) & (genotypes < 0.95)
    assert np.array_equal(got[inside], genotypes[inside]) and inside.mean() < 0.5


def test_one_row_of_shape_angles_broadcasts_over_many_designs():
    task = ArmTask(points=[[250.0, 0.0], [50.0, 133.3]], vectors=3)
    lengths = np.array([[100.0, 80.0, 70.0], [90.0, 80.0, 70.0]])
    beta = np.radians([[40.0, 140.0]])
    both = arm_fitness(task, lengths, beta, [1])
    for k in range(2):
        one = arm_fitness(task, lengths[k : k + 1], beta, [1])
        assert np.array_equal(both.tips[k], one.tips[0]) and both.fitness[k] == one.fitness[0]
    assert both.d_end[0] != both.d_end[1]
