"""Fabrication parameters of wrapping-based dual-material panels, and eq. 6.

Cross-section (z = 0 at the bottom face, total height ``h``)::

    z = h          +----------------------+          outer face, inset b from creases
                  /   shell (TPU, s thick) \\         chamfer (eq. 6)
    z = (h+t)/2  +-------------------------+  ...    crease layer: mid-layer (PLA)
    z = (h-t)/2  +-------------------------+  ...    and crease sheet (TPU), thickness t
                  \\        infill (PLA)    /
    z = 0          +----------------------+

Two panels folded about their crease by ``theta_max = 2 atan(2b / (h - t))``
meet face to face along their chamfers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from origami_cad._args import Arg, brief_value, check_numbers
from origami_cad.errors import FabricationError
from origami_cad.kinematics.limits import bias_for_theta_max, crease_fold_limit

__all__ = [
    "DENSITY_G_CM3",
    "FabricationParams",
    "bias_for_p_max",
    "bias_for_theta_max",
    "fabrication_params",
    "layer_height",
    "theta_max",
]

#: Densities used for the mass estimate, g/cm^3.
DENSITY_G_CM3 = {"PLA": 1.24, "TPU": 1.21}


def bias_for_p_max(p_max: float, height: float, thickness: float) -> float:
    """Eq. 6 inverted for ``p_max = theta_max / pi`` in (0, 1): the inner bias ``b``, mm."""
    if not 0.0 < p_max < 1.0:
        raise FabricationError(
            f"p_max must lie in (0, 1) (eq. 6: theta_max / 180 deg), got {p_max:g}"
        )
    return bias_for_theta_max(p_max * math.pi, height, thickness)


def theta_max(bias: float, height: float, thickness: float) -> float:
    """Eq. 6: the largest fold angle before neighbouring chamfers meet, radians.

    ``theta_max = 2 atan(2 b / (h - t))`` with inner bias ``b``, shell height ``h``
    and crease thickness ``t`` (all mm). The one implementation, element-wise, is
    :func:`origami_cad.kinematics.limits.crease_fold_limit` (the arm's design uses it).
    """
    return float(crease_fold_limit(bias, height, thickness))


#: The finest feature a printed structure's length may ask for, mm (a nozzle's tenth):
#: 1e-300 mm is no solid the B-rep kernel can build.
MIN_FEATURE = 0.01
#: The largest length a printed structure's parameter may have, mm (a print bed's few
#: hundred millimetres, with room to spare).
MAX_LENGTH = 10_000.0
#: A positive length of :class:`FabricationParams`: finite, at least :data:`MIN_FEATURE`.
FIELD_LENGTH = Arg(min=MIN_FEATURE, max=MAX_LENGTH, optional=False)


@dataclass(frozen=True)
class FabricationParams:
    """Parameters of the printed structure (all lengths mm).

    Parameters
    ----------
    bias : float
        ``b``: inset of each panel's outer face from its crease edges.
    height : float
        ``h``: total height of a panel (maximum shell height).
    thickness : float
        ``t``: thickness of the crease layer (mid-layers and crease sheet).
    shell : float
        ``s``: wall thickness of the TPU shell on the outer faces and chamfers.
    midlayer_bias : float
        ``m``: extra inset of the mid-layers beyond ``b`` (room for the creases).
    border_margin : float
        Inset of the panels from border and cut edges (their sides are vertical).
    hole_diameter : float
        Diameter of the string holes.
    holes : str or list of (x, y)
        ``"auto"`` (one hole per panel at the pole of inaccessibility of its
        operation region), ``"pattern"`` (the pattern's own holes), ``"none"``,
        or a list of points (each on a panel).
    """

    bias: float = 3.0
    height: float = 2.2
    thickness: float = 0.4
    shell: float = 0.8
    midlayer_bias: float = 0.5
    border_margin: float = 0.0
    hole_diameter: float = 2.0
    holes: Any = "auto"

    def __post_init__(self) -> None:
        # each message starts with the field's name: the command line says its option there
        for name in ("bias", "height", "thickness", "shell", "hole_diameter"):
            FIELD_LENGTH.check(name, getattr(self, name), FabricationError)
        for name in ("midlayer_bias", "border_margin"):
            value = Arg(min=0.0, max=MAX_LENGTH, optional=False).check(
                name, getattr(self, name), FabricationError
            )
            if 0 < value < MIN_FEATURE:
                raise FabricationError(
                    f"{name}: must be 0 or at least {MIN_FEATURE:g} mm (no printer makes a "
                    f"finer feature), got {value!r}"
                )
        if self.height <= self.thickness:
            raise FabricationError(
                f"height: {self.height:g} mm must exceed the crease thickness = "
                f"{self.thickness:g} mm (eq. 6: the fold limit is 2 atan(2b / (h - t)))"
            )
        if self.shell >= self.half_height - 1e-6:
            raise FabricationError(
                f"shell: {self.shell:g} mm must be thinner than a panel half "
                f"(h - t) / 2 = {self.half_height:g} mm (no infill would be left)"
            )
        if isinstance(self.holes, str):
            if self.holes not in ("auto", "pattern", "none"):
                raise FabricationError(
                    f"holes: expected 'auto', 'pattern', 'none' or points, got "
                    f"{brief_value(self.holes)}"
                )
        else:
            if isinstance(self.holes, bytes | dict) or not hasattr(self.holes, "__iter__"):
                raise FabricationError(
                    f"holes: expected 'auto', 'pattern', 'none' or points, got "
                    f"{brief_value(self.holes)}"
                )
            pts = [
                check_numbers(f"holes[{i}]", p, length=2, error=FabricationError)
                for i, p in enumerate(self.holes)
            ]
            object.__setattr__(self, "holes", tuple(pts))

    @property
    def half_height(self) -> float:
        """Height of each panel half, ``(h - t) / 2``, mm."""
        return (self.height - self.thickness) / 2.0

    @property
    def theta_max(self) -> float:
        """Eq. 6, radians."""
        return theta_max(self.bias, self.height, self.thickness)

    @property
    def p_max(self) -> float:
        """``theta_max / pi``."""
        return self.theta_max / math.pi

    def to_dict(self) -> dict[str, Any]:
        return {
            "bias_mm": self.bias,
            "height_mm": self.height,
            "thickness_mm": self.thickness,
            "shell_mm": self.shell,
            "midlayer_bias_mm": self.midlayer_bias,
            "border_margin_mm": self.border_margin,
            "hole_diameter_mm": self.hole_diameter,
            "holes": self.holes if isinstance(self.holes, str) else [list(p) for p in self.holes],
        }


def layer_height(params: FabricationParams, largest: float = 0.2) -> float:
    """The largest layer height (mm, at most ``largest``) that resolves every layer.

    Each panel half ``(h - t) / 2``, the crease layer ``t`` and the shell ``s`` are a
    whole number of layers, so no layer straddles two materials' boundary. Tries
    ``largest``, then steps of 0.01 mm down to 0.05 mm; falls back to 0.05 mm. The print
    settings use it (:mod:`~origami_cad.fabrication.slicer`); a panel given a thinner
    shell wall (:func:`~origami_cad.fabrication.plan.panel_biases`) gets a whole number
    of these layers too.
    """
    targets = (params.half_height, params.thickness, params.shell)
    for hundredths in range(round(largest * 100), 4, -1):
        h = hundredths / 100
        if all(abs(x / h - round(x / h)) < 1e-6 for x in targets):
            return h
    return 0.05


def fabrication_params(
    *,
    bias: float | None = None,
    theta_max: float | None = None,
    p_max: float | None = None,
    **fields: Any,
) -> FabricationParams:
    """``FabricationParams`` from at most one of the bias or a fold limit (eq. 6).

    Parameters
    ----------
    bias : float, optional
        The inner bias ``b``, mm.
    theta_max : float, optional
        The largest fold angle of every crease, degrees in (0, 180): gives ``b`` by
        eq. 6 inverted (:func:`bias_for_theta_max`) at the ``height`` and ``thickness``.
    p_max : float, optional
        The largest fold ratio ``theta_max / 180 deg`` in (0, 1): gives ``b`` likewise.
    **fields
        Other ``FabricationParams`` fields (``height``, ``thickness``... mm); ``None``
        values keep their defaults.

    Returns
    -------
    FabricationParams
        The parameters; nothing is built or written.

    Raises
    ------
    FabricationError
        More than one of ``bias``, ``theta_max`` and ``p_max``, or one out of range.

    Examples
    --------
    >>> round(fabrication_params(theta_max=146.6).bias, 3)
    3.0
    """
    given = [v is not None for v in (bias, theta_max, p_max)]
    if sum(given) > 1:
        raise FabricationError("give only one of the bias, theta_max and p_max")
    fields = {k: v for k, v in fields.items() if v is not None}
    height = fields.get("height", FabricationParams.height)
    thickness = fields.get("thickness", FabricationParams.thickness)
    if theta_max is not None:
        bias = bias_for_theta_max(math.radians(theta_max), height, thickness)
        _check_derived_bias("theta_max", theta_max, bias, height, thickness)
    elif p_max is not None:
        bias = bias_for_p_max(p_max, height, thickness)
        _check_derived_bias("p_max", p_max, bias, height, thickness)
    if bias is not None:
        fields["bias"] = bias
    return FabricationParams(**fields)


def _check_derived_bias(name: str, value: float, bias: float, height: float, thickness: float):
    """Refuse a fold limit (``theta_max`` deg, or ``p_max``) whose bias (eq. 6) is finer than
    a printer makes or longer than :data:`MAX_LENGTH`, naming it and its range."""
    if MIN_FEATURE <= bias <= MAX_LENGTH:
        return
    scale, unit = (180.0 / math.pi, " deg") if name == "theta_max" else (1.0 / math.pi, "")
    low = float(crease_fold_limit(MIN_FEATURE, height, thickness)) * scale
    high = float(crease_fold_limit(MAX_LENGTH, height, thickness)) * scale
    raise FabricationError(
        f"{name}: {value:g}{unit} needs an inner bias of {bias:.3g} mm (eq. 6); it must lie "
        f"in [{low:.4g}, {high:.6g}]{unit} for a bias of {MIN_FEATURE:g} to {MAX_LENGTH:g} mm"
    )
