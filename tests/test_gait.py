"""The crawler's gait found by search: design-gait and the chain after it.

The searches here are tiny (one friction, two candidates, two steps between keyframes):
they check that the search's outputs are what every chained step accepts, not how far
the designed gait walks (``make bench`` runs the full search; docs/crawler.md).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import CRAWLER, copy_crawler, gait_file_text

from origami_cad.cli import main
from origami_cad.commands import execute
from origami_cad.crawler.gait import (
    DIMENSION,
    P_FLOOR,
    GaitSettings,
    GaitTerms,
    cma_strategy,
    combine_terms,
    decode_gait,
    design_gait,
    encode_gait,
    hard_hits,
    settings_score,
)
from origami_cad.crawler.robot import load_gait, load_robot, with_gait
from origami_cad.crawler.walk import (
    SERVO_SPEED_RPM,
    check_servo_speed,
    turn_rates,
)
from origami_cad.design.search import UnitBox
from origami_cad.drive.sequence import load_sequence
from origami_cad.errors import SimulationError

ROBOT = CRAWLER / "crawler.toml"


def test_every_genome_decodes_to_a_gait_within_the_limits_that_drive_and_crawl_accept(
    robot, tmp_path
):
    """Random genomes (and the bounds' corners): keyframes within the floor and the
    blockers, over one cycle, front legs first; written as gait.toml, read back by
    crawl's reader and drive's, and slow enough for the servo."""
    rng = np.random.default_rng(7)
    genomes = [*rng.uniform(0, 1, (12, DIMENSION)), np.zeros(DIMENSION), np.ones(DIMENSION)]
    for k, x in enumerate(genomes):
        t, p = decode_gait(robot, x, cycle=32.0)
        assert t[0] == 0 and t[-1] == 32.0 and np.all(np.diff(t) > 0)
        assert p.min() >= P_FLOOR - 1e-9 and p.max() <= robot.blocker_angle / 180.0
        np.testing.assert_array_equal(p[0], p[-1])  # a cycle ends where it starts
        assert np.all(p[1, :2] > p[0, :2]) and np.all(p[1, 2:] == p[0, 2:])  # front first
        walker = with_gait(robot, t, p)
        check_servo_speed(walker)
        path = tmp_path / f"gait_{k}.toml"
        path.write_text(gait_file_text(walker), encoding="utf-8")
        back = load_gait(path, robot)
        np.testing.assert_allclose(back.gait_p, p, atol=1e-12)
        np.testing.assert_allclose(back.gait_t, t, atol=1e-12)
        assert len(load_sequence(path).keyframes) == len(t)


def test_the_hand_gaits_genome_is_its_strokes(robot):
    """encode_gait: the robot file's crawl strokes (30 -> 55 deg, front legs first), not
    its rest at 20 deg before and after them; a decoded genome encodes back to itself."""
    _, p = decode_gait(robot, encode_gait(robot))
    hand = robot.gait_p
    assert abs(180 * p.min() - 180 * hand[1].min()) < 1.0
    assert abs(180 * p.max() - 180 * hand.max()) < 1.0
    x = np.array([0.2, 0.7, 0.6, 0.3, 0.5, 0.5, 0.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(encode_gait(with_gait(robot, *decode_gait(robot, x))), x, atol=1e-3)


def test_the_search_never_returns_a_gait_worse_than_the_robots_own(robot):
    """The best scores at least the hand gait's objective, however the budget and the
    mix: at 0.8 the hand gait's legs jam, which is scored, not a reason to discard it."""
    settings = GaitSettings(
        frictions=(0.6, 0.8), mix="worst", popsize=2, generations=1, steps=2, sigma0=0.3
    )
    design = design_gait(robot, settings)
    hand = design.candidates[0]
    assert hand.hand and hand.terms == design.hand and hand.score == design.hand_score
    np.testing.assert_array_equal(hand.ratios, robot.gait_p)  # the file's own keyframes
    assert not hard_hits(design.best)
    assert design.best.score >= design.hand_score
    assert design.best.score == max(c.score for c in design.candidates if not hard_hits(c))
    assert min(design.history[0]) >= design.hand_score


def _terms(scores, frictions=(0.4, 0.6, 0.8)):
    return [GaitTerms(mu, s, 0, 0, 0, 0, 0, (), s) for mu, s in zip(frictions, scores, strict=True)]


def test_the_shortfall_mix_ranks_candidates_by_their_worst_shortfall():
    """Even (60 mm everywhere: 3 mm short of 63 at 0.6) against lopsided (46 / 70 / 46:
    1 mm over every target): the mean and the worst prefer the even one, the shortfall
    mix the one that meets the issue's 45 / 63 / 45, and the targets given decide."""
    even, lopsided = _terms([60.0, 60.0, 60.0]), _terms([46.0, 70.0, 46.0])
    for mix in ("mean", "worst"):
        assert combine_terms(even, mix) > combine_terms(lopsided, mix)
    shortfall = GaitSettings(mix="shortfall")
    assert shortfall.target_values() == (45.0, 63.0, 45.0)
    assert settings_score(even, shortfall) == -3.0
    assert settings_score(lopsided, shortfall) == 1.0
    easy = GaitSettings(mix="shortfall", targets=(50.0, 50.0, 50.0))
    assert settings_score(even, easy) == 10.0 > settings_score(lopsided, easy) == -4.0
    order = GaitSettings(mix="shortfall", frictions=(0.8, 0.6, 0.4))  # targets by friction
    assert settings_score(_terms([46.0, 70.0, 40.0], (0.8, 0.6, 0.4)), order) == -5.0


def test_targets_must_match_the_frictions():
    with pytest.raises(ValueError, match="2 targets for 3 frictions"):
        GaitSettings(targets=(45.0, 63.0))
    with pytest.raises(ValueError, match=r"no target at friction 0\.5"):
        GaitSettings(mix="shortfall", frictions=(0.5,))
    with pytest.raises(ValueError, match="one target per friction"):
        combine_terms(_terms([50.0, 50.0, 50.0]), "shortfall")


def test_a_shortfall_search_scores_every_candidate_by_its_shortfall(robot):
    settings = GaitSettings(
        frictions=(0.6,), mix="shortfall", targets=(63.0,), popsize=2, generations=1, steps=2
    )
    design = design_gait(robot, settings)
    assert len(design.candidates) == 3
    for c in design.candidates:
        assert c.score == pytest.approx(c.terms[0].score - 63.0, abs=1e-3)


@pytest.mark.parametrize("given", [["--targets", "45", "63"], ["--frictions", "0.5", "--mix",
                                   "shortfall"]])  # fmt: skip
def test_design_gait_refuses_targets_that_do_not_match_the_frictions(tmp_path, capsys, given):
    out = tmp_path / "out"
    rc = main(["design-gait", str(ROBOT), "-o", str(out), *given])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "--targets" in err[0] and "friction" in err[0]
    assert not out.exists()


def test_a_gait_past_a_blocker_or_the_servo_speed_is_refused_by_name(robot, tmp_path):
    path = tmp_path / "gait.toml"
    path.write_text(
        "[[keyframe]]\nt = 0\np = [0.2, 0.2, 0.2, 0.2]\n"
        "[[keyframe]]\nt = 10\np = [0.34, 0.2, 0.2, 0.2]\n",
        encoding="utf-8",
    )
    named = r"gait.toml: keyframe #2 \(t = 10 s\): p = 0.34 folds leg .*blocker \(60 deg"
    with pytest.raises(SimulationError, match=named):
        load_gait(path, robot)
    fast = with_gait(robot, [0.0, 0.5, 1.0], [[0.12] * 4, [0.33] * 4, [0.12] * 4])
    rate = float(turn_rates(fast).max()) * 60
    assert rate > SERVO_SPEED_RPM
    refused = r"\(servo \d\) must twist at .* over its servo's 103 rev/min"
    with pytest.raises(SimulationError, match=refused):
        check_servo_speed(fast)
    path.write_text(
        "[[tsa]]\nid = 9\n[[keyframe]]\nt = 0\np = [0.2, 0.2, 0.2, 0.2]\n"
        "[[keyframe]]\nt = 10\np = [0.2, 0.2, 0.2, 0.2]\n",
        encoding="utf-8",
    )
    with pytest.raises(SimulationError, match=r"ids \[9\] are not the robot's servos"):
        load_gait(path, robot)


def test_crawl_refuses_a_too_fast_gait_in_one_line(tmp_path, capsys):
    gait = tmp_path / "fast.toml"
    gait.write_text(
        "[[keyframe]]\nt = 0\np = [0.12, 0.12, 0.12, 0.12]\n"
        "[[keyframe]]\nt = 0.5\np = [0.33, 0.33, 0.33, 0.33]\n",
        encoding="utf-8",
    )
    rc = main(["crawl", str(ROBOT), "-o", str(tmp_path / "out"), "--gait", str(gait)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "rev/min" in err[0] and "fast.toml" in err[0]
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("broken", ["legs", "routes"])
def test_a_robot_without_legs_or_routes_gets_one_line(tmp_path, capsys, broken):
    robot = copy_crawler(tmp_path)
    text = robot.read_text(encoding="utf-8")
    if broken == "legs":
        head, _, rest = text.partition("[[leg]]")
        text = head + "[[mass]]" + rest.split("[[mass]]", 1)[1]
    else:
        (tmp_path / "route_rl.toml").unlink()
    robot.write_text(text, encoding="utf-8")
    rc = main(["design-gait", str(robot), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1, err
    assert ("[[leg]]" in err[0]) if broken == "legs" else ("route_rl.toml" in err[0])
    assert not (tmp_path / "out").exists()


def test_design_gait_to_crawl_to_drive(tmp_path):
    """The chain: design-gait's gait.toml walks in crawl --gait exactly as the search
    scored it, and drive --dry-run runs it on emulated servos."""
    out = tmp_path / "gait"
    done = execute(
        "design-gait", str(ROBOT), str(out), frictions=[0.6], popsize=2, generations=1,
        steps=2, gif_frames=3,
    )  # fmt: skip
    names = {p.name for p in out.iterdir()}
    assert names == {f.name for f in done.files}
    design = done.result  # the library's data: every candidate, the best of the clean ones
    assert len(design.candidates) == 1 + 2  # the hand gait, then the population
    clean = [c for c in design.candidates if not hard_hits(c)]
    assert design.best.score == max(c.score for c in clean or design.candidates)
    assert design.history[0][-1] == max(c.score for c in design.candidates)
    assert [t.friction for t in design.hand] == [0.6]
    # reproducible: the seed gives the same population again (cma's seed 0 is the clock)
    settings = design.settings
    start = design.candidates[0].genome
    again = UnitBox(DIMENSION)(np.asarray(cma_strategy(0, settings, start).ask()))
    np.testing.assert_array_equal(again, [c.genome for c in design.candidates[1:]])
    report = json.loads((out / "results.json").read_text())
    assert len(report["candidates"]) == 3 and report["what_limits_the_stride"]["leg_length_mm"]
    assert report["targets_mm"] is None  # the mean mix has none
    best = report["best"]["per_friction"][0]
    crawl = execute(
        "crawl", str(ROBOT), str(tmp_path / "crawl"), gait=str(out / "gait.toml"),
        cycles=1, steps=2, friction=0.6, gif_frames=2,
    )  # fmt: skip
    forward = float(crawl.result.displacement_per_cycle()[0])
    assert forward == pytest.approx(best["forward_mm_per_cycle"], rel=1e-6, abs=1e-6)
    assert (
        main(["drive", str(out / "gait.toml"), "--dry-run", "--log", str(tmp_path / "l.csv")]) == 0
    )
    # sequence takes the robot and its designed gait: the same keyframes, drive runs them
    seq = tmp_path / "seq.toml"
    assert main(["sequence", str(ROBOT), str(out / "gait.toml"), "-o", str(seq)]) == 0
    written, designed = load_sequence(seq), load_sequence(out / "gait.toml")
    assert written.keyframes == designed.keyframes  # times, kinds (p) and fold ratios
    assert "origami-cad sequence" in seq.read_text(encoding="utf-8")
    assert main(["drive", str(seq), "--dry-run", "--log", str(tmp_path / "s.csv")]) == 0


def test_sequence_of_a_robot_takes_its_gait_file_and_refuses_keyframes(tmp_path, capsys):
    """``sequence ROBOT.toml GAIT.toml``: the robot file's own gait written as a gait file
    gives back its keyframes; keyframes on the command line, or none for a pattern, are
    refused in one line."""
    gait = tmp_path / "hand.toml"
    robot = load_robot(ROBOT)
    gait.write_text(gait_file_text(robot), encoding="utf-8")
    seq = tmp_path / "seq.toml"
    assert main(["sequence", str(ROBOT), str(gait), "-o", str(seq), "--repeat", "2"]) == 0
    back = load_gait(seq, robot)
    np.testing.assert_allclose(back.gait_p, robot.gait_p)
    assert load_sequence(seq).repeat == 2
    capsys.readouterr()
    argv = ["sequence", str(ROBOT), str(gait), "-o", str(tmp_path / "no.toml")]
    for extra, said in ((["--keyframes", "0:0.1"], "--keyframes: not with a robot file"),
                        (["--ids", "1,2"], "--ids: not with a robot file"),
                        (["--model", "simulation"], "--model: not with a robot file")):  # fmt: skip
        assert main([*argv, *extra]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and said in err[0] and "crawler.toml" in err[0], err
    pattern = ["sequence", str(CRAWLER / "crawler.fold"), str(CRAWLER / "route_fl.toml")]
    assert main([*pattern, "-o", str(tmp_path / "no.toml")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--keyframes: required" in err[0], err
    assert not (tmp_path / "no.toml").exists()


def test_a_gait_too_fast_for_the_servo_is_never_walked_and_named(robot):
    """Servo speed is known from the keyframes: such a candidate is not simulated, it is
    scored below every walked one and names the limit (only the hand gait walks here)."""
    from origami_cad.crawler.gait import FAILED, GaitLimits

    slow = GaitLimits(servo_rpm=1.0)  # every stroke of a 32 s cycle needs more
    settings = GaitSettings(frictions=(0.6,), popsize=2, generations=1, steps=2, limits=slow)
    design = design_gait(robot, settings)
    for c in design.candidates[1:]:
        assert c.score < FAILED and "over the servo's 1 " in c.terms[0].hits[0] + " "
    assert design.hand[0].score > FAILED  # the hand gait was walked, past the limit
    assert design.candidates[0].hand and hard_hits(design.candidates[0])
