"""Diagnostics where tools put them: the library warns through ``warnings`` and the
``origami_cad`` logger (silent by default: a NullHandler); the command line prints
warnings on stderr, never stdout, obeys --quiet / --verbose / --debug and ORIGAMI_CAD_LOG,
and draws progress only on a terminal."""

from __future__ import annotations

import json
import logging
import sys
from pathlib import Path

import pytest

import origami_cad as oc
from origami_cad import cli
from origami_cad.commands import COMMANDS
from origami_cad.errors import OrigamiCadWarning

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.fixture
def tiny(tmp_path) -> Path:
    """A 2 x 2 mm pattern: its size is warned about (a FOLD file written in inches?)."""
    path = tmp_path / "tiny.fold"
    path.write_text(
        json.dumps(
            {
                "file_spec": 1.2,
                "vertices_coords": [[0, 0], [2, 0], [2, 2], [0, 2], [1, 0], [1, 2]],
                "edges_vertices": [[0, 4], [4, 1], [1, 2], [2, 5], [5, 3], [3, 0], [4, 5]],
                "edges_assignment": ["B", "B", "B", "B", "B", "B", "V"],
                "faces_vertices": [[0, 4, 5, 3], [4, 1, 2, 5]],
            }
        )
    )
    return path


def test_the_library_logger_is_silent_until_configured():
    handlers = logging.getLogger("origami_cad").handlers
    assert any(isinstance(h, logging.NullHandler) for h in handlers)


def test_fabricate_warns_a_script_through_warnings_and_logging(caplog):
    design = oc.load_design(EXAMPLES / "miura_6x4.toml")
    with caplog.at_level(logging.WARNING, logger="origami_cad"):
        with pytest.warns(OrigamiCadWarning) as caught:
            fab = oc.fabricate(design)
    said = [str(w.message) for w in caught]
    assert fab.warnings and set(fab.warnings) <= set(said)
    # Python shows each warning at the script's line, not at the package's argument checks
    assert {w.filename for w in caught} == {__file__}
    logged = [r.getMessage() for r in caplog.records if r.name.startswith("origami_cad")]
    assert set(fab.warnings) <= set(logged)
    # a shipped example that warns at its defaults says why and what the user must do
    comments = " ".join(
        line.lstrip("#").strip()
        for line in (EXAMPLES / "miura_6x4.toml").read_text().splitlines()
        if line.startswith("#")
    )
    for line in fab.warnings:
        assert " ".join(line.split()[:6]) in comments, line


def test_warnings_go_to_stderr_and_quiet_silences_them(tiny, tmp_path, capsys, monkeypatch):
    out = tmp_path / "t.svg"
    assert cli.main(["convert", str(tiny), str(out)]) == 0
    got = capsys.readouterr()
    assert "origami-cad: warning" not in got.out and got.out.startswith("wrote ")
    assert got.err.startswith("origami-cad: warning: ") and "2 x 2 mm" in got.err
    assert got.err.count("under 10 mm") == 1  # said once
    for argv in (["--quiet", "convert"], ["convert", "-q"]):
        assert cli.main([*argv[:1], *argv[1:], str(tiny), str(tmp_path / "q.svg")]) == 0
        got = capsys.readouterr()
        assert got.out == "" and got.err == "", argv
    monkeypatch.setenv(cli.LOG_ENV, "quiet")
    assert cli.main(["convert", str(tiny), str(tmp_path / "e.svg")]) == 0
    assert capsys.readouterr().err == ""
    assert (tmp_path / "q.svg").stat().st_size > 0 and (tmp_path / "e.svg").stat().st_size > 0


def test_a_library_warning_is_said_once_in_the_commands_words(tmp_path, capsys):
    """fabricate's warnings come from the library (logger) and the command: one line each."""
    argv = ["fabricate", str(EXAMPLES / "miura_6x4.toml"), "-o", str(tmp_path / "f")]
    assert cli.main(argv) == 0
    got = capsys.readouterr()
    lines = got.err.splitlines()
    assert lines and all(line.startswith("origami-cad: warning: ") for line in lines)
    assert len(lines) == len(set(lines)) == 2
    assert "origami-cad: warning" not in got.out and "creases reach" not in got.out


def test_debug_shows_the_traceback_of_an_internal_error(tmp_path, capsys, monkeypatch):
    def broken(self, a):
        raise ZeroDivisionError("a bug")

    monkeypatch.setattr(COMMANDS["tg"], "run", broken)
    argv = ["tg", str(EXAMPLES / "fig2_tg.toml"), "-o", str(tmp_path / "tg.png")]
    assert cli.main(argv) == 3
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.count("\n") == 1 and "internal error" in err
    assert cli.main([*argv, "--debug"]) == 3
    err = capsys.readouterr().err
    assert "Traceback (most recent call last)" in err and "ZeroDivisionError: a bug" in err
    monkeypatch.setenv(cli.LOG_ENV, "debug")
    assert cli.main(argv) == 3
    assert "Traceback" in capsys.readouterr().err


def test_verbose_shows_the_librarys_info_lines(tmp_path, capsys):
    argv = ["fabricate", str(EXAMPLES / "miura_6x4.toml"), "-o", str(tmp_path / "f")]
    assert cli.main([*argv, "--verbose", "--shell", "0.6"]) == 0
    err = capsys.readouterr().err
    assert "origami-cad: info: built the solids of 24 panels" in err


@pytest.mark.parametrize("name", ["fabricate", "design-arm", "design-gait", "plan-route",
                                  "simulate"])  # fmt: skip
def test_long_commands_show_progress_on_a_terminal_only(name, monkeypatch):
    cls = COMMANDS[name]
    assert cls.PROGRESS
    assert cli._progress(cls) == (None, None)  # under pytest stderr is no terminal
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    display, report = cli._progress(cls)
    assert display is not None and callable(report)
    assert cli._progress(cls, logging.ERROR) == (None, None)  # --quiet
