"""Sequence files: one writer, byte for byte what the commands wrote before it.

The SHA-256 digests below are of the files ``sequence`` (an arm's route, a robot's gait)
and ``crawl`` wrote on the examples before the three sequence writers became one, with
the output folder's path replaced by ``OUT``; the same commands must write the same bytes.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

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
