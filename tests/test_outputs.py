"""Outputs never destroy the user's files.

An output folder keeps everything the command did not write; an output that
resolves to an input is refused; links are written through, devices and pipes
written into, never replaced; an interrupt leaves nothing behind.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from conftest import ink

from origami_cad._fileio import atomic_directory, atomic_path
from origami_cad._signals import Interrupted, handle_signals
from origami_cad.cli import main
from origami_cad.errors import OutputError

SMALL_MIURA = """\
[pattern]
kind = "miura"
rows = 2
columns = 2
panel_length = 20.0
panel_width = 25.0
sector_angle = 65.0
"""


def _user_project(folder: Path) -> dict[Path, bytes]:
    """A folder holding the user's own files; returns their contents."""
    files = {
        folder / "design.toml": SMALL_MIURA.encode(),
        folder / "notes.txt": b"do not lose me\n",
        folder / "sub" / "important.dat": bytes(range(256)),
    }
    for path, data in files.items():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    return files


def _assert_kept(files: dict[Path, bytes]) -> None:
    for path, data in files.items():
        assert path.read_bytes() == data, f"{path} was changed"


def _no_leftovers(folder: Path) -> None:
    assert [p.name for p in folder.rglob(".oc-*")] == []


def test_fabricate_into_the_folder_of_its_input_keeps_the_users_files(tmp_path, capsys):
    proj = tmp_path / "proj"
    files = _user_project(proj)
    assert main(["fabricate", str(proj / "design.toml"), "-o", str(proj)]) == 0, (
        capsys.readouterr().err
    )
    _assert_kept(files)
    names = {p.name for p in proj.iterdir()}
    assert {"infills.stl", "shells.stl", "print.3mf", "fabrication.json"} <= names
    assert (proj / "creases.stl").stat().st_size > 1000
    _no_leftovers(proj)
    # a second run replaces its own files and still keeps the user's
    assert main(["fabricate", str(proj / "design.toml"), "-o", str(proj), "--bias", "2"]) == 0
    _assert_kept(files)
    report = json.loads((proj / "fabrication.json").read_text())
    assert report["parameters"]["bias_mm"] == 2.0


@pytest.mark.parametrize("where", [".", "cwd"])
def test_the_current_folder_as_output(tmp_path, monkeypatch, capsys, where):
    files = _user_project(tmp_path)
    monkeypatch.chdir(tmp_path)
    out = "." if where == "." else str(Path.cwd())
    code = main(["part", "driver-adapter", "-o", out])
    assert code == 0, capsys.readouterr().err
    _assert_kept(files)
    assert (tmp_path / "driver-adapter.step").stat().st_size > 1000
    _no_leftovers(tmp_path)


def test_a_failing_command_leaves_the_folder_as_it_was(tmp_path, capsys):
    files = _user_project(tmp_path)
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    assert main(
        ["fabricate", str(tmp_path / "design.toml"), "-o", str(tmp_path), "--thickness", "5"]
    )
    assert "thickness" in capsys.readouterr().err
    _assert_kept(files)
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before
    # a folder created for the output is removed again, with its new parents
    assert (
        main(
            [
                "fabricate",
                str(tmp_path / "design.toml"),
                "-o",
                str(tmp_path / "a" / "b"),
                "--thickness",
                "5",
            ]
        )
        == 2
    )
    assert not (tmp_path / "a").exists()


