"""Generate the crawler of the paper's Fig. 7: its crease pattern, routes and robot file.

Run: python examples/crawler/make_crawler.py   (rewrites crawler.fold, route_*.toml and
crawler.toml here, and examples/crawler_designed/)

The generator is the library's (``origami_cad.crawler.design``, docs/crawler.md): this
script passes it the design numbers below.

* ``DESIGN``: the built robot (body 180 mm, legs 90 mm), written here with its hand gait.
  It is 349.9 mm long at its 20 deg rest, over the paper's 340 mm, so the envelope is
  reported, not enforced, for it.
* ``DESIGNED``: the crawler found by ``design-gait --design`` (docs/crawler.md,
  "Designing the crawler"), within the paper's 340 x 320 x 122 mm, written to
  ``examples/crawler_designed/`` walking ``GAIT``, its one gait for every ground (57.5 /
  65.1 / 63.2 mm per cycle at friction 0.4 / 0.6 / 0.8).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1]))

from origami_cad.crawler.design import (  # noqa: E402
    ENVELOPE,
    CrawlerDesign,
    crawler_extent,
    crawler_files,
    write_crawler,
)

#: The built robot's design numbers (mm, deg): CrawlerDesign's defaults.
DESIGN = CrawlerDesign()
#: The designed crawler (mm, deg): longer legs on a body shortened to keep 340 mm at the
#: 20 deg rest, and a 0.9 mm TPU crease layer (0.5 mm shell) that unfolds the legs.
DESIGNED = CrawlerDesign(
    body_length=108.4,
    leg_length=122.8,
    leg_hole=14.4,
    body_hole=33.6,
    blocker_angle=58.9,
    crease_thickness=0.9,
    shell=0.5,
)
#: Keyframes (s; fold ratios p = fold angle / 180 deg, [FL, FR, RL, RR]) of the designed
#: crawler's one gait (design-gait's joint search, --mix shortfall, over 0.4, 0.6, 0.8).
GAIT = (
    [0.0, 5.0, 7.88, 12.88, 14.46, 19.46, 22.55, 27.56, 32.0],
    [
        [0.11299, 0.11299, 0.11259, 0.11259],
        [0.29405, 0.32722, 0.11259, 0.11259],
        [0.29405, 0.32722, 0.11259, 0.11259],
        [0.29405, 0.32722, 0.32722, 0.29864],
        [0.29405, 0.32722, 0.32722, 0.29864],
        [0.11299, 0.11299, 0.32722, 0.29864],
        [0.11299, 0.11299, 0.32722, 0.29864],
        [0.11299, 0.11299, 0.11259, 0.11259],
        [0.11299, 0.11299, 0.11259, 0.11259],
    ],
)
HEADER = """\
# The designed crawler's one gait, found with its design by design-gait --design
# (CMA-ES, --mix shortfall against 45 / 63 / 45 mm at friction 0.4 / 0.6 / 0.8):
# 57.5 / 65.1 / 63.2 mm per cycle at 0.4 / 0.6 / 0.8, drift under 1.5 mm. docs/crawler.md,
# "Designing the crawler". Fold ratios p = fold angle / 180 deg of [front left, front
# right, rear left, rear right]."""


def main() -> None:
    write_crawler(crawler_files(DESIGN, envelope=None), HERE)
    designed = HERE.parent / "crawler_designed"
    write_crawler(crawler_files(DESIGNED, GAIT, header=HEADER), designed)
    paper = " x ".join(f"{v:g}" for v in ENVELOPE)
    for name, d in (("built", DESIGN), ("designed", DESIGNED)):
        size = " x ".join(f"{v:.1f}" for v in crawler_extent(d, 20.0))
        print(f"{name}, at the 20 deg rest: {size} mm (the paper's {paper} mm)")


if __name__ == "__main__":
    main()
