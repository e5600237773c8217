"""Generate the crawler of the paper's Fig. 7: its crease pattern and its four TSA routes.

Run: python examples/crawler/make_crawler.py   (rewrites crawler.fold and route_*.toml here)

The robot (see docs/crawler.md) heads along +x. It is one printed sheet:

* a body panel, 180 x 200 mm, with a 6 mm notch in the middle of its front and rear edges so
  that no three vertices of its outline are collinear (the simulator triangulates panels as
  fans and the notch keeps every triangle proper);
* four legs, trapezoids 90 mm long hinged to the body's front and rear edges by MOUNTAIN
  creases (a leg folds down under the body and lifts it), 85 mm wide at the hinge and
  flaring to 140 mm at the foot, so that the flat sheet is 360 x 320 mm and the robot
  standing on its legs at 25-55 deg is 283-344 mm long (the paper: 340 x 320 x 122 mm).

Each leg carries its own onboard TSA module (``tsa-module`` of the parts library) on its top
face, twist axis pointing at the body. The module's four strings leave the exit guide, go
down through four holes of the leg 12 mm from the hinge, run under the mountain crease
(DCQC: below a mountain) to four holes of the body 30 mm from the hinge, come up through
them and are tied on top. Twisting the strands shortens the strings under the hinge and
folds the leg down. Hole points are written into the routes and into crawler.toml's
fabrication holes from the same numbers below, so the printed holes are the routed ones.
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1]))

from origami_cad.pattern import CreasePattern  # noqa: E402
from origami_cad.pattern.formats.fold import write_fold  # noqa: E402

#: Half the body's length (x) and width (y), mm.
BODY_X, BODY_Y = 90.0, 100.0
#: Notch depth at the middle of the front and rear edges, mm, and the legs' inner edge (|y|).
NOTCH, LEG_IN = 6.0, 15.0
#: Leg length (hinge to foot), mm; the foot's half-width reach (|y| of its outer corner).
LEG_LENGTH, FOOT_OUT, FOOT_IN = 90.0, 160.0, 20.0
#: Holes: distance of the leg's holes and of the body's holes from the hinge, mm.
LEG_HOLE, BODY_HOLE = 12.0, 30.0
#: The four strings' |y| across a leg, mm (evenly over the hinge's 85 mm).
STRING_Y = (25.0, 45.0, 65.0, 85.0)
#: TSA: twisted strands from hub to exit guide (the module's guide_distance), mm.
TSA_LENGTH, TSA_RADIUS, TSA_HELIX = 24.0, 0.6, 75.0
#: String exit above the leg's top face: the module's mount (1 mm) plus half the servo's
#: width (XL330: 20 mm), i.e. the twist axis's height, mm.
EXIT_HEIGHT = 11.0
#: The exit guide's distance from the module's centre along its twist axis:
#: 1 + hub 4 + guide_distance 24 + 1.5 (middle of the guide's hole), mm.
EXIT_OFFSET = 30.5

#: The legs: label, servo ID, name, x sign (+1 front), y sign (+1 left).
LEGS = (
    ("leg_fl", 1, "front left", 1, 1),
    ("leg_fr", 2, "front right", 1, -1),
    ("leg_rl", 3, "rear left", -1, 1),
    ("leg_rr", 4, "rear right", -1, -1),
)


def crawler_pattern() -> CreasePattern:
    """The crease pattern: one body panel and four legs on mountain creases (mm)."""
    bx, by = BODY_X, BODY_Y
    verts = [
        (-bx, -by),  # 0
        (bx, -by),  # 1
        (bx, -LEG_IN),  # 2
        (bx - NOTCH, 0.0),  # 3 front notch
        (bx, LEG_IN),  # 4
        (bx, by),  # 5
        (-bx, by),  # 6
        (-bx, LEG_IN),  # 7
        (-bx + NOTCH, 0.0),  # 8 rear notch
        (-bx, -LEG_IN),  # 9
    ]
    edges = [(i, (i + 1) % 10) for i in range(10)]
    assign = ["B"] * 10
    # leg creases: front right 1-2, front left 4-5, rear left 6-7, rear right 9-0
    for e in ((1, 2), (4, 5), (6, 7), (9, 0)):
        assign[edges.index(e)] = "M"
    foot = bx + LEG_LENGTH
    for hinge, (sx, sy) in (
        ((4, 5), (1, 1)),
        ((1, 2), (1, -1)),
        ((6, 7), (-1, 1)),
        ((9, 0), (-1, -1)),
    ):
        a, b = hinge
        # the foot's corners next to a and b: the outer one flares to FOOT_OUT
        tip = []
        for v in (a, b):
            y = verts[v][1]
            tip.append((sx * foot, sy * (FOOT_OUT if abs(y) > LEG_IN else FOOT_IN)))
        ia = len(verts)
        verts += [tip[0], tip[1]]
        edges += [(a, ia), (ia, ia + 1), (ia + 1, b)]
        assign += ["B", "B", "B"]
    cp = CreasePattern(verts, edges, assign, metadata={"title": "crawler"})
    labels = []
    for fi in range(len(cp.faces)):
        cx, cy = cp.face_centroids()[fi]
        if abs(cx) < BODY_X:
            labels.append("body")
        else:
            labels.append(("leg_f" if cx > 0 else "leg_r") + ("l" if cy > 0 else "r"))
    return cp.with_face_labels(labels)


def leg_holes(sx: int, sy: int) -> tuple[list[tuple[float, float]], list[tuple[float, float]]]:
    """The four holes of a leg and the four matching holes of the body, (x, y) mm."""
    leg = [(sx * (BODY_X + LEG_HOLE), sy * y) for y in STRING_Y]
    body = [(sx * (BODY_X - BODY_HOLE), sy * y) for y in STRING_Y]
    return leg, body


def module_centre(cp: CreasePattern, label: str) -> tuple[float, float]:
    """Where the parts library centres a TSA module on a panel: its inset outer face's centroid."""
    from origami_cad.fabrication import plan_panels

    outline = plan_panels(cp).outline(label)
    import shapely

    foot = shapely.Polygon(outline.outer).buffer(-1.0, join_style="mitre")
    return float(foot.centroid.x), float(foot.centroid.y)


