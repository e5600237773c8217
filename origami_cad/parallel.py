"""Where the searches run: a process pool on this machine, or a Dask cluster.

The arm design's CMA-ES runs (:func:`origami_cad.design.search.design_arm`) and the
route planner's tasks (:func:`origami_cad.strings.plan.run_tasks`) take any
``concurrent.futures.Executor`` (a Dask cluster's, for example); without one they use
:func:`local_pool`. :func:`open_executor` gives either by a scheduler's address.

This module sits below every stage that runs a search (``design`` and ``strings``), so
neither imports the other for it.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import multiprocessing
import multiprocessing.context
from collections.abc import Iterator

from origami_cad.errors import OptionsError

__all__ = ["local_pool", "open_executor", "start_context"]


def start_context() -> multiprocessing.context.BaseContext:
    """The start method of the pool's workers: fork where available (so that user scripts
    without a ``__main__`` guard can run searches), else spawn."""
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("fork" if "fork" in methods else "spawn")


def local_pool(tasks: int) -> cf.ProcessPoolExecutor:
    """A process pool with one worker per core, and no more workers than ``tasks``.

    >>> with local_pool(3) as pool:
    ...     list(pool.map(abs, [-1, 2, -3]))
    [1, 2, 3]
    """
    workers = max(1, min(int(tasks), multiprocessing.cpu_count()))
    return cf.ProcessPoolExecutor(max_workers=workers, mp_context=start_context())


@contextlib.contextmanager
def open_executor(scheduler: str | None, timeout: float = 20.0) -> Iterator[cf.Executor | None]:
    """A context giving the executor of a search, closed on exit.

    Parameters
    ----------
    scheduler : str or None
        None: no executor (the searches then make their own :func:`local_pool`);
        otherwise the address of a Dask scheduler (``tcp://10.0.0.5:8786``), whose
        cluster's executor is given.
    timeout : float
        Seconds to wait for the scheduler.

    Raises
    ------
    OptionsError
        If dask.distributed is not installed, or the scheduler cannot be reached.

    Examples
    --------
    >>> with open_executor(None) as executor:
    ...     print(executor)
    None
    """
    if scheduler is None:
        yield None
        return
    try:
        from distributed import Client
    except ImportError:
        raise OptionsError(
            "--scheduler needs dask.distributed: pip install 'origami-cad[dask]'"
        ) from None
    try:
        client = Client(scheduler, timeout=f"{timeout:g}s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise OptionsError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
    try:
        yield client.get_executor()
    finally:
        client.close()
