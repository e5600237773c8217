"""A griffe extension for the API reference: the top-level ``parts/`` folder read as
``origami_cad.parts``.

setuptools installs ``parts/`` as ``origami_cad.parts`` (``package-dir`` in
pyproject.toml); griffe reads the source tree, whose ``origami_cad/`` has no ``parts/``,
so this extension reads the folder's modules and hangs them under ``origami_cad`` as the
installed package has them.
"""

from __future__ import annotations

from pathlib import Path

import griffe


def _visit(name: str, path: Path, parent: griffe.Module, loader: griffe.GriffeLoader):
    module = griffe.visit(
        name,
        filepath=path,
        code=path.read_text(encoding="utf-8"),
        parent=parent,
        extensions=loader.extensions,
        docstring_parser=loader.docstring_parser,
        docstring_options=loader.docstring_options,
        lines_collection=loader.lines_collection,
        modules_collection=loader.modules_collection,
    )
    parent.set_member(name, module)
    return module


class PartsSubpackage(griffe.Extension):
    """Read ``parts/`` as ``origami_cad.parts`` once ``origami_cad`` is loaded."""

    def on_package(self, *, pkg: griffe.Module, loader: griffe.GriffeLoader, **kwargs) -> None:
        if pkg.name != "origami_cad" or "parts" in pkg.members:
            return
        folder = Path(pkg.filepath).parent.parent / "parts"
        parts = _visit("parts", folder / "__init__.py", pkg, loader)
        for path in sorted(folder.glob("*.py")):
            if path.stem != "__init__":
                _visit(path.stem, path, parts, loader)
