"""The help of every command is written for the command line: its options' units, choices
and defaults as the user types them, positional arguments explained, and no Python name
(snake_case words, dotted module paths, class names, calls, constants)."""

from __future__ import annotations

import argparse
import re

import pytest

from origami_cad.cli import build_parser, command_words, main
from origami_cad.commands import COMMANDS

#: product and format names written in CamelCase that are not Python classes
PRODUCTS = {"MuJoCo", "PyGamiX", "PrusaSlicer", "OrcaSlicer", "OpenCascade", "FreeCAD"}
#: a file name (``robot.json``, ``tsa_module_*.stl``) is the user's word, not Python's
FILE_NAME = re.compile(
    r"[\w*.-]*\.(?:json|toml|fold|stl|step|3mf|png|gif|glb|csv|xml|svg|dxf|opx|html)\b"
)
PYTHON = {
    "snake_case word": re.compile(r"(?<![\w-])[a-z][a-z0-9]*_[a-z0-9_]+\b"),
    "dotted path": re.compile(r"\b[a-z_][a-z0-9_]*\.[a-z_][a-z0-9_]*\.[A-Za-z_]\w*"),
    "origami_cad module": re.compile(r"origami_cad\b"),
    "class name": re.compile(r"\b[A-Z][a-z0-9]+[A-Z][A-Za-z0-9]*\b"),
    "call": re.compile(r"\b\w+\(\)"),
    "constant": re.compile(r"\b[A-Z][A-Z0-9]*_[A-Z0-9_]+\b"),
    "Python literal": re.compile(r"\b(?:None|True|False)\b|=\s*\"|\"\w+\""),
}


def _subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(subs.choices)


def _python_names(text: str) -> list[str]:
    text = FILE_NAME.sub("FILE", text)
    found = []
    for what, pattern in PYTHON.items():
        for m in pattern.finditer(text):
            if what == "class name" and m[0] in PRODUCTS:
                continue
            found.append(f"{what}: {m[0]!r}")
    return found


@pytest.mark.parametrize("name", [n for n, c in COMMANDS.items() if not c.HIDDEN])
def test_a_command_help_has_no_python_name(name):
    text = _subparsers()[name].format_help()
    assert not _python_names(text), f"{name} --help:\n" + "\n".join(_python_names(text))


def test_the_detector_finds_what_the_help_must_not_hold():
    """The patterns above catch each kind of Python name (a detector that never fires
    would pass any help)."""
    bad = (
        "params is a FabricationParams; a name of origami_cad.drive.BUSES; use a "
        "smaller hole_diameter; see simulate(); over STRAIN_LIMIT; holes = 'none'"
    )
    kinds = {f.split(":")[0] for f in _python_names(bad)}
    assert kinds == set(PYTHON) - {"Python literal"} | {"snake_case word"}
    assert _python_names('model = "dcqc" or None')
    fine = "writes robot.json and tsa_module_*.stl; MuJoCo model; --hole-diameter MM"
    assert not _python_names(fine)


@pytest.mark.parametrize("name", [n for n, c in COMMANDS.items() if not c.HIDDEN])
def test_a_command_usage_shows_its_choices_and_every_argument_has_help(name):
    sub = _subparsers()[name]
    usage = sub.format_usage()
    for opt in COMMANDS[name].OPTIONS:
        if opt.allowed is not None and opt.flag != "":
            assert "{" + ",".join(map(str, opt.allowed)) + "}" in usage, (name, opt.name)
    for action in sub._actions:
        assert action.help, f"{name}: {action.dest} has no help"
        if action.help and action.option_strings and action.metavar is None:
            # an option listing its values in its help must declare them (usage {a,b})
            listed = re.search(r"\b(\w+)\|(\w+)\b|\bone of\b", action.help)
            assert not listed, f"{name} {action.option_strings[-1]}: undeclared choices"


def test_defaults_are_shown_as_typed_in_the_users_units(capsys):
    with pytest.raises(SystemExit):
        main(["fabricate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    # the bed has no default (a warning past 200 x 200 mm): none is shown, nor Python's None
    assert "--bed X Y your printer's bed" in text and "200 x 200" in text
    assert "(200.0, 200.0)" not in text and "None" not in text
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "mm/s (default 16.67)" in text and "16.666" not in text


def test_a_library_hint_names_the_options_on_the_command_line():
    """A library error names its arguments; the command line says them as options."""
    fabricate = COMMANDS["fabricate"]
    hint = "panel c0r1s2: no room (room for 1.2 mm); use a smaller hole_diameter or holes = 'none'"
    shown = command_words(hint, fabricate)
    assert shown.endswith("use a smaller --hole-diameter or --holes none")
    assert "c0r1s2" in shown  # other words are left alone
    # a word that is an option's name but not marked up, nor snake_case, stays a word
    assert command_words("the holes of the panel", fabricate) == "the holes of the panel"


def test_each_command_summary_is_a_whole_sentence():
    """The one-line summaries of ``origami-cad --help`` stop at a sentence's end, not at
    an abbreviation's dot ("Fig. 8") or at an ellipsis standing for the outputs."""
    parser = build_parser()
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for action in subs._choices_actions:
        text = action.help or ""
        assert text.count("(") == text.count(")"), (action.dest, text)
        assert not text.endswith(("...", "Fig", "eq")), (action.dest, text)
