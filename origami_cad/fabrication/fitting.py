"""Fit every panel to the print: the inner bias, shell wall and mid-layer margin each gets.

A panel too small for the parameters is not refused at once: it gives up, in order, the
largest inner bias (down to :data:`MIN_BIAS`), its automatic hole, the thickest shell wall
(down to :data:`MIN_SHELL`), the widest mid-layer margin (down to
:data:`MIN_MIDLAYER_BIAS`), and last its PLA: a panel too small for any infill is printed
in TPU alone (its halves solid TPU, no mid-layer, the crease sheet running through it).
Each step keeps the others as large as then fits. Only a panel too small even for its TPU
halves at :data:`MIN_BIAS` (or for a hole it was given) is refused, naming the width at
which the pattern prints. :func:`panel_biases` does it; :func:`~origami_cad.fabrication.
plan.plan_panels` uses it and warns about every panel it changed.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.ops import polylabel

from origami_cad.errors import PatternError
from origami_cad.fabrication.panels import FREE_EDGES, panel_fits, panel_outline
from origami_cad.fabrication.params import FabricationParams, layer_height
from origami_cad.pattern.model import CreasePattern

__all__ = [
    "MIN_BIAS",
    "MIN_MIDLAYER_BIAS",
    "MIN_SHELL",
    "PanelBiases",
    "panel_biases",
]

#: The smallest inner bias a panel gets, mm, when the default does not fit it. Eq. 6 gives
#: each half of a crease a fold limit of ``atan(2 b / (h - t))``: at 0.2 mm and the default
#: h - t = 1.8 mm, 12.5 deg, so a crease between two such panels folds to 25.1 deg before
#: their chamfers meet (146.6 deg at the default 3 mm); a smaller chamfer is under half a
#: 0.4 mm nozzle's line, which a slicer no longer draws as a slope.
MIN_BIAS = 0.2

#: The thinnest shell wall a panel gets, mm, when it is too small for ``params.shell`` even
#: at :data:`MIN_BIAS`: one line of a 0.4 mm nozzle, the thinnest wall a slicer still
#: draws as a perimeter along the chamfer (thinner, it is dropped or left to gap fill and
#: the TPU no longer wraps the infill), and four 0.1 mm layers of top skin. A thinned wall
#: is a whole number of the print's layers (:func:`~origami_cad.fabrication.params.
#: layer_height`), so no layer straddles the TPU and the PLA.
MIN_SHELL = 0.4

#: The narrowest mid-layer margin ``m`` a panel gets, mm, when it is too small for
#: ``params.midlayer_bias`` even at :data:`MIN_BIAS` and :data:`MIN_SHELL`. The margin is
#: what the paper's mid-layer leaves the crease sheet inside the panel ("slightly larger
#: than the infills to leave more space for printing creases"): at 0.2 mm and ``b`` =
#: :data:`MIN_BIAS` the mid-layer stops 0.4 mm from the crease, one 0.4 mm nozzle line of
#: TPU on each side of it (two between two such panels), about where the infill stops on
#: the crease layer at :data:`MIN_SHELL` (0.41 mm). A panel too small for a mid-layer even
#: then is too small for its infill too, and is printed in TPU alone.
MIN_MIDLAYER_BIAS = 0.2


def _holes_by_face(cp: CreasePattern, params: FabricationParams) -> dict[int, list]:
    """The given holes ((x, y, diameter) mm) of each panel: ``holes`` as points or
    ``"pattern"`` (empty for ``"auto"`` and ``"none"``)."""
    spec = params.holes
    if isinstance(spec, str) and spec != "pattern":
        return {}
    points = (
        [(h.x, h.y, h.diameter) for h in cp.holes]
        if spec == "pattern"
        else [(x, y, params.hole_diameter) for x, y in spec]
    )
    faces = cp.faces_of_points(np.array([(x, y) for x, y, _ in points]).reshape(-1, 2))
    out: dict[int, list] = {}
    for pt, fi in zip(points, faces.tolist(), strict=True):
        out.setdefault(int(fi), []).append(pt)
    return out


@dataclass(frozen=True)
class PanelBiases:
    """The inner bias, shell wall and mid-layer margin of every panel, the panels too small
    for an automatic hole and those printed in TPU alone.

    ``bias`` (F,) mm; ``holeless`` the panels (face indices) printed without their
    automatic hole, because not even :data:`MIN_BIAS` leaves room for it; ``shell`` (F,)
    mm, or ``None`` when every panel has ``params.shell``; ``midlayer`` (F,) mm, each
    panel's mid-layer margin ``m``, or ``None`` when every panel has
    ``params.midlayer_bias``; ``tpu_only`` the panels printed in TPU alone (no infill, no
    mid-layer: their ``shell`` and ``midlayer`` are NaN).
    """

    bias: np.ndarray
    holeless: frozenset[int] = frozenset()
    shell: np.ndarray | None = None
    midlayer: np.ndarray | None = None
    tpu_only: frozenset[int] = frozenset()

    def reduced(self, default: float) -> np.ndarray:
        """The panels (face indices) whose bias is below ``default`` mm."""
        return np.flatnonzero(self.bias < default - 1e-12)

    def thinned(self, default: float) -> np.ndarray:
        """The panels (face indices) whose shell wall is below ``default`` mm (not those in
        TPU alone)."""
        if self.shell is None:
            return np.zeros(0, dtype=np.int64)
        return np.flatnonzero(self.shell < default - 1e-12)

    def narrowed(self, default: float) -> np.ndarray:
        """The panels (face indices) whose mid-layer margin is below ``default`` mm (not
        those in TPU alone)."""
        if self.midlayer is None:
            return np.zeros(0, dtype=np.int64)
        return np.flatnonzero(self.midlayer < default - 1e-12)

    def shell_of(self, fi: int, params: FabricationParams) -> float:
        """The shell wall of panel ``fi``, mm (``params.shell`` unless thinned; a panel in
        TPU alone has none: ``params.shell``, unused)."""
        if self.shell is None or not math.isfinite(self.shell[fi]):
            return params.shell
        return float(self.shell[fi])

    def midlayer_of(self, fi: int, params: FabricationParams) -> float | None:
        """The mid-layer margin of panel ``fi``, mm, when narrowed, else ``None``
        (``params.midlayer_bias``; a panel in TPU alone has none)."""
        if self.midlayer is None or not math.isfinite(self.midlayer[fi]):
            return None
        m = float(self.midlayer[fi])
        return None if m >= params.midlayer_bias - 1e-12 else m


@dataclass
class _Fit:
    """What one panel gets: shell wall, mid-layer margin (``None``: the default), whether
    its automatic hole stays, whether it is TPU alone (mm)."""

    shell: float
    midlayer: float | None = None
    hole: bool = True
    tpu_only: bool = False


def panel_biases(
    cp: CreasePattern,
    params: FabricationParams,
    minimum: float = MIN_BIAS,
    step: float = 0.01,
    min_shell: float = MIN_SHELL,
    min_midlayer: float = MIN_MIDLAYER_BIAS,
) -> PanelBiases:
    """The inner bias, shell wall and mid-layer margin of each panel, mm: ``params.bias``
    where it fits, else the largest that fits (a multiple of ``step``, found by bisection),
    down to ``minimum``.

    A panel fits a bias when it keeps every footprint (:func:`panel_outline`) and room for
    its hole (:func:`panel_fits`). With automatic holes, a panel that has no room for its
    hole even at ``minimum`` gets none (``holeless``), and the largest bias that fits it
    without. A panel too small even so gets the thickest shell wall that fits it at
    ``minimum`` (a whole number of print layers, down to ``min_shell``: with its hole if
    one fits, else without); one too small for the thinnest wall gets the widest mid-layer
    margin that fits it there (a multiple of ``step``, down to ``min_midlayer``), then the
    thickest wall that fits with it; one too small even then is printed in TPU alone (no
    infill, no mid-layer, no hole: ``tpu_only``). Then the largest bias that fits with
    what it got.

    Raises
    ------
    PatternError
        Naming the first panel that fits none of these (too small for its TPU halves at
        ``minimum``, or for a hole it was given), and the width that would print it.
    """
    given = _holes_by_face(cp, params)
    n = len(cp.faces)
    out = np.full(n, float(params.bias))
    shells = np.full(n, float(params.shell))
    mids = np.full(n, float(params.midlayer_bias))
    walls = _thinner_shells(params, min_shell)
    thinnest = walls[-1] if walls else params.shell
    holeless, tpu = set(), set()
    searched: dict[tuple, tuple[_Fit, float]] = {}  # by panel shape: a grid's panels repeat
    for fi in range(n):
        holes = tuple(given.get(fi, ()))
        if panel_fits(cp, fi, params, params.bias, holes):
            continue
        key = None if holes else _shape_key(cp, fi)
        if key in searched and _copy_fits(cp, fi, params, *searched[key]):
            fit, out[fi] = searched[key]
            _record_fit(fi, fit, params, shells, mids, holeless, tpu)
            continue
        fit = _least_fit(cp, fi, params, minimum, holes, walls)
        if fit is None:
            fit = _narrower_midlayer(cp, fi, params, minimum, holes, walls, min_midlayer, step)
        if fit is None and not holes and _tpu_fits(cp, fi, params, minimum):
            fit = _Fit(math.nan, math.nan, params.holes != "auto", True)
        if fit is None:
            raise PatternError(_too_small(cp, fi, params, minimum, holes, thinnest))
        _record_fit(fi, fit, params, shells, mids, holeless, tpu)

        def fits(b: float, fi=fi, holes=holes, fit=fit) -> bool:
            if fit.tpu_only:
                return _tpu_fits(cp, fi, params, b)
            return panel_fits(
                cp, fi, params, b, holes, fit.hole, fit.shell, midlayer_bias=fit.midlayer
            )

        out[fi] = _largest(fits, minimum, params.bias, step)
        if key is not None:
            searched[key] = (fit, float(out[fi]))
    if tpu and len(tpu) == n:
        raise PatternError(_no_pla(cp, params, minimum, thinnest))
    thinned = bool(tpu) or bool(np.any(shells < params.shell - 1e-12))
    narrowed = bool(tpu) or bool(np.any(mids < params.midlayer_bias - 1e-12))
    return PanelBiases(
        out,
        frozenset(holeless),
        shells if thinned else None,
        mids if narrowed else None,
        frozenset(tpu),
    )


def _copy_fits(cp: CreasePattern, fi: int, params, fit: _Fit, bias: float) -> bool:
    """Whether panel ``fi`` fits what a panel of its shape got (``fit`` at inner bias
    ``bias``, mm): a turned copy may leave its hole a rounding error less room, and is then
    searched for itself (``plan_panels`` places every hole the fitting let through)."""
    if fit.tpu_only:
        return _tpu_fits(cp, fi, params, bias)
    return panel_fits(cp, fi, params, bias, (), fit.hole, fit.shell, midlayer_bias=fit.midlayer)


def _record_fit(fi: int, fit: _Fit, params, shells, mids, holeless: set, tpu: set) -> None:
    """Write panel ``fi``'s shell wall and mid-layer margin (mm) and its sets."""
    shells[fi] = fit.shell
    mids[fi] = params.midlayer_bias if fit.midlayer is None else fit.midlayer
    if not fit.hole:
        holeless.add(fi)
    if fit.tpu_only:
        tpu.add(fi)


