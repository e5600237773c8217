"""The words of the crawler's files, for :mod:`origami_cad.crawler.design`: the comments
of its robot file (``examples/crawler/crawler.toml``) and of its route files, and the hand
gait. The files themselves are written by their formats' one writers
(:func:`~origami_cad.crawler.robot.dump_robot`, :func:`~origami_cad.strings.route.dump_route`).

Units: mm, deg, g, s.
"""

from __future__ import annotations

import numpy as np

__all__ = ["HAND_GAIT", "ROBOT_HEADER", "robot_notes", "route_header"]

#: The robot file's first lines.
ROBOT_HEADER = """\
# The crawling robot of the paper's Fig. 7 (340 x 320 x 122 mm, 361 g, 63 mm per 32 s cycle).
# Written with its pattern and routes by make_crawler.py (origami_cad.crawler.design, from
# the design numbers; run it after changing them). See docs/crawler.md for the design choices.
#   origami-cad robot examples/crawler/crawler.toml -o out/crawler          (printed robot)
#   origami-cad crawl examples/crawler/crawler.toml -o out/crawl --cycles 2   (walking)"""

_ROBOT = """\
pattern: one body panel, four legs on mountain creases; body: the panel whose motion is
the robot's; blocker_angle: a blocker on every leg crease (Fig. 7a, "up to 60 deg");
friction: TPU shell on a PVC cutting mat (docs/crawler.md, sources)."""

_HOLES = """\
Without a [fabrication] holes list the holes go exactly where the routes' strings run
(leg holes {leg_hole:g} mm and body holes {body_hole:g} mm from each hinge); give holes =
[[x, y], ...] to print others."""

_LEGS = """\
One leg module each: the TSA module (XL330, strands 24 mm = its guide distance, mount 1 mm
thick and 3 mm around the servo, hub and guide, not the whole leg: docs/crawler.md, mass
budget) rides on the leg, twist axis pointing at the body; servo IDs as
examples/crawler_gait.toml."""

_MASSES = """\
Hardware carried by the sheet, as point masses (g) for the simulation and the mass budget.
XL330-M288: 18 g (ROBOTIS e-manual); the module's printed hub, guide and mount are counted
from their solids by the robot command. A servo's case lies 13 mm behind its module's
centre (the leg's inset top face's centroid, {cx:.1f} mm, +-{cy:.1f} mm), away from the
body. Driver module (battery + controller): the paper's 109.71 g, plugged into the driver
adapter at the body's centre."""

_ADAPTER = """\
The driver adapter (parts library, 4 connectors) lies on the body's top face at its
centre, its long side along +x."""

_HAND_GAIT_NOTE = """\
The gait: one 32 s cycle, fold ratios p = fold angle / 180 deg of the legs
[front left, front right, rear left, rear right]. Legs fold down (mountain) and lift the body.
At rest (0 s) the legs are 20 deg down; get ready (6 s): stand at 30 deg; crawl (11 s): fold
the front legs to 55 deg (front feet hold, the body is drawn forward); fold the rear legs to
55 deg (16 s; the loaded front feet hold, the rear feet slide forward); step forward (21 s):
unfold the front legs to 30 deg (now the rear feet carry more of the weight and hold, the
front feet slide forward); push (26 s): unfold the rear legs (rear feet hold, the body is
pushed forward); relax (32 s): lie down. 30 deg = p 0.167, 55 deg = p 0.306, 20 deg = p 0.111.
The legs never go back to flat: at 20 deg (p 0.111) the strings under each hinge already
have a lever arm that picks the mountain branch. From a flat crease a string 1.1 mm below
the hinge shortens for both fold senses alike (the flat state is the longest), so the
strings alone cannot tell a leg to fold down rather than up (simulated: a rear leg flipped
up). The printed robot is set down with its legs bent 20 deg, as the paper's photos show."""

_DESIGNED_GAIT_NOTE = """\
The gait: fold ratios p = fold angle / 180 deg of the legs [front left, front right, rear
left, rear right]."""

#: The hand gait of ``examples/crawler``: keyframe times (K,) s and fold ratios (K, 4) of
#: [front left, front right, rear left, rear right] (20 -> 30 -> 55 deg and back).
HAND_GAIT = (
    np.array([0.0, 6.0, 11.0, 16.0, 21.0, 26.0, 32.0]),
    np.array([
        [0.111, 0.111, 0.111, 0.111],
        [0.167, 0.167, 0.167, 0.167],
        [0.306, 0.306, 0.167, 0.167],
        [0.306, 0.306, 0.306, 0.306],
        [0.167, 0.167, 0.306, 0.306],
        [0.167, 0.167, 0.167, 0.167],
        [0.111, 0.111, 0.111, 0.111],
    ]),
)  # fmt: skip


def _printed(design) -> str:
    if design.paper_sheet:
        return "Printed with the paper's b = 3, h = 2.2, t = 0.4 mm."
    return (
        f"Printed with b = 3, h = 2.2 mm and a t = {design.crease_thickness:g} mm TPU crease "
        f"layer (shell {design.shell:g} mm, the\nroutes' [fabrication]): a stiffer crease, "
        "which unfolds the legs."
    )


def robot_notes(design, module_xy, hand: bool, header: str | None = None) -> dict[str, str]:
    """The comments of ``design``'s robot file by table (``dump_robot``'s ``notes``):
    ``module_xy`` the front left module's centre (mm); the gait's comment is the hand
    gait's (``hand``), else ``header`` (comment lines, ``#`` signs and all, as
    ``make_crawler.py``'s ``HEADER``), else a line naming the legs."""
    holes = _HOLES.format(leg_hole=design.leg_hole, body_hole=design.body_hole)
    cx, cy = module_xy
    return {
        "robot": _ROBOT,
        "fabrication": f"{_printed(design)}\n{holes}",
        "leg": _LEGS,
        "mass": _MASSES.format(cx=cx, cy=cy),
        "adapter": _ADAPTER,
        "gait": _HAND_GAIT_NOTE if hand else _gait_note(header),
    }


def _gait_note(note: str | None) -> str:
    """The gait's comment as plain lines (a given note's ``#`` signs taken off)."""
    if not note:
        return _DESIGNED_GAIT_NOTE
    return "\n".join(line.removeprefix("#").removeprefix(" ") for line in note.splitlines())


def route_header(design, name: str, servo: int, label: str) -> str:
    """The comment lines opening a leg's route file (``dump_route``'s ``header``)."""
    return (
        f"# The crawler's {name} leg (servo ID {servo}), written by make_crawler.py.\n"
        f"# An onboard TSA module on panel {label} twists four strings; each goes down through\n"
        f"# the leg {design.leg_hole:g} mm from the hinge, under the mountain crease (DCQC: "
        "below a mountain),\n"
        f"# up through the body {design.body_hole:g} mm from the hinge, where it is tied.\n"
        "# Lengths mm, angles deg; the anchor is the exit guide, its height mm above the top face."
    )
