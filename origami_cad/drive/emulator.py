"""Emulated servos on a pseudo-terminal: the real protocols, no hardware.

:class:`DynamixelEmulator` answers Protocol 2.0 instruction packets as X-series
servos do (PING, READ, WRITE, SYNC_READ, SYNC_WRITE, CLEAR, REBOOT) from a
control-table subset, with a motion model: the position moves toward the goal
at the profile velocity, and the current rises when the string load is
exceeded (the motor stalls where the string is taut). A servo may also carry a
:class:`~origami_cad.drive.load.LoadCurve` (a sequence's simulated ``load``): the motor
then slows in proportion to the torque, draws current in proportion to it and stalls
beyond its model's stall torque (:data:`STALL_TORQUE`). :class:`SerialEmulator`
speaks the package's generic line protocol (``docs/serial-protocol.md``).

Faults can be injected for tests: drop the next status packets of a servo,
corrupt their CRC, report an overload, pull the cable (:meth:`~_PtyDevice.unplug`,
the host's port then fails as a USB adapter's does) and plug it back
(:meth:`~_PtyDevice.plug`); :meth:`~_PtyDevice.at_packet` times any of them to
the n-th packet received, so a test hits the same point on every run.

Examples
--------
>>> with DynamixelEmulator([1, 2]) as emu:   # doctest: +SKIP
...     print(emu.port)                       # e.g. /dev/pts/5, for dynamixel_sdk
"""

from __future__ import annotations

import contextlib
import math
import os
import select
import struct
import threading
import time
import tty
from collections import Counter
from dataclasses import dataclass, field

from origami_cad.drive.errors import DriveError
from origami_cad.drive.load import LoadCurve
from origami_cad.drive.protocol2 import (
    BROADCAST,
    CLEAR,
    PING,
    READ,
    REBOOT,
    SYNC_READ,
    SYNC_WRITE,
    WRITE,
    parse_packets,
    status_packet,
)

__all__ = ["MODELS", "STALL_TORQUE", "DynamixelEmulator", "EmulatedServo", "SerialEmulator"]

#: Model numbers of the servos the emulator can be (X series).
MODELS = {"XL330-M288": 1200, "XL330-M077": 1190, "XL430-W250": 1060, "XM430-W350": 1020}
#: Stall torque of each model at its rated voltage, N mm (ROBOTIS e-manual: 0.52 N m at
#: 5 V for the XL330-M288, 0.228 for the M077, 1.4 at 11.1 V for the XL430-W250, 4.1 at
#: 12 V for the XM430-W350). With ``stall_current`` it sets the torque constant.
STALL_TORQUE = {
    "XL330-M288": 520.0,
    "XL330-M077": 228.0,
    "XL430-W250": 1400.0,
    "XM430-W350": 4100.0,
}

TICKS_PER_TURN = 4096
#: One unit of Profile Velocity, rev/min.
VELOCITY_UNIT_RPM = 0.229
#: One unit of Present Current, mA (XL330).
CURRENT_UNIT_MA = 1.0
EXTENDED_LIMIT = 256 * TICKS_PER_TURN  # ticks, +-256 turns in extended position mode

# control table: address -> size (the subset the package uses)
_SIZES = {
    0: 2,
    2: 4,
    6: 1,
    7: 1,
    8: 1,
    9: 1,
    10: 1,
    11: 1,
    38: 2,
    64: 1,
    65: 1,
    68: 1,
    70: 1,
    102: 2,
    104: 4,
    108: 4,
    112: 4,
    116: 4,
    122: 1,
    123: 1,
    124: 2,
    126: 2,
    128: 4,
    132: 4,
    144: 2,
    146: 1,
}
_EEPROM_END = 64  # addresses below: writable only with torque off
_ERR_DATA_RANGE, _ERR_ACCESS, _ERR_INSTRUCTION, _HW_ALERT = 0x04, 0x07, 0x02, 0x80
_HW_OVERLOAD = 0x20


