"""The report's 3D views load in headless Chromium, offline, with no console error.

The page is written by the report's own writer (``write_report``) from the glb files
the ``fold`` and ``fabricate`` commands write for a small Miura. Chromium (Debian package
``chromium``) runs it with the network off; the viewer marks each figure it drew with
``data-rendered="ok"`` and counts uncaught errors and ``console.error`` calls in
``<html data-errors>``; Chromium's own log (``--enable-logging=stderr``) is checked for
console messages at error level too.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from html.parser import HTMLParser

import numpy as np
import pytest
from imageio.v3 import imread

from origami_cad.commands import execute
from origami_cad.viz.report import StepReport, write_report

CHROMIUM = next(
    (shutil.which(n) for n in ("chromium", "chromium-browser") if shutil.which(n)), None
)
pytestmark = pytest.mark.skipif(
    CHROMIUM is None, reason="headless Chromium absent (apt-get install -y chromium)"
)


def _chromium(tmp_path, page, *extra: str) -> subprocess.CompletedProcess:
    flags = [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--enable-logging=stderr",
        "--v=0",
        f"--user-data-dir={tmp_path / 'profile'}",
        "--virtual-time-budget=4000",
        "--window-size=1200,800",
    ]
    return subprocess.run(
        [CHROMIUM, *flags, *extra, page.as_uri()], capture_output=True, text=True, timeout=180
    )


class Attributes(HTMLParser):
    """The attributes of <html> and of every figure."""

    def __init__(self) -> None:
        super().__init__()
        self.root: dict[str, str] = {}
        self.figures: list[dict[str, str]] = []

    def handle_starttag(self, tag, attrs):
        if tag == "html":
            self.root = dict(attrs)
        elif tag == "figure":
            self.figures.append(dict(attrs))


@pytest.fixture(scope="module")
def page(tmp_path_factory, small_miura_module):
    out = tmp_path_factory.mktemp("report")
    execute("fold", small_miura_module, out / "folding.glb", ratio=0.9, frames=8)
    execute("fabricate", small_miura_module, out / "parts")
    step = StepReport(
        "miura",
        "A small Miura",
        views=[("folding.glb", "Folding"), ("parts/parts.glb", "Printed parts")],
    )
    return write_report(out / "index.html", [step])


@pytest.fixture(scope="module")
def small_miura_module(tmp_path_factory):
    path = tmp_path_factory.mktemp("design") / "small_miura.toml"
    path.write_text(
        '[pattern]\nkind = "miura"\nrows = 2\ncolumns = 2\npanel_length = 20.0\n'
        "panel_width = 25.0\nsector_angle = 65.0\n"
    )
    return path


def test_the_3d_views_render_with_no_console_error(tmp_path, page):
    done = _chromium(tmp_path, page, "--dump-dom")
    assert done.returncode == 0, done.stderr[-2000:]
    found = Attributes()
    found.feed(done.stdout)
    views = [f for f in found.figures if "oc-view" in f.get("class", "")]
    assert len(views) == 2
    assert [f.get("data-rendered") for f in views] == ["ok", "ok"], views
    width, height = 560, 420
    for f in views:  # each view's model covers a fair part of its canvas
        assert 0.02 * width * height < int(f["data-pixels"]) < 0.9 * width * height
    assert found.root.get("data-errors") == "0", found.root
    assert found.root.get("data-views-rendered") == "2"
    # Chromium logs every console message (at INFO, whatever its level): only the
    # software renderer's performance notes may be there
    console = re.findall(r":CONSOLE[:(]\d+\)?\] (.*)", done.stderr)
    assert not [m for m in console if "GL Driver Message" not in m], console
    assert "Uncaught" not in done.stderr


def test_a_broken_view_is_reported_as_a_console_error(tmp_path):
    """The checks above can fail: a view whose data is not a glb counts one error."""
    (tmp_path / "bad.glb").write_bytes(b"not a glTF binary")
    page = write_report(tmp_path / "index.html", [StepReport("a", "A", views=[("bad.glb", "x")])])
    done = _chromium(tmp_path, page, "--dump-dom")
    found = Attributes()
    found.feed(done.stdout)
    assert found.root.get("data-errors") == "1"
    assert [f.get("data-rendered") for f in found.figures] == ["error"]
    assert re.search(r":CONSOLE[:(]\d+\)?\] \"3D view 0: not a glb file\"", done.stderr)


def test_the_page_loads_nothing_from_the_network(page):
    text = page.read_text()
    assert "://" not in re.sub(r"<script type='application/octet-stream'.*?</script>", "", text)
    assert "<script src" not in text


def test_a_screenshot_shows_the_parts_in_their_colours(tmp_path, page):
    shot = tmp_path / "shot.png"
    done = _chromium(tmp_path, page, f"--screenshot={shot}")
    assert done.returncode == 0 and shot.is_file(), done.stderr[-2000:]
    rgb = imread(shot)[..., :3].astype(int)
    red = (rgb[..., 0] > 150) & (rgb[..., 1] < 110) & (rgb[..., 2] < 110)  # TPU shells
    cream = (np.abs(rgb - [242, 230, 201]).sum(-1) < 60) & (rgb.sum(-1) < 3 * 250)  # panels
    assert red.sum() > 500 and cream.sum() > 500
