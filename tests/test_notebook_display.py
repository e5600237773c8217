"""The curated objects in a notebook: short reprs, SVG patterns, 3D views, PNG stills.

What Jupyter calls (``repr``, ``_repr_svg_``, ``_repr_html_``, ``_repr_png_``) is called
here on real objects, and what it returns is read back: the SVG as XML, the view's glb
decoded from the page and its vertices compared with the folded state's, the PNG's size
and ink. The viewer runs in headless Chromium on a page of two notebook outputs.
"""

from __future__ import annotations

import base64
import io
import json
import re
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from imageio.v3 import imread

import origami_cad as oc
from origami_cad.kinematics.folding import FoldedState


@pytest.fixture(scope="module")
def design():
    return oc.miura_design(2, 3, 20.0, 25.0, 65.0)


@pytest.fixture(scope="module")
def fab(design):
    return oc.fabricate(design)


def _glb_positions(html: str) -> np.ndarray:
    """The panels' vertices (mm) of the first glb embedded in a view's HTML."""
    data = re.search(r"class='oc-glb'>\n(.*?)\n</script>", html, re.S).group(1)
    glb = base64.b64decode("".join(data.split()))
    assert glb[:4] == b"glTF"
    (length,) = struct.unpack("<I", glb[12:16])
    doc = json.loads(glb[20 : 20 + length])
    binary = glb[20 + length + 8 :]
    mesh = next(m for m in doc["meshes"] if m["name"] == "panels")
    acc = doc["accessors"][mesh["primitives"][0]["attributes"]["POSITION"]]
    view = doc["bufferViews"][acc["bufferView"]]
    raw = binary[view["byteOffset"] : view["byteOffset"] + view["byteLength"]]
    return np.frombuffer(raw, dtype=np.float32).reshape(acc["count"], 3)


def test_reprs_are_one_short_line_with_the_key_figures(design, fab):
    state = oc.fold_design(design, 0.4)
    general = oc.fold(design.pattern, 0.3, method="general")
    for obj in (design, state, general, fab, fab.plan, fab.parts, design.pattern):
        text = repr(obj)
        assert "\n" not in text and len(text) < 300, text
        assert "array(" not in text and "object at 0x" not in text, text
    assert "p=0.4 (closed form)" in repr(state)
    assert "(general)" in repr(general) and f"{general.strain:.2g} %" in repr(general)
    lo, hi = state.fold_angles.min(), state.fold_angles.max()
    assert f"{lo:.1f} to {hi:.1f} deg" in repr(state)
    assert f"{len(fab.plan.outlines)} panels" in repr(fab)
    assert f"{len(fab.holes)} holes" in repr(fab)
    solids = sum(len(v) for v in fab.parts.solids.values())
    assert f"{solids} solids" in repr(fab)
    assert repr(design.pattern) in repr(design) and "miura" in repr(design)


def test_a_pattern_and_a_design_show_as_svg(design):
    svg = design._repr_svg_()
    root = ET.fromstring(svg)
    assert root.tag.endswith("svg")
    assert svg.count("<path") == design.pattern._repr_svg_().count("<path")
    # a larger pattern draws more lines: the picture is the pattern's, not a fixed one
    bigger = oc.miura_design(4, 6, 20.0, 25.0, 65.0)._repr_svg_()
    assert bigger.count("<path") > svg.count("<path")


def test_a_folded_state_shows_its_own_glb_in_the_viewer(design):
    state = oc.fold_design(design, 0.6)
    assert state.pattern is design.pattern
    html = state._repr_html_()
    assert "<figure class='oc-view'>" in html and "window.ocGlbViewer" in html
    positions = _glb_positions(html)
    assert np.allclose(positions, state.coords, atol=1e-3)
    flat = oc.fold_design(design, 0.0)
    assert not np.allclose(_glb_positions(flat._repr_html_()), positions, atol=1e-3)


