"""One rule for a repeated ``-o``: a command that writes one result in several formats
(``pattern``, ``fold``) writes each file given; any other command refuses a second ``-o``
in one line, before any work, and writes nothing (never the last one silently)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from origami_cad.cli import main
from origami_cad.commands import COMMANDS

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_fold_writes_every_output_given(tmp_path):
    outs = [tmp_path / "a.fold", tmp_path / "a.png", tmp_path / "a.glb"]
    argv = ["fold", str(EXAMPLES / "fig2_tg.toml"), "--ratio", "0.6"]
    assert main([*argv, *(x for o in outs for x in ("-o", str(o)))]) == 0
    frames = json.loads(outs[0].read_text())["file_frames"]
    assert len(frames) == 1  # one state asked for: the .fold holds it alone
    assert outs[1].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert outs[2].read_bytes()[:4] == b"glTF"  # an animation: 30 states


@pytest.mark.parametrize(
    "argv",
    [
        ["tg", "{ex}/fig2_tg.toml", "-o", "{t}/a.png", "-o", "{t}/b.png"],
        ["fabricate", "{ex}/miura_6x4.toml", "-o", "{t}/a", "-o", "{t}/b"],
        ["part", "blocker", "-o", "{t}/a", "-o", "{t}/b"],
    ],
    ids=["file", "folder", "option"],
)
def test_a_one_output_command_refuses_a_second_o(tmp_path, capsys, argv):
    argv = [a.format(ex=EXAMPLES, t=tmp_path) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"-o: {argv[0]} writes one" in err, err
    assert not list(tmp_path.iterdir())


def test_every_command_with_o_follows_the_rule():
    """Each command's -o is a folder, a file, or several files (pattern, fold only)."""
    kinds = {n: c.OUTPUT for n, c in COMMANDS.items() if c.OUTPUT}
    assert {n for n, k in kinds.items() if k == "outputs"} == {"pattern", "fold"}
    assert set(kinds.values()) == {"output", "outputs", "folder"}
