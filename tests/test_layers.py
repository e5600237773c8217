"""The architecture as a contract: the dependency graph of ``docs/architecture.md``.

The page lists every stage (``pattern``, ``kinematics``, ..., ``cli``, ``demo``) and
module of its own below them (``parallel``) with the ones it imports, ``A → B, C``.
Every import of the package (lazy ones inside functions, and ``importlib.import_module``
of a literal name, too) must be an arrow of that list, every arrow must be an import that
exists, and the graph has no cycle. ``errors``, ``_fileio``, ``_inputs``, ``_libm``, ``_names``
and ``_toml`` are the base every node may use. Names starting with an underscore never cross
a module boundary, in the package, its tests or its benchmarks.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BASE = {
    "origami_cad",
    "origami_cad.errors",
    "origami_cad._fileio",
    "origami_cad._lazy",
    "origami_cad._signals",
    "origami_cad._inputs",
    "origami_cad._libm",
    "origami_cad._names",
    "origami_cad._toml",
    "origami_cad._args",
    "origami_cad._display",
}
PAGE = ROOT / "docs" / "architecture.md"
ARROW = re.compile(r"^(\w+)\s*→\s*(.*)$")
DYNAMIC = {"import_module", "__import__"}  # importlib.import_module("..."), __import__("...")


def documented_graph(text: str | None = None) -> dict[str, set[str]]:
    """The graph the page draws: the lines ``A → B, C`` of its "dependency graph" block."""
    text = PAGE.read_text(encoding="utf-8") if text is None else text
    block = re.search(r"## The dependency graph.*?```text\n(.*?)```", text, flags=re.S)
    assert block, "docs/architecture.md has no ```text block under '## The dependency graph'"
    graph: dict[str, set[str]] = {}
    for line in block.group(1).splitlines():
        match = ARROW.match(line.strip())
        if match:
            targets = {t.strip() for t in match.group(2).split("#")[0].split(",")}
            graph[match.group(1)] = targets - {""}
    return graph


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


def _is_module(dotted: str) -> bool:
    path = ROOT / Path(*_canonical(dotted).split("."))
    if dotted.startswith(("parts", "origami_cad.parts")):
        path = ROOT / Path(*_canonical(dotted).split(".")[1:])
    return path.with_suffix(".py").exists() or (path / "__init__.py").exists()


def _dynamic_import(node: ast.Call) -> str | None:
    """The literal module name of ``importlib.import_module("...")`` or ``__import__``."""
    func = node.func
    name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", None)
    if name in DYNAMIC and node.args and isinstance(node.args[0], ast.Constant):
        value = node.args[0].value
        return value if isinstance(value, str) else None
    if name in DYNAMIC and node.args and isinstance(node.args[0], ast.JoinedStr):
        # f"origami_cad.fabrication.{module}" (a lazy __init__): at least that package
        head = node.args[0].values[0] if node.args[0].values else None
        if isinstance(head, ast.Constant) and isinstance(head.value, str):
            return head.value.rpartition(".")[0] or None
    return None


def _names_a_module(node: ast.AST) -> bool:
    """A string constant that is the dotted name of a module of the package."""
    return (
        isinstance(node, ast.Constant)
        and isinstance(node.value, str)
        and re.fullmatch(r"origami_cad(\.\w+)+", node.value) is not None
        and _is_module(node.value)
    )


def _imports(path: Path):
    """(imported module, imported names, line) of every import in a file, lazy ones too.

        ``from origami_cad import jobs`` is an import of the module ``origami_cad.jobs``, and
    ``importlib.import_module("origami_cad.x")`` of ``origami_cad.x``, as is the string
    ``"origami_cad.x"`` (a module named for importlib).
    """
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
            names = [a.name for a in node.names]
            yield module, names, node.lineno
            for name in names:
                if _canonical(module) in BASE and _is_module(f"{module}.{name}"):
                    yield f"{module}.{name}", [], node.lineno
        elif isinstance(node, ast.Call) and (module := _dynamic_import(node)):
            yield module, [], node.lineno
        elif _names_a_module(node):  # a module's name for importlib, kept in a variable
            yield node.value, [], node.lineno


def _sources(*folders: str) -> list[Path]:
    """The modules of ``folders``, and the stubs of the lazy packages (``__init__.pyi``:
    the imports :func:`origami_cad._lazy.attach_stub` makes on first use)."""
    found = [p for f in folders for p in (ROOT / f).rglob("*.py")]
    found += [p for f in folders for p in (ROOT / f).rglob("__init__.pyi")]
    return sorted(found)


def _canonical(module: str) -> str:
    return "origami_cad." + module if module == "parts" or module.startswith("parts.") else module


def code_graph() -> dict[tuple[str, str], list[str]]:
    """Every import from one node to another: (importer, imported) -> where."""
    edges: dict[tuple[str, str], list[str]] = {}
    for path in _sources("origami_cad", "parts"):
        stage = _stage(_module_name(path))
        if stage is None:
            continue
        for module, _, line in _imports(path):
            target = _stage(_canonical(module))
            if target is not None and target != stage:
                edges.setdefault((stage, target), []).append(f"{path.relative_to(ROOT)}:{line}")
    return edges


def test_every_import_is_an_arrow_of_the_documented_graph():
    assert len(_sources("origami_cad", "parts")) > 40
    graph = documented_graph()
    bad = [
        f"{where[0]}: {a} imports {b}, no arrow {a} → {b} in docs/architecture.md"
        for (a, b), where in sorted(code_graph().items())
        if b not in graph.get(a, ())
    ]
    assert not bad, "\n".join(bad)


def test_every_documented_arrow_is_an_import_that_exists():
    edges = code_graph()
    missing = [
        f"{a} → {b}" for a, ts in documented_graph().items() for b in ts if (a, b) not in edges
    ]
    assert not missing, f"docs/architecture.md draws arrows no import makes: {missing}"


def test_every_arrow_of_the_data_table_is_an_import_that_exists():
    """The page's "what crosses each boundary" rows ``a → b, c`` (b and c import a)."""
    rows = re.findall(r"^\| (\w+) → ([\w, ]+) \|", PAGE.read_text(encoding="utf-8"), re.M)
    rows = [(a, b) for a, b in rows if a != "from"]  # the header
    assert len(rows) >= 6
    edges = code_graph()
    missing = [
        f"{a} → {b}"
        for a, targets in rows
        for b in map(str.strip, targets.split(","))
        if (b, a) not in edges
    ]
    assert not missing, f"docs/architecture.md's data table draws arrows no import makes: {missing}"