def test_a_state_without_its_pattern_offers_no_picture(design):
    state = oc.fold_design(design, 0.5)
    bare = FoldedState(state.p, state.coords, state.fold_angles)
    assert bare._repr_html_() is None and bare._repr_png_() is None
    assert "p=0.5" in repr(bare)


def _ink(png: bytes) -> float:
    image = imread(io.BytesIO(png))
    assert image.shape[:2] == (600, 800)
    return float(np.mean(np.any(image[..., :3] < 235, axis=2)))


def test_png_stills_with_pyvista_and_without(design, fab, monkeypatch):
    state = oc.fold_design(design, 0.5)
    rendered = state._repr_png_()
    assert rendered[:8] == b"\x89PNG\r\n\x1a\n" and 0.01 < _ink(rendered) < 0.9
    assert 0.01 < _ink(fab._repr_png_()) < 0.9
    monkeypatch.setitem(sys.modules, "pyvista", None)  # as without the viz extra
    drawn = state._repr_png_()
    assert drawn != rendered and 0.01 < _ink(drawn) < 0.9
    assert 0.01 < _ink(fab._repr_png_()) < 0.9


def test_a_fabrication_shows_its_parts_and_hands_viewers_its_assembly(fab):
    html = fab._repr_html_()
    assert "<figure class='oc-view'>" in html and "printed parts" in html
    # ocp_vscode (ocp_tessellate) takes an object with _obj, _obj_name and _tag as a
    # build123d builder, and draws getattr(obj, obj._obj_name) (BuildPart().part)
    assert all(hasattr(fab, n) for n in ("_obj", "_obj_name", "_tag"))
    part = getattr(fab, fab._obj_name)
    assert part is fab._obj is fab.part  # made once
    assert hasattr(part, "wrapped") and len(part.children) == len(fab.plan.outlines) + 1
    volume = sum(fab.volumes().values())
    assert part.volume == pytest.approx(volume, rel=1e-3)


def test_oc_show_draws_a_folded_state_alone(design):
    image = oc.show(oc.fold_design(design, 0.5), mode="offscreen", window_size=(400, 300))
    assert image.shape == (300, 400, 3)
    assert np.mean(np.any(image < 235, axis=2)) > 0.01


def test_importing_the_stages_loads_no_drawing_library():
    code = (
        "import sys, origami_cad.kinematics.folding, origami_cad.fabrication.build\n"
        "print(sorted(m for m in ('matplotlib', 'pyvista', 'origami_cad.viz') "
        "if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


CHROMIUM = next(
    (shutil.which(n) for n in ("chromium", "chromium-browser") if shutil.which(n)), None
)


@pytest.mark.skipif(CHROMIUM is None, reason="headless Chromium absent")
def test_two_notebook_outputs_each_render_once(tmp_path, design, fab):
    """A notebook puts each output's HTML (its figure and the viewer's script) in the page:
    every figure is drawn, once, with no console error."""
    outputs = [oc.fold_design(design, 0.7)._repr_html_(), fab._repr_html_()]
    page = tmp_path / "notebook.html"
    body = "".join(f"<div class='output'>{h}</div>" for h in outputs)
    page.write_text(f"<!DOCTYPE html><html><head><meta charset='utf-8'></head><body>{body}")
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
             "--enable-unsafe-swiftshader", "--no-first-run", "--disable-background-networking",
             f"--user-data-dir={tmp_path / 'profile'}", "--virtual-time-budget=4000",
             "--dump-dom"]  # fmt: skip
    done = subprocess.run(
        [CHROMIUM, *flags, page.as_uri()], capture_output=True, text=True, timeout=180
    )
    assert done.returncode == 0, done.stderr[-2000:]
    rendered = re.findall(r"<figure class=\"oc-view\"[^>]*data-rendered=\"(\w+)\"", done.stdout)
    assert rendered == ["ok", "ok"], done.stdout[-3000:]
    assert 'data-errors="0"' in done.stdout
    assert 'data-views-rendered="2"' in done.stdout
