"""Sequences from string models: fold-ratio keyframes turned into TSA turns by a simulation.

A sequence file's mapping (``[[tsa]] mapping = [[p, contraction_mm], ...]``) says
how far each onboard TSA must contract its strands for the structure to reach a
fold ratio. Typed by hand, nothing checks it. Here it comes from a model: a DCQC
result or a bar-and-hinge simulation of the structure and its route gives the
fold ratio ``p`` reached at each TSA rotation; :func:`model_mapping` samples that
curve (and every keyframe's fold ratio exactly) as contractions of the onboard
TSA model (``onboard_contraction``), so that ``drive``, which turns a
contraction back into motor turns with the same model's inverse, commands the
turns the model needed. :func:`model_sequence` makes the :class:`Sequence`, and
``drive.sequence.dump_sequence`` writes it.

>>> import numpy as np
>>> from origami_cad.strings import TSAParams
>>> tsa = TSAParams(model="onboard", length=150.0, radius=0.6, max_helix_angle=75.0)
>>> p, turns = np.linspace(0, 0.5, 11), np.linspace(0, 20, 11) ** 0.5 * 4
>>> m = model_mapping(p, turns, tsa, at=[0.33])
>>> bool(np.any(np.isclose(m[:, 0], 0.33)))
True
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from origami_cad.drive.sequence import Keyframe, SequenceTSA
from origami_cad.drive.sequence import Sequence as DriveSequence
from origami_cad.errors import DriveError
from origami_cad.strings.tsa import TSAParams, onboard_contraction

#: A keyframe's fold ratio may pass the model's range by this much (then it is its end).
AT_TOLERANCE = 1e-3

#: Decimals with which a sequence file holds fold ratios and contractions (mm). Mapping
#: points are merged at this precision, so that what is written always reads back
#: (strictly increasing fold ratios, non-decreasing contractions).
DECIMALS = 6

__all__ = [
    "fold_curve",
    "model_mapping",
    "model_sequence",
    "parse_keyframes",
    "route_tsa",
    "state_fold_ratios",
    "turns_at",
]


def parse_keyframes(items: Sequence[str], count: int) -> list[tuple[float, tuple[float, ...]]]:
    """Keyframes ``"T:P"`` or ``"T:P1,P2,..."`` (s, fold ratios) for ``count`` TSAs.

    A single fold ratio applies to every TSA. Times must start at 0 and increase;
    fold ratios lie in [0, 1]. Errors name the keyframe.
    """
    out: list[tuple[float, tuple[float, ...]]] = []
    if len(items) > 100_000:
        raise DriveError(f"{len(items)} keyframes; at most 100000")
    for k, text in enumerate(items):
        head, sep, tail = str(text).partition(":")
        try:
            if not sep:
                raise ValueError
            t = float(head)
            values = tuple(float(v) for v in tail.split(","))
        except ValueError:
            raise DriveError(
                f"keyframe {k + 1} {text!r}: expected TIME:P or TIME:P1,P2,... (s, fold ratios)"
            ) from None
        if len(values) == 1:
            values = values * count
        if len(values) != count:
            raise DriveError(
                f"keyframe {k + 1} {text!r}: {len(values)} fold ratios for {count} TSAs"
            )
        if not (math.isfinite(t) and 0 <= t <= 1e7):
            raise DriveError(f"keyframe {k + 1} {text!r}: time must be a number in [0, 1e7] s")
        if not all(math.isfinite(v) and 0.0 <= v <= 1.0 for v in values):
            raise DriveError(f"keyframe {k + 1} {text!r}: fold ratios must lie in [0, 1]")
        if out and t <= out[-1][0]:
            raise DriveError(f"keyframe {k + 1} {text!r}: times must increase")
        out.append((t, values))
    if len(out) < 2:
        raise DriveError("give at least two keyframes (TIME:P ...)")
    if out[0][0] != 0:
        raise DriveError(f"keyframe 1 {items[0]!r}: the first keyframe must be at t = 0")
    return out


def fold_curve(p: np.ndarray, turns: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The fold ratio against TSA turns as a strictly increasing curve.

    States without a fold ratio (NaN) are dropped, and a state that does not fold
    further than every earlier one (a pause, or a jam's last states) is skipped:
    the first turns at which each fold ratio is reached are kept.
    """
    p = np.asarray(p, dtype=float)
    turns = np.asarray(turns, dtype=float)
    ok = np.isfinite(p) & np.isfinite(turns)
    p, turns = p[ok], turns[ok]
    if not len(p):
        raise DriveError("the model has no state with a fold ratio")
    best = np.maximum.accumulate(p)
    keep = np.r_[True, best[1:] > best[:-1] + 1e-9]
    return p[keep], turns[keep]


