"""What the DCQC model of :mod:`origami_cad.strings.dcqc` returns: the states of a TSA's
turns (:class:`TurnStates`, :class:`DCQCResult`, an array per quantity: turns, fold ratio
p, tensions N, torque N mm, lengths mm), why it stopped (:class:`StopReason`), a jam
(:class:`Jam`) and the printed sheet's fold limit (:class:`FoldLimit`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

import numpy as np

__all__ = ["DCQCResult", "FoldLimit", "Jam", "StopReason", "TurnStates"]


class StopReason(StrEnum):
    """Why a string-driven folding ended (both string models use these)."""

    TURN_LIMIT = "turn_limit"  #: the TSA reached the route's max_turns
    HELIX_LIMIT = "helix_limit"  #: the onboard TSA's strands reached their maximum helix angle
    FOLD_LIMIT = "fold_limit"  #: eq. 6 or a blocker stops the creases the strings drive
    TENSION_LIMIT = "tension_limit"  #: a string pulls harder than the route's max_tension
    TORQUE_LIMIT = "torque_limit"  #: the TSA needs more than the route's max_torque
    JAM = "jam"  #: the strings would stretch instead of folding the sheet
    TIME_LIMIT = "time_limit"  #: the simulation used the wall-clock seconds it was given


@dataclass(frozen=True)
class Jam:
    """A string that would have to stretch for the sheet to fold further.

    ``string`` is 0-based; ``segment`` names the segment that lengthens as the
    sheet folds (``"anchor -> c0r0s5"`` or ``"c0r0s5 -> c0r0s4"``); ``p`` the fold
    ratio where it jams; ``stretch_mm`` how much the string would have to stretch
    to fold on (mm).
    """

    string: int
    segment: str
    p: float
    stretch_mm: float
    elastic: bool = False  # the string has stretched so far (elastic strings), not would have to

    def describe(self) -> str:
        stretch = "has stretched" if self.elastic else "would have to stretch"
        return (
            f"jam: string {self.string + 1} {stretch} by {self.stretch_mm:.3g} mm "
            f"at p = {self.p:.3f}; {self.hint()}"
        )

    def hint(self) -> str:
        """What lengthens, and what to change."""
        if self.segment.startswith("anchor"):
            return (
                f"its segment {self.segment} lengthens as the sheet folds (the first hole "
                "moves away from the TSA: move the anchor or thread from another side)"
            )
        return (
            f"its segment {self.segment} lengthens as the sheet folds (check its sides "
            "against the DCQC rule)"
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "string": self.string + 1,
            "segment": self.segment,
            "p": self.p,
            "stretch_mm": self.stretch_mm,
        }


@dataclass(frozen=True)
class FoldLimit:
    """The largest fold ratio a model may reach, and where it comes from."""

    p: float
    source: str  # "route" (p_max), "eq6" (the printed sheet) or "folder"
    edges: tuple[int, ...] = ()  # creases that reach eq. 6's theta_max first

    def describe(self) -> str:
        if self.source == "eq6":
            return (
                f"the printed sheet's fold limit p = {self.p:.3f} (eq. 6's theta_max on "
                f"crease{'s' if len(self.edges) > 1 else ''} "
                f"{', '.join(map(str, self.edges[:6]))})"
            )
        if self.source == "route":
            return f"the route's fold limit p_max = {self.p:g}"
        return f"the folder's largest fold ratio p = {self.p:g}"


class TurnStates:
    """What the results of both folding models share: one state per TSA angle.

    A base of :class:`DCQCResult` and
    :class:`~origami_cad.simulation.SimulationResult`, whose ``theta`` (S,) holds the
    TSA rotation of each state, rad.
    """

    theta: np.ndarray

    @property
    def turns(self) -> np.ndarray:
        """The TSA's turns at each state (S,)."""
        return self.theta / (2 * math.pi)

    def __len__(self) -> int:
        return len(self.theta)

    def __repr__(self) -> str:
        """One line: the states, the fold ratio's range, the TSA's turns and why it stopped."""
        p = np.asarray(getattr(self, "p", ()), float)
        span = "p not fitted"
        if np.isfinite(p).any():
            span = f"p {np.nanmin(p):.3g} to {np.nanmax(p):.3g}"
        turns = float(self.turns[-1]) if len(self.theta) else 0.0
        stop = getattr(self, "stop", "")
        return (
            f"<{type(self).__name__}: {len(self.theta)} states, {span}, "
            f"{turns:.3g} turns, stop {str(stop) or 'none'}>"
        )


@dataclass(repr=False)
class DCQCResult(TurnStates):
    """The quasi-static states (one row per state, NumPy columns) and why they end.

    Columns: ``theta`` (S,) TSA rotation, rad; ``turns`` (S,); ``p`` (S,) fold
    ratio; ``taut`` (S, k) bool, the strings that bind; ``tensions`` (S, k) N
    and ``torque`` (S,) N mm (NaN without a crease stiffness); ``routed_length``
    and ``tsa_length`` (S, k) mm; ``fold_angles`` (S, m) deg of every edge.
    """

    theta: np.ndarray
    p: np.ndarray
    taut: np.ndarray
    tensions: np.ndarray
    torque: np.ndarray
    routed_length: np.ndarray
    tsa_length: np.ndarray
    fold_angles: np.ndarray
    stop: StopReason
    reason: str
    limit: FoldLimit
    jam: Jam | None = None
    valid: bool = True
    initial_length_mm: list[float] = field(default_factory=list)
    violations: list[str] = field(default_factory=list)
    cutting: list[str] = field(default_factory=list)
    final_coords: np.ndarray | None = None
    final_strings: list[np.ndarray] = field(default_factory=list)
    placement: str = ""

    def to_dict(self) -> dict[str, Any]:
        """The JSON form (``dcqc.json``)."""

        def col(a: np.ndarray) -> list:  # NaN (no crease stiffness given) -> null
            if a.dtype.kind != "f":
                return a.tolist()
            out = a.astype(object)
            out[~np.isfinite(a)] = None
            return out.tolist()

        return {
            "valid": self.valid,
            "stop": self.stop.value,
            "reason": self.reason,
            "jam": None if self.jam is None else self.jam.to_dict(),
            "fold_limit": {"p": self.limit.p, "source": self.limit.source},
            "placement": self.placement,
            "initial_length_mm": self.initial_length_mm,
            "route_violations": self.violations,
            "segments_cutting_panels": self.cutting,
            "states": {
                "turns": col(self.turns),
                "theta_s_deg": col(np.degrees(self.theta)),
                "p": col(self.p),
                "taut": col(self.taut),
                "tensions_N": col(self.tensions),
                "tsa_torque_Nmm": col(self.torque),
                "routed_length_mm": col(self.routed_length),
                "tsa_length_mm": col(self.tsa_length),
            },
            "final": {"turns": float(self.turns[-1]), "p": float(self.p[-1])},
        }
