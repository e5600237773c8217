"""Exception types of the package.

Every error a user can cause by giving bad input is an :class:`OrigamiCadError`;
its message names the file, key, entity, panel or servo and what is wrong, so the
command-line tool can print it as one line and exit with code 2.
"""

from __future__ import annotations

__all__ = [
    "DesignError",
    "OrigamiCadError",
    "OutputError",
    "PatternError",
    "SimulationError",
]


class OrigamiCadError(Exception):
    """Base class of every error caused by bad input."""


class PatternError(OrigamiCadError, ValueError):
    """A crease pattern, or a file holding one, is malformed or cannot be used."""


class DesignError(OrigamiCadError, ValueError):
    """A design or task description (usually a TOML file) is malformed."""


class SimulationError(OrigamiCadError, ValueError):
    """A simulation cannot be set up or run with the given parameters."""


class OutputError(OrigamiCadError, ValueError):
    """An output path cannot be written safely (it is an input, a folder, a device...)."""
