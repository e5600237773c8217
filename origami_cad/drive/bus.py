"""What every servo bus shares: argument checks, the ``with`` block and a safe shutdown.

:class:`ServoBus` is the base of :class:`~origami_cad.drive.DynamixelBus` and
:class:`~origami_cad.drive.SerialBus`. A subclass opens its port in
``_open_port`` (``_try_open`` once more after it was lost, and ``_prepare`` before
the first time), pings its servos in ``_start``, closes the port in
``_close_port``, switches every servo off in ``stop()`` and stops a stalled one in
``_stop_stalled``. The base runs ``open()``, the reopening of a lost port and the
stall check, and makes ``close()`` and leaving the ``with`` block call ``stop()``
whatever ended the run, never hiding a servo left on.
"""

from __future__ import annotations

import contextlib
import math
import time
from collections.abc import Iterable
from typing import Any

from origami_cad.drive.errors import (
    PORT_ERRORS,
    DriveError,
    PortLostError,
    StallError,
    TorqueOffError,
    describe_exit,
    hold_ctrl_c,
    port_error_text,
)

__all__ = ["ServoBus", "check_turn_limit", "turn_limits"]


def turn_limits(ids, max_turns) -> dict[int, float]:
    """Each servo's twist limit, turns: ``max_turns`` is one number, a dict by ID or ``None``."""
    if max_turns is None:
        return {i: math.inf for i in ids}
    if isinstance(max_turns, dict):
        return {i: float(max_turns.get(i, math.inf)) for i in ids}
    return {i: float(max_turns) for i in ids}


def check_turn_limit(dxl_id: int, turns: float, limits: dict[int, float]) -> None:
    """Raise :class:`DriveError` if ``turns`` is not finite or exceeds the servo's limit (turns)."""
    limit = limits.get(dxl_id, math.inf)
    if not math.isfinite(turns) or abs(turns) > limit:
        raise DriveError(
            f"servo {dxl_id}: {turns:g} turns exceeds its limit of {limit:g} turns "
            "(the TSA would overtwist)"
        )


