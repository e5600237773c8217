"""Sequence files: one writer, byte for byte what the commands wrote before it.

The SHA-256 digests below are of the files ``sequence`` (an arm's route, a robot's gait)
and ``crawl`` wrote on the examples before the three sequence writers became one, with
the output folder's path replaced by ``OUT``; the same commands must write the same bytes.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest

from origami_cad.cli import main

ROOT = Path(__file__).resolve().parents[1]

ARM = ["examples/arm_design.toml", "examples/arm_route.toml"]
ROBOT = ["examples/crawler/crawler.toml", "examples/crawler_gait.toml"]
CASES = {
    "arm": (
        ["sequence", *ARM, "-o", "{out}/seq_arm.toml", "--keyframes", "0:0", "10:0.3", "20:0"],
        "seq_arm.toml",
        "cdf81c133abe25a2786bdbc9de49a6ed9aac94098d7dd8aae3fc7082191b684d",
    ),
    "arm-rate": (
        ["sequence", *ARM, "-o", "{out}/seq_arm2.toml", "--keyframes", "0:0", "10:0.3", "20:0",
         "--rate", "20", "--repeat", "3"],
        "seq_arm2.toml",
        "f47c02b3388a447d213fb5951fa581dafcf20f5b2ad860e63953366adc9a4cf1",
    ),
    "robot": (
        ["sequence", *ROBOT, "-o", "{out}/seq_robot.toml"],
        "seq_robot.toml",
        "a1644177cea0357f6f19bc539d6d79d55df1e45fbf822a9bec3e48309b0c675c",
    ),
    "crawl": (
        ["crawl", ROBOT[0], "-o", "{out}/crawl", "--cycles", "1", "--steps", "1"],
        "crawl/gait_sequence.toml",
        "38114dbccced7118fa23cd44e47002b9c0311226bc61dd008c8d6b8b1f7d70b1",
    ),
}  # fmt: skip


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_commands_write_the_sequence_files_they_wrote(name, tmp_path, monkeypatch):
    argv, written, digest = CASES[name]
    monkeypatch.chdir(ROOT)  # the inputs as the examples name them, in the files' headers
    assert main([a.format(out=tmp_path) for a in argv]) == 0
    text = (tmp_path / written).read_text(encoding="utf-8").replace(str(tmp_path), "OUT")
    assert hashlib.sha256(text.encode()).hexdigest() == digest, text[:2000]


def test_the_library_returns_sequences_and_the_writer_reads_back_exactly(tmp_path):
    from origami_cad.crawler.robot import load_robot
    from origami_cad.crawler.walk import gait_sequence
    from origami_cad.drive.sequence import Sequence, dump_sequence, load_sequence

    robot = load_robot(ROOT / "examples" / "crawler" / "crawler.toml")
    seq = gait_sequence(robot, repeat=2, rate=12.5)
    assert isinstance(seq, Sequence) and seq.ids == [leg.servo for leg in robot.legs]
    path = tmp_path / "exact.toml"
    path.write_text(dump_sequence(seq), encoding="utf-8")  # the exact layout: every float
    back = load_sequence(path)
    assert (back.repeat, back.rate, back.current_limit) == (2, 12.5, 1200.0)
    for a, b in zip(back.tsas, seq.tsas, strict=True):
        assert np.array_equal(a.mapping, b.mapping) and a.tsa.length == b.tsa.length
    assert back.keyframes == seq.keyframes


def _gait_with(tmp_path: Path, table: str) -> Path:
    """The example gait file with its [sequence] table replaced."""
    text = (ROOT / ROBOT[1]).read_text(encoding="utf-8")
    start = text.index("[sequence]")
    end = text.index("\n\n", start)
    path = tmp_path / "gait.toml"
    path.write_text(text[:start] + table + text[end:], encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ("[sequence]\nrate = 0", r"\[sequence\]: key 'rate'"),
        ("[sequence]\nrepeat = 1000000000", r"\[sequence\]: key 'repeat'"),
        ("[sequence]\nrate = 10\nspeed = 3", r"unknown key 'speed'"),
    ],
)
def test_sequence_and_drive_refuse_the_same_gait_file(tmp_path, capsys, table, message):
    import re

    gait = _gait_with(tmp_path, table)
    out = tmp_path / "seq.toml"
    assert main(["sequence", ROBOT[0], str(gait), "-o", str(out)]) == 2
    said = capsys.readouterr().err
    assert re.search(message, said) and not out.exists()
    assert main(["drive", str(gait), "--dry-run"]) == 2
    assert re.search(message, capsys.readouterr().err)


def test_sequence_uses_the_gait_files_table_unless_told_otherwise(tmp_path):
    from origami_cad.drive.sequence import load_sequence

    gait = _gait_with(tmp_path, "[sequence]\nrepeat = 4\nrate = 3\ncurrent_limit = 900")
    out = tmp_path / "seq.toml"
    assert main(["sequence", ROBOT[0], str(gait), "-o", str(out)]) == 0
    seq = load_sequence(out)
    assert (seq.repeat, seq.rate, seq.current_limit) == (4, 3.0, 900.0)
    assert main(["sequence", ROBOT[0], str(gait), "-o", str(out), "--rate", "20"]) == 0
    seq = load_sequence(out)
    assert (seq.repeat, seq.rate) == (4, 20.0)
    assert "--rate 20 --repeat 4" in out.read_text(encoding="utf-8")
