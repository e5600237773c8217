"""No output replaces a file an input names; a folder's outputs change as one set.

The referenced files are found through the inputs (a design's pattern file, a sequence's
``dcqc.json`` mapping, a file named by a file named by the input); the set commit is
broken at each step (a full disk, a Ctrl-C, ``kill -9``) and must leave all the old
files; real processes are interrupted at random moments over an earlier good output
and must leave all old or all new outputs.
"""

from __future__ import annotations

import errno
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from origami_cad._fileio import atomic_directory, check_outputs, clean_stale, referenced_files
from origami_cad._signals import Interrupted, handle_signals
from origami_cad.cli import main
from origami_cad.errors import OutputError

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
CLI = [sys.executable, "-m", "origami_cad.cli"]
SMALL_MIURA = (
    '[pattern]\nkind = "miura"\nrows = 2\ncolumns = 2\npanel_length = 20.0\n'
    "panel_width = 25.0\nsector_angle = 65.0\n"
)
STALE = re.compile(r"\.oc-([0-9a-f]{6})-([0-9]+)-")


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {
        p.relative_to(folder).as_posix(): p.read_bytes() for p in folder.rglob("*") if p.is_file()
    }


def _design_naming(folder: Path, pattern: str, source: Path = EXAMPLES / "miura_6x4.toml") -> Path:
    """A design file whose [pattern] is the file ``pattern`` (written from ``source``)."""
    assert main(["pattern", str(source), "-o", str(folder / pattern)]) == 0
    design = folder / "d.toml"
    design.write_text(f'[pattern]\nkind = "file"\npath = "{pattern}"\n')
    return design


def _sequence_naming(folder: Path, mapping: str) -> Path:
    (folder / mapping).write_text(
        json.dumps({"states": {"p": [0, 1], "tsa_length_mm": [[0], [9]]}})
    )
    seq = folder / "seq.toml"
    seq.write_text(
        f'[sequence]\nrate = 20.0\n[[tsa]]\nid = 1\nname = "a"\nlength = 120.0\nradius = 0.6\n'
        f'max_helix_angle = 75.0\nmapping = "{mapping}"\n'
        "[[keyframe]]\nt = 0.0\np = [0.0]\n[[keyframe]]\nt = 0.5\np = [0.5]\n"
    )
    return seq


