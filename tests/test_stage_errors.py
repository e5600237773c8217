"""Errors are raised by the stage they belong to, as ``origami_cad/errors.py`` describes.

Every ``raise`` of an :class:`~origami_cad.errors.OrigamiCadError` in a stage's modules,
and every error class a stage hands to a checker (``checked(SimulationError, ...)``,
``Table(..., DesignError)``, ``load_toml(path, StringsError)``), must be that stage's
class (or a subclass of it defined in the package, e.g. ``MjcfError``, ``StallError``)
or one the table below documents for it. Read from the source, so that a raise on a rare
path counts as much as a common one.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: The classes of ``errors.py`` and the stage each belongs to (errors.py's tree).
OWN = {
    "pattern": {"PatternError"},
    "kinematics": {"PatternError"},  # a pattern it cannot fold
    "design": {"DesignError"},
    "fabrication": {"FabricationError"},
    "parts": {"FabricationError"},  # "fabrication parameters, panels, parts"
    "strings": {"StringsError"},
    "simulation": {"SimulationError"},
    "crawler": {"SimulationError", "DesignError"},  # robot files and crawling; its design search
    "drive": {"DriveError"},
    "parallel": set(),
    "viz": set(),
}
#: What any stage may raise besides its own: a keyword out of range (``OptionsError``), an
#: output that cannot be written safely, a missing extra, and the pattern it was given.
EVERYWHERE = {"OptionsError", "OutputError", "ExtraError", "PatternError"}
#: The documented crossings: a design file is read where patterns are (``pattern.design``);
#: eq. 6's limits are fabrication parameters (``kinematics.limits``); the simulation takes
#: a route (``StringsError`` naming its key or string model); ...
DOCUMENTED = {
    "pattern": {"DesignError"},
    "kinematics": {"FabricationError"},
    "simulation": {"StringsError"},
    # simulate_dcqc's run parameters (steps, stiffness, friction), as the bar-and-hinge
    # simulation's: both quasi-static models refuse them alike
    "strings": {"SimulationError"},
}
BASES = {
    "OrigamiCadError", "PatternError", "DesignError", "FabricationError", "StringsError",
    "SimulationError", "DriveError", "OptionsError", "OutputError", "ExtraError",
}  # fmt: skip


def _subclasses() -> dict[str, str]:
    """Every error class defined in the package and the ``errors.py`` class it derives from."""
    parents: dict[str, str] = {}
    for path in [*(ROOT / "origami_cad").rglob("*.py"), *(ROOT / "parts").rglob("*.py")]:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef):
                for base in node.bases:
                    if isinstance(base, ast.Name):
                        parents.setdefault(node.name, base.id)
    roots = {}
    for name in parents:
        seen, at = set(), name
        while at in parents and at not in BASES and at not in seen:
            seen.add(at)
            at = parents[at]
        if at in BASES:
            roots[name] = at
    return roots | {b: b for b in BASES}


def _used_errors(path: Path, errors: dict[str, str]):
    """(line, class) of every error class a module raises or hands to a call."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.Raise) and node.exc is not None:
            exc = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
            if isinstance(exc, ast.Name) and exc.id in errors:
                yield node.lineno, exc.id
        elif isinstance(node, ast.Call):
            name = getattr(node.func, "id", getattr(node.func, "attr", ""))
            if name in ("isinstance", "issubclass"):
                continue
            for arg in [*node.args, *(k.value for k in node.keywords)]:
                if isinstance(arg, ast.Name) and arg.id in errors:
                    yield node.lineno, arg.id


def stage_of(path: Path) -> str | None:
    rel = path.relative_to(ROOT).parts
    if rel[0] == "parts":
        return "parts"
    return rel[1] if len(rel) > 2 else Path(rel[1]).stem


def test_each_stage_raises_its_own_errors():
    errors = _subclasses()
    assert {"MjcfError", "StallError", "WriteRefused"} <= set(errors)
    bad = []
    files = [*(ROOT / "origami_cad").rglob("*.py"), *(ROOT / "parts").rglob("*.py")]
    for path in sorted(files):
        stage = stage_of(path)
        if stage not in OWN:
            continue  # the base, the commands, the command line and the demo
        allowed = OWN[stage] | EVERYWHERE | DOCUMENTED.get(stage, set())
        for line, name in _used_errors(path, errors):
            if errors[name] not in allowed:
                bad.append(f"{path.relative_to(ROOT)}:{line}: {name} ({errors[name]}) in {stage}")
    assert not bad, "errors raised outside their stage:\n" + "\n".join(bad)


def test_the_check_sees_another_stages_error(tmp_path):
    src = tmp_path / "m.py"
    src.write_text(
        "from origami_cad.errors import DesignError, StringsError\n"
        "def f(x):\n"
        "    if x:\n"
        "        raise DesignError('x')\n"
        "    return Table(x, 'where', StringsError)\n"
    )
    assert list(_used_errors(src, _subclasses())) == [(4, "DesignError"), (5, "StringsError")]
