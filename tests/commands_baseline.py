"""Run every command on ``examples/`` and describe its outputs (issue 29's baseline).

``python tests/commands_baseline.py [NAMES...]`` rewrites ``tests/data/commands_baseline.json``
(all cases, or the named ones); ``tests/test_commands_baseline.py`` runs the fast cases
again and compares. A case's description: exit code, the files written (names), the
contents of its JSON, TOML and XML files (floats rounded, timings and versions dropped,
the output folder's path replaced by ``OUT``). Binary files (PNG, GIF, STL, STEP, 3MF,
GLB) are described by name only: their bytes are not stable across library versions.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import re
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
BASELINE = ROOT / "tests" / "data" / "commands_baseline.json"
CR = "crawler/crawler.toml"

# name: (argv with {ex} and {out}, fast: compared by the test on every run)
CASES: dict[str, tuple[list[str], bool]] = {
    "convert-fold": (["convert", "{ex}/data/boat.dxf", "{out}/boat.fold"], True),
    "convert-svg": (["convert", "{ex}/data/boat.dxf", "{out}/boat.svg", "--width", "100"], True),
    "check-boat": (["check", "{ex}/data/boat.dxf", "-v"], True),
    "pattern": (["pattern", "{ex}/miura_6x4.toml", "-o", "{out}/cp.fold", "-o",
                 "{out}/cp.png"], True),
    "pattern-tg": (["pattern", "{ex}/fig2_tg.toml", "-o", "{out}/cp.fold"], True),
    "fold": (["fold", "{ex}/fig2_tg.toml", "-o", "{out}/f.fold", "--ratio", "0.4",
              "--frames", "3"], True),
    "fold-boat": (["fold", "{ex}/data/boat.dxf", "-o", "{out}/b.fold", "--ratio", "0.3"], True),
    "tg": (["tg", "{ex}/fig2_tg.toml", "-o", "{out}/tg.png"], True),
    "design-arm": (["design-arm", "{ex}/arm_task.toml", "-o", "{out}/arm", "--runs", "2",
                    "--max-generations", "4"], False),
    "fabricate": (["fabricate", "{ex}/miura_6x4.toml", "-o", "{out}/fab", "--theta-max",
                   "150"], False),
    "route": (["route", "{ex}/miura_6x4.toml", "{ex}/miura_route.toml", "-o", "{out}/route"], True),
    "plan-route": (["plan-route", "{ex}/miura_6x4.toml", "-o", "{out}/plan/route.toml",
                    "--candidates", "4", "--strings", "2", "--budget", "60"], False),
    "simulate": (["simulate", "{ex}/miura_6x4.toml", "{ex}/miura_route.toml", "-o", "{out}/sim",
                  "--steps", "6"], False),
    "sequence": (["sequence", "{ex}/arm_design.toml", "{ex}/arm_route.toml", "-o",
                  "{out}/seq.toml", "--keyframes", "0:0", "10:0.3", "20:0"], True),
    "sequence-robot": (["sequence", "{ex}/" + CR, "{ex}/crawler_gait.toml", "-o",
                        "{out}/seq.toml"], True),
    "arm-scene": (["arm-scene", "{ex}/arm_task.toml", "{ex}/arm_design.toml",
                   "{ex}/arm_route.toml", "-o", "{out}/scene", "--steps", "8"], False),
    "robot": (["robot", "{ex}/" + CR, "-o", "{out}/robot", "--no-renders"], False),
    "crawl": (["crawl", "{ex}/" + CR, "-o", "{out}/crawl", "--cycles", "1", "--steps", "1"], False),
    "mjcf-route": (["mjcf", "{ex}/miura_6x4.toml", "{ex}/miura_route.toml", "-o",
                    "{out}/m.xml"], True),
    "mjcf-robot": (["mjcf", "{ex}/" + CR, "-o", "{out}/robot.xml"], True),
    "drive": (["drive", "{ex}/arm_fold.toml", "--dry-run", "--speed", "64", "--log",
               "{out}/log.csv"], False),
    "part": (["part", "tsa-module", "-o", "{out}/part", "--pattern", "{ex}/data/boat.dxf",
              "--panel", "f0"], False),
    "part-list": (["part", "--list"], True),
    "design-gait": (["design-gait", "{ex}/" + CR, "-o", "{out}/gait", "--popsize", "4",
                     "--generations", "1", "--steps", "1", "--frictions", "0.6"], False),
}  # fmt: skip
#: Commands no case runs, and why: ``emulate`` serves servos on a pseudo-terminal until it
#: is stopped (tests/test_drive.py runs it); ``demo`` chains the others (tests/test_demo.py).
NOT_RECORDED = {"emulate", "demo"}

_UNSTABLE = re.compile(r"seconds|_s$|time|version", re.IGNORECASE)


def _rounded(value, digits: int = 4):
    """JSON data with floats rounded to ``digits`` significant digits, timings dropped."""
    if isinstance(value, float):
        if not math.isfinite(value) or value == 0:
            return str(value) if not math.isfinite(value) else 0.0
        return float(f"{value:.{digits}g}")
    if isinstance(value, dict):
        return {k: _rounded(v, digits) for k, v in value.items() if not _UNSTABLE.search(k)}
    if isinstance(value, list):
        return [_rounded(v, digits) for v in value]
    return value


def summarized(value, keep: int = 5):
    """Long lists cut to their first and last ``keep`` items and their length."""
    if isinstance(value, dict):
        return {k: summarized(v, keep) for k, v in value.items()}
    if isinstance(value, list):
        items = [summarized(v, keep) for v in value]
        if len(items) > 3 * keep:
            return [*items[:keep], f"... {len(items)} items", *items[-keep:]]
        return items
    return value


def _text(path: Path, out: Path) -> str:
    text = path.read_text(encoding="utf-8").replace(str(out), "OUT").replace(str(EX), "EX")
    return re.sub(r"\d+\.\d+(?:e-?\d+)?", lambda m: f"{float(m.group()):.4g}", text)


def _xml(path: Path) -> dict:
    """An XML file (MJCF) as its elements' counts and names (the numbers are the
    simulation's; the structure is what a command writes)."""
    import xml.etree.ElementTree as ET

    root = ET.parse(path).getroot()
    counts: dict[str, int] = {}
    names = []
    for element in root.iter():
        counts[element.tag] = counts.get(element.tag, 0) + 1
        if "name" in element.attrib:
            names.append(f"{element.tag}:{element.attrib['name']}")
    return {"counts": counts, "names": summarized(names, 20)}


