"""A hostile script against the library: every argument of the public calls (the
curated table of ``test_api_hostile_all.py`` and the stages' other entry points: the
simulator, the route planner, the crawler, the drive sequences, the calibration, the
parts and the STEP tree), and every reader against files that are missing, folders,
FIFOs, endless devices, empty, binary garbage or cut short.

Each call raises its stage's ``origami_cad.errors`` type in one line, or returns; never
a bare Python error, a call past the time bound or a multi-line message. The default run
tries a fixed set of values that no argument accepts; ``make fuzz`` (``ORIGAMI_FUZZ_EXAMPLES``
set) tries every hostile value on every argument, and numbers replaced in every file."""

from __future__ import annotations

import math
import os
import random
import re
import warnings
from pathlib import Path

import numpy as np
import origami_cad.parts as parts
import pytest
from helpers_exec import InlineExecutor, bounded
from test_api_hostile_all import HOSTILE, _calls

import origami_cad as oc
from origami_cad.crawler.robot import load_gait, load_robot
from origami_cad.crawler.walk import simulate_gait
from origami_cad.drive import DynamixelBus, DynamixelEmulator
from origami_cad.drive.sequence import load_sequence, run_sequence
from origami_cad.errors import OrigamiCadError
from origami_cad.simulation.calibrate import calibrate, load_runs
from origami_cad.simulation.materials import load_materials
from origami_cad.strings.plan import plan_routes
from origami_cad.strings.plan_model import TSAPlacement

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
FUZZ = int(os.environ.get("ORIGAMI_FUZZ_EXAMPLES", "0")) > 0
fuzz_only = pytest.mark.skipif(not FUZZ, reason="make fuzz runs it (ORIGAMI_FUZZ_EXAMPLES)")

#: No argument of any public call accepts these: each must be refused by name, quickly.
NEVER = [math.nan, object(), np.zeros((2, 2, 2)), b"\x00"]
#: ``make fuzz``: every value of the curated sweep and more (sizes, shapes, paths, text).
EVERY = [*HOSTILE, np.zeros((2, 2, 2)), np.zeros(0), 10**9, -(10**9), 2**63, 1 + 2j, "nan",
         "1", {"a": 1}, (1.0,), Path("/nonexistent/x"), Path("/")]  # fmt: skip


def outcome(call, *args, **kwargs) -> str | None:
    """None when ``call`` returns or raises one line of ours, else what went wrong."""
    with bounded(), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            call(*args, **kwargs)
        except OrigamiCadError as exc:
            return f"a message of several lines: {exc!s:.200}" if "\n" in str(exc) else None
        except Exception as exc:
            return f"{type(exc).__name__}: {exc!s:.200}"
    return None


