"""What a new user meets first: ``python -m origami_cad``, the README's quick start, and an
install without the ``viz`` extra (no pyvista, no VTK)."""

from __future__ import annotations

import contextlib
import io
import json
import re
import subprocess
import sys
from pathlib import Path

import origami_cad

ROOT = Path(__file__).resolve().parents[1]


def test_python_dash_m_runs_the_command_line(tmp_path):
    version = subprocess.run(
        [sys.executable, "-m", "origami_cad", "--version"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert version.returncode == 0, version.stderr
    assert version.stdout.strip() == f"origami-cad {origami_cad.__version__}"
    missing = tmp_path / "missing.toml"
    bad = subprocess.run(
        [sys.executable, "-m", "origami_cad", "pattern", str(missing), "-o", "cp.png"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    assert bad.returncode == 2
    assert bad.stderr.count("\n") == 1 and str(missing) in bad.stderr, bad.stderr
    assert not (tmp_path / "cp.png").exists()


def _quick_start() -> str:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text.split("## Ten lines of Python", 1)[1]
    return re.search(r"```python\n(.*?)```", section, flags=re.S).group(1)


def test_the_readme_quick_start_prints_the_creases_fold_angles(tmp_path, monkeypatch):
    """The quick start uses the curated names and prints each kind of crease's fold angles
    (mountains negative, valleys positive, the main creases at p * 180 deg)."""
    code = _quick_start()
    assert "import origami_cad as oc" in code and "from origami_cad" not in code
    monkeypatch.chdir(tmp_path)
    shown = io.StringIO()
    namespace: dict = {}
    with contextlib.redirect_stdout(shown):
        exec(compile(code, "README.md", "exec"), namespace)
    lines = shown.getvalue().splitlines()
    found = {}
    for line in lines:
        kind, n, lo, hi = re.fullmatch(r"(\w): (\d+) creases, (\S+) to (\S+) deg", line).groups()
        found[kind] = (int(n), float(lo), float(hi))
    assert set(found) == {"M", "V"}, lines
    cp, state = namespace["cp"], namespace["state"]
    assert found["M"][0] + found["V"][0] == int((cp.assignments != "B").sum())
    assert found["M"][2] < 0 < found["V"][1]  # signs: valley positive
    main = 180.0 * state.p  # the main creases fold to p * pi
    assert found["M"][1] <= -main + 0.05 and found["V"][2] >= main - 0.05
    assert found["M"][2] == -round(main, 1) and found["V"][1] == round(main, 1)
    assert origami_cad.read_pattern(tmp_path / "out" / "fig2.fold").n_vertices == cp.n_vertices


# runs in a fresh interpreter where pyvista and VTK cannot be imported, as without the extra
NO_VIZ = """
import json, sys
sys.modules["pyvista"] = None
sys.modules["vtkmodules"] = None
from origami_cad.cli import main
from origami_cad.errors import ExtraError
from origami_cad.viz.render3d import import_pyvista
runs = {}
for name, argv in json.loads(sys.argv[1]).items():
    runs[name] = main(argv)
    print("---", flush=True)
try:
    import_pyvista()
    runs["library"] = "imported"
except ExtraError as exc:
    runs["library"] = [str(exc), isinstance(exc, ImportError)]
print(json.dumps(runs))
"""


def test_without_the_viz_extra_only_3d_renders_refuse(tmp_path, small_miura_toml):
    """Fabrication (STL, STEP, 3MF), the glb files and the 2D plots work; a 3D render refuses in one
    line naming the extra (about 5 s of CPU)."""
    fab, cp, folded = tmp_path / "fab", tmp_path / "cp.png", tmp_path / "folded.png"
    glb = tmp_path / "folding.glb"
    d = str(small_miura_toml)
    argv = {
        "fabricate": ["fabricate", d, "-o", str(fab)],
        "pattern": ["pattern", d, "-o", str(cp)],
        "glb": ["fold", d, "--ratio", "0.5", "--frames", "3", "-o", str(glb)],
        "fold": ["fold", d, "--ratio", "0.5", "-o", str(folded)],
    }
    run = subprocess.run(
        [sys.executable, "-c", NO_VIZ, json.dumps(argv)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    codes = json.loads(run.stdout.strip().splitlines()[-1])
    assert codes["fabricate"] == 0 and codes["pattern"] == 0 and codes["glb"] == 0, run.stderr
    for name in ("assembly.step", "print.3mf", "shells.stl", "panels.png", "parts.glb"):
        assert (fab / name).stat().st_size > 0, name
    assert cp.read_bytes()[:4] == b"\x89PNG" and glb.read_bytes()[:4] == b"glTF"
    # the 3D render: one line naming the extra, exit 2, nothing written
    assert codes["fold"] == 2 and not folded.exists()
    errors = [line for line in run.stderr.splitlines() if line.startswith("origami-cad: error:")]
    assert len(errors) == 1 and "pip install 'origami-cad[viz]'" in errors[0], run.stderr
    assert "Traceback" not in run.stderr
    message, is_import_error = codes["library"]
    assert "origami-cad[viz]" in message and "pyvista" in message and is_import_error
