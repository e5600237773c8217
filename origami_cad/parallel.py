"""Where the searches run: a process pool on this machine, or a Dask cluster.

The arm design's CMA-ES runs (:func:`origami_cad.design.arm.design_arm`) and the
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
import sys
from collections.abc import Iterator

from origami_cad.errors import OptionsError

__all__ = ["local_pool", "occ_loaded", "open_executor", "start_context"]


def occ_loaded() -> bool:
    """Whether OpenCascade (OCP, build123d's kernel) is loaded in this process.

    build123d runs OCC's booleans, validity checks and meshing in parallel, on OCC's
    thread pool. A process forked after that pool has started inherits the pool but not
    its threads, and its first parallel OCC operation waits for ever. Without OCP loaded,
    no such pool can exist.

    Examples
    --------
    >>> isinstance(occ_loaded(), bool)
    True
    """
    return "OCP" in sys.modules


def start_context() -> multiprocessing.context.BaseContext:
    """The start method of the pool's workers.

    ``fork`` while OpenCascade is not loaded (:func:`occ_loaded`): it is the fastest, and a
    user script without an ``if __name__ == "__main__":`` guard can run a search. Once OCP
    is loaded, ``forkserver``: its workers are forked from a fresh server process that
    never ran OCC, so a worker may build and mesh solids (a forked worker would hang on
    OCC's thread pool); a script that starts such a pool needs the ``__main__`` guard, as
    on every platform without ``fork``. ``spawn`` where neither is available.

    Examples
    --------
    >>> start_context().get_start_method() in ("fork", "forkserver", "spawn")
    True
    """
    methods = multiprocessing.get_all_start_methods()
    if "fork" in methods and not occ_loaded():
        return multiprocessing.get_context("fork")
    return multiprocessing.get_context("forkserver" if "forkserver" in methods else "spawn")


def local_pool(tasks: int) -> cf.ProcessPoolExecutor:
    """A process pool with one worker per core, and no more workers than ``tasks``.

    Its workers start by :func:`start_context`, so they may run OpenCascade even when this
    process already has.

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
