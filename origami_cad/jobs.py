"""Deprecated: the commands moved to :mod:`origami_cad.commands` (issue 29).

``origami_cad.jobs.run_fold(design, output, ratio=0.5)`` still works for one release,
with a ``DeprecationWarning``: it is ``origami_cad.commands.execute("fold", design,
output, ratio=0.5)``. ``Outputs`` is ``origami_cad.commands.Outputs`` and
``fabrication_params`` is ``origami_cad.fabrication.fabrication_params``. Nothing lives here.
"""

from __future__ import annotations

import functools
import warnings

__all__: list[str] = []

_MOVED = {
    "Outputs": ("origami_cad.commands", "Outputs"),
    "fabrication_params": ("origami_cad.fabrication", "fabrication_params"),
}


def __getattr__(name: str):
    import importlib

    if name in _MOVED:
        module, new = _MOVED[name]
        where = f"{module}.{new}"
        value = getattr(importlib.import_module(module), new)
    elif name.startswith("run_"):
        from origami_cad.commands import COMMANDS, execute

        command = name.removeprefix("run_").replace("_", "-")
        if command not in COMMANDS:
            raise AttributeError(f"module 'origami_cad.jobs' has no attribute {name!r}")
        where = f'origami_cad.commands.execute("{command}", ...)'
        value = functools.wraps(execute)(functools.partial(execute, command))
    else:
        raise AttributeError(f"module 'origami_cad.jobs' has no attribute {name!r}")
    warnings.warn(
        f"origami_cad.jobs.{name} is deprecated and will be removed in the next release; "
        f"use {where}",
        DeprecationWarning,
        stacklevel=2,
    )
    return value
