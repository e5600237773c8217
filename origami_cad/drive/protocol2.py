"""Dynamixel Protocol 2.0 packets: CRC-16, byte stuffing, encoding and parsing.

Used by the emulator (the device side). The host side is ``dynamixel_sdk``
itself, so tests exercise the real SDK against these packets on the wire.

Examples
--------
>>> instruction_packet(1, PING).hex(" ").upper()  # the test vector of the protocol
'FF FF FD 00 01 03 00 01 19 4E'
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "CLEAR",
    "HEADER",
    "PING",
    "READ",
    "REBOOT",
    "STATUS",
    "SYNC_READ",
    "SYNC_WRITE",
    "WRITE",
    "Packet",
    "crc16",
    "instruction_packet",
    "parse_packets",
    "status_packet",
    "stuff",
    "unstuff",
]

HEADER = b"\xff\xff\xfd\x00"
PING, READ, WRITE, REBOOT, CLEAR = 0x01, 0x02, 0x03, 0x08, 0x10
SYNC_READ, SYNC_WRITE, STATUS = 0x82, 0x83, 0x55
BROADCAST = 0xFE


def _crc_table() -> list[int]:
    table = []
    for i in range(256):
        crc = i << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) if crc & 0x8000 else (crc << 1)
        table.append(crc & 0xFFFF)
    return table


_TABLE = _crc_table()


def crc16(data: bytes) -> int:
    """CRC-16 of Protocol 2.0: polynomial 0x8005, initial value 0, not reflected."""
    crc = 0
    for byte in data:
        crc = ((crc << 8) ^ _TABLE[((crc >> 8) ^ byte) & 0xFF]) & 0xFFFF
    return crc


def stuff(payload: bytes) -> bytes:
    """Byte stuffing: every ``FF FF FD`` in the payload gets an extra ``FD``."""
    return payload.replace(b"\xff\xff\xfd", b"\xff\xff\xfd\xfd")


def unstuff(payload: bytes) -> bytes:
    """Undo :func:`stuff`."""
    return payload.replace(b"\xff\xff\xfd\xfd", b"\xff\xff\xfd")


def _packet(dxl_id: int, body: bytes) -> bytes:
    body = stuff(body)
    length = len(body) + 2
    head = HEADER + bytes([dxl_id, length & 0xFF, length >> 8]) + body
    crc = crc16(head)
    return head + bytes([crc & 0xFF, crc >> 8])


def instruction_packet(dxl_id: int, instruction: int, params: bytes = b"") -> bytes:
    """An instruction packet (host to device)."""
    return _packet(dxl_id, bytes([instruction]) + params)


def status_packet(dxl_id: int, error: int = 0, params: bytes = b"") -> bytes:
    """A status packet (device to host): instruction 0x55, then the error byte."""
    return _packet(dxl_id, bytes([STATUS, error]) + params)


@dataclass(frozen=True)
class Packet:
    """A parsed packet: id, instruction, unstuffed parameters, whether its CRC matched."""

    dxl_id: int
    instruction: int
    params: bytes
    crc_ok: bool


def parse_packets(buffer: bytearray) -> list[Packet]:
    """Take every complete packet out of ``buffer`` (which keeps any partial tail)."""
    out = []
    while True:
        start = buffer.find(HEADER)
        if start < 0:
            # keep a possible partial header at the end
            del buffer[: max(0, len(buffer) - 3)]
            return out
        if start:
            del buffer[:start]
        if len(buffer) < 7:
            return out
        length = buffer[5] | (buffer[6] << 8)
        total = 7 + length
        if len(buffer) < total:
            return out
        raw = bytes(buffer[:total])
        del buffer[:total]
        crc = raw[-2] | (raw[-1] << 8)
        body = unstuff(raw[7:-2])
        out.append(Packet(raw[4], body[0] if body else -1, body[1:], crc16(raw[:-2]) == crc))
