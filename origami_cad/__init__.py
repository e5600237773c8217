"""origami_cad: from an origami robot idea to printed, string-driven hardware.

Stages (data flows one way, each may import only the ones above it):
``pattern`` -> ``kinematics`` -> ``design`` -> ``fabrication`` -> ``strings``
-> ``simulation`` -> ``drive`` -> ``viz``.
"""

__version__ = "0.1.0"

__all__ = ["__version__"]
