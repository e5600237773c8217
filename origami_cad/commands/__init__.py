"""The commands of ``origami-cad``, one registry: each declared once, next to its code.

Each module holds one family of commands (``patterns``, ``design``, ``fabrication``,
``strings``, ``plan_route``, ``simulation``, ``calibrate``, ``robot``, ``gait``,
``sequence``, ``drive``, ``parts``; ``demo`` is declared by :mod:`origami_cad.demo`,
which chains the others, and ``completion`` by :mod:`origami_cad.cli`, each when its
module is imported); each command is a
:class:`Command` subclass registered with :func:`register`: its name, inputs, outputs and
options (types, units, ranges, help). :mod:`origami_cad.cli` is generated from
:data:`COMMANDS`; :func:`execute` runs a command from Python as the command line does.

>>> COMMANDS["check"].NAME, "calibrate" in COMMANDS
('check', True)
"""

from __future__ import annotations

from origami_cad.commands import (  # noqa: F401  (each module registers its commands)
    calibrate,
    design,
    drive,
    fabrication,
    gait,
    parts,
    patterns,
    plan_route,
    robot,
    sequence,
    simulation,
    strings,
)
from origami_cad.commands._base import (
    COMMANDS,
    FOLDER_HELP,
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

#: The order of ``origami-cad --help`` (a command not named here follows, as registered).
ORDER = (
    "convert", "check", "pattern", "fold", "tg", "design-arm", "fabricate", "route",
    "plan-route", "simulate", "calibrate", "sequence", "arm-scene", "robot", "crawl", "mjcf",
    "emulate", "drive", "part", "demo",
)  # fmt: skip
for _name in sorted(COMMANDS, key=lambda n: ORDER.index(n) if n in ORDER else len(ORDER)):
    COMMANDS[_name] = COMMANDS.pop(_name)

__all__ = [
    "COMMANDS",
    "FOLDER_HELP",
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
