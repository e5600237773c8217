"""mkdocs hook: the pictures of the gallery and of the guide pages, made at build time.

Each :data:`FIGURES` entry runs one command of ``origami-cad`` on a file of ``examples/``
through :func:`origami_cad.commands.execute` (as the demo does), off-screen, into a
temporary folder; the PNGs it reports are added to the site as
``gallery/<key>/<name>.png``, where the guide pages show them, and ``gallery.md``'s
``<!-- gallery -->`` line becomes every figure with the caption its command gives. No
picture is committed: a change in the library shows in the next build.

A command that fails stops the build with its one-line message.
"""

from __future__ import annotations

import logging
import os
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from mkdocs.exceptions import PluginError
from mkdocs.structure.files import File

log = logging.getLogger("mkdocs.hooks.gallery")

MARKER = "<!-- gallery -->"


@dataclass(frozen=True)
class Figure:
    """One command of the gallery: ``origami-cad COMMAND INPUTS -o OUTPUT --OPTIONS``.

    ``inputs`` are paths relative to ``examples/``; ``output`` is a file name, a list of
    them, or ``""`` for a folder; ``options`` are the command's options by keyword, in
    their units (mm, degrees); ``page`` is the guide page that explains the command.
    """

    key: str
    title: str
    page: str
    command: str
    inputs: tuple[str, ...]
    output: str | tuple[str, ...] = ""
    options: dict = field(default_factory=dict)
    #: the options whose values are file names of outputs, in the figure's folder
    file_options: tuple[str, ...] = ()


FIGURES = (
    Figure(
        "pattern",
        "A crease pattern from a transition graph",
        "patterns.md",
        "pattern",
        ("fig2_tg.toml",),
        ("pattern.png",),
        {"labels": True},
    ),
    Figure(
        "tg", "The transition graph's chain", "kinematics.md", "tg", ("fig2_tg.toml",), "tg.png"
    ),
    Figure(
        "fold",
        "The tessellation folded rigidly",
        "kinematics.md",
        "fold",
        ("fig2_tg.toml",),
        "folded.png",
        {"ratio": 0.5},
    ),
    Figure(
        "arm",
        "An origami arm designed by CMA-ES (a small budget)",
        "arm-design.md",
        "design-arm",
        ("arm_task.toml",),
        options={"runs": 2, "max_generations": 15},
    ),
    Figure(
        "parts",
        "Printed parts: the 6 x 4 Miura",
        "fabrication.md",
        "fabricate",
        ("miura_6x4.toml",),
        options={"renders": True, "name": "6 x 4 Miura"},
    ),
    Figure(
        "route",
        "A string route folding the Miura (DCQC)",
        "strings.md",
        "route",
        ("miura_6x4.toml", "miura_route.toml"),
    ),
    Figure(
        "simulation",
        "The boat pattern folded by its TSA (bar-and-hinge simulation)",
        "simulation.md",
        "simulate",
        ("data/boat.dxf", "boat_route.toml"),
        options={"steps": 24},
    ),
    Figure(
        "plan",
        "String routes planned by the DCQC principle",
        "route-planning.md",
        "plan-route",
        ("miura_6x4.toml",),
        "route.toml",
        {"strings": 4, "candidates": 16},
    ),
    Figure(
        "crawler",
        "The crawler, printed with its parts",
        "crawler.md",
        "robot",
        ("crawler/crawler.toml",),
    ),
    Figure(
        "crawl",
        "The crawler walking (bar-and-hinge simulation on the ground)",
        "crawler.md",
        "crawl",
        ("crawler/crawler.toml",),
        options={"cycles": 1, "steps": 3},
    ),
    Figure(
        "drive",
        "The crawler's gait on emulated servos",
        "driving.md",
        "drive",
        ("crawler_gait.toml",),
        "log.csv",
        {"dry_run": True, "speed": 32.0, "baudrate": 1_000_000, "plot": "turns.png"},
        ("plot",),
    ),
)