def _paths(value, out: Path):
    """JSON data with the examples' and the output folder's paths as ``EX`` and ``OUT``."""
    if isinstance(value, str):
        return value.replace(str(out), "OUT").replace(str(EX), "EX")
    if isinstance(value, dict):
        return {k: _paths(v, out) for k, v in value.items()}
    if isinstance(value, list):
        return [_paths(v, out) for v in value]
    return value


def describe(out: Path, rc: int, stdout: str) -> dict:
    """The exit code and what the command wrote into ``out``."""
    files = sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file())
    contents = {}
    for name in files:
        path = out / name
        if path.suffix == ".json" or path.suffix == ".fold":
            data = _rounded(json.loads(path.read_text(encoding="utf-8")))
            contents[name] = summarized(_paths(data, out))
        elif path.suffix == ".toml":
            contents[name] = _text(path, out)
        elif path.suffix == ".xml":
            contents[name] = _xml(path)
    lines = stdout.replace(str(out), "OUT").replace(str(EX), "EX").splitlines()
    return {"rc": rc, "files": files, "contents": contents, "stdout_lines": len(lines)}


def run_case(name: str, folder: Path) -> dict:
    """Run one case of :data:`CASES` into ``folder`` (created); its description."""
    from origami_cad.cli import main

    folder.mkdir(parents=True, exist_ok=True)
    argv = [a.format(ex=EX, out=folder) for a in CASES[name][0]]
    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        rc = main(argv)
    return describe(folder, rc, buffer.getvalue())


def main(names: list[str]) -> None:
    baseline = json.loads(BASELINE.read_text()) if BASELINE.exists() else {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in names or list(CASES):
            print(name, file=sys.stderr, flush=True)
            baseline[name] = run_case(name, Path(tmp) / name)
    BASELINE.write_text(json.dumps(baseline, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