def _shape_key(cp: CreasePattern, fi: int) -> tuple:
    """Panel ``fi``'s shape up to a rotation and translation of the plane: its sides'
    lengths (mm, to 1e-6) and turning angles (rad, to 1e-9), and which are creases, borders
    and cuts, from the least cyclic start. Two panels with one key fit the same biases (what
    :func:`~.panels.panel_outline` reads of a panel is its ring and its creases)."""
    pts = cp.vertices[cp.faces[fi]]
    d = np.roll(pts, -1, axis=0) - pts
    e = np.roll(d, -1, axis=0)  # the side after each side
    turn = np.arctan2(d[:, 0] * e[:, 1] - d[:, 1] * e[:, 0], np.einsum("ij,ij->i", d, e))
    assign = cp.assignments[cp.face_edges[fi]]
    kind = np.where(np.isin(assign, FREE_EDGES), assign, "crease")  # a cut has its kerf
    rows = list(
        zip(
            np.round(np.hypot(d[:, 0], d[:, 1]), 6).tolist(),
            np.round(turn, 9).tolist(),
            kind.tolist(),
            strict=True,
        )
    )
    return min(tuple(rows[k:] + rows[:k]) for k in range(len(rows)))


def _no_pla(cp: CreasePattern, params: FabricationParams, minimum: float, thinnest: float) -> str:
    """Why a pattern whose every panel would be printed in TPU alone is refused (a print
    with no rigid panel is no origami structure), and the width (mm) at which every panel
    has a PLA infill at inner bias ``minimum`` and shell wall ``thinnest`` (mm)."""
    m = _narrowest_midlayer(params)
    return (
        f"every panel is too small for a PLA infill even at the smallest inner bias, "
        f"{minimum:g} mm, shell wall, {thinnest:g} mm, and mid-layer margin, {m:g} mm, so "
        f"nothing rigid would be printed: " + _wider(cp, 0, _pla_check(params, minimum, thinnest))
    )


