"""Errors of the driver layer: each names the servo (or port) and the cause."""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator

from origami_cad.errors import DriveError, OrigamiCadError

__all__ = ["DriveError", "HardwareError", "PortLostError", "StallError", "TorqueOffError"]


class StallError(DriveError):
    """A TSA stalled: its current exceeded the limit (string tension too high).

    ``servo`` is the ID of the servo that stalled (None if unknown).
    """

    def __init__(self, message: str, servo: int | None = None) -> None:
        super().__init__(message)
        self.servo = servo


class HardwareError(DriveError):
    """A servo reported a hardware error (overload, overheating, input voltage, ...)."""


class PortLostError(DriveError):
    """The serial port stopped working (bus unplugged, emulator killed)."""


class TorqueOffError(DriveError):
    """Torque could not be switched off on some servos; ``servos`` lists their IDs."""

    def __init__(self, message: str, servos: list[int] | tuple[int, ...] = ()) -> None:
        super().__init__(message)
        self.servos = list(servos)


try:  # pyserial raises termios.error (not an OSError) on a vanished pseudo-terminal
    import termios

    #: What a serial port raises when it stops working (unplugged, emulator gone).
    PORT_ERRORS: tuple[type[BaseException], ...] = (OSError, termios.error)
except ImportError:  # pragma: no cover - Windows
    PORT_ERRORS = (OSError,)


def describe_exit(exc: BaseException) -> str:
    """One line for an exception that ended a run (to prefix a torque-off failure)."""
    if isinstance(exc, KeyboardInterrupt):
        return "interrupted (Ctrl-C)"
    if isinstance(exc, OrigamiCadError):
        return str(exc)
    return f"{type(exc).__name__}: {exc}"


def port_error_text(exc: BaseException) -> str:
    """A port failure in words: ``[Errno 5] Input/output error`` (also for ``termios.error``)."""
    errno = getattr(exc, "errno", None)
    if errno is None and len(exc.args) == 2 and isinstance(exc.args[0], int):
        errno = exc.args[0]  # termios.error(errno, text)
    if errno:
        import os

        return f"[Errno {errno}] {os.strerror(errno)}"
    return str(exc)


@contextlib.contextmanager
def hold_ctrl_c() -> Iterator[None]:
    """Hold Ctrl-C (SIGINT) and SIGTERM while the servos are being switched off; deliver
    them afterwards to the handler that was installed (Python's raises
    ``KeyboardInterrupt``; a program's own handler runs then, once per signal kind).

    Only in the main thread, and only for signals handled in Python (not ignored, not
    the system default). An error in the body wins over a held signal.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {
        sig: handler
        for sig in (signal.SIGINT, signal.SIGTERM)
        if callable(handler := signal.getsignal(sig))
    }
    pressed: list[int] = []
    for sig in previous:
        signal.signal(sig, lambda signum, frame: pressed.append(signum))
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    for sig in dict.fromkeys(pressed):
        previous[sig](sig, None)
