"""Hardware commands: ``emulate`` and ``drive`` (``sequence``, which writes what ``drive``
runs, is in :mod:`.sequence`)."""

from __future__ import annotations

import time
from pathlib import Path

from origami_cad._signals import finishing
from origami_cad.commands._base import Command, Option, Outputs, register, wrote
from origami_cad.errors import DriveError, OptionsError

__all__ = ["parse_ids", "protocols"]


def parse_ids(text: str) -> list[int]:
    """``--ids 1,2``: comma-separated servo IDs (``ValueError`` naming the form)."""
    if not all(v.strip().isdigit() for v in text.split(",")):
        raise ValueError(f"expected comma-separated IDs, got {text!r}")
    return [int(v) for v in text.split(",")]


def protocols() -> tuple[str, ...]:
    """The servo buses' names (:data:`origami_cad.drive.BUSES`, read when needed)."""
    from origami_cad.drive import BUSES

    return tuple(BUSES)


_PROTOCOL = Option("protocol", help="servo bus (dynamixel: Dynamixel Protocol 2.0; serial: "
                   "the small serial protocol)", default="dynamixel",
                   choices=protocols)  # fmt: skip


@register
class Emulate(Command):
    """Emulate servos on a pseudo-terminal until Ctrl-C, or for ``seconds`` (0: forever)."""

    NAME, ARGS = "emulate", ("ids",)
    OPTIONS = (
        Option("ids", "object", "servo IDs, comma-separated (default 1)", default=(1,),
               parse=parse_ids, metavar="ID[,ID...]"),
        Option("seconds", "float", "how long to run (0: until Ctrl-C)", "s", 0.0, min=0,
               max=1e7),
        _PROTOCOL,  # checked last: a test stops the checks of the others by a bad protocol
    )  # fmt: skip

    def run(self, a) -> Outputs:
        from origami_cad.drive import open_emulator

        ids = list(a.ids)
        if len(set(ids)) != len(ids) or not ids or any(not 0 <= i <= 252 for i in ids):
            raise DriveError(f"servo IDs must be distinct and in 0..252, got {ids}")
        with open_emulator(a.protocol, ids) as emu:
            a.echo(f"{a.protocol} emulator with servos {ids} on {emu.port}")
            a.echo(f"connect with --port {emu.port}; Ctrl-C to stop")
            deadline = time.monotonic() + a.seconds if a.seconds else None
            while deadline is None or time.monotonic() < deadline:
                time.sleep(0.1)
        return Outputs()


def _start_bus(stack, seq, a, emulate: dict | None):
    """The servo bus of a sequence: on ``a.port``, or on a new emulator given ``emulate``
    (``time_scale`` and ``load_scale``: its servos carry the sequence's loads)."""
    from origami_cad.drive import open_bus, open_emulator

    port, limits = a.port, {t.dxl_id: t.max_turns for t in seq.tsas}
    if emulate is not None:
        loads = seq.loads(emulate["load_scale"])
        emu = open_emulator(a.protocol, seq.ids, time_scale=emulate["time_scale"], loads=loads)
        port = stack.enter_context(emu).port
    bus = open_bus(
        a.protocol, port, a.baudrate, seq.ids, max_turns=limits,
        current_limit_ma=seq.current_limit, emulated=emulate is not None,
    )  # fmt: skip
    return stack.enter_context(bus)


def _drive_stopped(exc: BaseException, plot, names: dict[int, str], done=None) -> BaseException:
    """After a run stopped early: the ``plot`` of its readings (``done``: all of them, when
    only the shutdown failed), so log and plot stay one set; and the error to raise (a
    stall names the TSA, not only its servo ID)."""
    from origami_cad.drive import StallError
    from origami_cad.viz.drive_plots import save_drive_png

    ran = done or getattr(exc, "drive_log", None) or getattr(exc.__cause__, "drive_log", None)
    if plot and ran is not None:  # a run that never began has no log, and no plot
        with finishing():
            save_drive_png(ran, plot, names)
    if isinstance(exc, StallError) and names.get(exc.servo):
        return StallError(f"{names[exc.servo]}: {exc}", exc.servo)
    return exc


def _drive_numbers(seq, done, loads, names) -> list[tuple[str, str]]:
    import numpy as np

    # the largest lag is where a command jumps (to the first keyframe, a gait's step);
    # how closely the servos follow shows in the lag of 95 % of the readings
    lag, typical = float(done.lag.max()), float(np.percentile(done.lag, 95))
    peak = ", ".join(f"{names[i]} {c.peak:.1f}" for i, c in loads.items())
    return [
        ("cycle / readings", f"{seq.cycle:g} s / {done.target.size}"),
        (
            "lag of the servos behind their commands: 95 % of readings / largest",
            f"{typical:.3f} / {lag:.3f} turns",
        ),
        ("maximum commanded twist", f"{done.target.max():.2f} turns"),
        *([("peak load per servo (N mm)", peak)] if loads else []),
        ("largest current", f"{abs(done.current).max():.0f} mA"),
    ]


