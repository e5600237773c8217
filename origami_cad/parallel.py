"""Where the searches run: a process pool on this machine, or a Dask cluster; one call in a
forked child (:class:`ChildCall`: the STEP export beside the other exports).

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
import os
import pickle
import signal
from collections.abc import Callable, Iterator
from typing import Any

from origami_cad.errors import OptionsError

__all__ = ["ChildCall", "local_pool", "open_executor", "start_context"]

#: The signals a child's start and end are shielded from (they come inside ``fn`` only).
_STOPS = {signal.SIGINT, signal.SIGTERM}


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


def _sendable(exc: BaseException) -> BaseException:
    """``exc`` if it survives pickling, else a ``RuntimeError`` with the same text."""
    try:
        pickle.loads(pickle.dumps(exc))
    except Exception:
        return RuntimeError(str(exc) or type(exc).__name__)
    return exc


def _child_main(conn, fn: Callable[..., Any], args: tuple) -> None:
    """The child's whole life: run ``fn(*args)`` (signals let in), send the outcome, exit."""
    try:
        try:
            signal.pthread_sigmask(signal.SIG_UNBLOCK, _STOPS)
            outcome: tuple[str, Any] = ("ok", fn(*args))
        except BaseException as exc:  # every outcome goes to the parent
            outcome = ("error", exc)
        signal.pthread_sigmask(signal.SIG_BLOCK, _STOPS)
        if outcome[0] == "error":
            outcome = ("error", _sendable(outcome[1]))
        try:
            conn.send(outcome)
        except Exception as exc:  # an unpicklable result
            conn.send(("error", RuntimeError(f"the result could not be sent back: {exc}")))
    finally:
        os._exit(0)  # no clean-up of the parent's (atexit, open files' buffers) in the child


def _can_fork() -> bool:
    """Whether :class:`ChildCall` may fork: ``fork`` exists and this process may have children."""
    return (
        "fork" in multiprocessing.get_all_start_methods()
        and not multiprocessing.current_process().daemon
    )


class ChildCall:
    """``fn(*args)`` run in a forked child process while this one goes on; :meth:`result`.

    Where ``fork`` is not available (Windows, macOS' default is kept as is), or in a
    daemonic process (a ``multiprocessing.Pool`` or Dask worker, which may have no
    children), the call runs here, at once. The child is a copy of this process: ``fn`` sees
    every object as it is now, and what it changes stays in the child; its return value (or
    its exception, the same type and text; a ``RuntimeError`` with the text when it cannot
    be pickled) comes back through a pipe. The child takes SIGINT and SIGTERM only while
    ``fn`` runs, so an interrupt is ``fn``'s to clean up (``_fileio.atomic_path`` removes
    its temporary file); :meth:`stop` forwards one.

    >>> ChildCall(sum, [1, 2, 3]).result()
    6
    """

    def __init__(self, fn: Callable[..., Any], *args: Any) -> None:
        self._proc = None
        self._outcome: tuple[str, Any] = ("ok", None)
        if not _can_fork():
            self._outcome = ("ok", fn(*args))
            return
        ctx = multiprocessing.get_context("fork")
        self._conn, send = ctx.Pipe(duplex=False)
        previous = signal.pthread_sigmask(signal.SIG_BLOCK, _STOPS)
        try:
            self._proc = ctx.Process(target=_child_main, args=(send, fn, args), daemon=True)
            self._proc.start()
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, previous)
            send.close()

    def result(self) -> Any:
        """Wait for the call to end: its value, or its exception raised here."""
        if self._proc is not None:
            try:
                self._outcome = self._conn.recv()
            except EOFError:
                self._proc.join()
                self._outcome = (
                    "error",
                    ChildProcessError(f"the child process ended with code {self._proc.exitcode}"),
                )
            finally:
                self._proc.join()
                self._conn.close()
                self._proc = None
        kind, value = self._outcome
        if kind == "error":
            raise value
        return value

    def stop(self) -> None:
        """Interrupt the call (SIGINT: as Ctrl-C) and wait for the child to end; no result."""
        if self._proc is None:
            return
        if self._proc.is_alive():
            with contextlib.suppress(ProcessLookupError):
                os.kill(self._proc.pid, signal.SIGINT)
        self._proc.join()
        self._conn.close()
        self._proc = None
