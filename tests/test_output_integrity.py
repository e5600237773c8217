"""Every output is complete or absent: a write the file system refuses (a full disk, a
file over the size limit) exits 2 with one line naming the file, and the old file stays
byte for byte.

Each case runs the real command in a child process whose output folder is a tiny file
system: a tmpfs of a few hundred KB mounted in a private mount namespace (``unshare
-m``, as root), filled up after the old file was put there. Where that cannot be done,
the child's file size limit (``RLIMIT_FSIZE``) is set to 0 instead: every write of a byte
fails with ``EFBIG``, a real error of the kernel. Where neither can be set, the test is
skipped, saying why.
"""

from __future__ import annotations

import json
import os
import resource
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
SMALL_MIURA = (
    '[pattern]\nkind = "miura"\nrows = 2\ncolumns = 2\npanel_length = 20.0\n'
    "panel_width = 25.0\nsector_angle = 65.0\n"
)

#: The child: make the folder tiny, put the old files, fill it, run the command in-process.
CHILD = r"""
import json, os, resource, signal, subprocess, sys
spec = json.loads(sys.argv[1])
folder = spec["folder"]
if spec["mode"] == "tmpfs":
    subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={spec['size_kb']}k", "tmpfs", folder],
                   check=True)
for rel, data in spec["old"].items():
    path = os.path.join(folder, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as fh:
        fh.write(bytes.fromhex(data))
from origami_cad.cli import main  # imported before the disk is full
import origami_cad.commands  # noqa: F401 (every command registered)
if spec["mode"] == "tmpfs":
    with open(os.path.join(folder, ".fill"), "wb", buffering=0) as fh:  # a user's file
        try:
            while True:
                fh.write(b"\0" * 4096)
        except OSError:
            pass
    fill = os.path.join(folder, ".fill")
    os.truncate(fill, max(0, os.path.getsize(fill) - spec["free_kb"] * 1024))
else:  # joblib's warning that it cannot make its own files is no output of ours
    import warnings
    warnings.simplefilter("ignore")
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (spec["fsize"], resource.RLIM_INFINITY))
import contextlib, io
err = io.StringIO()
with contextlib.redirect_stderr(err):
    code = main(spec["argv"])
after = {}
for base, dirs, files in os.walk(folder):
    for name in files:
        path = os.path.join(base, name)
        with open(path, "rb") as fh:
            after[os.path.relpath(path, folder)] = fh.read().hex()
print(json.dumps({"code": code, "stderr": err.getvalue(), "after": after}))
"""


def _mode() -> tuple[str | None, str]:
    """How the child's disk is made tiny here, or ``None`` and why not."""
    if shutil.which("unshare") and shutil.which("mount"):
        probe = subprocess.run(
            ["unshare", "-m", "sh", "-c", "mount -t tmpfs -o size=4k tmpfs /mnt"],
            capture_output=True,
            timeout=30,
        )
        if probe.returncode == 0:
            return "tmpfs", ""
    try:
        resource.getrlimit(resource.RLIMIT_FSIZE)
    except (AttributeError, OSError) as exc:  # pragma: no cover - not on Linux
        return None, f"neither a private tmpfs nor a file size limit can be set here ({exc})"
    return "fsize", ""


MODE, WHY = ("fsize", "") if os.environ.get("ORIGAMI_TINY_DISK") == "fsize" else _mode()


def full_disk_run(tmp_path: Path, argv: list[str], old: dict[str, bytes], **kw) -> dict:
    """Run ``origami-cad argv`` (``OUT`` is the tiny folder) over the ``old`` files.

    ``size_kb``, ``free_kb``: the tmpfs and what is left free on it; ``fsize``: the
    file size limit, bytes, where there is no tmpfs. Returns the exit ``code``, the
    ``stderr`` and the files ``after`` (bytes by name, the filler ``.fill`` among them).
    """
    if MODE is None:
        pytest.skip(WHY)
    folder = tmp_path / "out"
    folder.mkdir()
    spec = {
        "folder": str(folder),
        "mode": MODE,
        "size_kb": kw.get("size_kb", 256),
        "free_kb": kw.get("free_kb", 0),
        "fsize": kw.get("fsize", 0),
        "old": {k: v.hex() for k, v in old.items()},
        "argv": [a.replace("OUT", str(folder)) for a in argv],
    }
    cmd = [sys.executable, "-c", CHILD, json.dumps(spec)]
    if MODE == "tmpfs":
        cmd = ["unshare", "-m", *cmd]
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert run.returncode == 0, run.stderr
    result = json.loads(run.stdout.splitlines()[-1])
    result["after"] = {k: bytes.fromhex(v) for k, v in result["after"].items()}
    result["folder"] = folder
    return result


