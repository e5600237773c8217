"""Twisted string actuators: the paper's ring-device model (eq. 8) and the standard model.

Units: mm and radians inside; :class:`TSAParams` reads degrees and turns at
the edges. Every function raises :class:`~origami_cad.errors.StringsError`
instead of returning NaN when asked for more than the strands can give.

Examples
--------
>>> import math
>>> round(float(ring_length(0.0, x_dis=60.0, d1=10.0, d2=8.0, d_s=0.5)), 6)  # = A0B0
60.008333
>>> x = onboard_contraction(math.radians(3600), length=100.0, radius=0.5)
>>> round(float(onboard_angle(x, length=100.0, radius=0.5)) / (2 * math.pi), 6)  # turns
10.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from origami_cad._args import Arg, brief_value, check_fields, check_number
from origami_cad.errors import StringsError

__all__ = [
    "TSAParams",
    "onboard_angle",
    "onboard_compliant_length",
    "onboard_contraction",
    "onboard_transmission",
    "ring_length",
    "ring_length_derivatives",
]


def ring_length(theta_s: Any, x_dis: Any, d1: float, d2: float, d_s: float) -> np.ndarray:
    """Eq. 8: remaining string length ``l_AB`` of the ring TSA after twisting ``theta_s``.

    .. math::

        l_{AB} = \\sqrt{x_{dis}^2 + \\frac{(d_2 - d_1\\cos\\theta)^2 + (d_1\\sin\\theta)^2}{4}}
        \\quad (0 \\le \\theta < \\pi), \\qquad
        \\sqrt{x_{dis}^2 + \\frac{(d_2 + d_1 + (\\theta - \\pi) d_s)^2}{4}}
        \\quad (\\theta \\ge \\pi)

    Parameters
    ----------
    theta_s : float or ndarray
        TSA rotation, radians (>= 0).
    x_dis : float or ndarray
        Distance from the TSA's rotation centre to the middle of the two
        first-entry holes, mm.
    d1 : float
        Rotation diameter of the TSA, mm.
    d2 : float
        Distance between the two first-entry holes, mm.
    d_s : float
        Width of the string, mm.

    Returns
    -------
    ndarray
        ``l_AB``, mm. Continuous at ``theta_s = pi``; ``l_AB(0) = A0B0``.
    """
    theta = np.asarray(theta_s, dtype=float)
    if np.any(theta < 0):
        raise StringsError("the TSA rotation theta_s must be >= 0")
    x = np.asarray(x_dis, dtype=float)
    first = ((d2 - d1 * np.cos(theta)) ** 2 + (d1 * np.sin(theta)) ** 2) / 4.0
    wound = (d2 + d1 + (theta - math.pi) * d_s) ** 2 / 4.0
    return np.sqrt(x**2 + np.where(theta < math.pi, first, wound))


def ring_length_derivatives(
    theta_s: Any, x_dis: Any, d1: float, d2: float, d_s: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Eq. 8 and its analytic derivatives: ``(l_AB, dl/dtheta, dl/dx_dis, d2l/dx_dis2)``.

    With ``l = sqrt(x^2 + q(theta))`` (``q`` the second term of eq. 8):
    ``dl/dtheta = q'(theta) / (2 l)``, ``dl/dx = x / l`` and ``d2l/dx2 = q / l^3``;
    ``q' = d1 d2 sin(theta) / 2`` on the first branch and
    ``d_s (d2 + d1 + (theta - pi) d_s) / 2`` on the wound one. The length is
    continuous at ``theta = pi`` but its rate jumps there, from 0 to
    ``d_s (d1 + d2) / (4 l)``, where the strings start winding on each other; at
    ``pi`` the wound branch's (right-hand) rate is returned.

    Parameters are those of :func:`ring_length` (radians, mm). Returns mm,
    mm/rad, dimensionless and 1/mm.

    Examples
    --------
    >>> l, dth, dx, dxx = ring_length_derivatives(1.0, 60.0, 10.0, 8.0, 0.5)
    >>> h = 1e-6
    >>> up, down = (ring_length(1.0 + s, 60.0, 10.0, 8.0, 0.5) for s in (h, -h))
    >>> bool(abs(dth - (up - down) / (2 * h)) < 1e-8)
    True
    """
    theta = np.asarray(theta_s, dtype=float)
    if np.any(theta < 0):
        raise StringsError("the TSA rotation theta_s must be >= 0")
    x = np.asarray(x_dis, dtype=float)
    first = theta < math.pi
    wound = d2 + d1 + (theta - math.pi) * d_s
    q = np.where(
        first, ((d2 - d1 * np.cos(theta)) ** 2 + (d1 * np.sin(theta)) ** 2) / 4.0, wound**2 / 4.0
    )
    dq = np.where(first, d1 * d2 * np.sin(theta) / 2.0, d_s * wound / 2.0)
    length = np.sqrt(x**2 + q)
    return length, dq / (2.0 * length), x / length, q / length**3


