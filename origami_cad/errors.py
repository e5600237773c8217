"""Exception types of the package.

Every error a user can cause by giving bad input is an :class:`OrigamiCadError`;
its message names the file, key, entity, panel or servo and what is wrong, so the
command-line tool can print it as one line and exit with code 2.

One class per stage, so that a handler catches the faults of one stage only::

    OrigamiCadError
    ├── PatternError       crease patterns and their files (.fold, .dxf, .svg)
    ├── DesignError        design and arm-task files, the arm's and the crawler's design search
    ├── FabricationError   fabrication parameters (eq. 6), panels, parts
    ├── StringsError       TSAs, string routes and route files, the route planner
    ├── SimulationError    the bar-and-hinge simulation and the DCQC model's run
    │                      parameters, robot files, crawling
    ├── DriveError         sequence files, servo buses, the emulator (drive/)
    ├── OptionsError       a command-line option or a keyword out of range
    ├── OutputError        an output path that cannot be written safely
    └── ExtraError         a feature whose optional dependencies (an extra) are missing

Any stage may also raise ``PatternError`` (the pattern it was given), ``OptionsError``,
``OutputError`` and ``ExtraError``; ``tests/test_stage_errors.py`` checks every stage.

The finer driving faults (``StallError``, ``PortLostError``, ...) derive from
:class:`DriveError` and live in :mod:`origami_cad.drive.errors`.

>>> issubclass(DriveError, OrigamiCadError), issubclass(DriveError, DesignError)
(True, False)
"""

from __future__ import annotations

import logging
import os
import sys
import warnings

__all__ = [
    "DesignError",
    "DesignWarning",
    "DriveError",
    "ExtraError",
    "FabricationError",
    "OptionsError",
    "OrigamiCadError",
    "OrigamiCadWarning",
    "OutputError",
    "PatternError",
    "SimulationError",
    "StringsError",
    "warn",
]


class OrigamiCadError(Exception):
    r"""Base class of every error caused by bad input.

    Its message is one line: a control character in it (a file named with a newline, a
    bidirectional override) is shown escaped, whatever built the message.

    >>> str(OrigamiCadError("a\nb.toml: missing key 'pattern'"))
    "a\\nb.toml: missing key 'pattern'"
    """

    def __init__(self, *args: object) -> None:
        if len(args) == 1 and isinstance(args[0], str) and not args[0].isprintable():
            args = ("".join(c if c.isprintable() else repr(c)[1:-1] for c in args[0]),)
        super().__init__(*args)


class PatternError(OrigamiCadError, ValueError):
    """A crease pattern, or a file holding one, is malformed or cannot be used."""


class DesignError(OrigamiCadError, ValueError):
    """A design or task description (usually a TOML file) is malformed, or the arm's
    design search cannot run with it."""


class OrigamiCadWarning(UserWarning):
    """A result the library returned but that may print, fold or walk badly (a panel's
    bias reduced, a sheet larger than the print bed...): the user should act on it."""


def warn(message: str, category: type[Warning] = OrigamiCadWarning, stacklevel: int = 2) -> None:
    """Say ``message`` where a script and a tool see it: ``warnings.warn`` (shown once
    per place by Python's default filter) and the ``origami_cad`` logger at WARNING
    (silent unless the script configures logging; the command line prints it on stderr).

    ``stacklevel`` is ``warnings.warn``'s, counted from the caller of :func:`warn`; the
    warning is shown at the first line outside the package at or above it (the user's
    call, never the package's argument checks), wherever ``warn`` is called from.
    """
    logging.getLogger("origami_cad").warning(message, extra={"origami_cad_warning": True})
    warnings.warn(message, category, stacklevel=_outside_level(stacklevel + 1))


def _outside_level(stacklevel: int) -> int:
    """``stacklevel`` (counted from :func:`warn`'s caller's caller), raised past the
    package's own frames, so that ``warnings.warn`` names the script's line."""
    package = os.path.dirname(os.path.abspath(__file__))
    inside = (package + os.sep, os.path.join(os.path.dirname(package), "parts") + os.sep)
    frame = sys._getframe(1)  # warn's frame is level 1 of warnings.warn's count
    level = 1
    while frame is not None and (level < stacklevel or frame.f_code.co_filename.startswith(inside)):
        frame = frame.f_back
        level += 1
    return level if frame is not None else stacklevel


class DesignWarning(OrigamiCadWarning):
    """A design search found a result it could not fully confirm (for example, an arm
    whose strings cannot fold it over its whole fold range); the result is still returned."""


class FabricationError(OrigamiCadError, ValueError):
    """Fabrication parameters (eq. 6, panels, holes) or a part's parameters are unusable."""


class StringsError(OrigamiCadError, ValueError):
    """A TSA, a string route (or its file) or a route search is malformed or impossible."""


class SimulationError(OrigamiCadError, ValueError):
    """A simulation (or a robot file it runs) cannot be set up or run with the given parameters."""


class DriveError(OrigamiCadError, RuntimeError):
    """A driving fault: a sequence file, a servo bus or its port, naming the servo or port."""


class OptionsError(OrigamiCadError, ValueError):
    """A command-line option (or the keyword behind it) is malformed or out of range."""


class OutputError(OrigamiCadError, ValueError):
    """An output path cannot be written safely (it is an input, a folder, a device...)."""


class ExtraError(OrigamiCadError, ImportError):
    """A feature needs an optional dependency that is not installed; the message names the
    extra that installs it (``pip install 'origami-cad[viz]'`` for the 3D renders)."""
