"""Live terminal displays of long jobs (rich): a progress bar and the servo table.

Each display is a context manager plus the callback a job reports to, so a job
never prints; the command line shows these while the job runs.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["progress_bar", "servo_table"]


def progress_bar(kind: str) -> tuple[Any, Callable[..., None]]:
    """A transient progress bar labelled ``kind`` on stderr, and its callback
    ``(done, total=None)``."""
    from rich.console import Console
    from rich.progress import Progress

    bar = Progress(transient=True, console=Console(stderr=True))
    task = bar.add_task(kind, total=None)
    return bar, lambda k, n=None, *rest: bar.update(task, completed=k, total=n)


def servo_table() -> tuple[Any, Callable[..., None]]:
    """A live table of target and measured turns and currents, and the drive callback.

    The callback takes ``(t in s, {id: target turns}, {id: (turns, current in mA)})``;
    its ``total`` attribute, ``(duration in s, time scale)`` when the run sets it,
    adds how far the run is and the wall-clock time it has left to the title.
    """
    from rich.live import Live
    from rich.table import Table

    live = Live(refresh_per_second=8, transient=True)

    def update(t: float, targets, state) -> None:
        title = f"t = {t:.2f} s"
        if update.total is not None:
            duration, scale = update.total
            left = (duration - t) / scale
            title += (
                f" of {duration:.6g} s ({100 * t / max(duration, 1e-9):.1f} %), {_clock(left)} left"
            )
        tab = Table("servo", "target turns", "measured turns", "current mA", title=title)
        for i, target in targets.items():
            tab.add_row(str(i), f"{target:.3f}", f"{state[i][0]:.3f}", f"{state[i][1]:.0f}")
        live.update(tab)

    update.total = None  # type: ignore[attr-defined]
    return live, update


def _clock(seconds: float) -> str:
    """``seconds`` as ``1 h 02 min``, ``3 min 05 s`` or ``12 s``."""
    s = max(round(seconds), 0)
    if s >= 3600:
        return f"{s // 3600} h {s % 3600 // 60:02d} min"
    return f"{s // 60} min {s % 60:02d} s" if s >= 60 else f"{s} s"