@dataclass
class Picture:
    """A PNG a figure's command made: its place in the site and its caption."""

    figure: Figure
    path: Path
    caption: str

    @property
    def uri(self) -> str:
        return f"gallery/{self.figure.key}/{self.path.name}"


_made: list[Picture] = []
_scratch = tempfile.TemporaryDirectory(prefix="origami-cad-gallery-")


def make_pictures(examples: Path, into: Path) -> list[Picture]:
    """Run every figure's command into ``into`` (a folder per figure); its PNGs, in order."""
    os.environ.setdefault("MPLBACKEND", "Agg")
    from origami_cad.commands import execute
    from origami_cad.errors import OrigamiCadError

    pictures = []
    for fig in FIGURES:
        folder = into / fig.key
        if isinstance(fig.output, tuple):
            output = [folder / name for name in fig.output]
        else:
            output = folder / fig.output if fig.output else folder
        inputs = [examples / name for name in fig.inputs]
        options = {k: folder / v if k in fig.file_options else v for k, v in fig.options.items()}
        start, cpu = time.perf_counter(), time.process_time()
        try:
            done = execute(fig.command, *inputs, output, **options)
        except OrigamiCadError as exc:
            raise PluginError(f"gallery: {fig.key} ({fig.command}): {exc}") from exc
        pngs = [(Path(p), caption) for p, caption in done.images if Path(p).suffix == ".png"]
        if not pngs:
            raise PluginError(f"gallery: {fig.key} ({fig.command}) made no PNG picture")
        pictures += [Picture(fig, path, caption) for path, caption in pngs]
        log.info(
            "gallery: %s, %d pictures in %.1f s (%.1f s CPU)",
            fig.key,
            len(pngs),
            time.perf_counter() - start,
            time.process_time() - cpu,
        )
    return pictures


def on_files(files, config):
    """Make the pictures (once per process: ``mkdocs serve`` reuses them) and add them."""
    if not _made:
        examples = Path(config.config_file_path).resolve().parent.parent / "examples"
        _made.extend(make_pictures(examples, Path(_scratch.name)))
    for pic in _made:
        files.append(File.generated(config, pic.uri, abs_src_path=str(pic.path)))
    return files


def command_line(fig: Figure) -> str:
    """The figure's command as a user types it (outputs under ``out/``)."""
    words = ["origami-cad", fig.command, *(f"examples/{name}" for name in fig.inputs)]
    outputs = fig.output if isinstance(fig.output, tuple) else (fig.output,)
    for name in outputs:
        words += ["-o", f"out/{fig.key}/{name}"]
    for key, value in fig.options.items():
        flag = "--" + key.replace("_", "-")
        if key in fig.file_options:
            words += [flag, f"out/{fig.key}/{value}"]
        elif value is True:
            words.append(flag)
        elif isinstance(value, str) and " " in value:
            words += [flag, f"'{value}'"]
        else:
            words += [flag, str(value)]
    return " ".join(words)


def gallery_markdown() -> str:
    """Every figure: its title, its command, the page that explains it, and each picture
    with its caption."""
    out = []
    for fig in FIGURES:
        out += [f"## {fig.title}", "", "```sh", command_line(fig), "```", ""]
        out += [f"See [{fig.page}]({fig.page}).", ""]
        for pic in (p for p in _made if p.figure is fig):
            out += [f"![{pic.caption}]({pic.uri})", "", f"*{pic.caption}*", ""]
    return "\n".join(out)


def on_page_markdown(markdown, page, config, files):
    """Put the figures into ``gallery.md`` in place of its marker."""
    if page.file.src_uri == "gallery.md":
        if MARKER not in markdown:
            raise PluginError(f"gallery.md has no {MARKER} line for the figures")
        return markdown.replace(MARKER, gallery_markdown())
    return markdown