def _narrowest_midlayer(params: FabricationParams) -> float:
    """The narrowest mid-layer margin a panel may get, mm."""
    return min(MIN_MIDLAYER_BIAS, params.midlayer_bias)


def _pla_check(params: FabricationParams, minimum: float, shell: float) -> Callable:
    """``pla(scaled, face)``: whether a panel has a PLA infill at inner bias ``minimum``,
    shell wall ``shell`` and the narrowest mid-layer margin (mm)."""
    m = _narrowest_midlayer(params)

    def pla(scaled: CreasePattern, face: int) -> bool:
        return panel_fits(scaled, face, params, minimum, (), False, shell, midlayer_bias=m)

    return pla


def _tpu_fits(cp: CreasePattern, fi: int, params: FabricationParams, bias: float) -> bool:
    """Whether panel ``fi`` keeps its TPU halves at inner bias ``bias`` (mm)."""
    return panel_fits(cp, fi, params, bias, auto_hole=False, tpu_only=True)


def _largest(fits: Callable[[float], bool], minimum: float, top: float, step: float) -> float:
    """The largest multiple of ``step`` (mm) from ``minimum`` (which fits) to below ``top``
    that ``fits``, found by bisection."""
    lo, hi = minimum, top
    while hi - lo > step / 4:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if fits(mid) else (lo, mid)
    best = max(minimum, math.floor(lo / step + 1e-9) * step)
    while best - step >= minimum and not fits(best):
        best -= step
    while best + step < top and fits(best + step):
        best += step
    return round(best, 10)


