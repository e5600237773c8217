"""Every option is used or refused: a single-valued option (or ``-o``, or a flag) given
twice, targets without the mix that scores them, empty or repeated design genes, and a
drive's port on a dry run (or a dry run's options on servos) are refused in one line,
exit code 2, with nothing written; the library refuses the same through its errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from origami_cad.cli import main
from origami_cad.commands import COMMANDS, execute
from origami_cad.crawler.design_search import DESIGN_BOUNDS, parse_design_bounds
from origami_cad.crawler.gait import GaitSettings
from origami_cad.errors import DesignError, OptionsError

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
ROBOT = EXAMPLES / "crawler" / "crawler.toml"


def refused(capsys, argv: list[str], needle: str) -> str:
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    lines = err.splitlines()
    assert len(lines) == 1 and needle in lines[0], err
    return lines[0]


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["fold", EXAMPLES / "fig2_tg.toml", "--ratio", "0.3", "--ratio", "0.5"], "--ratio"),
        (["tg", EXAMPLES / "fig2_tg.toml"], "-o"),  # one output: -o given twice below
        (["part", "blocker", "--angle", "30", "--angle", "45"], "--angle"),
        (["drive", EXAMPLES / "arm_fold.toml", "--dry-run", "--dry-run"], "--dry-run"),
    ],
)
def test_an_option_given_twice_is_refused(tmp_path, capsys, argv, needle):
    out = [tmp_path / "a.fold", tmp_path / "b.fold"] if argv[0] in ("fold", "tg") else []
    outs = ["-o", out[0], "-o", out[1]] if needle == "-o" else (["-o", out[0]] if out else [])
    if argv[0] == "part":
        outs = ["-o", tmp_path / "b.stl"]
    line = refused(capsys, [*argv, *outs], needle)
    assert "twice" in line or "one output" in line or "once" in line
    assert not any(tmp_path.iterdir())


def test_every_single_valued_option_of_every_command_is_refused_twice(capsys):
    """The parser's mechanism covers all commands: each value option once per command."""
    from origami_cad.cli import build_parser

    parser = build_parser()
    checked = 0
    for name, cls in COMMANDS.items():
        if cls.HIDDEN:
            continue
        sub = parser._subparsers._group_actions[0].choices[name]
        for action in sub._actions:
            if not action.option_strings or action.dest == "help":
                continue
            if action.dest.startswith("log_"):
                continue  # -q, --verbose, --debug: saying one twice changes nothing
            repeatable = type(action).__name__ == "_AppendAction"
            assert repeatable or type(action).__name__ in ("_Once", "_FlagOnce"), (
                name,
                action.option_strings,
            )
            checked += 1
    assert checked > 100


def test_targets_without_the_shortfall_mix_are_refused(tmp_path, capsys):
    refused(
        capsys,
        ["design-gait", ROBOT, "-o", tmp_path / "g", "--targets", "1", "2", "3", "--mix", "mean"],
        "'shortfall' mix only",
    )
    assert not (tmp_path / "g").exists()
    with pytest.raises(DesignError, match="targets are scored by the 'shortfall' mix only"):
        GaitSettings(targets=(45.0, 63.0, 45.0), mix="worst")
    with pytest.raises(DesignError, match="mix 'best' is not one of"):
        GaitSettings(mix="best")
    assert GaitSettings(targets=(1.0, 2.0, 3.0), mix="shortfall").target_values() == (1, 2, 3)


@pytest.mark.parametrize(
    ("design", "needle"),
    [("", "empty"), ("  ", "empty"), ("leg_length=100:120,leg_length=90:110", "given twice")],
)
def test_empty_or_repeated_design_genes_are_refused(tmp_path, capsys, design, needle):
    gene = next(iter(DESIGN_BOUNDS))
    design = design.replace("leg_length", gene)
    with pytest.raises(DesignError, match=needle):
        parse_design_bounds(design)
    refused(capsys, ["design-gait", ROBOT, "-o", tmp_path / "g", "--design", design], needle)
    assert not (tmp_path / "g").exists()
    assert parse_design_bounds("default") == DESIGN_BOUNDS


def test_a_port_on_a_dry_run_and_dry_run_options_on_servos_are_refused(tmp_path, capsys):
    seq = EXAMPLES / "arm_fold.toml"
    log = tmp_path / "log.csv"
    refused(capsys, ["drive", seq, "--port", "/dev/null", "--dry-run", "--log", log], "--port")
    refused(capsys, ["drive", seq, "--port", "/dev/null", "--speed", "3"], "--speed")
    refused(capsys, ["drive", seq, "--port", "/dev/null", "--load-scale", "2"], "--load-scale")
    with pytest.raises(OptionsError, match="dry run drives the emulator"):
        execute("drive", seq, log, port="/dev/null", dry_run=True)
    assert not log.exists()
    assert COMMANDS["drive"].default("speed") == 8.0  # the help still shows the default
