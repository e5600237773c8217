"""Crease-pattern file formats: one module per format, merged into one registry.

=========  =====================  ======================================
suffix     module                 notes
=========  =====================  ======================================
``.fold``  :mod:`.formats.fold`   FOLD 1.2 (JSON), lossless
``.dxf``   :mod:`.formats.dxf`    layers Mountain/Valley/Cut/Border, mm
``.svg``   :mod:`.formats.svg`    Origami Simulator colour convention
``.json``  :mod:`.formats.pygamix` PyGamiX's designs (read only), FOLD
``.opx``   :mod:`.formats.opx`    ORIPA's XML (line types, y down)
``.cp``    :mod:`.formats.cp`     ORIPA's plain text (Orihime, Rabbit Ear)
=========  =====================  ======================================

Each format module ends in two small dicts, ``readers`` and ``writers``, from a
lower-case suffix to ``read(path, mm_per_unit) -> CreasePattern`` (mm; ``mm_per_unit``
None for the unit the file declares; a reader that also takes ``tolerance=`` (mm, see
:func:`~origami_cad.pattern.planar.import_tolerance`) honours ``--tolerance``) and
``write(cp, path) -> Path`` (atomic).
:data:`READERS` and :data:`WRITERS` merge them; :func:`origami_cad.pattern.read_pattern`
and :func:`~origami_cad.pattern.write_pattern` dispatch through them. A new format is
its module and one line of :data:`MODULES`.

>>> sorted(READERS), sorted(WRITERS)
(['.cp', '.dxf', '.fold', '.json', '.opx', '.svg'], ['.cp', '.dxf', '.fold', '.opx', '.svg'])
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from origami_cad._toml import printable
from origami_cad.errors import PatternError
from origami_cad.pattern.formats import cp, dxf, fold, opx, pygamix, svg

__all__ = ["MODULES", "READERS", "WRITERS", "reader", "register", "writer"]

#: The format modules, one line each; their ``readers``/``writers`` make the registry.
MODULES = (
    fold,
    dxf,
    svg,
    pygamix,
    opx,
    cp,
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
