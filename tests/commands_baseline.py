"""Run every command on ``examples/`` and describe its outputs.

``python tests/commands_baseline.py [--bytes] [NAMES...]`` rewrites
``tests/data/commands_baseline.json`` and ``tests/data/commands_bytes.json`` (all cases, or
the named ones; ``--bytes``: the bytes only);
``tests/test_commands_baseline.py`` runs the fast cases again and compares.

Two records: the description below, portable across library versions, and the bytes of
every file written (:func:`digests`: a SHA-256 per file; timestamps, timings, versions, the
output folder's path, and what OpenCASCADE's STEP writer and the emulated servos vary from
one run to the next taken out), compared when the environment (:func:`environment`:
Python, NumPy, SciPy, matplotlib, build123d, OCP, trimesh, VTK, numba, the processor, the
system's Mesa) is the one that recorded them.

A case's description: exit code, the files written (names), the contents of its JSON,
TOML and XML files (floats rounded, timings and versions dropped,
the output folder's path replaced by ``OUT``). Binary files (PNG, GIF, STL, STEP, 3MF,
GLB) are described by name only: their bytes are not stable across library versions.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import math
import re
import sys
import tempfile
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
BASELINE = ROOT / "tests" / "data" / "commands_baseline.json"
BYTES = ROOT / "tests" / "data" / "commands_bytes.json"
CR = "crawler/crawler.toml"
MOUNTAIN = "pygamix/descriptionData/f-mountain-big-fix-new.json"

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
    "completion": (["completion", "bash"], True),
    "calibrate": (["calibrate", "{ex}/" + MOUNTAIN, "{ex}/pygamix/experiment/mountain/1_2.csv",
                   "--tendons", "2", "--fit", "hole-friction", "--evaluations", "3", "--step",
                   "10", "-o", "{out}/cal"], True),
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


#: Text files whose bytes are recorded with the output folder's path taken out.
_TEXT = {".toml", ".csv", ".xml", ".svg", ".dxf", ".opx", ".txt", ".step", ".md", ".html"}
#: What changes from one run to the next inside a file: STEP's header time stamp, a 3MF's
#: creation date.
_STAMPS = re.compile(
    r"FILE_NAME\([^;]*;|\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d(?:\.\d+)?(?:[+-]\d\d:?\d\d|Z)?"
)


def _unstable_dropped(value):
    """JSON data without its timings and versions (exact otherwise)."""
    if isinstance(value, dict):
        return {k: _unstable_dropped(v) for k, v in value.items() if not _UNSTABLE.search(k)}
    if isinstance(value, list):
        return [_unstable_dropped(v) for v in value]
    return value


#: A STEP file's assembly occurrences: OpenCASCADE numbers them with a counter of the
#: process, so the second export of a process numbers them on from the first's.
_OCCURRENCE = re.compile(r"NEXT_ASSEMBLY_USAGE_OCCURRENCE\('\d+'")
#: The columns of a ``drive`` log the emulated servos fill in real time (the emulator runs
#: on the wall clock): what was measured, not what was commanded.
_MEASURED = ("measured_turns", "current_mA")


#: A STEP file's presentation entities (colours and styles): OpenCASCADE writes them in
#: an order of its own from one export to the next, numbered as they come.
_STYLES = (
    "STYLED_ITEM", "OVER_RIDING_STYLED_ITEM", "PRESENTATION_STYLE", "SURFACE_S",
    "FILL_AREA_STYLE", "CURVE_STYLE", "INVISIBILITY", "DRAUGHTING_PRE_DEFINED", "COLOUR_RGB",
    "MECHANICAL_DESIGN_GEOMETRIC_PRESENTATION",
)  # fmt: skip


def _step_text(text: str) -> str:
    """A STEP text as recorded: entities unwrapped (the writer wraps lines by their
    length, numbers included), assembly occurrences numbered from 1 in the file's order,
    and the presentation entities as a sorted list of what each says, references to other
    presentation entities by their content: the same colours on the same shapes."""
    count = iter(range(1, 1 << 30))
    text = re.sub(r"\n[ \t]+", "", text)
    text = _OCCURRENCE.sub(lambda m: f"NEXT_ASSEMBLY_USAGE_OCCURRENCE('{next(count)}'", text)
    entity = re.compile(r"^#(\d+) = (.*)$")
    styles, kept = {}, []
    for line in text.splitlines():
        found = entity.match(line)
        if found and found.group(2).startswith(_STYLES):
            styles[found.group(1)] = found.group(2)
        else:
            kept.append(line)
    said: dict[str, str] = {}

    def says(number: str) -> str:
        if number not in said:
            body = re.sub(r"#(\d+)", lambda m: ref(m.group(1)), styles[number])
            said[number] = re.sub(  # a list of presentation entities: a set
                r"\((@\w+(?:,@\w+)*)\)", lambda m: f"({','.join(sorted(m[1].split(',')))})", body
            )
        return said[number]

    def ref(number: str) -> str:
        if number not in styles:
            return f"#{number}"
        return "@" + hashlib.sha256(says(number).encode()).hexdigest()[:16]

    return "\n".join([*kept, *sorted(says(n) for n in styles)])


def _commanded(text: str) -> str:
    """A CSV's text without the columns of :data:`_MEASURED` (a drive log's)."""
    rows = [line.split(",") for line in text.splitlines()]
    if not rows or not any(c in rows[0] for c in _MEASURED):
        return text
    keep = [k for k, c in enumerate(rows[0]) if c not in _MEASURED]
    return "\n".join(",".join(r[k] for k in keep if k < len(r)) for r in rows) + "\n"


def _normalized(path: Path, out: Path) -> bytes:
    """A file's bytes as recorded: JSON without timings and versions, text without the
    output folder's path and time stamps, STEP's occurrences renumbered, a drive log's
    commanded columns, an archive (3MF) member by member."""
    raw = path.read_bytes()
    suffix = path.suffix.lower()
    if suffix in (".json", ".fold"):
        data = _paths(_unstable_dropped(json.loads(raw)), out)
        return json.dumps(data, sort_keys=True).encode()
    if suffix in _TEXT:
        text = raw.decode("utf-8", errors="replace").replace(str(out), "OUT")
        text = _STAMPS.sub("STAMP", text.replace(str(EX), "EX"))
        if suffix == ".step":
            text = _step_text(text)
        elif suffix == ".csv":
            text = _commanded(text)
        return text.encode()
    if suffix == ".3mf":
        with zipfile.ZipFile(path) as zf:
            parts = [n.encode() + _STAMPS.sub("STAMP", zf.read(n).decode("latin-1")).encode(
                "latin-1") for n in sorted(zf.namelist())]  # fmt: skip
        return b"\0".join(parts)
    return raw


def digests(out: Path) -> dict[str, str]:
    """The SHA-256 of each file written into ``out`` (normalised: :func:`_normalized`)."""
    return {
        str(p.relative_to(out)): hashlib.sha256(_normalized(p, out)).hexdigest()
        for p in sorted(out.rglob("*"))
        if p.is_file()
    }


def _dpkg_version(package: str) -> str:
    """The version of a Debian package installed (``none``: not installed, or no dpkg)."""
    try:
        status = Path("/var/lib/dpkg/status").read_text(encoding="utf-8", errors="replace")
    except OSError:
        return "none"
    for block in status.split("\n\n"):
        if f"Package: {package}\n" in block and "Status: install ok installed" in block:
            found = re.search(r"^Version: (.+)$", block, re.MULTILINE)
            return found.group(1) if found else "none"
    return "none"


def _cpu() -> str:
    """The processor's model name (BLAS and NumPy pick their kernels by it)."""
    try:
        info = Path("/proc/cpuinfo").read_text(encoding="utf-8", errors="replace")
    except OSError:
        import platform

        return platform.processor() or "unknown"
    found = re.search(r"^model name\s*:\s*(.+)$", info, re.MULTILINE)
    return found.group(1).strip() if found else "unknown"


