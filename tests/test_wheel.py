"""The demo runs from a wheel installed in a fresh venv, outside the tree.

The wheel is built from this checkout (``pip wheel --no-deps``), installed into a new
venv whose only link to the current environment is a ``.pth`` file naming the current
site-packages (where the dependencies live: the package itself must come from the wheel),
and a demo step is run as a user would, from an empty folder.
"""

from __future__ import annotations

import os
import re
import shutil
import site
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# runs in the installed venv: where the package and its examples come from, then one step
# of the demo (Fig. 2: pattern, TG, folded states and a GIF) into ./out
STEP = """
import json, sys
from pathlib import Path
import origami_cad
from origami_cad.demo import STEPS, examples_dir, run_step
step = next(s for s in STEPS if s.key == "fig2")
rep = run_step(step, Path("out"), quick=True)
print(json.dumps({"package": origami_cad.__file__, "examples": str(examples_dir()),
                  "error": rep.error, "images": [p for p, _ in rep.images],
                  "files": rep.files}))
"""


def _clean_env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    env["MPLBACKEND"] = "Agg"
    return env


def _dependency_paths() -> list[str]:
    """The current environment's site-packages folders, where the dependencies are."""
    found = [*site.getsitepackages(), sysconfig.get_paths()["purelib"]]
    found += [p for p in sys.path if p.endswith("site-packages")]
    return [p for p in dict.fromkeys(found) if Path(p).is_dir() and Path(p) != ROOT]


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """A fresh venv with only the wheel built from this checkout installed into it."""
    tmp = tmp_path_factory.mktemp("wheel")
    # a copy of what a source distribution holds, so the build's scratch files stay in tmp
    src = tmp / "src"
    skip = shutil.ignore_patterns("__pycache__", "*.egg-info", "build")
    for name in ("origami_cad", "parts", "examples"):
        shutil.copytree(ROOT / name, src / name, ignore=skip)
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy2(ROOT / name, src / name)
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check", "--no-input"]
    # the build backend comes from the current environment (setuptools >= 77, the [test]
    # extra): no download
    # verbose: the build backend's own output (its warnings) is shown
    build = subprocess.run(
        [*pip, "wheel", "-v", "--no-deps", "--no-build-isolation", "-w", str(tmp / "dist"), src],
        check=True,
        capture_output=True,
        text=True,
        env=_clean_env(),
        cwd=tmp,
    )
    (tmp / "build.log").write_text(build.stdout + build.stderr)
    (wheel,) = (tmp / "dist").glob("origami_cad-*.whl")
    venv = tmp / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    purelib = subprocess.run(
        [python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout.strip()
    subprocess.run(
        [
            *pip,
            "--python",
            str(python),
            "install",
            "--no-deps",
            "--no-index",
            "--no-compile",
            str(wheel),
        ],
        check=True,
        capture_output=True,
        env=_clean_env(),
    )
    # only then the dependencies (so that pip never sees, nor tries to replace, the current
    # environment's origami-cad), appended after the venv's own site-packages: the wheel's
    # package wins
    Path(purelib, "zz_dependencies.pth").write_text("\n".join(_dependency_paths()) + "\n")
    return wheel, venv, Path(purelib)


def test_the_wheel_builds_without_a_warning(installed):
    wheel, _, _ = installed
    log = (wheel.parent.parent / "build.log").read_text()
    assert "running bdist_wheel" in log  # the backend's own output was read
    warnings = [line for line in log.splitlines() if re.search(r"warning", line, re.I)]
    assert not warnings, "\n".join(warnings)


def test_the_wheel_ships_py_typed_and_the_licence(installed):
    wheel, _, purelib = installed
    names = set(zipfile.ZipFile(wheel).namelist())
    assert "origami_cad/py.typed" in names
    (licence,) = [n for n in names if n.endswith(".dist-info/licenses/LICENSE")]
    text = zipfile.ZipFile(wheel).read(licence).decode()
    assert text.startswith("MIT License") and text == (ROOT / "LICENSE").read_text()
    meta = zipfile.ZipFile(wheel).read(licence.replace("licenses/LICENSE", "METADATA")).decode()
    assert "License-Expression: MIT" in meta and "License-File: LICENSE" in meta
    assert "Provides-Extra: viz" in meta and "Requires-Dist: pyvista" in meta
    urls = dict(
        line.removeprefix("Project-URL: ").split(", ", 1)
        for line in meta.splitlines()
        if line.startswith("Project-URL: ")
    )
    assert {"Homepage", "Documentation", "Source", "Issues", "Changelog"} <= set(urls)
    assert all(u.startswith("https://") for u in urls.values()), urls
    base = [line for line in meta.splitlines() if line.startswith("Requires-Dist: pyvista")]
    assert all("extra ==" in line for line in base), base  # only through an extra
    assert (purelib / "origami_cad" / "py.typed").is_file()


def test_the_wheel_ships_the_examples_the_demo_reads(installed):
    wheel, _, _ = installed
    names = set(zipfile.ZipFile(wheel).namelist())
    tree = {
        "origami_cad/examples/" + p.relative_to(ROOT / "examples").as_posix()
        for p in (ROOT / "examples").rglob("*")
        if p.is_file() and "__pycache__" not in p.parts
    }
    assert tree <= names, sorted(tree - names)
    assert "origami_cad/parts/tsa_module.py" in names
    assert not any(n.startswith(("examples/", "parts/", "tests/")) for n in names)


def test_the_demo_runs_from_the_installed_wheel_outside_the_tree(installed, tmp_path):
    import json

    _, venv, purelib = installed
    work = tmp_path / "user"
    work.mkdir()
    cli = subprocess.run(
        [venv / "bin" / "origami-cad", "demo", "--help"],
        capture_output=True,
        text=True,
        env=_clean_env(),
        cwd=work,
    )
    assert cli.returncode == 0 and "--quick" in cli.stdout, cli.stderr
    run = subprocess.run(
        [venv / "bin" / "python", "-c", STEP],
        capture_output=True,
        text=True,
        env=_clean_env(),
        cwd=work,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    done = json.loads(run.stdout.strip().splitlines()[-1])
    # the package and its examples are the wheel's, in the venv, not this checkout
    assert Path(done["package"]).is_relative_to(purelib), done["package"]
    assert Path(done["examples"]) == purelib / "origami_cad" / "examples"
    assert not done["error"], done["error"]
    assert "fig2/folding.gif" in done["images"] and "fig2/pattern.fold" in done["files"]
    assert (work / "out" / "fig2" / "folding.gif").read_bytes()[:3] == b"GIF"
    folded = json.loads((work / "out" / "fig2" / "pattern.fold").read_text())
    assert len(folded["vertices_coords"]) > 10