def _check_twist(theta: np.ndarray, length: float, radius: float, max_helix: float) -> None:
    limit = length * math.sin(max_helix)
    worst = float(np.max(np.abs(theta))) * radius
    if worst >= limit:
        raise StringsError(
            f"a twist of {float(np.max(np.abs(theta))) / (2 * math.pi):.3g} turns exceeds what "
            f"strands of {length:g} mm and radius {radius:g} mm can give (theta r = {worst:.4g} "
            f"mm must stay below L0 sin(max helix angle) = {limit:.4g} mm)"
        )


def onboard_contraction(
    theta: Any, length: float, radius: float, max_helix: float = math.radians(80.0)
) -> np.ndarray:
    """Contraction of a twisted pair: ``x = L0 - sqrt(L0^2 - (theta r)^2)``, mm.

    Parameters
    ----------
    theta : float or ndarray
        Motor angle, radians.
    length : float
        ``L0``: untwisted length of the strands, mm.
    radius : float
        ``r``: helix radius of the twisted pair, mm.
    max_helix : float
        Largest helix angle allowed, radians (< pi/2); beyond it the strands
        cannot twist further and it is an error.
    """
    t = np.asarray(theta, dtype=float)
    _check_twist(t, length, radius, max_helix)
    return length - np.sqrt(length**2 - (t * radius) ** 2)


def onboard_angle(
    contraction: Any, length: float, radius: float, max_helix: float = math.radians(80.0)
) -> np.ndarray:
    """Inverse of :func:`onboard_contraction`: the motor angle (radians) for a contraction (mm)."""
    x = np.asarray(contraction, dtype=float)
    if np.any(x < 0):
        raise StringsError("a TSA contraction must be >= 0 mm")
    max_x = length - length * math.cos(max_helix)
    if np.any(x >= max_x):
        raise StringsError(
            f"a contraction of {float(np.max(x)):.4g} mm exceeds what strands of {length:g} mm "
            f"can give at the maximum helix angle ({max_x:.4g} mm)"
        )
    return np.sqrt(length**2 - (length - x) ** 2) / radius


def onboard_transmission(
    theta: Any, length: float, radius: float, max_helix: float = math.radians(80.0)
) -> np.ndarray:
    """Transmission ratio ``tau / F = theta r^2 / sqrt(L0^2 - (theta r)^2)``, mm."""
    t = np.asarray(theta, dtype=float)
    _check_twist(t, length, radius, max_helix)
    return t * radius**2 / np.sqrt(length**2 - (t * radius) ** 2)


def onboard_compliant_length(
    theta: Any, force: Any, length: float, radius: float, stiffness: float
) -> np.ndarray:
    """Actuator length with string stiffness: ``sqrt(L0^2 (1 + F/K)^2 - theta^2 r^2)``, mm.

    ``force`` in N, ``stiffness`` ``K`` in N (force per unit strain).
    """
    t = np.asarray(theta, dtype=float)
    stretched = length * (1.0 + np.asarray(force, dtype=float) / stiffness)
    if np.any(t * radius >= stretched):
        raise StringsError("the twist exceeds what the stretched strands can give")
    return np.sqrt(stretched**2 - (t * radius) ** 2)


