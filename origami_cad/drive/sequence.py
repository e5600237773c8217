"""Motion sequences for TSAs: keyframes in fold ratio, contraction or turns, run on a bus.

Sequence file (TOML)::

    [sequence]
    repeat = 2                  # gait cycles
    rate = 20.0                 # Hz, command and read rate
    current_limit = 1000.0      # mA, optional: stop a stalling TSA
    [[tsa]]
    id = 1                      # servo ID
    name = "front left"
    length = 100.0              # mm, strands (onboard TSA model)
    radius = 0.5                # mm
    max_helix_angle = 80.0      # deg
    mapping = [[0.0, 0.0], [0.5, 6.0], [1.0, 14.0]]   # [p, contraction mm] ...
    # or: mapping = "out/route/dcqc.json"  (fold ratio against string taken by the TSA)
    load = [[0.0, 1.2], [8.0, 4.5], [16.0, 2.0]]      # optional: [t s, N mm] over a cycle
    [[keyframe]]
    t = 0.0                     # s
    p = [0.0, 0.0]              # one value per TSA (or contraction = [...] mm, turns = [...])

Targets are interpolated linearly between keyframes; fold ratios become
contractions through each TSA's mapping and contractions become motor turns
through the TSA model (never beyond its maximum twist). A TSA's optional ``load``
is the torque its strings put on the servo over one cycle (``crawl`` writes it from the
simulated gait); a dry run's emulated servo carries it (:mod:`origami_cad.drive.load`).
The run's log is columnar (:class:`DriveLog`) and streamed to CSV row by row.
"""

from __future__ import annotations

import contextlib
import csv
import io
import itertools
import json
import math
import os
import signal
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad._args import Arg, brief_value, checked
from origami_cad._fileio import GrowingFile
from origami_cad._names import one_line, toml_string, visible
from origami_cad._toml import Table, finite_toml, load_toml
from origami_cad.drive.errors import DriveError, describe_exit, hold_ctrl_c
from origami_cad.drive.load import LoadCurve
from origami_cad.errors import OutputError, StringsError
from origami_cad.strings.tsa import TSAParams, onboard_angle

__all__ = [
    "LOG_FIELDS",
    "MAX_DURATION",
    "MAX_STEPS",
    "SEQUENCE_LAYOUTS",
    "DriveLog",
    "Keyframe",
    "Sequence",
    "SequenceLayout",
    "SequenceTSA",
    "check_time_scale",
    "dump_sequence",
    "load_sequence",
    "load_sequence_table",
    "note_stop",
    "run_sequence",
    "stop_reason",
]


@dataclass(frozen=True)
class SequenceTSA:
    """One TSA of a sequence: servo, TSA model and fold-ratio-to-contraction mapping (mm)."""

    dxl_id: int
    name: str
    tsa: TSAParams
    mapping: np.ndarray  # (k, 2): fold ratio, contraction mm (increasing)
    load: np.ndarray | None = None  # (k, 2): time s over one cycle, torque N mm
    comment: str = ""  # where the mapping comes from: a comment line above its table

    def contraction(self, p: float) -> float:
        """String contraction (mm) that brings the structure to fold ratio ``p``."""
        lo, hi = self.mapping[0, 0], self.mapping[-1, 0]
        if not lo - 1e-12 <= p <= hi + 1e-12:
            raise DriveError(
                f"servo {self.dxl_id} ({self.name}): fold ratio {p:g} is outside "
                f"its mapping [{lo:g}, {hi:g}]"
            )
        return float(np.interp(p, self.mapping[:, 0], self.mapping[:, 1]))

    def turns(self, contraction: float) -> float:
        """Motor turns giving ``contraction`` mm (TSA model inverse)."""
        try:
            theta = onboard_angle(
                contraction,
                self.tsa.length,
                self.tsa.radius,
                math.radians(self.tsa.max_helix_angle),
            )
        except StringsError as exc:
            raise DriveError(f"servo {self.dxl_id} ({self.name}): {exc}") from None
        return float(theta) / (2 * math.pi)

    @property
    def max_turns(self) -> float:
        return 0.99 * self.tsa.max_theta() / (2 * math.pi)


