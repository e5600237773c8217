"""The domain logic that left the commands, called as a script calls it: no files."""

from __future__ import annotations

import math

import numpy as np
import pytest

from origami_cad.errors import FabricationError, StringsError
from origami_cad.fabrication import fabrication_params, theta_max
from origami_cad.pattern.design import load_design
from origami_cad.strings import load_route, simulate_dcqc
from origami_cad.strings.route import parse_route


@pytest.fixture(scope="module")
def miura(examples):
    return load_design(examples / "miura_6x4.toml")


def test_fabrication_params_from_a_fold_limit_meet_eq6():
    for degrees in (120.0, 146.6, 170.0):
        params = fabrication_params(theta_max=degrees, height=3.0)
        got = math.degrees(theta_max(params.bias, params.height, params.thickness))
        assert got == pytest.approx(degrees, abs=1e-6) and params.height == 3.0
    ratio = fabrication_params(p_max=0.7)
    assert theta_max(ratio.bias, ratio.height, ratio.thickness) == pytest.approx(0.7 * math.pi)
    with pytest.raises(FabricationError, match="only one"):
        fabrication_params(bias=2.0, theta_max=120.0)


def test_a_route_parsed_from_text_is_the_file_read(examples, miura):
    text = (examples / "miura_route.toml").read_text()
    assert parse_route(text, miura.pattern) == load_route(
        examples / "miura_route.toml", miura.pattern
    )
    with pytest.raises(StringsError, match=r"^mine\.toml: "):
        parse_route(text.replace("[route]", "[rout]"), miura.pattern, "mine.toml")


def test_fold_by_strings_is_the_dcqc_model_and_holds_the_panel_asked(examples, miura):
    from origami_cad.simulation import SimulationParams
    from origami_cad.simulation.string_models import fold_by_strings

    spec = load_route(examples / "miura_route.toml", miura.pattern)
    direct = simulate_dcqc(miura, spec, **SimulationParams.for_route(spec).dcqc_stiffness())
    folded = fold_by_strings(miura, spec, "dcqc")
    assert np.allclose(folded.p, direct.p) and np.allclose(folded.turns, direct.turns)
    with pytest.raises(StringsError, match="no panel labelled 'nope'"):
        fold_by_strings(miura, spec, "dcqc", fixed_panel="nope")
    with pytest.raises(StringsError, match="model must be one of dcqc, simulation"):
        fold_by_strings(miura, spec, "rigid")


# ---------------------------------------------------------------- the arm's strings and scene


@pytest.fixture(scope="module")
def arm(examples):
    """The example arm as a script has it: its task, design (as design-arm's record) and
    route, and its strings' folding (DCQC)."""
    from origami_cad.design import ArmDesign, load_task
    from origami_cad.simulation.string_models import fold_by_strings

    task, _ = load_task(examples / "arm_task.toml")
    design = load_design(examples / "arm_design.toml")
    tg = design.tg
    record = ArmDesign(
        tuple(tg.lengths), tuple(tg.shape_angles), int(tg.entry_flag), math.nan, None,
        np.empty((0, 2)), run=0, generations=0, history=(), bias=3.0,
    )  # fmt: skip
    spec = load_route(examples / "arm_route.toml", design.pattern)
    return task, design, record, spec, fold_by_strings(design, spec, "dcqc")


def test_choose_arm_tsa_folds_the_arm_over_its_range_and_writes_nothing(arm, tmp_path, monkeypatch):
    from origami_cad.design.arm_route import ARM_TSA_LENGTHS, choose_arm_tsa
    from origami_cad.design.arm_scene import designed_arm_path
    from origami_cad.strings.route import parse_route

    task, design, record, _, _ = arm
    monkeypatch.chdir(tmp_path)
    chosen = choose_arm_tsa(record, task, header="# mine\n")
    assert not list(tmp_path.iterdir())  # nothing written
    assert chosen.error is None and chosen.tsa_length in ARM_TSA_LENGTHS
    assert chosen.text.startswith("# mine\n")
    p_e, _ = designed_arm_path(task, record.tg(task, task.unit_width or 36.0), 3.0)
    assert float(chosen.result.p[-1]) == pytest.approx(p_e, abs=2e-3)
    assert str(chosen.result.stop) not in ("helix_limit", "turn_limit")
    # the text is the route it folded: read back, the same strings fold the same way
    again = simulate_dcqc(design, parse_route(chosen.text, design.pattern))
    assert np.allclose(again.p, chosen.result.p) and np.allclose(again.turns, chosen.result.turns)
    # strands too short to twist that far: the longest is kept, stopped by its twist
    short = choose_arm_tsa(record, task, lengths=(8.0, 10.0))
    assert short.tsa_length == 10.0 and str(short.result.stop) in ("helix_limit", "turn_limit")
    assert short.result.p[-1] < p_e - 1e-3


