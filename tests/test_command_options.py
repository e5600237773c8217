"""Every option of every command, fed hostile values.

Each option is declared once with its type and range (``origami_cad.commands``); the
command skeleton checks every one before any work. Here each option of each command gets
NaN, infinities, negative, zero, huge and text values: the exit code is 0, 1 or 2, never
3 (an internal error) and never a traceback; a value outside the option's declared range
is refused in one line that names the option. The inputs are files that do not exist, so
a value that passes its check costs nothing (the command stops at its input, rc 2); every
number has a finite range, so no value asks for unbounded work.
"""

from __future__ import annotations

import pytest

from origami_cad.cli import main
from origami_cad.commands import COMMANDS
from origami_cad.errors import OptionsError

VALUES = ("nan", "-inf", "-1", "0", "0.5", "1e300", "1e9", "text", "")
SKIPPED = {"demo"}  # its only value option is the output folder; a valid one runs the demo


def _cases():
    for name, cls in COMMANDS.items():
        if cls.HIDDEN or name in SKIPPED:
            continue
        for opt in cls.OPTIONS:
            if opt.flag != "" and opt.kind != "flag" and not opt.positional:
                yield pytest.param(name, opt, id=f"{name}{opt.shown}")


def _argv(name: str, opt, value: str) -> list[str]:
    cls = COMMANDS[name]
    argv = [name, *(f"missing_{i}.toml" for i in cls.INPUTS)]
    # the other positional arguments a command needs (calibrate's runs): files missing too
    argv += [f"missing_{o.name}.csv" for o in cls.OPTIONS if o.positional and o.nargs == "+"]
    argv += ["-o", "out.toml" if cls.OUTPUT != "folder" else "out"] if cls.OUTPUT else []
    if name == "emulate" and opt.name != "protocol":
        argv += ["--protocol", "nothing"]  # a valid value would otherwise emulate until Ctrl-C
    if name == "sequence" and opt.name != "keyframes":
        argv += ["--keyframes", "0:0"]
    count = opt.nargs if isinstance(opt.nargs, int) else 1
    return [*argv, opt.shown, *[value] * count]


def _refused(opt, value: str) -> bool:
    """Whether the option's declaration refuses the value."""
    count = opt.nargs if isinstance(opt.nargs, int) else 1
    given = [value] * count if count > 1 or opt.nargs == "+" else value
    try:
        opt.check([given] if opt.repeat and opt.kind != "object" else given)
    except OptionsError:
        return True
    return False


@pytest.mark.parametrize("name, opt", list(_cases()))
def test_every_option_refuses_a_bad_value_in_one_line(name, opt, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    if opt.kind in ("float", "int"):  # no unbounded work: every number has a finite range
        assert opt.min is not None and opt.max is not None, f"{name} {opt.shown}: no range"
    for value in VALUES:
        rc = main(_argv(name, opt, value))
        out = capsys.readouterr()
        lines = out.err.strip().splitlines()
        assert rc in (0, 1, 2), (value, out.err)
        assert "Traceback" not in out.err and len(lines) <= 1, (value, out.err)
        if _refused(opt, value):
            assert rc == 2 and lines and opt.shown in lines[0], (value, out.err)
            assert lines[0].startswith(f"origami-cad: error: {opt.shown}: "), lines[0]
    assert not list(tmp_path.iterdir()), "a refused or failed command wrote something"


@pytest.mark.parametrize(
    "argv, shown",
    [
        (["simulate", "{ex}/miura_6x4.toml", "{ex}/miura_route.toml", "-o", "s", "--gravity",
          "1e300"], "--gravity"),
        (["simulate", "{ex}/miura_6x4.toml", "{ex}/miura_route.toml", "-o", "s", "--ground",
          "1e300"], "--ground"),
        (["check", "{ex}/data/boat.dxf", "--angle-tolerance", "1e300"], "--angle-tolerance"),
        (["check", "{ex}/data/boat.dxf", "--angle-tolerance", "-1"], "--angle-tolerance"),
        (["plan-route", "{ex}/miura_6x4.toml", "-o", "r.toml", "--candidates", "1e9"],
         "--candidates"),
        (["fold", "{ex}/fig2_tg.toml", "-o", "f.fold", "--ratio", "nan"], "--ratio"),
        (["fabricate", "{ex}/miura_6x4.toml", "-o", "fab", "--height", "nan"], "--height"),
        (["sequence", "{ex}/arm_design.toml", "{ex}/arm_route.toml", "-o", "s.toml",
          "--keyframes", "-1:0.2", "5:0"], "keyframe"),
    ],
)  # fmt: skip
def test_the_issues_cases_are_refused_before_any_work(argv, shown, examples, tmp_path,
                                                      monkeypatch, capsys):  # fmt: skip
    monkeypatch.chdir(tmp_path)
    rc = main([a.format(ex=examples) for a in argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and shown in err[0], err
    assert not list(tmp_path.iterdir())


def test_a_bad_value_is_one_line_not_argparse_usage(capsys):
    assert main(["fold", "x.toml", "-o", "y.fold", "--frames"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("origami-cad: error: ") and "--frames" in err[0]
