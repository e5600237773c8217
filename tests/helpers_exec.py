"""How the tests run the library's calls: an executor that runs each task at once in this
process (no process pool in a test), and a time bound on a call."""

from __future__ import annotations

import concurrent.futures as cf
import signal
from contextlib import contextmanager

#: no call under :func:`bounded` may run longer than this by default, s (wall clock)
BOUND_S = 20


class InlineExecutor(cf.Executor):
    """A real Executor that runs each call in this process when submitted; what the call
    raises is kept in its future, raised by ``result()`` as a pool's future raises it."""

    def submit(self, fn, /, *args, **kwargs):
        future: cf.Future = cf.Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except BaseException as exc:
            future.set_exception(exc)
        return future


@contextmanager
def bounded(seconds: int = BOUND_S):
    """Fail the test when the body runs longer than ``seconds`` (wall clock, SIGALRM)."""

    def _late(signum, frame):
        raise TimeoutError(f"a hostile call ran past {seconds} s")

    old = signal.signal(signal.SIGALRM, _late)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