def test_arm_scene_metrics_measure_the_tip_against_the_design(arm):
    from origami_cad.design.arm_route import arm_chain_path
    from origami_cad.design.arm_scene import arm_scene_metrics, designed_arm_path
    from origami_cad.kinematics import tessellation_vertices

    task, design, _, spec, folded = arm
    tg = design.tg
    p_e, designed = designed_arm_path(task, tg, spec.fabrication.bias)
    assert designed.shape == (task.samples, len(tg.lengths) + 1, 2)
    assert np.allclose(designed[0, 0], tg.start)  # the chain starts at T_s
    # the rigid folding at the strings' fold ratios: the designed arm itself
    ratios = np.asarray(folded.p, dtype=float)
    states = tessellation_vertices(tg, ratios).reshape(len(ratios), -1, 3)
    chain = arm_chain_path(tg, states, ratios)
    m = arm_scene_metrics(task, tg, folded, chain, designed, p_e)
    assert m["max_distance_from_designed_tip_mm"] == pytest.approx(0.0, abs=1e-6)
    d_end = float(np.linalg.norm(chain[-1, -1] - task.points[-1]))
    assert m["final_distance_from_P_end_mm"] == pytest.approx(d_end)
    assert m["closest_distance_from_P_end_mm"] <= d_end
    assert m["tsa_turns"] == pytest.approx(float(folded.turns[-1]))
    assert m["states_touching_prohibited_area"] == 0
    assert m["designed_fold_ratio_end"] == p_e == pytest.approx(float(ratios[-1]), abs=2e-3)
    # a chain 5 mm off the design is 5 mm off, and into the prohibited area it touches it
    shifted = arm_scene_metrics(task, tg, folded, chain + np.array([5.0, 0.0]), designed, p_e)
    assert shifted["max_distance_from_designed_tip_mm"] == pytest.approx(5.0)
    inside = np.asarray(task.prohibited[0].representative_point().coords[0])
    into = chain.copy()
    into[-1, -1] = inside
    assert (
        arm_scene_metrics(task, tg, folded, into, designed, p_e)["states_touching_prohibited_area"]
        == 1
    )


# ---------------------------------------------------------------- sequences from routes


def test_route_tsa_gives_a_sequence_drive_reads(arm, tmp_path):
    from origami_cad.drive.from_model import fold_curve, model_sequence, route_tsa, turns_at
    from origami_cad.drive.sequence import dump_sequence, load_sequence
    from origami_cad.errors import DriveError

    _, design, _, spec, folded = arm
    top = float(np.nanmax(folded.p))
    entry, figures = route_tsa(design.pattern, spec.tsa, folded, [0.0, 0.3], servo=3, name="arm")
    mapping = entry["mapping"]
    assert (entry["id"], entry["name"]) == (3, "arm") and 0.3 in mapping[:, 0]
    assert np.all(np.diff(mapping[:, 0]) > 0) and np.all(np.diff(mapping[:, 1]) >= 0)
    p, turns = fold_curve(folded.p, folded.turns)
    assert np.allclose(figures["turns_at"], turns_at(p, turns, [0.0, 0.3]))
    assert figures["p_range"][1] == pytest.approx(top)
    made = model_sequence([entry], [(0.0, (0.0,)), (10.0, (0.3,))], rate=20.0)
    assert made.ids == [3] and made.keyframes[-1].values == (0.3,)
    text = dump_sequence(made, layout="model")
    path = tmp_path / "seq.toml"
    path.write_text(text)
    seq = load_sequence(path)  # what drive reads
    assert seq.ids == [3] and seq.rate == 20.0 and seq.keyframes[-1].values == (0.3,)
    with pytest.raises(DriveError, match=r"outside what its strings reach"):
        route_tsa(design.pattern, spec.tsa, folded, [top + 0.1], servo=1, name="arm")


# ---------------------------------------------------------------- the robot's mass budget


def test_robot_mass_budget_adds_the_sheet_the_printed_and_the_bought_parts(examples):
    from origami_cad.parts.robot import robot_mass_budget

    from origami_cad.crawler.robot import load_robot

    robot = load_robot(examples / "crawler" / "crawler.toml")
    bought = [(m.name, m.grams) for m in robot.masses]
    report = {
        "infills": {"kind": "structure", "mass_g": 80.0},  # the sheet's: in sheet_g already
        "tsa_module_a": {"kind": "tsa-module", "mass_g": 11.5},
        "blocker_a": {"kind": "blocker", "mass_g": 1.25},
    }
    budget = robot_mass_budget(200.0, report, bought)
    assert budget.printed_parts_g == 12.75
    assert budget.total_g == pytest.approx(212.75 + sum(m.grams for m in robot.masses))
    data = budget.to_dict(reference_g=361.45)
    assert data["bought_parts_g"] == {m.name: m.grams for m in robot.masses}
    assert data["difference_percent"] == pytest.approx(100 * (budget.total_g / 361.45 - 1))
    assert "paper_g" not in budget.to_dict()
    twice = robot_mass_budget(200.0, {}, [*bought, bought[0]])  # one name twice: added up
    assert twice.bought_parts_g[bought[0][0]] == 2 * bought[0][1]
    assert twice.total_g == pytest.approx(budget.total_g - 12.75 + bought[0][1])


# ---------------------------------------------------------------- ranking


def test_rank_designs_puts_the_largest_fold_range_of_the_tied_first_and_drops_infeasible():
    from types import SimpleNamespace as D

    from origami_cad.design import rank_designs

    runs = [
        D(fitness=math.inf * -1, fold_ratio_end=0.9, run=0),
        D(fitness=50.0, fold_ratio_end=0.9, run=1),
        D(fitness=math.nan, fold_ratio_end=0.9, run=2),
        D(fitness=50.0 - 1e-4, fold_ratio_end=0.2, run=3),
        D(fitness=55.0, fold_ratio_end=0.1, run=4),
        D(fitness=55.0 - 1e-4, fold_ratio_end=0.3, run=5),
    ]
    assert [d.run for d in rank_designs(runs)] == [5, 4, 1, 3]
    assert rank_designs([r for r in runs if not math.isfinite(r.fitness)]) == []
    assert rank_designs([]) == []
