"""Driver layer: sync-write plus sync-read round trips for four servos at 1 Mbps (emulator)."""

from __future__ import annotations

from clock import Clock

from origami_cad.drive import DynamixelBus, DynamixelEmulator


def run() -> list[tuple[str, float, str]]:
    ids = [1, 2, 3, 4]
    with DynamixelEmulator(ids) as emu, DynamixelBus(emu.port, 1_000_000, ids) as bus:
        bus.read()
        n = 300
        clock = Clock()
        for k in range(n):
            bus.set_turns({i: 0.01 * (k % 10) for i in ids})
            bus.read()
        dt, cpu = clock.lap()
    return [
        ("sync write + sync read round trips per second, 4 servos, 1 Mbps", n / dt, ""),
        ("  milliseconds per round trip (wall)", 1000 * dt / n, ""),
        ("  CPU milliseconds per round trip (this process)", 1000 * cpu / n, ""),
    ]
