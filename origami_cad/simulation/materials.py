"""The materials file (``materials.toml``): one place for the printed sheet's and the strings'
physical constants, read by ``simulate``, ``route``, ``crawl`` and ``mjcf`` (``--materials``).

File (every key optional; the defaults and their sources below)::

    [crease]                   # the TPU crease layer
    modulus = 26.0             # MPa, Young's modulus
    thickness = 0.4            # mm, t
    hinge_zone = 7.0           # mm, w: the width that bends, 2 (b + m) of the print
    density = 1.21             # g/cm^3
    # stiffness = 0.0387       # N mm/rad per mm of crease: given, it replaces E t^3 / (12 w)
    # law_angles = [0, 60, 100]      # deg: the softening law's points (default: linear)
    # law_factors = [1, 0.58, 0.35]  # the stiffness there over `stiffness`
    [panel]                    # the PLA panels
    modulus = 3500.0           # MPa
    thickness = 2.2            # mm, h
    density = 1.24             # g/cm^3
    [string]
    axial_stiffness = 6000.0   # N, EA
    hole_friction = 0.0        # string on the hole's edge (capstan law)

The crease's bending stiffness per unit length is a function of its thickness:
``k(t) = E t^3 / (12 w)`` (N mm / rad / mm; a plate strip of width ``w`` bending
uniformly), :meth:`Materials.crease_stiffness`; a file may give ``stiffness`` instead
(a measured or calibrated value), which then holds at its own thickness ``t0`` and
scales as ``(t / t0)^3`` at another.

The crease softens as it folds when the file gives ``law_angles`` (deg, from 0,
increasing) and ``law_factors`` (>= 0, as many): the crease's stiffness (its moment's
slope) is the stiffness above times the factor, piecewise linear in the fold angle and
constant past the last point. Without them the crease is a linear spring (every result
as before). PyGamiX 3.0.2's simulator (``phys_sim25.py``, ``kb``) makes its printed TPU
crease's stiffness fall with the fold angle: 0.147 at 0 deg, 0.085 at 60 deg, 0.052 at
100 deg (factors 1, 0.58, 0.35), a law fitted by its authors to their own bench.

Defaults and sources: PLA's modulus 3500 MPa and TPU 95A's 26 MPa are the values of
the filament makers' data sheets that the paper's print used (the project's
``SimulationParams`` defaults, docs/simulation.md); the densities are
``fabrication.params.DENSITY_G_CM3`` (PLA 1.24, TPU 1.21 g/cm^3, data sheets); the
thicknesses and hinge zone are the paper's print (``FabricationParams``: h = 2.2,
t = 0.4, b = 3, m = 0.5 mm); the string's EA is a 0.5 mm UHMWPE braid (about 0.1 mm^2
of fibre at an effective 60 GPa, about 3.5 % stretch at its 200 N breaking load);
the hole friction defaults to 0 (no friction: the models as they were) since no
measurement of it is at hand - ``origami-cad calibrate`` fits it to force curves.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass
from pathlib import Path

from origami_cad._args import Arg, checked
from origami_cad._toml import Table, finite_toml, load_toml, toml_table
from origami_cad.errors import SimulationError
from origami_cad.fabrication.params import DENSITY_G_CM3, FabricationParams
from origami_cad.simulation.model import SimulationParams, check_crease_law

__all__ = ["Materials", "dump_materials", "load_materials", "parse_materials"]

_PRINT = FabricationParams()


@dataclass(frozen=True)
class Materials:
    """The materials file's values (MPa, mm, g/cm^3, N; see the module docstring)."""

    crease_modulus: float = 26.0
    crease_thickness: float = _PRINT.thickness
    hinge_zone: float = 2.0 * (_PRINT.bias + _PRINT.midlayer_bias)
    crease_density: float = DENSITY_G_CM3["TPU"]
    crease_stiffness_given: float | None = None
    panel_modulus: float = 3500.0
    panel_thickness: float = _PRINT.height
    panel_density: float = DENSITY_G_CM3["PLA"]
    string_axial_stiffness: float = 6000.0
    hole_friction: float = 0.0
    law_angles: tuple[float, ...] = (0.0,)
    law_factors: tuple[float, ...] = (1.0,)

    @property
    def crease_law(self) -> tuple[tuple[float, float], ...]:
        """The crease's softening law, ``((deg, factor), ...)`` (see the module docstring)."""
        return tuple(zip(self.law_angles, self.law_factors, strict=True))

    def crease_stiffness(self, thickness: float | None = None) -> float:
        """Bending stiffness of a crease per unit length at ``thickness`` mm (default the
        file's), N mm / rad / mm: ``E t^3 / (12 w)``, or the given stiffness scaled by
        ``(t / t0)^3``."""
        t = self.crease_thickness if thickness is None else float(thickness)
        if self.crease_stiffness_given is not None:
            return self.crease_stiffness_given * (t / self.crease_thickness) ** 3
        return self.crease_modulus * t**3 / (12.0 * self.hinge_zone)

    def overrides(self) -> dict[str, float]:
        """These materials as :class:`SimulationParams` fields (for ``for_route(**...)``).
        The crease's modulus is the one that gives :meth:`crease_stiffness` over the hinge
        zone."""
        modulus = self.crease_stiffness() * 12.0 * self.hinge_zone / self.crease_thickness**3
        return {
            "panel_modulus": self.panel_modulus,
            "panel_thickness": self.panel_thickness,
            "crease_modulus": modulus,
            "crease_thickness": self.crease_thickness,
            "hinge_zone": self.hinge_zone,
            "string_axial_stiffness": self.string_axial_stiffness,
            "density": self.panel_density,
            "hole_friction": self.hole_friction,
            "crease_law": self.crease_law,
        }

    def simulation_params(self, **overrides) -> SimulationParams:
        """The bar-and-hinge model's parameters with these materials and no printed fold
        limit (180 deg); ``overrides`` set any other field (loads, the fold limit)."""
        return SimulationParams(**{"fold_limit": 180.0, **self.overrides(), **overrides})

    def dcqc_stiffness(self) -> dict[str, float]:
        """The DCQC model's keywords (``crease_stiffness``, ``string_stiffness``,
        ``hole_friction``) with these materials."""
        return self.simulation_params().dcqc_stiffness()

    def replace(self, **values) -> Materials:
        """A copy with these fields replaced (checked as the file's values are)."""
        return _checked(dataclasses.replace(self, **values), "materials")


