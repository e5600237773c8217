# ruff: noqa: E501  (the template is crawler.toml's own text, lines and all)
"""The crawler's robot file (``crawler.toml``) as text, for :mod:`origami_cad.crawler.design`.

The text is ``examples/crawler/crawler.toml``'s, with the design's numbers put in: the
blocker angle, the holes' distances from the hinges, the servos' places (each
``SERVO_BEHIND`` mm behind its module's centre, away from the body), the printed sheet
and the gait. Units: mm, deg, g, s.
"""

from __future__ import annotations

import numpy as np

from origami_cad._toml import finite_toml
from origami_cad.errors import DesignError

__all__ = ["robot_text"]

_BODY = """# The crawling robot of the paper's Fig. 7 (340 x 320 x 122 mm, 361 g, 63 mm per 32 s cycle).
# Written with its pattern and routes by make_crawler.py (origami_cad.crawler.design, from
# the design numbers; run it after changing them). See docs/crawler.md for the design choices.
#   origami-cad robot examples/crawler/crawler.toml -o out/crawler          (printed robot)
#   origami-cad crawl examples/crawler/crawler.toml -o out/crawl --cycles 2   (walking)
[robot]
pattern = "crawler.fold"      # one body panel, four legs on mountain creases
body = "body"                 # the panel whose motion is the robot's
{blocker_line}# deg: a blocker on every leg crease (Fig. 7a, "up to 60 deg")
friction = 0.6                # TPU shell on a PVC cutting mat (docs/crawler.md, sources)

{printed} Without a [fabrication] holes list the
# holes go exactly where the routes' strings run (leg holes {leg_hole:g} mm and body holes {body_hole:g} mm from
# each hinge); give holes = [[x, y], ...] to print others.

# One leg module each: the TSA module (XL330, strands 24 mm = its guide distance, mount 1 mm
# thick and 3 mm around the servo, hub and guide, not the whole leg: docs/crawler.md, mass
# budget) rides on the leg, twist axis pointing at the body; servo IDs as
# examples/crawler_gait.toml.
{legs}# Hardware carried by the sheet, as point masses (g) for the simulation and the mass budget.
# XL330-M288: 18 g (ROBOTIS e-manual); the module's printed hub, guide and mount are counted
# from their solids by the robot command. A servo's case lies 13 mm behind its module's
# centre (the leg's inset top face's centroid, {cx:.1f} mm, +-{cy:.1f} mm), away from the body. Driver module (battery + controller): the paper's
# 109.71 g, plugged into the driver adapter at the body's centre.
[[mass]]
name = "driver module"
panel = "body"
at = [0.0, 0.0]
grams = 109.71

{servo_masses}# The driver adapter (parts library, 4 connectors) lies on the body's top face at its centre.
[adapter]
at = [0.0, 0.0]
heading = 0.0                 # deg: its long side along +x

"""

#: One ``[[leg]]`` table of the robot file.
_LEG = """[[leg]]
panel = "{label}"
route = "{route}"
servo = {servo}
name = "{name}"

"""
#: One servo's ``[[mass]]`` table (XL330-M288, 18 g), ``at`` its case's centre on the leg.
_SERVO_MASS = """[[mass]]
name = "servo {name}"
panel = "{label}"
at = {at}
grams = 18.0

"""

