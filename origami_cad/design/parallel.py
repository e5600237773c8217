"""Deprecated: the process pool moved to :mod:`origami_cad.parallel` (below every stage)."""

from __future__ import annotations

import warnings

from origami_cad.parallel import local_pool, start_context

__all__ = ["local_pool", "start_context"]

warnings.warn(
    "origami_cad.design.parallel moved to origami_cad.parallel; this path goes in the next release",
    DeprecationWarning,
    stacklevel=2,
)