@dataclass(frozen=True)
class Keyframe:
    """Targets at time ``t`` (s): ``kind`` is ``p``, ``contraction`` (mm) or ``turns``."""

    t: float
    kind: str
    values: tuple[float, ...]


@dataclass(frozen=True)
class Sequence:
    """A loaded sequence: TSAs, keyframes, repeats and rates."""

    tsas: tuple[SequenceTSA, ...]
    keyframes: tuple[Keyframe, ...]
    repeat: int = 1
    rate: float = 20.0
    current_limit: float | None = None
    source: Path | None = None  # the file it was read from

    @property
    def cycle(self) -> float:
        """Duration of one cycle, s."""
        return self.keyframes[-1].t

    @property
    def ids(self) -> list[int]:
        return [t.dxl_id for t in self.tsas]

    def loads(self, scale: float = 1.0) -> dict[int, LoadCurve]:
        """Each loaded TSA's torque curve (N mm, repeating every cycle), times ``scale``."""
        return {
            t.dxl_id: LoadCurve(t.load[:, 0], t.load[:, 1] * scale, self.cycle)
            for t in self.tsas
            if t.load is not None
        }

    def turns_at(self, t: float) -> dict[int, float]:
        """Commanded motor turns of every TSA at time ``t`` (s) since the start."""
        local = self.cycle if t >= self.cycle * self.repeat else t % self.cycle
        times = [k.t for k in self.keyframes]
        j = int(np.searchsorted(times, local, side="right")) - 1
        j = min(max(j, 0), len(times) - 2)
        a, b = self.keyframes[j], self.keyframes[j + 1]
        w = 0.0 if b.t == a.t else min(max((local - a.t) / (b.t - a.t), 0.0), 1.0)
        out = {}
        for k, tsa in enumerate(self.tsas):
            out[tsa.dxl_id] = (1 - w) * self._turns(tsa, a, k) + w * self._turns(tsa, b, k)
        return out

    @staticmethod
    def _turns(tsa: SequenceTSA, frame: Keyframe, k: int) -> float:
        v = frame.values[k]
        if frame.kind == "turns":
            return v
        if frame.kind == "p":
            v = tsa.contraction(v)
        return tsa.turns(v)


#: Largest dcqc.json a mapping may name, bytes.
MAX_MAPPING_FILE = 50_000_000
#: Most command/read cycles in one run (about 14 h at 20 Hz).
MAX_STEPS = 1_000_000
#: Longest run, s (``repeat`` x the cycle): a day, at any rate. A dry run takes this
#: divided by its ``--speed``; both limits are checked when the sequence is loaded.
MAX_DURATION = 86_400.0
#: Highest command rate, Hz (a 57600 bps bus manages about 100 Hz).
MAX_RATE = 1000.0


def _finite_number(value: Any) -> bool:
    return (
        not isinstance(value, bool)
        and isinstance(value, int | float)
        and math.isfinite(value)
        and abs(value) < 1e12
    )