def route_text(cp: CreasePattern, label: str, servo: int, name: str, sx: int, sy: int) -> str:
    """The route TOML of one leg's TSA."""
    cx, cy = module_centre(cp, label)
    ax = cx - sx * EXIT_OFFSET  # the twist axis points at the body (heading 180 deg front)
    leg, body = leg_holes(sx, sy)
    lines = [
        f"# The crawler's {name} leg (servo ID {servo}), written by make_crawler.py.",
        f"# An onboard TSA module on panel {label} twists four strings; each goes down through",
        "# the leg 12 mm from the hinge, under the mountain crease (DCQC: below a mountain),",
        "# up through the body 30 mm from the hinge, where it is tied.",
        "[tsa]",
        'model = "onboard"',
        f"length = {TSA_LENGTH}           # mm, twisted strands (the module's guide_distance)",
        f"radius = {TSA_RADIUS}            # mm",
        f"max_helix_angle = {TSA_HELIX}   # deg",
        "",
        "[route]",
        "thickness = 2.2",
        "step = 20.0              # deg per quasi-static step",
        "max_turns = 8",
        "",
    ]
    for (lx, ly), (bx, by) in zip(leg, body, strict=True):
        lines += [
            "[[route.strings]]",
            f'anchor_panel = "{label}"',
            f"anchor = [{ax:.3f}, {cy:.3f}, {EXIT_HEIGHT}]   # exit guide, mm above the top face",
            f"holes = [[{lx:.1f}, {ly:.1f}], [{bx:.1f}, {by:.1f}]]",
            'sides = ["top", "bottom"]',
            "",
        ]
    return "\n".join(lines)


def main() -> None:
    cp = crawler_pattern()
    write_fold(cp, HERE / "crawler.fold")
    for label, servo, name, sx, sy in LEGS:
        path = HERE / f"route_{label[4:]}.toml"
        path.write_text(route_text(cp, label, servo, name, sx, sy), encoding="utf-8")
    holes = []
    for _, _, _, sx, sy in LEGS:
        leg, body = leg_holes(sx, sy)
        holes += leg + body
    print("fabrication holes:")
    print("holes = [" + ", ".join(f"[{x:.1f}, {y:.1f}]" for x, y in holes) + "]")


if __name__ == "__main__":
    main()
