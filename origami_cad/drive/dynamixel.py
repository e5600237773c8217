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
- :meth:`DynamixelBus.stop` disables torque on every servo and reads it back;
  :meth:`DynamixelBus.close` and leaving the ``with`` block do too, on an
  exception and on Ctrl-C (KeyboardInterrupt), even one that lands inside a
  ``dynamixel_sdk`` transaction (see the class notes).

Faults raise :class:`DriveError` naming the servo and the cause: no status
packet (after ``retries`` further attempts), CRC error, a port that cannot be
opened; :class:`HardwareError` for hardware error bits (overload,
overheating, input voltage, ...); :class:`PortLostError` for a port that
stops working; :class:`TorqueOffError` for servos whose torque off could not
be confirmed. ``docs/driving.md`` lists what happens on each fault.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable

from origami_cad.drive.bus import ServoBus
from origami_cad.drive.errors import (
    PORT_ERRORS,
    DriveError,
    HardwareError,
    PortLostError,
    TorqueOffError,
    hold_ctrl_c,
    port_error_text,
)

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


def max_turns_for(tsa, safety: float = 0.95) -> float:
    """The most a TSA may twist, turns: ``safety`` times its model's maximum.

    ``tsa`` is a :class:`~origami_cad.strings.tsa.TSAParams` (onboard model:
    the maximum helix angle of its strands).
    """
    return safety * tsa.max_theta() / (2 * math.pi)


class _NoStatus(DriveError):
    """No status packet came back (after the retries)."""


def _servo_list(ids) -> str:
    ids = list(ids)
    return f"servo {ids[0]}" if len(ids) == 1 else f"servos {', '.join(map(str, ids))}"


def _add_reply_slack(port, slack_ms: float) -> None:
    """Make ``port`` (a ``dynamixel_sdk.PortHandler``) wait ``slack_ms`` longer for replies."""
    base = port.setPacketTimeout

    def set_packet_timeout(packet_length):
        base(packet_length)
        port.packet_timeout += slack_ms

    port.setPacketTimeout = set_packet_timeout


