"""Interrupts while outputs are put in place: SIGINT and SIGTERM noted, raised or held.

Within :func:`handle_signals` (the command line) an interrupt raises :class:`Interrupted`
and is remembered, so that every pending atomic output of :mod:`origami_cad._fileio`
refuses to complete (:func:`raise_if_interrupted`) even where a library swallowed the
``KeyboardInterrupt``; :func:`signals_held` holds them over a commit, :func:`finishing`
over what a stopped run still owes its user; :func:`written` lists the outputs put in
place whole.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Iterator

__all__ = [
    "Interrupted",
    "finishing",
    "handle_signals",
    "interrupted",
    "note_written",
    "raise_if_interrupted",
    "signals_held",
    "written",
]


class Interrupted(KeyboardInterrupt):
    """Raised by the signal handlers for SIGINT and SIGTERM; ``signum`` says which."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


_received: list[int] = []
_written: list[str] = []


def interrupted() -> int | None:
    """The number of the first interrupting signal received since the handlers were installed."""
    return _received[0] if _received else None


def written() -> list[str]:
    """The outputs put in place, whole, since the handlers were installed (the paths as
    given): what an interrupted command still wrote."""
    return list(_written)


def note_written(path: str) -> None:
    """Note an output put in place, whole (for :func:`written`)."""
    _written.append(path)


def _in_import(frame) -> bool:
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib"):
            return True
        frame = frame.f_back
    return False


def _on_signal(signum: int, frame) -> None:
    if _in_import(frame):
        # an exception inside a module's import can crash an extension module's
        # initialisation (VTK segfaults): deliver the signal again once it is done
        threading.Timer(0.05, os.kill, (os.getpid(), signum)).start()
        return
    first = not _received
    _received.append(signum)
    if first:  # a second signal must not cut short the clean-up the first one started
        sys.unraisablehook = _quiet_unraisable
        raise Interrupted(signum)


def _quiet_unraisable(unraisable) -> None:
    """After an interrupt, say nothing of errors in ``__del__`` (no traceback on stderr).

    The interrupt may have cut an object short in its constructor (a pyvista
    ``Renderer`` during a render), whose ``__del__`` then fails when the process
    exits; the command has already said it was interrupted and wrote nothing.
    """


@contextlib.contextmanager
def handle_signals(exiting: bool = False) -> Iterator[None]:
    """Within the block, SIGINT and SIGTERM raise :class:`Interrupted` and are remembered.

    Used by the command-line tool (main thread only). The remembered signal
    makes every pending atomic output refuse to complete, so an interrupt that a
    library swallowed (a VTK callback, a worker loop) still leaves nothing behind.
    The previous handlers are restored and the memory cleared on leaving; with
    ``exiting`` (the process ends after the block), further signals are ignored
    instead: the command has finished (or been interrupted), and a Ctrl-C while the
    interpreter shuts down must not replace its exit code by a death by SIGINT.
    The handlers are installed whatever the process inherited (a background job starts
    with SIGINT ignored), so a command stops cleanly on either signal.
    """
    _received.clear()
    _written.clear()
    previous = {sig: signal.signal(sig, _on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            # None: a handler installed from C, which Python cannot put back
            restored = signal.SIG_DFL if handler is None else handler
            signal.signal(sig, signal.SIG_IGN if exiting else restored)
        _received.clear()
        _written.clear()


@contextlib.contextmanager
def finishing() -> Iterator[None]:
    """Within the block, outputs complete although an interrupt came, and further
    SIGINT and SIGTERM wait (main thread): for what a stopped run still owes its
    user (``drive``'s plot of the readings its log kept). The interrupt stays noted."""
    saved = list(_received)
    _received.clear()
    try:
        with signals_held() as held:
            yield
    finally:
        _received[:] = saved + [s for s in held if s not in saved]


def raise_if_interrupted() -> None:
    """Raise :class:`Interrupted` if a signal came (an output must not complete)."""
    if _received:
        raise Interrupted(_received[0])


@contextlib.contextmanager
def signals_held() -> Iterator[list[int]]:
    """Within the block, SIGINT and SIGTERM are noted, not raised (main thread only).

    The list yielded holds the signals that came; the caller decides what they undo.
    A signal the process ignores stays ignored, and every handler found is restored.
    Inside another such block, the signals are passed on to it on leaving, and the
    list emptied: the outer block decides.
    """
    held: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield held
        return

    def hold(signum, frame):
        held.append(signum)

    hold.holds = True
    # a signal the process ignores (SIGINT of a background job, or under `nohup ... &`)
    # stays ignored; one whose handler Python cannot restore (None: installed from C) is
    # left alone
    previous = {
        sig: handler
        for sig in (signal.SIGINT, signal.SIGTERM)
        if (handler := signal.getsignal(sig)) not in (signal.SIG_IGN, None)
    }
    for sig in previous:
        signal.signal(sig, hold)
    try:
        yield held
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        outer = previous[held[0]] if held else None
        if outer is _on_signal:  # the command reports it
            _received.extend(held)
        elif getattr(outer, "holds", False):
            for signum in held:
                outer(signum, None)
            held.clear()
