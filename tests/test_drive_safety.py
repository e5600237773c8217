"""Safety of the driver under faults: no servo is ever left powered, no fault goes unreported.

Every scenario runs the real ``dynamixel_sdk`` (or pyserial) against the emulator on a real
pseudo-terminal, injects the fault at a chosen packet (deterministically: a hook in the SDK's
port I/O, or the emulator's ``at_packet``), and then reads every servo's Torque Enable back
through a fresh connection.
"""

from __future__ import annotations

import csv
import os
import random
import re
import signal
import threading
from pathlib import Path

import dynamixel_sdk as sdk
import pytest
import serial

from origami_cad.cli import main
from origami_cad.drive import (
    DriveError,
    DynamixelBus,
    DynamixelEmulator,
    SerialBus,
    SerialEmulator,
)
from origami_cad.drive.errors import HardwareError, PortLostError, StallError, TorqueOffError
from origami_cad.drive.sequence import LOG_FIELDS, check_time_scale, load_sequence, run_sequence
from origami_cad.drive.serial import frame, unframe
from origami_cad.errors import OrigamiCadError

IDS = [1, 2, 3]


@pytest.fixture(autouse=True)
def patient_sdk(monkeypatch):
    """Wait up to 102 ms for a status packet instead of 34 ms.

    dynamixel_sdk's reply timeout allows for a USB adapter's 16 ms latency timer; a
    pseudo-terminal has none, but a loaded test machine may not schedule the emulator's
    thread in time. Packet counts (where faults are injected) then stay as planned.
    """
    monkeypatch.setattr(sdk.port_handler, "LATENCY_TIMER", 50)


RATE, CYCLE = 50.0, 0.6  # 31 command cycles
SCALE = 4.0  # the run takes 0.15 s
# packets the host sends before shutting down: 3 pings + 3 x 4 set-up writes + 3 torque-on
# writes, then a sync write and a sync read per cycle
OPEN_PACKETS = 6 * len(IDS)
RUN_PACKETS = OPEN_PACKETS + 2 * (round(CYCLE * RATE) + 1)


def write_sequence(folder: Path, ids, name: str = "seq.toml") -> Path:
    """A small sequence: every TSA folds to p = 0.5 and back in CYCLE seconds."""
    text = f"[sequence]\nrate = {RATE}\n"
    for i in ids:
        text += (
            f'[[tsa]]\nid = {i}\nname = "tsa {i}"\nlength = 120.0\nradius = 0.6\n'
            "max_helix_angle = 75.0\nmapping = [[0.0, 0.0], [1.0, 20.0]]\n"
        )
    n = len(ids)
    for t, p in ((0.0, 0.0), (CYCLE / 2, 0.5), (CYCLE, 0.0)):
        text += f"[[keyframe]]\nt = {t}\np = {[p] * n}\n"
    path = folder / name
    path.write_text(text)
    return path


def torque_over_the_wire(port: str, ids) -> dict[int, int]:
    """Torque Enable (address 64) of every servo, read through a fresh connection."""
    ph = sdk.PacketHandler(2.0)
    handler = sdk.PortHandler(port)
    assert handler.openPort()
    try:
        out = {}
        for i in ids:
            for _ in range(10):  # a loaded machine may miss the SDK's 34 ms timeout
                value, comm, _error = ph.read1ByteTxRx(handler, i, 64)  # alerts tolerated
                if comm == sdk.COMM_SUCCESS:
                    out[i] = value
                    break
            else:
                raise AssertionError(f"servo {i} does not answer on {port}")
        return out
    finally:
        handler.closePort()


def assert_all_off(emu: DynamixelEmulator) -> None:
    ids = list(emu.servos)
    assert torque_over_the_wire(emu.port, ids) == dict.fromkeys(ids, 0)
    assert [emu.servos[i].table[64] for i in ids] == [0] * len(ids)


def replug_at(emu, link: Path, packet: int) -> None:
    """``link`` points at the emulator's port; at ``packet`` the port is unplugged and
    plugged back, and ``link`` follows it (a udev link such as /dev/serial/by-id/...)."""
    link.symlink_to(emu.port)

    def replug():
        emu.unplug()
        emu.plug()
        link.unlink()
        link.symlink_to(emu.port)

    emu.at_packet(packet, replug)


def log_note(path: Path) -> str | None:
    """The comment line ending a log (why the run stopped), or None; only the last line
    may be a comment."""
    lines = path.read_text(encoding="utf-8").splitlines()
    notes = [k for k, line in enumerate(lines) if line.startswith("#")]
    assert notes in ([], [len(lines) - 1]), lines[-3:]
    return lines[-1] if notes else None


