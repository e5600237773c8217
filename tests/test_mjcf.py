"""Robots into MuJoCo: the exports load, count right, settle, fold like Fig. 5,
walk, render, and bad input is refused by name. Headless; skipped without mujoco."""

from __future__ import annotations

import dataclasses
import functools
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

os.environ.setdefault("MUJOCO_GL", "egl")  # headless: before mujoco is first imported
mujoco = pytest.importorskip("mujoco")

from origami_cad.cli import main  # noqa: E402
from origami_cad.crawler.mujoco import (  # noqa: E402
    mjcf_source,
    play_gait,
    render_gait_frame,
    robot_mjcf,
    robot_mjcf_source,
)
from origami_cad.crawler.robot import load_robot  # noqa: E402
from origami_cad.pattern.design import load_design  # noqa: E402
from origami_cad.pattern.model import CreasePattern  # noqa: E402
from origami_cad.simulation.mjcf import MjcfError, load_mjcf_source, spanning_tree, to_mjcf  # noqa: E402
from origami_cad.simulation.mujoco_run import (  # noqa: E402
    crease_angles,
    hold_mean_pose,
    load_model,
    set_fold,
    tie_strings,
    tsa_actuators,
    tsa_controls,
    vertex_coords,
)
from origami_cad.simulation.simulate import fold_ratio_fit, rigid_table  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
MIURA = (EX / "miura_6x4.toml", [EX / "miura_route.toml"])
ARM = (EX / "arm_design.toml", [EX / "arm_route.toml"])
CRAWLER = (EX / "crawler" / "crawler.toml", [])


@functools.cache
def _xml(which: str) -> str:
    source, routes = {"miura": MIURA, "arm": ARM, "crawler": CRAWLER}[which]
    return robot_mjcf(source) if which == "crawler" else to_mjcf(source, routes)


@pytest.mark.parametrize("which", ["miura", "arm", "crawler"])
def test_every_export_loads_with_the_counts_of_its_pattern_and_routes(which, tmp_path):
    source, routes = {"miura": MIURA, "arm": ARM, "crawler": CRAWLER}[which]
    path = tmp_path / "model.xml"
    path.write_text(_xml(which), encoding="utf-8")
    model = mujoco.MjModel.from_xml_path(str(path))
    src = robot_mjcf_source(source) if which == "crawler" else load_mjcf_source(source, routes)
    cp = src.pattern
    creases = int(cp.edge_mask("M", "V", "F").sum())
    panels = len(cp.faces)
    hinges = sum(model.jnt_type == mujoco.mjtJoint.mjJNT_HINGE)
    assert hinges == panels - 1  # one per crease of the spanning tree
    _, _, loops = spanning_tree(cp, 0)
    assert len(loops) == creases - (panels - 1)
    assert model.neq == 2 * len(loops)  # two connects close each loop crease
    strings = sum(len(r.strings) for r in src.routes)
    assert model.ntendon == model.nu == strings
    assert model.nbody == panels + 1  # and the world
    grams = float(model.body_mass.sum()) * 1e3
    if which == "crawler":  # the paper's robot weighs 361 g
        assert 300 < grams < 420


def _mesh_props(verts, tris, density):
    """Mass (g), centre (mm) and inertia about it (g mm^2) of a closed triangle mesh,
    by signed tetrahedra from the origin (what trimesh computes), density g/cm^3."""
    a, b, c = (verts[tris[:, k]] for k in range(3))
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    vol = det.sum() / 6.0
    com = (det[:, None] * (a + b + c)).sum(axis=0) / 24.0 / vol
    canon = (np.ones((3, 3)) + np.eye(3)) / 120.0
    stack = np.stack([a, b, c], axis=2)  # (n, 3 coords, 3 vertices)
    cov = np.einsum("n,nik,kl,njl->ij", det, stack, canon, stack)
    cov -= vol * np.outer(com, com)
    rho = density * 1e-3
    return vol * rho, com, (np.trace(cov) * np.eye(3) - cov) * rho


