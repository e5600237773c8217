"""Deprecated: the DXF format moved to :mod:`origami_cad.pattern.formats.dxf`.

This path keeps working for one release (it is the same module), with a
``DeprecationWarning``.
"""

import sys
import warnings

from origami_cad.pattern.formats import dxf as moved

warnings.warn(
    "origami_cad.pattern.dxf moved to origami_cad.pattern.formats.dxf",
    DeprecationWarning,
    stacklevel=2,
)
sys.modules[__name__] = moved
