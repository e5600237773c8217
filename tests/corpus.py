"""The whole chain on the public crease-pattern corpus (``make corpus``).

Every pattern of ``tests/data/corpus.toml`` (files written by Origami Simulator, the FOLD
format's examples and, where present, PyGamiX) goes through the commands a user runs, each
in a fresh folder and a subprocess with a time limit, at 150 mm wide:

1. ``check FILE``: passes with no error (status 0);
2. ``fold FILE --ratio 0.3``: passes when the fold really folds, measured on the written
   FOLD file itself: at least half the mountain and valley creases turn by more than 5 deg
   (the dihedral angle between the two faces, from the 3D coordinates) and no edge changes
   length by more than 5 %;
3. ``fabricate FILE``: status 0;
4. ``plan-route FILE --tsa ring`` (no ``--strings``): status 0;
5. ``simulate FILE route.toml``: status 0 on what plan-route wrote.

It prints a table (Markdown with ``--markdown FILE``): each stage's result, and on failure
the command's own one-line reason. ``--fast`` runs only the patterns marked fast (the ones
``tests/test_corpus.py`` runs inside ``make test``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

DATA = Path(__file__).resolve().parent / "data"
MANIFEST = DATA / "corpus.toml"
STAGES = ("check", "fold", "fabricate", "plan-route", "simulate")
WIDTH = "150"
RATIO = "0.3"
TURN_DEG = 5.0  # a crease "turns" when its dihedral angle exceeds this
MAX_STRAIN = 0.05  # the largest relative change of an edge's length
TIMEOUT_S = 180.0


@dataclass
class Stage:
    """One command's outcome on one pattern."""

    name: str
    ok: bool
    code: int | None
    seconds: float
    message: str = ""


@dataclass
class Row:
    """The chain's outcome on one pattern."""

    file: str
    kind: str
    stages: list[Stage] = field(default_factory=list)

    def passed(self, stage: str) -> bool:
        return any(s.name == stage and s.ok for s in self.stages)


def load_manifest(fast: bool = False) -> list[dict]:
    """The corpus's entries (``fast``: only those marked fast), each with ``file`` and ``kind``."""
    entries = tomllib.loads(MANIFEST.read_text())["pattern"]
    extra = DATA / "pygamix" / "corpus.toml"
    if extra.exists():
        for e in tomllib.loads(extra.read_text()).get("pattern", []):
            entries.append({**e, "file": f"pygamix/{e['file']}"})
    return [e for e in entries if e.get("fast") or not fast]


def _cli() -> list[str]:
    script = Path(sys.executable).with_name("origami-cad")
    if script.exists():
        return [str(script)]
    return [sys.executable, "-c", "import sys; from origami_cad.cli import main; sys.exit(main())"]


def _run(args: list[str], cwd: Path, timeout: float) -> tuple[int | None, float, str]:
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(
            [*_cli(), *args],
            cwd=cwd,
            capture_output=True,
            text=True,
            timeout=timeout,
            stdin=subprocess.DEVNULL,
        )
    except subprocess.TimeoutExpired:
        return None, time.perf_counter() - t0, f"over {timeout:.0f} s"
    seconds = time.perf_counter() - t0
    lines = [ln for ln in (proc.stderr + "\n" + proc.stdout).splitlines() if ln.strip()]
    bad = [ln for ln in lines if ln.startswith(("error", "origami-cad:", "internal"))]
    message = (bad or lines[-1:] or [""])[0]
    return proc.returncode, seconds, message.strip()


def _unit_normal(points: list[list[float]]) -> tuple[float, float, float]:
    from origami_cad.fabrication.polyhedra import newell_normal

    nx, ny, nz = newell_normal([tuple(p) for p in points])
    n = math.sqrt(nx * nx + ny * ny + nz * nz) or 1.0
    return nx / n, ny / n, nz / n


