"""The origami-cad command: it runs the library and reports bad input in one line, exit 2."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import ink

from origami_cad.cli import main
from origami_cad.pattern import read_fold, read_fold_frames

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_help_lists_every_command(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--help"])
    assert info.value.code == 0
    out = capsys.readouterr().out
    for cmd in ("convert", "check", "pattern", "fold", "tg", "demo"):
        assert cmd in out


def test_every_command_help_is_plain_text():
    """The descriptions come from the commands' docstrings: no reST roles or ``literals``."""
    from origami_cad.cli import build_parser

    parser = build_parser()
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    assert len(subs.choices) > 10
    for name, sub in subs.choices.items():
        text = sub.format_help()
        assert "``" not in text and ":func:`" not in text and ":class:`" not in text, name


def test_pattern_fold_and_tg_from_the_fig2_example(tmp_path, capsys):
    design = str(EXAMPLES / "fig2_tg.toml")
    assert (
        main(["pattern", design, "-o", str(tmp_path / "cp.fold"), "-o", str(tmp_path / "cp.png")])
        == 0
    )
    cp = read_fold(tmp_path / "cp.fold")
    assert len(cp.faces) == 30
    covered, (left, top, right, bottom) = ink(tmp_path / "cp.png")
    assert 0.01 < covered < 0.5  # creases and border drawn, not a blank or black picture
    width, height = cp.bounds[2] - cp.bounds[0], cp.bounds[3] - cp.bounds[1]
    assert (right - left) / (bottom - top) == pytest.approx(width / height, rel=0.1)
    assert (
        main(["fold", design, "--ratio", "0.98", "--frames", "4", "-o", str(tmp_path / "f.fold")])
        == 0
    )
    data = json.loads((tmp_path / "f.fold").read_text())
    assert len(data["file_frames"]) == 4
    assert data["file_frames"][-1]["frame_classes"] == ["foldedForm"]
    frames = read_fold_frames(tmp_path / "f.fold")
    np.testing.assert_allclose(
        frames[1], np.column_stack([cp.vertices, np.zeros(cp.n_vertices)]), atol=1e-9
    )
    last = np.array(data["file_frames"][-1]["edges_foldAngle"])
    assert np.isclose(np.abs(last), 0.98 * 180, atol=1e-6).sum() >= 15  # main creases, 3 copies
    assert main(["tg", design, "-o", str(tmp_path / "tg.png")]) == 0
    covered, _ = ink(tmp_path / "tg.png")
    assert 0.005 < covered < 0.5


def test_fold_renders_png_and_gif(tmp_path):
    design = str(EXAMPLES / "miura_6x4.toml")
    assert main(["fold", design, "--ratio", "0.6", "-o", str(tmp_path / "m.png")]) == 0
    covered, _ = ink(tmp_path / "m.png")
    assert 0.05 < covered < 0.9  # the folded sheet fills a good part of the view
    assert (
        main(["fold", design, "--ratio", "0.6", "--frames", "3", "-o", str(tmp_path / "m.gif")])
        == 0
    )
    import imageio.v3 as iio

    frames = iio.imread(tmp_path / "m.gif", index=None, plugin="pillow")
    assert frames.shape[0] == 3
    assert not np.array_equal(frames[0], frames[-1])  # it moves
    # each frame says its fold ratio in the top-left corner: dark text that changes
    corner = frames[:, :30, :150, :3].astype(int).max(axis=-1)
    assert all((c < 100).sum() > 50 for c in corner)
    assert not np.array_equal(corner[0] < 100, corner[-1] < 100)


def test_check_exit_codes(tmp_path, capsys):
    ok = str(EXAMPLES / "fig2_tg.toml")
    main(["pattern", ok, "-o", str(tmp_path / "a.fold")])
    assert main(["check", str(tmp_path / "a.fold")]) == 0
    bad = {
        "vertices_coords": [[0, 0], [1, 0], [1, 1]],
        "edges_vertices": [[0, 1], [1, 2]],
        "edges_assignment": ["B", "B"],
    }
    (tmp_path / "open.fold").write_text(json.dumps(bad))
    assert main(["check", str(tmp_path / "open.fold")]) == 1
    assert "open-border" in capsys.readouterr().out


@pytest.mark.parametrize(
    "args, message",
    [
        (["convert", "missing.fold", "x.svg"], "missing.fold: no such file"),
        (["convert", str(EXAMPLES / "fig2_tg.toml"), "x.fold"], "unknown crease-pattern format"),
        (
            ["fold", str(EXAMPLES / "fig2_tg.toml"), "--ratio", "1.5", "-o", "x.fold"],
            "--ratio: expected a finite number in [0, 1], got 1.5",
        ),
        (["fold", str(EXAMPLES / "fig2_tg.toml"), "-o", "x.obj"], ".fold, .png, .gif"),
        (["pattern", "nothing.toml", "-o", "x.fold"], "nothing.toml: no such file"),
    ],
)
def test_bad_input_exits_2_with_one_line(tmp_path, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)
    proc = subprocess.run(
        [sys.executable, "-m", "origami_cad.cli", *args],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr
    assert message in lines[0]
    assert list(tmp_path.glob("x.*")) == []  # nothing half-written
