"""The driver layer against the emulator: real dynamixel_sdk packets on a pseudo-terminal."""

from __future__ import annotations

import csv
import re
import time
from pathlib import Path

import dynamixel_sdk as sdk
import numpy as np
import pytest
from conftest import ink, panel_frames

from origami_cad.cli import main
from origami_cad.drive import (
    DriveError,
    DynamixelBus,
    DynamixelEmulator,
    SerialBus,
    SerialEmulator,
    StallError,
)
from origami_cad.drive.protocol2 import (
    PING,
    SYNC_READ,
    SYNC_WRITE,
    crc16,
    instruction_packet,
    parse_packets,
    status_packet,
    stuff,
    unstuff,
)
from origami_cad.drive.sequence import load_sequence, run_sequence
from origami_cad.drive.serial import crc8, frame, unframe

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
IDS = [1, 2, 3, 4]


def test_protocol_test_vector_crc_and_stuffing():
    assert instruction_packet(1, PING) == bytes.fromhex("FFFFFD0001030001194E")
    payload = b"\x01\xff\xff\xfd\x02"
    assert stuff(payload) == b"\x01\xff\xff\xfd\xfd\x02"
    assert unstuff(stuff(payload)) == payload
    buf = bytearray(b"\x00\x13" + status_packet(3, 0, b"\xff\xff\xfd") + b"\xff\xff")
    packets = parse_packets(buf)
    assert len(packets) == 1 and packets[0].crc_ok and packets[0].params == b"\x00\xff\xff\xfd"
    assert buf == bytearray(b"\xff\xff")  # a partial header stays for the next read
    # the SDK's own CRC agrees with ours
    raw = list(instruction_packet(7, 0x02, b"\x84\x00\x04\x00"))
    ph = sdk.PacketHandler(2.0)
    assert ph.updateCRC(0, raw, len(raw) - 2) == crc16(bytes(raw[:-2]))


@pytest.fixture(autouse=True)
def patient_sdk(monkeypatch):
    """Wait up to 102 ms for a status packet, not 34 ms (see test_drive_safety.py)."""
    monkeypatch.setattr(sdk.port_handler, "LATENCY_TIMER", 50)


@pytest.fixture()
def emulator():
    with DynamixelEmulator(IDS, load_turns={3: 2.0}) as emu:
        yield emu


def test_ping_model_and_mode_switch(emulator):
    with DynamixelBus(emulator.port, ids=IDS) as bus:
        assert bus.models == {i: 1200 for i in IDS}  # XL330-M288
        for i in IDS:
            assert bus.read_value(i, 11, 1) == 4  # extended position mode
            assert bus.read_value(i, 64, 1) == 1  # torque on
        # EEPROM items cannot be written with torque on: the servo refuses, and we say which
        with pytest.raises(DriveError, match=r"servo 2: access error .*torque off"):
            bus._write(2, 11, 1, 3)
    for i in IDS:  # leaving the block turned torque off
        assert emulator.servos[i].table[64] == 0


def test_sync_write_and_read_multi_turn_and_negative(emulator):
    targets = {1: 1.5, 2: -2.25, 3: 0.75, 4: -0.125}
    with DynamixelBus(emulator.port, ids=IDS, profile_velocity=0) as bus:
        bus.set_turns(targets)
        state = bus.wait(targets, tolerance=1e-3)
        assert emulator.instructions[SYNC_WRITE] == 1  # one packet for all four servos
        assert emulator.instructions[SYNC_READ] >= 1
        for i, t in targets.items():
            assert state[i][0] == pytest.approx(t, abs=1e-3)
            assert emulator.servos[i].value(116) == round(t * 4096)