def state_fold_ratios(p: np.ndarray, fold_angles: np.ndarray, creases: np.ndarray) -> np.ndarray:
    """Each state's fold ratio: the model's ``p``, else the most folded crease's angle / 180.

    A pattern without a one-parameter rigid folding (a robot whose legs hinge on
    single creases) has no fold ratio in a bar-and-hinge simulation (``p`` NaN);
    its states are then measured by ``max |fold angle| / 180 deg`` over ``creases``
    (the creases its strings drive, or all of them).

    Parameters
    ----------
    p : ndarray, shape (S,)
        Fold ratio of each state, NaN where unknown.
    fold_angles : ndarray, shape (S, m)
        Fold angle of every edge in each state, degrees.
    creases : ndarray of int
        Edges whose angles measure the folding.
    """
    p = np.asarray(p, dtype=float)
    if np.isfinite(p).any():
        return p
    angles = np.abs(np.asarray(fold_angles, dtype=float)[:, np.asarray(creases, dtype=int)])
    return angles.max(axis=1) / 180.0


def turns_at(p: np.ndarray, turns: np.ndarray, at: Any) -> np.ndarray:
    """TSA turns at fold ratios ``at`` on a curve from :func:`fold_curve` (linear)."""
    return np.interp(np.asarray(at, dtype=float), p, turns)


def model_mapping(
    p: np.ndarray,
    turns: np.ndarray,
    tsa: TSAParams,
    at: Sequence[float] = (),
    points: int = 21,
    where: str = "the model",
) -> np.ndarray:
    """A sequence mapping ``[[p, contraction_mm], ...]`` from a model's fold curve.

    Parameters
    ----------
    p, turns : ndarray
        Fold ratio and TSA turns of the model's states (:func:`fold_curve` is applied).
    tsa : TSAParams
        The onboard TSA (``model = "onboard"``) whose contraction ``drive`` inverts.
    at : sequence of float
        Fold ratios that must be mapping points (the keyframes), so that ``drive``
        reproduces the model's turns there exactly; one within ``AT_TOLERANCE`` of
        the curve's range is taken at its end.
    points : int
        Evenly spaced fold ratios over the curve, besides ``at``.
    where : str
        Names the model in errors.

    Returns
    -------
    ndarray, shape (k, 2)
        Increasing fold ratios and non-decreasing contractions, mm.
    """
    if tsa.model != "onboard":
        raise DriveError(
            f"{where}: its TSA is a {tsa.model!r} TSA; a sequence drives onboard TSAs "
            '(model = "onboard" in the route\'s [tsa])'
        )
    p, turns = fold_curve(p, turns)
    lo, hi = float(p[0]), float(p[-1])
    at = np.asarray(list(at), dtype=float)
    far = at[(at < lo - AT_TOLERANCE) | (at > hi + AT_TOLERANCE)]
    if len(far):
        raise DriveError(
            f"{where}: fold ratio {far[0]:g} is outside what its strings reach, "
            f"p = {lo:.4g} .. {hi:.4g}"
        )
    # merged at the precision the file holds: two points that print alike are one point
    grid = np.unique(
        np.round(np.r_[np.linspace(lo, hi, max(points, 2)), np.clip(at, lo, hi)], DECIMALS)
    )
    if len(grid) < 2:
        raise DriveError(
            f"{where}: its strings fold it only from p = {lo:.6g} to {hi:.6g}, "
            "too little for a mapping"
        )
    theta = 2 * math.pi * turns_at(p, turns, np.clip(grid, lo, hi))
    contraction = onboard_contraction(
        theta, tsa.length, tsa.radius, math.radians(tsa.max_helix_angle)
    )
    return np.column_stack([grid, np.round(np.maximum.accumulate(contraction), DECIMALS)])


def _fixed(value: float) -> str:
    """``value`` at the sequence file's precision (:data:`DECIMALS`), trailing zeros kept."""
    return f"{value:.{DECIMALS}f}"


