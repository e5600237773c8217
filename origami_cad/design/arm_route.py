"""The string route of a designed arm: one onboard TSA on the base panel (the paper's Fig. 8).

The paper folds its arm with one TSA whose strings run along the arm, parallel
to the transition vectors. :func:`arm_route_toml` writes that route for a TG
design as a route file (``docs/strings.md``) that ``route``, ``simulate`` and
``sequence`` read: the TSA rides on the base panel ``c{c}r0s0`` of the middle
copy ``c``, at the main crease's side of that panel, and one string per panel
row of that copy threads the panels ``s1 .. sn`` of its row, in order, through
their automatic holes (placed as ``fabricate`` places them). Every hole-to-hole
segment crosses one leg; its side is left to the DCQC rule (``sides = "auto"``:
above valleys, below mountains), so shortening the strings closes the legs and,
through the one-degree-of-freedom rigid folding, folds the whole arm.

The route states the printed sheet (``[fabrication]`` b, h, t), so both string
models stop where the first crease reaches eq. 6's limit: the end of the fold
range the arm was designed for.

>>> from origami_cad.pattern.tg import TGDesign
>>> tg = TGDesign([60.0, 50.0, 40.0], [70.0, 110.0], 1, 36.0, 3)
>>> text = arm_route_toml(tg)
>>> 'anchor_panel = "c1r0s0"' in text and 'holes = ["c1r0s1", "c1r0s2"]' in text
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from origami_cad._names import toml_string
from origami_cad._toml import finite_toml
from origami_cad.errors import DesignError, OrigamiCadError
from origami_cad.kinematics.limits import bias_for_theta_max
from origami_cad.pattern.tg import TGDesign, tg_pattern

__all__ = ["ARM_TSA_LENGTHS", "ArmStrings", "arm_chain_path", "arm_route_toml", "choose_arm_tsa"]

#: Strand lengths (mm) tried for the arm's onboard TSA, shortest first.
ARM_TSA_LENGTHS = (150.0, 225.0, 340.0, 500.0, 750.0)


def arm_route_toml(
    tg: TGDesign,
    *,
    bias: float | None = 3.0,
    height: float = 2.2,
    thickness: float = 0.4,
    tsa_length: float = 150.0,
    tsa_radius: float = 0.6,
    max_helix_angle: float = 75.0,
    mount_height: float = 10.0,
    max_turns: float | None = None,
    take_up: float = 0.1,
    header: str = "",
) -> str:
    """The route file (TOML text) of an arm folded by one onboard TSA on its base panel.

    Parameters
    ----------
    tg : TGDesign
        The arm's tessellation (e.g. ``ArmDesign.tg(task)``); at least two vectors.
    bias, height, thickness : float
        ``b``, ``h``, ``t`` of the printed sheet (eq. 6), mm; ``bias = None``: no
        ``[fabrication]`` table (the strings fold as far as the rigid folding goes).
    tsa_length, tsa_radius : float
        Strand length and radius of the onboard TSA, mm.
    max_helix_angle : float
        Largest helix angle of the twisted strands, degrees.
    mount_height : float
        Height of the TSA's string exit above the base panel's top face, mm.
    max_turns : float, optional
        TSA turns at most (default: the strands' largest twist, where their helix
        angle reaches ``max_helix_angle``, rounded up).
    take_up : float
        String (mm) the TSA takes up per quasi-static step.
    header : str
        Comment lines put first (each starting with ``#``).

    Returns
    -------
    str
        A route file; the strings' holes are panel labels (automatic holes).
    """
    n = len(tg.lengths) - 1
    if n < 1:
        raise DesignError("an arm route needs at least two transition vectors")
    cp = tg_pattern(tg)
    copy = int(tg.copies) // 2
    base = f"c{copy}r0s0"
    x, y = _tsa_position(cp, tg, base)
    if max_turns is None:
        twist = tsa_length * np.sin(np.radians(max_helix_angle)) / tsa_radius
        max_turns = float(np.ceil(twist / (2 * np.pi)))
    lines = [header.rstrip("\n")] if header else []
    lines += _tsa_lines(tsa_length, tsa_radius, max_helix_angle)
    if bias is not None:
        lines += _fabrication_lines(bias, height, thickness)
    lines += [
        "[route]",
        f"thickness = {height:g}              # mm: hole exits sit half of it off the sheet",
        f"take_up = {take_up:g}",
        f"max_turns = {max_turns:g}",
        "",
    ]
    for row in (0, 1):
        lines += _string_lines(copy, row, n, base, (x, y, mount_height))
    return finite_toml("\n".join(lines), "the arm's route file", DesignError)


def _tsa_position(cp, tg: TGDesign, base: str) -> tuple[float, float]:
    """Where the TSA sits on the base panel, mm.

    In the middle of the panel's main-crease edge, a quarter of the row height
    inside the panel (both strings leave it towards their rows); the panel's
    centroid if that point falls outside it.
    """
    face = cp.faces[cp.face_index(base)]
    corners = cp.vertices[face]
    top_y = corners[:, 1].max()
    on_crease = corners[np.isclose(corners[:, 1], top_y)]
    x = float(on_crease[:, 0].mean())
    y = float(top_y - tg.row_height / 4.0)
    if cp.face_of_point(x, y) != cp.face_index(base):
        x, y = (float(v) for v in corners.mean(axis=0))
    return x, y


def _tsa_lines(tsa_length: float, tsa_radius: float, max_helix_angle: float) -> list[str]:
    """The route file's ``[tsa]`` table: an onboard TSA (mm, degrees)."""
    return [
        "[tsa]",
        'model = "onboard"',
        f"length = {tsa_length:g}          # mm, twisted strands",
        f"radius = {tsa_radius:g}           # mm",
        f"max_helix_angle = {max_helix_angle:g}   # deg",
        "",
    ]


def _fabrication_lines(bias: float, height: float, thickness: float) -> list[str]:
    """The route file's ``[fabrication]`` table: b, h, t of eq. 6, mm."""
    return [
        "[fabrication]                # the printed arm: eq. 6 stops its creases",
        f"bias = {bias:.6g}",
        f"height = {height:g}",
        f"thickness = {thickness:g}",
        "",
    ]


def _string_lines(
    copy: int, row: int, n: int, base: str, anchor: tuple[float, float, float]
) -> list[str]:
    """One ``[[route.strings]]`` table: from the TSA through panels ``s1 .. sn`` of a row."""
    x, y, mount_height = anchor
    holes = ", ".join(f'"c{copy}r{row}s{k}"' for k in range(1, n + 1))
    return [
        f"[[route.strings]]            # along panel row r{row} of copy {copy}",
        f"anchor_panel = {toml_string(base)}     # the onboard TSA on the base panel",
        f"anchor = [{x:.4f}, {y:.4f}, {mount_height:g}]",
        f"holes = [{holes}]",
        'sides = "auto"               # DCQC: above valleys, below mountains',
        "",
    ]


def _rigid_fit(src: np.ndarray, dst: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotation ``R`` and shift ``s`` with ``src @ R.T + s`` closest to ``dst`` (Kabsch)."""
    cs, cd = src.mean(axis=0), dst.mean(axis=0)
    u, _, vt = np.linalg.svd((src - cs).T @ (dst - cd))
    flip = np.sign(np.linalg.det(vt.T @ u.T)) or 1.0
    rot = vt.T @ np.diag([1.0, 1.0, flip]) @ u.T
    return rot, cd - cs @ rot.T


def arm_chain_path(tg: TGDesign, states: np.ndarray, ratios: np.ndarray) -> np.ndarray:
    """The TG chain of folded states of an arm's sheet, in the design's 2D frame, mm.

    Each state (vertex coordinates in the pattern's vertex order, e.g. a
    bar-and-hinge simulation's ``states``) is placed by its base panels, segment 0
    of every row, fitted rigidly onto the rigid folding at that state's fold ratio;
    the joints of the middle copy's main crease then give the TG points ``(a, b)``
    from their 3D position ``(a, y, -b)`` (the frame of
    :func:`~origami_cad.kinematics.fold3d.tessellation_vertices`), ``T_s`` first and
    ``T_e`` last.

    Parameters
    ----------
    tg : TGDesign
        The arm's tessellation.
    states : ndarray, shape (S, n_vertices, 3)
        Folded states, mm.
    ratios : ndarray, shape (S,)
        Fold ratio of each state (where to place its base).

    Returns
    -------
    ndarray, shape (S, n + 2, 2)
        Joints of the chain, mm.
    """
    from origami_cad.kinematics.fold3d import tessellation_vertices

    states = np.asarray(states, dtype=float)
    ratios = np.clip(np.nan_to_num(np.asarray(ratios, dtype=float)), 0.0, 1.0)
    grid = tessellation_vertices(tg, ratios)  # (S, rows + 1, n + 2, 3)
    cols = grid.shape[2]
    rows = np.arange(grid.shape[1])
    base = (rows[:, None] * cols + np.array([0, 1])[None, :]).reshape(-1)
    main_row = 2 * (int(tg.copies) // 2) + 1
    out = np.empty((len(states), cols, 2))
    for k, coords in enumerate(states):
        rigid = grid[k].reshape(-1, 3)
        rot, shift = _rigid_fit(coords[base], rigid[base])
        joints = coords[main_row * cols : (main_row + 1) * cols] @ rot.T + shift
        out[k, :, 0] = joints[:, 0]
        out[k, :, 1] = -joints[:, 2]
    return out


@dataclass(frozen=True)
class ArmStrings:
    """The string route chosen for a designed arm (:func:`choose_arm_tsa`).

    Attributes
    ----------
    text : str
        The route file (TOML), its header first.
    tsa_length : float
        The onboard TSA's strand length, mm.
    result : DCQCResult or None
        Its strings folding the arm (DCQC model), or ``None`` when the route cannot be
        built or simulated.
    error : OrigamiCadError or None
        Why not (e.g. a panel too small for its hole), naming the route ``route.toml``.
    """

    text: str
    tsa_length: float
    result: Any = None
    error: OrigamiCadError | None = None


def _arm_bias(design, task) -> float | None:
    """The printed sheet's bias b (mm) of the arm's route: eq. 6 of the task's fold limit
    when it gives one (``None`` at 180 deg: no limit), else the design's own."""
    if task.fold_limit is None:
        return design.bias
    if task.fold_limit >= 180:
        return None
    return bias_for_theta_max(math.radians(task.fold_limit), task.height, task.thickness)


def choose_arm_tsa(
    design, task, *, header: str = "", lengths: tuple[float, ...] = ARM_TSA_LENGTHS
) -> ArmStrings:
    """The shortest onboard TSA whose strings fold a designed arm over its whole range.

    Each strand length of ``lengths`` is tried, shortest first: the arm's route
    (:func:`arm_route_toml`, on the design's tessellation at the task's unit width) is
    folded by the DCQC model until a length whose strings are not stopped by the
    strands' twist (``helix_limit``, ``turn_limit``); the longest is kept otherwise.
    Nothing is written.

    Parameters
    ----------
    design : ArmDesign
        The designed arm (``design_arm``'s result).
    task : ArmTask
        Its task: the unit width, ``[fabrication]`` b, h, t (mm) or ``fold_limit`` (deg).
    header : str
        Comment lines the route file starts with.
    lengths : tuple of float
        Strand lengths tried, mm.

    Returns
    -------
    ArmStrings
        The route text, its TSA length (mm) and its DCQC result, or the error that kept
        it from being simulated.

    Examples
    --------
    >>> import math, numpy as np
    >>> from origami_cad.design import ArmDesign, load_task
    >>> from origami_cad.pattern.design import load_design
    >>> task, _ = load_task("examples/arm_task.toml")
    >>> tg = load_design("examples/arm_design.toml").tg
    >>> arm = ArmDesign(tg.lengths, tg.shape_angles, tg.entry_flag, math.nan, None,
    ...                 np.empty((0, 2)), run=0, generations=0, history=())
    >>> chosen = choose_arm_tsa(arm, task)  # folds it; writes nothing
    >>> chosen.tsa_length, round(float(chosen.result.p[-1]), 3), chosen.text[:5]
    (150.0, 0.335, '[tsa]')
    """
    from origami_cad.pattern.design import Design
    from origami_cad.strings import simulate_dcqc
    from origami_cad.strings.route import parse_route

    tg = design.tg(task, task.unit_width or 36.0)
    loaded = Design(tg_pattern(tg), tg, "transition-graph")
    fab = {"bias": _arm_bias(design, task), "height": task.height, "thickness": task.thickness}
    chosen = None
    for length in lengths:
        text = arm_route_toml(tg, **fab, tsa_length=length, header=header)
        try:
            result = simulate_dcqc(loaded, parse_route(text, loaded.pattern, "route.toml"))
        except OrigamiCadError as exc:
            return ArmStrings(text, length, error=exc)
        chosen = ArmStrings(text, length, result)
        if str(result.stop) not in ("helix_limit", "turn_limit"):
            break
    return chosen