class DynamixelBus(ServoBus):
    """A bus of Dynamixel X servos driving TSAs (context manager).

    Parameters
    ----------
    port : str
        Serial port, e.g. ``/dev/ttyUSB0`` (or the emulator's pseudo-terminal).
    baudrate : int
        Baud rate of the servos (57600 by default, as shipped).
    ids : iterable of int
        Servo IDs.
    profile_velocity, profile_acceleration : int
        Written to every servo on open (X-series units: 0.229 rpm, 214.577 rev/min^2).
    retries : int
        Further attempts after a missing status packet before failing.
    reply_slack : float
        Extra time to wait for a status packet beyond ``dynamixel_sdk``'s own
        timeout (about 34 ms), s. 0 on real hardware; a dry run against the
        emulator, which shares this process and its cores, gives it more so that a
        loaded machine is not taken for a missing servo.
    **limits
        The safety limits of :class:`~origami_cad.drive.bus.ServoBus`, by keyword:
        ``max_turns`` (dict or float: per servo or for all, turns; defaults to the
        +-256 turns of extended position mode), ``current_limit_ma`` (a servo whose
        present current exceeds it is stopped as stalled, mA), ``stop_attempts``
        (attempts per servo to switch its torque off, and read it back as off,
        before :meth:`stop` reports it) and ``reopen_timeout`` (how long
        :meth:`stop` keeps trying to reopen a lost port, s).

    Notes
    -----
    Safety guarantees (each tested against the emulator, reading every
    servo's Torque Enable back afterwards):

    - :meth:`open` pings every servo before it enables any torque; if one is
      missing or faulty, or anything fails (Ctrl-C included), every servo that
      answered is switched off again before the error is raised;
    - :meth:`close` and leaving the ``with`` block switch torque off on every
      servo (see :meth:`stop`), whatever ended the run;
    - a Ctrl-C inside a ``dynamixel_sdk`` transaction leaves the port marked
      busy: the next transaction clears that state and drops the late status
      packet first;
    - a hardware error (overload, overheating, ...) in any status packet,
      including those of the sync read, raises :class:`HardwareError` naming
      the servo and the error, after torque off on every servo;
    - a port that stops working raises :class:`PortLostError` naming it; the
      shutdown then tries to reopen it for ``reopen_timeout`` seconds to reach
      the servos;
    - a servo whose torque could not be switched off is never silently
      skipped: :class:`TorqueOffError` names it.
    """

    def __init__(
        self,
        port: str,
        baudrate: int = 57600,
        ids: Iterable[int] = (1,),
        *,
        profile_velocity: int = 200,
        profile_acceleration: int = 50,
        retries: int = 2,
        reply_slack: float = 0.0,
        **limits,
    ) -> None:
        # limits: max_turns, current_limit_ma, stop_attempts, reopen_timeout (ServoBus)
        super().__init__(port, baudrate, ids, **limits)
        self.max_turns = {i: min(v, EXTENDED_TURNS) for i, v in self.max_turns.items()}
        self.profile_velocity = profile_velocity
        self.profile_acceleration = profile_acceleration
        self.retries = retries
        if not (math.isfinite(reply_slack) and 0 <= reply_slack <= 10):
            raise DriveError(f"reply slack must be within 0..10 s, got {reply_slack}")
        self.reply_slack = float(reply_slack)
        self.current_unit = CURRENT_UNIT_MA
        self._sdk = None
        self._ph = None
        self._reached: list[int] = []  # servos that answered: the ones stop() switches off
        self._dirty = False  # a transaction was interrupted: drain the port first

    # ------------------------------------------------------------------ set-up
    def open(self) -> DynamixelBus:
        """Open the port, ping every servo, switch to extended position mode, enable torque.

        Every servo must answer before torque goes on anywhere. On any failure
        (a missing servo, a hardware error, Ctrl-C) torque is switched off on
        every servo that answered, the port is closed and the error raised.
        """
        return super().open()

    def _prepare(self) -> None:
        import dynamixel_sdk as sdk

        self._sdk = sdk
        self._ph = sdk.PacketHandler(2.0)
        self._reached = []
        self._dirty = False

    def _start(self) -> None:
        self._ping_all()
        for i in self.ids:
            self._write(i, ADDR["torque"], 1, 0)
            self._write(i, ADDR["operating_mode"], 1, EXTENDED_POSITION_MODE)
            self._write(i, ADDR["profile_acceleration"], 4, self.profile_acceleration)
            self._write(i, ADDR["profile_velocity"], 4, self.profile_velocity)
        for i in self.ids:
            self._write(i, ADDR["torque"], 1, 1)

    def _open_port(self):
        port = self._sdk.PortHandler(self.port_name)
        try:
            opened = port.openPort() and port.setBaudRate(self.baudrate)
        except PORT_ERRORS as exc:  # serial.SerialException, OSError
            raise DriveError(f"port {self.port_name} cannot be opened: {exc}") from None
        if not opened:
            raise DriveError(f"port {self.port_name} cannot be opened at {self.baudrate} bps")
        if self.reply_slack:
            _add_reply_slack(port, 1000.0 * self.reply_slack)
        return port

    def _ping_all(self) -> None:
        """Ping every servo; raise naming every one that does not answer."""
        missing: dict[int, DriveError] = {}
        for i in self.ids:
            try:
                self.models[i] = self._call(i, "ping", lambda i=i: self._ph.ping(self._port, i))
            except HardwareError:
                self._reached.append(i)  # it answered: its torque may be on
                raise
            except PortLostError:
                raise
            except DriveError as exc:
                missing[i] = exc
                continue
            self._reached.append(i)
        if not missing:
            return
        if all(isinstance(e, _NoStatus) for e in missing.values()):
            them = "its ID" if len(missing) == 1 else "their IDs"
            raise DriveError(
                f"{_servo_list(missing)} did not answer a ping on port {self.port_name} at "
                f"{self.baudrate} bps ({self.retries + 1} attempts): check {them}, the baud "
                "rate, the wiring and the power; no torque was enabled"
            )
        raise DriveError("; ".join(str(e) for e in missing.values()) + "; no torque was enabled")

    def _close_port(self, port) -> None:
        port.closePort()

    # ------------------------------------------------------------------ low level
    def _io(self, fn):
        """Run ``fn`` (SDK calls on the port): a lost port becomes :class:`PortLostError`.

        An exception inside the SDK (Ctrl-C while it waits for a status packet)
        leaves ``is_using`` set and a late status packet on its way: both are
        cleared before the next transaction.
        """
        port = self._open()
        try:
            if self._dirty or port.is_using:
                self._recover(port)
            return fn()
        except PORT_ERRORS as exc:
            raise self._lost(exc) from exc
        except BaseException:
            port.is_using = False
            self._dirty = True
            raise

    def _recover(self, port) -> None:
        """Clear the SDK's busy flag and drop any late status packet (up to 0.2 s)."""
        port.is_using = False
        deadline = time.monotonic() + 0.2
        time.sleep(0.01)
        while True:
            waiting = port.getBytesAvailable()
            port.clearPort()
            if not waiting or time.monotonic() > deadline:
                break
            time.sleep(0.01)
        self._dirty = False

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
            raise HardwareError(
                f"servo {dxl_id}: hardware error: {self._hardware_error(dxl_id)} ({what}); "
                "reboot the servo to clear it"
            )

    def _hardware_error(self, dxl_id: int) -> str:
        """The bits of Hardware Error Status (address 70), by name."""
        value, comm, _ = self._io(
            lambda: self._ph.read1ByteTxRx(self._port, dxl_id, ADDR["hardware_error"])
        )
        if comm != self._sdk.COMM_SUCCESS:
            return "unknown (Hardware Error Status could not be read)"
        names = [name for bit, name in HARDWARE_ERRORS.items() if value & bit]
        return ", ".join(names) or f"status {value:#04x}"

    def _call(
        self, dxl_id: int, what: str, fn, tolerate_alert: bool = False, retries: int | None = None
    ):
        """Run an SDK transaction, retrying a missing status packet ``retries`` times."""
        retries = self.retries if retries is None else retries
        for attempt in range(retries + 1):
            result = self._io(fn)
            value, comm, error = result if len(result) == 3 else (None, *result)
            if comm == self._sdk.COMM_RX_TIMEOUT and attempt < retries:
                self._io(self._port.clearPort)
                continue
            if comm == self._sdk.COMM_RX_TIMEOUT:
                raise _NoStatus(
                    f"servo {dxl_id}: no status packet (timeout) after {retries + 1} "
                    f"attempts ({what})"
                )
            self._check(dxl_id, what, comm, error, tolerate_alert)
            return value
        raise AssertionError("unreachable")  # pragma: no cover

    def _write(
        self,
        dxl_id: int,
        addr: int,
        size: int,
        value: int,
        tolerate_alert: bool = False,
        retries: int | None = None,
    ) -> None:
        fn = {1: self._ph.write1ByteTxRx, 2: self._ph.write2ByteTxRx, 4: self._ph.write4ByteTxRx}
        what = f"write {value} at address {addr}"
        self._call(
            dxl_id,
            what,
            lambda: fn[size](self._port, dxl_id, addr, value),
            tolerate_alert,
            retries,
        )

    def read_value(self, dxl_id: int, addr: int, size: int, tolerate_alert: bool = False) -> int:
        """Read one control-table item (unsigned)."""
        fn = {1: self._ph.read1ByteTxRx, 2: self._ph.read2ByteTxRx, 4: self._ph.read4ByteTxRx}
        return self._call(
            dxl_id,
            f"read address {addr}",
            lambda: fn[size](self._port, dxl_id, addr),
            tolerate_alert,
        )

    # ------------------------------------------------------------------ motion
    def set_turns(self, targets: dict[int, float]) -> None:
        """Goal positions of several servos in one SyncWrite, turns.

        Raises :class:`DriveError` (nothing sent) if a goal exceeds a servo's limit.
        """
        self.check_goals(targets)
        params: list[int] = []
        for i, turns in targets.items():
            params += [i, *turns_to_ticks(turns).to_bytes(4, "little", signed=True)]
        comm = self._io(
            lambda: self._ph.syncWriteTxOnly(
                self._port, ADDR["goal_position"], 4, params, len(params)
            )
        )
        if comm != self._sdk.COMM_SUCCESS:
            raise DriveError(
                f"sync write to servos {list(targets)} failed: {self._ph.getTxRxResult(comm)}"
            )

    def _sync_read_once(self) -> tuple[int, dict[int, list[int]], dict[int, int], int | None]:
        """One SyncRead of present current, velocity and position (126-135) of every servo.

        Unlike ``GroupSyncRead`` it keeps each status packet's error byte
        (hardware alerts). Returns the result code, the data and error byte of
        every servo read, and the first servo that did not answer.
        """
        sdk, ph, port = self._sdk, self._ph, self._port
        comm = ph.syncReadTx(port, ADDR["present_current"], 10, self.ids, len(self.ids), False)
        data: dict[int, list[int]] = {}
        errors: dict[int, int] = {}
        if comm != sdk.COMM_SUCCESS:
            return comm, data, errors, None
        for i in self.ids:
            raw, comm, error = ph.readRx(port, i, 10)
            if comm != sdk.COMM_SUCCESS:
                return comm, data, errors, i
            data[i], errors[i] = raw, error
        return comm, data, errors, None

    def read(self) -> dict[int, tuple[float, float]]:
        """Present position (turns) and current (mA) of every servo, in one SyncRead.

        Stops a servo whose current exceeds ``current_limit_ma`` and raises
        :class:`StallError` naming it. A hardware alert in any servo's status
        switches torque off on every servo and raises :class:`HardwareError`
        naming the servo and its Hardware Error Status.
        """
        sdk = self._sdk
        for attempt in range(self.retries + 1):
            comm, data, errors, missing = self._io(self._sync_read_once)
            if comm == sdk.COMM_SUCCESS:
                break
            who = f"servo {missing}" if missing is not None else f"servos {self.ids}"
            if comm == sdk.COMM_RX_CORRUPT:
                raise DriveError(f"{who}: CRC error in its status packet (sync read)")
            if comm != sdk.COMM_RX_TIMEOUT:
                raise DriveError(f"{who}: {self._ph.getTxRxResult(comm)} (sync read)")
            if attempt == self.retries:
                raise DriveError(
                    f"{who}: no status packet (timeout) after "
                    f"{self.retries + 1} attempts (sync read)"
                )
            self._io(self._port.clearPort)
        for i, error in errors.items():
            if error & 0x7F:
                name = STATUS_ERRORS.get(error & 0x7F, f"error {error & 0x7F}")
                raise DriveError(f"servo {i}: {name} (sync read)")
        alerts = [i for i, error in errors.items() if error & 0x80]
        if alerts:
            what = "; ".join(
                f"servo {i}: hardware error: {self._hardware_error(i)}" for i in alerts
            )
            self._fail(
                HardwareError(
                    f"{what} (sync read); torque switched off on every servo; reboot "
                    f"{'it' if len(alerts) == 1 else 'them'} to clear the error"
                )
            )
        out = {}
        for i in self.ids:
            raw = bytes(data[i])
            current = int.from_bytes(raw[0:2], "little", signed=True)
            ticks = int.from_bytes(raw[6:10], "little", signed=True)
            out[i] = (ticks_to_turns(ticks), current * self.current_unit)
        self.stop_on_stall(out)
        return out

    def _stop_stalled(self, dxl_id: int) -> str:
        self.stop_servo(dxl_id)
        return "the servo was stopped"

    def _fail(self, exc: DriveError) -> None:
        """Switch every servo off, then raise ``exc`` (with any torque-off failure)."""
        try:
            with hold_ctrl_c():
                self.stop()
        except TorqueOffError as stop_exc:
            raise TorqueOffError(f"{exc}; {stop_exc}", stop_exc.servos) from exc
        raise exc

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

    def reboot(self, dxl_id: int) -> None:
        """Reboot a servo (clears its Hardware Error Status; its torque comes back off)."""
        self._call(
            dxl_id, "reboot", lambda: self._ph.reboot(self._port, dxl_id), tolerate_alert=True
        )

    # ------------------------------------------------------------------ stopping
    def stop_servo(self, dxl_id: int) -> None:
        """Disable torque on one servo (even one reporting a hardware alert), read back as off.

        Raises :class:`TorqueOffError` naming it if that fails ``stop_attempts`` times.
        """
        cause = self._stop_servo(dxl_id)
        if cause is not None:
            raise TorqueOffError(
                f"torque off could not be confirmed on servo {dxl_id} on port "
                f"{self.port_name} (cut its power): {cause}",
                [dxl_id],
            )

    def _stop_servo(self, dxl_id: int) -> str | None:
        """Switch one servo off, confirmed: None, or why it failed ``stop_attempts`` times."""
        cause = ""
        for _ in range(self.stop_attempts):
            try:
                if self._torque_off_once(dxl_id):
                    return None
                cause = f"servo {dxl_id}: Torque Enable still reads 1 after writing 0"
            except PortLostError:
                raise
            except DriveError as exc:
                cause = str(exc)
        return cause

    def _torque_off_once(self, dxl_id: int) -> bool:
        if self.read_value(dxl_id, ADDR["torque"], 1, tolerate_alert=True) == 0:
            return True
        self._write(dxl_id, ADDR["torque"], 1, 0, tolerate_alert=True)
        return self.read_value(dxl_id, ADDR["torque"], 1, tolerate_alert=True) == 0

    def _try_open(self):
        port = self._sdk.PortHandler(self.port_name)
        try:
            if port.openPort() and port.setBaudRate(self.baudrate):
                self._dirty = False
                return port, ""
            return None, f"the baud rate {self.baudrate} cannot be set"
        except PORT_ERRORS as exc:
            return None, port_error_text(exc)

    def stop(self) -> None:
        """Switch torque off on every servo, confirmed by reading Torque Enable back.

        One SyncWrite switches every servo off at once; each is then read back
        and, while still on, switched off on its own (``stop_attempts`` times).
        A lost port is reopened once. A Ctrl-C while stopping is held until
        every servo has been tried, then raised. Raises :class:`TorqueOffError`
        naming every servo that could not be switched off.
        """
        if self._port is None or self._sdk is None:
            return
        targets = list(self._reached)
        interrupt: KeyboardInterrupt | None = None
        params = [v for i in targets for v in (i, 0)]
        try:
            self._io(
                lambda: self._ph.syncWriteTxOnly(self._port, ADDR["torque"], 1, params, len(params))
            )
        except KeyboardInterrupt as exc:
            interrupt = exc
        except DriveError:
            pass  # each servo is tried on its own below
        failed: dict[int, str] = {}
        reopened = False
        lost: str | None = None  # why the port is gone for good
        for i in targets:
            for _ in range(self.stop_attempts + 1):
                if lost is not None:
                    failed[i] = lost
                    break
                try:
                    cause = self._stop_servo(i)
                except KeyboardInterrupt as exc:
                    interrupt = exc  # finish switching off first
                    continue
                except PortLostError as exc:
                    if reopened:
                        lost = f"the port was lost again after reopening it ({exc})"
                    else:
                        reason = self._reopen()
                        reopened = True
                        if reason is not None:
                            lost = f"the port is lost and cannot be reopened ({reason})"
                    continue
                if cause is not None:
                    failed[i] = cause
                break
            else:
                failed[i] = failed.get(i) or "interrupted while switching it off"
        if failed:
            grouped: dict[str, list[int]] = {}
            for i, msg in failed.items():
                grouped.setdefault(msg, []).append(i)
            causes = "; ".join(
                msg if msg.startswith(f"servo {ids[0]}:") else f"{_servo_list(ids)}: {msg}"
                for msg, ids in grouped.items()
            )
            raise TorqueOffError(
                f"torque off could not be confirmed on {_servo_list(failed)} on port "
                f"{self.port_name} (cut the servos' power): {causes}",
                list(failed),
            )
        self._powered = False
        if interrupt is not None:
            raise interrupt
