"""The commands of ``origami-cad``, one registry: each declared once, next to its code.

Each module holds one family of commands (``patterns``, ``design``, ``fabrication``,
``strings``, ``simulation``, ``robot``, ``drive``, ``parts``; the ``demo`` command is
declared by :mod:`origami_cad.demo`, which chains the others); each command is a
:class:`Command` subclass registered with :func:`register`: its name, inputs, outputs and
options (types, units, ranges, help). :mod:`origami_cad.cli` is generated from
:data:`COMMANDS`; :func:`execute` runs a command from Python as the command line does.

>>> sorted(COMMANDS)[:3]
['arm-scene', 'check', 'convert']
"""

from __future__ import annotations

from origami_cad.commands import (  # noqa: F401  (each module registers its commands)
    design,
    drive,
    fabrication,
    parts,
    patterns,
    robot,
    simulation,
    strings,
)
from origami_cad.commands._base import (
    COMMANDS,
    SIZING,
    Command,
    Option,
    Outputs,
    check_suffix,
    execute,
    moved,
    register,
    sources,
    staged,
    wrote,
)

__all__ = [
    "COMMANDS",
    "SIZING",
    "Command",
    "Option",
    "Outputs",
    "check_suffix",
    "execute",
    "moved",
    "register",
    "sources",
    "staged",
    "wrote",
]
