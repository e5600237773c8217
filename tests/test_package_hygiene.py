"""The package's own text: no docstring, comment or page of the documentation cites an
internal issue number, and no module is over 800 lines.

An issue number means nothing to a user reading the installed package; the code says
what it does and why, the changelog and the history say when. Another project's issue
is a source and may be cited by its name (``build123d issues #954``).
"""

from __future__ import annotations

import io
import re
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: "issue 31", "issues 29 and 30", "(#12)": a citation of this project's tracker
CITATION = re.compile(r"(?i)\bissues?\s+#?\d+|\(#\d+\)")
#: another project's tracker, named before the number: allowed
ELSEWHERE = re.compile(r"(?i)\b(build123d|ocp|numpy|scipy|mujoco|trimesh|pyvista)\s+issues?\s+#\d+")


def _texts(path: Path):
    """(line, text) of every comment and string constant (docstrings too) of a file."""
    source = path.read_text(encoding="utf-8")
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type in (tokenize.COMMENT, tokenize.STRING):
            yield tok.start[0], tok.string


def citations(path: Path) -> list[str]:
    """``line: 'citation'`` of every internal issue number a file's text cites."""
    found = []
    for line, text in _texts(path):
        text = ELSEWHERE.sub("", text)
        found += [f"{line}: {m.group(0)!r}" for m in CITATION.finditer(text)]
    return found


def test_no_docstring_or_comment_cites_an_issue_number():
    files = sorted([*(ROOT / "origami_cad").rglob("*.py"), *(ROOT / "parts").rglob("*.py")])
    assert len(files) > 100
    found = [f"{f.relative_to(ROOT)}:{c}" for f in files for c in citations(f)]
    assert not found, "\n".join(found)


def test_no_page_of_the_documentation_or_example_cites_an_issue_number():
    """The documentation, the examples and the benchmarks are read without the tracker."""
    pages = sorted([ROOT / "README.md", *(ROOT / "docs").rglob("*.md")])
    scripts = sorted([*(ROOT / "examples").rglob("*.py"), *(ROOT / "benchmarks").rglob("*.py")])
    assert len(pages) > 10 and scripts
    found = [
        f"{page.relative_to(ROOT)}:{k}: {m.group(0)!r}"
        for page in pages
        for k, line in enumerate(page.read_text(encoding="utf-8").splitlines(), start=1)
        for m in CITATION.finditer(ELSEWHERE.sub("", line))
    ]
    found += [f"{f.relative_to(ROOT)}:{c}" for f in scripts for c in citations(f)]
    assert not found, "\n".join(found)


def test_the_check_sees_a_citation_and_lets_another_projects_pass(tmp_path):
    src = tmp_path / "m.py"
    src.write_text(
        '"""Gait search (issue 31)."""\n'
        "x = 1  # see issues 29 and 30\n"
        "# older build123d issues #954, #1197\n"
        "y = 2  # the same as (#12)\n"
    )
    assert citations(src) == ["1: 'issue 31'", "2: 'issues 29'", "4: '(#12)'"]


#: The most lines a module of the package may have: past it, split it by concept
#: (the record from its clean-up, the results from the solver), not by line count.
MAX_LINES = 800


def test_no_module_is_over_800_lines():
    files = sorted([*(ROOT / "origami_cad").rglob("*.py"), *(ROOT / "parts").rglob("*.py")])
    long = {
        str(f.relative_to(ROOT)): n
        for f in files
        if (n := len(f.read_text(encoding="utf-8").splitlines())) > MAX_LINES
    }
    assert not long, f"modules over {MAX_LINES} lines: {long}"