def test_turn_limits_are_enforced_before_anything_is_sent(emulator):
    with DynamixelBus(emulator.port, ids=IDS, max_turns={1: 3.0}) as bus:
        with pytest.raises(DriveError, match=r"servo 1: 3\.5 turns exceeds its limit of 3 turns"):
            bus.set_turns({1: 3.5, 2: 0.5})
        with pytest.raises(DriveError, match="servo 2: 300 turns exceeds its limit of 256"):
            bus.set_turns({2: 300.0})
        bus.read()  # a round trip: every packet sent before it has been handled
        assert emulator.instructions[SYNC_WRITE] == 0
        bus.clear_multi_turn(4)


def test_a_stalling_tsa_is_stopped(emulator):
    with DynamixelBus(emulator.port, ids=IDS, current_limit_ma=1000, profile_velocity=0) as bus:
        bus.set_turns({3: 4.0})
        with pytest.raises(StallError, match="servo 3: current 1500 mA exceeds the limit"):
            deadline = time.monotonic() + 5
            while time.monotonic() < deadline:
                bus.read()
                time.sleep(0.01)
        assert emulator.servos[3].table[64] == 0  # torque off on the stalled servo
        assert emulator.servos[1].table[64] == 1


def test_dropped_status_is_retried_then_fails_with_the_servo_named(emulator):
    with DynamixelBus(emulator.port, ids=IDS, retries=2) as bus:
        emulator.drop_status(2, 2)
        assert bus.read_value(2, 11, 1) == 4  # two drops, third attempt answers
        emulator.drop_status(2, 3)
        with pytest.raises(DriveError, match=r"servo 2: no status packet \(timeout\) after 3"):
            bus.read_value(2, 11, 1)
        emulator.drop_status(4, 5)
        with pytest.raises(DriveError, match="servo 4: no status packet"):
            bus.read()


def test_a_late_status_packet_is_a_timeout_unless_the_bus_allows_slack():
    """A status packet 150 ms late (a loaded machine running the emulator) is a missing
    servo for the SDK's 34 ms timeout, and is read when the bus allows 0.5 s of slack."""
    for slack, ok in ((0.0, False), (0.5, True)):
        with (
            DynamixelEmulator([1]) as emu,
            DynamixelBus(emu.port, ids=[1], retries=0, reply_slack=slack) as bus,
        ):
            emu.at_packet(emu.received + 1, lambda: time.sleep(0.15))
            if ok:
                assert bus.read_value(1, 11, 1) == 4  # extended position mode
            else:
                with pytest.raises(DriveError, match=r"servo 1: no status packet"):
                    bus.read_value(1, 11, 1)
    with pytest.raises(DriveError, match="reply slack"):
        DynamixelBus("/dev/null", ids=[1], reply_slack=-1.0)


def test_corrupted_crc_and_hardware_error_are_reported(emulator):
    with DynamixelBus(emulator.port, ids=IDS) as bus:
        emulator.corrupt_status(1, 1)
        with pytest.raises(DriveError, match="servo 1: CRC error"):
            bus.read_value(1, 132, 4)
        emulator.report_overload(4)
        with pytest.raises(DriveError, match="servo 4: hardware error: overload"):
            bus.read_value(4, 132, 4)


def test_port_that_cannot_be_opened():
    with pytest.raises(DriveError, match="port /dev/does-not-exist cannot be opened"):
        DynamixelBus("/dev/does-not-exist", ids=[1]).open()


def test_generic_serial_protocol_happy_path_and_checksum_error():
    assert unframe(frame("OK R 1 2.5000 60")) == "OK R 1 2.5000 60"
    assert crc8(b"123456789") == 0xF4  # CRC-8/SMBUS check value
    with pytest.raises(DriveError, match="checksum error"):
        unframe("OK S*00")
    with SerialEmulator([1, 2]) as emu, SerialBus(emu.port, ids=[1, 2], max_turns=5.0) as bus:
        assert bus.models == {1: 9000, 2: 9000}
        bus.set_turns({1: 0.4, 2: -0.3})
        time.sleep(0.15)
        state = bus.read()
        assert state[1][0] == pytest.approx(0.4) and state[2][0] == pytest.approx(-0.3)
        with pytest.raises(DriveError, match="servo 1: 9 turns exceeds its limit of 5"):
            bus.set_turns({1: 9.0})
        emu.device.corrupt_replies = 1
        with pytest.raises(DriveError, match="motor 1: checksum error"):
            bus.read()
        # a command with a bad checksum gets ERR 1 from the board
        assert emu.device.handle("R 1*00").startswith("ERR 1 checksum")
        assert emu.device.handle(frame("X 1")).startswith("ERR 2")
        assert emu.device.handle(frame("G 9 1.0")).startswith("ERR 3")


