"""The command registry: one place per command, thin commands, CLI syntax in the CLI.

Every command of ``origami-cad`` is declared once in ``origami_cad/commands/``; these
tests keep it that way: the modules stay short, each ``run`` stays a thin body over the
library, the command line is the registry's (nothing else), and the command-line syntax
(``--tsa ring|onboard:PANEL``, ``--budget TURNS[,NMM]``, command lines rebuilt into
file headers) lives only in ``commands/`` and ``cli.py``.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from origami_cad.cli import build_parser
from origami_cad.commands import COMMANDS, Option, execute
from origami_cad.errors import OptionsError

ROOT = Path(__file__).resolve().parents[1]
COMMANDS_DIR = ROOT / "origami_cad" / "commands"
MAX_MODULE, MAX_RUN = 300, 40


def _runs():
    for path in sorted(COMMANDS_DIR.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef):
                for item in node.body:
                    if isinstance(item, ast.FunctionDef) and item.name == "run":
                        yield f"{path.name}:{node.name}", item.end_lineno - item.lineno + 1


def test_no_command_module_is_over_300_lines_and_no_run_over_40():
    long = {
        p.name: n
        for p in COMMANDS_DIR.glob("*.py")
        if (n := len(p.read_text(encoding="utf-8").splitlines())) > MAX_MODULE
    }
    assert not long, f"modules over {MAX_MODULE} lines: {long}"
    runs = dict(_runs())
    assert len(runs) >= len(COMMANDS) - 1  # every command's body is found (not the base's)
    assert not {k: n for k, n in runs.items() if n > MAX_RUN}, runs


MAX_PRIVATE = 3
#: the skeleton itself: its private helpers are the commands' infrastructure
INFRASTRUCTURE = {"_base.py", "_options.py", "_outputs.py"}


def _private_functions(path: Path) -> list[str]:
    """The module-level ``def _x`` of a module (its private helpers)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return [
        node.name
        for node in tree.body
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and node.name.startswith("_")
    ]


def test_no_command_module_holds_more_than_three_private_helpers():
    """The library decides; a command parses, calls and writes: a command module with many
    private helpers holds decisions a script calling the library would not get."""
    counts = {
        p.name: _private_functions(p)
        for p in sorted(COMMANDS_DIR.glob("*.py"))
        if p.name not in INFRASTRUCTURE
    }
    assert "_write_arm_files" in counts["design.py"]  # it sees them
    over = {n: f for n, f in counts.items() if len(f) > MAX_PRIVATE}
    assert not over, f"command modules with more than {MAX_PRIVATE} private helpers: {over}"


def test_the_cli_is_the_registry():
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    shown = {n for n, c in COMMANDS.items() if not c.HIDDEN}
    assert set(sub.choices) == shown
    for name in shown:  # every declared option with a flag is an option of the command line
        flags = {s for a in sub.choices[name]._actions for s in a.option_strings}
        for opt in COMMANDS[name].OPTIONS:
            if opt.flag != "" and not opt.positional:
                assert opt.shown in flags, (name, opt.shown)


SKELETON = {"check_outputs", "atomic_directory", "check_suffix"}  # the skeleton's calls