def _mapping(t: Table, base: Path, length: float) -> np.ndarray:
    """The ``mapping`` key: ``[[p, contraction_mm], ...]`` or a dcqc.json path, checked."""
    raw = t.data.get("mapping")
    t.used.add("mapping")
    if isinstance(raw, str):
        path = (base / raw).resolve()
        if not path.exists():
            raise t.error("mapping", f"{path}: no such file")
        if not path.is_file():
            raise t.error("mapping", f"{path} is not a regular file")
        if path.stat().st_size > MAX_MAPPING_FILE:
            raise t.error("mapping", f"{path} is larger than {MAX_MAPPING_FILE} bytes")
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
            states = data["states"]  # columns: p (S,), tsa_length_mm (S, strings)
            first = states["tsa_length_mm"][0][0]
            pairs = [
                (p, row[0]) for p, row in zip(states["p"], states["tsa_length_mm"], strict=True)
            ]
        except (ValueError, KeyError, IndexError, TypeError, RecursionError):
            raise t.error("mapping", f"{path} is not a dcqc.json result") from None
        for k, (fold, taken) in enumerate(pairs):
            if not (_finite_number(fold) and _finite_number(taken) and _finite_number(first)):
                raise t.error(
                    "mapping",
                    f"{path}: step {k}: 'p' and 'tsa_length_mm' must be finite numbers, "
                    f"got {fold!r} and {taken!r}",
                )
        arr = np.array([(fold, taken - first) for fold, taken in pairs], dtype=float)
        # keep the strictly increasing part (a DCQC result may pause at a fold ratio)
        keep = np.r_[True, np.diff(arr[:, 0]) > 1e-9]
        arr = arr[keep]
        if len(arr) < 2:
            raise t.error("mapping", f"{path}: fewer than two distinct fold ratios")
    elif isinstance(raw, list):
        arr = np.array(t.pairs("mapping", min_length=2))
    else:
        raise t.error("mapping", "expected [[p, contraction_mm], ...] or a dcqc.json path")
    for k, (fold, contraction) in enumerate(arr.tolist()):  # Python floats: shown as 0.5
        if not (math.isfinite(fold) and 0.0 <= fold <= 1.0):
            raise t.error("mapping", f"item {k}: fold ratio {fold!r} is not within [0, 1]")
        if not (math.isfinite(contraction) and 0.0 <= contraction < length):
            raise t.error(
                "mapping",
                f"item {k}: contraction {contraction!r} mm is not within [0, {length:g}) mm "
                "(the strands' length)",
            )
    if np.any(np.diff(arr[:, 0]) <= 0) or np.any(np.diff(arr[:, 1]) < 0):
        raise t.error("mapping", "fold ratios must increase and contractions must not decrease")
    return arr


def _load(t: Table) -> np.ndarray:
    """The ``load`` key: ``[[t_s, torque_Nmm], ...]``, times from 0 and increasing."""
    arr = np.array(t.pairs("load", min_length=2))
    if arr[0, 0] != 0 or np.any(np.diff(arr[:, 0]) <= 0):
        raise t.error("load", "times must start at 0 s and increase")
    if np.any(arr[:, 1] < 0):
        k = int(np.argmax(arr[:, 1] < 0))
        raise t.error("load", f"item {k}: torque {arr[k, 1]:g} N mm is negative")
    return arr


def _name(t: Table, default: str) -> str:
    name = t.string("name", default)
    if not name.strip() or len(name) > 100 or not visible(name):
        raise t.error("name", f"expected 1-100 printable characters, got {name[:40]!r}")
    return name


def check_time_scale(time_scale: Any, what: str = "time_scale") -> float:
    """``time_scale`` (the CLI's ``--speed``) as a float; :class:`DriveError` unless finite,
    in [0.1, 1000].

    At most 1000: beyond it the emulated servos cannot keep up and the run
    would only measure the host's scheduling; at least 0.1: a run ten times slower than
    real time is the slowest worth watching (1e-300 would never end).
    """
    if (
        isinstance(time_scale, bool)
        or not isinstance(time_scale, int | float)
        or not math.isfinite(time_scale)
        or not 0.1 <= time_scale <= 1000
    ):
        raise DriveError(f"{what} must be a number in [0.1, 1000], got {brief_value(time_scale)}")
    return float(time_scale)