def assert_valid_log(path: Path, ids, stopped: str | None = None) -> list[dict[str, str]]:
    """The CSV log reads back whole: header, complete rows, one row per servo per cycle.

    ``stopped``: a pattern the last line, the comment saying why the run stopped, matches.
    """
    note = log_note(path)
    if stopped is not None:
        assert note is not None and re.search(stopped, note), note
    with path.open(newline="") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    with path.open(newline="") as fh:
        assert next(csv.reader(fh)) == list(LOG_FIELDS)
    for row in rows:
        assert None not in row and all(row[k] not in (None, "") for k in LOG_FIELDS)
        float(row["measured_turns"])
    assert len(rows) % len(ids) == 0
    assert [int(r["id"]) for r in rows] == ids * (len(rows) // len(ids))
    return rows


class CtrlC:
    """Raise KeyboardInterrupt inside dynamixel_sdk's port I/O, at packet ``packet``.

    ``phase``: ``before write`` (the SDK has marked the port busy, nothing sent yet),
    ``in flight`` (the packet is on the wire, the SDK is about to wait for its status),
    ``mid reply`` (the first bytes of the next status packet have been read).
    """

    def __init__(self, monkeypatch, packet: int, phase: str) -> None:
        self.packet, self.phase = packet, phase
        self.writes = 0
        self.fired = False
        self.busy_when_fired: bool | None = None
        self.armed = True
        write, read = sdk.PortHandler.writePort, sdk.PortHandler.readPort
        hook = self

        def write_port(port, data):
            hook.writes += 1
            if hook.due("before write"):
                hook.fire(port)
            n = write(port, data)
            if hook.due("in flight"):
                hook.fire(port)
            return n

        def read_port(port, length):
            mid = hook.armed and not hook.fired and hook.phase == "mid reply"
            if mid and hook.writes >= hook.packet:
                data = read(port, min(length, 4))
                if data:
                    hook.fire(port)
                return data
            return read(port, length)

        monkeypatch.setattr(sdk.PortHandler, "writePort", write_port)
        monkeypatch.setattr(sdk.PortHandler, "readPort", read_port)

    def due(self, phase: str) -> bool:
        return self.armed and not self.fired and self.phase == phase and self.writes == self.packet

    def fire(self, port) -> None:
        self.fired = True
        self.busy_when_fired = port.is_using
        raise KeyboardInterrupt


_rng = random.Random(19)
CTRL_C_PACKETS = sorted(
    {1, OPEN_PACKETS, OPEN_PACKETS + 1, OPEN_PACKETS + 2, RUN_PACKETS - 1}
    | set(_rng.sample(range(2, RUN_PACKETS), 7))
)


@pytest.mark.parametrize("phase", ["before write", "in flight", "mid reply"])
@pytest.mark.parametrize("packet", CTRL_C_PACKETS)
def test_ctrl_c_anywhere_leaves_every_servo_off(tmp_path, monkeypatch, packet, phase):
    seq = load_sequence(write_sequence(tmp_path, IDS))
    log = tmp_path / "log.csv"
    opened = False
    with DynamixelEmulator(IDS, time_scale=SCALE) as emu:
        hook = CtrlC(monkeypatch, packet, phase)
        with pytest.raises(KeyboardInterrupt):  # not a swallowed or replaced error
            with DynamixelBus(emu.port, ids=IDS, profile_velocity=0) as bus:
                opened = True
                run_sequence(seq, bus, log, time_scale=SCALE)
        hook.armed = False
        assert hook.fired
        # inside a transaction: the SDK had marked the port busy (the reported bug)
        assert hook.busy_when_fired
        assert_all_off(emu)
    if opened:  # the log was opened before the first command
        rows = assert_valid_log(log, IDS)
        assert len(rows) <= len(IDS) * max(0, packet - OPEN_PACKETS) // 2


@pytest.mark.parametrize("packet", [3, OPEN_PACKETS + 5, OPEN_PACKETS + 24])
def test_a_real_sigint_while_the_sdk_waits_for_a_status(tmp_path, packet, python_sigint):
    """SIGINT sent by the emulator as it receives the packet: the host is inside txRxPacket."""
    seq = load_sequence(write_sequence(tmp_path, IDS))
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    with DynamixelEmulator(IDS, time_scale=SCALE) as emu:
        emu.at_packet(packet, lambda: os.kill(os.getpid(), signal.SIGINT))
        with pytest.raises(KeyboardInterrupt):
            with DynamixelBus(emu.port, ids=IDS, profile_velocity=0) as bus:
                run_sequence(seq, bus, time_scale=SCALE)
                threading.Event().wait(5)  # the signal is on its way; never reached
        assert_all_off(emu)


def test_a_real_sigint_during_the_shutdown_is_held_until_every_servo_is_off(
    tmp_path, python_sigint
):
    seq = load_sequence(write_sequence(tmp_path, IDS))
    with DynamixelEmulator(IDS, time_scale=SCALE) as emu:
        # the shutdown's SyncWrite is packet RUN_PACKETS + 1; then each servo is read back
        emu.at_packet(RUN_PACKETS + 2, lambda: os.kill(os.getpid(), signal.SIGINT))
        with pytest.raises(KeyboardInterrupt):
            with DynamixelBus(emu.port, ids=IDS, profile_velocity=0) as bus:
                run_sequence(seq, bus, time_scale=SCALE)
        assert emu.received >= RUN_PACKETS + 1 + len(IDS)  # every servo was read back
        assert_all_off(emu)
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_a_second_ctrl_c_during_the_shutdown_does_not_stop_it(tmp_path, monkeypatch):
    seq = load_sequence(write_sequence(tmp_path, IDS))
    with DynamixelEmulator(IDS, time_scale=SCALE) as emu:
        first = CtrlC(monkeypatch, OPEN_PACKETS + 10, "in flight")
        with pytest.raises(KeyboardInterrupt):
            with DynamixelBus(emu.port, ids=IDS, profile_velocity=0) as bus:
                try:
                    run_sequence(seq, bus, time_scale=SCALE)
                finally:
                    assert first.fired
                    # the user presses Ctrl-C again on the shutdown's first packets
                    monkeypatch.undo()
                    second = CtrlC(monkeypatch, 1, "in flight")
                    CtrlC(monkeypatch, 2, "mid reply")
        monkeypatch.undo()
        assert second.fired
        assert_all_off(emu)


def test_ctrl_c_with_a_servo_that_cannot_be_reached_names_it(tmp_path, monkeypatch):
    seq = load_sequence(write_sequence(tmp_path, IDS))
    with DynamixelEmulator(IDS, time_scale=SCALE) as emu:
        hook = CtrlC(monkeypatch, OPEN_PACKETS + 6, "in flight")
        # servo 2 stops answering (its cable came loose) as the Ctrl-C comes
        emu.at_packet(OPEN_PACKETS + 6, lambda: emu.drop_status(2, 10**6))
        with pytest.raises(TorqueOffError) as info:
            with DynamixelBus(emu.port, ids=IDS, profile_velocity=0) as bus:
                run_sequence(seq, bus, time_scale=SCALE)
        assert hook.fired
        message = str(info.value)
        assert message.startswith(
            "interrupted (Ctrl-C); torque off could not be confirmed on servo 2 "
        )
        assert info.value.servos == [2]
        assert isinstance(info.value.__cause__, KeyboardInterrupt)
        emu.servos[2].drop = 0
        # it did get the shutdown's SyncWrite (no status is sent to that): the error
        # only says it could not be confirmed
        assert_all_off(emu)


def test_an_absent_servo_enables_no_torque_at_all(tmp_path, capsys):
    seq = write_sequence(tmp_path, [1, 7])
    (tmp_path / "l.csv").write_text("the log of an earlier run\n")
    with DynamixelEmulator([1, 2]) as emu:
        code = main(["drive", str(seq), "--port", emu.port, "--log", str(tmp_path / "l.csv")])
        err = capsys.readouterr().err.strip()
        assert code == 2
        assert err.count("\n") == 0
        assert "servo 7 did not answer a ping" in err and emu.port in err
        assert "no torque was enabled" in err
        assert_all_off(emu)
        # a run that never began writes no log: the earlier one is kept as it was
        assert (tmp_path / "l.csv").read_text() == "the log of an earlier run\n"
        assert not list(tmp_path.glob(".oc-*"))
        # servo 1 never had its torque enabled: its goal was never moved either
        assert emu.servos[1].value(11) == 3  # still in position mode: nothing configured
        # the same through the library, with two missing servos named at once
        with pytest.raises(DriveError, match="servos 7, 9 did not answer"):
            DynamixelBus(emu.port, ids=[1, 7, 2, 9]).open()
        assert_all_off(emu)


def test_a_servo_left_on_by_an_earlier_run_is_switched_off_when_another_is_missing(tmp_path):
    with DynamixelEmulator([1, 2]) as emu:
        emu.servos[2].table[64] = 1
        with pytest.raises(DriveError, match="servo 7"):
            DynamixelBus(emu.port, ids=[2, 7]).open()
        assert_all_off(emu)


def test_a_servo_that_stops_answering_mid_run_is_named_and_the_others_are_off(tmp_path):
    seq = load_sequence(write_sequence(tmp_path, IDS))
    with DynamixelEmulator(IDS, time_scale=SCALE) as emu:
        emu.at_packet(OPEN_PACKETS + 9, lambda: emu.drop_status(3, 10**6))
        with pytest.raises(TorqueOffError) as info:
            with DynamixelBus(emu.port, ids=IDS, profile_velocity=0, retries=1) as bus:
                run_sequence(seq, bus, tmp_path / "log.csv", time_scale=SCALE)
        message = str(info.value)
        assert message.startswith("servo 3: no status packet (timeout) after 2 attempts")
        assert "torque off could not be confirmed on servo 3" in message
        assert info.value.servos == [3]
        emu.servos[3].drop = 0
        assert_all_off(emu)  # servo 3 got the SyncWrite, but could not confirm it
    note = r"^# stopped at t = [0-9.]+ s: servo 3: no status packet \(timeout\)"
    rows = assert_valid_log(tmp_path / "log.csv", IDS, stopped=note)
    assert 0 < len(rows) <= len(IDS) * 4  # the cycles before the fault


@pytest.mark.parametrize("servo", [1, 3])
def test_an_overload_status_stops_the_run_at_once(tmp_path, capsys, servo):
    seq = write_sequence(tmp_path, IDS)
    log = tmp_path / "log.csv"
    with DynamixelEmulator(IDS) as emu:
        emu.at_packet(OPEN_PACKETS + 10, lambda: emu.report_overload(servo))
        code = main(["drive", str(seq), "--port", emu.port, "--log", str(log)])
        err = capsys.readouterr().err.strip()
        assert code == 2 and err.count("\n") == 0
        assert f"servo {servo}: hardware error: overload (sync read)" in err
        assert_all_off(emu)
    rows = assert_valid_log(log, IDS, stopped=rf"servo {servo}: hardware error: overload")
    # the overload came with the 5th sync read: that reading already saw the alert
    assert 0 < len(rows) <= len(IDS) * 4


def test_an_overload_in_the_library_raises_a_hardware_error_and_stops_all(tmp_path):
    with DynamixelEmulator(IDS) as emu:
        with DynamixelBus(emu.port, ids=IDS, profile_velocity=0) as bus:
            bus.read()
            emu.report_overload(2)
            with pytest.raises(HardwareError, match="servo 2: hardware error: overload"):
                bus.read()
            # already off before the with block ends
            assert [emu.servos[i].table[64] for i in IDS] == [0, 0, 0]
        assert_all_off(emu)
        # a servo still in alarm when the bus opens: refused, nothing enabled
        with pytest.raises(HardwareError, match=r"servo 2: hardware error: overload \(ping\)"):
            DynamixelBus(emu.port, ids=IDS).open()
        assert_all_off(emu)
        # rebooting clears it
        emu.servos[2].table[70] = 0
        emu.servos[2].overload = False
        with DynamixelBus(emu.port, ids=IDS) as bus:
            assert bus.read_value(2, 64, 1) == 1


@pytest.mark.parametrize("packet", [OPEN_PACKETS - 2, OPEN_PACKETS + 7])
def test_a_lost_port_is_one_line_naming_it(tmp_path, capsys, packet):
    seq = write_sequence(tmp_path, IDS)
    log = tmp_path / "log.csv"
    port = tmp_path / "ttyUSB0"  # a link that goes with the device (as under /dev/serial/)
    with DynamixelEmulator(IDS) as emu:
        port.symlink_to(emu.port)
        emu.at_packet(packet, lambda: (port.unlink(), emu.unplug()))
        code = main(["drive", str(seq), "--port", str(port), "--log", str(log)])
        err = capsys.readouterr().err.strip()
    assert code == 2 and err.count("\n") == 0
    assert err.startswith(f"origami-cad: error: port {port} was lost ")
    # nothing can reach the servos any more, and the message says so
    assert f"torque off could not be confirmed on servos 1, 2, 3 on port {port}" in err
    assert "cannot be reopened" in err
    if packet > OPEN_PACKETS:
        assert all(emu.servos[i].table[64] == 1 for i in IDS)  # truly unreachable
        assert 0 < len(assert_valid_log(log, IDS)) <= len(IDS) * 3


def test_a_port_that_comes_back_is_reopened_to_switch_every_servo_off(tmp_path):
    """A USB adapter re-enumerated under the same udev link (/dev/serial/by-id/...)."""
    seq = load_sequence(write_sequence(tmp_path, IDS))
    link = tmp_path / "ttyUSB-servos"
    with DynamixelEmulator(IDS, time_scale=SCALE) as emu:
        replug_at(emu, link, OPEN_PACKETS + 11)
        with pytest.raises(PortLostError, match=f"port {link} was lost"):
            with DynamixelBus(str(link), ids=IDS, profile_velocity=0) as bus:
                run_sequence(seq, bus, time_scale=SCALE)
        assert_all_off(emu)


def test_faults_leave_a_valid_log_up_to_the_fault(tmp_path):
    seq = load_sequence(write_sequence(tmp_path, IDS))
    faults = {
        "crc": lambda emu: emu.corrupt_status(2, 1),
        "timeout": lambda emu: emu.drop_status(1, 3),
    }
    for name, fault in faults.items():
        log = tmp_path / f"{name}.csv"
        with DynamixelEmulator(IDS, time_scale=SCALE) as emu:
            emu.at_packet(OPEN_PACKETS + 14, lambda emu=emu, fault=fault: fault(emu))
            with pytest.raises(DriveError, match=r"CRC error|no status packet"):
                with DynamixelBus(emu.port, ids=IDS, profile_velocity=0) as bus:
                    run_sequence(seq, bus, log, time_scale=SCALE)
            assert_all_off(emu)
        why = assert_valid_log(log, IDS, stopped=r"^# stopped at .*(CRC error|no status packet)")
        assert 0 < len(why) <= len(IDS) * 6, name
    # a stall
    log = tmp_path / "stall.csv"
    with DynamixelEmulator(IDS, time_scale=SCALE, load_turns={2: 0.5}) as emu:
        with pytest.raises(StallError, match="servo 2: current 1500 mA"):
            with DynamixelBus(emu.port, ids=IDS, profile_velocity=0, current_limit_ma=1000) as bus:
                run_sequence(seq, bus, log, time_scale=SCALE)
        assert_all_off(emu)
    rows = assert_valid_log(log, IDS, stopped=r"^# stopped at .*: servo 2: current 1500 mA")
    assert 0 < len(rows) < len(IDS) * 31
    # Ctrl-C between cycles: the log has every finished cycle
    log = tmp_path / "ctrl-c.csv"

    def interrupt(t, targets, state):
        if t >= 10 / RATE - 1e-9:
            raise KeyboardInterrupt

    with DynamixelEmulator(IDS, time_scale=SCALE) as emu:
        with pytest.raises(KeyboardInterrupt):
            with DynamixelBus(emu.port, ids=IDS, profile_velocity=0) as bus:
                run_sequence(seq, bus, log, time_scale=SCALE, progress=interrupt)
        assert_all_off(emu)
    rows = assert_valid_log(log, IDS, stopped=r"^# stopped at t = 0\.2 s: interrupted \(Ctrl-C\)$")
    assert len(rows) == len(IDS) * 11
    assert float(rows[-1]["t_s"]) == pytest.approx(10 / RATE)


def test_the_log_is_never_the_sequence_and_never_a_folder(tmp_path, capsys):
    seq = write_sequence(tmp_path, IDS)
    before = seq.read_bytes()
    code = main(["drive", str(seq), "--dry-run", "--log", str(seq)])
    assert code == 2
    assert "the output would overwrite the input" in capsys.readouterr().err
    assert seq.read_bytes() == before
    (tmp_path / "folder").mkdir()
    assert main(["drive", str(seq), "--dry-run", "--log", str(tmp_path / "folder")]) == 2
    (tmp_path / "file").write_text("x")
    assert main(["drive", str(seq), "--dry-run", "--log", str(tmp_path / "file" / "l.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and "is a folder" in err[0] and "is a file, not a folder" in err[1]


# ---------------------------------------------------------------- generic serial protocol
def motors_over_the_wire(port: str, ids) -> dict[int, bool]:
    """Whether each motor of a line-protocol board is enabled (``R``: mA > 0), fresh connection."""
    out = {}
    with serial.Serial(port, 115200, timeout=1.0) as ser:
        for i in ids:
            ser.reset_input_buffer()
            ser.write((frame(f"R {i}") + "\n").encode())
            reply = unframe(ser.readline().decode()).split()
            assert reply[:3] == ["OK", "R", str(i)]
            out[i] = float(reply[4]) > 0
    return out


def assert_motors_off(emu: SerialEmulator) -> None:
    ids = list(emu.device.enabled)
    assert motors_over_the_wire(emu.port, ids) == dict.fromkeys(ids, False)
    assert not any(emu.device.enabled.values())


class SerialCtrlC:
    """Raise KeyboardInterrupt in pyserial at line ``line``: before it is written, or after."""

    def __init__(self, monkeypatch, line: int, phase: str) -> None:
        self.line, self.phase, self.writes, self.fired = line, phase, 0, False
        write = serial.Serial.write
        hook = self

        def write_line(ser, data):
            hook.writes += 1
            due = not hook.fired and hook.writes == hook.line
            if due and hook.phase == "before write":
                hook.fired = True
                raise KeyboardInterrupt
            n = write(ser, data)
            if due and hook.phase == "in flight":
                hook.fired = True
                raise KeyboardInterrupt
            return n

        monkeypatch.setattr(serial.Serial, "write", write_line)


SERIAL_OPEN_LINES = len(IDS)
SERIAL_RUN_LINES = SERIAL_OPEN_LINES + 2 * len(IDS) * (round(CYCLE * RATE) + 1)


@pytest.mark.parametrize("phase", ["before write", "in flight"])
@pytest.mark.parametrize(
    "line", [1, SERIAL_OPEN_LINES + 1, SERIAL_OPEN_LINES + 5, 40, SERIAL_RUN_LINES - 1]
)
def test_serial_ctrl_c_anywhere_leaves_every_motor_off(tmp_path, monkeypatch, line, phase):
    seq = load_sequence(write_sequence(tmp_path, IDS))
    with SerialEmulator(IDS) as emu:
        hook = SerialCtrlC(monkeypatch, line, phase)
        with pytest.raises(KeyboardInterrupt):
            with SerialBus(emu.port, ids=IDS) as bus:
                run_sequence(seq, bus, time_scale=SCALE)
        assert hook.fired
        monkeypatch.undo()
        assert_motors_off(emu)


def test_serial_stale_reply_of_an_interrupted_command_is_skipped(monkeypatch):
    with SerialEmulator(IDS) as emu:
        with SerialBus(emu.port, ids=IDS) as bus:
            bus.set_turns({1: 0.5})
            hook = SerialCtrlC(monkeypatch, 1, "in flight")
            with pytest.raises(KeyboardInterrupt):
                bus._ask("R 2", 2)  # its reply arrives late
            assert hook.fired
            monkeypatch.undo()
            emu.device.position[3] = 1.25
            assert bus.read()[3][0] == pytest.approx(1.25)
        assert_motors_off(emu)


def test_serial_absent_motor_lost_port_and_stall(tmp_path, capsys):
    seq = write_sequence(tmp_path, [1, 7])
    with SerialEmulator([1, 2]) as emu:
        log = tmp_path / "absent.csv"
        argv = ["drive", str(seq), "--port", emu.port, "--protocol", "serial", "--log", str(log)]
        code = main(argv)
        err = capsys.readouterr().err.strip()
        assert code == 2 and err.count("\n") == 0
        assert "motor 7" in err and "no motor was enabled" in err
        assert_motors_off(emu)
    assert not log.exists() and not list(tmp_path.glob(".oc-*"))  # never began: no log
    seq = write_sequence(tmp_path, IDS)
    log = tmp_path / "serial.csv"
    port = tmp_path / "ttyACM0"
    with SerialEmulator(IDS) as emu:
        port.symlink_to(emu.port)
        emu.at_packet(SERIAL_OPEN_LINES + 20, lambda: (port.unlink(), emu.unplug()))
        code = main(
            ["drive", str(seq), "--port", str(port), "--protocol", "serial", "--log", str(log)]
        )
        err = capsys.readouterr().err.strip()
    assert code == 2 and err.count("\n") == 0
    assert err.startswith(f"origami-cad: error: port {port} was lost")
    assert "motors 1, 2, 3" in err and "may still be on" in err
    assert len(assert_valid_log(log, IDS)) == len(IDS) * 3  # no retries in this protocol
    # a stall: the board reports 60 mA for a moving motor
    with SerialEmulator(IDS) as emu:
        with pytest.raises(StallError, match="motor 1: current 60 mA exceeds the limit of 50"):
            with SerialBus(emu.port, ids=IDS, current_limit_ma=50) as bus:
                bus.set_turns({1: 2.0})
                bus.read()
        assert_motors_off(emu)


def test_serial_port_that_comes_back_is_reopened(tmp_path):
    seq = load_sequence(write_sequence(tmp_path, IDS))
    link = tmp_path / "ttyACM-board"
    with SerialEmulator(IDS) as emu:
        replug_at(emu, link, SERIAL_OPEN_LINES + 8)
        with pytest.raises(PortLostError, match=f"port {link} was lost"):
            with SerialBus(str(link), ids=IDS) as bus:
                run_sequence(seq, bus, time_scale=SCALE)
        assert_motors_off(emu)


# ---------------------------------------------------------------- sequence files
BAD_SEQUENCES = [
    ("mapping = [[0.0, 0.0], [1.0, 20.0]]", "mapping = [[0.0, 0.0], [1.0, nan]]", "'mapping'"),
    ("mapping = [[0.0, 0.0], [1.0, 20.0]]", "mapping = [[0.0, 0.0], [1.0, inf]]", "'mapping'"),
    (
        "mapping = [[0.0, 0.0], [1.0, 20.0]]",
        "mapping = [[0.0, 0.0], [1e300, 20.0]]",
        "finite numbers within",
    ),
    ("mapping = [[0.0, 0.0], [1.0, 20.0]]", "mapping = [[0.0, 0.0], [1.0, 1e300]]", "'mapping'"),
    ("mapping = [[0.0, 0.0], [1.0, 20.0]]", "mapping = [[0.0, -5.0], [1.0, 20.0]]", "'mapping'"),
    ("mapping = [[0.0, 0.0], [1.0, 20.0]]", "mapping = [[0.0, 0.0], [true, 20.0]]", "'mapping'"),
    ("mapping = [[0.0, 0.0], [1.0, 20.0]]", 'mapping = [[0.0, 0.0], ["1", 20.0]]', "'mapping'"),
    ("mapping = [[0.0, 0.0], [1.0, 20.0]]", "mapping = 5", "'mapping'"),
    ("t = 0.3", "t = nan", "key 't'"),
    ("t = 0.3", "t = inf", "key 't'"),
    ("t = 0.6", "t = 1e300", "key 't'"),
    ("t = 0.6", "t = 0.2", "#3: key 't'"),
    ("p = [0.5, 0.5, 0.5]", "p = [0.5, nan, 0.5]", "key 'p'"),
    ("p = [0.5, 0.5, 0.5]", "p = [0.5, 1e300, 0.5]", "key 'p': item 1 is not a finite"),
    ("p = [0.5, 0.5, 0.5]", "p = [0.5, 0.5]", "key 'p'"),
    ("p = [0.5, 0.5, 0.5]", "turns = [0.5, 1e300, 0.5]", "key 'turns': item 1 is not a"),
    ("p = [0.5, 0.5, 0.5]", "contraction = [0.5, inf, 0.5]", "key 'contraction'"),
    ("id = 2", "id = 1", "#2: key 'id': servo id 1 is already used by [[tsa]] #1"),
    ("id = 2", "id = 2.0", "#2: key 'id'"),
    ("id = 2", "id = true", "#2: key 'id'"),
    ("id = 2", "id = 999", "#2: key 'id'"),
    ("id = 2", "id = -1", "#2: key 'id'"),
    ("length = 120.0", "length = 1e300", "key 'length'"),
    ("length = 120.0", "length = nan", "key 'length'"),
    ("radius = 0.6", "radius = 1e-300", "key 'radius'"),
    ("max_helix_angle = 75.0", "max_helix_angle = inf", "key 'max_helix_angle'"),
    ('name = "tsa 2"', 'name = "evil\\nline"', "key 'name'"),
    ("rate = 50.0", "rate = inf", "[sequence]: key 'rate'"),
    ("rate = 50.0", "rate = 1e9", "[sequence]: key 'rate'"),
    ("rate = 50.0", "rate = 0", "[sequence]: key 'rate'"),
    ("rate = 50.0", "rate = 50.0\nrepeat = 1000000000000", "[sequence]: key 'repeat'"),
    ("rate = 50.0", "rate = 50.0\nrepeat = 1000000", "command cycles"),
    ("rate = 50.0", "rate = 50.0\ncurrent_limit = nan", "key 'current_limit'"),
    ("rate = 50.0", "rate = 50.0\ncurrent_limit = 0", "key 'current_limit'"),
]


@pytest.mark.parametrize(("old", "new", "where"), BAD_SEQUENCES)
def test_bad_sequence_values_are_refused_naming_file_table_and_key(tmp_path, old, new, where):
    path = write_sequence(tmp_path, IDS)
    text = path.read_text()
    # change the value in the second [[tsa]] / keyframe where there is one
    at = text.find(old, text.find(old) + 1) if text.count(old) > 1 else text.find(old)
    assert at >= 0, old
    path.write_text(text[:at] + new + text[at + len(old) :])
    with pytest.raises(DriveError) as info:
        load_sequence(path)
    message = str(info.value)
    assert message.startswith(str(path)) and where in message
    assert "\n" not in message


def test_bad_dcqc_mapping_files_are_refused(tmp_path):
    path = write_sequence(tmp_path, [1])
    text = path.read_text().replace("mapping = [[0.0, 0.0], [1.0, 20.0]]", 'mapping = "r.json"')
    path.write_text(text)
    cases = {
        '{"states": {"p": [0.0, NaN], "tsa_length_mm": [[0.0], [5.0]]}}': "finite numbers",
        '{"states": {"p": [0.0, "1"], "tsa_length_mm": [[0.0], [5.0]]}}': "finite numbers",
        '{"states": {"p": [0.0], "tsa_length_mm": [[0.0]]}}': "fewer than two",
        '{"states": {"p": [], "tsa_length_mm": []}}': "not a dcqc.json",
        '{"states": {"p": [0.0, 0.5], "tsa_length_mm": [[0.0]]}}': "not a dcqc.json",
        "[" * 100_000: "not a dcqc.json",
    }
    for content, expected in cases.items():
        (tmp_path / "r.json").write_text(content)
        with pytest.raises(DriveError, match=expected) as info:
            load_sequence(path)
        assert "[[tsa]] #1: key 'mapping'" in str(info.value)


@pytest.mark.parametrize("value", [0, -1, float("nan"), float("inf"), 1e300, True, "2"])
def test_time_scale_must_be_finite_and_positive(tmp_path, value, capsys):
    with pytest.raises(DriveError, match="time_scale must be a number in"):
        check_time_scale(value)
    seq = load_sequence(write_sequence(tmp_path, IDS))
    with SerialEmulator(IDS) as emu, SerialBus(emu.port, ids=IDS) as bus:
        with pytest.raises(DriveError):
            run_sequence(seq, bus, time_scale=value)
        assert emu.received == len(IDS)  # pings only: no goal was sent
    if not isinstance(value, bool | str):
        code = main(["drive", str(tmp_path / "seq.toml"), "--dry-run", "--speed", str(value)])
        assert code == 2
        err = capsys.readouterr().err  # finite but out of range: the job; NaN, inf: argparse
        assert "speed must be a number in [0.1, 1000]" in err or "expected a finite number" in err


def test_emulator_and_bus_refuse_repeated_or_bad_ids():
    for make in (DynamixelEmulator, SerialEmulator):
        with pytest.raises(OrigamiCadError, match=r"servo IDs \[1\] are given more than once"):
            make([1, 1])
    with pytest.raises(DriveError, match="repeat"):
        DynamixelBus("/dev/null", ids=[3, 3])
    with pytest.raises(DriveError, match=r"outside 0\.\.252"):
        DynamixelBus("/dev/null", ids=[254])
    with pytest.raises(DriveError, match="time scale"):
        DynamixelEmulator([1], time_scale=float("nan"))
    for bus in (DynamixelBus, SerialBus):
        for baudrate in (0, -9600, 57600.5, True):
            with pytest.raises(DriveError, match="baud rate must be a positive whole number"):
                bus("/dev/null", baudrate, ids=[1])


MUTATIONS = [
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "0",
    "-1",
    "9223372036854775807",
    "1e-320",
    '"x"',
    "true",
    "[]",
    "[[]]",
    "[1]",
    "{}",
    "{a = 1}",
    "[nan, nan]",
    '"/dev/zero"',
    '"../../../etc/passwd"',
    "[[0, 0], [1, 1e308]]",
    "[[0, 0], [0, 1]]",
    "[[1.0, 0.0], [0.0, 1.0]]",
    "2024-01-01",
    "[0.5, 0.5, 0.5]",
]


def test_mutated_sequence_files_load_or_fail_with_one_line(tmp_path):
    """400 seeded mutations of a good file: a usable sequence or one clear error, nothing else."""
    base = write_sequence(tmp_path, IDS).read_text().splitlines()
    rng = random.Random(2026)
    path = tmp_path / "mutant.toml"
    for _ in range(400):
        lines = list(base)
        for _ in range(rng.randint(1, 3)):
            i = rng.choice([k for k, line in enumerate(lines) if " = " in line])
            lines[i] = f"{lines[i].split(' = ')[0]} = {rng.choice(MUTATIONS)}"
        path.write_text("\n".join(lines) + "\n")
        try:
            seq = load_sequence(path)
        except OrigamiCadError as exc:
            assert "\n" not in str(exc) and str(exc).startswith(str(path))
            continue
        for t in (0.0, seq.cycle / 3, seq.cycle * seq.repeat):
            turns = seq.turns_at(t)
            assert all(abs(turns[tsa.dxl_id]) <= tsa.max_turns for tsa in seq.tsas)
        assert 0 < seq.rate <= 1000 and seq.cycle * seq.repeat * seq.rate <= 1_000_000