def _thinner_shells(params: FabricationParams, min_shell: float) -> list[float]:
    """The shell walls thinner than ``params.shell`` a panel may get, thickest first, mm:
    whole numbers of print layers (:func:`layer_height`), none below ``min_shell``."""
    layer = layer_height(params)
    top = math.floor(params.shell / layer + 1e-6) - 1
    least = math.ceil(min_shell / layer - 1e-6)
    return [round(k * layer, 10) for k in range(top, max(least, 1) - 1, -1)]


def _least_fit(
    cp: CreasePattern,
    fi: int,
    params: FabricationParams,
    minimum: float,
    holes: tuple,
    walls: list[float],
    midlayer: float | None = None,
) -> _Fit | None:
    """The shell wall (mm) and whether the automatic hole stays, for panel ``fi`` at inner
    bias ``minimum`` and mid-layer margin ``midlayer`` (mm, ``None``: the default):
    ``params.shell`` with the hole, else without it (automatic holes), else the thickest of
    ``walls`` (thickest first) with the hole, else without; ``None`` when none fits. Walls
    are searched by bisection (a panel that fits a wall fits every thinner one)."""
    auto = params.holes == "auto"

    def fits(hole: bool, wall: float | None = None) -> bool:
        return panel_fits(cp, fi, params, minimum, holes, hole, wall, midlayer_bias=midlayer)

    for hole in (True, False) if auto else (True,):
        if fits(hole):
            return _Fit(params.shell, midlayer, hole)
    for hole in (True, False) if auto else (True,):
        if not walls or not fits(hole, walls[-1]):
            continue
        lo, hi = 0, len(walls) - 1  # walls[hi] fits; find the first (thickest) that fits
        while lo < hi:
            mid = (lo + hi) // 2
            lo, hi = (lo, mid) if fits(hole, walls[mid]) else (mid + 1, hi)
        return _Fit(walls[lo], midlayer, hole)
    return None


