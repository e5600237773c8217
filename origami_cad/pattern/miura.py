"""Miura-based tessellations: the classic Miura-ori and the general grid of a TG.

The grid has straight horizontal crease lines (the *main creases* on the centre
line of every tessellation unit, and the long edges shared by two units) and
zigzag lines (*legs*) through the joints. Segment ``k`` of a main crease has
length ``l_k`` along +x; at joint ``k`` (between segments ``k-1`` and ``k``) the
legs leave the main crease at the shape angle ``beta_k`` (degrees, measured from
+x; above 90 deg they lean backwards) and reach the long edges ``h`` away, where
``h`` is half the unit width. Rows alternate lower/upper half of a unit, so copy
``c`` has its main crease at ``y = y_s + c * 2h``.

Assignments make every interior vertex a flat-foldable degree-4 vertex:

- main-crease segment ``k``: valley if its entry flag is 1, mountain if 0;
  flags alternate along the main crease;
- long edges shared by two units: the opposite of the main-crease segment beside;
- legs at joint ``k``: the type of main segment ``k-1`` when ``beta_k < 90`` deg,
  of segment ``k`` when ``beta_k > 90`` deg (the unique crease of the vertex is
  then the other main segment; see ``docs/kinematics.md``);
- outer long edges and the two short ends: border. The short ends follow the
  legs of the nearest joint (a zigzag end, so the end panels are
  parallelograms like the others, whatever the lean of the legs).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from origami_cad import _libm
from origami_cad.errors import PatternError
from origami_cad.pattern.model import MAX_VERTICES, CreasePattern

__all__ = [
    "MAX_PANELS",
    "leg_gaps",
    "miura_pattern",
    "miura_tessellation",
    "tessellation_leg_offsets",
]

#: Most panels a generated tessellation may have; its vertices are limited too
#: (:data:`~origami_cad.pattern.model.MAX_VERTICES`, about one per panel).
MAX_PANELS = 100_000
#: The smallest feature of a tessellation (the closest two vertices, or a vertex and a
#: crease it is not on) must be this many times the tolerance within which the pattern
#: merges vertices (``DEFAULT_RELATIVE_TOLERANCE`` of its size, which grows with the
#: rows): a TG of thousands of copies is refused instead of having its vertices merged.
MIN_FEATURE_TOLERANCES = 1.5


def tessellation_leg_offsets(shape_angles: np.ndarray, row_height: float) -> np.ndarray:
    """Forward x-offset of each joint's legs at the long edges, mm: ``h cot(beta)``.

    Parameters
    ----------
    shape_angles : ndarray
        ``beta_1 .. beta_n``, radians.
    row_height : float
        ``h``, half the unit width, mm.
    """
    return row_height / _libm.tan(shape_angles)


def leg_gaps(lengths: np.ndarray, shape_angles: np.ndarray, row_height: float) -> np.ndarray:
    """Distance between neighbouring legs along the long edges, per segment, mm.

    Segment ``k`` spans ``l_k + h cot(beta_{k+1}) - h cot(beta_k)`` on the long
    edges (the short ends follow their nearest legs). A gap <= 0 means two legs
    cross and the crease pattern does not exist. Vectorised: ``lengths`` (D, n+1)
    in mm, ``shape_angles`` (D, n) in radians; returns (D, n + 1).
    """
    l = np.atleast_2d(np.asarray(lengths, dtype=float))
    b = np.atleast_2d(np.asarray(shape_angles, dtype=float))
    if b.shape[1] == 0:
        return l.copy()
    off = tessellation_leg_offsets(b, row_height)
    off = np.concatenate([off[:, :1], off, off[:, -1:]], axis=1)
    return l + off[:, 1:] - off[:, :-1]


def miura_tessellation(
    lengths: Sequence[float],
    shape_angles: Sequence[float],
    entry_flag: int,
    row_height: float,
    rows: int,
    start: tuple[float, float] = (0.0, 0.0),
    title: str = "",
) -> CreasePattern:
    """The crease pattern of a Miura-based tessellation.

    Parameters
    ----------
    lengths : sequence of float
        ``l_0 .. l_n``, main-crease segment lengths, mm (> 0).
    shape_angles : sequence of float
        ``beta_1 .. beta_n``, degrees, each strictly between 0 and 180.
    entry_flag : int
        ``EF_0``: 1 if the first main-crease segment is a valley, 0 if a mountain.
    row_height : float
        Height of one panel row (half the unit width), mm.
    rows : int
        Number of panel rows (2 per tessellation unit), >= 1.
    start : (float, float)
        ``T_s``: where the first main crease starts, mm.
    title : str
        Stored in the pattern's metadata.

    Returns
    -------
    CreasePattern
        Faces are labelled ``c{copy}r{row}s{segment}`` (row 0 below the main
        crease of the copy, 1 above it).
    """
    l = np.asarray(lengths, dtype=float)
    beta_deg = np.asarray(shape_angles, dtype=float)
    n = len(l) - 1
    rows = _checked_rows(l, beta_deg, entry_flag, row_height, rows, start)
    h = float(row_height)
    x_joint, offsets = _joint_positions(l, beta_deg, h, start)
    _check_features(x_joint, offsets, beta_deg, entry_flag, h, rows)
    verts = _grid_vertices(x_joint, offsets, h, rows, start)
    edges, assign = _grid_edges(beta_deg, entry_flag, rows)
    cp = CreasePattern(verts, edges, assign, metadata={"title": title} if title else None)
    if cp.n_vertices != len(verts) or cp.notes:  # a feature under the tolerance: merged
        raise PatternError(
            f"the row height {h:g} mm (a TG's unit_width / 2) and the segment lengths "
            f"({float(l.min()):g} to {float(l.max()):g} mm) are too far apart in size: "
            f"vertices closer than {cp.tolerance:.3g} mm (1e-6 of the pattern's size) merge"
        )
    return cp.with_face_labels(_grid_labels(cp, n + 2))


def _grid_vertices(
    x_joint: np.ndarray, offsets: np.ndarray, h: float, rows: int, start: tuple[float, float]
) -> np.ndarray:
    """The grid's vertices (mm): line ``r`` (of ``rows + 1``), joint ``k``, at ``r * nj + k``.

    ``x_joint`` and ``offsets`` (mm) from :func:`_joint_positions`, ``h`` the row height.
    """
    nl = rows + 1  # horizontal lines
    ys = start[1] - h + h * np.arange(nl)
    is_main = (np.arange(nl) % 2) == 1
    xs = np.where(is_main[:, None], x_joint[None, :], (x_joint + offsets)[None, :])
    return np.stack([xs, np.broadcast_to(ys[:, None], xs.shape)], axis=-1).reshape(-1, 2)


def _smallest_feature(verts: np.ndarray, edges: np.ndarray, within: float) -> float:
    """The smallest distance (mm) between two vertices, or a vertex and an edge it is not
    on, if below ``within`` mm; else ``inf``. O(n log n) (trees)."""
    import shapely
    from scipy.spatial import cKDTree

    gaps, _ = cKDTree(verts).query(verts, k=2, distance_upper_bound=within)
    best = float(gaps[:, 1].min())
    lines = shapely.linestrings(verts[edges])
    points = shapely.points(verts)
    v, e = shapely.STRtree(lines).query(points, predicate="dwithin", distance=within)
    other = (edges[e, 0] != v) & (edges[e, 1] != v)
    if other.any():
        best = min(best, float(shapely.distance(points[v[other]], lines[e[other]]).min()))
    return best


def _check_features(
    x_joint: np.ndarray,
    offsets: np.ndarray,
    beta_deg: np.ndarray,
    entry_flag: int,
    h: float,
    rows: int,
) -> None:
    """PatternError when ``rows`` rows would make the pattern so large that its
    tolerance (``DEFAULT_RELATIVE_TOLERANCE`` of its size) comes within
    :data:`MIN_FEATURE_TOLERANCES` of its smallest feature, which one copy (two
    rows) has already: its vertices would be merged. Lengths in mm, angles in degrees.
    A single copy finer than that is left to the pattern's own checks (as before).
    """
    from origami_cad.pattern.model import DEFAULT_RELATIVE_TOLERANCE as rel

    unit = _grid_vertices(x_joint, offsets, h, 2, (0.0, 0.0))
    width = float(np.ptp(unit[:, 0]))
    tol = rel * math.hypot(width, rows * h)
    if rows <= 2 or tol <= rel * math.hypot(width, 2 * h):
        return
    edges = _grid_edges(beta_deg, entry_flag, 2)[0]
    feature = _smallest_feature(unit, edges, MIN_FEATURE_TOLERANCES * tol)
    if feature > MIN_FEATURE_TOLERANCES * tol:
        return
    if feature <= MIN_FEATURE_TOLERANCES * rel * math.hypot(width, 2 * h):
        return  # one copy is that fine already: not a matter of the row count
    top = math.sqrt(max((feature / MIN_FEATURE_TOLERANCES / rel) ** 2 - width**2, 0.0)) / h
    raise PatternError(
        f"{rows:,} rows make the pattern {rows * h:.4g} mm tall: vertices closer than "
        f"{tol:.3g} mm (1e-6 of its size) would merge, and its smallest feature is "
        f"{feature:.3g} mm (it must be {MIN_FEATURE_TOLERANCES:g} times the tolerance): at "
        f"most {int(top):,} rows ({int(top) // 2:,} TG copies)"
    )


def _checked_rows(
    l: np.ndarray,
    beta_deg: np.ndarray,
    entry_flag: int,
    row_height: float,
    rows: int,
    start: tuple[float, float],
) -> int:
    """``rows`` as an int once every input of :func:`miura_tessellation` is valid.

    ``l`` in mm, ``beta_deg`` in degrees, ``row_height`` in mm, ``start`` in mm;
    PatternError naming the first bad input otherwise.
    """
    n = len(l) - 1
    if n < 0:
        raise PatternError("at least one transition vector (segment length) is needed")
    if beta_deg.shape != (n,):
        raise PatternError(f"{n + 1} segment lengths need {n} shape angles, got {beta_deg.size}")
    for k, v in enumerate(l):
        if not (math.isfinite(v) and v > 0):
            raise PatternError(f"lengths[{k}] (l_{k}) must be > 0 mm, got {v}")
    for k, b in enumerate(beta_deg):
        if not (0.0 < b < 180.0):
            raise PatternError(
                f"shape_angles[{k}] (beta_{k + 1}) must lie in (0, 180) deg, got {b}"
            )
    if entry_flag not in (0, 1):
        raise PatternError(f"entry_flag must be 0 or 1, got {entry_flag}")
    if not (math.isfinite(row_height) and row_height > 0):
        raise PatternError(f"row height must be > 0 mm, got {row_height}")
    if isinstance(rows, bool) or int(rows) != rows or rows < 1:
        raise PatternError(f"rows must be a whole number >= 1, got {rows}")
    rows = int(rows)
    if rows * (n + 1) > MAX_PANELS:
        raise PatternError(
            f"{rows} rows x {n + 1} segments = {rows * (n + 1):,} panels, more than the "
            f"limit of {MAX_PANELS:,}"
        )
    if (rows + 1) * (n + 2) > MAX_VERTICES:
        raise PatternError(
            f"{rows} rows x {n + 1} segments make {(rows + 1) * (n + 2):,} vertices, more "
            f"than the limit of {MAX_VERTICES:,} (MAX_VERTICES)"
        )
    if not all(math.isfinite(float(v)) for v in start):
        raise PatternError(f"start {tuple(start)} is not a finite point")
    return rows


def _joint_positions(
    l: np.ndarray, beta_deg: np.ndarray, h: float, start: tuple[float, float]
) -> tuple[np.ndarray, np.ndarray]:
    """``(x_joint, offsets)``: x of the ``n + 2`` joints on the main crease, mm,
    and the x shift of each leg's ends on the neighbouring lines, mm.

    ``l`` in mm, ``beta_deg`` in degrees, ``h`` the row height in mm. PatternError
    when two legs cross.
    """
    n = len(l) - 1
    x_joint = np.concatenate([[0.0], np.cumsum(l)]) + start[0]  # n + 2 joints incl. ends
    offsets = np.zeros(n + 2)
    if n:
        offsets[1:-1] = tessellation_leg_offsets(np.radians(beta_deg), h)
        offsets[0], offsets[-1] = offsets[1], offsets[-2]  # ends follow the nearest legs
    gaps = leg_gaps(l, np.radians(beta_deg), h)[0]
    bad = np.flatnonzero(gaps <= 1e-9 * max(1.0, float(l.sum())))
    if bad.size:
        k = int(bad[0])
        raise PatternError(
            f"the legs of joints {k} and {k + 1} cross (vector {k}, l_{k} = {l[k]:g} mm, is too "
            f"short for shape angles near 0 or 180 deg at this unit width)"
        )
    return x_joint, offsets


def _grid_edges(beta_deg: np.ndarray, entry_flag: int, rows: int) -> tuple[np.ndarray, np.ndarray]:
    """``(edges, assignments)`` of the tessellation grid, horizontal edges first.

    Vertex ``r * (n + 2) + k`` is line ``r``, joint ``k``; ``beta_deg`` (degrees)
    picks each leg's assignment, ``entry_flag`` the first main segment's.
    """
    n = len(beta_deg)
    nl = rows + 1
    nj = n + 2
    is_main = (np.arange(nl) % 2) == 1

    def vid(r: np.ndarray | int, k: np.ndarray | int) -> np.ndarray:
        return np.asarray(r) * nj + np.asarray(k)

    seg_type = np.where((np.arange(n + 1) + entry_flag) % 2 == 1, "V", "M")  # EF_k alternates
    opposite = np.where(seg_type == "V", "M", "V")
    # horizontal edges
    r_idx, k_idx = np.meshgrid(np.arange(nl), np.arange(n + 1), indexing="ij")
    h_edges = np.stack([vid(r_idx, k_idx), vid(r_idx, k_idx + 1)], axis=-1).reshape(-1, 2)
    h_assign = np.where(is_main[:, None], seg_type[None, :], opposite[None, :]).astype("<U1")
    h_assign[0, :] = "B"
    h_assign[-1, :] = "B"
    # vertical edges (legs and short ends)
    r_idx, k_idx = np.meshgrid(np.arange(rows), np.arange(nj), indexing="ij")
    v_edges = np.stack([vid(r_idx, k_idx), vid(r_idx + 1, k_idx)], axis=-1).reshape(-1, 2)
    leg_type = np.empty(nj, dtype="<U1")
    leg_type[0] = leg_type[-1] = "B"
    if n:
        before, after = seg_type[:-1], seg_type[1:]
        leg_type[1:-1] = np.where(beta_deg <= 90.0, before, after)
    v_assign = np.broadcast_to(leg_type[None, :], (rows, nj))
    edges = np.vstack([h_edges, v_edges])
    assign = np.concatenate([h_assign.ravel(), v_assign.ravel()])
    return edges, assign


def _grid_labels(cp: CreasePattern, n_joints: int) -> list[str]:
    # vertex r * n_joints + k is line r, joint k (normalisation keeps the order of a
    # grid that needs no repair); each panel's lowest vertex is its lower-left corner
    labels = []
    for ring in cp.faces:
        r, k = divmod(int(ring.min()), n_joints)
        labels.append(f"c{r // 2}r{r % 2}s{k}")
    return labels


def _check_panel_sizes(
    rows: int, columns: int, panel_length: float, panel_width: float, sector_angle: float
) -> None:
    """PatternError naming ``panel_width`` or ``panel_length`` (mm) when it is so small
    beside the whole pattern that its vertices would merge (the pattern's tolerance is
    ``DEFAULT_RELATIVE_TOLERANCE`` of its size; a feature must be
    :data:`MIN_FEATURE_TOLERANCES` times that)."""
    from origami_cad.pattern.model import DEFAULT_RELATIVE_TOLERANCE as rel

    lean = panel_width / math.tan(math.radians(sector_angle))
    size = math.hypot(columns * panel_length + lean, rows * panel_width)
    least = MIN_FEATURE_TOLERANCES * rel * size
    for key, value in (("panel_width", panel_width), ("panel_length", panel_length)):
        if not value > least:
            raise PatternError(
                f"{key} = {value:g} mm is too small beside a pattern {size:.4g} mm across: "
                f"vertices closer than {rel * size:.3g} mm (1e-6 of its size) merge; it "
                f"must exceed {least:.3g} mm"
            )


def miura_pattern(
    rows: int,
    columns: int,
    panel_length: float,
    panel_width: float,
    sector_angle: float,
    entry_flag: int = 1,
) -> CreasePattern:
    """The classic Miura-ori.

    Parameters
    ----------
    rows : int
        Panel rows (across the straight crease lines), >= 1.
    columns : int
        Panel columns (along the straight crease lines), >= 1.
    panel_length : float
        Length of a panel along the straight creases, mm.
    panel_width : float
        Height of a panel row, perpendicular to the straight creases, mm.
    sector_angle : float
        Acute angle between the straight creases and the zigzag creases, degrees
        (0 < angle < 90).
    entry_flag : int
        1: the first straight segment of each main crease is a valley; 0: mountain.

    Returns
    -------
    CreasePattern
        ``rows * panel_width`` mm high; each straight crease is
        ``columns * panel_length`` mm long, the zigzag ends lean by
        ``panel_width / tan(sector_angle)``. Lower-left corner at the origin.

    Examples
    --------
    >>> cp = miura_pattern(4, 6, 20.0, 30.0, 60.0)
    >>> [round(v, 3) for v in cp.bounds]
    [0.0, 0.0, 137.321, 120.0]
    """
    if columns < 1:
        raise PatternError(f"columns must be >= 1, got {columns}")
    if not 0.0 < sector_angle < 90.0:
        raise PatternError(f"sector_angle must lie in (0, 90) deg, got {sector_angle}")
    _check_panel_sizes(rows, columns, panel_length, panel_width, sector_angle)
    betas = [sector_angle] * (columns - 1)
    return miura_tessellation(
        [panel_length] * columns,
        betas,
        entry_flag,
        panel_width,
        rows,
        start=(0.0, panel_width),
        title=f"Miura-ori {rows} x {columns}",
    )