def _assert_refused(result: dict, named: str, old: dict[str, bytes]) -> None:
    """Exit 2, one line naming ``named`` (inside the output folder), the old files as
    they were and nothing else left behind."""
    err = result["stderr"]
    assert result["code"] == 2, err
    assert err.count("\n") == 1 and err.startswith("origami-cad: error: "), err
    assert f"{result['folder']}/{named}: cannot be written" in err, err
    expected = "File too large" if MODE == "fsize" else "No space left on device"
    assert expected in err, err
    after = {k: v for k, v in result["after"].items() if k != ".fill"}
    assert after == old  # byte for byte, and no temporary file, no half-written new one


CASES = {
    "fold-gif": (["fold", f"{EX}/fig2_tg.toml", "--frames", "2", "-o", "OUT/a.gif"], "a.gif"),
    "fold-png": (["fold", f"{EX}/fig2_tg.toml", "-o", "OUT/a.png"], "a.png"),
    "pattern-png": (["pattern", f"{EX}/miura_6x4.toml", "-o", "OUT/x.png"], "x.png"),
    "pattern-fold": (["pattern", f"{EX}/miura_6x4.toml", "-o", "OUT/x.fold"], "x.fold"),
    "pattern-svg": (["pattern", f"{EX}/miura_6x4.toml", "-o", "OUT/x.svg"], "x.svg"),
    "pattern-dxf": (["pattern", f"{EX}/miura_6x4.toml", "-o", "OUT/x.dxf"], "x.dxf"),
    "convert-json": (["convert", f"{EX}/data/boat.dxf", "OUT/b.fold"], "b.fold"),
    "sequence-toml": (
        [
            "sequence",
            f"{EX}/arm_design.toml",
            f"{EX}/arm_route.toml",
            "-o",
            "OUT/seq.toml",
            "--keyframes",
            "0:0",
            "10:0.3",
            "20:0",
        ],
        "seq.toml",
    ),
}


@pytest.mark.parametrize("case", CASES)
def test_a_full_disk_exits_2_naming_the_file_and_keeps_the_old_one(tmp_path, case):
    argv, name = CASES[case]
    old = {name: b"the user's own " + name.encode() + b", kept byte for byte\n"}
    _assert_refused(full_disk_run(tmp_path, argv, old), name, old)


def test_a_gif_cut_short_by_the_disk_keeps_the_old_one(tmp_path):
    """Room for part of the GIF: the write fails in the middle, not at its first byte."""
    if MODE != "tmpfs":
        pytest.skip("a disk with a few KB free needs the private tmpfs")
    argv, name = CASES["fold-gif"]
    old = {name: bytes(range(256)) * 8}
    _assert_refused(full_disk_run(tmp_path, argv, old, free_kb=12), name, old)


def test_fabricate_on_a_full_disk_keeps_the_old_set(tmp_path):
    design = tmp_path / "d.toml"
    design.write_text(SMALL_MIURA)
    old = {
        "fab/fabrication.json": b'{"old": true}\n',
        "fab/print.3mf": b"old 3mf",
        "fab/notes.md": b"mine",
    }
    argv = ["fabricate", str(design), "-o", "OUT/fab"]
    result = full_disk_run(tmp_path, argv, old, size_kb=1024, free_kb=64)
    err = result["stderr"]
    assert result["code"] == 2 and err.count("\n") == 1, err
    assert f"{result['folder']}/fab/" in err and "the folder's old files are kept" in err, err
    assert {k: v for k, v in result["after"].items() if k != ".fill"} == old
