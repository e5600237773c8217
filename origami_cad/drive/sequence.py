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
    [[keyframe]]
    t = 0.0                     # s
    p = [0.0, 0.0]              # one value per TSA (or contraction = [...] mm, turns = [...])

Targets are interpolated linearly between keyframes; fold ratios become
contractions through each TSA's mapping and contractions become motor turns
through the TSA model (never beyond its maximum twist).
"""

from __future__ import annotations

import csv
import itertools
import json
import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from origami_cad._fileio import atomic_write
from origami_cad._toml import Table, load_toml
from origami_cad.drive.errors import DriveError
from origami_cad.errors import DesignError
from origami_cad.strings.tsa import TSAParams, onboard_angle

__all__ = ["Keyframe", "Sequence", "SequenceTSA", "load_sequence", "run_sequence"]


@dataclass(frozen=True)
class SequenceTSA:
    """One TSA of a sequence: servo, TSA model and fold-ratio-to-contraction mapping (mm)."""

    dxl_id: int
    name: str
    tsa: TSAParams
    mapping: np.ndarray  # (k, 2): fold ratio, contraction mm (increasing)

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
        except DesignError as exc:
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

    @property
    def cycle(self) -> float:
        """Duration of one cycle, s."""
        return self.keyframes[-1].t

    @property
    def ids(self) -> list[int]:
        return [t.dxl_id for t in self.tsas]

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


def _mapping(t: Table, base: Path) -> np.ndarray:
    raw = t.data.get("mapping")
    t.used.add("mapping")
    if isinstance(raw, str):
        path = (base / raw).resolve()
        if not path.is_file():
            raise t.error("mapping", f"{path}: no such file")
        try:
            data = json.loads(path.read_text())
            states = data["states"]  # columns: p (S,), tsa_length_mm (S, strings)
            taken = [row[0] - states["tsa_length_mm"][0][0] for row in states["tsa_length_mm"]]
            pairs = list(zip(states["p"], taken, strict=True))
        except (ValueError, KeyError, IndexError, TypeError):
            raise t.error("mapping", f"{path} is not a dcqc.json result") from None
        arr = np.array(pairs, dtype=float)
        # keep the strictly increasing part (a DCQC result may pause at a fold ratio)
        keep = np.r_[True, np.diff(arr[:, 0]) > 1e-9]
        arr = arr[keep]
    elif isinstance(raw, list):
        arr = np.array(t.pairs("mapping", min_length=2))
    else:
        raise t.error("mapping", "expected [[p, contraction_mm], ...] or a dcqc.json path")
    if np.any(np.diff(arr[:, 0]) <= 0) or np.any(np.diff(arr[:, 1]) < 0):
        raise t.error("mapping", "fold ratios must increase and contractions must not decrease")
    return arr


def load_sequence(path: str | os.PathLike[str]) -> Sequence:
    """Read a sequence file; errors name the file, table and key."""
    p = Path(path)
    top = Table(load_toml(p), str(p))
    seq = top.table("sequence", {})
    raw_tsas = top.data.get("tsa")
    raw_frames = top.data.get("keyframe")
    top.used |= {"tsa", "keyframe"}
    top.finish()
    if not isinstance(raw_tsas, list) or not raw_tsas:
        raise DesignError(f"{p}: expected at least one [[tsa]] table")
    if not isinstance(raw_frames, list) or len(raw_frames) < 2:
        raise DesignError(f"{p}: expected at least two [[keyframe]] tables")
    tsas = []
    for k, item in enumerate(raw_tsas):
        t = Table(item, f"{p} [[tsa]] #{k + 1}")
        tsa = SequenceTSA(
            dxl_id=t.integer("id", low=0, high=252),
            name=t.string("name", f"tsa {k + 1}"),
            tsa=TSAParams(
                model="onboard",
                length=t.number("length", 100.0, low=0, low_open=True),
                radius=t.number("radius", 0.5, low=0, low_open=True),
                max_helix_angle=t.number(
                    "max_helix_angle", 80.0, low=0, high=90, low_open=True, high_open=True
                ),
            ),
            mapping=_mapping(t, p.parent),
        )
        t.finish()
        tsas.append(tsa)
    if len({t.dxl_id for t in tsas}) != len(tsas):
        raise DesignError(f"{p}: two [[tsa]] tables have the same servo id")
    frames = []
    for k, item in enumerate(raw_frames):
        t = Table(item, f"{p} [[keyframe]] #{k + 1}")
        when = t.number("t", low=0)
        kinds = [name for name in ("p", "contraction", "turns") if t.has(name)]
        if len(kinds) != 1:
            raise DesignError(f"{t.where}: give exactly one of 'p', 'contraction', 'turns'")
        values = t.numbers(kinds[0], length=len(tsas))
        t.finish()
        frames.append(Keyframe(when, kinds[0], tuple(values)))
    if frames[0].t != 0 or any(b.t <= a.t for a, b in itertools.pairwise(frames)):
        raise DesignError(f"{p}: keyframe times must start at 0 and increase")
    sequence = Sequence(
        tuple(tsas),
        tuple(frames),
        repeat=seq.integer("repeat", 1, low=1),
        rate=seq.number("rate", 20.0, low=0, low_open=True),
        current_limit=seq.number("current_limit", None, low=0)
        if seq.has("current_limit")
        else None,
    )
    seq.used.add("current_limit")
    seq.finish()
    for tsa in tsas:  # every keyframe must be reachable safely
        for frame in frames:
            try:
                turns = Sequence._turns(tsa, frame, tsas.index(tsa))
            except DriveError as exc:
                raise DesignError(f"{p}: keyframe at t = {frame.t:g} s: {exc}") from None
            if abs(turns) > tsa.max_turns:
                raise DesignError(
                    f"{p}: keyframe at t = {frame.t:g} s asks servo {tsa.dxl_id} ({tsa.name}) "
                    f"for {turns:.2f} turns, beyond its TSA's {tsa.max_turns:.2f}"
                )
    return sequence


def run_sequence(
    sequence: Sequence,
    bus: Any,
    log: str | os.PathLike[str] | None = None,
    *,
    time_scale: float = 1.0,
    progress: Callable[[float, dict[int, float], dict[int, tuple[float, float]]], None]
    | None = None,
) -> list[dict[str, Any]]:
    """Run a sequence on an open bus; every command and reading goes to the CSV ``log``.

    ``time_scale`` > 1 runs faster than real time (dry runs). Returns the log rows.
    """
    total = sequence.cycle * sequence.repeat
    period = 1.0 / sequence.rate
    rows: list[dict[str, Any]] = []
    start = time.monotonic()
    k = 0
    while True:
        t = k * period
        if t > total + 1e-9:
            break
        wake = start + t / time_scale
        delay = wake - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        targets = sequence.turns_at(t)
        bus.set_turns(targets)
        state = bus.read()
        for i in sequence.ids:
            rows.append(
                {
                    "t_s": round(t, 6),
                    "id": i,
                    "target_turns": targets[i],
                    "measured_turns": state[i][0],
                    "current_mA": state[i][1],
                }
            )
        if progress is not None:
            progress(t, targets, state)
        k += 1
    if log is not None:
        with atomic_write(log, "w", newline="", encoding="utf-8") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    return rows
