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


def _not_warnings(stderr: str) -> str:
    """stderr without the design's warnings (they come before the failure's one line)."""
    return "".join(s for s in stderr.splitlines(True) if not s.startswith("origami-cad: warning:"))


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
    assert result["code"] == 2 and len(_not_warnings(err).splitlines()) == 1, err
    assert f"{result['folder']}/fab/" in err and "the folder's old files are kept" in err, err
    assert {k: v for k, v in result["after"].items() if k != ".fill"} == old


#: The child: ``fabricate`` twice into a folder holding an older set, a SIGINT delivered
#: by a hook on the rename of the set's ``when``-th file (``last``: after the whole set).
INTERRUPTED = r"""
import contextlib, io, json, os, signal, sys
from pathlib import Path
from origami_cad.cli import main
design, folder = sys.argv[1], Path(sys.argv[2]).resolve()
real, results = os.replace, {}
def hooked(src, dst, *a, **k):
    real(src, dst, *a, **k)
    into = Path(dst).parent == folder and not str(src).endswith(".old")
    done = Path(dst).name == "journal.json" and json.loads(Path(dst).read_text())["state"] == "done"
    hooked.n += into
    if (when == "last" and done) or hooked.n == when:
        os.kill(os.getpid(), signal.SIGINT)
os.replace = hooked
for when in (3, "last"):
    hooked.n = 0
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["fabricate", design, "-o", str(folder), "--bias", str(len(results) + 2)])
    files = {p.name: [p.stat().st_ino, p.read_bytes().hex()] for p in folder.iterdir()}
    results[str(when)] = {"code": code, "stderr": err.getvalue(), "files": files}
    os.replace = hooked
print(json.dumps(results))
"""


def test_ctrl_c_while_fabricate_installs_its_set_rolls_back_or_completes(tmp_path):
    """A SIGINT between two renames of the set: the old set comes back, exit 130 and
    'nothing more was written'; one after the last rename: the whole new set, exit 130
    naming the folder written in full. Never a mix, never a silent exit 0."""
    design = tmp_path / "d.toml"
    design.write_text(SMALL_MIURA)
    folder = tmp_path / "fab"
    assert subprocess.run(
        [sys.executable, "-m", "origami_cad.cli", "fabricate", str(design), "-o", str(folder)],
        capture_output=True, timeout=300, cwd=ROOT,
    ).returncode == 0  # fmt: skip
    (folder / "notes.md").write_text("mine")
    before = {p.name: (p.stat().st_ino, p.read_bytes()) for p in folder.iterdir()}
    run = subprocess.run(
        [sys.executable, "-c", INTERRUPTED, str(design), str(folder)],
        capture_output=True, text=True, timeout=300, cwd=ROOT,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    results = json.loads(run.stdout.splitlines()[-1])
    middle, last = results["3"], results["last"]
    assert middle["code"] == 130 and last["code"] == 130
    assert _not_warnings(middle["stderr"]) == "origami-cad: interrupted; nothing more was written\n"
    assert {k: (i, bytes.fromhex(v)) for k, (i, v) in middle["files"].items()} == before
    assert _not_warnings(last["stderr"]) == (
        f"origami-cad: interrupted after writing {folder} in full; nothing more was written\n"
    )
    after = {k: (i, bytes.fromhex(v)) for k, (i, v) in last["files"].items()}
    assert after.keys() == before.keys() and after["notes.md"] == before["notes.md"]
    replaced = {k for k in before if after[k][0] != before[k][0]}  # a new file, by its inode
    assert replaced == set(before) - {"notes.md"}, replaced
    assert after["fabrication.json"][1] != before["fabrication.json"][1]  # --bias 3


@pytest.mark.parametrize(
    "argv",
    [
        ["pattern", f"{EX}/miura_6x4.toml", "-o", "/dev/stdout"],
        ["convert", f"{EX}/data/boat.dxf", "/dev/stdout"],
        ["fold", f"{EX}/fig2_tg.toml", "--frames", "2", "-o", "/dev/stdout"],
    ],
)
def test_dev_stdout_takes_the_first_format_and_the_messages_go_to_stderr(argv):
    run = subprocess.run(
        [sys.executable, "-m", "origami_cad.cli", *argv],
        capture_output=True, text=True, timeout=120, cwd=ROOT,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    data = json.loads(run.stdout)  # a FOLD file, and nothing else
    assert data["file_spec"] and len(data["vertices_coords"]) > 3
    assert "wrote /dev/stdout" in run.stderr
    assert os.path.islink("/dev/stdout")


def test_an_output_that_is_a_hard_link_to_the_input_is_refused(tmp_path, capsys):
    from origami_cad.cli import main

    source = tmp_path / "p.fold"
    assert main(["convert", f"{EX}/data/boat.dxf", str(source)]) == 0
    before = source.read_bytes()
    os.link(source, tmp_path / "h.fold")
    capsys.readouterr()
    assert main(["convert", str(source), str(tmp_path / "h.fold"), "--width", "50"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "h.fold" in err and "hard link" in err, err
    assert source.read_bytes() == before
    # a design naming the pattern: a hard link to that pattern is refused too
    design = tmp_path / "d.toml"
    design.write_text('[pattern]\nkind = "file"\npath = "p.fold"\n')
    assert main(["fold", str(design), "-o", str(tmp_path / "h.fold")]) == 2
    assert "hard link" in capsys.readouterr().err and source.read_bytes() == before


@pytest.mark.parametrize("where", [".", "sub"])
def test_demo_refuses_to_write_among_its_inputs(tmp_path, monkeypatch, capsys, where):
    import origami_cad.demo
    from origami_cad.cli import main

    examples = tmp_path / "examples"
    examples.mkdir()
    (examples / "fig2_tg.toml").write_text((EX / "fig2_tg.toml").read_text())
    monkeypatch.setattr(origami_cad.demo, "examples_dir", lambda: examples)
    out = examples / where
    assert main(["demo", "-o", str(out), "--quick"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "examples" in err and "inputs" in err, err
    assert sorted(p.name for p in examples.iterdir()) == ["fig2_tg.toml"]