@dataclass(frozen=True)
class TSAParams:
    """A TSA as the route file's ``[tsa]`` table describes it (mm).

    ``model = "ring"`` (eq. 8) uses ``d1``, ``d2``, ``string_width`` and takes
    ``x_dis`` from the geometry (anchor to first-entry hole), or from ``x_dis``
    when given. ``model = "onboard"`` uses ``length`` (strands), ``radius`` and
    ``max_helix_angle`` (degrees).
    """

    model: str = "ring"
    d1: float = 10.0
    d2: float = 8.0
    string_width: float = 0.5
    x_dis: float | None = None
    length: float = 100.0
    radius: float = 0.5
    max_helix_angle: float = 80.0

    def __post_init__(self) -> None:
        if not isinstance(self.model, str) or self.model not in ("ring", "onboard"):
            raise StringsError(
                f"[tsa] model must be 'ring' or 'onboard', got {brief_value(self.model)}"
            )
        for name in ("d1", "d2", "string_width", "length", "radius"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | float | np.number):
                raise StringsError(f"[tsa] {name} must be a number of mm, got {brief_value(value)}")
            check_number(f"[tsa] {name}", value, low=0.0, open_min=True, error=StringsError)
        check_fields(
            self,
            StringsError,
            {"x_dis": Arg(min=0.0, max=1e5), "max_helix_angle": Arg(optional=False)},
        )
        if not 0 < self.max_helix_angle < 90:
            raise StringsError("[tsa] max_helix_angle must lie in (0, 90) deg")

    def consumed(self, theta_s: Any, x_dis: Any) -> np.ndarray:
        """Length of string between the TSA and the first hole after twisting ``theta_s``, mm.

        For the ring model it is eq. 8 with the current ``x_dis``; for the onboard
        model the straight distance plus the contraction of the twisted strands.
        """
        if self.model == "ring":
            x = x_dis if self.x_dis is None else self.x_dis
            return ring_length(theta_s, x, self.d1, self.d2, self.string_width)
        return np.asarray(x_dis, dtype=float) + onboard_contraction(
            theta_s, self.length, self.radius, math.radians(self.max_helix_angle)
        )

    def consumed_derivatives(
        self, theta_s: Any, x_dis: Any
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`consumed` and its analytic derivatives (no finite differences).

        Returns ``(length, d/dtheta, d/dx_dis, d2/dx_dis2)`` in mm, mm/rad, 1 and 1/mm:
        eq. 8's derivatives (:func:`ring_length_derivatives`) for the ring model, and
        for the onboard model ``dx/dtheta`` = :func:`onboard_transmission`, 1 and 0.
        With a fixed ``x_dis`` in the route the length does not depend on the geometry.
        """
        x = np.asarray(x_dis, dtype=float)
        if self.model == "ring":
            fixed = self.x_dis is not None
            length, dth, dx, dxx = ring_length_derivatives(
                theta_s, self.x_dis if fixed else x, self.d1, self.d2, self.string_width
            )
            length, dth = np.broadcast_arrays(length, dth)
            if fixed:
                dx, dxx = np.zeros_like(length), np.zeros_like(length)
            return (
                length,
                dth,
                np.broadcast_to(dx, length.shape),
                np.broadcast_to(dxx, length.shape),
            )
        helix = math.radians(self.max_helix_angle)
        c = onboard_contraction(theta_s, self.length, self.radius, helix)
        rate = onboard_transmission(theta_s, self.length, self.radius, helix)
        length, rate = np.broadcast_arrays(x + c, rate)
        return length, rate, np.ones_like(length), np.zeros_like(length)

    def max_theta(self) -> float:
        """Largest twist the TSA can make, radians (infinite for the ring model)."""
        if self.model == "ring":
            return math.inf
        return self.length * math.sin(math.radians(self.max_helix_angle)) / self.radius * 0.999