def environment() -> dict[str, str]:
    """What the bytes of the outputs depend on beside the code: library versions, the
    processor (BLAS kernels), the system's Mesa (VTK's off-screen renders)."""
    import platform
    from importlib.metadata import PackageNotFoundError, version

    found = {"python": platform.python_version(), "machine": platform.machine(), "cpu": _cpu(),
             "mesa": _dpkg_version("libgl1-mesa-dri")}  # fmt: skip
    for name in ("numpy", "scipy", "matplotlib", "build123d", "cadquery-ocp-novtk", "trimesh",
                 "vtk", "pyvista", "shapely", "pillow", "numba"):  # fmt: skip
        try:
            found[name] = version(name)
        except PackageNotFoundError:
            found[name] = "none"
    return found


def run_case(name: str, folder: Path) -> dict:
    """Run one case of :data:`CASES` into ``folder`` (created); its description."""
    from origami_cad.cli import main

    folder.mkdir(parents=True, exist_ok=True)
    argv = [a.format(ex=EX, out=folder) for a in CASES[name][0]]
    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        rc = main(argv)
    return describe(folder, rc, buffer.getvalue())


def main(args: list[str]) -> None:
    """Record the cases named in ``args`` (all without names); ``--bytes``: their bytes
    only, the descriptions kept (a new environment, or bytes not recorded yet)."""
    bytes_only = "--bytes" in args
    names = [a for a in args if a != "--bytes"]
    unknown = sorted(set(names) - set(CASES))
    if unknown:
        raise SystemExit(f"no such case: {', '.join(unknown)} (cases: {', '.join(CASES)})")
    baseline = json.loads(BASELINE.read_text()) if BASELINE.exists() else {}
    recorded = json.loads(BYTES.read_text()) if BYTES.exists() else {}
    if recorded.get("environment") != environment():  # bytes of another set-up: start anew
        recorded = {"environment": environment(), "cases": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for name in names or list(CASES):
            print(name, file=sys.stderr, flush=True)
            described = run_case(name, Path(tmp) / name)
            if not bytes_only:
                baseline[name] = described
            recorded["cases"][name] = digests(Path(tmp) / name)
    BASELINE.write_text(json.dumps(baseline, indent=1, sort_keys=True) + "\n")
    BYTES.write_text(json.dumps(recorded, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