def _narrower_midlayer(
    cp: CreasePattern,
    fi: int,
    params: FabricationParams,
    minimum: float,
    holes: tuple,
    walls: list[float],
    min_midlayer: float,
    step: float,
) -> _Fit | None:
    """For panel ``fi``, too small for ``params.midlayer_bias`` at inner bias ``minimum`` and
    the thinnest wall: the widest mid-layer margin (a multiple of ``step`` from
    ``min_midlayer`` up, mm) that fits it there, with the automatic hole if one fits, then
    the thickest wall that fits with that margin; ``None`` when not even ``min_midlayer``
    fits."""
    if min_midlayer >= params.midlayer_bias:
        return None
    thinnest = walls[-1] if walls else params.shell
    for hole in (True, False) if params.holes == "auto" else (True,):

        def fits(m: float, hole=hole) -> bool:
            return panel_fits(cp, fi, params, minimum, holes, hole, thinnest, midlayer_bias=m)

        if fits(min_midlayer):
            m = _largest(fits, min_midlayer, params.midlayer_bias, step)
            return _least_fit(cp, fi, params, minimum, holes, walls, m)
    return None


def _too_small(
    cp: CreasePattern,
    fi: int,
    params: FabricationParams,
    minimum: float,
    holes: tuple = (),
    shell: float | None = None,
) -> str:
    """Why panel ``fi`` is refused at inner bias ``minimum``, shell wall ``shell`` (mm,
    default ``params.shell``) and the narrowest mid-layer margin, or in TPU alone, and what
    would print it."""
    label = cp.face_labels[fi]
    shell = params.shell if shell is None else shell
    m = _narrowest_midlayer(params)
    least = (
        f"the smallest inner bias, {minimum:g} mm, shell wall, {shell:g} mm, and mid-layer "
        f"margin, {m:g} mm"
    )
    try:
        panel_outline(cp, fi, params, minimum, tpu_only=True)
    except PatternError as exc:

        def halves(scaled: CreasePattern, face: int) -> bool:
            return _tpu_fits(scaled, face, params, minimum)

        return f"{exc} even printed in TPU alone (no infill, no mid-layer): " + _wider(
            cp, fi, halves, _pla_check(params, minimum, shell)
        )
    at = dict(shell=shell, midlayer_bias=m)
    if not panel_fits(cp, fi, params, minimum, (), False, **at):
        d = max(h[2] for h in holes)

        def room(scaled: CreasePattern, face: int) -> bool:
            found = _room(scaled, face, params, minimum, **at)
            return found is not None and found[2] >= d

        wider, width = _wider(cp, fi, room), _width_that_fits(cp, fi, room)
        if width is not None:  # where, at the width named
            x0, _, x1, _ = cp.bounds
            found = _room(cp.scaled(width / (x1 - x0)), fi, params, minimum, **at)
            if found is not None and found[2] >= d:
                x, y = found[0], found[1]
                wider += f", where it has room for a {d:g} mm hole at ({x:.3f}, {y:.3f}) mm"
        return (
            f"panel {label} has a hole but is too small for a PLA infill even at {least}, so it "
            f"has no operation region (it would be printed in TPU alone): drop its hole, or "
            f"{wider}"
        )
    x, y, room = _room(cp, fi, params, minimum, **at)
    for hx, hy, d in holes:
        if not panel_fits(cp, fi, params, minimum, ((hx, hy, d),), **at):
            return (
                f"the hole at ({hx:g}, {hy:g}) mm (diameter {d:g} mm) does not fit the operation "
                f"region of panel {label} even at {least}: it has room for a hole of up to "
                f"{room:g} mm at ({x:.3f}, {y:.3f}) mm; move it there and make it no larger"
            )
    return (
        f"panel {label}: no room for a {params.hole_diameter:g} mm hole even at {least} (room "
        f"for {room:g} mm): use a smaller --hole-diameter or --holes none"
    )


