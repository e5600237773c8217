"""Crease-pattern file formats: one module per format, merged into one registry.

=========  =====================  ======================================
suffix     module                 notes
=========  =====================  ======================================
``.fold``  :mod:`.formats.fold`   FOLD 1.2 (JSON), lossless
``.dxf``   :mod:`.formats.dxf`    layers Mountain/Valley/Cut/Border, mm
``.svg``   :mod:`.formats.svg`    Origami Simulator colour convention
``.json``  :mod:`.formats.pygamix` PyGamiX's designs (read only), FOLD
=========  =====================  ======================================

Each format module ends in two small dicts, ``readers`` and ``writers``, from a
lower-case suffix to ``read(path, mm_per_unit) -> CreasePattern`` (mm; ``mm_per_unit``
None for the unit the file declares) and ``write(cp, path) -> Path`` (atomic).
:data:`READERS` and :data:`WRITERS` merge them; :func:`origami_cad.pattern.read_pattern`
and :func:`~origami_cad.pattern.write_pattern` dispatch through them. A new format is
its module and one line of :data:`MODULES`.

>>> sorted(READERS), sorted(WRITERS)
(['.dxf', '.fold', '.json', '.svg'], ['.dxf', '.fold', '.svg'])
"""

from __future__ import annotations

import importlib.abc
import importlib.util
import sys
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any, ClassVar

from origami_cad._toml import printable
from origami_cad.errors import PatternError
from origami_cad.pattern.formats import dxf, fold, pygamix, svg

__all__ = ["MODULES", "READERS", "WRITERS", "reader", "register", "writer"]

#: The format modules, one line each; their ``readers``/``writers`` make the registry.
MODULES = (
    fold,
    dxf,
    svg,
    pygamix,
)

MODULES_BY_NAME = {m.__name__.rsplit(".", 1)[-1]: m for m in MODULES}
#: suffix -> ``read(path, mm_per_unit) -> CreasePattern``
READERS: dict[str, Callable[..., Any]] = {k: v for m in MODULES for k, v in m.readers.items()}
#: suffix -> ``write(cp, path) -> Path``
WRITERS: dict[str, Callable[..., Path]] = {k: v for m in MODULES for k, v in m.writers.items()}


def register(module: Any) -> None:
    """Add a format module's ``readers`` and ``writers`` (suffix -> function) to the registry.

    For a format outside the package (a plugin, a test); the package's own are in
    :data:`MODULES`.
    """
    READERS.update({k.lower(): v for k, v in getattr(module, "readers", {}).items()})
    WRITERS.update({k.lower(): v for k, v in getattr(module, "writers", {}).items()})


def _lookup(registry: dict, path: Path, what: str, known: str) -> Callable[..., Any]:
    try:
        return registry[path.suffix.lower()]
    except KeyError:
        suffix = path.suffix.lower() or "(no extension)"
        raise PatternError(
            f"{printable(str(path), 300)}: {what} {suffix!r} ({known}: {', '.join(registry)}"
            f"{'; .png through origami_cad.viz' if registry is WRITERS else ''})"
        ) from None


def reader(path: Path) -> Callable[..., Any]:
    """The reader of ``path`` by its suffix; :class:`PatternError` naming the readable ones."""
    return _lookup(READERS, path, "unknown crease-pattern format", "readable")


def writer(path: Path) -> Callable[..., Path]:
    """The writer of ``path`` by its suffix; :class:`PatternError` naming the writable ones."""
    return _lookup(WRITERS, path, "cannot write crease patterns as", "writable")


class _MovedFormats(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """The old paths ``origami_cad.pattern.dxf``, ``.svg`` and ``.fold``: importing one
    gives the format's module here, with a ``DeprecationWarning`` (for one release)."""

    OLD: ClassVar[dict[str, str]] = {f"origami_cad.pattern.{n}": n for n in ("dxf", "fold", "svg")}

    def find_spec(self, fullname: str, path: Any = None, target: Any = None) -> Any:
        if fullname not in self.OLD:
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec: Any) -> Any:
        name = self.OLD[spec.name]
        warnings.warn(
            f"{spec.name} moved to origami_cad.pattern.formats.{name}",
            DeprecationWarning,
            stacklevel=2,
        )
        return MODULES_BY_NAME[name]

    def exec_module(self, module: Any) -> None:
        """The module is the format's, already run."""


if not any(isinstance(f, _MovedFormats) for f in sys.meta_path):
    sys.meta_path.append(_MovedFormats())