@checked(DriveError, path=Arg("path", optional=False))
def load_sequence(path: str | os.PathLike[str]) -> Sequence:
    """Read a sequence file; errors name the file, table and key."""
    p = Path(path)
    top = Table(load_toml(p, DriveError), str(p), DriveError)
    seq = top.table("sequence", {})
    raw_tsas = top.data.get("tsa")
    raw_frames = top.data.get("keyframe")
    top.used |= {"tsa", "keyframe"}
    top.finish()
    if not isinstance(raw_tsas, list) or not raw_tsas:
        raise DriveError(f"{p}: expected at least one [[tsa]] table")
    if not isinstance(raw_frames, list) or len(raw_frames) < 2:
        raise DriveError(f"{p}: expected at least two [[keyframe]] tables")
    if len(raw_tsas) > 253:
        raise DriveError(f"{p}: {len(raw_tsas)} [[tsa]] tables; a bus holds at most 253 servos")
    if len(raw_frames) > 100_000:
        raise DriveError(f"{p}: {len(raw_frames)} [[keyframe]] tables; at most 100000")
    tsas = _read_tsas(raw_tsas, p)
    frames = _read_keyframes(raw_frames, p, len(tsas))
    given = _sequence_table(seq)
    sequence = Sequence(
        tuple(tsas),
        tuple(frames),
        repeat=given.get("repeat", 1),
        rate=given.get("rate", 20.0),
        current_limit=given.get("current_limit"),
        source=p,
    )
    steps = sequence.cycle * sequence.repeat * sequence.rate
    if steps > MAX_STEPS:
        raise DriveError(
            f"{p} [sequence]: {sequence.repeat} x {sequence.cycle:g} s at {sequence.rate:g} Hz "
            f"is {steps:.3g} command cycles; at most {MAX_STEPS} (lower 'repeat' or 'rate')"
        )
    if sequence.cycle * sequence.repeat > MAX_DURATION:
        raise DriveError(
            f"{p} [sequence]: {sequence.repeat} x {sequence.cycle:g} s is "
            f"{sequence.cycle * sequence.repeat:.4g} s; a run lasts at most {MAX_DURATION:g} s "
            "(MAX_DURATION, a day; lower 'repeat' or the keyframe times)"
        )
    gap = min(b.t - a.t for a, b in itertools.pairwise(frames))
    if sequence.rate * gap < 1.0:
        raise DriveError(
            f"{p} [sequence]: key 'rate': {sequence.rate:g} Hz commands every "
            f"{1.0 / sequence.rate:.3g} s, less often than the {gap:g} s between two "
            "keyframes: a keyframe would never be commanded (raise 'rate')"
        )
    _check_reachable(p, tsas, frames)
    for k, tsa in enumerate(tsas):
        if tsa.load is not None and tsa.load[-1, 0] > sequence.cycle + 1e-9:
            raise DriveError(
                f"{p} [[tsa]] #{k + 1}: key 'load': it runs to {tsa.load[-1, 0]:g} s, "
                f"past the cycle's {sequence.cycle:g} s"
            )
    return sequence


def _sequence_table(seq: Table) -> dict[str, Any]:
    """The keys a ``[sequence]`` table gives (``repeat``, ``rate`` Hz, ``current_limit``
    mA), each checked; a key it does not give is left out."""
    out: dict[str, Any] = {}
    if seq.has("repeat"):
        out["repeat"] = seq.integer("repeat", 1, low=1, high=1_000_000)
    if seq.has("rate"):
        out["rate"] = seq.number("rate", 20.0, low=0, high=MAX_RATE, low_open=True)
    if seq.has("current_limit"):
        out["current_limit"] = seq.number("current_limit", None, low=0, high=100_000, low_open=True)
    seq.finish()
    return out


def load_sequence_table(path: str | os.PathLike[str]) -> dict[str, Any]:
    """The ``[sequence]`` table of a sequence or gait file, checked as :func:`load_sequence`
    checks it: the keys it gives among ``repeat``, ``rate`` (Hz) and ``current_limit``
    (mA); :class:`DriveError` naming the file, table and key otherwise. The rest of the
    file is not read (a gait file for ``crawl`` need not hold ``[[tsa]]`` tables).

    >>> load_sequence_table("examples/crawler_gait.toml")
    {'repeat': 1, 'rate': 10.0, 'current_limit': 1200.0}
    """
    p = Path(path)
    top = Table(load_toml(p, DriveError), str(p), DriveError)
    seq = top.table("sequence", {})
    return _sequence_table(seq)