def _room(
    cp: CreasePattern, fi: int, params: FabricationParams, bias: float, **kw
) -> tuple[float, float, float] | None:
    """Where panel ``fi``'s operation region at inner bias ``bias`` (mm; ``kw``: the other
    arguments of :func:`panel_outline`) has the most room for a hole: the centre (mm) and the
    diameter (mm) of the largest disc in it, less 2 um so that the centre may be rounded to
    1 um (as the messages give it), rounded down to 1 um; ``None`` without one."""
    try:
        region = panel_outline(cp, fi, params, bias, **kw).region_polygon()
    except PatternError:
        return None
    if region.is_empty:
        return None
    part = max(shapely.get_parts(region), key=lambda p: p.area)
    pole = polylabel(part, tolerance=1e-4)
    diameter = math.floor((2.0 * part.boundary.distance(pole) - 0.002) * 1000.0) / 1000.0
    return float(pole.x), float(pole.y), diameter


def _wider(
    cp: CreasePattern,
    fi: int,
    fits: Callable[[CreasePattern, int], bool],
    pla: Callable[[CreasePattern, int], bool] | None = None,
) -> str:
    """The remedy for panel ``fi`` that does not ``fits``: the width at which every panel
    does (:func:`_scale_that_fits`) and, given ``pla``, some panel has a PLA infill (a print
    of TPU alone is refused)."""
    x0, _, x1, _ = cp.bounds
    width = _width_that_fits(cp, fi, fits)
    if width is not None and pla is not None:
        scaled = cp.scaled(width / (x1 - x0))
        if not any(pla(scaled, f) for f in range(len(cp.faces))):
            rigid = _width_that_fits(cp, 0, pla)
            width = None if rigid is None else max(width, rigid)
    if width is None:
        return f"print the pattern larger (it is {x1 - x0:.1f} mm wide: --width)"
    return f"print the pattern at least {width:g} mm wide (it is {x1 - x0:.1f} mm: --width)"


def _width_that_fits(
    cp: CreasePattern, fi: int, fits: Callable[[CreasePattern, int], bool]
) -> float | None:
    """The width (mm, :func:`_ceil3`) at which ``cp`` scaled ``fits`` every panel, found
    from panel ``fi`` (:func:`_scale_that_fits`), or ``None``."""
    x0, _, x1, _ = cp.bounds
    factor = _scale_that_fits(cp, fi, fits)
    return None if factor is None else _ceil3((x1 - x0) * factor)


def _ceil3(width: float) -> float:
    """``width`` (mm) rounded up to three significant figures, whole mm from 100 mm on."""
    digits = max(0, 2 - math.floor(math.log10(width))) if width > 0 else 0
    return math.ceil(width * 10**digits - 1e-9) / 10**digits


def _scale_that_fits(
    cp: CreasePattern, fi: int, fits: Callable[[CreasePattern, int], bool]
) -> float | None:
    """The least factor (to 1 %) by which ``cp`` scaled ``fits`` (``fits(scaled, face)``)
    panel ``fi``, and then every panel, or ``None`` beyond 64 times (or after 16 panels,
    each needing more than the last)."""
    lo, todo = 1.0, [fi]
    for _ in range(16):
        face, hi = todo[0], 2.0 * lo
        while not fits(cp.scaled(hi), face):
            lo, hi = hi, 2.0 * hi
            if hi > 64.0:
                return None
        while hi / lo > 1.01:
            mid = math.sqrt(lo * hi)
            lo, hi = (lo, mid) if fits(cp.scaled(mid), face) else (mid, hi)
        scaled = cp.scaled(hi)
        todo = [f for f in range(len(cp.faces)) if not fits(scaled, f)]
        if not todo:
            return hi
        lo = hi
    return None
