"""Fabrication: dual-material printable structures as exact B-rep solids (section III-C, IV-A).

Two steps: :func:`plan_panels` plans the panels as plain data (footprints, holes,
crease limits), :func:`build_fabrication` builds the solids of a plan;
:func:`fabricate` does both.

The names are imported on first use, so that the plain-data modules (``params``,
``panels``, ``plan``) load without build123d: ``origami-cad --help`` and the commands
that build no solid start without OCP.

>>> from origami_cad.fabrication import FabricationParams
>>> round(FabricationParams(bias=3, height=2.2, thickness=0.4).p_max, 3)
0.814
"""

from origami_cad._lazy import attach_stub

#: The names of ``__init__.pyi``, each listed once there, imported on first use.
__getattr__, __dir__, __all__ = attach_stub(__name__, __file__)