def _read_tsas(raw_tsas: list, p: Path) -> list[SequenceTSA]:
    """The ``[[tsa]]`` tables of sequence file ``p``: distinct servo ids, lengths in mm."""
    tsas: list[SequenceTSA] = []
    first_table: dict[int, int] = {}
    for k, item in enumerate(raw_tsas):
        t = Table(item, f"{p} [[tsa]] #{k + 1}", DriveError)
        dxl_id = t.integer("id", low=0, high=252)
        if dxl_id in first_table:
            raise t.error(
                "id", f"servo id {dxl_id} is already used by [[tsa]] #{first_table[dxl_id] + 1}"
            )
        first_table[dxl_id] = k
        length = t.number("length", 100.0, low=0, high=10_000, low_open=True)
        radius = t.number("radius", 0.5, low=0.01, high=100)
        if radius >= length:
            raise t.error("radius", f"{radius:g} mm must be smaller than the length {length:g} mm")
        tsa = SequenceTSA(
            dxl_id=dxl_id,
            name=_name(t, f"tsa {k + 1}"),
            tsa=TSAParams(
                model="onboard",
                length=length,
                radius=radius,
                max_helix_angle=t.number(
                    "max_helix_angle", 80.0, low=0, high=90, low_open=True, high_open=True
                ),
            ),
            mapping=_mapping(t, p.parent, length),
            load=_load(t) if t.has("load") else None,
        )
        t.finish()
        tsas.append(tsa)
    return tsas


def _read_keyframes(raw_frames: list, p: Path, n_tsas: int) -> list[Keyframe]:
    """The ``[[keyframe]]`` tables of sequence file ``p``: one value per TSA, times (s)
    from 0 and increasing.
    """
    frames = []
    for k, item in enumerate(raw_frames):
        t = Table(item, f"{p} [[keyframe]] #{k + 1}", DriveError)
        when = t.number("t", low=0, high=1e7)
        kinds = [name for name in ("p", "contraction", "turns") if t.has(name)]
        if len(kinds) != 1:
            raise DriveError(f"{t.where}: give exactly one of 'p', 'contraction', 'turns'")
        values = t.numbers(kinds[0], length=n_tsas)
        t.finish()
        frames.append(Keyframe(when, kinds[0], tuple(values)))
    if frames[0].t != 0:
        raise DriveError(f"{p} [[keyframe]] #1: key 't': the first keyframe must be at t = 0")
    for k, (a, b) in enumerate(itertools.pairwise(frames)):
        if b.t <= a.t:
            raise DriveError(
                f"{p} [[keyframe]] #{k + 2}: key 't': {b.t:g} s does not come after the "
                f"previous keyframe's {a.t:g} s (times must increase)"
            )
    return frames


def _check_reachable(p: Path, tsas: list[SequenceTSA], frames: list[Keyframe]) -> None:
    """Raise :class:`DriveError` for a keyframe that asks a servo for more turns than
    its TSA can make (or none it can reach), naming the keyframe, key and servo.
    """
    for k, frame in enumerate(frames):
        where = f"{p} [[keyframe]] #{k + 1}: key '{frame.kind}'"
        for j, tsa in enumerate(tsas):
            try:
                turns = Sequence._turns(tsa, frame, j)
            except DriveError as exc:
                raise DriveError(f"{where} (t = {frame.t:g} s): {exc}") from None
            if not math.isfinite(turns) or abs(turns) > tsa.max_turns:
                raise DriveError(
                    f"{where} (t = {frame.t:g} s) asks servo {tsa.dxl_id} ({tsa.name}) "
                    f"for {turns:.4g} turns, beyond its TSA's {tsa.max_turns:.4g}"
                )


LOG_FIELDS = ("t_s", "id", "target_turns", "measured_turns", "current_mA")


