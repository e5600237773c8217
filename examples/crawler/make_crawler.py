"""Generate the crawler of the paper's Fig. 7: its crease pattern, routes and robot file.

Run: python examples/crawler/make_crawler.py   (rewrites crawler.fold, route_*.toml and
crawler.toml here)

The generator is the library's (``origami_cad.design.crawler``, docs/crawler.md): this
script passes it the design numbers below. With the defaults it writes the committed
files. The as-built robot is 349 mm long at its 20 deg rest, over the paper's 340 mm, so
the envelope is reported here, not enforced (``design-gait --design`` enforces it).
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

#: The design numbers (mm, deg); CrawlerDesign's defaults are the built robot's.
DESIGN = CrawlerDesign()


def main() -> None:
    files = crawler_files(DESIGN, envelope=None)
    write_crawler(files, HERE)
    rest = crawler_extent(DESIGN, 20.0)
    size = " x ".join(f"{v:.1f}" for v in rest)
    paper = " x ".join(f"{v:g}" for v in ENVELOPE)
    print(f"at the 20 deg rest: {size} mm (the paper's {paper} mm)")


if __name__ == "__main__":
    main()