CASES = {
    # the design names cp.fold, and fold would write over it
    "fold": ("cp.fold", ["fold", "{d}", "-o", "{t}/cp.fold"]),
    "pattern": ("cp.dxf", ["pattern", "{d}", "-o", "{t}/cp.dxf"]),
    # the pattern the design names is a file fabricate (simulate) writes into the folder
    "fabricate": ("pattern_with_holes.fold", ["fabricate", "{d}", "-o", "{t}"]),
    "simulate": ("states.fold", ["simulate", "{d}", "{r}", "-o", "{t}"]),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_an_output_over_the_pattern_a_design_names_is_refused(tmp_path, capsys, case):
    pattern, argv = CASES[case]
    design = _design_naming(tmp_path, pattern)
    route = tmp_path / "route.toml"
    route.write_bytes((EXAMPLES / "miura_route.toml").read_bytes())
    before = _snapshot(tmp_path)
    capsys.readouterr()
    code = main([a.format(d=design, t=tmp_path, r=route) for a in argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and err.startswith("origami-cad: error: "), err
    assert f"would overwrite {tmp_path / pattern}, which the input {design} names" in err
    assert "key 'pattern.path'" in err
    assert _snapshot(tmp_path) == before  # nothing replaced, nothing added


def test_a_drive_log_over_the_mapping_its_sequence_names_is_refused(tmp_path, capsys):
    seq = _sequence_naming(tmp_path, "dcqc.json")
    before = _snapshot(tmp_path)
    code = main(["drive", str(seq), "--dry-run", "--log", str(tmp_path / "dcqc.json")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert f"which the input {seq} names (key 'tsa[0].mapping')" in err
    assert _snapshot(tmp_path) == before


def test_files_named_by_named_files_are_protected_too(tmp_path):
    """robot -> route file -> a file the route names: found through both."""
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "deep.fold").write_text("{}")
    (tmp_path / "route.toml").write_text('[extra]\nnotes = "sub/deep.fold"\n')
    (tmp_path / "robot.toml").write_text('[[leg]]\nroute = "route.toml"\nname = "not a file"\n')
    found = referenced_files([tmp_path / "robot.toml"])
    assert found == {
        (tmp_path / "route.toml").resolve(): (tmp_path / "robot.toml", "leg[0].route"),
        (tmp_path / "sub" / "deep.fold").resolve(): (
            (tmp_path / "route.toml").resolve(),
            "extra.notes",
        ),
    }
    with pytest.raises(OutputError, match=r"deep\.fold, which the input .*route\.toml names"):
        check_outputs([tmp_path / "robot.toml"], files=[tmp_path / "sub" / "deep.fold"])
    # a cycle of files naming each other ends
    (tmp_path / "a.toml").write_text('x = "b.toml"\n')
    (tmp_path / "b.toml").write_text('x = "a.toml"\n')
    assert set(referenced_files([tmp_path / "a.toml"])) == {(tmp_path / "b.toml").resolve()}


# ----------------------------------------------------------------- the set commit


def _write_set(folder: Path, text: str, names="abcd") -> None:
    with atomic_directory(folder) as stage:
        for n in names:
            (stage / f"{n}.txt").write_text(f"{text} {n}")


def _assert_old(folder: Path, user: bytes = b"mine") -> None:
    assert {p.name: p.read_text() for p in folder.glob("*.txt")} == {
        f"{n}.txt": f"old {n}" for n in "abcd"
    }
    assert (folder / "notes.md").read_bytes() == user
    assert not list(folder.glob(".oc-*"))


@pytest.fixture
def old_set(tmp_path) -> Path:
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "notes.md").write_bytes(b"mine")
    _write_set(folder, "old")
    return folder


def _replace_hook(monkeypatch, folder: Path, after: int, action) -> list:
    """Call ``action`` once, after the ``after``-th rename of a new file into ``folder``."""
    real, done = os.replace, []

    def hooked(src, dst, *args, **kwargs):
        real(src, dst, *args, **kwargs)
        if Path(dst).parent == folder.resolve() and Path(src).suffix != ".old" and not done:
            if len([1 for _ in hooked.calls]) + 1 >= after:
                done.append(True)
                action()
            hooked.calls.append(dst)

    hooked.calls = []
    monkeypatch.setattr(os, "replace", hooked)
    return done


def test_a_full_disk_while_putting_files_in_place_keeps_the_old_set(old_set, monkeypatch):
    def full():
        raise OSError(errno.ENOSPC, "No space left on device")

    done = _replace_hook(monkeypatch, old_set, 2, full)
    with pytest.raises(OutputError, match="No space left on device"):
        _write_set(old_set, "new", "abcde")
    assert done
    _assert_old(old_set)
    assert not (old_set / "e.txt").exists()  # a new name is removed again


def test_a_ctrl_c_while_putting_files_in_place_keeps_the_old_set(old_set, monkeypatch):
    done = _replace_hook(monkeypatch, old_set, 2, lambda: os.kill(os.getpid(), signal.SIGINT))
    with handle_signals(), pytest.raises(Interrupted):
        _write_set(old_set, "new", "abcde")
    assert done
    _assert_old(old_set)


KILLED = """
import os, signal, sys
from pathlib import Path
from origami_cad._fileio import atomic_directory, atomic_path
folder, mode = Path(sys.argv[1]).resolve(), sys.argv[2]
real, n = os.replace, [0]
def dying(src, dst, *a, **k):
    real(src, dst, *a, **k)
    if Path(dst).parent == folder and not str(src).endswith(".old"):
        n[0] += 1
        if n[0] == 2:
            os.kill(os.getpid(), signal.SIGKILL)
os.replace = dying
if mode == "commit":
    with atomic_directory(folder) as stage:
        for k in "abcde":
            (stage / f"{k}.txt").write_text(f"new {k}")
else:  # killed while writing: a staging folder and a temporary file are left
    with atomic_directory(folder) as stage, atomic_path(folder / "single.txt") as tmp:
        (stage / "a.txt").write_text("half")
        tmp.write_text("half")
        os.kill(os.getpid(), signal.SIGKILL)
"""


def _killed(folder: Path, mode: str) -> None:
    run = subprocess.run([sys.executable, "-c", KILLED, str(folder), mode], timeout=120)
    assert run.returncode == -signal.SIGKILL


def test_kill_9_while_putting_files_in_place_is_rolled_back_by_the_next_run(old_set):
    _killed(old_set, "commit")
    texts = {p.name: p.read_text() for p in old_set.glob("*.txt")}
    assert sorted(texts.values()) != sorted(f"old {n}" for n in "abcd")  # a mix was left
    assert list(old_set.glob(".oc-*"))
    removed = clean_stale(old_set)
    assert removed and all(STALE.match(p.name) for p in removed)
    _assert_old(old_set)
    assert not (old_set / "e.txt").exists()


def test_what_a_killed_run_left_is_removed_and_never_listed(old_set, capsys):
    _killed(old_set, "write")
    left = sorted(p.name for p in old_set.glob(".oc-*"))
    assert len(left) == 2, left  # the staging folder and the temporary file
    # only ours, only stale: another machine's or a live process's are kept
    pid = int(STALE.match(left[0]).group(2))
    other_host = old_set / left[0].replace(STALE.match(left[0]).group(1), "000000", 1)
    alive = old_set / left[1].replace(f"-{pid}-", f"-{os.getppid()}-", 1)
    os.rename(old_set / left[0], other_host)
    (old_set / left[1]).rename(alive)
    (old_set / ".oc-notes").write_text("a name like ours, but not one")
    _killed(old_set, "write")
    assert main(["part", "driver-adapter", "-o", str(old_set)]) == 0
    out = capsys.readouterr().out
    assert ".oc-" not in out and "driver-adapter.step" in out
    kept = sorted(p.name for p in old_set.glob(".oc-*"))
    assert kept == sorted([other_host.name, alive.name, ".oc-notes"])
    _assert_old_but(old_set, {"driver-adapter.step", "driver-adapter.stl"})


def _assert_old_but(folder: Path, new: set[str]) -> None:
    assert {p.name for p in folder.iterdir() if not p.name.startswith(".")} == {
        "notes.md",
        *(f"{n}.txt" for n in "abcd"),
        *new,
    }
    assert all(p.read_text() == f"old {p.stem}" for p in folder.glob("[!.]*.txt"))


DRIVE_SEQUENCE = """\
[sequence]
rate = 20.0
[[tsa]]
id = 1
name = "a"
length = 120.0
radius = 0.6
max_helix_angle = 75.0
mapping = [[0.0, 0.0], [1.0, 20.0]]
[[keyframe]]
t = 0.0
p = [0.0]
[[keyframe]]
t = 1.5
p = [0.5]
[[keyframe]]
t = 3.0
p = [0.0]
"""


def test_a_double_ctrl_c_during_drive_exits_130_with_every_servo_off(tmp_path):
    from origami_cad.drive import DynamixelEmulator

    seq = tmp_path / "seq.toml"
    seq.write_text(DRIVE_SEQUENCE.replace("rate = 20.0", "rate = 20.0\nrepeat = 20"))
    log = tmp_path / "log.csv"
    with DynamixelEmulator([1]) as emu:
        proc = subprocess.Popen(
            [*CLI, "drive", str(seq), "--port", emu.port, "--log", str(log)],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        )  # fmt: skip
        deadline = time.monotonic() + 120
        while not (log.exists() and log.read_text().count("\n") > 5):
            assert time.monotonic() < deadline and proc.poll() is None, proc.stderr.read()
            time.sleep(0.05)
        assert emu.servos[1].table[64] == 1  # running, torque on
        proc.send_signal(signal.SIGINT)
        time.sleep(0.02)
        proc.send_signal(signal.SIGINT)  # while the servos are being switched off
        err = proc.stderr.readline()
        if proc.poll() is None:  # and once more while the interpreter shuts down
            proc.send_signal(signal.SIGINT)
        err += proc.communicate(timeout=120)[1]
        assert proc.returncode == 130, err
        assert err.count("\n") == 1 and "interrupted" in err, err
        assert emu.servos[1].table[64] == 0  # torque off
    lines = log.read_text().splitlines()
    assert lines[0].startswith("t_s,id,") and len(lines) > 5
    assert re.fullmatch(r"# stopped at t = [0-9.]+ s: interrupted \(Ctrl-C\)", lines[-1]), lines[-1]
