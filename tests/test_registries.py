"""The registries: a toy pattern format and a toy servo bus added as a user would, one
module and one registry line each; unknown suffixes and protocols name the known ones;
the error classes catch only their own stage's faults."""

from __future__ import annotations

import importlib.util
import math
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from origami_cad.cli import main
from origami_cad.commands import execute
from origami_cad.drive import BUSES, BusType, SerialBus, SerialEmulator, open_bus, open_emulator
from origami_cad.errors import (
    DesignError,
    DriveError,
    FabricationError,
    OptionsError,
    OrigamiCadError,
    PatternError,
    SimulationError,
    StringsError,
)
from origami_cad.pattern import formats, miura_pattern, read_pattern, write_pattern

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

# a format module as a user writes it: its reader, its writer, its two dicts
TOY_FORMAT = '''
"""A toy format: one crease a line, ``x1 y1 x2 y2 letter``, in the file's units."""
from pathlib import Path

import numpy as np

from origami_cad.errors import PatternError
from origami_cad.pattern import CreasePattern


def read_toy(path, mm_per_unit=None):
    rows = [line.split() for line in Path(path).read_text().splitlines() if line.strip()]
    if any(len(r) != 5 for r in rows):
        raise PatternError(f"{path}: a line needs x1 y1 x2 y2 letter")
    points = np.array([[float(v) for v in r[:4]] for r in rows]).reshape(-1, 2)
    points *= 1.0 if mm_per_unit is None else mm_per_unit
    edges = np.arange(len(points)).reshape(-1, 2)
    return CreasePattern(points, edges, "".join(r[4] for r in rows))


def write_toy(cp, path):
    lines = [
        f"{float(a[0])!r} {float(a[1])!r} {float(b[0])!r} {float(b[1])!r} {letter}"
        for (a, b), letter in zip(cp.vertices[cp.edges], cp.assignments)
    ]
    Path(path).write_text("\\n".join(lines) + "\\n")
    return Path(path)


readers = {".toy": read_toy}
writers = {".toy": write_toy}
'''


@pytest.fixture
def toy_format(tmp_path, monkeypatch):
    """The toy format's module, imported from its file and registered (one line)."""
    source = tmp_path / "toy_format.py"
    source.write_text(textwrap.dedent(TOY_FORMAT))
    spec = importlib.util.spec_from_file_location("toy_format", source)
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, "toy_format", module)
    spec.loader.exec_module(module)
    saved = dict(formats.READERS), dict(formats.WRITERS)
    formats.register(module)  # the registry line
    yield module
    for registry, before in zip((formats.READERS, formats.WRITERS), saved, strict=True):
        registry.clear()
        registry.update(before)


def test_a_toy_format_is_read_and_written_through_the_registry(tmp_path, toy_format):
    cp = miura_pattern(rows=2, columns=3, panel_length=20.0, panel_width=30.0, sector_angle=60.0)
    out = write_pattern(cp, tmp_path / "cp.toy")
    assert out.read_text().count("\n") == len(cp.edges)
    back = read_pattern(out)  # dispatch, unit and size checks of read_pattern
    assert len(back.edges) == len(cp.edges)
    assert np.allclose(back.vertices[back.edges], cp.vertices[cp.edges])
    assert list(back.assignments) == list(cp.assignments)
    assert np.allclose(read_pattern(out, unit="cm").bounds, np.array(cp.bounds) * 10)
    # the same file in FOLD, through the registry too, and back
    again = read_pattern(write_pattern(back, tmp_path / "cp.fold"))
    assert np.allclose(again.vertices[again.edges], cp.vertices[cp.edges])
    # a malformed toy file is the reader's PatternError, naming the file
    (tmp_path / "bad.toy").write_text("1 2 3\n")
    with pytest.raises(PatternError, match=r"bad\.toy"):
        read_pattern(tmp_path / "bad.toy")


def test_a_toy_format_is_a_design_path_and_a_cli_output(tmp_path, toy_format, capsys):
    cp = miura_pattern(rows=2, columns=2, panel_length=20.0, panel_width=30.0, sector_angle=60.0)
    write_pattern(cp, tmp_path / "cp.toy")
    assert main(["check", str(tmp_path / "cp.toy")]) == 0, capsys.readouterr().err
    out = tmp_path / "again.toy"
    assert main(["convert", str(tmp_path / "cp.toy"), str(out)]) == 0
    assert out.read_text() == (tmp_path / "cp.toy").read_text()


