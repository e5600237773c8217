"""Servo TSAs over Dynamixel Protocol 2.0, on ``dynamixel_sdk``.

:class:`DynamixelBus` puts every servo in extended position (multi-turn) mode,
so one TSA can twist its strings many turns; positions are exchanged in turns
(4096 ticks each). Extended position mode spans -256 to +256 turns: goals
beyond are refused (:meth:`DynamixelBus.clear_multi_turn` re-zeroes a servo's
turn count at its present position if a long gait drifts toward the limit).

Safety:

- a per-servo maximum number of turns (from the TSA model's maximum
  contraction, see :func:`max_turns_for`): a goal beyond it is refused, never sent;
- a current limit: :meth:`DynamixelBus.read` stops a servo whose present
  current exceeds it (the string is taut, the TSA stalls) and raises
  :class:`StallError` naming it;
- :meth:`DynamixelBus.stop` disables torque on every servo; leaving the
  ``with`` block does too, on an exception and on Ctrl-C (KeyboardInterrupt).

Faults raise :class:`DriveError` naming the servo and the cause: no status
packet (after ``retries`` further attempts), CRC error, hardware error bits
(overload, overheating, input voltage, ...), a port that cannot be opened.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable

from origami_cad.drive.errors import DriveError, StallError
from origami_cad.drive.serial import _check_limit, _limits

__all__ = [
    "ADDR",
    "HARDWARE_ERRORS",
    "STATUS_ERRORS",
    "TICKS_PER_TURN",
    "DynamixelBus",
    "max_turns_for",
    "ticks_to_turns",
    "turns_to_ticks",
]

TICKS_PER_TURN = 4096
EXTENDED_TURNS = 256
#: Control-table addresses of the X series used here.
ADDR = {
    "model": 0,
    "operating_mode": 11,
    "current_limit": 38,
    "torque": 64,
    "hardware_error": 70,
    "profile_acceleration": 108,
    "profile_velocity": 112,
    "goal_position": 116,
    "present_current": 126,
    "present_velocity": 128,
    "present_position": 132,
}
EXTENDED_POSITION_MODE = 4
#: Bits of Hardware Error Status (address 70).
HARDWARE_ERRORS = {
    0x01: "input voltage error",
    0x04: "overheating",
    0x08: "motor encoder error",
    0x10: "electrical shock",
    0x20: "overload",
}
#: Status packet error values (the low 7 bits of the error byte).
STATUS_ERRORS = {
    1: "result fail",
    2: "instruction error",
    3: "CRC error in the instruction",
    4: "data range error (value out of range)",
    5: "data length error",
    6: "data limit error",
    7: "access error (EEPROM items are writable only with torque off)",
}
CURRENT_UNIT_MA = 1.0  # XL330; 2.69 mA for XL430 (set DynamixelBus.current_unit)


def turns_to_ticks(turns: float) -> int:
    """Motor turns to position ticks (4096 per turn)."""
    return round(turns * TICKS_PER_TURN)


def ticks_to_turns(ticks: int) -> float:
    """Position ticks to motor turns."""
    return ticks / TICKS_PER_TURN


def _signed32(value: int) -> int:
    return value - (1 << 32) if value & 0x80000000 else value


def _signed16(value: int) -> int:
    return value - (1 << 16) if value & 0x8000 else value


def max_turns_for(tsa, safety: float = 0.95) -> float:
    """The most a TSA may twist, turns: ``safety`` times its model's maximum.

    ``tsa`` is a :class:`~origami_cad.strings.tsa.TSAParams` (onboard model:
    the maximum helix angle of its strands).
    """
    return safety * tsa.max_theta() / (2 * math.pi)


class DynamixelBus:
    """A bus of Dynamixel X servos driving TSAs (context manager).

    Parameters
    ----------
    port : str
        Serial port, e.g. ``/dev/ttyUSB0`` (or the emulator's pseudo-terminal).
    baudrate : int
        Baud rate of the servos (57600 by default, as shipped).
    ids : iterable of int
        Servo IDs.
    max_turns : dict or float, optional
        Safety limit per servo (or for all), turns; defaults to the +-256 turns
        of extended position mode.
    current_limit_ma : float, optional
        A servo whose present current exceeds it is stopped (stall), mA.
    profile_velocity, profile_acceleration : int
        Written to every servo on open (X-series units: 0.229 rpm, 214.577 rev/min^2).
    retries : int
        Further attempts after a missing status packet before failing.
    """

    def __init__(
        self,
        port: str,
        baudrate: int = 57600,
        ids: Iterable[int] = (1,),
        *,
        max_turns: dict | float | None = None,
        current_limit_ma: float | None = None,
        profile_velocity: int = 200,
        profile_acceleration: int = 50,
        retries: int = 2,
    ) -> None:
        self.port_name = port
        self.baudrate = baudrate
        self.ids = [int(i) for i in ids]
        limits = _limits(self.ids, max_turns)
        self.max_turns = {i: min(v, EXTENDED_TURNS) for i, v in limits.items()}
        self.current_limit_ma = current_limit_ma
        self.profile_velocity = profile_velocity
        self.profile_acceleration = profile_acceleration
        self.retries = retries
        self.current_unit = CURRENT_UNIT_MA
        self.models: dict[int, int] = {}
        self._port = None
        self._ph = None

    # ------------------------------------------------------------------ set-up
    def open(self) -> DynamixelBus:
        """Open the port, ping every servo, switch to extended position mode, enable torque."""
        import dynamixel_sdk as sdk

        self._sdk = sdk
        self._port = sdk.PortHandler(self.port_name)
        self._ph = sdk.PacketHandler(2.0)
        try:
            opened = self._port.openPort()
        except Exception as exc:  # serial.SerialException, OSError
            raise DriveError(f"port {self.port_name} cannot be opened: {exc}") from None
        if not opened or not self._port.setBaudRate(self.baudrate):
            raise DriveError(f"port {self.port_name} cannot be opened at {self.baudrate} bps")
        try:
            for i in self.ids:
                self.models[i] = self._call(i, "ping", lambda i=i: self._ph.ping(self._port, i))
                self._write(i, ADDR["torque"], 1, 0)
                self._write(i, ADDR["operating_mode"], 1, EXTENDED_POSITION_MODE)
                self._write(i, ADDR["profile_acceleration"], 4, self.profile_acceleration)
                self._write(i, ADDR["profile_velocity"], 4, self.profile_velocity)
                self._write(i, ADDR["torque"], 1, 1)
        except BaseException:
            self.close()
            raise
        self._sync_write = sdk.GroupSyncWrite(self._port, self._ph, ADDR["goal_position"], 4)
        # one sync read covers present current (126), velocity (128) and position (132)
        self._sync_read = sdk.GroupSyncRead(self._port, self._ph, ADDR["present_current"], 10)
        for i in self.ids:
            self._sync_read.addParam(i)
        return self

    def close(self) -> None:
        if self._port is not None:
            self._port.closePort()
            self._port = None

    def __enter__(self) -> DynamixelBus:
        return self.open()

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if self._port is not None:
                self.stop(raise_errors=exc_type is None)
        finally:
            self.close()

    # ------------------------------------------------------------------ low level
    def _check(
        self, dxl_id: int, what: str, comm: int, error: int, tolerate_alert: bool = False
    ) -> None:
        sdk = self._sdk
        if comm == sdk.COMM_RX_CORRUPT:
            raise DriveError(f"servo {dxl_id}: CRC error in its status packet ({what})")
        if comm != sdk.COMM_SUCCESS:
            raise DriveError(f"servo {dxl_id}: {self._ph.getTxRxResult(comm)} ({what})")
        if error & 0x7F:
            name = STATUS_ERRORS.get(error & 0x7F, f"error {error & 0x7F}")
            raise DriveError(f"servo {dxl_id}: {name} ({what})")
        if error & 0x80 and not tolerate_alert:
            raise DriveError(
                f"servo {dxl_id}: hardware error: {self._hardware_error(dxl_id)} ({what})"
            )

    def _hardware_error(self, dxl_id: int) -> str:
        value, comm, _ = self._ph.read1ByteTxRx(self._port, dxl_id, ADDR["hardware_error"])
        if comm != self._sdk.COMM_SUCCESS:
            return "unknown (Hardware Error Status could not be read)"
        names = [name for bit, name in HARDWARE_ERRORS.items() if value & bit]
        return ", ".join(names) or f"status {value:#04x}"

    def _call(self, dxl_id: int, what: str, fn, tolerate_alert: bool = False):
        """Run an SDK transaction, retrying a missing status packet ``retries`` times."""
        for attempt in range(self.retries + 1):
            result = fn()
            value, comm, error = result if len(result) == 3 else (None, *result)
            if comm == self._sdk.COMM_RX_TIMEOUT and attempt < self.retries:
                self._port.clearPort()
                continue
            if comm == self._sdk.COMM_RX_TIMEOUT:
                raise DriveError(
                    f"servo {dxl_id}: no status packet (timeout) after {self.retries + 1} "
                    f"attempts ({what})"
                )
            self._check(dxl_id, what, comm, error, tolerate_alert)
            return value
        raise AssertionError("unreachable")  # pragma: no cover

    def _write(
        self, dxl_id: int, addr: int, size: int, value: int, tolerate_alert: bool = False
    ) -> None:
        fn = {1: self._ph.write1ByteTxRx, 2: self._ph.write2ByteTxRx, 4: self._ph.write4ByteTxRx}
        what = f"write {value} at address {addr}"
        self._call(dxl_id, what, lambda: fn[size](self._port, dxl_id, addr, value), tolerate_alert)

    def read_value(self, dxl_id: int, addr: int, size: int) -> int:
        """Read one control-table item (unsigned)."""
        fn = {1: self._ph.read1ByteTxRx, 2: self._ph.read2ByteTxRx, 4: self._ph.read4ByteTxRx}
        return self._call(
            dxl_id, f"read address {addr}", lambda: fn[size](self._port, dxl_id, addr)
        )

    # ------------------------------------------------------------------ motion
    def set_turns(self, targets: dict[int, float]) -> None:
        """Goal positions of several servos in one GroupSyncWrite, turns.

        Raises :class:`DriveError` (nothing sent) if a goal exceeds a servo's limit.
        """
        for i, turns in targets.items():
            if i not in self.max_turns:
                raise DriveError(f"servo {i} is not on this bus (ids {self.ids})")
            _check_limit(i, turns, self.max_turns)
        self._sync_write.clearParam()
        for i, turns in targets.items():
            data = turns_to_ticks(turns).to_bytes(4, "little", signed=True)
            self._sync_write.addParam(i, list(data))
        comm = self._sync_write.txPacket()
        if comm != self._sdk.COMM_SUCCESS:
            raise DriveError(
                f"sync write to servos {list(targets)} failed: {self._ph.getTxRxResult(comm)}"
            )

    def read(self) -> dict[int, tuple[float, float]]:
        """Present position (turns) and current (mA) of every servo, in one GroupSyncRead.

        Stops a servo whose current exceeds ``current_limit_ma`` and raises
        :class:`StallError` naming it.
        """
        for attempt in range(self.retries + 1):
            comm = self._sync_read.txRxPacket()
            if comm == self._sdk.COMM_SUCCESS:
                break
            # the SDK reads status packets in order and stops at the first failure,
            # leaving that servo's data empty
            data = self._sync_read.data_dict
            missing = [i for i in self.ids if len(data.get(i) or []) != 10]
            who = f"servo {missing[0]}" if missing else f"servos {self.ids}"
            if comm == self._sdk.COMM_RX_CORRUPT:
                raise DriveError(f"{who}: CRC error in its status packet (sync read)")
            if attempt == self.retries:
                raise DriveError(
                    f"{who}: no status packet (timeout) after "
                    f"{self.retries + 1} attempts (sync read)"
                )
            self._port.clearPort()
        out = {}
        for i in self.ids:
            current = _signed16(self._sync_read.getData(i, ADDR["present_current"], 2))
            ticks = _signed32(self._sync_read.getData(i, ADDR["present_position"], 4))
            out[i] = (ticks_to_turns(ticks), current * self.current_unit)
        if self.current_limit_ma is not None:
            for i, (turns, current) in out.items():
                if abs(current) > self.current_limit_ma:
                    self.stop_servo(i)
                    raise StallError(
                        f"servo {i}: current {abs(current):.0f} mA exceeds the limit of "
                        f"{self.current_limit_ma:g} mA at {turns:.3f} turns (string tension "
                        "too high); the servo was stopped"
                    )
        return out

    def wait(
        self, targets: dict[int, float], tolerance: float = 0.01, timeout: float = 10.0
    ) -> dict[int, tuple[float, float]]:
        """Read until every servo is within ``tolerance`` turns of its target."""
        deadline = time.monotonic() + timeout
        while True:
            state = self.read()
            if all(abs(state[i][0] - t) <= tolerance for i, t in targets.items()):
                return state
            if time.monotonic() > deadline:
                far = {
                    i: state[i][0] for i, t in targets.items() if abs(state[i][0] - t) > tolerance
                }
                raise DriveError(
                    f"servos {sorted(far)} did not reach their goals in {timeout:g} s (at {far})"
                )
            time.sleep(0.005)

    def clear_multi_turn(self, dxl_id: int) -> None:
        """Re-zero the servo's turn count at its present position (CLEAR instruction)."""
        self._call(dxl_id, "clear multi-turn", lambda: self._ph.clearMultiTurn(self._port, dxl_id))

    def stop_servo(self, dxl_id: int) -> None:
        """Disable torque on one servo (even one reporting a hardware alert)."""
        self._write(dxl_id, ADDR["torque"], 1, 0, tolerate_alert=True)

    def stop(self, raise_errors: bool = True) -> None:
        """Disable torque on every servo (all are tried even if one fails)."""
        errors = []
        for i in self.ids:
            try:
                self.stop_servo(i)
            except DriveError as exc:
                errors.append(str(exc))
        if errors and raise_errors:
            raise DriveError("; ".join(errors))