def fold_measures(path: Path) -> tuple[float, float, int]:
    """(share of M/V creases turning > 5 deg, largest edge strain, M/V count) of a FOLD file.

    Measured on the last frame's 3D coordinates against the file's flat crease pattern
    (the top-level ``vertices_coords``): the dihedral angle between the faces on either side
    of each crease, and each edge's length change relative to its flat length.
    """
    doc = json.loads(path.read_text())
    flat = [list(map(float, v)) + [0.0] * (3 - len(v)) for v in doc["vertices_coords"]]
    frames = doc.get("file_frames") or [doc]
    coords = frames[-1].get("vertices_coords", doc["vertices_coords"])
    coords = [list(map(float, v)) + [0.0] * (3 - len(v)) for v in coords]
    edges = doc["edges_vertices"]
    kinds = doc.get("edges_assignment", ["U"] * len(edges))
    faces = doc.get("faces_vertices", [])
    side: dict[tuple[int, int], list[int]] = {}
    for f, loop in enumerate(faces):
        for i, a in enumerate(loop):
            b = loop[(i + 1) % len(loop)]
            side.setdefault((min(a, b), max(a, b)), []).append(f)
    normals = [_unit_normal([coords[v] for v in loop]) for loop in faces]
    turned = creases = 0
    strain = 0.0
    for (a, b), kind in zip(edges, kinds, strict=True):
        rest = math.dist(flat[a], flat[b])
        if rest > 0:
            strain = max(strain, abs(math.dist(coords[a], coords[b]) - rest) / rest)
        if kind not in ("M", "V"):
            continue
        creases += 1
        pair = side.get((min(a, b), max(a, b)), [])
        if len(pair) == 2:
            dot = sum(p * q for p, q in zip(normals[pair[0]], normals[pair[1]], strict=True))
            if math.degrees(math.acos(max(-1.0, min(1.0, dot)))) > TURN_DEG:
                turned += 1
    return (turned / creases if creases else 0.0), strain, creases


def run_pattern(entry: dict, timeout: float = TIMEOUT_S, keep: Path | None = None) -> Row:
    """Run the chain on one corpus entry; ``keep`` keeps the outputs in that folder."""
    src = DATA / entry["file"]
    row = Row(entry["file"], entry.get("kind", ""))
    work = Path(tempfile.mkdtemp(prefix="oc-corpus-"))
    try:
        code, sec, msg = _run(["check", str(src)], work, timeout)
        row.stages.append(Stage("check", code == 0, code, sec, "" if code == 0 else msg))

        code, sec, msg = _run(
            ["fold", str(src), "--width", WIDTH, "--ratio", RATIO, "-o", "fold.fold"], work, timeout
        )
        ok = code == 0
        if ok:
            share, strain, creases = fold_measures(work / "fold.fold")
            ok = share >= 0.5 and strain <= MAX_STRAIN
            msg = f"{share:.0%} of {creases} creases turn > {TURN_DEG:g} deg, strain {strain:.1%}"
        row.stages.append(Stage("fold", ok, code, sec, msg))

        code, sec, msg = _run(["fabricate", str(src), "--width", WIDTH, "-o", "fab"], work, timeout)
        row.stages.append(Stage("fabricate", code == 0, code, sec, "" if code == 0 else msg))

        code, sec, msg = _run(
            ["plan-route", str(src), "--width", WIDTH, "--tsa", "ring", "-o", "route/route.toml"],
            work,
            timeout,
        )
        routed = code == 0
        row.stages.append(Stage("plan-route", routed, code, sec, "" if routed else msg))

        if routed:
            code, sec, msg = _run(
                ["simulate", str(src), "route/route.toml", "--width", WIDTH, "-o", "sim"],
                work,
                timeout,
            )
            row.stages.append(Stage("simulate", code == 0, code, sec, "" if code == 0 else msg))
        else:
            row.stages.append(Stage("simulate", False, None, 0.0, "no route"))
    finally:
        if keep is not None:
            dest = keep / Path(entry["file"]).stem
            shutil.rmtree(dest, ignore_errors=True)
            shutil.copytree(work, dest)
        shutil.rmtree(work, ignore_errors=True)
    return row