def _stage_calls(tmp: Path) -> dict:
    """The stages' entry points outside the curated table, each with arguments that work."""
    miura = oc.load_design(EXAMPLES / "miura_6x4.toml")
    route = oc.load_route(EXAMPLES / "miura_route.toml", miura.pattern)
    small = oc.miura_design(2, 2, 20.0, 20.0, 60.0)
    robot = load_gait(EXAMPLES / "crawler_gait.toml", load_robot(EXAMPLES / "crawler/crawler.toml"))
    seq = load_sequence(EXAMPLES / "arm_fold.toml")
    run = tmp / "run.csv"
    run.write_text("time_s,tension_N,pull_mm\n0,0,0\n0.1,2,1.5\n0.2,3,3\n0.3,4,4.5\n")
    runs = load_runs([run])

    def drive(sequence=seq, log=None, time_scale=40.0, progress=None):
        with (
            DynamixelEmulator([1], time_scale=40) as emu,
            DynamixelBus(emu.port, ids=[1], profile_velocity=0) as bus,
        ):
            return run_sequence(sequence, bus, log, time_scale=time_scale, progress=progress)

    return {
        "simulate": (oc.simulate, {"cp": miura.pattern, "route": route, "params": None,
                     "design": miura, "steps": 20, "fixed_panel": None, "fold_limits": None,
                     "prefold": 3.0, "tension_limit": None, "jam_ratio": 0.8, "jam_steps": 3,
                     "max_string_strain": 0.02, "max_bar_strain": 0.01, "max_dp": 0.01,
                     "max_states": 5000, "progress": None, "free": False}),
        "fabricate": (oc.fabricate, {"source": small, "params": None, "bed": None,
                                     "progress": None}),
        "write_fabrication": (oc.write_fabrication, {"fab": oc.fabricate(small),
                                                     "folder": tmp / "fab", "slicer": None}),
        "with_fold_path": (oc.with_fold_path, {"design": small, "params": None, "samples": 11}),
        "plan_routes": (plan_routes, {"design": small, "tsa": TSAPlacement(
            "ring", None, tsa=oc.TSAParams(model="ring")), "n_strings": 2, "target_p": None,
            "target_angles": None, "free_panels": (), "existing_holes": (), "candidates": 8,
            "seed": 0, "executor": InlineExecutor(), "progress": None, "check": 1}),
        "simulate_gait": (simulate_gait, {"robot": robot, "cycles": 1, "steps": 3,
                          "reverse": False, "params": None, "friction": None, "prefold": None,
                          "progress": None}),
        "load_robot": (load_robot, {"path": EXAMPLES / "crawler/crawler.toml"}),
        "load_gait": (load_gait, {"path": EXAMPLES / "crawler_gait.toml", "robot": robot}),
        "load_sequence": (load_sequence, {"path": EXAMPLES / "arm_fold.toml"}),
        "load_materials": (load_materials, {"path": EXAMPLES / "materials.toml"}),
        "load_runs": (load_runs, {"paths": [run], "tsa": None, "x_dis": None, "servo": None}),
        "run_sequence": (drive, {"sequence": seq, "log": None, "time_scale": 40.0,
                                 "progress": None}),
        "calibrate": (calibrate, {"cp": miura.pattern, "route": route, "runs": runs,
                      "materials": None, "fit": ("crease_stiffness",), "step": 2.0,
                      "max_evaluations": 2, "names": None}),
        "Blocker": (parts.Blocker, {"plan": None, "crease": None, "params": None,
                                    "mountain": False}),
        "TSAModule": (parts.TSAModule, {"params": None, "plan": None, "panel": None}),
        "export_step_tree": (oc.export_step_tree, {"shape": parts.Blocker(),
                                                   "path": tmp / "blocker.step"}),
    }  # fmt: skip


@pytest.fixture(scope="module")
def every_call(tmp_path_factory) -> dict:
    tmp = tmp_path_factory.mktemp("probe")
    table = {k: v for k, v in _calls(tmp).items() if k != "design_arm"}  # CMA-ES: the fuzz
    return {**table, **_stage_calls(tmp)}


def test_no_argument_takes_what_no_argument_accepts(every_call, tmp_path, monkeypatch):
    """NaN, an object, a 3-D array and bytes, on every argument of every call: each is
    refused with the call's stage error in one line (or, where the argument is free-form,
    accepted), quickly."""
    monkeypatch.chdir(tmp_path)
    failures = []
    for name, (func, good) in every_call.items():
        for key in sorted(good):
            for value in NEVER:
                problem = outcome(func, **{**good, key: value})
                if problem:
                    failures.append(f"{name}({key}={type(value).__name__}): {problem}")
    assert not failures, "\n".join(failures)