@dataclass
class EmulatedServo:
    """One emulated X-series servo (positions in ticks, 4096 per turn)."""

    dxl_id: int
    model: int = MODELS["XL330-M288"]
    table: bytearray = field(default_factory=lambda: bytearray(150))
    position: float = 0.0
    load_turns: float | None = None  # where the string becomes taut (stall), turns
    stall_current: int = 1500  # mA when stalled against the string
    moving_current: int = 60  # mA while moving freely
    last_update: float = 0.0
    load: LoadCurve | None = None  # torque on the shaft against sequence time, N mm
    stall_torque: float = STALL_TORQUE["XL330-M288"]  # N mm
    load_start: float | None = None  # servo time of the first goal: the load's t = 0
    # injected faults (counts of status packets to drop / corrupt)
    drop: int = 0
    corrupt: int = 0
    overload: bool = False
    time_scale: float = 1.0  # > 1: the servo lives faster than real time (dry runs)

    def __post_init__(self) -> None:
        self.write(0, struct.pack("<H", self.model))
        self.table[6] = 52  # firmware
        self.table[7] = self.dxl_id
        self.table[8] = 1  # 57600 bps
        self.table[11] = 3  # position mode
        self.write(38, struct.pack("<H", 1750))
        self.table[68] = 2
        self.write(144, struct.pack("<H", 50))  # 5.0 V
        self.table[146] = 30  # deg C

    # -- raw table access
    def read(self, addr: int, size: int) -> bytes:
        self.update()
        return bytes(self.table[addr : addr + size])

    def write(self, addr: int, data: bytes) -> None:
        self.table[addr : addr + len(data)] = data

    def value(self, addr: int) -> int:
        size = _SIZES[addr]
        raw = bytes(self.table[addr : addr + size])
        return int.from_bytes(raw, "little", signed=addr in (102, 104, 116, 124, 126, 128, 132))

    @property
    def torque(self) -> bool:
        return self.table[64] == 1

    def load_torque(self, now: float) -> float:
        """Torque the load asks of the motor at servo time ``now``, N mm (0 before the
        first goal, whose arrival starts the load's clock)."""
        if self.load is None or self.load_start is None:
            return 0.0
        return self.load.at(now - self.load_start)

    def update(self, now: float | None = None) -> None:
        """Advance the motion model to ``now`` (monotonic seconds, scaled).

        The motor moves toward its goal at the profile velocity, slowed in proportion
        to the load's torque (a DC motor's torque-speed line); it cannot wind against a
        load at or beyond its stall torque, nor past ``load_turns`` (a taut string).
        Its current is the free-running (or idle) current plus the load's torque over
        the torque constant ``stall_torque / stall_current``, or ``stall_current`` when
        stalled.
        """
        now = time.monotonic() * self.time_scale if now is None else now
        dt = max(0.0, now - self.last_update) if self.last_update else 0.0
        self.last_update = now
        goal = float(self.value(116))
        velocity = self.value(112) or 1023  # 0 means the maximum speed
        speed = velocity * VELOCITY_UNIT_RPM / 60.0 * TICKS_PER_TURN  # ticks/s
        load = self.load_torque(now) if self.torque else 0.0
        free = max(0.0, 1.0 - load / self.stall_torque)  # share of the no-load speed
        limit = math.inf if self.load_turns is None else self.load_turns * TICKS_PER_TURN
        if self.torque and dt > 0:
            up = speed * free * dt  # winding: against the load
            step = max(-speed * dt, min(up, goal - self.position))
            target = self.position + step
            if target > limit and step > 0:  # the taut string stops the motor
                target = max(self.position, limit)
            self.position = target
        taut = goal > limit and self.position >= limit - 1
        stalled = self.torque and (taut or free == 0.0)
        moving = self.torque and abs(goal - self.position) > 1 and not stalled
        held = load * self.stall_current / self.stall_torque
        idle = self.moving_current if moving else 5
        current = self.stall_current if stalled else min(idle + held, self.stall_current)
        self.write(126, struct.pack("<h", int(current / CURRENT_UNIT_MA)))
        self.write(
            128, struct.pack("<i", int(speed * free / TICKS_PER_TURN * 60 / 0.229) if moving else 0)
        )
        self.write(132, struct.pack("<i", round(self.position)))
        self.table[122] = 1 if moving else 0
        if self.overload:
            self.table[70] |= _HW_OVERLOAD

    def handle_write(self, addr: int, data: bytes) -> int:
        """Apply a WRITE; returns the status error byte."""
        if addr < _EEPROM_END and self.torque:
            return _ERR_ACCESS
        if addr == 116:
            goal = struct.unpack("<i", data[:4])[0]
            if self.table[11] == 4 and abs(goal) > EXTENDED_LIMIT:
                return _ERR_DATA_RANGE
        self.update()
        self.write(addr, data)
        if addr == 116 and self.load_start is None and self.torque:
            self.load_start = self.last_update
        if addr == 64 and data[0] == 0:
            self.write(116, struct.pack("<i", round(self.position)))
        return 0

    def error_byte(self) -> int:
        return _HW_ALERT if self.table[70] else 0


def _check_ids(ids: list[int]) -> None:
    if not ids:
        raise DriveError("an emulator needs at least one servo ID")
    repeated = sorted({i for i in ids if ids.count(i) > 1})
    if repeated:
        raise DriveError(f"servo IDs {repeated} are given more than once (IDs {ids})")
    bad = [i for i in ids if not 0 <= i <= 252]
    if bad:
        raise DriveError(f"servo IDs {bad} are outside 0..252")