@pytest.mark.parametrize("which", ["miura", "crawler"])
def test_panel_masses_and_inertias_are_those_of_the_printed_solids(which):
    from origami_cad.fabrication.params import DENSITY_G_CM3
    from origami_cad.simulation.mjcf import printed_panels

    source, routes = {"miura": MIURA, "crawler": CRAWLER}[which]
    src = robot_mjcf_source(source) if which == "crawler" else load_mjcf_source(source, routes)
    cp = src.pattern
    model, _ = load_model(_xml(which))
    panels, sheet_g = printed_panels(src)
    points = sum(grams for _, grams, _, _ in src.masses)
    # the whole model against the fabrication's own estimate (fabrication.json), 1 %
    assert float(model.body_mass.sum()) * 1e3 == pytest.approx(sheet_g + points, rel=0.01)
    # the sheet alone, closer than its crease strips weigh (1.6 g of the crawler's 202 g):
    # the strips are shared out between the panels, none lost or counted twice
    printed = sum(p.props.mass for p in panels.values())
    assert printed == pytest.approx(sheet_g, rel=1e-3)
    tpu = {f: sum(m == "TPU" for m, _, _ in p.meshes) for f, p in panels.items()}
    assert min(tpu.values()) >= 2  # every panel has its TPU shells (and crease strips)
    for face in (0, len(cp.faces) // 2):
        mass, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
        parts = [_mesh_props(v, t, DENSITY_G_CM3[m]) for m, v, t in panels[face].meshes]
        label = cp.face_labels[face]
        parts += [
            (grams, np.r_[at, 1.1], np.zeros((3, 3)))
            for _, grams, panel, at in src.masses
            if panel == label
        ]
        for m, c, inertia in parts:
            mass, first = mass + m, first + m * c
            second += inertia + m * (c @ c * np.eye(3) - np.outer(c, c))
        com = first / mass
        about_com = second - mass * (com @ com * np.eye(3) - np.outer(com, com))
        body = model.body(cp.face_labels[face])
        assert float(body.mass[0]) * 1e3 == pytest.approx(mass, rel=0.01)
        assert np.linalg.norm(body.ipos * 1e3 - com) < 0.05  # mm
        # MuJoCo's principal moments against the meshes' (the tessellation's), a few %
        mine = np.sort(np.linalg.eigvalsh(about_com)) * 1e-9
        assert np.sort(body.inertia) == pytest.approx(mine, rel=0.03)


def test_panels_show_their_printed_meshes_and_collide_with_convex_hulls():
    model, _ = load_model(_xml("crawler"))
    visual = model.geom_group == 1
    collide = (model.geom_contype | model.geom_conaffinity) > 0
    assert visual.any() and not (visual & collide).any()  # the real meshes only show
    hulls = collide & (model.geom_type == mujoco.mjtGeom.mjGEOM_MESH)
    assert hulls.sum() == 2 * 5  # two convex halves a panel
    body = model.body("body").id
    vis = [g for g in np.flatnonzero(visual) if model.geom_bodyid[g] == body]
    verts = sum(int(model.mesh_vertnum[model.geom_dataid[g]]) for g in vis)
    hull = [g for g in np.flatnonzero(hulls) if model.geom_bodyid[g] == body]
    assert verts > 10 * sum(int(model.mesh_vertnum[model.geom_dataid[g]]) for g in hull)


def test_the_flat_sheet_settles_on_the_ground_within_its_hinge_ranges():
    model, data = load_model(_xml("miura"))
    hinge = np.flatnonzero(model.jnt_type == mujoco.mjtJoint.mjJNT_HINGE)
    adr, lo, hi = model.jnt_qposadr[hinge], *model.jnt_range[hinge].T
    worst = 0.0
    while data.time < 1.0:
        mujoco.mj_step(model, data)
        q = data.qpos[adr]
        worst = max(worst, float(np.max(np.maximum(lo - q, q - hi))))
    assert worst <= 1e-3  # rad, never past a range
    assert np.abs(data.qvel).max() < 1e-2  # at rest
    assert data.xpos[1:, 2].max() < 2.2e-3  # lying on the ground (h = 2.2 mm)


@pytest.fixture(scope="module")
def fig5_models():
    from origami_cad.simulation import SimulationParams, simulate
    from origami_cad.strings import load_route, simulate_dcqc

    design = load_design(MIURA[0])
    route = load_route(MIURA[1][0], design.pattern)
    params = SimulationParams.from_fabrication(route.fabrication)
    dcqc = simulate_dcqc(design, route, **params.dcqc_stiffness())
    sim = simulate(design.pattern, route, params, design=design)
    return design, sim, dcqc


def _fit(model, data, cp, table) -> float:
    angles = crease_angles(model, data, cp.n_edges)
    mask = np.isfinite(angles) & cp.edge_mask("M", "V")
    return fold_ratio_fit(np.nan_to_num(angles), table, mask)


def test_fig5_the_ring_tsa_folds_the_miura_like_both_string_models(fig5_models):
    design, sim, dcqc = fig5_models
    cp = design.pattern
    table = rigid_table(design)
    model, data = load_model(to_mjcf(*MIURA, gravity=0, ground=False))
    acts = tsa_actuators(model)
    set_fold(model, data, table, 0.02)  # off the flat bifurcation, as the simulator starts
    top = float(sim.turns[-1])
    gaps, turns = [], 0.0
    for target in np.linspace(top / 5, top, 5):  # five take-ups, each approached slowly
        while turns < target or data.time < 0.6 * target / top * 5 + 0.3 * len(gaps):
            turns = min(target, turns + 8.0 * model.opt.timestep)
            tsa_controls(model, data, [turns], acts)
            if int(data.time / model.opt.timestep) % 10 == 0:
                hold_mean_pose(model, data, cp)
            mujoco.mj_step(model, data)
        p = _fit(model, data, cp, table)
        gaps.append(
            (
                p,
                float(np.interp(turns, sim.turns, sim.p)),
                float(np.interp(turns, dcqc.turns, dcqc.p)),
            )
        )
    gaps = np.array(gaps)
    print("Fig. 5 p (MuJoCo, bar-and-hinge, DCQC):", gaps.round(3).tolist())
    assert gaps[-1, 0] > 0.45  # it does fold
    assert np.abs(gaps[:, 0] - gaps[:, 1]).max() < 0.05
    assert np.abs(gaps[:, 0] - gaps[:, 2]).max() < 0.05


def _arm_p_e(tg, route):
    from origami_cad.design import load_task, reachable_fold_angle

    task, _ = load_task(EX / "arm_task.toml")
    beta = np.radians(np.asarray(tg.shape_angles, dtype=float))[None, :]
    limit = task.crease_limit(route.fabrication.bias if task.fold_limit is None else None)
    return float(reachable_fold_angle(beta, limit)[0] / math.pi)


def test_the_arm_tip_at_p_e_is_on_the_designed_path():
    from origami_cad.design.arm_route import arm_chain_path
    from origami_cad.kinematics.chain import chain_points

    design = load_design(ARM[0])
    cp, tg = design.pattern, design.tg
    src = load_mjcf_source(*ARM)
    p_e = _arm_p_e(tg, src.routes[0])
    table = rigid_table(design)
    model, data = load_model(to_mjcf(src, gravity=0, ground=False))
    acts = tsa_actuators(model)
    set_fold(model, data, table, 0.05)  # off the flat sheet, strings tied taut
    tie_strings(model, data)
    turns, p = 0.0, 0.05
    while p < p_e and turns < 38.0:
        turns += 10.0 * model.opt.timestep
        tsa_controls(model, data, [turns], acts)
        mujoco.mj_step(model, data)
        if int(data.time / model.opt.timestep) % 20 == 0:
            p = _fit(model, data, cp, table)
    for _ in range(200):  # hold and settle
        tsa_controls(model, data, [turns], acts)
        mujoco.mj_step(model, data)
    p = _fit(model, data, cp, table)
    tip = arm_chain_path(tg, vertex_coords(model, data, cp)[None], np.array([p]))[0, -1]
    beta = np.radians(np.asarray(tg.shape_angles, dtype=float))[None, :]
    path = chain_points(
        np.linspace(0.0, p_e * math.pi, 400),
        tg.lengths,
        beta,
        tg.entry_flag,
        tg.hypar_base,
        tg.start,
    )[0][:, -1]
    gap = float(np.min(np.linalg.norm(path - tip, axis=1)))
    at_p = chain_points(
        np.array([p * math.pi]), tg.lengths, beta, tg.entry_flag, tg.hypar_base, tg.start
    )[0][0, -1]
    print(
        f"arm in MuJoCo: p = {p:.3f} (p_e {p_e:.3f}) after {turns:.1f} turns; tip {gap:.2f} "
        f"mm from the designed path, {np.linalg.norm(tip - at_p):.2f} mm from its point at p"
    )
    assert abs(p - p_e) < 0.02
    assert gap < 5.0


def test_the_crawler_moves_forward_under_its_gait():
    robot = load_robot(CRAWLER[0])
    model, data = load_model(robot_mjcf(robot, timestep=1e-3))
    body = model.body(robot.body).id
    play_gait(model, data, robot, 3.0)  # stand up on the strings
    x0 = data.xipos[body].copy()  # the body panel's centre of mass
    play_gait(model, data, robot, float(robot.gait_t[-1]), start=3.0)
    dx = (data.xipos[body] - x0) * 1e3
    print(f"crawler in MuJoCo: {dx[0]:.1f} mm forward, {dx[1]:.1f} mm sideways per cycle")
    # with Coulomb's cone and stiff friction the feet stick (3 mm a cycle without:
    # docs/mujoco.md); the quasi-static crawl makes 36.6 mm
    assert dx[0] > 20.0 and abs(dx[1]) < 5.0


# --------------------------------------------------------------------------- bad input


def test_a_hole_off_its_named_panel_is_refused_by_name():
    src = load_mjcf_source(*MIURA)
    spec = src.routes[0]
    string = spec.strings[0]
    moved = dataclasses.replace(string, faces=(string.faces[1], *string.faces[1:]))
    bad = dataclasses.replace(spec, strings=(moved, *spec.strings[1:]))
    with pytest.raises(MjcfError, match=r"string 1: hole c1r1s5 .* not on its panel c1r1s4"):
        to_mjcf(MIURA[0], [bad])


def test_a_robot_file_is_refused_by_the_design_export_and_read_by_the_command(tmp_path):
    with pytest.raises(MjcfError, match=r"crawler.toml: a robot file: .*robot_mjcf"):
        to_mjcf(CRAWLER[0])
    out = tmp_path / "robot.xml"
    assert main(["mjcf", str(CRAWLER[0]), "-o", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == robot_mjcf(CRAWLER[0])
    with pytest.raises(MjcfError, match="names its own routes"):
        to_mjcf(robot_mjcf_source(CRAWLER[0]), MIURA[1])
    with pytest.raises(MjcfError, match="a robot file names its own routes"):
        mjcf_source(CRAWLER[0], MIURA[1])


def test_a_crease_on_the_border_is_refused_by_name():
    square = [[0, 0], [10, 0], [10, 10], [0, 10], [5, 0], [5, 10]]
    edges = [[0, 4], [4, 1], [1, 2], [2, 5], [5, 3], [3, 0], [4, 5]]
    cp = CreasePattern(square, edges, "MBBBBBV")  # edge 0 is a mountain on the border
    with pytest.raises(MjcfError, match=r"crease 0 .* not between two panels"):
        to_mjcf(cp)


def test_a_tsa_model_without_an_mjcf_construction_is_refused_by_name():
    @dataclasses.dataclass(frozen=True)
    class CompliantTSA:  # a TSA with string compliance in its law (not ring/onboard)
        model: str = "compliant"

    src = load_mjcf_source(*MIURA)
    bad = dataclasses.replace(src.routes[0], tsa=CompliantTSA())
    with pytest.raises(MjcfError, match="TSA model 'compliant' has no MJCF construction"):
        to_mjcf(MIURA[0], [bad])


def test_the_cli_writes_a_model_mujoco_loads_and_refuses_bad_input_without_a_file(tmp_path, capsys):
    out = tmp_path / "model.xml"
    assert main(["mjcf", str(MIURA[0]), str(MIURA[1][0]), "-o", str(out)]) == 0
    assert mujoco.MjModel.from_xml_path(str(out)).ntendon == 4
    bad = tmp_path / "bad.xml"
    code = main(["mjcf", str(MIURA[0]), str(ARM[1][0]), "-o", str(bad)])
    assert code == 2 and not bad.exists() and not list(tmp_path.glob("*.tmp*"))
    assert "error:" in capsys.readouterr().err


# --------------------------------------------------------------------------- pictures, example


def test_a_frame_of_the_crawler_mid_stride_renders_off_screen(tmp_path):
    import imageio.v3 as iio

    try:
        path = render_gait_frame(CRAWLER[0], tmp_path / "frame.png", at=11.0)
    except MjcfError as exc:
        pytest.skip(str(exc))
    image = iio.imread(path)
    assert image.shape == (480, 640, 3) and image.std() > 5  # not a blank frame


def test_the_controller_example_runs_closed_loop_and_plots(tmp_path):
    run = subprocess.run(
        [sys.executable, str(EX / "mujoco_crawler.py"), "--seconds", "3", "-o", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "trajectory.png").stat().st_size > 10_000
    assert "mm/s" in run.stdout


def test_turns_map_to_take_up_by_eq8():
    """The control is the string eq. 8 takes up: zero at the start, growing with the turns."""
    from origami_cad.strings.tsa import ring_length

    model, data = load_model(_xml("miura"))
    acts = tsa_actuators(model)
    tsa, guide, hole = acts.tsas[0], acts.guide[0], acts.hole[0]
    u = [float(tsa_controls(model, data, [t], acts)[0]) for t in (0.0, 0.4, 5.0)]
    assert u[0] == pytest.approx(0.0, abs=1e-12)
    d1, d2, ds = tsa.d1, tsa.d2, tsa.string_width
    x = float(np.linalg.norm(data.site_xpos[hole] - data.site_xpos[guide])) * 1e3
    expect = ring_length(2 * math.pi * 5.0, x, d1, d2, ds) - ring_length(0.0, x, d1, d2, ds)
    assert u[2] * 1e3 == pytest.approx(float(expect), rel=1e-9)
    assert 0 < u[1] < u[2]