def test_the_graph_names_every_node_and_has_no_cycle():
    graph = documented_graph()
    nodes = {_stage(_module_name(p)) for p in _sources("origami_cad", "parts")} - {None}
    assert nodes == set(graph), (
        f"nodes in the code but not the page (or back): {nodes ^ set(graph)}"
    )
    done: set[str] = set()

    def visit(node: str, path: tuple[str, ...]) -> None:
        assert node not in path, f"cycle: {' → '.join((*path, node))}"
        if node not in done:
            for target in graph[node]:
                visit(target, (*path, node))
            done.add(node)

    for node in graph:
        visit(node, ())


def _type_checking_lines(tree: ast.AST) -> set[int]:
    """The lines of ``if TYPE_CHECKING:`` blocks: imports for type checkers only."""
    lines: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and getattr(node.test, "id", None) == "TYPE_CHECKING":
            for child in node.body:
                lines.update(n.lineno for n in ast.walk(child) if hasattr(n, "lineno"))
    return lines


def module_graph() -> dict[str, set[str]]:
    """Every module of the package and the modules it imports at run time (at module
    level or inside a function; not in ``if TYPE_CHECKING:``), the top-level package's
    lazy stub left out (it names the modules of the API, it imports none of them until a
    name is used). A lazy package's ``__init__.pyi`` counts as its ``__init__.py``'s.

    The notebook hooks' one call up (``_display`` -> ``viz.notebook``, when an object is
    displayed, as trimesh's ``_repr_html_`` reaches its viewer) is the documented way of
    the base into a stage (test_the_notebook_hooks_reach_the_viz_only_on_display), not
    an arrow of the graph."""
    paths = _sources("origami_cad", "parts")
    modules = {_module_name(p) for p in paths}
    graph: dict[str, set[str]] = {}
    for path in paths:
        name = _module_name(path)
        if name == "origami_cad":
            continue
        skip = _type_checking_lines(ast.parse(path.read_text(encoding="utf-8")))
        targets = graph.setdefault(name, set())
        for module, names, line in _imports(path):
            if line in skip:
                continue
            module = _canonical(module)
            for dotted in (module, *(f"{module}.{n}" for n in names)):
                if dotted in modules and dotted not in (name, "origami_cad"):
                    targets.add(dotted)
    graph["origami_cad._display"].discard("origami_cad.viz.notebook")
    return graph


