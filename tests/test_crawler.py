"""The crawler of the paper's Fig. 7: files, printing and walking in simulation."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest
from conftest import (
    CRAWLER,
    copy_crawler,
    gait_file_text,
    gif_motion,
    ink,
    make_crawler_script,
    panel_frames,
)

from origami_cad.cli import main
from origami_cad.crawler.robot import load_robot
from origami_cad.crawler.walk import (
    STUCK_DEG,
    gait_loads,
    gait_turns,
    leg_contraction,
    simulate_gait,
)
from origami_cad.drive.errors import StallError
from origami_cad.drive.sequence import load_sequence
from origami_cad.errors import SimulationError
from origami_cad.fabrication import FabricationParams, plan_panels
from origami_cad.pattern import read_pattern
from origami_cad.pattern.check import check_pattern

ROBOT = CRAWLER / "crawler.toml"


@pytest.fixture(scope="module")
def forward(robot):
    return simulate_gait(robot, cycles=1, steps=3)


def test_files_are_what_the_generator_writes(robot):
    from origami_cad.crawler.design import crawler_files

    files = crawler_files(make_crawler_script().DESIGN, envelope=None)  # the script's numbers
    cp = files.pattern
    on_disk = read_pattern(CRAWLER / "crawler.fold")
    assert np.allclose(cp.vertices, on_disk.vertices)
    assert cp.assignments.tolist() == on_disk.assignments.tolist()
    assert sorted(on_disk.face_labels) == ["body", "leg_fl", "leg_fr", "leg_rl", "leg_rr"]
    for name, text in files.texts().items():  # the routes and crawler.toml
        assert (CRAWLER / name).read_text(encoding="utf-8") == text
    assert set(files.texts()) == {"crawler.toml", *files.routes}
    assert files.routes["route_fl.toml"] == robot.legs[0].route  # the data, read back
    # the printed holes are the routed holes
    routed = {p for leg in robot.legs for s in leg.route.strings for p in s.points}
    assert routed == set(robot.holes)


def test_pattern_checks_and_size(robot):
    cp = robot.pattern
    assert [p for p in check_pattern(cp) if p.severity == "error"] == []
    x0, y0, x1, y1 = cp.bounds
    assert (x1 - x0, y1 - y0) == (360.0, 320.0)  # flat; the paper's robot is 340 x 320 standing
    assert len(robot.legs) == 4 and all(len(leg.route.strings) == 4 for leg in robot.legs)
    assert all(cp.assignments[leg.crease] == "M" for leg in robot.legs)
    assert robot.blockers == {leg.crease: 60.0 for leg in robot.legs}


def test_fabrication_prints_every_routed_hole(robot):
    plan = plan_panels(robot.pattern, FabricationParams(holes=robot.holes))
    assert len(plan.holes) == 32
    by_panel = plan.holes_by_label()
    assert {k: len(v) for k, v in by_panel.items()} == {
        "body": 16,
        "leg_fl": 4,
        "leg_fr": 4,
        "leg_rl": 4,
        "leg_rr": 4,
    }


def test_gait_turns_follow_the_string_model(robot):
    leg = robot.legs[0]
    c = leg_contraction(robot.pattern, leg, np.array([0.0, 0.1, 0.2, 0.3]))
    assert c[0] == pytest.approx(0.0, abs=1e-9)
    assert np.all(np.diff(c) > 0)  # folding down shortens the strings under the hinge
    turns = gait_turns(robot)
    assert turns.shape == (7, 4)
    # the front legs (fold 55 deg) need more twist than the standing legs (30 deg)
    assert turns[2, 0] > turns[1, 0] > turns[0, 0] > 0
    assert turns.max() * 2 * math.pi < leg.route.tsa.max_theta()


def test_one_cycle_crawls_forward_and_blockers_hold(robot, forward):
    (per,) = forward.displacement_per_cycle()
    assert per > 10.0  # mm, along +x, the heading the gait intends
    assert forward.blocked.max() <= 60.0 + 1.0  # blocker + the barrier's give
    assert forward.converged.all()
    assert forward.tensions.min() >= 0.0 and forward.torque.max() > 0.0
    # the robot is lifted on its legs while it walks
    assert forward.body[:, 2].max() > 50.0


def test_the_gait_played_backwards_crawls_backwards(robot):
    back = simulate_gait(robot, cycles=1, steps=3, reverse=True)
    (per,) = back.displacement_per_cycle()
    assert per < -10.0


def test_at_high_friction_the_legs_jam_and_the_notes_name_them(robot, forward):
    """docs/crawler.md, friction: the strings only pull, so a leg unfolds only if its foot
    slides outward; at friction 1 the feet grip, the legs stay folded and the stride
    collapses (the stride at friction 0.6 is the designed one, with no leg stuck)."""
    assert not [n for n in forward.notes if "stayed folded" in n]
    sticky = simulate_gait(robot, cycles=1, steps=3, friction=1.0)
    (per,) = sticky.displacement_per_cycle()
    assert per < 0.5 * forward.displacement_per_cycle()[0]
    stuck = [n for n in sticky.notes if "stayed folded" in n]
    assert [n.split(" stayed")[0] for n in stuck] == [
        f"{leg.name} (servo {leg.servo})" for leg in robot.legs
    ]
    assert stuck[2].startswith("rear left (servo 3) stayed folded at 60 deg")  # its blocker
    # the cycle ends with every leg still folded far past the 20 deg it is laid down at
    assert (sticky.fold[-1] > 180.0 * robot.gait_p[-1] + STUCK_DEG).all()
    # from the jam on the body stands still
    jam = int(np.argmax(sticky.fold[:, 2] > 59.0))
    assert np.ptp(sticky.body[jam + 2 :, 0]) < 1.0


def test_a_gait_past_the_blockers_is_refused(tmp_path):
    text = ROBOT.read_text(encoding="utf-8").replace("0.306, 0.306, 0.167", "0.4, 0.306, 0.167")
    copy_crawler(tmp_path, leave_out=("crawler.toml",))
    bad = tmp_path / "crawler.toml"
    bad.write_text(text, encoding="utf-8")
    with pytest.raises(SimulationError, match="past its blocker"):
        load_robot(bad)
    # a gait file names the keyframe and the leg (the third leg, at its fourth keyframe)
    from origami_cad.crawler.robot import with_gait

    robot = load_robot(ROBOT)
    p = np.array(robot.gait_p, copy=True)
    p[3, 2] = 0.35
    with pytest.raises(SimulationError) as err:
        with_gait(robot, robot.gait_t, p, where="gait.toml")
    t = robot.gait_t[3]
    assert str(err.value) == (
        f"gait.toml: keyframe #4 (t = {t:g} s): p = 0.35 folds leg "
        f"{robot.legs[2].name!r} past its blocker (60 deg = p 0.333)"
    )


def test_crawl_command(tmp_path, capsys):
    out = tmp_path / "crawl"
    assert main(["crawl", str(ROBOT), "-o", str(out), "--cycles", "1", "--steps", "2"]) == 0
    data = json.loads((out / "crawl.json").read_text())
    assert len(data["displacement_per_cycle_mm"]) == 1
    assert data["paper_mm_per_cycle"] == 63.0
    frames, moved = gif_motion(out / "crawl.gif")
    assert frames >= 3 and 0.005 < moved < 0.5  # the robot moves; the view stays put
    for name in ("crawl.png", "gait.png"):  # displacement over height; fold angle over twist
        covered, _ = ink(out / name)
        assert 0.02 < covered < 0.3, name  # curves, axes and labels: not blank, not black
        assert len(panel_frames(out / name)) == 2, name
    # the sequence says how it was made and carries each servo's simulated load
    text = (out / "gait_sequence.toml").read_text()
    assert f"origami-cad crawl {ROBOT} -o {out} --cycles 1 --steps 2" in text
    # the same gait, as TSA turns from the model, drives emulated servos to the end
    seq = load_sequence(out / "gait_sequence.toml")
    assert [t.name for t in seq.tsas] == ["front left", "front right", "rear left", "rear right"]
    robot = load_robot(ROBOT)
    assert list(seq.turns_at(11.0).values()) == pytest.approx(gait_turns(robot)[2], rel=1e-3)
    torque = np.array(data["torque_Nmm"])
    for k, tsa in enumerate(seq.tsas):
        assert tsa.load[:, 1].max() == pytest.approx(torque[:, k].max(), abs=1e-3)
    log = tmp_path / "drive.csv"
    args = ["drive", str(out / "gait_sequence.toml"), "--dry-run", "--speed", "32"]
    assert main([*args, "--log", str(log), "--baudrate", "1000000"]) == 0
    with log.open() as fh:
        rows = list(csv.DictReader(fh))
    assert {int(r["id"]) for r in rows} == {1, 2, 3, 4}
    front = [float(r["measured_turns"]) for r in rows if r["id"] == "1"]
    # the emulated front-left servo twists up to the crawl's 3.8 turns and back
    assert max(front) == pytest.approx(gait_turns(robot)[2, 0], abs=0.1)
    capsys.readouterr()
    assert main(["crawl", str(ROBOT), "-o", str(tmp_path / "x"), "--cycles", "0"]) == 2
    assert "cycles" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def _shared(a, b) -> float:
    """Volume two shapes share, mm^3 (a real boolean of the solids read back)."""
    from build123d import Compound

    common = Compound(a.solids()) & Compound(b.solids())
    return 0.0 if common is None else float(sum(s.volume for s in common.solids()))


@pytest.fixture(scope="module")
def printed(tmp_path_factory):
    from origami_cad.commands import execute

    out = tmp_path_factory.mktemp("robot") / "robot"
    return out, execute("robot", ROBOT, out, renders=False)


def test_robot_step_holds_named_parts_that_do_not_interpenetrate(printed):
    from build123d import import_step

    out, _ = printed
    from origami_cad.fabrication.assembly import solids_by_part

    back = import_step(out / "robot.step")
    solids = {c.label: c for c in back.children}
    expected = {"sheet", "driver_adapter"}
    expected |= {
        f"tsa_module_{k}" for k in ("front_left", "front_right", "rear_left", "rear_right")
    }
    expected |= {f"blocker_{k}" for k in ("front_left", "front_right", "rear_left", "rear_right")}
    assert set(solids) == expected
    # the sheet: a child per panel (its FOLD label) and the crease strips
    panels = {c.label for c in solids["sheet"].children}
    assert "creases" in panels and len(panels) == len(load_robot(ROBOT).pattern.faces) + 1
    # coloured: every solid, the sheet's in its material's colour
    for leaf in back.leaves:
        assert leaf.color is not None, leaf.label
    by_part = solids_by_part(solids["sheet"])
    assert tuple(by_part["shells"][0].color)[:3] == pytest.approx((0.839, 0.153, 0.157), abs=0.01)
    for leaf in solids["blocker_rear_left"].leaves:  # the blocker's solid, in orange
        assert tuple(leaf.color)[:3] == pytest.approx((1.0, 0.498, 0.055), abs=0.01)
    # read back, every pair of parts (not the sheet's own four) shares no volume with another
    from build123d import Compound

    names = sorted(n for n in solids if n != "sheet")
    sheet = Compound(by_part["shells"])
    for i, a in enumerate(names):
        assert _shared(solids[a], sheet) < 1e-3, a
        for b in names[i + 1 :]:
            assert _shared(solids[a], solids[b]) < 1e-3, (a, b)
    # the check sees an overlap: the same blocker pushed 1 mm into the sheet
    from build123d import Compound, Location

    pushed = Compound(solids["blocker_front_left"].solids()).moved(Location((0, 0, 1.0)))
    assert _shared(pushed, sheet) > 1.0
    # every module stands on its leg, above the sheet's top face (z = h = 2.2 mm)
    for k in ("front_left", "rear_right"):
        box = solids[f"tsa_module_{k}"].bounding_box()
        assert box.min.Z == pytest.approx(2.2, abs=1e-6)
        assert abs(box.center().X) > 90.0  # on the leg, beyond the hinge at |x| = 90
    # the blockers of the mountain leg creases sit under the sheet, across the hinge
    box = solids["blocker_front_left"].bounding_box()
    assert box.max.Z == pytest.approx(0.0, abs=1e-6) and box.min.X < 90.0 < box.max.X


def test_robot_mass_estimate_against_the_paper(printed):
    out, _ = printed
    data = json.loads((out / "robot.json").read_text())
    budget = data["mass_budget"]
    assert data["interpenetrating_mm3"] == {}
    parts = budget["sheet_g"] + budget["printed_parts_g"] + sum(budget["bought_parts_g"].values())
    assert budget["total_g"] == pytest.approx(parts)
    # as printed with the 3MF's paper-like settings (docs/crawler.md): within 5 % of 361.45 g
    assert abs(budget["total_g"] - 361.45) < 0.05 * 361.45
    assert budget["paper_g"] == 361.45
    assert budget["difference_percent"] == pytest.approx(100 * (budget["total_g"] / 361.45 - 1))
    assert budget["printed_g"] == pytest.approx(budget["sheet_g"] + budget["printed_parts_g"])
    from origami_cad.fabrication.slicer import PRINT_SETTINGS

    assert data["print_settings"] == PRINT_SETTINGS
    # printed with walls, skins and sparse infill: never more than solid, the shells less
    solids = data["solids"]
    for name, v in solids.items():  # the mesh's volume within 0.5 % of the B-rep's
        assert v["mass_g"] <= v["solid_mass_g"] * 1.005, (name, v["mass_g"], v["solid_mass_g"])
    assert solids["shells"]["mass_g"] < 0.9 * solids["shells"]["solid_mass_g"]
    sheet = ("infills", "midlayers", "shells", "creases")
    assert budget["sheet_g"] == pytest.approx(sum(solids[n]["mass_g"] for n in sheet))
    # a module's mount plate holds its servo, hub and guide, not the whole leg: it lies
    # within the leg's outer half, beyond the string holes 12 mm from the hinge (|x| = 90)
    for k in ("front_left", "front_right", "rear_left", "rear_right"):
        module = solids[f"tsa_module_{k}"]
        (x0, y0, _), (x1, y1, _) = module["bbox_mm"]
        assert min(abs(x0), abs(x1)) > 90.0 + 12.0 and (x1 - x0) * (y1 - y0) < 0.4 * 90 * 140
        assert module["solid_mass_g"] < 8.0  # g; with the whole leg face as its mount: 13.6 g
    for name in ("infills.stl", "shells.stl", "print.3mf", "assembly.step", "robot.step"):
        assert (out / name).stat().st_size > 0
    assert (out / "tsa_module_front_left.stl").read_bytes()[:5] != b"solid"  # binary STL


def test_a_jammed_leg_stalls_its_servo_by_name(tmp_path, robot):
    """The gait's sequence on emulated servos whose rear-left strings go taut at 2 turns."""
    from origami_cad.drive.dynamixel import DynamixelBus
    from origami_cad.drive.emulator import DynamixelEmulator
    from origami_cad.drive.errors import StallError
    from origami_cad.drive.sequence import run_sequence

    path = tmp_path / "gait.toml"
    path.write_text(gait_file_text(robot), encoding="utf-8")
    seq = load_sequence(path)
    ids = [leg.servo for leg in robot.legs]
    log = tmp_path / "stall.csv"
    with DynamixelEmulator(ids, time_scale=32.0, load_turns={3: 2.0}) as emu:
        with pytest.raises(StallError, match="servo 3"):
            with DynamixelBus(emu.port, ids=ids, profile_velocity=0, current_limit_ma=1000) as bus:
                run_sequence(seq, bus, log, time_scale=32.0)
        assert all(s.table[64] == 0 for s in emu.servos.values())  # torque off everywhere