def test_unknown_suffixes_name_the_known_formats(tmp_path, toy_format):
    (tmp_path / "cp.ori").write_text("<opx/>")
    known = r"readable: \.fold, \.dxf, \.svg, \.json, \.opx, \.cp, \.toy"
    with pytest.raises(PatternError, match=r"cp\.ori.*" + known):
        read_pattern(tmp_path / "cp.ori")
    cp = miura_pattern(rows=2, columns=2, panel_length=20.0, panel_width=30.0, sector_angle=60.0)
    with pytest.raises(PatternError, match=r"writable: \.fold, \.dxf, \.svg, \.opx, \.cp, \.toy"):
        write_pattern(cp, tmp_path / "cp.ori")
    assert not (tmp_path / "cp.ori.tmp").exists()


def test_the_unreleased_old_paths_are_gone():
    """0.1.0 is unreleased: the paths that moved before it are gone, not forwarded."""
    for gone in (
        "origami_cad.jobs",
        "origami_cad.design.parallel",
        "origami_cad.fabrication.export",
        "origami_cad.pattern.dxf",
        "origami_cad.pattern.svg",
        "origami_cad.pattern.fold",
    ):
        with pytest.raises(ModuleNotFoundError):
            importlib.import_module(gone)
    import origami_cad.crawler.walk as crawler
    import origami_cad.design.limits as limits

    assert not hasattr(crawler, "load_robot") and not hasattr(crawler, "MOVED_TO_ROBOT")
    assert not hasattr(limits, "crease_fold_limit")


# ---------------------------------------------------------------------- fabrication exports


def write_toy_volumes(fab, folder):
    """A toy export as a user writes it: each printed part's volume, one line each (mm^3)."""
    path = Path(folder) / "volumes.txt"
    parts = fab.report()["parts"]
    path.write_text("".join(f"{name} {v['volume_mm3']!r}\n" for name, v in parts.items()))
    return {"toy": path}


def test_a_toy_export_is_written_with_the_others_through_the_registry(tmp_path, monkeypatch):
    from origami_cad.fabrication import FabricationParams, exports, fabricate, write_fabrication

    monkeypatch.setitem(exports.WRITERS, "toy", write_toy_volumes)  # the registry line
    cp = miura_pattern(rows=2, columns=2, panel_length=30.0, panel_width=30.0, sector_angle=65.0)
    fab = fabricate(cp, FabricationParams(shell=0.5))
    paths = write_fabrication(fab, tmp_path)
    assert paths["toy"] == tmp_path / "volumes.txt" and "toy" in paths.timings
    volumes = dict(line.split() for line in paths["toy"].read_text().splitlines())
    stls = sorted(p.stem for p in tmp_path.glob("*.stl"))
    assert sorted(volumes) == stls and len(stls) == 4  # one line per part, as its STL
    assert all(float(v) > 0 for v in volumes.values())
    assert {"stl", "step", "3mf"} <= set(exports.WRITERS) and paths["json"].exists()


# ---------------------------------------------------------------------------- servo buses


class ToyBus(SerialBus):
    """A board that calls its servos motors: the serial protocol under its own name."""

    unit = "motor"
    device = "the toy board"


@pytest.fixture
def toy_bus(monkeypatch):
    monkeypatch.setitem(BUSES, "toy", BusType(ToyBus, SerialEmulator))  # the registry line
    return "toy"


def test_a_toy_bus_drives_a_sequence_through_the_registry(tmp_path, toy_bus):
    with open_emulator(toy_bus, [1, 2], time_scale=4.0) as emu:
        with open_bus(toy_bus, emu.port, 115200, [1, 2], max_turns=3.0) as bus:
            assert isinstance(bus, ToyBus)
            bus.set_turns({1: 0.5, 2: 0.25})
    # the drive command takes it by name: a dry run on its emulator, to the end
    done = run_drive(
        EXAMPLES / "arm_fold.toml", tmp_path / "log.csv", dry_run=True, speed=200.0,
        protocol=toy_bus, baudrate=115200,
    ).result  # fmt: skip
    assert done.target.max() > 0.5 and (tmp_path / "log.csv").stat().st_size > 0


KNOWN = "protocol must be one of dynamixel, serial, toy, got 'canbus'"
OPTION = "--protocol: expected one of dynamixel, serial, toy, got 'canbus'"


def test_an_unknown_protocol_names_the_known_ones(tmp_path, toy_bus, capsys):
    for call in (
        lambda: open_bus("canbus", "/dev/null"),
        lambda: open_emulator("canbus", [1]),
    ):
        with pytest.raises(DriveError, match=KNOWN):
            call()
    # the commands check their --protocol against the same registry, before any work
    for call in (
        lambda: run_emulate([1], protocol="canbus", seconds=0.1, echo=lambda _: None),
        lambda: run_drive(EXAMPLES / "arm_fold.toml", tmp_path / "l.csv", dry_run=True,
                          protocol="canbus"),
    ):  # fmt: skip
        with pytest.raises(OptionsError, match=OPTION):
            call()
    # before, the serial bus got it silently; now the drive refuses it (a run that never
    # began writes no log)
    assert not (tmp_path / "l.csv").exists()
    code = main(["emulate", "--protocol", "canbus", "--seconds", "0.1"])
    err = capsys.readouterr().err
    assert code == 2 and OPTION in err and err.count("\n") == 1