def model_sequence(
    tsas: Sequence[dict[str, Any]],
    keyframes: Sequence[tuple[float, Sequence[float]]],
    *,
    rate: float = 10.0,
    repeat: int = 1,
) -> DriveSequence:
    """The sequence ``drive`` runs, from string models' TSAs (write it with
    ``dump_sequence(seq, layout="model")``).

    ``tsas``: one dict per TSA with ``id`` (servo), ``name``, ``tsa``
    (:class:`TSAParams`, onboard), ``mapping`` (from :func:`model_mapping`) and
    optional ``comment`` (as :func:`route_tsa` gives them); ``keyframes``: ``(t s, fold
    ratio per TSA)``, each fold ratio rounded to :data:`DECIMALS` and kept within its
    TSA's mapping (``rate`` in Hz).
    """
    items = [
        SequenceTSA(
            dxl_id=int(item["id"]),
            name=item["name"],
            tsa=item["tsa"],
            mapping=item["mapping"],
            comment=item.get("comment") or "",
        )
        for item in tsas
    ]
    frames = []
    for t, values in keyframes:  # within each mapping (AT_TOLERANCE at its ends)
        kept = [
            min(max(round(v, DECIMALS), item.mapping[0, 0]), item.mapping[-1, 0])
            for v, item in zip(values, items, strict=True)
        ]
        frames.append(Keyframe(float(t), "p", tuple(float(v) for v in kept)))
    return DriveSequence(tuple(items), tuple(frames), repeat=int(repeat), rate=float(rate))


def route_tsa(
    pattern,
    tsa: TSAParams,
    result,
    at: Sequence[float],
    *,
    servo: int,
    name: str,
    points: int = 21,
    where: str = "the model",
    label: str | None = None,
) -> tuple[dict[str, Any], dict[str, Any]]:
    """One TSA of a sequence from a route's string model: its entry and its figures.

    Parameters
    ----------
    pattern : CreasePattern
        The folded pattern (its mountain and valley creases measure the fold ratio).
    tsa : TSAParams
        The route's onboard TSA.
    result : DCQCResult or SimulationResult
        The route's folding (``p``, ``fold_angles`` rad, ``turns``, ``torque`` N mm,
        ``reason``), e.g. ``origami_cad.simulation.string_models.fold_by_strings``.
    at : sequence of float
        The keyframes' fold ratios for this TSA: mapping points.
    servo, name : int, str
        The servo's ID and the TSA's name.
    points : int
        Mapping points besides ``at`` (:func:`model_mapping`).
    where : str
        Names the route and model in errors.
    label : str, optional
        Names them in the entry's comment (default ``where``).

    Returns
    -------
    entry : dict
        For :func:`model_sequence`: ``id``, ``name``, ``tsa``, ``mapping``, ``comment``.
    figures : dict
        ``p_range`` (first, last fold ratio), ``turns`` (the last), ``turns_at`` (the
        turns at ``at``) and ``peak_torque`` (N mm, NaN when unknown).

    Examples
    --------
    >>> from origami_cad.pattern.design import load_design
    >>> from origami_cad.strings import load_route, simulate_dcqc
    >>> arm = load_design("examples/arm_design.toml")
    >>> spec = load_route("examples/arm_route.toml", arm.pattern)
    >>> entry, figures = route_tsa(arm.pattern, spec.tsa, simulate_dcqc(arm, spec),
    ...                            [0.0, 0.3], servo=1, name="arm")
    >>> seq = model_sequence([entry], [(0.0, (0.0,)), (20.0, (0.3,))])  # drive's input
    >>> bool(0.3 in entry["mapping"][:, 0]), round(figures["p_range"][1], 3)
    (True, 0.335)
    """
    creases = np.flatnonzero(pattern.edge_mask("M", "V"))
    ratios = state_fold_ratios(result.p, result.fold_angles, creases)
    mapping = model_mapping(ratios, result.turns, tsa, at, points, where)
    p, turns = fold_curve(ratios, result.turns)
    torque = np.asarray(result.torque, dtype=float)
    peak = float(np.nanmax(torque)) if np.isfinite(torque).any() else float("nan")
    entry = {
        "id": servo,
        "name": name,
        "tsa": tsa,
        "mapping": mapping,
        "comment": (
            f"servo {servo}: {label or where}: p = {p[0]:.3f} .. {p[-1]:.3f} in {turns[-1]:.2f} "
            f"turns ({result.reason})"
        ),
    }
    figures = {
        "p_range": (float(p[0]), float(p[-1])),
        "turns": float(turns[-1]),
        "turns_at": turns_at(p, turns, at),
        "peak_torque": peak,
    }
    return entry, figures
