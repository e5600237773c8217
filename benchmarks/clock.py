"""Wall-clock and CPU seconds side by side, for the benchmarks (not a benchmark itself).

On a shared machine the wall clock measures the load as much as the code: every wall
time a benchmark prints has this process's CPU time (``time.process_time``) beside it.
"""

from __future__ import annotations

import time


class Clock:
    """Wall and CPU seconds since it started or since the last :meth:`lap`."""

    def __init__(self) -> None:
        self._wall, self._cpu = time.perf_counter(), time.process_time()

    def lap(self) -> tuple[float, float]:
        """(wall s, CPU s) since the last lap, and start the next."""
        wall, cpu = time.perf_counter(), time.process_time()
        out = (wall - self._wall, cpu - self._cpu)
        self._wall, self._cpu = wall, cpu
        return out


def cpu_row(cpu: float, target: str = "") -> tuple[str, float, str]:
    """The row printed under a wall time: this process's CPU seconds."""
    return ("  CPU s (process_time)", cpu, target)