@pytest.mark.parametrize(
    "name, key, value",
    [
        ("simulate", "max_dp", None),
        ("simulate", "jam_ratio", None),
        ("simulate", "progress", 1.0),
        ("simulate", "cp", "pattern.fold"),
        ("simulate_gait", "cycles", 10_000),  # x 1000 steps: 60 million states
        ("simulate_gait", "robot", None),
        ("plan_routes", "free_panels", "c0r0s0"),
        ("plan_routes", "target_angles", [1, 2]),
        ("plan_routes", "executor", 4),
        ("calibrate", "max_evaluations", 10**9),
        ("calibrate", "fit", "crease_stiffness"),
        ("calibrate", "runs", [([0.0, 1.0], [0.0])]),
        ("load_runs", "paths", "run.csv"),
        ("load_runs", "paths", ["/dev/zero"]),
        ("run_sequence", "sequence", "arm_fold.toml"),
        ("write_fabrication", "fab", None),
        ("export_step_tree", "shape", None),
        ("with_fold_path", "samples", 1),
    ],
)
def test_the_probes_findings_are_refused_by_name(every_call, name, key, value):
    """What the probe found raising a bare error, running unbounded or reading a device."""
    func, good = every_call[name]
    kwargs = {**good, key: value}
    if name == "simulate_gait" and key == "cycles":
        kwargs["steps"] = 1000
    with bounded(), pytest.raises(OrigamiCadError) as err:
        func(**kwargs)
    assert key in str(err.value) or name in str(err.value) or "/dev/zero" in str(err.value)
    assert "\n" not in str(err.value)


def test_a_bad_array_is_named_on_one_line():
    with pytest.raises(OrigamiCadError) as err:
        oc.fold(oc.miura_design(2, 2, 20.0, 20.0, 60.0), np.zeros((3, 3, 3)))
    assert "fold: p" in str(err.value) and "\n" not in str(err.value)


