"""Driving hardware: servo TSAs over Dynamixel Protocol 2.0 or a generic serial protocol.

The buses are registered by name in :mod:`origami_cad.drive.buses` (:func:`open_bus`).

Everything runs without hardware against :mod:`origami_cad.drive.emulator`.
"""

from origami_cad.drive.buses import BUSES, BusType, bus_type, open_bus, open_emulator
from origami_cad.drive.dynamixel import DynamixelBus, max_turns_for, ticks_to_turns, turns_to_ticks
from origami_cad.drive.emulator import DynamixelEmulator, SerialEmulator
from origami_cad.drive.errors import (
    DriveError,
    HardwareError,
    PortLostError,
    StallError,
    TorqueOffError,
)
from origami_cad.drive.serial import SerialBus

__all__ = [
    "BUSES",
    "BusType",
    "DriveError",
    "DynamixelBus",
    "DynamixelEmulator",
    "HardwareError",
    "PortLostError",
    "SerialBus",
    "SerialEmulator",
    "StallError",
    "TorqueOffError",
    "bus_type",
    "max_turns_for",
    "open_bus",
    "open_emulator",
    "ticks_to_turns",
    "turns_to_ticks",
]
