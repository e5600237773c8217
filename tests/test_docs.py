"""Every Python code block of the README and docs/ runs (the docs cannot drift from the code)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def blocks(page: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)


@pytest.mark.parametrize("page", [p for p in PAGES if blocks(p)], ids=lambda p: p.name)
def test_code_blocks_run(page, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    namespace: dict = {}
    for code in blocks(page):  # blocks of one page share a namespace, in order
        exec(compile(code, str(page), "exec"), namespace)


# ------------------------------------------------------------------ names the docs cite

IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*(\(\))?")


def _defined_names() -> tuple[dict[str, set[str]], set[str]]:
    """Each module of the package (dotted name) with the names it defines or imports, and
    every name defined anywhere (modules, functions, classes, methods, constants, fields;
    not imports: ``Sequence`` must be the drive's class, not ``collections.abc``'s)."""
    import ast

    modules: dict[str, set[str]] = {}
    everywhere: set[str] = set()
    for top in ("origami_cad", "parts"):
        for path in sorted((ROOT / top).rglob("*.py")):
            rel = path.relative_to(ROOT).with_suffix("").parts
            dotted = ".".join(("origami_cad", *rel) if top == "parts" else rel)
            dotted = dotted.removesuffix(".__init__")
            names, imported = set(), set()
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                    names.add(node.name)
                elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
                    names.add(node.id)
                elif isinstance(node, ast.ImportFrom | ast.Import):
                    imported.update((a.asname or a.name).split(".")[0] for a in node.names)
            modules[dotted] = names | imported  # a module re-exports what it imports
            everywhere |= names | {dotted.rsplit(".", 1)[-1]}
    return modules, everywhere


def _resolves(name: str, modules: dict[str, set[str]], everywhere: set[str]) -> bool:
    """A dotted ``origami_cad...`` name is a module or a name in its module; a file name
    (``x.py``, ``a/b``) exists in the repository or the package; an identifier is defined
    somewhere in the package."""
    if name.endswith((".py", ".pyi", ".md", "/")) or "/" in name:
        base = name.rstrip("/")
        return (
            (ROOT / base).exists()
            or (ROOT / "origami_cad" / base).exists()
            or any(
                next((ROOT / top).rglob(base), None) is not None
                for top in ("origami_cad", "parts", "docs")
            )
        )
    name = name.removesuffix("()")
    if name.startswith("origami_cad."):
        if name in modules:
            return True
        module, _, attr = name.rpartition(".")
        return attr in modules.get(module, set())
    return all(part in everywhere for part in name.split(".") if part != "self")


def cited_names(page: Path) -> list[str]:
    """The code names a page cites: backticked identifiers (a call's name without its
    arguments) that are dotted, capitalised or contain an underscore (so ``p`` or
    ``load`` are left alone), and the file names in backticks and in diagrams."""
    text = page.read_text(encoding="utf-8")
    out = []
    for token in re.findall(r"`([^`\n]+)`", text):
        call = re.match(r"([A-Za-z_][\w.]*)\(", token)
        token = call.group(1) if call else token
        if re.fullmatch(r"[\w./-]+\.(py|md)|[\w.-]+(/[\w.-]+)*/", token):
            out.append(token)
        elif (
            IDENT.fullmatch(token)
            and ("." in token or "_" in token or token[0].isupper())
            and token not in {"None", "True", "False"}
            and not re.fullmatch(r"[A-Za-z]_\w{1,2}", token)  # maths: v_0, T_s, T_e
        ):
            out.append(token)
    fences = re.findall(r"^```(\w*)\n(.*?)^```", text, flags=re.S | re.M)  # paired fences
    for block in (body for lang, body in fences if not lang):  # the diagrams
        out += re.findall(r"\b\w+\.py\b", block)
    return out


def test_the_architecture_page_cites_only_names_that_exist():
    """docs/architecture.md is read by a newcomer: every module, file, class and function
    it names must still be there (a rename or a removal fails here)."""
    page = ROOT / "docs" / "architecture.md"
    modules, everywhere = _defined_names()
    names = cited_names(page)
    assert len(names) > 40  # the test reads the page's names, not nothing
    missing = sorted({n for n in names if not _resolves(n, modules, everywhere)})
    assert not missing, f"docs/architecture.md names what does not exist: {missing}"
    links = re.findall(r"\]\(([^)#]+)\)", page.read_text(encoding="utf-8"))
    assert all((page.parent / link).exists() for link in links), links


def _python_names(text: str) -> set[str]:
    """The dotted names of the package a page cites in backticks (``oc.`` is the
    package's usual alias: ``import origami_cad as oc``); a pattern (``run_*``) is not one."""
    out = set()
    for token in re.findall(r"`([^`\n]+)`", text):
        match = re.match(r"(origami_cad|oc)((?:\.\w+)+)(\*?)", token)
        if match and not match.group(3):
            out.add("origami_cad" + match.group(2))
    return out


def _imported(name: str):
    """What ``name`` is, as a script gets it: its longest importable module, then getattr."""
    import importlib

    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        try:
            value = importlib.import_module(".".join(parts[:k]))
        except ModuleNotFoundError:
            continue
        for attr in parts[k:]:
            value = getattr(value, attr)
        return value
    raise ModuleNotFoundError(name)


def test_every_python_name_the_docs_cite_imports():
    """A user's script keeps working: each ``origami_cad.x.y`` (or ``oc.x``) of the README
    and docs/ is imported and looked up as a script would (a moved name may warn)."""
    import warnings

    cited = {(n, p.name) for p in PAGES for n in _python_names(p.read_text(encoding="utf-8"))}
    assert len(cited) > 40
    broken = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        for name, page in sorted(cited):
            try:
                _imported(name)
            except (ImportError, AttributeError) as exc:
                broken.append(f"{page}: {name}: {exc}")
    assert not broken, "\n".join(broken)
    # the lookup sees a name that does not exist
    with pytest.raises(AttributeError):
        _imported("origami_cad.fabrication.no_such_name")
    assert _python_names("`oc.fabricate`, `origami_cad.jobs.run_*`") == {"origami_cad.fabricate"}


# ------------------------------------------------------------------ the pictures of the docs


def _gallery_hook():
    """docs/hooks/gallery.py, the mkdocs hook that draws the pictures at build time."""
    import importlib.util

    pytest.importorskip("mkdocs", reason="the docs extra is not installed (pip install .[docs])")
    import sys

    name = "origami_cad_docs_gallery_hook"
    if name not in sys.modules:  # its dataclasses look their module up
        spec = importlib.util.spec_from_file_location(name, ROOT / "docs/hooks/gallery.py")
        sys.modules[name] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules[name])
    return sys.modules[name]


def test_every_picture_a_page_shows_is_drawn_by_the_docs_build_or_committed():
    """``make docs`` (run by .ci/run) draws the gallery/ pictures; here, without building:
    every image a page links is a committed file or under the folder of a gallery figure,
    and each figure's guide page shows at least one of its pictures."""
    figures = {fig.key: fig for fig in _gallery_hook().FIGURES}
    assert len(figures) >= 6
    shown: dict[str, set[str]] = {}
    for page in sorted((ROOT / "docs").glob("*.md")):
        for link in re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", page.read_text(encoding="utf-8")):
            if link.startswith("gallery/"):
                key = link.split("/")[1]
                assert key in figures, f"{page.name}: {link} is drawn by no gallery figure"
                shown.setdefault(key, set()).add(page.name)
            else:
                assert (page.parent / link).is_file(), f"{page.name}: {link} does not exist"
    for key, fig in figures.items():
        assert (ROOT / "docs" / fig.page).is_file(), fig.page
        assert fig.page in shown.get(key, set()), f"{fig.page} shows no picture of {key}"
    gallery = (ROOT / "docs" / "gallery.md").read_text(encoding="utf-8")
    assert _gallery_hook().MARKER in gallery
