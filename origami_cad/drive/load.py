"""The load a servo carries over a sequence: torque against time, from a simulation.

A sequence file's ``[[tsa]] load = [[t_s, torque_Nmm], ...]`` (``crawl`` writes it from
the simulated gait) is the torque the TSA's strings put on its servo's shaft over one
cycle. The emulator plays it: the motor slows as the load rises, draws current in
proportion to it and stalls beyond its model's stall torque, so a gait that would stall
a real servo stalls in a dry run too.

>>> import numpy as np
>>> curve = LoadCurve(np.array([0.0, 10.0]), np.array([0.0, 20.0]), period=10.0)
>>> curve.at(5.0), curve.at(15.0)
(10.0, 10.0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["LoadCurve"]


@dataclass(frozen=True)
class LoadCurve:
    """Torque on a servo's shaft against time, repeated every ``period``.

    Attributes
    ----------
    t : ndarray (k,)
        Times from the start of a cycle, s (increasing, from 0).
    torque : ndarray (k,)
        Torque the load asks of the motor, N mm (>= 0), linear between samples.
    period : float
        The curve repeats every ``period`` s (a sequence's cycle).
    """

    t: np.ndarray
    torque: np.ndarray
    period: float

    def at(self, t: float) -> float:
        """The torque at time ``t`` s since the sequence started, N mm."""
        local = t % self.period if self.period > 0 and math.isfinite(t) else 0.0
        return float(np.interp(local, self.t, self.torque))

    def scaled(self, factor: float) -> LoadCurve:
        """The same curve with every torque times ``factor`` (a heavier robot, a margin)."""
        return LoadCurve(self.t, self.torque * float(factor), self.period)

    @property
    def peak(self) -> float:
        """The largest torque, N mm."""
        return float(self.torque.max())
