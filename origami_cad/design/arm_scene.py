"""The printed arm in its scene (the paper's Fig. 8): the designed tip path and how the
arm folded by its strings compares with it, ``P_end`` and the task's areas."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from origami_cad.design.fitness import area_edges
from origami_cad.design.predicates import touches_area
from origami_cad.kinematics.chain import chain_points
from origami_cad.kinematics.limits import reachable_fold_angle

__all__ = ["arm_scene_metrics", "arm_scene_numbers", "designed_arm_path"]


def designed_arm_path(task, tg, bias: float | None = None) -> tuple[float, np.ndarray]:
    """The designed chain over the printed arm's fold range.

    Parameters
    ----------
    task : ArmTask
        The arm's task (``samples`` states; ``fold_limit`` or b, h, t of eq. 6).
    tg : TGDesign
        The arm's transition graph (lengths mm, shape angles deg).
    bias : float, optional
        The printed sheet's bias b, mm (a route's ``[fabrication]``); default the task's.

    Returns
    -------
    p_e : float
        The end of the fold range: where eq. 6's limit stops the first crease, legs
        included.
    joints : ndarray, shape (samples, n + 2, 2)
        The chain's joints at even fold ratios from 0 to ``p_e``, mm.

    Examples
    --------
    >>> from origami_cad.design import load_task
    >>> from origami_cad.pattern.design import load_design
    >>> task, _ = load_task("examples/arm_task.toml")
    >>> tg = load_design("examples/arm_design.toml").tg
    >>> p_e, joints = designed_arm_path(task, tg, bias=3.0)
    >>> round(p_e, 3), joints.shape == (task.samples, len(tg.lengths) + 1, 2)
    (0.335, True)
    """
    beta = np.radians(np.asarray(tg.shape_angles, dtype=float))[None, :]
    bias = task.bias if bias is None else bias
    limit = task.crease_limit(bias if task.fold_limit is None else None)
    p_e = float(reachable_fold_angle(beta, limit)[0] / math.pi)
    angles = np.linspace(0.0, p_e * math.pi, task.samples)
    designed = chain_points(angles, tg.lengths, beta, tg.entry_flag, tg.hypar_base, tg.start)
    return p_e, designed[0]


def arm_scene_metrics(task, tg, result, simulated, designed, p_e: float) -> dict[str, Any]:
    """The arm folded by its strings against its design, ``P_end`` and the task's areas.

    Parameters
    ----------
    task : ArmTask
        The task (``points``: ``P_start``, ``P_end`` mm; ``prohibited`` areas).
    tg : TGDesign
        The arm's transition graph.
    result : SimulationResult or DCQCResult
        The folding: ``p (S,)``, ``turns (S,)``, ``torque (S,)`` N mm, ``stop``, ``reason``.
    simulated : ndarray, shape (S, n + 2, 2)
        Each state's chain (``arm_chain_path``), mm.
    designed : ndarray, shape (D, n + 2, 2)
        The designed chain (:func:`designed_arm_path`), mm.
    p_e : float
        The designed fold range's end.

    Returns
    -------
    dict
        Plain data (lengths mm, torque N mm): the tip's final and closest distance from
        ``P_end``, its largest distance from the designed tip at the same fold ratio,
        the states touching a prohibited area, the TSA turns, the largest torque, why the
        folding stopped, and both tip paths.

    Examples
    --------
    The arm folded by its route in the DCQC model, each state's chain from the rigid
    folding at its fold ratio: it follows the designed tip exactly.

    >>> from origami_cad.design import load_task
    >>> from origami_cad.design.arm_route import arm_chain_path
    >>> from origami_cad.kinematics import tessellation_vertices
    >>> from origami_cad.pattern.design import load_design
    >>> from origami_cad.strings import load_route, simulate_dcqc
    >>> task, _ = load_task("examples/arm_task.toml")
    >>> arm = load_design("examples/arm_design.toml")
    >>> folded = simulate_dcqc(arm, load_route("examples/arm_route.toml", arm.pattern))
    >>> p = np.asarray(folded.p)
    >>> states = tessellation_vertices(arm.tg, p).reshape(len(p), -1, 3)
    >>> chain = arm_chain_path(arm.tg, states, p)
    >>> p_e, designed = designed_arm_path(task, arm.tg, bias=3.0)
    >>> m = arm_scene_metrics(task, arm.tg, folded, chain, designed, p_e)
    >>> round(m["max_distance_from_designed_tip_mm"], 6), m["states_touching_prohibited_area"]
    (0.0, 0)
    """
    ratios = np.asarray(result.p, dtype=float)
    beta = np.radians(np.asarray(tg.shape_angles, dtype=float))[None, :]
    tips = simulated[:, -1]
    d_end = np.linalg.norm(tips - task.points[-1], axis=1)
    known = np.isfinite(ratios)
    rigid = chain_points(  # the designed tip at each state's fold ratio
        ratios[known] * math.pi, tg.lengths, beta, tg.entry_flag, tg.hypar_base, tg.start
    )[0, :, -1]
    deviation = float(np.linalg.norm(tips[known] - rigid, axis=1).max()) if known.any() else 0.0
    z = simulated[..., 0] + 1j * simulated[..., 1]
    hits = np.zeros(len(z), dtype=bool)
    for edges in area_edges(task.prohibited):
        hits |= touches_area(z, edges)
    torque = np.asarray(result.torque, dtype=float)
    finite = np.isfinite(torque).any()
    return {
        "designed_fold_ratio_end": p_e,
        "simulated_fold_ratio_end": float(np.nanmax(ratios)) if np.isfinite(ratios).any() else None,
        "final_tip_mm": tips[-1].tolist(),
        "final_distance_from_P_end_mm": float(d_end[-1]),
        "closest_distance_from_P_end_mm": float(d_end.min()),
        "first_state_fold_ratio": float(ratios[0]),
        "max_distance_from_designed_tip_mm": deviation,
        "states_touching_prohibited_area": int(hits.sum()),
        "tsa_turns": float(result.turns[-1]),
        "max_tsa_torque_Nmm": float(np.nanmax(torque)) if finite else float("nan"),
        "stop": str(result.stop),
        "reason": result.reason,
        "simulated_tip_mm": tips.tolist(),
        "designed_tip_mm": designed[:, -1].tolist(),
    }


def arm_scene_numbers(summary: dict[str, Any]) -> list[tuple[str, str]]:
    """The key numbers of an arm scene (labels and values: mm, N mm, turns) from the
    summary of :func:`arm_scene_metrics`."""
    return [
        ("designed fold range", f"p = 0 .. {summary['designed_fold_ratio_end']:.3f}"),
        (
            "simulated tip: distance from P_end at the end",
            f"{summary['final_distance_from_P_end_mm']:.2f} mm",
        ),
        (
            "simulated tip: largest distance from the designed tip",
            f"{summary['max_distance_from_designed_tip_mm']:.2f} mm",
        ),
        ("states touching the prohibited area", str(summary["states_touching_prohibited_area"])),
        ("TSA turns to fold it", f"{summary['tsa_turns']:.1f}"),
        ("largest TSA torque", f"{summary['max_tsa_torque_Nmm']:.3g} N mm"),
        ("why the folding stops", summary["reason"]),
    ]
