"""A generic line protocol for boards that are not Dynamixel (Arduino, ESP32, ...).

One ASCII command per line, each line ending in ``*HH``: the CRC-8 (polynomial
0x07, initial 0) of every byte before the ``*``, as two upper-case hex digits.
The full specification is ``docs/serial-protocol.md``; a reference firmware is
``examples/firmware/origami_tsa/origami_tsa.ino``.

=====================  ==============================  ============================
command                meaning                         reply
=====================  ==============================  ============================
``P <id>``             ping                            ``OK P <id> <model>``
``G <id> <turns>``     go to motor position (turns)    ``OK G <id>``
``R <id>``             read                            ``OK R <id> <turns> <mA>``
``S``                  stop: every motor off           ``OK S``
=====================  ==============================  ============================

Errors: ``ERR <code> <text>`` with code 1 checksum, 2 unknown command,
3 unknown id, 4 out of range, 5 syntax.

Examples
--------
>>> frame("P 1")
'P 1*1D'
>>> unframe("OK P 1 9000*EF")
'OK P 1 9000'
"""

from __future__ import annotations

import math
import time

from origami_cad.drive.bus import ServoBus
from origami_cad.drive.errors import (
    PORT_ERRORS,
    DriveError,
    PortLostError,
    TorqueOffError,
    hold_ctrl_c,
    port_error_text,
)

__all__ = [
    "LineDevice",
    "SerialBus",
    "crc8",
    "frame",
    "unframe",
]

#: The largest motor position the protocol accepts, turns.
MAX_TURNS = 10000.0
BOARD_MODEL = 9000


def crc8(data: bytes) -> int:
    """CRC-8, polynomial 0x07, initial value 0 (CRC-8/SMBUS)."""
    crc = 0
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = ((crc << 1) ^ 0x07) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc


def frame(text: str) -> str:
    """``text*HH``: a line with its checksum."""
    return f"{text}*{crc8(text.encode('ascii')):02X}"


def unframe(line: str) -> str:
    """The text of a framed line; :class:`DriveError` if the checksum is missing or wrong."""
    line = line.strip()
    text, star, check = line.rpartition("*")
    if not star or len(check) != 2:
        raise DriveError(f"reply {line!r} has no checksum")
    try:
        value = int(check, 16)
    except ValueError:
        raise DriveError(f"reply {line!r} has a malformed checksum") from None
    if crc8(text.encode("ascii")) != value:
        raise DriveError(f"checksum error in reply {line!r}")
    return text


class LineDevice:
    """The device side of the protocol (what the reference firmware does), in Python.

    Motors move toward their goal at ``speed`` turns per second of device time, which
    runs ``time_scale`` times faster than real time (an emulator's dry run).
    """

    def __init__(self, ids, speed: float = 5.0, time_scale: float = 1.0) -> None:
        self.goal = {int(i): 0.0 for i in ids}
        self.position = {int(i): 0.0 for i in ids}
        self.enabled = {int(i): False for i in ids}
        self.speed = speed
        self.time_scale = time_scale
        self.corrupt_replies = 0
        self._last = time.monotonic() * time_scale

    def _advance(self) -> None:
        now = time.monotonic() * self.time_scale
        dt, self._last = now - self._last, now
        for i, goal in self.goal.items():
            if self.enabled[i]:
                step = max(-self.speed * dt, min(self.speed * dt, goal - self.position[i]))
                self.position[i] += step

    def _reply(self, text: str) -> str:
        line = frame(text)
        if self.corrupt_replies:
            self.corrupt_replies -= 1
            line = line[:-1] + ("0" if line[-1] != "0" else "1")
        return line

    def handle(self, line: str) -> str | None:
        """Answer one command line (without its newline)."""
        if not line:
            return None
        text, star, check = line.rpartition("*")
        if not star or len(check) != 2 or crc8(text.encode("ascii")) != int(check, 16):
            return self._reply("ERR 1 checksum")
        self._advance()
        parts = text.split()
        cmd, args = parts[0], parts[1:]
        try:
            if cmd == "S" and not args:
                for i in self.enabled:
                    self.enabled[i] = False
                    self.goal[i] = self.position[i]
                return self._reply("OK S")
            if cmd not in ("P", "G", "R"):
                return self._reply(f"ERR 2 unknown command {cmd}")
            dev = int(args[0])
            if dev not in self.goal:
                return self._reply(f"ERR 3 unknown id {dev}")
            if cmd == "P" and len(args) == 1:
                return self._reply(f"OK P {dev} {BOARD_MODEL}")
            if cmd == "R" and len(args) == 1:
                return self._reply(
                    f"OK R {dev} {self.position[dev]:.4f} {60 if self.enabled[dev] else 0}"
                )
            if cmd == "G" and len(args) == 2:
                turns = float(args[1])
                if not math.isfinite(turns) or abs(turns) > MAX_TURNS:
                    return self._reply(f"ERR 4 out of range {args[1]}")
                self.goal[dev] = turns
                self.enabled[dev] = True
                return self._reply(f"OK G {dev}")
        except (ValueError, IndexError):
            pass
        return self._reply(f"ERR 5 syntax {text}")


