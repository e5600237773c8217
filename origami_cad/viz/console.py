"""Live terminal displays of long jobs (rich): a progress bar and the servo table.

Each display is a context manager plus the callback a job reports to, so a job
never prints; the command line shows these while the job runs.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["progress_bar", "servo_table"]


def progress_bar(kind: str) -> tuple[Any, Callable[..., None]]:
    """A transient progress bar labelled ``kind``, and its callback ``(done, total=None)``."""
    from rich.progress import Progress

    bar = Progress(transient=True)
    task = bar.add_task(kind, total=None)
    return bar, lambda k, n=None, *rest: bar.update(task, completed=k, total=n)


def servo_table() -> tuple[Any, Callable[..., None]]:
    """A live table of target and measured turns and currents, and the drive callback.

    The callback takes ``(t in s, {id: target turns}, {id: (turns, current in mA)})``.
    """
    from rich.live import Live
    from rich.table import Table

    live = Live(refresh_per_second=8, transient=True)

    def update(t: float, targets, state) -> None:
        tab = Table("servo", "target turns", "measured turns", "current mA", title=f"t = {t:.2f} s")
        for i, target in targets.items():
            tab.add_row(str(i), f"{target:.3f}", f"{state[i][0]:.3f}", f"{state[i][1]:.0f}")
        live.update(tab)

    return live, update
