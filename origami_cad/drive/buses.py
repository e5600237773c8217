"""The servo buses by name: each protocol's bus class and its emulator, in one registry.

=============  ===========================  ================================
name           bus                          emulator
=============  ===========================  ================================
``dynamixel``  :class:`.DynamixelBus`       :class:`.DynamixelEmulator`
``serial``     :class:`.SerialBus`          :class:`.SerialEmulator`
=============  ===========================  ================================

A new kind of motor board is one module (its :class:`~origami_cad.drive.bus.ServoBus`
subclass and its emulator) and one line of :data:`BUSES`. A name that is not in the
registry is a :class:`~origami_cad.errors.DriveError` naming the known ones.

Examples
--------
>>> with open_emulator("serial", [1, 2]) as emu:
...     with open_bus("serial", emu.port, ids=[1, 2]) as bus:
...         print(type(bus).__name__, bus.ids)
SerialBus [1, 2]
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from origami_cad.drive.bus import ServoBus
from origami_cad.drive.dynamixel import DynamixelBus
from origami_cad.drive.emulator import DynamixelEmulator, SerialEmulator
from origami_cad.drive.load import LoadCurve
from origami_cad.drive.serial import SerialBus
from origami_cad.errors import DriveError

__all__ = ["BUSES", "BusType", "bus_type", "open_bus", "open_emulator"]


@dataclass(frozen=True)
class BusType:
    """One protocol: its bus class, its emulator and the options a sequence runs with.

    Attributes
    ----------
    bus : type
        The :class:`~origami_cad.drive.bus.ServoBus` subclass, called as
        ``bus(port, baudrate, ids, max_turns=..., current_limit_ma=..., **options)``.
    emulator : callable
        Makes the emulator, ``emulator(ids, time_scale=...)`` (a context manager with a
        ``port``): servos on a pseudo-terminal that speak the protocol.
    options : mapping
        Keywords of ``bus`` for running a sequence (e.g. Dynamixel's ``profile_velocity
        = 0``: the sequence sets the speed).
    emulated_options : mapping
        Keywords of ``bus`` on its emulator (e.g. more time for the emulator's replies).
    carries_loads : bool
        Whether ``emulator`` takes ``loads`` (a :class:`~origami_cad.drive.load.LoadCurve`
        per servo ID, torque against turns, N mm).
    """

    bus: type[ServoBus]
    emulator: Callable[..., Any]
    options: Mapping[str, Any] = field(default_factory=dict)
    emulated_options: Mapping[str, Any] = field(default_factory=dict)
    carries_loads: bool = False


#: The registry: protocol name -> :class:`BusType`. A new bus is one line here.
BUSES: dict[str, BusType] = {
    "dynamixel": BusType(
        DynamixelBus,
        DynamixelEmulator,
        options={"profile_velocity": 0},
        emulated_options={"reply_slack": 0.5},
        carries_loads=True,
    ),
    "serial": BusType(SerialBus, SerialEmulator),
}


def bus_type(name: str) -> BusType:
    """The :class:`BusType` registered as ``name``; :class:`DriveError` naming the known ones."""
    try:
        return BUSES[name]
    except (KeyError, TypeError):
        raise DriveError(f"protocol must be one of {', '.join(BUSES)}, got {name!r}") from None


def open_bus(
    name: str,
    port: str,
    baudrate: int = 57600,
    ids: Iterable[int] = (1,),
    *,
    max_turns: dict | float | None = None,
    current_limit_ma: float | None = None,
    emulated: bool = False,
    **options: Any,
) -> ServoBus:
    """The servo bus of protocol ``name`` on ``port`` (not yet open: use it in ``with``).

    Parameters
    ----------
    name : str
        A protocol of :data:`BUSES` (``"dynamixel"``, ``"serial"``).
    port : str
        Serial port path, or an emulator's pseudo-terminal.
    baudrate : int
        Baud rate, bits/s.
    ids : iterable of int
        Servo IDs, each once, in 0..252.
    max_turns : dict or float, optional
        Safety limit per servo ID (or for all), turns.
    current_limit_ma : float, optional
        Current above which a servo is stopped as stalled, mA.
    emulated : bool
        The port is the protocol's emulator (its ``emulated_options`` apply).
    **options
        More keywords of the bus class, over the protocol's ``options``.

    Returns
    -------
    ServoBus

    Raises
    ------
    DriveError
        For an unknown protocol (naming the known ones) or bad IDs, baud rate or limits.
    """
    kind = bus_type(name)
    extra = {**kind.options, **(kind.emulated_options if emulated else {}), **options}
    return kind.bus(
        port, baudrate, ids, max_turns=max_turns, current_limit_ma=current_limit_ma, **extra
    )


def open_emulator(
    name: str,
    ids: Iterable[int],
    *,
    time_scale: float = 1.0,
    loads: Mapping[int, LoadCurve] | None = None,
) -> Any:
    """The emulator of protocol ``name`` with servos ``ids`` (a context manager with ``port``).

    ``time_scale`` speeds its clock up (> 0); ``loads`` (torque against turns per servo ID,
    N mm) is carried by the protocols that can (``carries_loads``), ignored by the others.
    """
    kind = bus_type(name)
    extra = {"loads": dict(loads or {})} if kind.carries_loads else {}
    return kind.emulator(list(ids), time_scale=time_scale, **extra)
