"""origami_cad: from an origami robot idea to printed, string-driven hardware.

Subpackages (a graph without a circle, docs/architecture.md; each imports only the ones
it names there): ``pattern`` (crease patterns and their formats), ``kinematics`` (the TG
chain, rigid folding), ``design`` (the paper's arm search), ``fabrication`` (printable
solids and their exports), ``strings`` (TSAs, routes, DCQC, route planning),
``simulation`` (bar-and-hinge folding, MuJoCo), ``drive`` (servo buses, sequences),
``crawler`` (the legged robot: its file, design, gait search and walk), ``viz`` (plots,
renders, the report) and ``commands`` (the command line's registry).

``import origami_cad as oc`` gives the names a script of the paper's pipeline needs
(:data:`__all__`, docs/api.md): patterns and designs, folding, arm design, fabrication
and its assembly, string routes and DCQC, simulation, route planning, the build123d
parts and ``show``. They are imported on first use, so ``import origami_cad`` stays
light (it loads no build123d, NumPy or pyvista).
"""

import logging

from origami_cad._lazy import attach_stub

# a library logs, the application shows: the "origami_cad" logger (and its children) is
# silent unless a script configures logging; the command line prints it on stderr
logging.getLogger("origami_cad").addHandler(logging.NullHandler())

__version__ = "0.1.0"

#: The names of ``__init__.pyi``, each listed once there, imported on first use.
__getattr__, __dir__, _names = attach_stub(__name__, __file__)
__all__ = [*_names, "__version__"]
