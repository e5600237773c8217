"""One lazy-loading mechanism for the packages whose names are imported on first use.

A package lists each of its names once, in its ``__init__.pyi`` stub, as the import that
gives it (``from origami_cad.fabrication.build import Fabrication, fabricate``): type
checkers and editors read the stub; at run time :func:`attach_stub` reads the same
lines and imports a name's module only when the name is first used (PEP 562), so that
``import origami_cad`` loads no build123d, NumPy or pyvista. The scheme of scikit-image's
``lazy_loader.attach_stub``, without the dependency.
"""

from __future__ import annotations

import ast
import importlib
import os
from collections.abc import Callable
from pathlib import Path

__all__ = ["attach_stub", "stub_names"]


def stub_names(stub: str | os.PathLike[str]) -> dict[str, str]:
    """Each name a stub imports and the module it comes from (absolute imports only)."""
    tree = ast.parse(Path(stub).read_text(encoding="utf-8"))
    names: dict[str, str] = {}
    for node in tree.body:
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant):
            continue  # the stub's docstring
        if not isinstance(node, ast.ImportFrom) or node.level or node.module is None:
            raise ImportError(f"{stub}:{getattr(node, 'lineno', 1)}: not an absolute import")
        for alias in node.names:
            names[alias.asname or alias.name] = node.module
    return names


def attach_stub(
    package: str, init_file: str
) -> tuple[Callable[[str], object], Callable[[], list[str]], list[str]]:
    """``(__getattr__, __dir__, __all__)`` of ``package`` from its ``__init__.pyi``.

    Use as ``__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)`` in the
    package's ``__init__.py``; a name is imported once, then kept in the package.
    """
    names = stub_names(Path(init_file).with_suffix(".pyi"))
    namespace = importlib.import_module(package).__dict__

    def __getattr__(name: str) -> object:
        module = names.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(names))

    return __getattr__, __dir__, sorted(names)