# ---------------------------------------------------------------------------- errors


def _bad_files(tmp_path: Path) -> dict[str, Path]:
    files = {
        "route": "[tsa]\nmodel = 'ring'\n[route]\nthickness = -1\n",
        "sequence": "[sequence]\nrepeat = 1\nrate = 10\n",
        "task": "[task]\npoints = [[1, 2]]\n",
        "robot": "[robot]\npattern = 'missing.fold'\n",
        "pattern.fold": '{"vertices_coords": [[0, 0]], "edges_vertices": [[0, 7]]}',
    }
    for name, text in files.items():
        (tmp_path / f"{name}.toml" if "." not in name else tmp_path / name).write_text(text)
    return {n.split(".")[0]: tmp_path / (n if "." in n else f"{n}.toml") for n in files}


def _faults(tmp_path: Path) -> dict[type, list]:
    from origami_cad.crawler.robot import load_robot
    from origami_cad.design import load_task
    from origami_cad.drive.sequence import load_sequence
    from origami_cad.fabrication import bias_for_theta_max
    from origami_cad.strings import load_route

    f = _bad_files(tmp_path)
    cp = miura_pattern(rows=2, columns=2, panel_length=20.0, panel_width=30.0, sector_angle=60.0)
    return {
        PatternError: [lambda: read_pattern(f["pattern"])],
        DesignError: [lambda: load_task(f["task"])],
        FabricationError: [lambda: bias_for_theta_max(math.radians(190.0), 2.2, 0.4)],
        StringsError: [lambda: load_route(f["route"], cp)],
        SimulationError: [lambda: load_robot(f["robot"])],
        OptionsError: [  # every option is checked by the command skeleton, before any work
            lambda: run_emulate([1], seconds=-1.0),
            lambda: run_crawl_friction(tmp_path),
            lambda: run_drive(
                EXAMPLES / "arm_fold.toml", tmp_path / "l.csv", dry_run=True, load_scale=-1.0
            ),
        ],
        DriveError: [
            lambda: load_sequence(f["sequence"]),
            lambda: run_emulate([1, 1], seconds=0.1),  # servo IDs
            lambda: open_bus("dynamixel", "/dev/null", ids=[]),
        ],
    }


def run_drive(*args, **kwargs):
    return execute("drive", *args, **kwargs)


def run_emulate(*args, **kwargs):
    return execute("emulate", *args, **kwargs)


def run_crawl_friction(tmp_path: Path):
    return execute(
        "crawl", EXAMPLES / "crawler" / "crawler.toml", tmp_path / "crawl", friction=-1.0
    )


def test_except_drive_error_catches_only_driving_faults(tmp_path):
    for cls, calls in _faults(tmp_path).items():
        for call in calls:
            try:
                call()
            except DriveError as exc:
                assert cls is DriveError, f"a {cls.__name__} fault was caught as driving: {exc}"
            except OrigamiCadError as exc:
                assert cls is not DriveError, f"a driving fault escaped DriveError: {exc!r}"
                assert type(exc) is cls or isinstance(exc, cls), (cls, exc)
            else:
                pytest.fail(f"no {cls.__name__} raised")


def test_each_stage_error_is_its_own_class_under_the_root():
    classes = [
        PatternError, DesignError, FabricationError, StringsError, SimulationError,
        DriveError, OptionsError,
    ]  # fmt: skip
    for cls in classes:
        assert issubclass(cls, OrigamiCadError)
        assert [c for c in classes if issubclass(cls, c)] == [cls]  # none is another's


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["check", "{tmp}/pattern.fold"], "edges_vertices"),
        (["design-arm", "{tmp}/task.toml", "-o", "{tmp}/d"], "task.toml"),
        (["fabricate", "{miura}", "-o", "{tmp}/f", "--theta-max", "180"], "--theta-max"),
        (["route", "{miura}", "{tmp}/route.toml", "-o", "{tmp}/r"], "route.toml"),
        (["robot", "{tmp}/robot.toml", "-o", "{tmp}/rb"], "robot.toml"),
        (["drive", "{tmp}/sequence.toml", "--dry-run"], "sequence.toml"),
        (["emulate", "--seconds", "-1"], "--seconds: expected a finite number in [0, 1e+07]"),
    ],
)
def test_the_cli_maps_every_stage_error_to_exit_2_and_one_line(tmp_path, capsys, argv, message):
    _bad_files(tmp_path)
    names = {"tmp": tmp_path, "miura": EXAMPLES / "miura_6x4.toml"}
    code = main([a.format(**names) for a in argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
