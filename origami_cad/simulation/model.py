"""Bar-and-hinge model of a printed crease pattern (Schenk and Guest; Liu and Paulino).

Every panel is triangulated. Bars on every triangle edge carry axial stiffness;
fold hinges on the creases are rotational springs (per unit length) with a
rest angle; stiff facet hinges on the panels' diagonals keep them flat. Units:
mm, N, N mm (energy in mJ), radians inside.

Defaults reproduce a printed TPU-crease, PLA-panel structure (paper Fig. 4):
PLA panels (E = 3500 MPa, 2.2 mm thick) and TPU 95A creases (E = 26 MPa,
0.4 mm thick over a 7 mm hinge zone between mid-layers).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import shapely

from origami_cad._args import Arg, check_fields
from origami_cad.errors import PatternError, SimulationError
from origami_cad.fabrication.params import DENSITY_G_CM3, FabricationParams
from origami_cad.pattern.model import CreasePattern
from origami_cad.pattern.triangles import triangulate_panel

__all__ = ["SimulationParams", "Structure", "build_structure", "check_crease_law"]

_PRINTED = FabricationParams()  # the default printed sheet (paper Fig. 4)

_POSITIVE = Arg(min=0.0, open_min=True, max=1e12, optional=False)
#: What each field of :class:`SimulationParams` must be (its unit in the class's docstring).
_FIELDS = {
    "panel_modulus": _POSITIVE,
    "panel_thickness": Arg(min=0.0, open_min=True, max=1e4, optional=False),
    "crease_modulus": _POSITIVE,
    "crease_thickness": Arg(min=0.0, open_min=True, max=1e4, optional=False),
    "hinge_zone": Arg(min=0.0, open_min=True, max=1e4, optional=False),
    "string_axial_stiffness": _POSITIVE,
    "fold_limit": Arg(min=0.0, open_min=True, max=180.0, optional=False),
    "limit_margin": Arg(min=0.0, max=180.0, optional=False),
    "density": Arg(min=0.0, open_min=True, max=1e3, optional=False),
    "gravity": Arg(min=-1e9, max=1e9, optional=False),
    "ground": Arg(min=-1e6, max=1e6),
    "friction": Arg(min=0.0, max=100.0, optional=False),
    "ground_stiffness": _POSITIVE,
    "slip": Arg(min=0.0, open_min=True, max=1e6, optional=False),
}


@dataclass(frozen=True)
class SimulationParams:
    """Physical parameters (mm, N, MPa = N/mm^2; angles in degrees at the edges).

    Attributes
    ----------
    panel_modulus : float
        Young's modulus of the panels, MPa (PLA 3500).
    panel_thickness : float
        Panel thickness, mm (the printed sheet's h; 2.2 by default).
    crease_modulus : float
        Young's modulus of the crease material, MPa (TPU 95A about 26).
    crease_thickness : float
        Crease layer thickness, mm (the printed sheet's t; 0.4 by default).
    hinge_zone : float
        Width of the bending zone of a crease, mm (2 (b + m): 7 for b = 3, m = 0.5).
    string_axial_stiffness : float
        ``EA`` of a string, N (a 0.5 mm UHMWPE braid: about 0.1 mm^2 of fibre at
        an effective 60 GPa, i.e. about 3.5 % stretch at its 200 N breaking load:
        6000).
    fold_limit : float
        Default fold limit of every crease, degrees (eq. 6's theta_max of the printed
        sheet: 146.6 for b = 3, h = 2.2, t = 0.4).
    limit_margin : float
        The barrier starts this many degrees before the limit, degrees (0: at the
        limit; the barrier is quadratic, so energy and moment stay continuous).
    density : float
        Panel density, g/cm^3 (PLA's, from ``fabrication.params``).
    gravity : float
        Gravitational acceleration along -z, mm/s^2 (0: none; 9810 on Earth).
    ground : float or None
        Height of a ground plane, mm (None: no ground). The panels' bottom faces
        rest on it: nodes on the mid-surface stay half a panel thickness above it.
    friction : float
        Coulomb friction coefficient between the structure and the ground (0: none).
    ground_stiffness : float
        Penalty stiffness of the ground per node, N/mm.
    slip : float
        Friction's stick-slip regularisation: a node pushed sideways below
        ``friction x normal force`` creeps by about this much per step, mm.
    hole_friction : float
        Friction coefficient of a string sliding through a panel's hole (the capstan
        law, :mod:`origami_cad.strings.friction`; 0: none).
    crease_law : tuple of (float, float)
        The creases' softening law: points ``(fold angle, degrees; stiffness factor)``,
        the first at 0 deg, the angles increasing, the factors >= 0. A crease's
        stiffness (the slope of its moment) is :attr:`crease_stiffness` times the
        factor, piecewise linear in the fold angle and constant past the last point
        (:func:`~origami_cad.simulation.mechanics.crease_law`); the default ``((0, 1),)``
        is the linear spring.
    """

    panel_modulus: float = 3500.0
    panel_thickness: float = _PRINTED.height
    crease_modulus: float = 26.0
    crease_thickness: float = _PRINTED.thickness
    hinge_zone: float = 2.0 * (_PRINTED.bias + _PRINTED.midlayer_bias)
    string_axial_stiffness: float = 6000.0
    fold_limit: float = math.degrees(_PRINTED.theta_max)
    limit_margin: float = 0.0
    density: float = DENSITY_G_CM3["PLA"]
    gravity: float = 0.0
    ground: float | None = None
    friction: float = 0.5
    ground_stiffness: float = 100.0
    slip: float = 1e-3
    hole_friction: float = 0.0
    crease_law: tuple[tuple[float, float], ...] = ((0.0, 1.0),)

    def __post_init__(self) -> None:
        check_fields(self, SimulationError, _FIELDS)
        object.__setattr__(self, "crease_law", check_crease_law(self.crease_law))

    def law_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """The crease law as the solver takes it: angles (P,) rad, factors (P,)."""
        law = np.array(self.crease_law, dtype=float).reshape(-1, 2)
        return np.radians(law[:, 0]), law[:, 1].copy()

    @classmethod
    def from_fabrication(cls, fab: FabricationParams, **overrides) -> SimulationParams:
        """The parameters of a sheet printed with ``fab``: one source for h, t, b and eq. 6.

        ``panel_thickness = h``, ``crease_thickness = t``, ``hinge_zone = 2 (b + m)``,
        ``fold_limit`` = eq. 6's ``theta_max`` in degrees and the panels' density that
        of PLA; ``overrides`` set any other field (materials, loads).

        >>> p = SimulationParams.from_fabrication(FabricationParams(bias=2.0))
        >>> round(p.fold_limit, 1), p.hinge_zone
        (131.5, 5.0)
        """
        values = {
            "panel_thickness": fab.height,
            "crease_thickness": fab.thickness,
            "hinge_zone": 2.0 * (fab.bias + fab.midlayer_bias),
            "fold_limit": math.degrees(fab.theta_max),
            "density": DENSITY_G_CM3["PLA"],
        }
        values.update(overrides)
        return cls(**values)

    @classmethod
    def for_route(cls, route, **overrides) -> SimulationParams:
        """The sheet a route file describes, with the same fold limit as the DCQC model.

        With the route's ``[fabrication]`` table, :meth:`from_fabrication` (eq. 6's
        ``theta_max`` on every crease); without it the default materials and no printed
        fold limit: the creases may fold up to flat (180 deg), the limit of the
        pattern's folder at p = 1 that the DCQC model takes then
        (:func:`~origami_cad.strings.dcqc.fold_limit`). ``overrides`` set any field.
        """
        if route.fabrication is not None:
            return cls.from_fabrication(route.fabrication, **overrides)
        return cls(**{"fold_limit": 180.0, **overrides})

    @property
    def crease_stiffness(self) -> float:
        """Rotational stiffness of a crease per unit length, N mm / rad / mm: E t^3 / (12 w)."""
        return self.crease_modulus * self.crease_thickness**3 / (12.0 * self.hinge_zone)

    def dcqc_stiffness(self) -> dict[str, float]:
        """The same creases and strings for the DCQC model: keywords of
        :func:`~origami_cad.strings.simulate_dcqc` (``crease_stiffness``, N mm / rad / mm,
        and ``string_stiffness``, the strings' EA in N), so that both string models fold
        one sheet with one set of materials.
        """
        return {
            "crease_stiffness": self.crease_stiffness,
            "string_stiffness": self.string_axial_stiffness,
            "hole_friction": self.hole_friction,
        }

    @property
    def panel_bending(self) -> float:
        """Bending stiffness of a panel, N mm: E h^3 / 12."""
        return self.panel_modulus * self.panel_thickness**3 / 12.0


def check_crease_law(law, where: str = "SimulationParams: crease_law"):
    """``law`` as a tuple of ``(degrees, factor)`` points, or a :class:`SimulationError`
    naming ``where``: the first at 0 deg, the angles increasing up to 180 deg, the
    factors finite and >= 0, at least one point."""
    try:
        points = tuple((float(a), float(f)) for a, f in law)
    except (TypeError, ValueError, OverflowError):
        raise SimulationError(f"{where}: expected (degrees, factor) pairs") from None
    if not points or points[0][0] != 0.0:
        raise SimulationError(f"{where}: the first point must be at 0 deg")
    for i, (a, f) in enumerate(points):
        if not (math.isfinite(a) and math.isfinite(f) and f >= 0 and a <= 180.0):
            raise SimulationError(
                f"{where}: point {i} ({a:g} deg, {f:g}): the angle must lie in [0, 180] deg "
                "and the factor be finite and >= 0"
            )
        if i and a <= points[i - 1][0]:
            raise SimulationError(f"{where}: point {i}: the angles must increase")
    return points


@dataclass
class Structure:
    """The bar-and-hinge model (plain arrays): nodes are the pattern's vertices."""

    x0: np.ndarray  # (n, 3) flat positions, mm
    triangles: np.ndarray  # (T, 3)
    bars: np.ndarray  # (B, 2)
    bar_rest: np.ndarray  # (B,) mm
    bar_k: np.ndarray  # (B,) N/mm
    hinges: np.ndarray  # (H, 4)
    hinge_k: np.ndarray  # (H,) N mm / rad
    hinge_rest: np.ndarray  # (H,) rad
    hinge_limit: np.ndarray  # (H,) rad (inf: none)
    hinge_edge: np.ndarray  # (H,) pattern edge, -1 for facet hinges
    weight: np.ndarray  # (n,) N
    fixed: np.ndarray  # (n,) bool
    limit_k: float = 0.0
    limit_margin: float = 0.0
    notes: list[str] = field(default_factory=list)
    hinge_soft: np.ndarray | None = None  # (H,) bool: the creases that follow the law
    law_angles: np.ndarray = field(default_factory=lambda: np.zeros(1))  # (P,) rad
    law_factors: np.ndarray = field(default_factory=lambda: np.ones(1))  # (P,)

    def __post_init__(self) -> None:
        if self.hinge_soft is None:
            self.hinge_soft = np.zeros(len(self.hinges), dtype=bool)

    @property
    def folds(self) -> np.ndarray:
        return self.hinge_edge >= 0


def _triangulate(
    cp: CreasePattern, ring: np.ndarray, label: str, size: float
) -> list[tuple[int, int, int]]:
    """Panel ``ring``'s triangles; ``size`` is the pattern's (mm), for the zero-area check."""
    if shapely.Polygon(cp.vertices[ring]).area <= 1e-6 * max(size, 1.0) ** 2:
        raise PatternError(f"panel {label} has zero area: it cannot be simulated")
    return triangulate_panel(cp, ring)


def build_structure(
    cp: CreasePattern,
    params: SimulationParams | None = None,
    fixed_panel: str | None = None,
    fold_limits: dict[int, float] | None = None,
    free: bool = False,
) -> Structure:
    """Build the bar-and-hinge model of ``cp``.

    Parameters
    ----------
    cp : CreasePattern
        The pattern (mm).
    params : SimulationParams
        Materials and loads.
    fixed_panel : str, optional
        Label of the panel held in place (default: the panel nearest the pattern's
        centroid).
    fold_limits : dict, optional
        Fold limit of particular creases, ``{edge index: degrees}`` (blockers);
        the others use ``params.fold_limit``.
    free : bool
        Hold no panel: the structure rests on the ground (needs gravity and a
        ground plane, which :func:`~origami_cad.simulation.simulate` checks).
    """
    params = params or SimulationParams()
    if not cp.faces:
        raise PatternError("the pattern has no panels to simulate")
    tris = _panel_triangles(cp)
    x0 = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    tri_area = 0.5 * np.abs(
        np.cross(x0[tris[:, 1]] - x0[tris[:, 0]], x0[tris[:, 2]] - x0[tris[:, 0]])[:, 2]
    )
    bars, bar_rest, bar_k = _bars(x0, tris, tri_area, params)
    hinges, k_fold, hedge, hlimit = _hinges(cp, x0, tris, params, fold_limits)
    # weights: a third of each triangle's mass on its nodes
    weight = np.zeros(cp.n_vertices)
    mass = tri_area * params.panel_thickness * params.density * 1e-3 / 1000.0  # kg
    np.add.at(weight, tris.ravel(), np.repeat(mass / 3.0, 3) * params.gravity / 1000.0)  # N
    fixed, note = _held_panel(cp, fixed_panel, free)
    law_angles, law_factors = params.law_arrays()
    return Structure(
        x0=x0,
        triangles=tris,
        bars=bars,
        bar_rest=bar_rest,
        bar_k=bar_k,
        hinges=hinges,
        hinge_k=k_fold,
        hinge_rest=np.zeros(len(hinges)),
        hinge_limit=hlimit,
        hinge_edge=hedge,
        weight=weight,
        fixed=fixed,
        # a blocker or a closed chamfer is rigid: the barrier out-stiffens the panels
        limit_k=1e3 * float(max(np.max(k_fold), 1.0)),
        limit_margin=math.radians(params.limit_margin),
        notes=[note],
        hinge_soft=hedge >= 0,
        law_angles=law_angles,
        law_factors=law_factors,
    )


def _panel_triangles(cp: CreasePattern) -> np.ndarray:
    """Every panel triangulated: node triples (t, 3), panel by panel."""
    tris, size = [], cp.size  # (computed once: it measures every vertex)
    for fi, ring in enumerate(cp.faces):
        tris.extend(_triangulate(cp, ring, cp.face_labels[fi], size))
    return np.array(tris, dtype=np.int64)


def _bars(x0: np.ndarray, tris: np.ndarray, tri_area: np.ndarray, params: SimulationParams):
    """The unique triangle edges (b, 2), their rest lengths (b,) mm and axial stiffness
    (b,) N/mm, ``E h A / L^2`` from the area each carries (a third of each triangle's).
    """
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    key = np.sort(e, axis=1)
    bars, inverse = np.unique(key, axis=0, return_inverse=True)
    bar_rest = np.linalg.norm(x0[bars[:, 1]] - x0[bars[:, 0]], axis=1)
    carried = np.zeros(len(bars))
    np.add.at(carried, inverse, np.tile(tri_area / 3.0, 3))
    bar_k = params.panel_modulus * params.panel_thickness * carried / bar_rest**2
    return bars, bar_rest, bar_k


def _hinges(cp, x0, tris, params: SimulationParams, fold_limits):
    """Hinges ``(i, j, k, l)`` (h, 4) on every interior triangle edge, their stiffness
    (h,) N mm/rad, pattern edge (h,) (-1: a diagonal inside a panel, a stiff facet
    hinge) and fold limit (h,) rad (``fold_limits`` ``{edge: degrees}`` first).

    Vectorised: each triangle's directed sides ``i -> j`` (its third vertex ``k`` on the
    left), in triangle order; a hinge where the reverse side ``j -> i`` (third vertex
    ``l``) exists, listed at its side with ``i < j``.
    """
    n = len(x0)
    tris = np.asarray(tris, dtype=np.int64).reshape(-1, 3)
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    # directed sides in the order (a, b), (b, c), (c, a) per triangle
    side_i = np.stack([a, b, c], axis=1).ravel()
    side_j = np.stack([b, c, a], axis=1).ravel()
    third = np.stack([c, a, b], axis=1).ravel()
    key = side_i * n + side_j
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    # the last side of each key wins, as a dict would keep it
    last = np.r_[sorted_key[1:] != sorted_key[:-1], True]
    uniq_key, uniq_pos = sorted_key[last], order[last]
    first = np.sort(order[np.r_[True, sorted_key[1:] != sorted_key[:-1]]])  # insertion order
    pick = uniq_pos[np.searchsorted(uniq_key, key[first])]
    i, j, k = side_i[first], side_j[first], third[pick]
    reverse = j * n + i
    at = np.minimum(np.searchsorted(uniq_key, reverse), max(len(uniq_key) - 1, 0))
    has = (i < j) & (len(uniq_key) > 0) & (uniq_key[at] == reverse)
    i, j, k = i[has], j[has], k[has]
    l = third[uniq_pos[at[has]]]
    # the pattern edge along each hinge (a pattern's edges are unique once normalised)
    lo, hi = np.minimum(cp.edges[:, 0], cp.edges[:, 1]), np.maximum(cp.edges[:, 0], cp.edges[:, 1])
    ekey = lo * n + hi
    eorder = np.argsort(ekey, kind="stable")
    hkey = np.minimum(i, j) * n + np.maximum(i, j)
    pe = np.full(len(i), -1, dtype=np.int64)
    if len(ekey):
        pos = np.minimum(np.searchsorted(ekey[eorder], hkey), len(ekey) - 1)
        found = ekey[eorder][pos] == hkey
        pe[found] = eorder[pos[found]]
    crease = (pe >= 0) & np.isin(cp.assignments[np.maximum(pe, 0)], ("M", "V", "U", "F", "J"))
    axis = x0[j] - x0[i]
    length = np.linalg.norm(axis, axis=1)
    h1 = np.abs(np.cross(axis, x0[k] - x0[i])[:, 2]) / length
    h2 = np.abs(np.cross(axis, x0[l] - x0[i])[:, 2]) / length
    facet_k = params.panel_bending * length / np.maximum(0.5 * (h1 + h2), 1e-6)
    hk = np.where(crease, params.crease_stiffness * length, facet_k)
    default_limit = math.radians(params.fold_limit)
    limits = {int(e): math.radians(v) for e, v in (fold_limits or {}).items()}
    hlimit = np.full(len(i), default_limit)
    for e, v in limits.items():
        hlimit[crease & (pe == e)] = v
    hlimit[~crease] = math.inf
    return (
        np.stack([i, j, k, l], axis=1).astype(np.int64).reshape(-1, 4),
        hk.astype(float),
        np.where(crease, pe, -1).astype(np.int64),
        hlimit,
    )


def _held_panel(cp: CreasePattern, fixed_panel: str | None, free: bool):
    """The held nodes (n,) bool and the note saying which panel is held.

    ``fixed_panel`` by label, by default the panel nearest the centroid; none if ``free``.
    """
    fixed = np.zeros(cp.n_vertices, dtype=bool)
    if free:
        return fixed, "no panel is held: the structure rests on the ground"
    if fixed_panel is None:
        centre = cp.vertices.mean(axis=0)
        dist = np.linalg.norm(cp.face_centroids() - centre, axis=1)
        fixed_face = int(np.argmin(dist))
    else:
        fixed_face = cp.face_index(fixed_panel)
    fixed[cp.faces[fixed_face]] = True
    return fixed, f"panel {cp.face_labels[fixed_face]} is held in place"
