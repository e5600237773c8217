"""Real processes interrupted at random moments over an earlier good output leave all the
old outputs or all new ones: ``fabricate``, ``simulate`` and
``drive`` (its log and plot). A file of its own, so that it runs beside the others.

``ORIGAMI_SIGNAL_RUNS`` (default 3) sets the interrupts per command.
"""

from __future__ import annotations

import os
import random
import re
import signal
import subprocess
import time
from pathlib import Path

from test_output_sets import CLI, DRIVE_SEQUENCE, EXAMPLES, SMALL_MIURA


def _state(folder: Path, names) -> dict[str, tuple[int, bytes]]:
    return {n: ((folder / n).stat().st_ino, (folder / n).read_bytes()) for n in names}


def _interrupted_runs(tmp_path: Path, old: list[str], new: list[str], names, runs: int, seed: int):
    """Run ``old`` to completion, then ``new`` ``runs`` times, each sent SIGINT at a random
    moment of its run; after each, every output is the old one or every output is new."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.md").write_text("mine")
    start = time.monotonic()
    subprocess.run(CLI + old, check=True, capture_output=True, timeout=600)
    duration = time.monotonic() - start
    keep = tmp_path / "keep"  # links to the old files: their inodes cannot be reused
    keep.mkdir()
    rng = random.Random(seed)
    seen = set()
    for k in range(runs):
        before = _state(out, names)
        for n in names:
            os.link(out / n, keep / f"{k}-{n}")
        proc = subprocess.Popen(
            CLI + new, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
        )
        time.sleep(rng.uniform(0.3, 1.1) * duration)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=600)
        after = _state(out, names)
        changed = {n for n in names if after[n] != before[n]}
        if proc.returncode == -signal.SIGINT:  # before Python had even imported the program
            assert err == "" and not changed, err
        else:
            assert proc.returncode in (0, 130), err
        said = [s for s in err.splitlines() if not s.startswith("origami-cad: warning: ")]
        assert "Traceback" not in err and len(said) <= 1, err  # the design's warnings aside
        assert changed in (set(), set(names)), (proc.returncode, sorted(changed))
        if proc.returncode == 0:
            assert changed == set(names)
        seen.add(bool(changed))
        assert not list(out.glob(".oc-*")) and (out / "notes.md").read_text() == "mine"
    return out, seen


# interrupts per command: a modest time budget; ORIGAMI_SIGNAL_RUNS=20 for a longer search
SIGNAL_RUNS = int(os.environ.get("ORIGAMI_SIGNAL_RUNS", "3"))


def test_fabricate_interrupted_at_random_moments_leaves_all_old_or_all_new(tmp_path):
    design = tmp_path / "d.toml"
    design.write_text(SMALL_MIURA)
    names = [
        "infills.stl", "midlayers.stl", "shells.stl", "creases.stl", "assembly.step",
        "print.3mf", "fabrication.json", "parts.glb", "panels.png", "pattern_with_holes.fold",
    ]  # fmt: skip
    out = str(tmp_path / "out")
    _interrupted_runs(
        tmp_path, ["fabricate", str(design), "-o", out],
        ["fabricate", str(design), "-o", out, "--bias", "2"], names, SIGNAL_RUNS, seed=32,
    )  # fmt: skip


def test_simulate_interrupted_at_random_moments_leaves_all_old_or_all_new(tmp_path):
    names = ["states.fold", "simulation.json", "fold.gif", "folded.png", "route.png"]
    args = ["simulate", str(EXAMPLES / "miura_6x4.toml"), str(EXAMPLES / "miura_route.toml")]
    out = str(tmp_path / "out")
    _interrupted_runs(
        tmp_path, [*args, "-o", out, "--steps", "3"], [*args, "-o", out, "--steps", "4"],
        names, max(1, SIGNAL_RUNS - 1), seed=33,
    )  # fmt: skip


def test_drive_interrupted_at_random_moments_leaves_all_old_or_all_new(tmp_path):
    """The log and the plot: a stopped run's log says why, and its plot shows what ran."""
    seq = tmp_path / "seq.toml"
    seq.write_text(DRIVE_SEQUENCE)
    out = tmp_path / "out"
    args = ["drive", str(seq), "--dry-run", "--log", str(out / "log.csv")]
    args += ["--plot", str(out / "log.png")]
    out, _ = _interrupted_runs(
        tmp_path, [*args, "--speed", "4"], [*args, "--speed", "1"], ["log.csv", "log.png"],
        max(1, SIGNAL_RUNS - 1), seed=34,
    )  # fmt: skip
    last = (out / "log.csv").read_text().splitlines()[-1]
    assert not last.startswith("#") or re.fullmatch(
        r"# (stopped at .*|not started): interrupted \(Ctrl-C\)", last
    )
