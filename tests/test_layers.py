"""The architecture as a contract: stages import only the stages above them.

The order is the guide's (``docs/architecture.md``): pattern, kinematics, design,
fabrication, strings, parts, simulation, drive, viz, jobs, then the CLI and the
demo. ``errors``, ``_fileio``, ``_names`` and ``_toml`` are the base every stage may use.
Names starting with an underscore never cross a module boundary, in the package,
its tests or its benchmarks.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BASE = {
    "origami_cad",
    "origami_cad.errors",
    "origami_cad._fileio",
    "origami_cad._libm",
    "origami_cad._names",
    "origami_cad._toml",
}
ORDER = [
    "pattern",
    "kinematics",
    "design",
    "fabrication",
    "strings",
    "parts",
    "simulation",
    "drive",
    "viz",
    "jobs",
    "cli",
    "demo",
]
# the one edge against the order: the CLI dispatches the `demo` command
ALLOWED = {("cli", "demo")}


def _module_name(path: Path) -> str:
    rel = path.relative_to(ROOT).with_suffix("")
    parts = list(rel.parts)
    if parts[0] == "parts":  # the top-level folder is installed as origami_cad.parts
        parts = ["origami_cad", *parts]
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _stage(module: str) -> str | None:
    if module in BASE or not module.startswith("origami_cad."):
        return None
    return module.split(".")[1]


def _imports(path: Path):
    """(imported module, imported names, line) of every import in a file, lazy ones too."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    here = _module_name(path) if path.is_relative_to(ROOT / "origami_cad") else ""
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, [], node.lineno
        elif isinstance(node, ast.ImportFrom) and node.module:
            module = node.module
            if node.level:  # relative import
                base = here.split(".")[: -node.level + (path.name == "__init__.py")]
                module = ".".join([*base, module])
            yield module, [a.name for a in node.names], node.lineno


def _sources(*folders: str) -> list[Path]:
    return sorted(p for f in folders for p in (ROOT / f).rglob("*.py"))


def _canonical(module: str) -> str:
    return "origami_cad." + module if module == "parts" or module.startswith("parts.") else module


def test_every_stage_imports_only_the_stages_above_it():
    files = _sources("origami_cad", "parts")
    assert len(files) > 40
    bad = []
    for path in files:
        stage = _stage(_module_name(path))
        if stage is None:
            continue
        for module, _, line in _imports(path):
            target = _stage(_canonical(module))
            if target is None or target == stage or (stage, target) in ALLOWED:
                continue
            if target not in ORDER or ORDER.index(target) > ORDER.index(stage):
                bad.append(f"{path.relative_to(ROOT)}:{line}: {stage} imports {module}")
    assert not bad, "\n".join(bad)


def test_the_base_imports_no_stage():
    for name in ("errors.py", "_fileio.py", "_toml.py"):
        for module, _, line in _imports(ROOT / "origami_cad" / name):
            assert _stage(_canonical(module)) is None, f"{name}:{line} imports {module}"


@pytest.mark.parametrize("folder", ["origami_cad", "parts", "tests", "benchmarks"])
def test_no_private_name_crosses_a_module(folder):
    bad = []
    for path in _sources(folder):
        for module, names, line in _imports(path):
            if not _canonical(module).startswith("origami_cad"):
                continue
            for name in names:
                private = name.startswith("_") and not name.startswith("__")
                is_module = (ROOT / Path(*_canonical(module).split(".")) / f"{name}.py").exists()
                if private and not is_module:
                    bad.append(f"{path.relative_to(ROOT)}:{line}: {name} from {module}")
    assert not bad, "\n".join(bad)


def test_the_contract_sees_a_violation(tmp_path):
    """The checker itself: a kinematics module importing the simulation is caught."""
    stage = _stage("origami_cad.kinematics.chain")
    target = _stage(_canonical("origami_cad.simulation.solver"))
    assert ORDER.index(target) > ORDER.index(stage)
    src = tmp_path / "m.py"
    src.write_text("def f():\n    from origami_cad.simulation import simulate\n")
    assert [m for m, _, _ in _imports(src)] == ["origami_cad.simulation"]
