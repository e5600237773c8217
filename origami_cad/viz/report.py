"""The HTML report of the demo: one self-contained page, a section per step.

3D views (``StepReport.views``: glb files written by :mod:`origami_cad.viz.gltf`) are
embedded in the page as base64 and drawn by a small WebGL viewer shipped with the
package (``glb_viewer.js``, inlined): the page needs no network and no server.
"""

from __future__ import annotations

import base64
import importlib.resources
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from origami_cad._fileio import atomic_write
from origami_cad._names import html_text

__all__ = ["MAX_EMBEDDED_BYTES", "StepReport", "view_figure", "viewer_script", "write_report"]

#: The glb bytes a page embeds at most, all views together; further views are linked.
MAX_EMBEDDED_BYTES = 3_000_000


@dataclass
class StepReport:
    """What one demo step shows: pictures, key numbers and every file it wrote.

    Paths are relative to the report's folder.
    """

    key: str
    title: str
    summary: str = ""
    images: list[tuple[str, str]] = field(default_factory=list)  # (path, caption)
    numbers: list[tuple[str, str]] = field(default_factory=list)  # (name, value with unit)
    files: list[str] = field(default_factory=list)
    views: list[tuple[str, str]] = field(default_factory=list)  # (glb path, caption)
    seconds: float = 0.0
    error: str = ""
    columns: int = 0  # images per row (a gallery: 3); 0: as many as fit


#: characters an HTML page cannot hold (C0 controls but tab/newline/return, DEL, lone
#: surrogates): replaced by U+FFFD so that no message breaks the page or its encoding


_text = html_text  # any text made safe for HTML content and quoted attributes


def _href(path: str) -> str:
    """A relative link: a path that looks like a URL scheme (``javascript:``) gets ``./``."""
    path = str(path)
    if re.match(r"^[A-Za-z][A-Za-z0-9+.-]*:", path):
        path = "./" + path
    return _text(path)


_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:0;color:#222;
background:#fafafa}
header{background:#1f2a44;color:#fff;padding:24px 40px}
header h1{margin:0 0 6px 0;font-size:26px} header p{margin:0;opacity:.85}
nav{padding:10px 40px;background:#e9edf5;font-size:14px} nav a{margin-right:16px;color:#1f2a44}
section{background:#fff;margin:24px 40px;padding:20px 28px;border-radius:8px;
box-shadow:0 1px 3px rgba(0,0,0,.12)}
h2{margin-top:0} .meta{color:#666;font-size:13px}
.imgs{display:flex;flex-wrap:wrap;gap:16px}
figure{margin:0;flex:1 1 360px;max-width:560px} figure img{width:100%;border:1px solid #ddd;
border-radius:4px;background:#fff} figcaption{font-size:13px;color:#555;margin-top:4px}
table{border-collapse:collapse;margin:12px 0} td{padding:3px 14px 3px 0;font-size:14px}
td.v{font-weight:600;font-variant-numeric:tabular-nums}
.files{font-size:13px;columns:3} .files a{color:#1f4fd6}
.err{color:#b00020;font-weight:600}
figure.oc-view canvas{width:100%;aspect-ratio:4/3;border:1px solid #ddd;border-radius:4px;
background:#fff;touch-action:none;cursor:grab}
.oc-controls{display:flex;gap:8px;align-items:center;font-size:13px}
.oc-controls input{flex:1}
.imgs.grid{display:grid;gap:12px} .imgs.grid figure{max-width:none}
"""


def viewer_script() -> str:
    """The JavaScript of the offline glb viewer (``origami_cad/viz/glb_viewer.js``)."""
    return importlib.resources.files("origami_cad.viz").joinpath("glb_viewer.js").read_text()


def view_figure(glb: bytes, caption: str, link: str = "") -> str:
    """A ``<figure class="oc-view">`` holding a glb (base64) for :func:`viewer_script`.

    ``link`` (a relative path) adds a link to the glb file under the caption.
    """
    data = base64.b64encode(glb).decode("ascii")
    lines = [data[i : i + 76] for i in range(0, len(data), 76)]
    more = f" (<a href='{_href(link)}'>{_text(link)}</a>)" if link else ""
    return (
        "<figure class='oc-view'><canvas width='560' height='420'></canvas>"
        "<script type='application/octet-stream' class='oc-glb'>\n"
        + "\n".join(lines)
        + f"\n</script><figcaption>{_text(caption)}: drag to turn, wheel to zoom{more}"
        "</figcaption></figure>"
    )


def _views(folder: Path, step: StepReport, budget: list[int]) -> list[str]:
    """The 3D views of a step; a view over the remaining ``budget`` (bytes) is a link."""
    parts = []
    for src, cap in step.views:
        glb = (folder / src).read_bytes()
        if len(glb) <= budget[0]:
            budget[0] -= len(glb)
            parts.append(view_figure(glb, cap, src))
        else:
            parts.append(
                f"<figure><p><a href='{_href(src)}'>{_text(src)}</a></p>"
                f"<figcaption>{_text(cap)} (glb, for Blender or a glTF viewer)</figcaption>"
                "</figure>"
            )
    return parts


def write_report(
    path: str | os.PathLike[str],
    steps: Sequence[StepReport],
    *,
    title: str = "origami_cad: the paper, end to end",
    subtitle: str = "",
) -> Path:
    """Write the report page (atomic). Images and files are linked relatively."""
    e = _text
    budget = [MAX_EMBEDDED_BYTES]
    parts = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        f"<title>{e(title)}</title><style>{_CSS}</style></head><body>",
        f"<header><h1>{e(title)}</h1><p>{e(subtitle)}</p></header><nav>",
    ]
    parts += [f"<a href='#{e(s.key)}'>{e(s.title)}</a>" for s in steps]
    parts.append("</nav>")
    for s in steps:
        parts.append(f"<section id='{e(s.key)}'><h2>{e(s.title)}</h2>")
        parts.append(f"<p class='meta'>{s.seconds:.1f} s</p>")
        if s.error:
            parts.append(f"<p class='err'>This step failed: {e(s.error)}</p>")
        if s.summary:
            parts.append(f"<p>{e(s.summary)}</p>")
        if s.numbers:
            parts.append("<table>")
            parts += [f"<tr><td>{e(k)}</td><td class='v'>{e(v)}</td></tr>" for k, v in s.numbers]
            parts.append("</table>")
        if s.images or s.views:
            grid = f" grid' style='grid-template-columns:repeat({int(s.columns)},1fr)"
            parts.append(f"<div class='imgs{grid if s.columns > 0 else ''}'>")
            parts += _views(Path(path).parent, s, budget)
            for src, cap in s.images:
                parts.append(
                    f"<figure><a href='{_href(src)}'><img src='{_href(src)}' alt='{e(cap)}'></a>"
                    f"<figcaption>{e(cap)}</figcaption></figure>"
                )
            parts.append("</div>")
        if s.files:
            parts.append("<p><b>Files</b></p><div class='files'>")
            parts += [f"<div><a href='{_href(f)}'>{e(f)}</a></div>" for f in s.files]
            parts.append("</div>")
        parts.append("</section>")
    if any(s.views for s in steps):
        parts.append(f"<script>\n{viewer_script()}</script>")
    parts.append("</body></html>\n")
    with atomic_write(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(parts))
    return Path(path)