def test_crawler_gait_dry_run_with_csv_log(tmp_path, capsys):
    log = tmp_path / "crawler.csv"
    plot = tmp_path / "crawler.png"
    code = main(
        [
            "drive",
            str(EXAMPLES / "crawler_gait.toml"),
            "--dry-run",
            "--speed",
            "32",
            "--log",
            str(log),
            "--plot",
            str(plot),
        ]
    )
    assert code == 0
    rows = list(csv.DictReader(log.open()))
    seq = load_sequence(EXAMPLES / "crawler_gait.toml")
    steps = int(seq.cycle * seq.rate) + 1
    assert len(rows) == 4 * steps
    assert {int(r["id"]) for r in rows} == set(IDS)
    by_time = [r for r in rows if float(r["t_s"]) == 16.0]
    front = seq.tsas[0].turns(seq.tsas[0].contraction(0.306))
    assert float(by_time[0]["target_turns"]) == pytest.approx(front)
    # the emulated servos follow their commands closely (at 32 x real time a scheduling
    # hiccup of the loaded test machine shows as lag: judge the bulk, not the worst row)
    lags = np.array([abs(float(r["target_turns"]) - float(r["measured_turns"])) for r in rows])
    assert np.median(lags) < 0.25 and np.mean(lags < 1.0) > 0.9
    covered, _ = ink(plot)
    assert 0.02 < covered < 0.3  # curves, axes and labels: not blank, not black
    assert len(panel_frames(plot)) == len(IDS)  # a panel per servo
    assert "dry run" in capsys.readouterr().out


