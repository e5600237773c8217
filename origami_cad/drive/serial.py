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

from origami_cad.drive.errors import DriveError

__all__ = ["LineDevice", "SerialBus", "crc8", "frame", "unframe"]

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

    Motors move toward their goal at ``speed`` turns per second.
    """

    def __init__(self, ids, speed: float = 5.0) -> None:
        self.goal = {int(i): 0.0 for i in ids}
        self.position = {int(i): 0.0 for i in ids}
        self.enabled = {int(i): False for i in ids}
        self.speed = speed
        self.corrupt_replies = 0
        self._last = time.monotonic()

    def _advance(self) -> None:
        now = time.monotonic()
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


class SerialBus:
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
    max_turns : dict or float, optional
        Safety limit per motor (or for all), turns.
    """

    def __init__(
        self,
        port: str,
        baudrate: int = 115200,
        ids=(1,),
        *,
        timeout: float = 0.5,
        max_turns: dict | float | None = None,
    ) -> None:
        self.port_name = port
        self.baudrate = baudrate
        self.ids = [int(i) for i in ids]
        self.timeout = timeout
        self.max_turns = _limits(self.ids, max_turns)
        self.models: dict[int, int] = {}
        self._ser = None

    def open(self) -> SerialBus:
        import serial

        try:
            self._ser = serial.Serial(self.port_name, self.baudrate, timeout=self.timeout)
        except (serial.SerialException, OSError) as exc:
            raise DriveError(f"port {self.port_name} cannot be opened: {exc}") from None
        for i in self.ids:
            reply = self._ask(f"P {i}", i).split()
            self.models[i] = int(reply[3])
        return self

    def close(self) -> None:
        if self._ser is not None:
            self._ser.close()
            self._ser = None

    def __enter__(self) -> SerialBus:
        return self.open()

    def __exit__(self, *exc) -> None:
        try:
            if self._ser is not None:
                self.stop()
        finally:
            self.close()

    def _ask(self, text: str, dxl_id: int | None = None) -> str:
        who = f"motor {dxl_id}" if dxl_id is not None else "the board"
        self._ser.reset_input_buffer()
        self._ser.write((frame(text) + "\n").encode("ascii"))
        raw = self._ser.readline()
        if not raw:
            raise DriveError(f"{who}: no reply to {text!r} (timeout)")
        try:
            reply = unframe(raw.decode("ascii", "replace"))
        except DriveError as exc:
            raise DriveError(f"{who}: {exc}") from None
        if reply.startswith("ERR"):
            raise DriveError(f"{who}: the board answered {reply!r} to {text!r}")
        return reply

    def set_turns(self, targets: dict[int, float]) -> None:
        """Command motor positions, turns."""
        for i, turns in targets.items():
            _check_limit(i, turns, self.max_turns)
            self._ask(f"G {i} {turns:.4f}", i)

    def read(self) -> dict[int, tuple[float, float]]:
        """Present position (turns) and current (mA) of every motor."""
        out = {}
        for i in self.ids:
            parts = self._ask(f"R {i}", i).split()
            out[i] = (float(parts[3]), float(parts[4]))
        return out

    def stop(self) -> None:
        """Turn every motor off."""
        self._ask("S")


def _limits(ids, max_turns) -> dict[int, float]:
    if max_turns is None:
        return {i: math.inf for i in ids}
    if isinstance(max_turns, dict):
        return {i: float(max_turns.get(i, math.inf)) for i in ids}
    return {i: float(max_turns) for i in ids}


def _check_limit(dxl_id: int, turns: float, limits: dict[int, float]) -> None:
    limit = limits.get(dxl_id, math.inf)
    if not math.isfinite(turns) or abs(turns) > limit:
        raise DriveError(
            f"servo {dxl_id}: {turns:g} turns exceeds its limit of {limit:g} turns "
            "(the TSA would overtwist)"
        )