class SerialBus(ServoBus):
    """Host side of the line protocol, with the same interface as ``DynamixelBus``.

    Parameters
    ----------
    port : str
        Serial port (or pseudo-terminal) path.
    baudrate : int
        Baud rate.
    ids : iterable of int
        Motor IDs on the board.
    timeout : float
        Seconds to wait for each reply.
    **limits
        The safety limits of :class:`~origami_cad.drive.bus.ServoBus`, by keyword:
        ``max_turns`` (dict or float: per motor or for all, turns),
        ``current_limit_ma`` (a motor whose current exceeds it stops every motor,
        ``S``, and raises :class:`StallError` naming it, mA), ``stop_attempts``
        (attempts to have ``S`` confirmed by the board before :meth:`stop` reports
        the motors as possibly still on) and ``reopen_timeout`` (how long
        :meth:`stop` keeps trying to reopen a lost port, s).

    Notes
    -----
    The same safety guarantees as :class:`~origami_cad.drive.DynamixelBus`:
    :meth:`open` pings every motor before any is enabled and, on any failure
    (Ctrl-C included), sends ``S`` before raising; :meth:`close` and leaving
    the ``with`` block send ``S`` until the board confirms it; a reply to an
    earlier, interrupted command is recognised and skipped; a lost port raises
    :class:`PortLostError` naming it (the shutdown reopens it once); a stop
    that is never confirmed raises :class:`TorqueOffError` naming the motors.
    """

    unit = "motor"
    device = "the board"

    def __init__(
        self,
        port: str,
        baudrate: int = 115200,
        ids=(1,),
        *,
        timeout: float = 0.5,
        **limits,
    ) -> None:
        # limits: max_turns, current_limit_ma, stop_attempts, reopen_timeout (ServoBus)
        super().__init__(port, baudrate, ids, **limits)
        if not (math.isfinite(timeout) and timeout > 0):
            raise DriveError(f"reply timeout must be finite and > 0 s, got {timeout}")
        self.timeout = timeout

    def open(self) -> SerialBus:
        """Open the port and ping every motor (nothing is enabled until the first goal).

        On any failure (a missing motor, Ctrl-C) the board is sent ``S`` and the
        port closed before the error is raised.
        """
        return super().open()

    def _start(self) -> None:
        missing = {}
        for i in self.ids:
            try:
                self.models[i] = int(self._ask(f"P {i}", i).split()[3])
            except PortLostError:
                raise
            except (DriveError, ValueError, IndexError) as exc:
                missing[i] = str(exc) if isinstance(exc, DriveError) else f"motor {i}: bad reply"
        if missing:
            raise DriveError("; ".join(missing.values()) + "; no motor was enabled")

    def _open_port(self):
        import serial

        try:
            return serial.Serial(self.port_name, self.baudrate, timeout=self.timeout)
        except (serial.SerialException, OSError, ValueError) as exc:
            raise DriveError(f"port {self.port_name} cannot be opened: {exc}") from None

    def _close_port(self, port) -> None:
        port.close()

    def _ask(self, text: str, dxl_id: int | None = None) -> str:
        """Send one command; its reply, skipping stale replies to earlier commands."""
        who = f"motor {dxl_id}" if dxl_id is not None else "the board"
        port = self._open()
        parts = text.split()
        expect = " ".join(["OK", *parts[:2]]) if parts[0] != "S" else "OK S"
        try:
            port.reset_input_buffer()
            port.write((frame(text) + "\n").encode("ascii"))
            deadline = time.monotonic() + self.timeout
            while True:
                raw = port.readline()
                if not raw:
                    raise DriveError(f"{who}: no reply to {text!r} (timeout)")
                try:
                    reply = unframe(raw.decode("ascii", "replace"))
                except DriveError as exc:
                    raise DriveError(f"{who}: {exc}") from None
                if reply.startswith("ERR"):
                    raise DriveError(f"{who}: the board answered {reply!r} to {text!r}")
                if reply == expect or reply.startswith(expect + " "):
                    return reply
                if time.monotonic() > deadline:  # only stale replies: give up
                    raise DriveError(f"{who}: no reply to {text!r} (got {reply!r})")
        except PORT_ERRORS as exc:
            raise self._lost(exc) from exc

    def set_turns(self, targets: dict[int, float]) -> None:
        """Command motor positions, turns (every goal is checked before any is sent)."""
        self.check_goals(targets)
        for i, turns in targets.items():
            self._ask(f"G {i} {turns:.4f}", i)

    def read(self) -> dict[int, tuple[float, float]]:
        """Present position (turns) and current (mA) of every motor.

        With ``current_limit_ma``, a motor above it stops every motor and
        raises :class:`StallError` naming it.
        """
        out = {}
        for i in self.ids:
            reply = self._ask(f"R {i}", i)
            try:
                turns, current = (float(v) for v in reply.split()[3:5])
            except ValueError:
                raise DriveError(f"motor {i}: malformed reply {reply!r}") from None
            if not (math.isfinite(turns) and math.isfinite(current)):
                raise DriveError(f"motor {i}: non-finite reading in {reply!r}")
            out[i] = (turns, current)
        self.stop_on_stall(out)
        return out

    def _stop_stalled(self, dxl_id: int) -> str:
        with hold_ctrl_c():
            self.stop()
        return "every motor was stopped"

    def _try_open(self):
        import serial

        try:
            return serial.Serial(self.port_name, self.baudrate, timeout=self.timeout), ""
        except (OSError, ValueError) as exc:
            return None, port_error_text(exc)

    def stop(self) -> None:
        """Turn every motor off: ``S`` until the board confirms it (``stop_attempts`` times).

        A lost port is reopened once; a Ctrl-C meanwhile is held until the stop
        is confirmed or given up, then raised. Raises :class:`TorqueOffError`
        naming the motors if the board never confirmed.
        """
        if self._port is None:
            return
        interrupt: KeyboardInterrupt | None = None
        cause = ""
        reopened = confirmed = False
        for _ in range(self.stop_attempts + 1):  # + 1: one reopening of a lost port
            try:
                self._ask("S")
                confirmed = True
                break
            except KeyboardInterrupt as exc:
                interrupt, cause = exc, "interrupted while stopping"
            except PortLostError as exc:
                if reopened:
                    cause = f"the port was lost again after reopening it ({exc})"
                    break
                reopened = True
                reason = self._reopen()
                if reason is not None:
                    cause = f"the port is lost and cannot be reopened ({reason})"
                    break
            except DriveError as exc:
                cause = str(exc)
        if not confirmed:
            raise TorqueOffError(
                f"motors {', '.join(map(str, self.ids))} on port {self.port_name} may still be "
                f"on: the board did not confirm the stop (cut their power): {cause}",
                self.ids,
            )
        self._powered = False
        if interrupt is not None:
            raise interrupt