def test_a_leg_over_its_torque_limit_stops_the_gait_by_name(tmp_path):
    copy_crawler(tmp_path, leave_out=("route_rl.toml",))
    text = (CRAWLER / "route_rl.toml").read_text(encoding="utf-8")
    assert "max_turns = 8.0\n" in text
    text = text.replace("max_turns = 8.0\n", "max_turns = 8.0\nmax_torque = 2.0   # N mm\n")
    (tmp_path / "route_rl.toml").write_text(text, encoding="utf-8")
    robot = load_robot(tmp_path / "crawler.toml")
    result = simulate_gait(robot, cycles=1, steps=2)
    assert str(result.stop) == "torque_limit"
    assert "rear left (servo 3)" in result.reason and "max_torque of 2 N mm" in result.reason
    assert result.torque[-1, 2] > 2.0 and (result.torque[:-1, 2] <= 2.0).all()
    assert len(result.t) < 13  # stopped before the end of the cycle


def test_bad_robot_files_are_refused_naming_file_and_key(tmp_path, capsys):
    copy_crawler(tmp_path, leave_out=("crawler.toml",))
    good = ROBOT.read_text(encoding="utf-8")
    cases = [
        (good.replace('panel = "leg_rl"', 'panel = "leg_xx"'), "[[leg]] #3: key 'panel'"),
        (good.replace("servo = 4", "servo = 3"), "servo IDs must differ"),
        (good.replace("friction = 0.6", "friction = -1"), "key 'friction'"),
        (good.replace("at = [153.0, 75.0]", "at = [0.0, 0.0]"), "is not on panel 'leg_fl'"),
        (good.replace('route = "route_fr.toml"', 'route = "nowhere.toml"'), "nowhere.toml"),
        (good + "\n[extra]\n", "unknown key 'extra'"),
    ]
    for k, (text, message) in enumerate(cases):
        path = tmp_path / f"bad{k}.toml"
        path.write_text(text, encoding="utf-8")
        out = tmp_path / f"out{k}"
        assert main(["robot", str(path), "-o", str(out), "--no-renders"]) == 2, message
        err = capsys.readouterr().err
        assert message in err and f"bad{k}.toml" in err and err.count("\n") == 1, err
        assert not out.exists()


