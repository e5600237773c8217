"""Where the searches run by default: a process pool on this machine.

The arm design's CMA-ES runs (:func:`origami_cad.design.search.design_arm`) and the
route planner's tasks (:func:`origami_cad.strings.plan.run_tasks`) take any
``concurrent.futures.Executor`` (a Dask cluster's, for example); without one they use
:func:`local_pool`.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import multiprocessing.context

__all__ = ["local_pool", "start_context"]


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