def import_circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The circles of a module graph: each strongly connected set of more than one
    module, as one path around it."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    circles: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            members = []
            while True:
                w = stack.pop()
                members.append(w)
                if w == v:
                    break
            if len(members) > 1:
                circles.append(sorted(members))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return circles


def test_no_import_circle_between_modules():
    """Not only the stages: no two modules import each other, directly or around a
    circle, at module level or lazily inside a function."""
    graph = module_graph()
    assert len(graph) > 100
    circles = import_circles(graph)
    assert not circles, "import circles: " + "; ".join(" <-> ".join(c) for c in circles)


def test_the_circle_finder_sees_every_circle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": {"f"}, "f": {"e"}}
    assert import_circles(graph) == [["a", "b", "c"], ["e", "f"]]
    assert import_circles({"a": {"b"}, "b": set()}) == []


def test_the_notebook_hooks_reach_the_viz_only_on_display():
    """``_display.py`` is the base's one way into a stage: the module that draws, named for
    importlib and imported inside a function (when an object is displayed), never at import."""
    path = ROOT / "origami_cad" / "_display.py"
    tree = ast.parse(path.read_text(encoding="utf-8"))
    top = [n for n in tree.body if isinstance(n, (ast.Import, ast.ImportFrom))]
    assert all(
        _stage(_canonical(m.module or "")) is None for m in top if isinstance(m, ast.ImportFrom)
    )
    staged = {m for m, _, _ in _imports(path) if _stage(_canonical(m)) is not None}
    assert staged == {"origami_cad.viz.notebook"}


def test_the_base_imports_no_stage():
    for name in (
        "errors.py", "_fileio.py", "_signals.py", "_lazy.py", "_inputs.py", "_libm.py",
        "_names.py", "_toml.py",
    ):  # fmt: skip
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
    """The checker itself: a kinematics module importing the simulation, directly or
    through importlib, is an import the graph has no arrow for."""
    graph = documented_graph()
    assert "simulation" not in graph["kinematics"]
    src = tmp_path / "m.py"
    src.write_text(
        "import importlib\n"
        "SOLVER = 'origami_cad.simulation.solver'\n"
        "def f():\n"
        "    from origami_cad.simulation import simulate\n"
        "    importlib.import_module(SOLVER)\n"
        "    return importlib.import_module('origami_cad.simulation.model')\n"
        "def g(name):\n"
        "    return importlib.import_module(f'origami_cad.simulation.{name}')\n"
    )
    found = sorted({(line, _stage(m)) for m, _, line in _imports(src)})
    assert found == [
        (1, None), (2, "simulation"), (4, "simulation"), (6, "simulation"), (8, "simulation")
    ]  # fmt: skip


def test_the_lazy_packages_are_seen_importing_their_modules():
    """fabrication/ and viz/ import their names on first use, from the modules their
    ``__init__.pyi`` names: the checker reads the stub's imports as the package's."""
    for stage, module in (("fabrication", "build"), ("viz", "pyvista_mesh")):
        stub = ROOT / "origami_cad" / stage / "__init__.pyi"
        assert stub in _sources("origami_cad")
        found = {m for m, _, _ in _imports(stub)}
        assert f"origami_cad.{stage}.{module}" in found, found


def test_the_page_parser_reads_arrows_and_empty_nodes():
    text = "## The dependency graph\n\n```text\nb   →\na   → b, c  # note\n```\n"
    assert documented_graph(text) == {"a": {"b", "c"}, "b": set()}