@fuzz_only
def test_fuzz_every_hostile_value_on_every_argument(every_call, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    failures = []
    for name, (func, good) in every_call.items():
        for key in sorted(good):
            for value in EVERY:
                problem = outcome(func, **{**good, key: value})
                if problem:
                    failures.append(f"{name}({key}={repr(value)[:30]!r}): {problem}")
    assert not failures, "\n".join(failures)


# --------------------------------------------------------------------------- files
def _readers(tmp: Path) -> dict:
    miura = oc.load_design(EXAMPLES / "miura_6x4.toml")
    robot = load_robot(EXAMPLES / "crawler/crawler.toml")
    opx = tmp / "pattern.opx"
    oc.write_pattern(miura.pattern, opx)
    run = tmp / "run.csv"
    run.write_text("time_s,tension_N,pull_mm\n0,0,0\n0.1,2,1.5\n0.2,3,3\n")
    return {
        "fold": (oc.read_pattern, EXAMPLES / "gallery/fold/simple.fold"),
        "svg": (oc.read_pattern, EXAMPLES / "gallery/origami_simulator/miura-ori.svg"),
        "dxf": (oc.read_pattern, EXAMPLES / "data/boat.dxf"),
        "opx": (oc.read_pattern, opx),
        "pygamix": (oc.read_pattern, EXAMPLES / "gallery/pygamix/waterbomb.json"),
        "design": (oc.load_design, EXAMPLES / "fig2_tg.toml"),
        "route": (lambda p: oc.load_route(p, miura.pattern), EXAMPLES / "miura_route.toml"),
        "task": (oc.load_task, EXAMPLES / "arm_task.toml"),
        "robot": (load_robot, EXAMPLES / "crawler/crawler.toml"),
        "gait": (lambda p: load_gait(p, robot), EXAMPLES / "crawler_gait.toml"),
        "sequence": (load_sequence, EXAMPLES / "arm_fold.toml"),
        "materials": (load_materials, EXAMPLES / "materials.toml"),
        "run": (lambda p: load_runs([p]), run),
        "mjcf": (oc.to_mjcf, EXAMPLES / "miura_6x4.toml"),
    }


@pytest.fixture(scope="module")
def readers(tmp_path_factory) -> dict:
    return _readers(tmp_path_factory.mktemp("readers"))


def _unreadable(tmp: Path, suffix: str) -> dict[str, Path]:
    """Paths no reader can read: each must be refused, naming the file."""
    folder = tmp / f"folder{suffix}"
    folder.mkdir(exist_ok=True)
    fifo = tmp / f"fifo{suffix}"
    if not fifo.exists():
        os.mkfifo(fifo)
    loop = tmp / f"loop{suffix}"
    if not loop.is_symlink():
        loop.symlink_to(loop)
    empty = tmp / f"empty{suffix}"
    empty.write_bytes(b"")
    garbage = tmp / f"garbage{suffix}"
    garbage.write_bytes(bytes(random.Random(43).randrange(256) for _ in range(400)))
    return {"missing": tmp / f"missing{suffix}", "folder": folder, "fifo": fifo,
            "symlink loop": loop, "/dev/zero": Path("/dev/zero"), "empty": empty,
            "garbage": garbage}  # fmt: skip


READERS = ["fold", "svg", "dxf", "opx", "pygamix", "design", "route", "task", "robot", "gait",
           "sequence", "materials", "run", "mjcf"]  # fmt: skip


@pytest.mark.parametrize("reader", READERS)
def test_every_reader_refuses_what_is_no_file_of_its_format(readers, reader, tmp_path):
    load, good = readers[reader]
    failures = []
    for what, path in _unreadable(tmp_path, good.suffix).items():
        if reader == "materials" and what == "empty":
            continue  # every key of a materials file has a default: empty is all defaults
        with bounded(), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                load(path)
                failures.append(f"{what}: read as if it were a file")
            except OrigamiCadError as exc:
                if "\n" in str(exc):
                    failures.append(f"{what}: a message of several lines")
            except Exception as exc:
                failures.append(f"{what}: {type(exc).__name__}: {exc!s:.200}")
    data = good.read_bytes()
    for cut in (0.2, 0.5, 0.9):  # cut short: refused or read, never a bare error
        path = tmp_path / f"cut{good.suffix}"
        path.write_bytes(data[: int(len(data) * cut)])
        problem = outcome(load, path)
        if problem:
            failures.append(f"cut at {cut:.0%}: {problem}")
    assert not failures, "\n".join(failures)


NUMBER = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?(?![\w.])")


@fuzz_only
@pytest.mark.parametrize("reader", READERS[:-1])
def test_fuzz_numbers_replaced_in_every_format(readers, reader, tmp_path):
    load, good = readers[reader]
    text = good.read_bytes().decode("utf-8", "replace")
    numbers = list(NUMBER.finditer(text))
    rnd = random.Random(43)
    failures = []
    for replacement in ("nan", "inf", "-1e999", "1e308", "-0.0", "0", "9" * 30, '"x"', "[]"):
        for k in rnd.sample(range(len(numbers)), min(8, len(numbers))):
            m = numbers[k]
            path = tmp_path / f"number{good.suffix}"
            path.write_text(text[: m.start()] + replacement + text[m.end() :], encoding="utf-8")
            problem = outcome(load, path)
            if problem:
                failures.append(f"number {k} = {replacement}: {problem}")
    assert not failures, "\n".join(failures)


# --------------------------------------------------------------------------- third sweep
_PLAN = None


def _plan():
    global _PLAN
    if _PLAN is None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            _PLAN = oc.plan_panels(oc.miura_design(2, 2, 20.0, 20.0, 60.0))
    return _PLAN


@pytest.mark.parametrize(
    "make, named",
    [
        (lambda: parts.Blocker(rotation=math.nan), "rotation"),
        (lambda: parts.Blocker(rotation="x"), "rotation"),
        (lambda: parts.DriverAdapter(rotation=np.zeros(0)), "rotation"),
        (lambda: parts.RingRail(align=0), "align"),
        (lambda: parts.RingRail(align=np.zeros(3)), "align"),
        (lambda: parts.TSAModule(mode="add"), "mode"),
        (lambda: parts.TSAModule(body=1.0), "body"),
        (lambda: parts.RingRail(centre=math.nan), "centre"),
        (lambda: parts.RingRail(angles=np.zeros((2, 2, 2))), "angles"),
        (lambda: parts.Blocker(angle=np.zeros((2, 2))), "angle"),
        (lambda: parts.Blocker(length=1e-320), "length"),
        (lambda: parts.Blocker(angle="\u0663"), "angle"),
        (lambda: parts.DriverAdapter(connectors=math.inf), "connectors"),
        (lambda: parts.Blocker(params=parts.BlockerParams(angle=math.nan)), "angle"),
        (lambda: parts.RingRailParams(centre="ab"), "centre"),
        (lambda: parts.Blocker(thickness=5.0, height=2.2), "thickness"),
        (
            lambda: parts.TSAModule(plan=_plan(), panel="c0r0s0", servo="big", body=(200, 200, 30)),
            "servo's case",
        ),
    ],
)
def test_the_parts_refuse_hostile_arguments_by_name(make, named):
    """Placement arguments, scalars for tuples, arrays, sizes below a solid, infinite
    counts, parameter dataclasses built directly, a servo larger than its panel."""
    with bounded(), pytest.raises(OrigamiCadError) as err:
        make()
    assert named in str(err.value) and "\n" not in str(err.value), str(err.value)


def test_a_route_of_another_pattern_is_refused_by_its_hole():
    miura = oc.load_design(EXAMPLES / "miura_6x4.toml")
    route = oc.load_route(EXAMPLES / "miura_route.toml", miura.pattern)
    small = oc.miura_design(2, 2, 20.0, 20.0, 60.0)
    with bounded(), pytest.raises(OrigamiCadError, match="pattern has 4 panels"):
        oc.simulate_dcqc(small, route, max_dp=0.05)


def test_a_file_name_with_a_newline_is_named_on_one_line(tmp_path):
    with pytest.raises(OrigamiCadError) as err:
        oc.to_mjcf(tmp_path / "a\nb.toml")
    assert "\n" not in str(err.value)


def test_tiny_printed_sizes_are_refused_before_the_kernel_sees_them():
    for key in ("thickness", "hole_diameter", "midlayer_bias"):
        with pytest.raises(OrigamiCadError, match=rf"^{key}: .*(\[0\.01, |at least 0\.01 mm)"):
            oc.FabricationParams(**{key: 1e-320})


@pytest.mark.parametrize(
    "argv, named",
    [
        (["fold", "{ex}/fig2_tg.toml", "-o", "{tmp}/a.fold", "--frames", "9" * 400], "--frames"),
        (["fold", "{ex}/fig2_tg.toml", "-o", "{tmp}/a.fold", "--frames", "\u0663"], "--frames"),
        (["drive", "{ex}/arm_fold.toml", "--dry-run", "--speed", "1e-320"], "--speed"),
        (["drive", "{ex}/arm_fold.toml", "--dry-run", "--port", ""], "--port"),
        (["part", "blocker", "-o", "{tmp}/p", "--crease", "9" * 400], "--crease"),
    ],
)
def test_the_cli_refuses_huge_exotic_or_ignored_option_values(tmp_path, capsys, argv, named):
    from origami_cad.cli import main

    code = main([a.format(ex=EXAMPLES, tmp=tmp_path) for a in argv])
    err = capsys.readouterr().err
    assert code == 2 and named in err and err.count("\n") == 1, err
    assert len(err) < 400, err


def test_a_design_of_another_pattern_and_a_step_below_the_grid_are_refused(every_call):
    func, good = every_call["simulate"]
    with bounded(), pytest.raises(OrigamiCadError, match="design: its pattern has 12 edges"):
        func(**{**good, "design": oc.miura_design(2, 2, 20.0, 20.0, 60.0)})
    func, good = every_call["calibrate"]
    with bounded(), pytest.raises(OrigamiCadError, match=r"step .*\[0.1, 1e4\), got 1e-320"):
        func(**{**good, "step": 1e-320})
    func, good = every_call["run_sequence"]
    with bounded(), pytest.raises(OrigamiCadError, match=r"\[0.1, 1000\], got 1e-320"):
        func(**{**good, "time_scale": 1e-320})


@pytest.mark.parametrize(
    "argv",
    [
        ["check", "{fifo}"],
        [
            "sequence",
            "{fifo}",
            "{ex}/arm_route.toml",
            "-o",
            "{tmp}/s.toml",
            "--keyframes",
            "0:0",
            "9:0.3",
        ],
    ],
    ids=["check", "sequence"],
)
def test_a_fifo_input_is_refused_before_anything_reads_it(tmp_path, capsys, argv):
    """The search for files a TOML input names, and sequence's test for a robot file,
    opened a FIFO and waited for a writer."""
    from origami_cad.cli import main

    fifo = tmp_path / "design.toml"
    os.mkfifo(fifo)
    with bounded(10):
        code = main([a.format(fifo=fifo, ex=EXAMPLES, tmp=tmp_path) for a in argv])
    err = capsys.readouterr().err
    assert code == 2 and "not a regular file" in err and err.count("\n") == 1, err


def test_sequence_of_a_robot_checks_its_gait_files_tsa_tables_as_drive_does(tmp_path, capsys):
    """``sequence ROBOT GAIT`` took the gait's keyframes and passed ``radius = inf`` in its
    ``[[tsa]]`` tables, which ``drive`` refuses on the same file."""
    from origami_cad.cli import main

    gait = tmp_path / "gait.toml"
    text = (EXAMPLES / "crawler_gait.toml").read_text(encoding="utf-8")
    gait.write_text(text.replace("radius = 0.6 ", "radius = inf ", 1), encoding="utf-8")
    robot = EXAMPLES / "crawler" / "crawler.toml"
    code = main(["sequence", str(robot), str(gait), "-o", str(tmp_path / "s.toml")])
    err = capsys.readouterr().err
    assert code == 2 and "radius" in err and err.count("\n") == 1, err
    assert not (tmp_path / "s.toml").exists()


@pytest.mark.parametrize(
    "make, named",
    [
        (lambda: oc.miura_design(2, 2, 20.0, 1e-9, 65.0), "panel_width = 1e-09 mm"),
        (lambda: oc.miura_design(2, 2, 1e-9, 20.0, 65.0), "panel_length = 1e-09 mm"),
        (lambda: oc.tg_design([[40, 0], [30, 25]], fold_ratio=0.5, unit_width=1e-9), "unit_width"),
    ],
)
def test_a_panel_too_small_for_the_tolerance_is_named_not_an_internal_error(make, named):
    with pytest.raises(OrigamiCadError) as err:
        make()
    assert named in str(err.value) and "internal" not in str(err.value), str(err.value)


@pytest.mark.parametrize("load", [oc.load_design, oc.load_task, oc.read_pattern])
def test_a_file_named_with_a_newline_is_named_on_one_line_by_every_loader(tmp_path, load):
    path = tmp_path / "a\nb.toml"
    path.write_text("")
    with pytest.raises(OrigamiCadError) as err:
        load(path)
    assert "\n" not in str(err.value) and "a\\nb" in str(err.value), str(err.value)


@pytest.mark.parametrize("token", ["NaN", "Infinity", "1e999"])
@pytest.mark.parametrize(
    "source",
    [
        EXAMPLES / "gallery/fold/simple.fold",
        EXAMPLES / "pygamix/descriptionData/f-mountain-big-fix-new.json",
    ],
    ids=["fold", "pygamix"],
)
def test_json_readers_refuse_what_no_strict_json_holds(tmp_path, source, token):
    """Python's JSON reader takes NaN, Infinity and 1e999 (as inf): in a key the reader
    does not use (faceOrders, PyGamiX's kps) they passed unseen."""
    text = source.read_text(encoding="utf-8")
    m = re.search(r"(?<![\w.])-?\d+(?:\.\d+)?(?![\w.])", text[len(text) // 2 :])
    at = len(text) // 2 + m.start()
    path = tmp_path / f"bad{source.suffix}"
    path.write_text(text[:at] + token + text[at + len(m.group()) :], encoding="utf-8")
    with pytest.raises(OrigamiCadError, match="not a finite number"):
        oc.read_pattern(path)
