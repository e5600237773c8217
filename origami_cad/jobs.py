"""Deprecated: the commands moved to :mod:`origami_cad.commands` (issue 29).

``origami_cad.jobs.run_fold(design, output, ratio=0.5)`` still works for one release,
with a ``DeprecationWarning``: it is ``origami_cad.commands.execute("fold", design,
output, ratio=0.5)`` (``run_mjcf(source, routes, output)`` keeps its old order).
``Outputs`` is ``origami_cad.commands.Outputs``, ``fabrication_params`` is
``origami_cad.fabrication.fabrication_params`` and ``parameter_default(run_fold, "ratio")``
is ``origami_cad.commands.COMMANDS["fold"].default("ratio")``. Nothing lives here.
"""

from __future__ import annotations

import functools
import warnings

__all__: list[str] = []

_MOVED = {
    "Outputs": ("origami_cad.commands", "Outputs"),
    "fabrication_params": ("origami_cad.fabrication", "fabrication_params"),
}

#: The old jobs' positional order, where it is not the command's.
_OLD_ORDER = {"mjcf": ("source", "routes", "output")}


def _job(command: str):
    """The old ``run_*`` job of ``command``: ``execute`` with its old positional order."""
    from origami_cad.commands import execute

    order = _OLD_ORDER.get(command, ())

    @functools.wraps(execute)
    def job(*args, **kwargs):
        if order:  # by name: the command's own order differs
            if len(args) > len(order):
                raise TypeError(f"run_{command}: at most {len(order)} positional arguments")
            kwargs.update(zip(order, args, strict=False))
            args = ()
        return execute(command, *args, **kwargs)

    job.command = command
    return job


def _parameter_default(job, name: str):
    """The default of an old job's parameter ``name`` (``None`` when it has none)."""
    from origami_cad.commands import COMMANDS

    cls = COMMANDS[getattr(job, "command", job.__name__.removeprefix("run_").replace("_", "-"))]
    flag = any(o.name == name and o.kind == "flag" for o in cls.OPTIONS)
    value = cls.default(name)
    return False if value is None and flag else value


def __getattr__(name: str):
    import importlib

    if name in _MOVED:
        module, new = _MOVED[name]
        where = f"{module}.{new}"
        value = getattr(importlib.import_module(module), new)
    elif name == "parameter_default":
        where = 'origami_cad.commands.COMMANDS["fold"].default("ratio")'
        value = _parameter_default
    elif name.startswith("run_"):
        from origami_cad.commands import COMMANDS

        command = name.removeprefix("run_").replace("_", "-")
        if command not in COMMANDS:
            raise AttributeError(f"module 'origami_cad.jobs' has no attribute {name!r}")
        where = f'origami_cad.commands.execute("{command}", ...)'
        value = _job(command)
    else:
        raise AttributeError(f"module 'origami_cad.jobs' has no attribute {name!r}")
    warnings.warn(
        f"origami_cad.jobs.{name} is deprecated and will be removed in the next release; "
        f"use {where}",
        DeprecationWarning,
        stacklevel=2,
    )
    return value
