"""A whole robot as one assembly: the printed sheet with its parts in place (Fig. 7a).

:func:`robot_assembly` places, on a fabricated pattern, TSA modules on panels, blockers on
creases (on the top face for a valley, mirrored onto the bottom face for a mountain: a
mountain fold is a valley seen from below, and the printed sheet is symmetric about its
mid-plane ``z = h/2``) and a free-standing part such as the driver adapter at a point of a
panel's top face. :func:`write_robot_step` writes it as one STEP of named, coloured
solids, and :func:`robot_report` gives each solid's volume, mass and bounding box as plain
data. The placements come in as plain data (labels, edge indices, points, degrees);
build123d objects stay in this module.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import shapely
from build123d import Color, Compound, Location, export_stl

from origami_cad._fileio import atomic_path
from origami_cad._names import one_line, path_component
from origami_cad.errors import FabricationError
from origami_cad.fabrication.assembly import MATERIAL_COLORS, moved_tree, solids_by_part
from origami_cad.fabrication.build import Fabrication
from origami_cad.fabrication.exports.step import export_step_tree
from origami_cad.fabrication.params import DENSITY_G_CM3
from origami_cad.fabrication.printmass import printed_mass
from origami_cad.fabrication.solids import PART_MATERIALS, PART_NAMES

from .registry import build_part

__all__ = [
    "PAPER_CRAWLER_G",
    "PART_COLORS",
    "BlockerPlacement",
    "FreePlacement",
    "MassBudget",
    "ModulePlacement",
    "RobotAssembly",
    "display_color",
    "robot_assembly",
    "robot_mass_budget",
    "robot_mass_numbers",
    "robot_mass_report",
    "robot_overlaps",
    "robot_render_style",
    "robot_report",
    "robot_tree",
    "write_robot_step",
    "write_robot_stls",
]

#: Display colours (sRGB hex) of the added parts: modules dark grey, blockers orange,
#: adapter blue (the sheet keeps its materials' colours).
PART_COLORS = {"tsa-module": "#404040", "blocker": "#FF7F0E", "driver-adapter": "#1F77B4"}

#: The paper's crawler's weight, g (the mass budget's reference).
PAPER_CRAWLER_G = 361.45


@dataclass(frozen=True)
class ModulePlacement:
    """A TSA module on a panel: its name in the assembly, the panel label, its parameters."""

    name: str
    panel: str
    values: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class BlockerPlacement:
    """A blocker on crease ``crease`` (edge index) stopping it at ``angle`` degrees."""

    name: str
    crease: int
    angle: float
    values: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class FreePlacement:
    """A free-standing part (``part``, e.g. ``driver-adapter``) centred at ``at`` (mm) on the
    sheet's top face, its long side (the part's +y) turned to ``heading`` degrees from +x."""

    name: str
    part: str
    at: tuple[float, float]
    heading: float = 0.0
    values: Mapping[str, Any] = field(default_factory=dict)


@dataclass
class RobotAssembly:
    """The robot's solids by name (build123d shapes; stay in ``parts``) and their materials.

    ``sheet`` is the printed sheet as an assembly (``Fabrication.assembly``) at the fold
    ratio ``ratio``; ``solids`` holds its four parts (by part name) and the added parts.
    """

    solids: dict[str, Any]
    materials: dict[str, str]
    kinds: dict[str, str]
    sheet: Any = None
    ratio: float = 0.0


def robot_assembly(
    fab: Fabrication,
    modules: Sequence[ModulePlacement] = (),
    blockers: Sequence[BlockerPlacement] = (),
    free: Sequence[FreePlacement] = (),
    ratio: float = 0.0,
) -> RobotAssembly:
    """Place parts on a fabricated sheet, folded to ``ratio``; names must be unique.

    Parameters
    ----------
    fab : Fabrication
        The printed sheet (its four parts keep their names: infills, midlayers, shells,
        creases).
    modules, blockers, free : sequences of placements
        The TSA modules (on panels), blockers (on creases) and free-standing parts.
    ratio : float
        Fold ratio p in [0, 1] (0: flat, as printed): every part moves with the panel it
        is bonded to (a blocker with the panel on its crease's left, a free part with the
        panel under its centre), as the panels move in ``fab.assembly(ratio)``.
    """
    from origami_cad.fabrication.assembly import sheet_motion

    plan = fab.plan
    cp = plan.pattern
    h = plan.params.height
    sheet = fab.assembly(ratio)
    motion = sheet_motion(cp, plan.params, ratio, fab.design).locations
    by_part = solids_by_part(sheet)
    solids: dict[str, Any] = {}
    materials: dict[str, str] = {}
    kinds: dict[str, str] = {}

    def add(name: str, shape: Any, material: str, kind: str) -> None:
        if name in solids:
            raise FabricationError(f"two parts of the robot are named {name!r}")
        solids[name] = shape
        materials[name] = material
        kinds[name] = kind

    for part in PART_NAMES:
        add(part, Compound(by_part[part]), PART_MATERIALS[part], "structure")
    for m in modules:
        shape = build_part("tsa-module", m.values, pattern=plan, panel=m.panel)
        face = cp.face_index(m.panel)
        add(m.name, moved_tree(shape, motion[face]), "PLA", "tsa-module")
    for b in blockers:
        if cp.assignments[b.crease] not in ("M", "V"):
            raise FabricationError(f"blocker {b.name!r}: edge {b.crease} is not a crease")
        mountain = cp.assignments[b.crease] == "M"
        values = {**b.values, "angle": b.angle}
        shape = build_part("blocker", values, pattern=plan, crease=b.crease, mountain=mountain)
        face = int(cp.edge_faces()[b.crease][0])
        add(b.name, moved_tree(shape, motion[face]), "PLA", "blocker")
    for f in free:
        shape = build_part(f.part, f.values)
        box = shape.bounding_box()
        centre = (box.min + box.max) * 0.5
        shape = shape.moved(Location((-centre.X, -centre.Y, -box.min.Z)))
        shape = shape.moved(Location((f.at[0], f.at[1], h), (0, 0, 1), f.heading - 90.0))
        under = shapely.Point(f.at)
        faces = [
            k for k, poly in enumerate(cp.face_polygons()) if shapely.Polygon(poly).covers(under)
        ]
        loc = motion[faces[0]] if faces else Location()
        add(f.name, moved_tree(shape, loc), "PLA", f.part)
    return RobotAssembly(solids, materials, kinds, sheet, float(ratio))


def robot_report(
    robot: RobotAssembly, settings: Mapping[str, Any] | None = None
) -> dict[str, dict[str, Any]]:
    """Per solid: kind, material, volume (mm^3), printed mass (g) and bounding box (mm).

    ``mass_g`` is the mass as printed with the print settings ``settings`` (walls, skins
    and sparse infill: :func:`~origami_cad.fabrication.printmass.printed_mass`; default
    the 3MF's, ``slicer_settings()``), ``solid_mass_g`` the solid volume's.
    ``printed_volume_mm3``, ``mass_g`` and ``solid_mass_g`` leave out a TSA module's servo
    (a bought part, modelled as its case): add its datasheet mass.
    """
    out = {}
    for name, shape in robot.solids.items():
        volume = float(sum(s.volume for s in shape.solids()))
        box = shape.bounding_box()
        material = robot.materials[name]
        # a TSA module's servo is a stand-in box, not printed: its volume is reported apart
        bought = sum(
            float(sum(s.volume for s in c.solids()))
            for c in getattr(shape, "children", ())
            if getattr(c, "label", "") == "servo"
        )
        out[name] = {
            "kind": robot.kinds[name],
            "material": material,
            "volume_mm3": volume,
            "printed_volume_mm3": volume - bought,
            "mass_g": printed_mass({material: _printed_solids(shape)}, settings)[material],
            "solid_mass_g": (volume - bought) / 1000.0 * DENSITY_G_CM3[material],
            "bbox_mm": [[box.min.X, box.min.Y, box.min.Z], [box.max.X, box.max.Y, box.max.Z]],
        }
    return out


def _printed_solids(shape: Any) -> list[Any]:
    """The solids of ``shape`` that are printed: all but a TSA module's servo stand-in."""
    children = getattr(shape, "children", ()) or ()
    if not children:
        return list(shape.solids())
    return [s for c in children if getattr(c, "label", "") != "servo" for s in c.solids()]


def robot_overlaps(robot: RobotAssembly, names: Sequence[str] | None = None) -> dict:
    """Volume (mm^3) shared by each pair of the named solids (default: all), where > 0."""
    keys = list(names or robot.solids)
    out = {}
    for i, a in enumerate(keys):
        for b in keys[i + 1 :]:
            sa, sb = robot.solids[a], robot.solids[b]
            ba, bb = sa.bounding_box(), sb.bounding_box()
            if (
                ba.max.X < bb.min.X
                or bb.max.X < ba.min.X
                or ba.max.Y < bb.min.Y
                or bb.max.Y < ba.min.Y
                or ba.max.Z < bb.min.Z
                or bb.max.Z < ba.min.Z
            ):
                continue
            common = sa & sb
            volume = float(sum(s.volume for s in common.solids())) if common else 0.0
            if volume > 0:
                out[(a, b)] = volume
    return out


def _color(hexa: str) -> Color:
    hexa = hexa.lstrip("#")
    return Color(*(int(hexa[i : i + 2], 16) / 255 for i in (0, 2, 4)))


def display_color(robot: RobotAssembly, name: str) -> str:
    """The colour (sRGB hex) solid ``name`` is shown in: its material's for the sheet's
    parts, its kind's (:data:`PART_COLORS`) for the added ones."""
    kind = robot.kinds[name]
    return MATERIAL_COLORS[robot.materials[name]] if kind == "structure" else PART_COLORS[kind]


def write_robot_step(
    robot: RobotAssembly, path: str | os.PathLike[str], label: str = "robot"
) -> Path:
    """Write the robot as one STEP assembly of named, coloured parts (atomic).

    The sheet is its assembly tree (panels by label, each solid in its material's colour,
    the crease strips); each added part is a child named as placed, every solid of it in
    its kind's colour (:data:`PART_COLORS`), so FreeCAD shows the colours with STEP
    compound merge on or off.
    """
    return export_step_tree(robot_tree(robot, label), path)


def robot_tree(robot: RobotAssembly, label: str = "robot") -> Compound:
    """The robot as one labelled, coloured ``Compound`` tree: the sheet, then the parts."""
    children = []
    if robot.sheet is not None:
        sheet = moved_tree(robot.sheet, Location())
        sheet.label = "sheet"
        children.append(sheet)
    for name, shape in robot.solids.items():
        if robot.sheet is not None and robot.kinds[name] == "structure":
            continue
        node = moved_tree(shape, Location())
        node.label = name
        color = _color(display_color(robot, name))
        _paint(node, color)
        children.append(node)
    tree = Compound(children=children)
    tree.label = label
    return tree


def _paint(node: Any, color: Color) -> None:
    """Give ``node`` and every node below it the colour ``color``."""
    node.color = color
    for child in getattr(node, "children", ()) or ():
        _paint(child, color)


def write_robot_stls(
    robot: RobotAssembly, folder: str | os.PathLike[str], kinds: Sequence[str] | None = None
) -> dict[str, Path]:
    """Write ``<name>.stl`` (binary, in place on the robot) of each solid of the given kinds
    (default: every added part, not the sheet, which ``write_fabrication`` writes).

    Each file name is checked by :func:`origami_cad._names.path_component` before any
    file is written: a solid whose name cannot be one file in ``folder`` (``/``, ``..``,
    control characters, a Windows device name, ...) is a :class:`FabricationError` naming it.
    """
    chosen = {}
    for name, shape in robot.solids.items():
        kind = robot.kinds[name]
        if (kinds is None and kind == "structure") or (kinds is not None and kind not in kinds):
            continue
        try:
            chosen[name] = (Path(folder) / path_component(f"{name}.stl"), shape)
        except ValueError as exc:
            raise FabricationError(f"the solid {one_line(str(name)[:60])}: {exc}") from None
    out = {}
    for name, (path, shape) in chosen.items():
        with atomic_path(path) as tmp:
            if export_stl(shape, str(tmp), tolerance=0.01, angular_tolerance=0.1) is False:
                raise OSError(f"{path}: the STL writer failed")
        out[name] = path
    return out


@dataclass(frozen=True)
class MassBudget:
    """A robot's mass, g: its printed sheet, its printed parts and its bought parts.

    Attributes
    ----------
    sheet_g : float
        The printed sheet (PLA panels and TPU creases), g.
    printed_parts_g : float
        The printed parts added to it (TSA modules, blockers, adapter), g.
    bought_parts_g : dict of str to float
        Each bought part (servos, the driver module) by name, g.
    """

    sheet_g: float
    printed_parts_g: float
    bought_parts_g: dict[str, float]

    @property
    def total_g(self) -> float:
        """The whole robot, g."""
        return self.sheet_g + self.printed_parts_g + sum(self.bought_parts_g.values())

    def to_dict(self, reference_g: float | None = None) -> dict[str, Any]:
        """For a JSON file; with ``reference_g`` (a weighed robot, g), its difference in %."""
        out: dict[str, Any] = {
            "sheet_g": self.sheet_g,
            "printed_parts_g": self.printed_parts_g,
            "bought_parts_g": dict(self.bought_parts_g),
            "printed_g": self.sheet_g + self.printed_parts_g,
            "total_g": self.total_g,
        }
        if reference_g is not None:
            out["paper_g"] = reference_g
            out["difference_percent"] = 100.0 * (self.total_g - reference_g) / reference_g
        return out


def robot_mass_budget(
    sheet_g: float,
    report: Mapping[str, Mapping[str, Any]],
    bought: Mapping[str, float] | Sequence[tuple[str, float]],
) -> MassBudget:
    """The robot's mass budget: its sheet, the printed parts of its report, its bought parts.

    Parameters
    ----------
    sheet_g : float
        The printed sheet's mass, g: as printed, from the 3MF's print settings
        (:func:`~origami_cad.fabrication.printmass.printed_mass` of its parts' solids;
        ``Fabrication.report()["total_mass_g"]`` is the solid volume's).
    report : dict
        :func:`robot_report`'s solids: each ``kind`` and printed ``mass_g`` (g, from the
        print settings); the sheet's
        own solids (kind ``"structure"``) are left out, as ``sheet_g`` holds them.
    bought : dict of str to float, or sequence of (str, float)
        The bought parts' masses by name, g (a robot file's ``[[mass]]`` tables); parts
        sharing a name are added up.

    Returns
    -------
    MassBudget
        Plain data; nothing is written.

    Examples
    --------
    >>> report = {"infills": {"kind": "structure", "mass_g": 90.0},
    ...           "blocker_0": {"kind": "blocker", "mass_g": 2.5},
    ...           "tsa_module_0": {"kind": "tsa-module", "mass_g": 12.0}}
    >>> budget = robot_mass_budget(150.0, report, [("servo", 55.0), ("servo", 55.0)])
    >>> budget.printed_parts_g, budget.bought_parts_g, budget.total_g
    (14.5, {'servo': 110.0}, 274.5)
    >>> round(budget.to_dict(reference_g=250.0)["difference_percent"], 2)
    9.8
    """
    printed = sum(float(v["mass_g"]) for v in report.values() if v["kind"] != "structure")
    parts: dict[str, float] = {}
    for name, grams in bought.items() if isinstance(bought, Mapping) else bought:
        parts[str(name)] = parts.get(str(name), 0.0) + float(grams)
    return MassBudget(float(sheet_g), printed, parts)


def robot_mass_report(
    source: str | os.PathLike[str],
    fab: Fabrication,
    report: Mapping[str, Mapping[str, Any]],
    overlaps: Mapping[tuple[str, str], float],
    bought: Sequence[tuple[str, float]],
) -> dict[str, Any]:
    """``robot.json``'s content: the mass budget from the print settings the 3MF carries
    (g, against the paper's crawler, :data:`PAPER_CRAWLER_G`), those settings, each solid
    of :func:`robot_report` and the interpenetrating pairs (mm^3).

    ``source`` names the robot file; ``bought``: its bought parts, (name, g).
    """
    from origami_cad.fabrication.printmass import sheet_print_mass
    from origami_cad.fabrication.slicer import PRINT_SETTINGS, slicer_settings

    settings = slicer_settings(fab.params)
    sheet = sum(sheet_print_mass(fab, settings).values())
    budget = robot_mass_budget(sheet, report, bought).to_dict(reference_g=PAPER_CRAWLER_G)
    return {
        "robot": str(source),
        "mass_budget": budget,
        "print_settings": {k: settings[k] for k in PRINT_SETTINGS},
        "solids": dict(report),
        "interpenetrating_mm3": {f"{x} / {y}": v for (x, y), v in overlaps.items()},
    }


def robot_mass_numbers(data: Mapping[str, Any]) -> list[tuple[str, str]]:
    """The key numbers of :func:`robot_mass_report`'s ``data``: the masses (g) against the
    paper's crawler, the parts by kind, the interpenetrating pairs."""
    budget, kinds = data["mass_budget"], [v["kind"] for v in data["solids"].values()]
    sheet, printed, total = budget["sheet_g"], budget["printed_parts_g"], budget["total_g"]
    bought = sum(budget["bought_parts_g"].values())
    return [
        ("sheet mass (as printed)", f"{sheet:.1f} g"),
        ("printed parts", f"{printed:.1f} g"),
        ("bought parts (servos, driver module)", f"{bought:.1f} g"),
        (f"mass estimate (paper: {PAPER_CRAWLER_G:g} g)",
         f"{total:.0f} g ({budget['difference_percent']:+.0f} %)"),
        (
            "parts",
            f"{kinds.count('tsa-module')} TSA modules, {kinds.count('blocker')} blockers, "
            f"{kinds.count('driver-adapter')} driver adapter",
        ),
        ("interpenetrating pairs", str(len(data["interpenetrating_mm3"]))),
    ]  # fmt: skip


def robot_render_style(
    robot: RobotAssembly, names: Sequence[str]
) -> tuple[dict[str, str], dict[str, str]]:
    """The legend labels and colours (sRGB hex) of the added parts ``names`` in a render:
    each part's kind (plural when several share it) and :func:`display_color`."""
    kinds = {n: robot.kinds[n] for n in names}
    labels = {
        n: k.replace("-", " ") + "s" * (list(kinds.values()).count(k) > 1) for n, k in kinds.items()
    }
    return labels, {n: display_color(robot, n) for n in names}
