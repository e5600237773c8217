"""One writer per file format: no module but a format's writer spells its tables.

The project's TOML formats (docs/architecture.md, "The project's file formats") are each
written by one function beside its reader. A second writer (a template string, f-strings
building ``[route]`` lines, a ``toml_table("leg", ...)`` call elsewhere) writes files its
reader may not read back the same; this test finds one in ``origami_cad/`` and ``parts/``
by the tables it spells: a string line that is a table header, or ``toml_table`` called
with a table's name. Docstrings, comparisons (``"[robot]" in text`` sniffs a file) and
error messages (a header in the middle of a line) are not writers.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: format: (its writer's module, the tables it writes)
FORMATS = {
    "route": ("origami_cad/strings/route.py", {"tsa", "fabrication", "route", "route.strings"}),
    "robot": (
        "origami_cad/crawler/robot.py",
        {"robot", "fabrication", "leg", "mass", "adapter", "gait", "gait.keyframe"},
    ),
    "sequence": ("origami_cad/drive/sequence.py", {"sequence", "tsa", "keyframe"}),
    "design": ("origami_cad/pattern/design.py", {"pattern"}),
    "task": ("origami_cad/design/task.py", {"arm", "fabrication", "search", "obstacle"}),
}
#: the generic TOML writer every format's writer calls
GENERIC = {"origami_cad/_toml.py"}
HEADER = re.compile(r"(?m)^[ \t]*\[\[?([A-Za-z_][\w.]*)\]\]?[ \t]*(?:#.*)?$")


def _allowed(table: str) -> set[str]:
    return {module for module, tables in FORMATS.values() if table in tables}


def _docstrings(tree: ast.AST) -> set[int]:
    """ids of the docstring constants of a module, its classes and functions."""
    out = set()
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr):
            value = body[0].value
            if isinstance(value, ast.Constant) and isinstance(value.value, str):
                out.add(id(value))
    return out


def _strings(tree: ast.AST):
    """(line, text) of every string literal that is not a docstring or a comparison's
    operand; an f-string's text with ``{}`` for each value."""
    skip = _docstrings(tree)
    for node in ast.walk(tree):
        if isinstance(node, ast.Compare):
            for side in (node.left, *node.comparators):
                skip.add(id(side))
    inside = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.JoinedStr):
            inside.update(id(v) for v in node.values)
            if id(node) not in skip:
                text = "".join(
                    v.value if isinstance(v, ast.Constant) else "{}" for v in node.values
                )
                yield node.lineno, text
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Constant)
            and isinstance(node.value, str)
            and id(node) not in skip | inside
        ):
            yield node.lineno, node.value


def tables_written(source: str) -> list[tuple[int, str]]:
    """(line, table) of each table a module's source spells as a writer would."""
    tree = ast.parse(source)
    found = [(line, m.group(1)) for line, text in _strings(tree) for m in HEADER.finditer(text)]
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and node.args:
            f = node.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            first = node.args[0]
            if name == "toml_table" and isinstance(first, ast.Constant):
                found.append((node.lineno, str(first.value)))
    return found


def test_the_search_finds_a_second_writer():
    """The kinds of writer it replaced: a template, f-string lines, a toml_table call."""
    template = 'TEXT = """# a leg\\n[[leg]]\\npanel = "{label}"\\n"""\n'
    lines = 'def f(x):\n    return ["[route]", f"thickness = {x}", "", "[[route.strings]]"]\n'
    call = 'def g(t):\n    return toml_table("gait.keyframe", t, array=True)\n'
    assert tables_written(template) == [(1, "leg")]
    assert sorted(t for _, t in tables_written(lines)) == ["route", "route.strings"]
    assert tables_written(call) == [(2, "gait.keyframe")]
    # what is no writer: a docstring, a sniff, an error message naming a table
    quiet = (
        'def h(text, p):\n    """[route]\n    thickness = 2"""\n'
        '    if "[robot]" in text:\n        raise ValueError(f"{p} [[leg]] #2: bad")\n'
    )
    assert tables_written(quiet) == []


def test_each_format_is_written_by_its_one_writer():
    """Every table a module spells is one its format's writer module writes."""
    wrong = []
    files = [*sorted((ROOT / "origami_cad").rglob("*.py")), *sorted((ROOT / "parts").rglob("*.py"))]
    seen = set()
    for path in files:
        rel = path.relative_to(ROOT).as_posix()
        if rel in GENERIC:
            continue
        for line, table in tables_written(path.read_text(encoding="utf-8")):
            allowed = _allowed(table)
            if allowed and rel not in allowed:
                wrong.append(f"{rel}:{line}: writes [{table}] (its writer: {sorted(allowed)})")
            seen.add((rel, table))
    assert not wrong, "\n".join(wrong)
    for fmt, (module, tables) in FORMATS.items():  # each writer is found where it is
        assert any((module, t) in seen for t in tables), (fmt, module)
