"""Origami robots as MuJoCo models (MJCF): panels, crease hinges, string tendons, TSAs.

:func:`to_mjcf` turns a design (a crease pattern and its routes), or an
:class:`MjcfSource` a caller builds (the crawler's robot:
``origami_cad.crawler.mujoco.robot_mjcf``), into MJCF text. The construction, in SI
units inside the model (m, kg, s, N; the project's mm, g and degrees are converted at
this edge):

* **Panels** are bodies, one per face, arranged along a breadth-first spanning tree of
  the panel-adjacency graph from a root panel (the source's ``body``, the route's
  ``fixed_panel``, else the panel nearest the sheet's centre). Every body's frame is
  the pattern's frame in the flat state, so a geom, site or anchor is placed by its
  pattern coordinates. Each panel shows its printed solids as visual mesh geoms (PLA
  infills and mid-layer, TPU shells and its share of the crease sheet, holes cut where
  the strings run: :func:`~.mjcf_solids.panel_solids`, which fabricates the sheet) and
  collides through two convex mesh geoms, the convex hulls of its two printed halves
  (outer face to the crease layer). Its ``inertial`` (mass, centre of mass, full
  inertia) is the exact volume integral of those solids at each material's density
  (``fabrication.params.DENSITY_G_CM3``) plus its point masses.
* **Creases** of the tree are hinge joints on the crease's axis, oriented so that a
  positive joint angle is a valley fold (radians, the sign of ``fold_angles``), with the
  crease's rotational stiffness ``E t^3 / (12 w)`` times its length
  (:attr:`SimulationParams.crease_stiffness`), a damping and a range of
  +-eq. 6's ``theta_max`` (the route's ``[fabrication]``) or the source's ``crease_limits``.
* **Loops**: each crease not in the tree is closed by two ``connect`` equality
  constraints, at its two end points (together a hinge).
* **Strings** are spatial tendons through sites: the TSA's guide (fixed in the world,
  or on the panel of an onboard TSA), then at each hole the exit on the side the string
  reaches it, and the exit on the other side where the string changes face.
* **TSAs**: one ``general`` actuator per string, on its tendon, whose control ``u`` is
  the string the TSA has taken up, m (0 at the start): force = ``kp (T0 - u - length)
  - kv velocity``, clamped to pulling only (``forcerange = [-200 N, 0]``), ``T0`` the
  tendon's length as exported and ``kp`` the string's axial stiffness ``EA / L0``
  (N/m). The servo's turns are mapped to ``u`` by
  :func:`~origami_cad.simulation.mujoco_run.tsa_controls` with eq. 8 (ring) or the onboard
  model, as the project's simulators consume string
  (:meth:`~origami_cad.strings.TSAParams.consumed`): ``u = consumed(theta, x_dis) -
  x_dis - (consumed(0, x0) - x0)``, ``x_dis`` the current guide-to-first-hole distance
  and ``x0`` the exported one. MJCF's actuator gains are affine in the control and
  eq. 8 is not, hence the user-side map; what it needs (the TSA's parameters, ``x0``)
  is stored in the model as a ``custom`` numeric named after the actuator.
* **Point masses** are massive spheres without contact; the **ground** is a plane
  with the source's friction.
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections import deque
from dataclasses import dataclass

import numpy as np

from origami_cad._args import Arg, brief_value, checked
from origami_cad._names import xml_text
from origami_cad._toml import input_file
from origami_cad.errors import SimulationError
from origami_cad.fabrication.params import FabricationParams
from origami_cad.fabrication.plan import plan_panels
from origami_cad.pattern.design import Design, load_pattern_source
from origami_cad.pattern.model import CreasePattern
from origami_cad.simulation.mjcf_solids import MassProps, panel_solids
from origami_cad.simulation.mjcf_strings import MJ, TSA_CODES, tendon_specs, tendon_xml
from origami_cad.simulation.model import SimulationParams
from origami_cad.strings.route import RouteSpec, load_route

__all__ = [
    "MJ",
    "STICK_SLIP",
    "Contact",
    "MjcfError",
    "MjcfSource",
    "load_mjcf_source",
    "printed_panels",
    "to_mjcf",
]


class MjcfError(SimulationError):
    """Input a MuJoCo model cannot be made from (names the string, hole, crease or TSA)."""


@dataclass(frozen=True)
class MjcfSource:
    """What :func:`to_mjcf` exports: a pattern, its routes and, for a body free on the
    ground (a legged robot), that body and what it carries.

    ``body`` is the root panel's label (``None``: a sheet, rooted as the module says);
    ``holes`` the string holes cut in the printed panels, mm (``None``: where the routes'
    strings run); ``crease_limits`` the range of a crease by index, degrees (others:
    eq. 6); ``masses`` the point masses ``(name, grams, panel label, (x, y) mm)``;
    ``friction`` the Coulomb coefficient of the ground (``None``: the parameters').
    """

    design: Design | None
    pattern: CreasePattern
    routes: tuple[RouteSpec, ...]
    body: str | None = None
    holes: tuple[tuple[float, float], ...] | None = None
    crease_limits: dict[int, float] = dataclasses.field(default_factory=dict)
    masses: tuple[tuple[str, float, str, tuple[float, float]], ...] = ()
    friction: float | None = None


def load_mjcf_source(source, routes=()) -> MjcfSource:
    """A design or pattern file, or a Design or CreasePattern, with its route files.

    ``routes`` are route files or :class:`RouteSpec`. A robot file is refused
    (:class:`MjcfError`): its model is ``origami_cad.crawler.mujoco.robot_mjcf``'s.
    """
    if isinstance(routes, str | bytes | os.PathLike) or not hasattr(routes, "__iter__"):
        raise MjcfError(
            f"routes must be a list of route files or RouteSpecs, got {brief_value(routes)}"
        )
    routes = list(routes)
    bad = next((r for r in routes if not isinstance(r, RouteSpec | str | os.PathLike)), None)
    if bad is not None:
        raise MjcfError(f"routes: expected route files or RouteSpecs, got {brief_value(bad)}")
    if isinstance(source, (str, os.PathLike)):
        path, _ = input_file(source, MjcfError)  # a name with a newline shown on one line
        try:
            text = path.read_text(encoding="utf-8") if path.suffix.lower() == ".toml" else ""
        except (OSError, UnicodeDecodeError) as exc:
            raise MjcfError(
                f"{path}: cannot be read as UTF-8 text ({exc.__class__.__name__})"
            ) from None
        if "[robot]" in text:
            raise MjcfError(
                f"{path}: a robot file: its MuJoCo model is origami_cad.crawler.mujoco."
                "robot_mjcf's (origami-cad mjcf reads it)"
            )
        source = load_pattern_source(path)
    design = source if isinstance(source, Design) else Design(source, None, "file")
    cp = design.pattern
    specs = [r if isinstance(r, RouteSpec) else load_route(r, cp) for r in routes]
    return MjcfSource(design, cp, tuple(specs))


@dataclass(frozen=True)
class Contact:
    """How contacts resist sliding: MuJoCo's friction cone and contact softness.

    Attributes
    ----------
    cone : str
        ``"pyramidal"`` (MuJoCo's default) or ``"elliptic"``.
    condim : int
        3: sliding friction only (no torsional or rolling).
    impratio : float
        Ratio of frictional to normal constraint impedance (> 1: stiffer friction,
        less creep in sticking).
    time_constant : float or None
        Contact ``solref`` time constant, s (None: MuJoCo's 0.02 s; it is clamped to
        two time steps).
    noslip_iterations : int
        Iterations of MuJoCo's no-slip solver (0: none), which removes the creep of
        sticking contacts that the soft constraints leave.
    """

    cone: str = "pyramidal"
    condim: int = 3
    impratio: float = 1.0
    time_constant: float | None = None
    noslip_iterations: int = 0

    def option_xml(self) -> str:
        """The ``<option>`` attributes."""
        return (
            f'cone="{self.cone}" impratio="{self.impratio:.6g}" '
            f'noslip_iterations="{self.noslip_iterations}"'
        )

    def geom_xml(self, timestep: float) -> str:
        """The contact attributes of a geom (timestep, s)."""
        out = f'condim="{self.condim}"'
        if self.time_constant is not None:
            out += f' solref="{max(self.time_constant, 2 * timestep):.6g} 1"'
        return out


#: The contact model of the exports: MuJoCo's elliptic cone is Coulomb's (the pyramid
#: approximates it) and ``impratio = 10`` makes friction ten times stiffer than the normal
#: contact, so that a sticking foot does not creep: the crawler's stride went from 1.5 to
#: 46.8 mm per cycle (docs/mujoco.md, the measured table).
STICK_SLIP = Contact(cone="elliptic", impratio=10.0)


def _panel_graph(cp: CreasePattern) -> list[tuple[int, int, int]]:
    """(crease, face a, face b) of every crease; refuses a crease not between two panels."""
    ef = cp.edge_faces()
    out = []
    for e in np.flatnonzero(cp.edge_mask("M", "V", "F")):
        a, b = (int(v) for v in ef[e])
        if a < 0 or b < 0:
            i, j = cp.edges[e]
            raise MjcfError(
                f"crease {e} ({cp.assignments[e]}, vertices {i}-{j}) is not between two "
                "panels: a hinge needs a panel on each side"
            )
        out.append((int(e), a, b))
    return out


def _root(cp: CreasePattern, source: MjcfSource) -> int:
    if source.body is not None:
        return cp.face_index(source.body)
    fixed = next((r.fixed_panel for r in source.routes if r.fixed_panel), None)
    if fixed:
        return cp.face_index(fixed)
    centre = cp.vertices.mean(axis=0)
    return int(np.argmin(np.linalg.norm(cp.face_centroids() - centre, axis=1)))


def spanning_tree(cp: CreasePattern, root: int):
    """Breadth-first tree of the panels: parent crease of each face and the loop creases.

    Returns ``(order, parent, loops)``: faces in visiting order, ``parent[f] = (face,
    crease)`` (the root's is ``(-1, -1)``), and the creases closing loops.
    """
    graph = _panel_graph(cp)
    adj: dict[int, list[tuple[int, int]]] = {}
    for e, a, b in graph:
        adj.setdefault(a, []).append((b, e))
        adj.setdefault(b, []).append((a, e))
    parent, order, queue, used = {root: (-1, -1)}, [root], deque([root]), set()
    while queue:
        f = queue.popleft()
        for g, e in adj.get(f, []):
            if g not in parent:
                parent[g] = (f, e)
                used.add(e)
                order.append(g)
                queue.append(g)
    missing = sorted(set(range(len(cp.faces))) - set(parent))
    if missing:
        raise MjcfError(
            f"panel {cp.face_labels[missing[0]]} is joined to {cp.face_labels[root]} by no "
            "chain of creases: one model needs one connected sheet"
        )
    return order, parent, [e for e, _, _ in graph if e not in used]


def _check_routes(cp: CreasePattern, routes) -> None:
    import shapely

    polys = cp.face_polygons()
    for r, spec in enumerate(routes):
        if spec.tsa.model not in TSA_CODES:
            raise MjcfError(
                f"route {r + 1}: TSA model {spec.tsa.model!r} has no MJCF construction "
                f"(only {', '.join(TSA_CODES)})"
            )
        for s, string in enumerate(spec.strings):
            for name, face, (x, y) in zip(string.names, string.faces, string.points, strict=True):
                poly = polys[face]
                if not shapely.covers(poly, shapely.Point(x, y)):
                    raise MjcfError(
                        f"route {r + 1}, string {s + 1}: hole {name} at ({x:g}, {y:g}) mm is "
                        f"not on its panel {cp.face_labels[face]}"
                    )


def _v(values, scale: float = MJ) -> str:
    """Numbers as an MJCF attribute (scaled: mm to m by default); NaN or infinity refused."""
    out = [float(v) * scale for v in values]
    if not all(math.isfinite(v) for v in out):
        raise MjcfError(f"MJCF: a value is not finite ({' '.join(map(str, out))})")
    return " ".join(f"{v:.9g}" for v in out)


def _fabrication(source: MjcfSource) -> FabricationParams:
    return next(
        (r.fabrication for r in source.routes if r.fabrication is not None), FabricationParams()
    )


def _meshes(source: MjcfSource, fab: FabricationParams) -> dict[int, list[np.ndarray]]:
    """Vertices (mm) of each panel's two collision hulls, centred on the crease layer.

    The convex hulls of the two printed halves (outer face to the crease layer, the
    footprints :func:`~origami_cad.fabrication.plan_panels` plans for the solids).
    """
    plan = plan_panels(source.design if source.design.tg else source.pattern, fab)
    z_low, z_mid = -fab.height / 2.0, -fab.height / 2.0 + fab.half_height
    z_up, z_top = z_mid + fab.thickness, fab.height / 2.0
    out = {}
    for o in plan.outlines:
        lower = np.vstack([_lift(o.outer, z_low), _lift(o.inner, z_mid)])
        upper = np.vstack([_lift(o.inner, z_up), _lift(o.outer, z_top)])
        out[o.index] = [lower, upper]
    return out


_SOLIDS: dict = {}


def printed_panels(source: MjcfSource, fab: FabricationParams | None = None):
    """The printed solids of every panel (:func:`~.mjcf_solids.panel_solids`), cached.

    The holes are cut where the routes' strings run (or at the source's ``holes``); the
    result is kept per pattern and parameters, as fabricating takes seconds.
    """
    fab = fab or _fabrication(source)
    if source.holes is not None:
        holes = source.holes
    else:
        points = (p for r in source.routes for st in r.strings for p in st.points)
        holes = tuple(dict.fromkeys((float(x), float(y)) for x, y in points)) or fab.holes
    fab = dataclasses.replace(fab, holes=holes)
    cp = source.pattern
    key = (cp.vertices.tobytes(), repr(cp.faces), fab, source.design.tg is not None)
    if key not in _SOLIDS:
        _SOLIDS[key] = panel_solids(source.design if source.design.tg else cp, fab)
    return _SOLIDS[key]


def _lift(ring: np.ndarray, z: float) -> np.ndarray:
    return np.column_stack([ring, np.full(len(ring), z)])


def _hinge_axis(cp: CreasePattern, e: int, parent_face: int) -> tuple[np.ndarray, np.ndarray]:
    """Point and unit axis of crease ``e`` (mm) such that +angle folds the child as a valley."""
    i, j = cp.edges[e]
    a, b = cp.vertices[i], cp.vertices[j]
    axis = (b - a) / np.linalg.norm(b - a)
    left = cp.edge_faces()[e, 0] == parent_face  # the parent lies left of a -> b
    return np.r_[a, 0.0], np.r_[-axis if left else axis, 0.0]


def _limits(source: MjcfSource, fab: FabricationParams, params: SimulationParams):
    """Range of each crease, radians: eq. 6 (``theta_max``) or the source's limits (deg)."""
    base = fab.theta_max if any(r.fabrication for r in source.routes) else None
    base = math.radians(params.fold_limit) if base is None else base
    limits = dict.fromkeys(range(source.pattern.n_edges), base)
    for e, degrees in source.crease_limits.items():
        limits[int(e)] = math.radians(degrees)
    return limits


def _body_xml(source, fab, params, meshes, sites, masses, damping, held) -> list[str]:
    """The tree of panel bodies: joint, inertial, collision and visual geoms, sites."""
    cp = source.pattern
    root = _root(cp, source)
    order, parent, _ = spanning_tree(cp, root)
    limits = _limits(source, fab, params)
    lengths = cp.edge_lengths()
    children: dict[int, list[int]] = {}
    for f in order[1:]:
        children.setdefault(parent[f][0], []).append(f)
    lines: list[str] = []
    solids, _ = printed_panels(source, fab)

    def body(f: int, depth: int) -> None:
        pad = "  " * depth
        label = cp.face_labels[f]
        free = source.body is not None
        z0 = fab.height / 2.0 + 1.0 if f == root and free else 0.0
        lines.append(f'{pad}<body name={_attr(label)} pos="0 0 {z0 * MJ:.9g}">')
        if f == root and (free or not (held or any(r.fixed_panel for r in source.routes))):
            lines.append(f'{pad}  <freejoint name="root"/>')
        elif f != root:
            pf, e = parent[f]
            at, axis = _hinge_axis(cp, e, pf)
            k = params.crease_stiffness * lengths[e] * MJ  # N m / rad
            c = damping * lengths[e] * MJ
            lim = limits[e]
            lines.append(
                f'{pad}  <joint name="crease{e}" type="hinge" pos="{_v(at)}" '
                f'axis="{_v(axis, 1.0)}" stiffness="{k:.6g}" damping="{c:.6g}" '
                f'limited="true" range="{-lim:.6g} {lim:.6g}"/>'
            )
        lines.append(pad + "  " + _inertial_xml(solids[f].props, masses.get(f, [])))
        for h, _ in enumerate(meshes[f]):
            lines.append(f'{pad}  <geom mesh={_attr(f"{label}_{h}")} class="panel"/>')
        for k, (material, _, _) in enumerate(solids[f].meshes):
            lines.append(f'{pad}  <geom mesh={_attr(f"{label}_v{k}")} class="{material}"/>')
        for name, _, at in masses.get(f, []):
            lines.append(
                f'{pad}  <geom name={_attr(name)} type="sphere" size="0.004" pos="{_v(at)}" '
                'contype="0" conaffinity="0" rgba="0.2 0.2 0.2 1"/>'
            )
        for name, at in sites.get(f, []):
            lines.append(f'{pad}  <site name="{name}" pos="{_v(at)}"/>')
        for g in children.get(f, []):
            body(g, depth + 1)
        lines.append(f"{pad}</body>")

    body(root, 2)
    return lines


def _inertial_xml(props: MassProps, masses) -> str:
    """A body's ``<inertial>``: its printed solids and point masses (g, mm -> SI)."""
    for _, grams, at in masses:
        props = props + MassProps.point(grams, at)
    i = props.inertia * 1e-9  # g mm^2 -> kg m^2
    full = (i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2])
    return (
        f'<inertial pos="{_v(props.com)}" mass="{props.mass * 1e-3:.9g}" '
        f'fullinertia="{_v(full, 1.0)}"/>'
    )


def _masses(source: MjcfSource, fab: FabricationParams) -> dict[int, list]:
    out: dict[int, list] = {}
    cp = source.pattern
    for name, grams, panel, (x, y) in source.masses:
        at = np.array([x, y, fab.height / 2.0])
        out.setdefault(cp.face_index(panel), []).append((name, grams, at))
    return out


@checked(
    SimulationError,
    source=Arg(
        "object", types=(str, os.PathLike, Design, CreasePattern, MjcfSource), optional=False
    ),
    params=Arg("object", types=(SimulationParams,)),
    contact=Arg("object", types=(Contact,)),
    gravity=Arg(min=-1e9, max=1e9, optional=False),
    friction=Arg(min=0.0, max=100.0),
    crease_damping=Arg(min=0.0, max=1e9, optional=False),
    timestep=Arg(min=0.0, open_min=True, max=0.1, optional=False),
    armature=Arg(min=0.0, max=1e3, optional=False),
)
def to_mjcf(
    source,
    routes=(),
    *,
    params: SimulationParams | None = None,
    gravity: float = 9810.0,
    ground: bool = True,
    friction: float | None = None,
    crease_damping: float = 2e-3,
    timestep: float = 5e-4,
    armature: float = 1e-6,
    contact: Contact | None = None,
) -> str:
    """The MJCF model (XML text) of a design and its routes, or of an :class:`MjcfSource`.

    Parameters
    ----------
    source : path, Design, CreasePattern or MjcfSource
        A design or pattern file, the loaded object, or a source built by the caller
        (a robot's: ``origami_cad.crawler.mujoco.robot_mjcf_source``).
    routes : sequence of path or RouteSpec
        Route files; an :class:`MjcfSource` brings its own.
    params : SimulationParams, optional
        Crease and string materials (default: the first route's ``[fabrication]``).
    gravity : float
        Gravitational acceleration along -z, mm/s^2 (0: none).
    ground : bool
        A ground plane at z = 0 (the sheet's bottom face rests on it).
    friction : float, optional
        Coulomb coefficient (default: the source's, else ``params.friction``).
    crease_damping : float
        Viscous damping of a crease per unit length, N mm s / rad / mm.
    timestep : float
        Integration step, s.
    armature : float
        Rotor inertia added to every joint, kg m^2: keeps the mass matrix of the
        light panels (about 1e-8 kg m^2 each) well conditioned.
    contact : Contact, optional
        The friction cone and contact softness (default :data:`STICK_SLIP`).

    Returns
    -------
    str
        The MJCF document; nothing is written.

    Raises
    ------
    MjcfError
        A hole not on its panel, a crease not between two panels, a TSA model
        without an MJCF construction.
    """
    no_routes = routes is None or (isinstance(routes, tuple | list) and not routes)
    src = source if isinstance(source, MjcfSource) else load_mjcf_source(source, routes)
    if not no_routes and isinstance(source, MjcfSource):
        raise MjcfError(
            "the source names its own routes (a robot file: its legs'): give no route files"
        )
    cp = src.pattern
    _panel_graph(cp)
    _check_routes(cp, src.routes)
    fab = _fabrication(src)
    params = params or (
        SimulationParams.for_route(src.routes[0]) if src.routes else SimulationParams()
    )
    mu = next(m for m in (friction, src.friction, params.friction) if m is not None)
    meshes = _meshes(src, fab)
    tendons = tendon_specs(src.routes, params)
    sites: dict[int, list] = {}
    for _, string_sites, *_ in tendons:
        for face, name, at in string_sites:
            sites.setdefault(face, []).append((name, at))
    held = src.body is None and not any(r.fixed_panel for r in src.routes) and not gravity
    contact = contact or STICK_SLIP
    visuals = printed_panels(src, fab)[0]
    lines = _header_xml(cp, meshes, visuals, timestep, gravity, armature, mu, contact)
    lines += _world_xml(sites, ground, mu, held, contact, timestep)
    lines += _body_xml(src, fab, params, meshes, sites, _masses(src, fab), crease_damping, held)
    lines += ["  </worldbody>", *_loops_xml(src), *tendon_xml(tendons), "</mujoco>"]
    return "\n".join(lines) + "\n"


def _attr(text: str) -> str:
    """A name from the user's files as a quoted XML attribute value (:func:`xml_text`)."""
    return f'"{xml_text(text)}"'


def _header_xml(cp, meshes, visuals, timestep, gravity, armature, mu, contact: Contact):
    """Options, defaults (materials, constraint softness, contacts) and the panels' meshes."""
    lines = [
        f"<mujoco model={_attr(cp.title or 'origami')}>",
        '  <compiler angle="radian" autolimits="true"/>',
        f'  <option timestep="{timestep:.6g}" gravity="0 0 {-gravity * MJ:.6g}" '
        f'integrator="Euler" iterations="200" ls_iterations="50" {contact.option_xml()}/>',
        "  <default>",
        f'    <joint armature="{armature:.6g}" solreflimit="{2 * timestep:.6g} 1"/>',
        f'    <equality solref="{2 * timestep:.6g} 1" solimp="0.99 0.999 0.001"/>',
        '    <default class="PLA"><geom type="mesh" contype="0" conaffinity="0" group="1" '
        'rgba="0.85 0.75 0.45 1"/></default>',
        '    <default class="TPU"><geom type="mesh" contype="0" conaffinity="0" group="1" '
        'rgba="0.25 0.45 0.8 1"/></default>',
        '    <default class="panel"><geom type="mesh" group="3" '
        f'friction="{mu:.6g} 0.005 0.0001" {contact.geom_xml(timestep)} '
        'rgba="0.85 0.75 0.45 0.3"/></default>',
        '    <site size="0.0008" rgba="0.9 0.1 0.1 1"/>',
        "  </default>",
        '  <visual><global offwidth="1280" offheight="960"/></visual>',
        "  <asset>",
    ]
    for f, halves in sorted(meshes.items()):
        for h, verts in enumerate(halves):
            name = _attr(f"{cp.face_labels[f]}_{h}")
            lines.append(f'    <mesh name={name} vertex="{_v(verts.ravel())}"/>')
    for f, panel in sorted(visuals.items()):
        for k, (_, verts, tris) in enumerate(panel.meshes):
            lines.append(
                f'    <mesh name={_attr(f"{cp.face_labels[f]}_v{k}")} vertex="{_v(verts.ravel())}" '
                f'face="{" ".join(map(str, tris.ravel()))}"/>'
            )
    return [*lines, "  </asset>"]


def _world_xml(sites: dict, ground: bool, mu: float, held: bool, contact, timestep):
    """The world: light, ground plane, and the fixed guides (on the ``ring`` if held).

    A sheet free in the ring, pulled evenly, keeps its mean pose: the root panel is held
    and the ring of guides follows the sheet (``mujoco_run.hold_mean_pose``).
    """
    lines = ["  <worldbody>", '    <light pos="0 0 1.5" dir="0 0 -1" directional="true"/>']
    if ground:
        lines.append(
            f'    <geom name="ground" type="plane" size="2 2 0.01" friction="{mu:.6g} 0.005 0.0001"'
            f' {contact.geom_xml(timestep)} rgba="0.6 0.65 0.7 1"/>'
        )
    world = [f'    <site name="{name}" pos="{_v(at)}"/>' for name, at in sites.get(-1, [])]
    if held:
        world = ['    <body name="ring" mocap="true">', *("  " + w for w in world), "    </body>"]
    return lines + world


def _loops_xml(src: MjcfSource) -> list[str]:
    cp = src.pattern
    root = _root(cp, src)
    _, _, loops = spanning_tree(cp, root)
    ef = cp.edge_faces()
    lines = ["  <equality>"]
    for e in loops:
        a, b = (cp.face_labels[int(f)] for f in ef[e])
        for v in cp.edges[e]:
            at = np.r_[cp.vertices[v], 0.0]
            lines.append(
                f'    <connect name="loop{e}_{v}" body1={_attr(a)} body2={_attr(b)} '
                f'anchor="{_v(at)}"/>'
            )
    return [*lines, "  </equality>"] if len(lines) > 1 else []
