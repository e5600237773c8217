"""What a new user meets first: an install without the ``viz`` extra (no pyvista, no VTK)."""

from __future__ import annotations

import json
import subprocess
import sys

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
    """Fabrication (STL, STEP, 3MF, glb) and the 2D plots work; a 3D render refuses in one
    line naming the extra (about 5 s of CPU)."""
    fab, cp, folded = tmp_path / "fab", tmp_path / "cp.png", tmp_path / "folded.png"
    d = str(small_miura_toml)
    argv = {
        "fabricate": ["fabricate", d, "-o", str(fab)],
        "pattern": ["pattern", d, "-o", str(cp)],
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
    assert codes["fabricate"] == 0 and codes["pattern"] == 0, run.stderr
    for name in ("assembly.step", "print.3mf", "shells.stl", "panels.png", "parts.glb"):
        assert (fab / name).stat().st_size > 0, name
    assert cp.read_bytes()[:4] == b"\x89PNG"
    # the 3D render: one line naming the extra, exit 2, nothing written
    assert codes["fold"] == 2 and not folded.exists()
    errors = [line for line in run.stderr.splitlines() if line.startswith("origami-cad:")]
    assert len(errors) == 1 and "pip install 'origami-cad[viz]'" in errors[0], run.stderr
    assert "Traceback" not in run.stderr
    message, is_import_error = codes["library"]
    assert "origami-cad[viz]" in message and "pyvista" in message and is_import_error