class _PtyDevice:
    """A pseudo-terminal whose device side runs in a thread."""

    def __init__(self) -> None:
        self._open_pty()
        self._thread: threading.Thread | None = None
        self.received = 0  # instruction packets (or command lines) received so far
        self._actions: dict[int, list] = {}

    def at_packet(self, n: int, action) -> None:
        """Call ``action()`` when the ``n``-th packet (or line) arrives, before answering it.

        Deterministic fault injection for tests: e.g. ``emu.at_packet(40, emu.unplug)``
        or ``emu.at_packet(40, lambda: emu.report_overload(2))``.
        """
        self._actions.setdefault(int(n), []).append(action)

    def _count_packet(self) -> bool:
        """Count a packet and run its scheduled actions; True if they unplugged the device."""
        stop = self._stop
        self.received += 1
        for action in self._actions.pop(self.received, []):
            action()
        return stop.is_set()

    def _open_pty(self) -> None:
        self.master, self.slave = os.openpty()
        tty.setraw(self.slave)
        tty.setraw(self.master)
        self.port = os.ttyname(self.slave)
        self._stop = threading.Event()

    def start(self):
        self._thread = threading.Thread(target=self._loop, daemon=True, name="servo-emulator")
        self._thread.start()
        return self

    def unplug(self) -> None:
        """Pull the cable: the host's port fails (EIO); the devices keep their state."""
        self.stop()

    def plug(self) -> None:
        """Plug the cable back in: a new pseudo-terminal, so :attr:`port` changes
        (as a USB adapter may come back under another name)."""
        self._open_pty()
        self._reset_input()
        self.start()

    def _reset_input(self) -> None:
        pass

    def stop(self) -> None:
        """Stop answering and close the pseudo-terminal (the host's port then fails)."""
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=2)
        fds, self.master, self.slave = (self.master, self.slave), -1, -1
        for fd in fds:  # once only: a closed descriptor's number may be reused
            if fd >= 0:
                with contextlib.suppress(OSError):
                    os.close(fd)

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    def _loop(self) -> None:
        stop, master = self._stop, self.master  # this pseudo-terminal's, even after plug()
        try:
            while not stop.is_set():
                ready, _, _ = select.select([master], [], [], 0.02)
                if not ready:
                    continue
                data = os.read(master, 4096)
                replies = self.feed(data)
                if stop.is_set():  # unplugged meanwhile: this descriptor is closed
                    return
                for reply in replies:
                    os.write(master, reply)
        except (OSError, ValueError):  # unplugged or stopped meanwhile
            return

    def feed(self, data: bytes) -> list[bytes]:  # pragma: no cover - overridden
        raise NotImplementedError


def _check_time_scale(time_scale: float) -> None:
    if not (math.isfinite(time_scale) and time_scale > 0):
        raise DriveError(f"emulator time scale must be finite and > 0, got {time_scale}")