def test_sequence_checks(tmp_path):
    text = (EXAMPLES / "crawler_gait.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("p = [0.306, 0.306, 0.167, 0.167]", "p = [0.306, 0.306, 0.167]"))
    with pytest.raises(DriveError, match="expected 4 numbers"):
        load_sequence(bad)
    bad.write_text(text.replace("max_helix_angle = 75", "max_helix_angle = 18", 1))
    with pytest.raises(
        DriveError, match=r"\[\[keyframe\]\] #2: key 'p' \(t = 6 s\): servo 1 \(front left\)"
    ):
        load_sequence(bad)
    # a mapping past the strands' length is named as the number written, not its numpy repr
    bad.write_text(text.replace("length = 24 ", "length = 5 ", 1))
    with pytest.raises(DriveError, match=r"item \d+: contraction 5\.\d+ mm is not within \[0, 5\)"):
        load_sequence(bad)
    # a rate too low to command every keyframe (1e-300 Hz ran one command)
    bad.write_text(text.replace("rate = 10 ", "rate = 1e-300 ", 1))
    with pytest.raises(DriveError, match=r"key 'rate': 1e-300 Hz .* the 5 s between two keyframes"):
        load_sequence(bad)
    seq = load_sequence(EXAMPLES / "arm_fold.toml")
    with (
        DynamixelEmulator([1], time_scale=40) as emu,
        DynamixelBus(emu.port, ids=[1], profile_velocity=0) as bus,
    ):
        done = run_sequence(seq, bus, time_scale=40)
    assert done.target.shape == (len(done.t), 1)
    assert done.target.max() == pytest.approx(
        seq.tsas[0].turns(seq.tsas[0].contraction(seq.tsas[0].mapping[-1, 0]))
    )


def test_protocol_page_examples_carry_true_checksums():
    page = (Path(__file__).resolve().parents[1] / "docs" / "serial-protocol.md").read_text()
    lines = [ln[2:] for ln in page.splitlines() if ln.startswith(("> ", "< "))]
    assert len(lines) >= 6
    for line in lines:
        text, _, _ = line.rpartition("*")
        assert frame(text) == line


def test_sequence_mapping_from_a_dcqc_result(tmp_path):
    import json

    from origami_cad.pattern.design import load_design
    from origami_cad.strings import load_route, simulate_dcqc

    design = load_design(EXAMPLES / "miura_6x4.toml")
    result = simulate_dcqc(design, load_route(EXAMPLES / "miura_route.toml", design.pattern))
    (tmp_path / "dcqc.json").write_text(json.dumps(result.to_dict()))
    text = (EXAMPLES / "arm_fold.toml").read_text()
    start = text.index("mapping = ")
    end = text.index("\n", start)
    text = text[:start] + 'mapping = "dcqc.json"' + text[end:]
    text = re.sub(r"p = \[0\.3\d*\]", "p = [0.3]", text)  # the arm's fold range end
    (tmp_path / "seq.toml").write_text(text)
    seq = load_sequence(tmp_path / "seq.toml")
    mapping = seq.tsas[0].mapping
    assert mapping[0, 0] == pytest.approx(result.p[0])
    assert np.all(np.diff(mapping[:, 0]) > 0) and np.all(np.diff(mapping[:, 1]) >= 0)
    taken = result.tsa_length[:, 0] - result.tsa_length[0, 0]
    assert mapping[-1, 1] == pytest.approx(max(taken))


# --------------------------------------------------------------------------- simulated loads
# examples/crawler_gait.toml is the crawl job's gait_sequence.toml: each TSA's ``load`` is
# the torque the simulated crawl needed of its servo, which dry runs apply.


def _first_overloaded(seq, scale: float, limit_ma: float) -> int:
    """The servo whose scaled load first draws more than ``limit_ma`` (XL330-M288 model:
    idle or running current plus torque over the torque constant, stall beyond 520 N mm)."""
    from origami_cad.drive.emulator import STALL_TORQUE

    stall, per_ma = STALL_TORQUE["XL330-M288"], STALL_TORQUE["XL330-M288"] / 1500.0
    t = np.linspace(0.0, seq.cycle, 3201)
    first = {}
    for i, curve in seq.loads(scale).items():
        torque = np.array([curve.at(x) for x in t])
        over = (torque >= stall) | (5.0 + torque / per_ma > limit_ma)
        if over.any():
            first[i] = t[np.argmax(over)]
    assert first, "no servo is overloaded"
    return min(first, key=first.get)


def test_the_derived_gait_runs_under_its_simulated_load(tmp_path):
    from origami_cad.commands import execute
    from origami_cad.drive.emulator import STALL_TORQUE

    seq = load_sequence(EXAMPLES / "crawler_gait.toml")
    loads = seq.loads()
    assert sorted(loads) == IDS and all(0.5 < c.peak < 20.0 for c in loads.values())  # N mm
    done = execute(
        "drive", EXAMPLES / "crawler_gait.toml", tmp_path / "log.csv", dry_run=True, speed=8.0,
        baudrate=1_000_000,
    ).result  # fmt: skip
    assert len(done.t) == int(seq.cycle * seq.rate) + 1  # it ran to the end
    # each servo draws the current its load asks (torque / torque constant, above idle)
    per_ma = STALL_TORQUE["XL330-M288"] / 1500.0
    for j, i in enumerate(done.ids):
        expected = np.array([loads[i].at(t) for t in done.t]) / per_ma
        residual = done.current[:, j] - expected  # idle (5 mA) or running (60 mA)
        fits = (np.abs(residual - 5.0) < 4.0) | (np.abs(residual - 60.0) < 4.0)
        assert fits.mean() > 0.9, (i, residual)
    # the CSV (streamed) holds the same readings as the columnar log
    rows = list(csv.DictReader((tmp_path / "log.csv").open()))
    assert [float(r["current_mA"]) for r in rows] == done.current.ravel().tolist()


def test_an_overloaded_gait_stalls_the_servo_that_carries_it(tmp_path, capsys):
    """The same gait with every simulated load x 100 (a robot 100 times as heavy)."""
    from origami_cad.drive.sequence import run_sequence

    seq = load_sequence(EXAMPLES / "crawler_gait.toml")
    stalling = _first_overloaded(seq, 100.0, seq.current_limit)
    name = {t.dxl_id: t.name for t in seq.tsas}[stalling]
    with DynamixelEmulator(IDS, time_scale=32.0, loads=seq.loads(100.0)) as emu:
        bus = DynamixelBus(
            emu.port, 1_000_000, IDS, current_limit_ma=seq.current_limit, profile_velocity=0
        )
        with pytest.raises(StallError, match=rf"servo {stalling}: current \d+ mA") as info:
            with bus:
                run_sequence(seq, bus, tmp_path / "a.csv", time_scale=32.0)
        assert info.value.servo == stalling
        assert all(s.table[64] == 0 for s in emu.servos.values())  # torque off everywhere
    # through the command line: exit code 2, the TSA named, the log kept up to the stall
    log = tmp_path / "b.csv"
    args = ["drive", str(EXAMPLES / "crawler_gait.toml"), "--dry-run", "--speed", "32"]
    assert main([*args, "--load-scale", "100", "--log", str(log), "--baudrate", "1000000"]) == 2
    err = capsys.readouterr().err
    assert f"{name}: servo {stalling}: current" in err and "Traceback" not in err
    rows = list(csv.DictReader(log.open()))
    assert 0 < len(rows) < 4 * int(seq.cycle * seq.rate)
    # with the simulated loads as they are, nothing stalls: the XL330 has a wide margin
    assert max(c.peak for c in seq.loads().values()) < 0.05 * 520.0


def test_load_curves_in_a_sequence_are_checked(tmp_path):
    text = (EXAMPLES / "crawler_gait.toml").read_text()
    start = text.index("load = [[0, ")
    line = text[start : text.index("\n", start)]
    cases = [
        ("load = [[0, 1.0], [40, 2.0]]", "past the cycle's 32 s"),
        ("load = [[1, 1.0], [2, 2.0]]", "times must start at 0 s and increase"),
        ("load = [[0, 1.0], [2, -2.0]]", "item 1: torque -2 N mm is negative"),
        ("load = [[0, 1.0]]", "key 'load': expected a list of at least 2"),
    ]
    for new, message in cases:
        bad = tmp_path / "bad.toml"
        bad.write_text(text.replace(line, new))
        with pytest.raises(DriveError, match=re.escape(message)):
            load_sequence(bad)


def test_a_serial_dry_run_keeps_up_with_its_time_scale(tmp_path):
    # the line-protocol board's emulator lives as fast as the sequence is run: at 16 x real
    # time its motors follow their commands as closely as the Dynamixel emulator's do
    logs = {}
    for protocol in ("serial", "dynamixel"):
        log = tmp_path / f"{protocol}.csv"
        args = ["drive", str(EXAMPLES / "crawler_gait.toml"), "--dry-run", "--speed", "16"]
        assert main([*args, "--protocol", protocol, "--log", str(log)]) == 0
        rows = list(csv.DictReader(log.open()))
        logs[protocol] = np.array(
            [abs(float(r["target_turns"]) - float(r["measured_turns"])) for r in rows]
        )
    target_span = max(float(r["target_turns"]) for r in rows)
    assert target_span > 2.0  # the motors really turned
    # (the gait's steps jump the command by 1.6 turns: the worst rows lag by that much in both;
    # before the board's emulator scaled its time, a tenth of the rows lagged by over 1 turn)
    for lags in logs.values():
        assert np.percentile(lags, 90) < 0.1