def test_the_example_gait_is_the_crawl_jobs_sequence(tmp_path, robot, forward):
    """examples/crawler_gait.toml is what `crawl --cycles 1 --steps 6` writes (its header)."""
    example = CRAWLER.parent / "crawler_gait.toml"
    text = example.read_text(encoding="utf-8")
    assert (
        "origami-cad crawl examples/crawler/crawler.toml -o out/crawl --cycles 1 --steps 6" in text
    )
    seq = load_sequence(example)
    (tmp_path / "now.toml").write_text(gait_file_text(robot, result=forward))
    now = load_sequence(tmp_path / "now.toml")
    assert [k.values for k in seq.keyframes] == [k.values for k in now.keyframes]
    assert [k.t for k in seq.keyframes] == [k.t for k in now.keyframes]
    assert (seq.repeat, seq.rate, seq.current_limit) == (now.repeat, now.rate, now.current_limit)
    for a, b in zip(seq.tsas, now.tsas, strict=True):
        assert (a.dxl_id, a.name, a.tsa) == (b.dxl_id, b.name, b.tsa)
        assert np.array_equal(a.mapping, b.mapping)
    # the loads: 6 steps between keyframes there, 3 here; the same equilibria where they meet
    times, torque = gait_loads(robot, forward)
    for k, tsa in enumerate(seq.tsas):
        there = np.interp(times, tsa.load[:, 0], tsa.load[:, 1])
        assert np.abs(there - torque[:, k]).max() < 0.03 * torque[:, k].max() + 0.02