def _skeleton_copies(path: Path) -> list[str]:
    """Where a module copies the skeleton: calls its checks, writes a "wrote" line itself,
    or names the unit/scale/width trio."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            f = node.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            if name in SKELETON:
                found.append(f"{path.name}:{node.lineno}: calls {name}")
        elif isinstance(node, ast.Attribute) and node.attr in ("unit", "scale", "width"):
            found.append(f"{path.name}:{node.lineno}: reads the option {node.attr} itself")
    found += [
        f"{path.name}:{line}: writes its own 'wrote' line"
        for line, text in _strings(path)
        if re.search(r"(^|[;:] )wrote ", text)
    ]
    return found


def test_the_skeleton_lives_in_one_place():
    """Output checks, the staging folder, size options and "wrote" lines: only in the
    skeleton (``_base.py``, ``_outputs.py``, ``_options.py``), never copied into a command."""
    skeleton = {"_base.py", "_outputs.py", "_options.py"}
    copies = [
        c for p in sorted(COMMANDS_DIR.glob("*.py")) if p.name not in skeleton
        for c in _skeleton_copies(p)
    ]  # fmt: skip
    assert not copies, "\n".join(copies)
    # the search sees them where they are
    assert any("check_outputs" in c for c in _skeleton_copies(COMMANDS_DIR / "_base.py"))
    assert any("'wrote'" in c for c in _skeleton_copies(COMMANDS_DIR / "_outputs.py"))


def test_a_wrote_line_and_the_format_checks_come_from_the_skeleton(tmp_path):
    out = execute("convert", "examples/data/boat.dxf", tmp_path / "boat.fold")
    assert out.messages[-1].startswith(f"wrote {tmp_path / 'boat.fold'} (")
    with pytest.raises(OptionsError, match=r"boat\.txt: a pattern is written as \.fold"):
        execute("convert", "examples/data/boat.dxf", tmp_path / "boat.txt")
    with pytest.raises(OptionsError, match=r"p\.jpg: the drive plot is written as \.png"):
        execute("drive", "examples/arm_fold.toml", tmp_path / "l.csv", dry_run=True,
                plot=tmp_path / "p.jpg")  # fmt: skip
    with pytest.raises(OptionsError, match=r"m\.txt: an MJCF model is written as \.xml"):
        execute("mjcf", "examples/miura_6x4.toml", tmp_path / "m.txt")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["boat.fold"]


def _strings(path: Path):
    """(line, text) of every string constant of a module that is not a docstring."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docs = {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef)
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
    }
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs:
            yield node.lineno, node.value


# --tsa, --budget, and a command line rebuilt from its pieces: "# origami-cad fold ...",
# f"origami-cad fold {path} ...", ["origami-cad", "fold", ...], "... origami-cad fold -o"
CLI_SYNTAX = re.compile(
    r"--tsa\b|--budget\b|^\s*#?\s*origami-cad [a-z]|^origami-cad$|origami-cad [a-z][a-z-]* $"
    r"|origami-cad [a-z][a-z-]* -"
)


def test_command_line_syntax_lives_only_in_the_commands_and_the_cli():
    found = []
    for path in sorted((ROOT / "origami_cad").rglob("*.py")):
        rel = path.relative_to(ROOT)
        if rel.parts[1] == "commands" or rel.name == "cli.py":
            continue
        found += [
            f"{rel}:{line}: {text[:60]!r}"
            for line, text in _strings(path)
            if CLI_SYNTAX.search(text)
        ]
    assert not found, "command-line syntax outside commands/ and cli.py:\n" + "\n".join(found)
    # the search sees it where it is
    inside = [t for p in COMMANDS_DIR.glob("*.py") for _, t in _strings(p) if CLI_SYNTAX.search(t)]
    assert any("--tsa" in t for t in inside) and any("origami-cad" in t for t in inside)
    rebuilt = [
        "# origami-cad fold a",
        "origami-cad",
        "run origami-cad fold ",
        "origami-cad fold -o",
    ]
    assert all(CLI_SYNTAX.search(t) for t in rebuilt)
    assert not any(
        CLI_SYNTAX.search(t)
        for t in ["written by origami-cad crawl: each", "reinstall origami-cad", "tsa"]
    )


def test_an_option_is_checked_before_any_work(tmp_path):
    out = tmp_path / "f.fold"
    with pytest.raises(
        OptionsError, match=r"^--ratio: expected a finite number in \[0, 1\], got nan$"
    ):
        execute("fold", "examples/fig2_tg.toml", out, ratio=float("nan"))
    with pytest.raises(
        OptionsError, match=r"^--frames: expected an integer in 1\.\.10000, got 2\.5$"
    ):
        execute("fold", "examples/fig2_tg.toml", out, frames=2.5)
    assert not out.exists()
    opt = Option("gap", "float", min=0, open_min=True, max=5)
    assert opt.check("2.5") == 2.5 and opt.check(5) == 5
    for bad in ("0", 0.0, "inf", "x", True, 6):
        with pytest.raises(OptionsError, match=r"^--gap: expected a finite number in \(0, 5\]"):
            opt.check(bad)


def test_design_arm_takes_the_task_files_limits():
    from origami_cad.commands import design
    from origami_cad.design import task

    assert (design.MAX_RUNS, design.MAX_GENERATIONS) == (task.MAX_RUNS, task.MAX_GENERATIONS)