_HAND_GAIT = """# The gait: one 32 s cycle, fold ratios p = fold angle / 180 deg of the legs
# [front left, front right, rear left, rear right]. Legs fold down (mountain) and lift the body.
# get ready: stand at 30 deg; crawl: fold the front legs to 55 deg (front feet hold, the body
# is drawn forward); fold the rear legs to 55 deg (the loaded front feet hold, the rear feet
# slide forward); step forward: unfold the front legs to 30 deg (now the rear feet carry more
# of the weight and hold, the front feet slide forward); push: unfold the rear legs (rear feet
# hold, the body is pushed forward); relax: lie down. 30 deg = p 0.167, 55 deg = p 0.306, 20 deg = p 0.111.
# The legs never go back to flat: at 20 deg (p 0.111) the strings under each hinge already
# have a lever arm that picks the mountain branch. From a flat crease a string 1.1 mm below
# the hinge shortens for both fold senses alike (the flat state is the longest), so the
# strings alone cannot tell a leg to fold down rather than up (simulated: a rear leg flipped
# up). The printed robot is set down with its legs bent 20 deg, as the paper's photos show.
[gait]
[[gait.keyframe]]
t = 0.0                       # at rest: legs 20 deg down (strings taut, see below)
p = [0.111, 0.111, 0.111, 0.111]
[[gait.keyframe]]             # get ready
t = 6.0
p = [0.167, 0.167, 0.167, 0.167]
[[gait.keyframe]]             # crawl: front legs fold
t = 11.0
p = [0.306, 0.306, 0.167, 0.167]
[[gait.keyframe]]             # rear legs fold
t = 16.0
p = [0.306, 0.306, 0.306, 0.306]
[[gait.keyframe]]             # step forward: front legs unfold
t = 21.0
p = [0.167, 0.167, 0.306, 0.306]
[[gait.keyframe]]             # push: rear legs unfold
t = 26.0
p = [0.167, 0.167, 0.167, 0.167]
[[gait.keyframe]]             # relax
t = 32.0
p = [0.111, 0.111, 0.111, 0.111]
"""


def _printed(design) -> str:
    if design.paper_sheet:
        return "# Printed with the paper's b = 3, h = 2.2, t = 0.4 mm."
    return (
        f"# Printed with b = 3, h = 2.2 mm and a t = {design.crease_thickness:g} mm TPU crease "
        f"layer (shell {design.shell:g} mm, the\n# routes' [fabrication]): a stiffer crease, "
        "which unfolds the legs.\n#"
    )


def _gait_text(times, ratios, header: str | None) -> str:
    lines = (
        [header.rstrip("\n")]
        if header
        else [
            "# The gait: fold ratios p = fold angle / 180 deg of the legs "
            "[front left, front right, rear left, rear right]."
        ]
    )
    lines += ["[gait]", *_keyframe_lines(times, ratios, "gait.keyframe")]
    return "\n".join(lines) + "\n"


def _keyframe_lines(times, ratios, table: str) -> list[str]:
    """``[[table]]`` tables of each keyframe's ``t`` (s) and ``p`` (fold ratios per leg),
    6 significant digits."""
    lines = []
    for t, p in zip(np.asarray(times, float), np.asarray(ratios, float), strict=True):
        row = ", ".join(f"{v:.6g}" for v in p)
        lines += [f"[[{table}]]", f"t = {t:.6g}", f"p = [{row}]"]
    return lines


def robot_text(design, servos, module_xy, gait=None, header: str | None = None) -> str:
    """``crawler.toml``'s text for ``design``: ``servos`` the legs' ``(panel label, servo
    ID, name, (x, y) mm of its case)``, ``module_xy`` the front left module's centre (mm,
    for the comments); ``gait`` (times (K,) s, fold ratios (K, 4)) replaces the hand gait,
    ``header`` its comment lines."""
    legs, masses = [], []
    for label, servo, name, (x, y) in servos:
        at = f"[{float(x)}, {float(y)}]"
        legs.append(
            _LEG.format(label=label, route=f"route_{label[4:]}.toml", servo=servo, name=name)
        )
        masses.append(_SERVO_MASS.format(label=label, name=name, at=at))
    cx, cy = module_xy
    text = _BODY.format(
        blocker_line=f"{'blocker_angle = ' + format(design.blocker_angle, '.1f'):<30}",
        printed=_printed(design),
        leg_hole=design.leg_hole,
        body_hole=design.body_hole,
        cx=cx,
        cy=cy,
        legs="".join(legs),
        servo_masses="".join(masses),
    )
    text += _HAND_GAIT if gait is None else _gait_text(*gait, header)
    return finite_toml(text, "the crawler's robot file", DesignError)