class ServoBus:
    """Base of the servo buses (context manager): checked arguments, close and shutdown.

    Parameters
    ----------
    port : str
        Serial port path (or the emulator's pseudo-terminal).
    baudrate : int
        Baud rate, bits/s.
    ids : iterable of int
        Servo (motor) IDs, each once, in 0..252.
    max_turns : dict or float, optional
        Safety limit per servo (or for all), turns.
    current_limit_ma : float, optional
        A servo whose present current exceeds it is stopped (stall), mA.
    stop_attempts : int
        Attempts to have a stop confirmed before :meth:`stop` reports a servo left on.
    reopen_timeout : float
        How long :meth:`stop` keeps trying to reopen a lost port, s.
    """

    #: What the bus calls the things it drives, in messages.
    unit = "servo"
    #: What the port connects to, in messages.
    device = "the servo bus"

    def __init__(
        self,
        port: str,
        baudrate: int,
        ids: Iterable[int],
        *,
        max_turns: dict | float | None = None,
        current_limit_ma: float | None = None,
        stop_attempts: int = 3,
        reopen_timeout: float = 1.0,
    ) -> None:
        self.port_name = port
        self.baudrate = baudrate
        self.ids = [int(i) for i in ids]
        if not self.ids:
            raise DriveError(f"a {type(self).__name__} needs at least one {self.unit} ID")
        if len(set(self.ids)) != len(self.ids):
            raise DriveError(f"{self.unit} IDs {self.ids} repeat an ID")
        bad = [i for i in self.ids if not 0 <= i <= 252]
        if bad:
            raise DriveError(f"{self.unit} IDs {bad} are outside 0..252")
        if isinstance(baudrate, bool) or not isinstance(baudrate, int) or baudrate <= 0:
            raise DriveError(f"baud rate must be a positive whole number, got {baudrate!r}")
        if current_limit_ma is not None and not (
            math.isfinite(current_limit_ma) and current_limit_ma > 0
        ):
            raise DriveError(f"current limit must be finite and > 0 mA, got {current_limit_ma}")
        self.max_turns = turn_limits(self.ids, max_turns)
        self.current_limit_ma = current_limit_ma
        self.stop_attempts = max(1, int(stop_attempts))
        self.reopen_timeout = reopen_timeout
        self.models: dict[int, int] = {}
        self._port: Any = None
        self._powered = False  # torque may be on somewhere: close() must stop

    # -- what a subclass provides
    def _prepare(self) -> None:
        """Set up what opening the port needs (called before the port is opened)."""

    def _open_port(self) -> Any:  # pragma: no cover - overridden
        raise NotImplementedError

    def _try_open(self) -> tuple[Any, str]:  # pragma: no cover - overridden
        """One attempt to reopen the port: ``(port, "")``, or ``(None, why not)``."""
        raise NotImplementedError

    def _start(self) -> None:  # pragma: no cover - overridden
        """Ping every servo (and enable it); raise on any failure."""
        raise NotImplementedError

    def stop(self) -> None:  # pragma: no cover - overridden
        raise NotImplementedError

    def _close_port(self, port) -> None:  # pragma: no cover - overridden
        raise NotImplementedError

    # -- shared
    def open(self) -> ServoBus:
        """Open the port and start every servo (``_start``).

        On any failure (a missing servo, Ctrl-C) every servo is stopped and the
        port closed before the error is raised.
        """
        if self._port is not None:
            raise DriveError(f"port {self.port_name} is already open")
        self._prepare()
        self._port = self._open_port()
        self._powered = True  # a previous run may have left servos powered
        try:
            self._start()
        except BaseException as exc:
            self._shutdown(exc)
            raise
        return self

    def _open(self) -> Any:
        """The open port; :class:`DriveError` if the bus was not opened."""
        if self._port is None:
            raise DriveError(f"port {self.port_name} is not open (open the bus first)")
        return self._port

    def _lost(self, exc: BaseException) -> PortLostError:
        """The error of a port that stopped working (``exc``: the port's error)."""
        return PortLostError(
            f"port {self.port_name} was lost ({port_error_text(exc)}): "
            f"{self.device} was unplugged, lost power or its emulator stopped"
        )

    def _reopen(self) -> str | None:
        """Reopen the port after it was lost, trying for ``reopen_timeout`` seconds.

        Returns why that failed, or None. (A USB adapter that glitched comes back
        within a second, often under a stable ``/dev/serial/by-id/`` link.)
        """
        with contextlib.suppress(*PORT_ERRORS, AttributeError):
            self._close_port(self._port)
        deadline = time.monotonic() + self.reopen_timeout
        while True:
            port, reason = self._try_open()
            if port is not None:
                self._port = port
                return None
            if time.monotonic() > deadline:
                return reason
            time.sleep(0.05)

    def close(self) -> None:
        """Switch every servo off (see :meth:`stop`), then close the port."""
        self._shutdown(None)

    def __enter__(self):
        return self.open()

    def __exit__(self, exc_type, exc, tb) -> None:
        self._shutdown(exc)

    def _shutdown(self, exc: BaseException | None) -> None:
        """Stop every servo and close the port; never hide a servo left on.

        ``exc`` is the exception ending the run, if any: a torque-off failure is
        then raised as a :class:`TorqueOffError` that names both.
        """
        if self._port is None:
            return
        try:
            if self._powered:
                with hold_ctrl_c():
                    self.stop()
        except TorqueOffError as stop_exc:
            if exc is None:
                raise
            if isinstance(exc, TorqueOffError):
                return  # already names the servos left on; the caller raises it
            raise TorqueOffError(f"{describe_exit(exc)}; {stop_exc}", stop_exc.servos) from exc
        finally:
            port, self._port = self._port, None
            with contextlib.suppress(*PORT_ERRORS, AttributeError):
                self._close_port(port)

    def check_goals(self, targets: dict[int, float]) -> None:
        """Raise :class:`DriveError` (before anything is sent) for a goal off the bus or
        beyond its servo's turn limit."""
        for i, turns in targets.items():
            if i not in self.max_turns:
                raise DriveError(f"{self.unit} {i} is not on this bus (ids {self.ids})")
            check_turn_limit(i, turns, self.max_turns)

    def over_current(self, state: dict[int, tuple[float, float]]) -> tuple[int, str] | None:
        """The first servo whose current passes ``current_limit_ma``, and what to say.

        ``state`` maps each ID to (turns, mA), as :meth:`read` returns it.
        """
        if self.current_limit_ma is None:
            return None
        for i, (turns, current) in state.items():
            if abs(current) > self.current_limit_ma:
                return i, (
                    f"{self.unit} {i}: current {abs(current):.0f} mA exceeds the limit of "
                    f"{self.current_limit_ma:g} mA at {turns:.3f} turns (string tension too "
                    "high)"
                )
        return None

    def stop_on_stall(self, state: dict[int, tuple[float, float]]) -> None:
        """Stop a servo whose current passes ``current_limit_ma`` (see ``_stop_stalled``)
        and raise :class:`StallError` naming it; ``state`` as for :meth:`over_current`."""
        stall = self.over_current(state)
        if stall is not None:
            raise StallError(f"{stall[1]}; {self._stop_stalled(stall[0])}", stall[0])

    def _stop_stalled(self, dxl_id: int) -> str:  # pragma: no cover - overridden
        """Stop what a stall of ``dxl_id`` needs stopped; say what was stopped."""
        raise NotImplementedError