_KEYS = {  # table -> {key in the file: (field, low bound open)}
    "crease": {"modulus": "crease_modulus", "thickness": "crease_thickness",
               "hinge_zone": "hinge_zone", "density": "crease_density",
               "stiffness": "crease_stiffness_given", "law_angles": "law_angles",
               "law_factors": "law_factors"},
    "panel": {"modulus": "panel_modulus", "thickness": "panel_thickness",
              "density": "panel_density"},
    "string": {"axial_stiffness": "string_axial_stiffness", "hole_friction": "hole_friction"},
}  # fmt: skip


def _checked(m: Materials, where: str) -> Materials:
    if len(m.law_angles) != len(m.law_factors):
        raise SimulationError(
            f"{where}: [crease] law_angles and law_factors must be as long "
            f"({len(m.law_angles)} and {len(m.law_factors)})"
        )
    check_crease_law(m.crease_law, f"{where}: [crease] law_angles, law_factors")
    for f in dataclasses.fields(m):
        v = getattr(m, f.name)
        if v is None or f.name in ("law_angles", "law_factors"):
            continue
        if f.name == "hole_friction":
            if not 0.0 <= v <= 10.0:
                raise SimulationError(f"{where}: [string] hole_friction must lie in [0, 10]")
        elif not v > 0:
            raise SimulationError(f"{where}: {f.name} must be > 0, got {v:g}")
    return m


def _from_data(data: dict, where: str) -> Materials:
    top = Table(data, where, SimulationError)
    values = {}
    for name, keys in _KEYS.items():
        table = top.table(name, {})
        for key, field in keys.items():
            if key.startswith("law_") and table.has(key):
                values[field] = tuple(table.numbers(key, min_length=1))
            elif table.has(key):
                low = 0.0 if key != "hole_friction" else None
                values[field] = table.number(key, low=low, low_open=low is not None, high=1e7)
        table.finish()
    top.finish()
    return _checked(Materials(**values), where)


@checked(SimulationError, path=Arg("path", optional=False))
def load_materials(path: str | os.PathLike[str]) -> Materials:
    """Read a materials file; errors (:class:`SimulationError`) name the file and the key."""
    p = Path(path)
    return _from_data(load_toml(p, SimulationError), str(p))


def parse_materials(text: str, name: str = "materials.toml") -> Materials:
    """A materials file from its TOML text, as :func:`load_materials` reads a file."""
    import tomllib

    try:
        data = tomllib.loads(text)
    except (tomllib.TOMLDecodeError, RecursionError) as exc:
        raise SimulationError(f"{name}: not valid TOML: {exc}") from None
    return _from_data(data, name)


def dump_materials(m: Materials, *, header: str = "") -> str:
    """The materials file of ``m`` (TOML text) that :func:`load_materials` reads back.

    >>> parse_materials(dump_materials(Materials(hole_friction=0.2))).hole_friction
    0.2
    """
    units = {"modulus": "MPa", "thickness": "mm", "hinge_zone": "mm", "density": "g/cm^3",
             "stiffness": "N mm/rad per mm", "axial_stiffness": "N (EA)",
             "hole_friction": "capstan law", "law_angles": "deg: the crease law's points",
             "law_factors": "the stiffness there over the crease's"}  # fmt: skip
    lines = [header.rstrip("\n")] if header else []
    for name, keys in _KEYS.items():
        items = {key: getattr(m, field) for key, field in keys.items()}
        if len(m.law_angles) == 1 and m.law_factors == (1.0,):  # the linear spring
            items = {k: v for k, v in items.items() if not k.startswith("law_")}
        comments = {k: units[k] for k in items}
        lines += [*([""] if lines else []), *toml_table(name, items, comments=comments)]
    return finite_toml("\n".join(lines) + "\n", "the materials file", SimulationError)
