"""Deprecated: the SVG format moved to :mod:`origami_cad.pattern.formats.svg`.

This path keeps working for one release (it is the same module), with a
``DeprecationWarning``.
"""

import sys
import warnings

from origami_cad.pattern.formats import svg as moved

warnings.warn(
    "origami_cad.pattern.svg moved to origami_cad.pattern.formats.svg",
    DeprecationWarning,
    stacklevel=2,
)
sys.modules[__name__] = moved