@dataclass
class DriveLog:
    """A driven sequence, columnar: one row per command cycle, one column per servo.

    Attributes
    ----------
    ids : tuple of int
        Servo IDs, the columns' order.
    t : ndarray (S,)
        Sequence time of each command cycle, s.
    target, measured : ndarray (S, n)
        Commanded and read-back motor positions, turns.
    current : ndarray (S, n)
        Present current, mA.
    """

    ids: tuple[int, ...]
    t: np.ndarray
    target: np.ndarray
    measured: np.ndarray
    current: np.ndarray

    @classmethod
    def empty(cls, ids, steps: int) -> DriveLog:
        """A log of ``steps`` command cycles, filled as they run (:meth:`record`)."""
        n = len(ids)
        return cls(tuple(ids), np.zeros(steps), *(np.full((steps, n), np.nan) for _ in range(3)))

    def record(self, k: int, t: float, targets: dict, state: dict) -> list[dict[str, Any]]:
        """Fill cycle ``k`` (time ``t`` s) from the bus; its CSV rows."""
        self.t[k] = t
        for j, i in enumerate(self.ids):
            self.target[k, j] = targets[i]
            self.measured[k, j], self.current[k, j] = state[i]
        return self.rows(k, k + 1)

    def first(self, steps: int) -> DriveLog:
        """The log of the first ``steps`` command cycles (those that ran)."""
        cut = slice(0, steps)
        return DriveLog(
            self.ids, self.t[cut], self.target[cut], self.measured[cut], self.current[cut]
        )

    @property
    def lag(self) -> np.ndarray:
        """How far each servo is behind its command, turns (S, n)."""
        return np.abs(self.target - self.measured)

    def rows(self, start: int = 0, stop: int | None = None) -> list[dict[str, Any]]:
        """The log as CSV rows (:data:`LOG_FIELDS`), one per servo per command cycle."""
        out = []
        for k in range(start, len(self.t) if stop is None else stop):
            for j, i in enumerate(self.ids):
                out.append(
                    {
                        "t_s": round(float(self.t[k]), 6),
                        "id": i,
                        "target_turns": float(self.target[k, j]),
                        "measured_turns": float(self.measured[k, j]),
                        "current_mA": float(self.current[k, j]),
                    }
                )
        return out

    def to_dict(self) -> dict[str, Any]:
        """Plain lists, for JSON."""
        return {
            "ids": list(self.ids),
            "t_s": self.t.tolist(),
            "target_turns": self.target.tolist(),
            "measured_turns": self.measured.tolist(),
            "current_mA": self.current.tolist(),
        }


@contextlib.contextmanager
def _open_log(log, sequence: Sequence):
    """The CSV log (a :class:`~origami_cad._fileio.GrowingFile`), made before anything
    moves and put in place of an old log only when the run begins; None without ``log``."""
    if log is None:
        yield None
        return
    path = Path(log)
    if sequence.source is not None and path.exists():
        with contextlib.suppress(OSError):
            if path.samefile(sequence.source):
                raise DriveError(f"{path}: the log would overwrite the sequence file itself")
    if path.exists() and not (path.is_file() or path.is_char_device() or path.is_fifo()):
        raise DriveError(f"{path}: the log must be a file, not a folder")
    try:
        fh = GrowingFile(path)
    except OSError as exc:
        raise DriveError(f"{path}: the log cannot be written ({exc.strerror or exc})") from None
    with fh:
        yield fh


def _csv_rows(rows: list[dict[str, Any]], header: bool = False) -> str:
    """CSV text of log rows (:data:`LOG_FIELDS`), whole lines, with the header first."""
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=list(LOG_FIELDS))
    if header:
        writer.writeheader()
    writer.writerows(rows)
    return text.getvalue()


