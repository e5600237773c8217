"""Driving hardware: servo TSAs over Dynamixel Protocol 2.0 or a generic serial protocol.

Everything runs without hardware against :mod:`origami_cad.drive.emulator`.
"""

from origami_cad.drive.dynamixel import DynamixelBus, max_turns_for, ticks_to_turns, turns_to_ticks
from origami_cad.drive.emulator import DynamixelEmulator, SerialEmulator
from origami_cad.drive.errors import DriveError, StallError
from origami_cad.drive.serial import SerialBus

__all__ = [
    "DriveError",
    "DynamixelBus",
    "DynamixelEmulator",
    "SerialBus",
    "SerialEmulator",
    "StallError",
    "max_turns_for",
    "ticks_to_turns",
    "turns_to_ticks",
]