#: ``drive``'s dry-run options when not given: time acceleration, loads' factor
DRY_RUN_DEFAULTS = {"speed": 8.0, "load_scale": 1.0}


@register
class Drive(Command):
    """Run a TSA sequence on servos at ``port`` (or an emulator: ``dry_run``), CSV ``log``.

    ``speed`` is the time acceleration of a dry run; its emulated Dynamixel servos carry
    each TSA's load (the torque a simulation predicts, N mm) times ``load_scale``, so
    a load past a servo's stall torque or the sequence file's current limit (mA) stops
    that servo by name. ``plot`` adds a PNG of the commanded and measured turns. Torque goes
    off on exit, error and Ctrl-C.
    """

    NAME, INPUTS, PROGRESS, ARGS = "drive", ("sequence",), "servo_table", ("sequence", "log")
    OPTIONS = (
        Option("port", help="serial port of the servos (e.g. /dev/ttyUSB0)"),
        _PROTOCOL,
        Option("baudrate", "int", "bits per second", default=57600, min=1, max=100_000_000),
        Option("dry_run", "flag", "start the emulator and drive it"),
        Option("speed", "float", "dry run: times faster than real time", min=0.1,
               max=1000),
        Option("load_scale", "float", "dry run: the emulated loads times this", min=0,
               max=1e6),
        Option("log", help="CSV log, written as it runs (none unless given)", metavar="FILE"),
        Option("plot", help="also a PNG of commanded and measured turns", metavar="FILE"),
    )  # fmt: skip

    @classmethod
    def library_defaults(cls) -> dict:
        """A dry run's defaults (given only with ``dry_run``)."""
        return DRY_RUN_DEFAULTS

    def prepare(self, a) -> None:
        """Refuse a run with no servos, or options the run would ignore (a port on a dry
        run, a dry run's options on servos), in one line naming them; then fill in the
        defaults and check the outputs."""
        if not a.dry_run and not a.port:
            raise DriveError("give the servos' port, or use a dry run on the emulator")
        if a.dry_run and a.port is not None:
            raise OptionsError(
                f"--port {a.port or repr(a.port)}: a dry run drives the emulator; "
                "give one of the two"
            )
        given = [n for n in DRY_RUN_DEFAULTS if getattr(a, n) is not None]
        if given and not a.dry_run:
            flags = ", ".join(f"--{n.replace('_', '-')}" for n in given)
            raise OptionsError(f"{flags}: used only by a dry run (--dry-run)")
        for name, value in DRY_RUN_DEFAULTS.items():
            setattr(a, name, value if getattr(a, name) is None else getattr(a, name))
        super().prepare(a)

    def outputs(self, a):
        return [p for p in (a.log, a.plot) if p], []

    def formats(self, a):
        return [(a.plot, (".png",), "the drive plot")] if a.plot is not None else []

    def run(self, a) -> Outputs:
        import contextlib

        import numpy as np

        from origami_cad.drive.sequence import load_sequence, run_sequence
        from origami_cad.viz.drive_plots import save_drive_png

        seq = load_sequence(a.sequence)
        emulate = {"time_scale": a.speed, "load_scale": a.load_scale} if a.dry_run else None
        scale = a.speed if a.dry_run else 1.0
        names, done = {t.dxl_id: t.name for t in seq.tsas}, None
        try:
            with contextlib.ExitStack() as stack:
                bus = _start_bus(stack, seq, a, emulate)
                done = run_sequence(seq, bus, a.log, time_scale=scale, progress=a.progress)
        except BaseException as exc:  # the plot shows what ran; a stall names the TSA
            raise _drive_stopped(exc, a.plot, names, done) from exc.__cause__
        if a.plot:
            with finishing():  # the log is complete: its plot follows, even past a Ctrl-C
                save_drive_png(done, a.plot, names)
        files = [Path(f) for f in (a.log, a.plot) if f]
        loads = seq.loads(a.load_scale if a.dry_run else 1.0)
        caption = "Commanded (dashed) and measured (solid) turns and current per TSA"
        lag = float(np.percentile(done.lag, 95))
        return Outputs(
            files=files,
            images=[(Path(a.plot), caption)] if a.plot else [],
            numbers=_drive_numbers(seq, done, loads, names),
            messages=[
                f"ran {seq.repeat} x {seq.cycle:g} s on servos {seq.ids}"
                f"{' (dry run)' if a.dry_run else ''}: {done.target.size} readings, "
                f"lag {lag:.3f} turns (95 % of readings), {float(done.lag.max()):.3f} at most",
                *map(wrote, files),
                *([] if a.log else ["note: no log was kept; --log FILE keeps every reading"]),
            ],
            result=done,
        )