@checked(
    DriveError,
    sequence=Arg("object", types=(Sequence,), optional=False),
    log=Arg("path"),
    progress=Arg("callable", length=3),
)
def run_sequence(
    sequence: Sequence,
    bus: Any,
    log: str | os.PathLike[str] | None = None,
    *,
    time_scale: float = 1.0,
    progress: Callable[[float, dict[int, float], dict[int, tuple[float, float]]], None]
    | None = None,
) -> DriveLog:
    """Run a sequence on an open bus; every command and reading goes to the CSV ``log``.

    ``time_scale`` > 1 runs faster than real time (dry runs); it must be
    finite and in (0, 1000]. Returns the columnar log (:class:`DriveLog`).

    The CSV log is written as the run goes, the rows of each reading written whole
    (columns :data:`LOG_FIELDS`), so a run ended by Ctrl-C, a stall, a timeout, a CRC
    or hardware error, a lost port or a full disk leaves a valid CSV up to its last
    reading. It is made (and checked) beside its path before the first command, and
    replaces an old log there only as the first command is sent: a run that never
    began leaves an old log as it was, and no new one. A log path that is the sequence
    file itself is refused. A run that stops early ends the log with a comment saying
    why (:func:`note_stop`), and the exception carries the readings of the cycles that
    ran as ``drive_log`` (a :class:`DriveLog`). A log the disk cannot hold stops the
    run (``WriteRefused``, an ``OutputError``, naming the log).

    ``progress(t, targets, state)`` is called after every reading (``t`` in s); a
    callback with a ``total`` attribute (the servo table of
    :func:`origami_cad.viz.console.servo_table`) first gets the run's duration
    (s) and ``time_scale`` there as ``(duration, time_scale)``, to show how far
    the run is and how long it has left.
    """
    time_scale = check_time_scale(time_scale)
    total = sequence.cycle * sequence.repeat
    if progress is not None and hasattr(progress, "total"):
        progress.total = (total, time_scale)
    period = 1.0 / sequence.rate
    steps = math.floor((total + 1e-9) / period) + 1
    while steps > 1 and (steps - 1) * period > total + 1e-9:
        steps -= 1
    out = DriveLog.empty(sequence.ids, steps)
    with _open_log(log, sequence) as fh:
        if fh is not None:
            fh.write(_csv_rows([], header=True))
        start = time.monotonic()
        t, ran, began = 0.0, 0, False
        try:
            for k in range(steps):
                t = k * period
                delay = start + t / time_scale - time.monotonic()
                if delay > 0:
                    time.sleep(delay)
                targets = sequence.turns_at(t)
                if fh is not None:
                    fh.publish()  # the run begins: its log replaces an old one
                began = True
                bus.set_turns(targets)
                state = bus.read()
                new = out.record(k, round(t, 6), targets, state)
                ran = k + 1
                if fh is not None:
                    fh.write(_csv_rows(new))  # whole rows, or none
                if progress is not None:
                    progress(t, targets, state)
        except BaseException as exc:
            if began:
                exc.drive_log = out.first(ran)  # what ran, for the caller (a plot of it)
            if fh is not None and fh.published:
                with hold_ctrl_c(), contextlib.suppress(OutputError):  # a full disk: no line
                    note_stop(fh, exc, t)
            raise
    return out


def stop_reason(exc: BaseException) -> str:
    """Why a run stopped, in one line naming the servo: the error, or the signal."""
    signum = getattr(exc, "signum", None)
    if signum is not None and signum == getattr(signal, "SIGTERM", None):
        return "terminated (SIGTERM)"
    return describe_exit(exc)


def note_stop(fh, exc: BaseException, t: float | None = None) -> None:
    """End the CSV log ``fh`` with the comment line saying why the run stopped.

    ``# stopped at t = 1.25 s: servo 3: no status packet ...`` (``t``: the sequence
    time of the command cycle that failed, s), or ``# not started: ...`` when no
    command was sent. Readers skip it as a comment (``pandas.read_csv(comment="#")``).
    """
    when = "not started" if t is None else f"stopped at t = {t:g} s"
    fh.write(f"# {when}: {one_line(stop_reason(exc))}\n")
    fh.flush()


@dataclass(frozen=True)
class SequenceLayout:
    """How :func:`dump_sequence` spells a sequence's numbers and comments: the file's look,
    never its meaning.

    Each ``*_format`` is a format spec for the numbers of that kind (``"r"``: ``repr``, the
    exact float); ``comments`` are the texts after a key's value (``"Hz"`` -> ``  # Hz``,
    aligned with ``width``'s spaces per key); ``keyframe_gap``: a blank line between
    keyframes.
    """

    rate_format: str = "r"
    time_format: str = "r"
    size_format: str = "r"  # length, radius, max_helix_angle, current_limit
    mapping_format: str = "r"
    value_format: str = "r"  # the keyframes' values
    load_formats: tuple[str, str] = ("r", "r")  # time s, torque N mm
    comments: tuple[tuple[str, str, int], ...] = (
        ("rate", "Hz", 3),
        ("current_limit", "mA", 3),
        ("length", "mm, twisted strands", 3),
        ("radius", "mm", 3),
        ("max_helix_angle", "deg", 3),
        ("mapping", "[p, contraction mm]", 3),
        ("load", "[t s, N mm]", 3),
    )
    keyframe_gap: bool = True