def table(rows: list[Row]) -> str:
    """The results as a Markdown table, with a line of totals."""
    out = ["| pattern | kind | " + " | ".join(STAGES) + " |", "|---|---|" + "---|" * len(STAGES)]
    for r in rows:
        cells = []
        for s in r.stages:
            mark = "pass" if s.ok else ("**exit 3**" if s.code == 3 else "no")
            note = f" ({s.message})" if s.message and (not s.ok or s.name == "fold") else ""
            cells.append(f"{mark}{note.replace('|', '/')}")
        out.append(f"| {Path(r.file).name} | {r.kind} | " + " | ".join(cells) + " |")
    totals = [sum(r.passed(s) for r in rows) for s in STAGES]
    out.append(
        f"| **{len(rows)} patterns** | | "
        + " | ".join(f"**{t} of {len(rows)}**" for t in totals)
        + " |"
    )
    return "\n".join(out)


#: The tool that wrote each source repository's files.
TOOLS = {
    "amandaghassaei/OrigamiSimulator": "Origami Simulator",
    "edemaine/fold": "FOLD's examples",
    "Sepkimmy-YPW/PyGamix-V3.0-release": "PyGamiX",
}
#: The lines that hold the corpus table in a docs page (``--docs PAGE`` rewrites it).
DOCS_BEGIN = "<!-- corpus table: begin (tests/corpus.py --docs) -->"
DOCS_END = "<!-- corpus table: end -->"
NOT_RUN = "not run"


def tool_of(entry: dict) -> str:
    """The tool that wrote a corpus entry's file (its ``source`` repository)."""
    return TOOLS.get(entry.get("source", ""), entry.get("source", "unknown"))


def licence_of(entry: dict) -> str:
    """The licence of a corpus entry's file: the ``LICENSE`` of its folder under ``data/``."""
    path = DATA / Path(entry["file"]).parts[0] / "LICENSE"
    first = path.read_text(encoding="utf-8").strip().splitlines()[0] if path.exists() else ""
    return "MIT" if first.startswith("MIT License") else (first or "unknown")


def _cells(row: Row) -> list[str]:
    cells = []
    for s in row.stages:
        mark = "pass" if s.ok else ("**exit 3**" if s.code == 3 else "no")
        note = f" ({s.message})" if s.message and (not s.ok or s.name == "fold") else ""
        cells.append(f"{mark}{note}".replace("|", "/"))
    return cells


def _page_rows(text: str) -> dict[str, list[str]]:
    """The stage cells of each pattern in a page's corpus table (by its ``file``)."""
    if DOCS_BEGIN not in text:
        return {}
    block = text.split(DOCS_BEGIN, 1)[1].split(DOCS_END, 1)[0]
    rows = {}
    for line in block.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 4 + len(STAGES) and cells[0].startswith("`"):
            rows[cells[0].strip("`")] = cells[4:]
    return rows


def docs_block(entries: list[dict], rows: dict[str, list[str]], stamp: str) -> str:
    """The page's corpus table: every entry with its tool, licence and kind, and each
    stage's result from ``rows`` (by file; ``not run`` where it has none)."""
    out = [
        DOCS_BEGIN,
        "",
        stamp,
        "",
        "| pattern | tool | licence | kind | " + " | ".join(STAGES) + " |",
        "|---|---|---|---|" + "---|" * len(STAGES),
    ]
    passed = [0] * len(STAGES)
    for e in entries:
        cells = rows.get(e["file"], [NOT_RUN] * len(STAGES))
        passed = [n + c.startswith("pass") for n, c in zip(passed, cells, strict=True)]
        out.append(
            f"| `{e['file']}` | {tool_of(e)} | {licence_of(e)} | {e.get('kind', '')} | "
            + " | ".join(cells)
            + " |"
        )
    n = len(entries)
    out.append(
        f"| **{n} patterns** | | | | " + " | ".join(f"**{k} of {n}**" for k in passed) + " |"
    )
    return "\n".join([*out, "", DOCS_END])


