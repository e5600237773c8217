"""Deprecated: the FOLD format moved to :mod:`origami_cad.pattern.formats.fold`.

This path keeps working for one release (it is the same module), with a
``DeprecationWarning``.
"""

import sys
import warnings

from origami_cad.pattern.formats import fold as moved

warnings.warn(
    "origami_cad.pattern.fold moved to origami_cad.pattern.formats.fold",
    DeprecationWarning,
    stacklevel=2,
)
sys.modules[__name__] = moved