#: The layouts the project writes: ``exact`` (every float as ``repr``: a script's
#: sequence read back bit for bit), ``model`` (``sequence`` from a string model: fold
#: ratios and contractions to 1e-6, DECIMALS of ``drive.from_model``), ``gait`` (a legged
#: robot's gait: ``crawl``, ``design-gait``, ``sequence ROBOT GAIT``; mappings to 1e-4 mm,
#: loads to 1e-3 N mm).
SEQUENCE_LAYOUTS: dict[str, SequenceLayout] = {
    "exact": SequenceLayout(),
    "model": SequenceLayout(
        size_format="g",
        mapping_format=".6f",
        value_format=".6f",
        comments=(
            ("rate", "Hz", 14),
            ("length", "mm, twisted strands", 11),
            ("radius", "mm", 12),
            ("max_helix_angle", "deg", 4),
            ("mapping", "[p, contraction mm], from the model", 3),
        ),
        keyframe_gap=False,
    ),
    "gait": SequenceLayout(
        rate_format="g",
        time_format="g",
        size_format="g",
        mapping_format=".4f",
        value_format="g",
        load_formats=("g", ".3f"),
        comments=(
            ("rate", "Hz", 14),
            ("current_limit", "mA: a stalling TSA is stopped", 3),
            ("length", "mm, twisted strands", 11),
            ("radius", "mm", 12),
            ("max_helix_angle", "deg", 3),
            ("mapping", "[p, mm]", 2),
            ("load", "[t s, N mm]", 2),
        ),
    ),
}


def _number(value: float, spec: str) -> str:
    """``value`` as TOML by the format ``spec`` (``"r"``: the exact float's ``repr``)."""
    return repr(float(value)) if spec == "r" else format(value, spec)


def dump_sequence(seq: Sequence, *, header: str = "", layout: str = "exact") -> str:
    """The sequence file (TOML text) of ``seq``: the one writer of the format that
    :func:`load_sequence` reads.

    ``header``: comment lines put first; ``layout``: a name of :data:`SEQUENCE_LAYOUTS`
    (how the numbers are spelled: ``exact`` reads back bit for bit). Each TSA's
    ``mapping`` (fold ratio, contraction mm) and ``load`` (t s, N mm) are written inline
    (also those read from a ``dcqc.json``), its ``comment`` above its table.

    >>> import tempfile, pathlib
    >>> seq = load_sequence("examples/crawler_gait.toml")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "seq.toml"
    >>> _ = path.write_text(dump_sequence(seq))
    >>> back = load_sequence(path)
    >>> back.keyframes == seq.keyframes, back.ids == seq.ids
    (True, True)
    """
    look = SEQUENCE_LAYOUTS[layout]
    notes = {key: " " * width + f"# {text}" for key, text, width in look.comments}

    def line(key: str, value: str) -> str:
        return f"{key} = {value}{notes.get(key, '')}"

    def pairs(arr: np.ndarray, first: str, second: str) -> str:
        return ", ".join(f"[{_number(a, first)}, {_number(b, second)}]" for a, b in arr)

    lines = [header.rstrip("\n")] if header else []
    lines += ["[sequence]", f"repeat = {int(seq.repeat)}"]
    lines.append(line("rate", _number(seq.rate, look.rate_format)))
    if seq.current_limit is not None:
        lines.append(line("current_limit", _number(seq.current_limit, look.size_format)))
    for item in seq.tsas:
        lines += ["", *([f"# {one_line(item.comment)}"] if item.comment else []), "[[tsa]]"]
        lines += [f"id = {int(item.dxl_id)}", f"name = {toml_string(item.name)}"]
        for key in ("length", "radius", "max_helix_angle"):
            lines.append(line(key, _number(getattr(item.tsa, key), look.size_format)))
        fmt = look.mapping_format
        lines.append(line("mapping", f"[{pairs(item.mapping, fmt, fmt)}]"))
        if item.load is not None:
            lines.append(line("load", f"[{pairs(item.load, *look.load_formats)}]"))
    for k, frame in enumerate(seq.keyframes):
        values = ", ".join(_number(v, look.value_format) for v in frame.values)
        lines += [""] if look.keyframe_gap or k == 0 else []
        lines += ["[[keyframe]]", f"t = {_number(frame.t, look.time_format)}"]
        lines.append(f"{frame.kind} = [{values}]")
    return finite_toml("\n".join(lines) + "\n", "the sequence file", DriveError)