def test_gait_loads_fold_the_simulation_onto_one_cycle(robot, forward):
    times, torque = gait_loads(robot, forward)
    assert times[0] == 0.0 and times[-1] == robot.cycle and np.all(np.diff(times) > 0)
    assert torque.shape == (len(times), 4)
    assert np.array_equal(torque[0], torque[-1])  # closed: the cycle repeats
    assert torque.max(axis=0) == pytest.approx(forward.torque.max(axis=0))


def test_a_heavier_robot_stalls_a_servo_the_designed_one_does_not(tmp_path, robot, forward):
    """The emulator's load comes from the simulation. The same gait on the crawler
    with five times the hardware mass (servos, driver module) needs more torque; on servos
    1/40 as strong as an XL330 (13 N mm: ``--load-scale 40``) the designed robot's gait runs
    and the heavy one stalls a servo, named."""
    from origami_cad.commands import execute

    copy_crawler(tmp_path, leave_out=("crawler.toml",))
    text = ROBOT.read_text(encoding="utf-8")
    text = text.replace("grams = 109.71", "grams = 548.55").replace("grams = 18.0", "grams = 90.0")
    (tmp_path / "heavy.toml").write_text(text, encoding="utf-8")
    heavy = load_robot(tmp_path / "heavy.toml")
    walked = simulate_gait(heavy, cycles=1, steps=3)
    assert walked.mass_g > 2.5 * forward.mass_g
    light_peak = gait_loads(robot, forward)[1].max(axis=0)
    heavy_peak = gait_loads(heavy, walked)[1].max(axis=0)
    assert heavy_peak.sum() > 2.0 * light_peak.sum()  # N mm: the torque follows the weight
    runs = {}
    for key, spec, result in (("light", robot, forward), ("heavy", heavy, walked)):
        path = tmp_path / f"{key}.toml"
        path.write_text(gait_file_text(spec, result=result), encoding="utf-8")
        try:
            csv = tmp_path / f"{key}.csv"
            execute("drive", path, csv, dry_run=True, speed=16.0, load_scale=40.0)
            runs[key] = "ran"
        except StallError as exc:
            runs[key] = str(exc)
    assert runs["light"] == "ran"
    # the first servo whose load passes 1200 mA (5 mA idle + torque x 40 / (520 / 1500))
    times, torque = gait_loads(heavy, walked)
    over = 5.0 + 40.0 * torque * 1500.0 / 520.0 > 1200.0
    assert over.any() and not (gait_loads(robot, forward)[1] * 40.0 * 1500.0 / 520.0 > 1140).any()
    first = np.array([np.argmax(col) if col.any() else len(times) for col in over.T])
    assert np.sum(first == first.min()) == 1  # one servo crosses first (at the samples)
    leg = heavy.legs[int(np.argmin(first))]
    assert runs["heavy"].startswith(f"{leg.name}: servo {leg.servo}: current"), runs["heavy"]
