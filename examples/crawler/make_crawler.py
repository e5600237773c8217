"""Generate the crawler of the paper's Fig. 7: its crease pattern, routes and robot file.

Run: python examples/crawler/make_crawler.py   (rewrites crawler.fold, route_*.toml and
crawler.toml here, and examples/crawler_designed/)

The generator is the library's (``origami_cad.design.crawler``, docs/crawler.md): this
script passes it the design numbers below.

* ``DESIGN``: the built robot (body 180 mm, legs 90 mm), written here with its hand gait.
  It is 349.9 mm long at its 20 deg rest, over the paper's 340 mm, so the envelope is
  reported, not enforced, for it.
* ``DESIGNED``: the crawler found by ``design-gait --design`` (issue 31; docs/crawler.md,
  "Designing the crawler"), within the paper's 340 x 320 x 122 mm, written to
  ``examples/crawler_designed/`` with two gaits: ``crawler.toml`` walks ``FLAT_GAIT`` (the
  search at friction 0.6: 66.2 mm per cycle there, 65.4 at 0.4) and ``gait_grip.toml`` is
  ``GRIP_GAIT`` (the joint search's, 49.5 mm at 0.8, where the first one jams).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1]))

from origami_cad.design.crawler import (  # noqa: E402
    ENVELOPE,
    CrawlerDesign,
    crawler_extent,
    crawler_files,
    write_crawler,
)
from origami_cad.design.crawler_toml import gait_file_text  # noqa: E402

#: The built robot's design numbers (mm, deg): CrawlerDesign's defaults.
DESIGN = CrawlerDesign()
#: The designed crawler (mm, deg): longer legs on a body shortened to keep 340 mm at the
#: 20 deg rest, and a 0.7 mm TPU crease layer (0.6 mm shell) that unfolds the legs.
DESIGNED = CrawlerDesign(
    body_length=108.2,
    leg_length=122.9,
    leg_hole=15.6,
    body_hole=24.9,
    blocker_angle=60.0,
    crease_thickness=0.7,
    shell=0.6,
)
#: Keyframes (s; fold ratios p = fold angle / 180 deg, [FL, FR, RL, RR]) of the designed
#: crawler's gait for friction 0.4-0.6 (design-gait --frictions 0.6 on it).
FLAT_GAIT = (
    [0.0, 3.92, 7.29, 11.22, 15.85, 19.77, 23.34, 27.27, 32.0],
    [
        [0.11111, 0.11111, 0.111, 0.111],
        [0.27962, 0.33333, 0.111, 0.111],
        [0.27962, 0.33333, 0.111, 0.111],
        [0.27962, 0.33333, 0.33333, 0.29064],
        [0.27962, 0.33333, 0.33333, 0.29064],
        [0.11111, 0.11111, 0.33333, 0.29064],
        [0.11111, 0.11111, 0.33333, 0.29064],
        [0.11111, 0.11111, 0.111, 0.111],
        [0.11111, 0.11111, 0.111, 0.111],
    ],
)
#: ... and for friction 0.8 (the joint search's over 0.4, 0.6 and 0.8, mean).
GRIP_GAIT = (
    [0.0, 6.39, 8.09, 13.33, 17.18, 23.57, 25.1, 30.33, 32.0],
    [
        [0.11489, 0.11489, 0.11197, 0.11197],
        [0.26956, 0.3282, 0.11197, 0.11197],
        [0.26956, 0.3282, 0.11197, 0.11197],
        [0.26956, 0.3282, 0.28149, 0.24196],
        [0.26956, 0.3282, 0.28149, 0.24196],
        [0.11489, 0.11489, 0.28149, 0.24196],
        [0.11489, 0.11489, 0.28149, 0.24196],
        [0.11489, 0.11489, 0.11197, 0.11197],
        [0.11489, 0.11489, 0.11197, 0.11197],
    ],
)
FLAT_HEADER = """\
# The gait for friction 0.4-0.6, found for this crawler by design-gait (CMA-ES at friction
# 0.6): 66.2 mm per cycle at 0.6, 65.4 at 0.4; at 0.8 its legs jam (use gait_grip.toml:
# origami-cad crawl crawler.toml --gait gait_grip.toml). docs/crawler.md, "Designing the
# crawler". Fold ratios p = fold angle / 180 deg of [front left, front right, rear left,
# rear right]."""
GRIP_HEADER = """\
# The designed crawler's gait for friction 0.8 (the joint design and gait search over
# 0.4, 0.6 and 0.8, mean): 44.7 / 51.6 / 49.5 mm per cycle at 0.4 / 0.6 / 0.8.
#   origami-cad crawl crawler.toml --gait gait_grip.toml --friction 0.8"""


def main() -> None:
    write_crawler(crawler_files(DESIGN, envelope=None), HERE)
    designed = HERE.parent / "crawler_designed"
    write_crawler(crawler_files(DESIGNED, FLAT_GAIT, header=FLAT_HEADER), designed)
    (designed / "gait_grip.toml").write_text(gait_file_text(*GRIP_GAIT, GRIP_HEADER), "utf-8")
    paper = " x ".join(f"{v:g}" for v in ENVELOPE)
    for name, d in (("built", DESIGN), ("designed", DESIGNED)):
        size = " x ".join(f"{v:.1f}" for v in crawler_extent(d, 20.0))
        print(f"{name}, at the 20 deg rest: {size} mm (the paper's {paper} mm)")


if __name__ == "__main__":
    main()
