"""Deprecated: the DXF format moved to :mod:`origami_cad.pattern.formats.dxf`.

This path keeps working for one release (it is the same module), with a ``DeprecationWarning``.
"""

from origami_cad.pattern.formats import moved_module

moved_module(__name__, "dxf")