def source_commit() -> str:
    """The commit the package was measured on (short hash; ``+changes`` when the tree has
    uncommitted changes to the package), or ``unknown`` outside a git checkout."""
    root = Path(__file__).resolve().parents[1]
    try:
        head = subprocess.run(
            ["git", "-C", str(root), "rev-parse", "--short=12", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
            timeout=30,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "-C", str(root), "status", "--porcelain", "--", "origami_cad"],
            capture_output=True,
            text=True,
            check=True,
            timeout=30,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return f"{head}{'+changes' if dirty else ''}"


def update_docs(
    page: Path, rows: list[Row], entries: list[dict] | None = None, commit: str | None = None
) -> None:
    """Rewrite the corpus table of ``page`` (between :data:`DOCS_BEGIN` and
    :data:`DOCS_END`): the patterns just run get their results, the others keep theirs;
    ``commit`` is the one measured (default: :func:`source_commit` now)."""
    text = page.read_text(encoding="utf-8")
    if DOCS_BEGIN not in text or DOCS_END not in text:
        raise SystemExit(f"{page}: no corpus table ({DOCS_BEGIN!r} ... {DOCS_END!r})")
    kept = _page_rows(text)
    kept.update({r.file: _cells(r) for r in rows})
    from origami_cad import __version__

    stamp = (
        f"Last run: origami_cad {__version__} at commit {commit or source_commit()}, "
        f"{time.strftime('%Y-%m-%d')}, {len(rows)} patterns run then (`make corpus` runs all "
        "of them)."
    )
    if not rows:
        stamp = (
            f"Rewritten with no pattern run (origami_cad {__version__}, "
            f"{time.strftime('%Y-%m-%d')}): `make corpus` fills in the results."
        )
    head, rest = text.split(DOCS_BEGIN, 1)
    tail = rest.split(DOCS_END, 1)[1]
    block = docs_block(entries or load_manifest(), kept, stamp)
    tmp = page.with_suffix(page.suffix + ".tmp")
    tmp.write_text(head + block + tail, encoding="utf-8")
    tmp.replace(page)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fast", action="store_true", help="only the patterns marked fast")
    ap.add_argument("--only", action="append", default=[], help="a file name part (repeat)")
    ap.add_argument("--jobs", type=int, default=max(1, (os.cpu_count() or 1) // 2))
    ap.add_argument("--timeout", type=float, default=TIMEOUT_S, help="seconds per command")
    ap.add_argument("--markdown", type=Path, help="also write the table to this file")
    ap.add_argument("--keep", type=Path, help="keep every output in this folder")
    ap.add_argument("--docs", type=Path, help="rewrite this page's corpus table (docs/patterns.md)")
    args = ap.parse_args(argv)
    entries = load_manifest(args.fast)
    if args.only:
        entries = [e for e in entries if any(o in e["file"] for o in args.only)]
    commit = source_commit()  # the code measured, whatever is committed during the run
    t0 = time.perf_counter()
    with ThreadPoolExecutor(args.jobs) as pool:
        rows = list(pool.map(lambda e: run_pattern(e, args.timeout, args.keep), entries))
    text = table(rows)
    print(text)
    slow = max((s.seconds for r in rows for s in r.stages), default=0.0)
    exit3 = sum(s.code == 3 for r in rows for s in r.stages)
    print(f"\n{len(rows)} patterns in {time.perf_counter() - t0:.0f} s; slowest step {slow:.0f} s;")
    print(f"exit code 3: {exit3}")
    if args.markdown:
        args.markdown.write_text(text + "\n")
    if args.docs:
        update_docs(args.docs, rows, commit=commit)
    return 0


if __name__ == "__main__":
    sys.exit(main())
