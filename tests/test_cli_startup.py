"""The command line starts light, and a Ctrl-C at any moment of its start is exit 130.

A Ctrl-C that lands inside an extension module's import (OCP's) surfaces as that
module's ``ImportError``, raised from the ``KeyboardInterrupt``: the CLI must still say
"interrupted" in one line, never print a traceback (CI once printed one from the signal test).
"""

from __future__ import annotations

import subprocess
import sys

import origami_cad.cli as cli

HEAVY = ("build123d", "OCP", "matplotlib", "pyvista", "trimesh", "mujoco")


def test_help_and_the_parser_load_no_cad_kernel_or_plotting():
    code = (
        "import sys, contextlib, io\n"
        "from origami_cad.cli import main\n"
        "for argv in (['--help'], ['fabricate', '--help'], ['simulate', '--help']):\n"
        "    with contextlib.redirect_stdout(io.StringIO()) as out:\n"
        "        try:\n"
        "            main(argv)\n"
        "        except SystemExit:\n"
        "            pass\n"
        "    assert 'usage' in out.getvalue(), argv\n"
        f"print(sorted({{m.split('.')[0] for m in sys.modules}} & set({HEAVY!r})))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]", done.stdout


def test_fabricate_help_still_shows_the_library_defaults(capsys):
    try:
        cli.main(["fabricate", "--help"])
    except SystemExit:
        pass
    out = " ".join(capsys.readouterr().out.split())
    assert "--height" in out and "(default 2.2)" in out


def _import_interrupted():
    try:
        raise KeyboardInterrupt
    except KeyboardInterrupt as exc:
        raise ImportError("initialization failed") from exc


def test_an_interrupt_inside_an_import_while_parsing_is_one_line_and_130(monkeypatch, capsys):
    def parser(commands):
        _import_interrupted()

    monkeypatch.setattr(cli, "_parser", parser)
    assert cli.main(["check", "x.fold"]) == 130
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "interrupted" in err and "Traceback" not in err


def test_an_import_error_not_caused_by_an_interrupt_is_not_called_one():
    try:
        raise ImportError("no module")
    except ImportError as exc:
        assert not cli._caused_by_interrupt(exc)
    try:
        _import_interrupted()
    except ImportError as exc:
        assert cli._caused_by_interrupt(exc)