class DynamixelEmulator(_PtyDevice):
    """X-series servos answering Protocol 2.0 on a pseudo-terminal.

    Parameters
    ----------
    ids : iterable of int
        Servo IDs on the bus.
    model : str
        One of :data:`MODELS`.
    load_turns : dict, optional
        Per servo ID, the motor turns at which its string becomes taut: beyond
        it the motor stalls and its current rises to ``stall_current``.
    loads : dict, optional
        Per servo ID, a :class:`~origami_cad.drive.load.LoadCurve`: the torque its
        load asks of it (N mm) against time since its first goal position, in servo
        time (a sequence's ``load``). Beyond the model's :data:`STALL_TORQUE` it stalls.
    time_scale : float
        Servo time runs this many times faster than real time (for dry runs of
        long sequences run with the same ``time_scale``).
    """

    def __init__(
        self,
        ids,
        model: str = "XL330-M288",
        load_turns: dict | None = None,
        time_scale: float = 1.0,
        loads: dict[int, LoadCurve] | None = None,
    ) -> None:
        ids = [int(i) for i in ids]
        _check_ids(ids)
        _check_time_scale(time_scale)
        if model not in MODELS:
            raise DriveError(f"unknown servo model {model!r}; one of {', '.join(MODELS)}")
        super().__init__()
        self.servos = {
            i: EmulatedServo(
                i,
                MODELS[model],
                load_turns=(load_turns or {}).get(i),
                time_scale=time_scale,
                load=(loads or {}).get(i),
                stall_torque=STALL_TORQUE[model],
            )
            for i in ids
        }
        self._buffer = bytearray()
        self._lock = threading.RLock()  # plug() from an injected action
        self.packets_in = 0
        self.instructions: Counter[int] = Counter()  # instruction packets received, by kind

    def _reset_input(self) -> None:
        with self._lock:
            self._buffer.clear()

    # -- fault injection
    def drop_status(self, dxl_id: int, count: int = 1) -> None:
        """Do not answer the next ``count`` packets addressed to ``dxl_id``."""
        self.servos[dxl_id].drop += count

    def corrupt_status(self, dxl_id: int, count: int = 1) -> None:
        """Send the next ``count`` status packets of ``dxl_id`` with a wrong CRC."""
        self.servos[dxl_id].corrupt += count

    def report_overload(self, dxl_id: int) -> None:
        """Set the overload bit of Hardware Error Status (the alert bit in every status)."""
        self.servos[dxl_id].overload = True

    def _status(self, servo: EmulatedServo, error: int = 0, params: bytes = b"") -> bytes | None:
        if servo.drop:
            servo.drop -= 1
            return None
        pkt = bytearray(status_packet(servo.dxl_id, error | servo.error_byte(), params))
        if servo.corrupt:
            servo.corrupt -= 1
            pkt[-1] ^= 0x5A
        return bytes(pkt)

    def feed(self, data: bytes) -> list[bytes]:
        out: list[bytes] = []
        with self._lock:
            self._buffer.extend(data)
            for pkt in parse_packets(self._buffer):
                if self._count_packet():  # unplugged by an injected fault
                    return []
                self.packets_in += 1
                self.instructions[pkt.instruction] += 1
                if not pkt.crc_ok:
                    continue  # a real servo ignores a corrupted instruction
                out.extend(r for r in self._answer(pkt) if r is not None)
        return out

    def _answer(self, pkt) -> list[bytes | None]:
        p = pkt.params
        if pkt.instruction == SYNC_WRITE and pkt.dxl_id == BROADCAST:
            addr, size = struct.unpack("<HH", p[:4])
            for k in range(4, len(p), size + 1):
                servo = self.servos.get(p[k])
                if servo is not None:
                    servo.handle_write(addr, p[k + 1 : k + 1 + size])
            return []
        if pkt.instruction == SYNC_READ and pkt.dxl_id == BROADCAST:
            addr, size = struct.unpack("<HH", p[:4])
            replies = []
            for dxl_id in p[4:]:
                servo = self.servos.get(dxl_id)
                if servo is not None:
                    replies.append(self._status(servo, 0, servo.read(addr, size)))
            return replies
        servo = self.servos.get(pkt.dxl_id)
        if servo is None:
            return []
        if pkt.instruction == PING:
            return [self._status(servo, 0, servo.read(0, 2) + servo.read(6, 1))]
        if pkt.instruction == READ:
            addr, size = struct.unpack("<HH", p[:4])
            return [self._status(servo, 0, servo.read(addr, size))]
        if pkt.instruction == WRITE:
            addr = struct.unpack("<H", p[:2])[0]
            return [self._status(servo, servo.handle_write(addr, p[2:]))]
        if pkt.instruction == CLEAR:
            servo.update()
            turns = int(servo.position // TICKS_PER_TURN)
            servo.position -= turns * TICKS_PER_TURN
            servo.write(116, struct.pack("<i", round(servo.position)))
            servo.update()
            return [self._status(servo)]
        if pkt.instruction == REBOOT:
            servo.table[64] = 0
            servo.table[70] = 0
            servo.overload = False
            return [self._status(servo)]
        return [self._status(servo, _ERR_INSTRUCTION)]


class SerialEmulator(_PtyDevice):
    """A board speaking the generic line protocol (see :mod:`origami_cad.drive.serial`).

    Parameters
    ----------
    ids : iterable of int
        Motor IDs on the board.
    corrupt_replies : int
        This many replies, from the first, get a wrong checksum (fault injection).
    time_scale : float
        The motors move this many times faster than real time (for dry runs of
        sequences run with the same ``time_scale``).
    """

    def __init__(self, ids, corrupt_replies: int = 0, time_scale: float = 1.0) -> None:
        ids = [int(i) for i in ids]
        _check_ids(ids)
        _check_time_scale(time_scale)
        super().__init__()
        from origami_cad.drive.serial import LineDevice

        self.device = LineDevice(ids, time_scale=time_scale)
        self.device.corrupt_replies = corrupt_replies
        self._buffer = b""

    def _reset_input(self) -> None:
        self._buffer = b""

    def feed(self, data: bytes) -> list[bytes]:
        self._buffer += data
        out = []
        while b"\n" in self._buffer:
            line, self._buffer = self._buffer.split(b"\n", 1)
            if self._count_packet():  # unplugged by an injected fault
                return []
            reply = self.device.handle(line.decode("ascii", "replace").strip())
            if reply is not None:
                out.append((reply + "\n").encode("ascii"))
        return out