@pytest.mark.parametrize(
    "argv",
    [
        ["fabricate", "{d}", "-o", "{d}"],
        ["tg", "{d}", "-o", "{d}"],
        ["convert", "{f}", "{f}"],
        ["pattern", "{d}", "-o", "{f}", "-o", "{f}"],
        ["fold", "{f}", "-o", "{f}"],
        ["route", "{d}", "{d}", "-o", "{d}"],
        ["drive", "{s}", "--dry-run", "--log", "{s}"],
        ["simulate", "{f}", "{d}", "-o", "{f}"],
    ],
)
def test_an_output_that_is_an_input_is_refused(tmp_path, capsys, argv):
    d, f, s = tmp_path / "d.toml", tmp_path / "p.fold", tmp_path / "seq.toml"
    d.write_text(SMALL_MIURA)
    assert main(["pattern", str(d), "-o", str(f)]) == 0
    s.write_text("[sequence]\n")  # never read: the output check comes first
    before = {p: p.read_bytes() for p in (d, f, s)}
    code = main([a.format(d=d, f=f, s=s) for a in argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and err.startswith("origami-cad: error: ")
    assert {p: p.read_bytes() for p in (d, f, s)} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.toml", "p.fold", "seq.toml"]


def test_an_output_file_named_like_an_input_inside_the_folder_is_refused(tmp_path, capsys):
    """The task file is called best.toml, the name design-arm writes its winner to."""
    task = tmp_path / "best.toml"
    task.write_text(
        (Path(__file__).resolve().parents[1] / "examples" / "arm_task.toml").read_text()
    )
    before = task.read_bytes()
    argv = ["design-arm", str(task), "-o", str(tmp_path), "--runs", "1", "--max-generations", "2"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "would overwrite the input" in err and "best.toml" in err
    assert task.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["best.toml"]


def test_a_link_is_written_through_and_stays_a_link(tmp_path):
    d = tmp_path / "d.toml"
    d.write_text(SMALL_MIURA)
    real = tmp_path / "real" / "tg.png"
    real.parent.mkdir()
    real.write_bytes(b"old")
    link = tmp_path / "link.png"
    link.symlink_to(real)
    assert main(["tg", str(d), "-o", str(link)]) == 0
    assert link.is_symlink() and link.resolve() == real
    covered, _ = ink(real)
    assert 0.005 < covered < 0.5  # the transition graph is drawn


def test_a_pipe_is_written_into_not_replaced(tmp_path):
    d = tmp_path / "d.toml"
    d.write_text(SMALL_MIURA)
    fifo = tmp_path / "out.png"
    os.mkfifo(fifo)
    got: list[bytes] = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()))
    reader.start()
    try:
        assert main(["tg", str(d), "-o", str(fifo)]) == 0
    finally:
        reader.join(timeout=30)
    assert fifo.is_fifo()
    assert got and 0.005 < ink(got[0])[0] < 0.5  # the whole picture came through the pipe


@pytest.mark.parametrize(
    ("output", "message"),
    [
        ("notes.txt/out.png", "is a file, not a folder"),
        ("pic.png", "is a folder"),
        ("x" * 300 + ".png", "too long"),
        ("tg.txt", "written as .png"),
    ],
)
def test_unwritable_outputs_are_named_in_one_line(tmp_path, capsys, output, message):
    files = _user_project(tmp_path)
    (tmp_path / "pic.png").mkdir()
    code = main(["tg", str(tmp_path / "design.toml"), "-o", str(tmp_path / output)])
    err = capsys.readouterr().err
    # the Miura design has no TG: the output is checked before the design is read
    assert code == 2 and message in err and err.count("\n") == 1, err
    _assert_kept(files)
    _no_leftovers(tmp_path)


def test_a_name_near_the_file_system_limit_is_written(tmp_path):
    files = _user_project(tmp_path)
    long = tmp_path / ("p" * 250 + ".fold")
    assert main(["pattern", str(tmp_path / "design.toml"), "-o", str(long)]) == 0
    assert long.stat().st_size > 100
    _assert_kept(files)


def test_an_interrupt_inside_the_block_writes_nothing(tmp_path):
    files = _user_project(tmp_path)
    with handle_signals(), pytest.raises(Interrupted):
        with atomic_directory(tmp_path) as tmp:
            (tmp / "a.txt").write_text("partial")
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(1)  # the handler raises at the next bytecode
    _assert_kept(files)
    assert not (tmp_path / "a.txt").exists()
    _no_leftovers(tmp_path)


def test_an_interrupt_a_library_swallowed_still_writes_nothing(tmp_path):
    target = tmp_path / "out.png"
    with handle_signals(), pytest.raises(Interrupted):
        with atomic_path(target) as tmp:
            tmp.write_bytes(b"partial")
            try:  # what a VTK callback does with the KeyboardInterrupt
                os.kill(os.getpid(), signal.SIGINT)
                time.sleep(1)
            except KeyboardInterrupt:
                pass
    assert not target.exists()
    _no_leftovers(tmp_path)
    # outside the block, interrupts are forgotten and writing works again
    with atomic_path(target) as tmp:
        tmp.write_bytes(b"done")
    assert target.read_bytes() == b"done"


def test_atomic_directory_refuses_a_file_in_place_of_the_folder(tmp_path):
    d = tmp_path / "d.toml"
    d.write_text("x")
    with pytest.raises(OutputError, match="not a folder"), atomic_directory(d):
        pass
    assert d.read_text() == "x"


def test_sigterm_while_rendering_a_gif_leaves_nothing(tmp_path):
    """A real process, terminated once its temporary GIF exists."""
    design = Path(__file__).resolve().parents[1] / "examples" / "miura_6x4.toml"
    out = tmp_path / "fold.gif"
    cmd = [sys.executable, "-m", "origami_cad.cli", "fold", str(design), "--ratio", "0.8"]
    proc = subprocess.Popen(
        [*cmd, "--frames", "400", "-o", str(out)], stderr=subprocess.PIPE, text=True
    )
    deadline = time.monotonic() + 120
    while not list(tmp_path.glob(".oc-*")) and proc.poll() is None:
        assert time.monotonic() < deadline, "the GIF was never started"
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + signal.SIGTERM, err
    assert "terminated" in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("into", ["pipe", "file"])
def test_dev_stdout_is_written_into_and_stays_a_link(tmp_path, into):
    """As root, replacing /dev/stdout would break the whole system."""
    d = tmp_path / "d.toml"
    d.write_text((Path(__file__).resolve().parents[1] / "examples" / "fig2_tg.toml").read_text())
    cmd = [sys.executable, "-m", "origami_cad.cli", "tg", str(d), "-o", "/dev/stdout"]
    if into == "pipe":
        data = subprocess.run(cmd, capture_output=True, check=True, timeout=120).stdout
    else:
        with open(tmp_path / "tg.png", "wb") as fh:
            subprocess.run(cmd, stdout=fh, check=True, timeout=120)
        data = (tmp_path / "tg.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and 0.005 < ink(data)[0] < 0.5  # nothing else
    assert os.path.islink("/dev/stdout")
    _no_leftovers(tmp_path)


def test_after_an_interrupt_a_failing_destructor_prints_no_traceback():
    """An object an interrupt cut short (a pyvista Renderer mid-constructor) whose
    ``__del__`` fails at exit: silent after the signal, reported without one."""
    code = """
import os, signal, sys
from origami_cad._signals import Interrupted, handle_signals

class Half:
    def __del__(self):
        raise AttributeError("half built")

keep = Half()
if sys.argv[1] == "signal":
    with handle_signals():
        try:
            os.kill(os.getpid(), signal.SIGTERM)
            signal.pause()
        except Interrupted:
            pass
del keep
"""
    runs = {
        mode: subprocess.run(
            [sys.executable, "-c", code, mode], capture_output=True, text=True, timeout=60
        )
        for mode in ("signal", "plain")
    }
    assert "half built" in runs["plain"].stderr  # Python reports it when nothing interrupted
    assert runs["signal"].stderr == "" and runs["signal"].returncode == 0
