"""``drive`` never loses a log: a run that never began writes none and leaves an old one
as it was; a log replaces an old one only once its run began; a full disk leaves a log
that ends on a whole row; a sequence whose names hide characters is refused before any
log is made. No default writes into the current folder."""

from __future__ import annotations

import csv
import os
from pathlib import Path

import pytest
from test_output_integrity import MODE, full_disk_run

from origami_cad.cli import main
from origami_cad.drive import DynamixelBus, DynamixelEmulator
from origami_cad.drive.sequence import LOG_FIELDS, load_sequence, run_sequence

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
OLD = "t_s,id,target_turns,measured_turns,current_mA\r\n0.0,1,0.5,0.5,10.0\r\n# an earlier run\n"


def _sequence(folder: Path, name: str = "tsa 1") -> Path:
    path = folder / "seq.toml"
    path.write_text(
        f'[sequence]\nrate = 20.0\n[[tsa]]\nid = 1\nname = "{name}"\nlength = 120.0\n'
        "radius = 0.6\nmax_helix_angle = 75.0\nmapping = [[0.0, 0.0], [1.0, 20.0]]\n"
        "[[keyframe]]\nt = 0.0\np = [0.0]\n[[keyframe]]\nt = 0.5\np = [0.5]\n",
        encoding="utf-8",
    )
    return path


def _port(tmp_path: Path, kind: str) -> str:
    """A port that cannot be opened as a serial port."""
    if kind == "missing":
        return str(tmp_path / "ttyUSB9")
    if kind == "folder":
        (tmp_path / "dir").mkdir()
        return str(tmp_path / "dir")
    if kind == "fifo":
        os.mkfifo(tmp_path / "fifo")
        return str(tmp_path / "fifo")
    if kind == "file":
        (tmp_path / "plain").write_text("not a port")
        return str(tmp_path / "plain")
    if kind == "dangling":
        (tmp_path / "link").symlink_to(tmp_path / "gone")
        return str(tmp_path / "link")
    return "/dev/null"


@pytest.mark.parametrize("kind", ["missing", "folder", "fifo", "file", "/dev/null", "dangling"])
@pytest.mark.parametrize("protocol", ["dynamixel", "serial"])
def test_a_run_that_never_began_writes_no_log_and_keeps_the_old_one(
    tmp_path, capsys, kind, protocol
):
    seq, log = _sequence(tmp_path), tmp_path / "old.csv"
    log.write_text(OLD, newline="")
    port = _port(tmp_path, kind)
    code = main(["drive", str(seq), "--port", port, "--protocol", protocol, "--log", str(log)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and port in err, err
    assert log.read_bytes() == OLD.encode()
    assert not list(tmp_path.glob(".oc-*"))
    new = tmp_path / "new.csv"
    code = main(["drive", str(seq), "--port", port, "--protocol", protocol, "--log", str(new)])
    assert code == 2 and not new.exists()


def test_a_log_replaces_the_old_one_only_when_the_run_begins(tmp_path):
    """Until the first command the old log is at its name and the new one beside it."""
    seq = load_sequence(_sequence(tmp_path))
    log = tmp_path / "old.csv"
    log.write_text(OLD, newline="")
    seen = []

    class Watching:  # the emulator's real bus, noting the folder at each command
        def __init__(self, bus):
            self.bus = bus

        def set_turns(self, targets):
            seen.append((log.read_bytes(), sorted(p.name for p in tmp_path.glob(".oc-*"))))
            return self.bus.set_turns(targets)

        def read(self):
            return self.bus.read()

    with DynamixelEmulator([1]) as emu, DynamixelBus(emu.port, ids=[1]) as bus:
        run_sequence(seq, Watching(bus), log, time_scale=50.0)
    # at the first command the new log is already in place (header only), nothing beside it
    assert seen[0] == (",".join(LOG_FIELDS).encode() + b"\r\n", [])
    rows = list(csv.DictReader(log.open(newline="")))
    assert len(rows) == len(seen) and rows[-1]["t_s"] == "0.5"


@pytest.mark.parametrize("name", ["a\u009bb", "front\u202eleft", "tab\there"])
def test_a_tsa_named_with_hidden_characters_is_refused_before_any_log(tmp_path, capsys, name):
    seq, log = _sequence(tmp_path, name.replace("\t", "\\t")), tmp_path / "old.csv"
    log.write_text(OLD, newline="")
    assert main(["drive", str(seq), "--dry-run", "--log", str(log)]) == 2
    err = capsys.readouterr().err
    assert "seq.toml" in err and "'name'" in err and err.count("\n") == 1, err
    assert log.read_bytes() == OLD.encode() and not list(tmp_path.glob(".oc-*"))


def test_a_full_disk_during_a_run_leaves_a_log_of_whole_rows(tmp_path):
    """The disk fills while the run goes: exit 2 naming the log, every line whole."""
    if MODE is None:
        pytest.skip("no tiny disk here")
    argv = ["drive", str(EXAMPLES / "crawler_gait.toml"), "--dry-run", "--speed", "1000",
            "--log", "OUT/log.csv"]  # fmt: skip
    result = full_disk_run(tmp_path, argv, {}, size_kb=64, free_kb=6, fsize=6000)
    err = result["stderr"]
    assert result["code"] == 2 and err.count("\n") == 1, err
    assert f"{result['folder']}/log.csv: cannot be written" in err, err
    text = result["after"]["log.csv"].decode()
    lines = text.splitlines()
    assert text.endswith("\n") and lines[0] == ",".join(LOG_FIELDS) and len(lines) > 10
    for line in lines[1:]:
        assert line.startswith("# stopped at") or len(line.split(",")) == len(LOG_FIELDS), line
    rows = list(csv.DictReader(lines))
    assert all(float(r["current_mA"]) == float(r["current_mA"]) for r in rows)


def test_drive_writes_no_log_into_the_current_folder_unless_asked(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    seq = _sequence(tmp_path)
    assert main(["drive", str(seq), "--dry-run", "--speed", "100"]) == 0
    assert "no log was kept" in capsys.readouterr().out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["seq.toml"]
