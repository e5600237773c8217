"""Errors of the driver layer: each names the servo (or port) and the cause."""

from __future__ import annotations

from origami_cad.errors import OrigamiCadError

__all__ = ["DriveError", "StallError"]


class DriveError(OrigamiCadError, RuntimeError):
    """Communication or safety failure, naming the servo or port and the cause."""


class StallError(DriveError):
    """A TSA stalled: its current exceeded the limit (string tension too high)."""
