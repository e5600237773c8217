"""What a gait search decides beyond the search: its settings, its refusal, its report.

``design-gait`` and a script share these: the settings built from the library's defaults,
the options given and the robot's limits (:func:`gait_settings`); the search, with or
without the crawler's design genes (:func:`search_gait`); the refusal of a search whose
every candidate passed a limit (:func:`check_within_limits`); the comment lines of the
gait and robot files it writes (:func:`gait_header`, :func:`crawler_gait_header`) and
results.json's content (:func:`gait_report`). Nothing here writes a file.

Units: mm (forward, drift), degrees (yaw), seconds (cycle, search time).
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
from collections.abc import Callable
from typing import Any

from origami_cad.crawler.design_search import CrawlerSearch, design_crawler, parse_design_bounds
from origami_cad.crawler.gait import (
    GaitDesign,
    GaitLimits,
    GaitSettings,
    design_gait,
    hard_hits,
    stride_limits,
)
from origami_cad.crawler.robot import PAPER_CRAWL_MM, Robot
from origami_cad.errors import DesignError, OptionsError

__all__ = [
    "check_within_limits",
    "crawler_gait_header",
    "gait_header",
    "gait_report",
    "gait_settings",
    "search_gait",
]


def gait_settings(robot: Robot, **given: Any) -> GaitSettings:
    """A gait search's settings: :class:`GaitSettings`'s defaults, ``given`` (its fields;
    ``None`` values are left out) and the robot's limits (``GaitLimits.of(robot)``).

    Raises :class:`OptionsError` in one line when ``targets`` does not give one target per
    friction (or the ``shortfall`` mix has a friction without a default target).
    """
    given = {k: v for k, v in given.items() if v is not None}
    for name in ("frictions", "targets"):
        if name in given:
            given[name] = tuple(given[name])
    try:
        return GaitSettings(limits=GaitLimits.of(robot), **given)
    except ValueError as exc:  # targets against frictions
        raise OptionsError(f"design-gait: {exc} (--targets)") from None


def search_gait(
    robot: Robot,
    settings: GaitSettings,
    design: str | dict | None = None,
    executor: cf.Executor | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[GaitDesign, CrawlerSearch | None]:
    """The gait search, or with ``design`` (the crawler's design genes' bounds, as
    :func:`~origami_cad.crawler.design_search.parse_design_bounds` reads them) the joint
    design and gait search: ``(GaitDesign, CrawlerSearch or None)``. Writes nothing."""
    if design is None:
        return design_gait(robot, settings, executor=executor, progress=progress), None
    bounds = parse_design_bounds(design)
    search = design_crawler(robot, settings, bounds, executor=executor, progress=progress)
    return search.gait, search


def check_within_limits(design: GaitDesign, where: str) -> None:
    """Refuse a search whose every candidate passed a limit (``crawl --gait`` and ``drive``
    would refuse its gait): :class:`DesignError`, one line naming the limit the best one
    passed; ``where`` names the robot file."""
    hard = hard_hits(design.best)
    if hard:
        raise DesignError(
            f"{where}: none of {len(design.candidates)} gaits stays within the limits; "
            f"the best: {hard[0]} (try a longer --cycle or more --generations)"
        )


def gait_header(design: GaitDesign, command: str) -> str:
    """The comment lines of a designed gait's file: its score and forward per cycle (mm)
    against the hand gait's and the paper's, the programs that read it, and ``command``
    (the command line that found it)."""
    best, hand = design.best, design.hand
    per = ", ".join(f"{t.forward:.1f} mm at {t.friction:g}" for t in best.terms)
    was = ", ".join(f"{t.forward:.1f} mm at {t.friction:g}" for t in hand)
    return (
        f"# A gait found by origami-cad design-gait (CMA-ES, score {best.score:.1f} mm, "
        f"{design.settings.mix} over frictions): forward per cycle {per}\n"
        f"# (the robot file's hand gait: {was}; the paper: {PAPER_CRAWL_MM:g} mm).\n"
        "# crawl reads its keyframes (origami-cad crawl ROBOT.toml --gait gait.toml), drive\n"
        "# runs it (origami-cad drive gait.toml --dry-run).\n"
        f"#   {command}\n"
    )


def crawler_gait_header(design: GaitDesign, command: str) -> str:
    """The gait comment of a designed crawler's robot file: forward per cycle (mm) at each
    friction, the legs' order, and ``command``."""
    per = ", ".join(f"{t.forward:.1f} mm at {t.friction:g}" for t in design.best.terms)
    return (
        f"# The gait found with this crawler's design by design-gait --design (forward per\n"
        f"# cycle {per}; the paper: {PAPER_CRAWL_MM:g} mm). Fold ratios p = fold angle / 180 deg\n"
        f"# of the legs [front left, front right, rear left, rear right].\n#   {command}"
    )


def gait_report(
    robot: Robot,
    design: GaitDesign,
    seconds: float,
    command: str,
    search: CrawlerSearch | None = None,
) -> dict:
    """results.json of a gait search: the settings, the best and the hand gait (mm per
    cycle), the limits, what limits the stride, every candidate; ``seconds``: search time;
    with the joint design search ``search``, its ``crawler_design`` too."""
    report = {
        "robot": str(robot.source),
        "command": command,
        "search_s": seconds,
        "settings": dataclasses.asdict(design.settings),
        "targets_mm": (  # the shortfall mix's target per friction, resolved
            list(design.settings.target_values()) if design.settings.mix == "shortfall" else None
        ),
        "paper_mm_per_cycle": PAPER_CRAWL_MM,
        "best": design.best.to_dict(),
        "hand_gait": {
            "score_mm": design.hand_score,
            "per_friction": [t.to_dict() for t in design.hand],
        },
        "best_score_per_generation": design.history,
        "what_limits_the_stride": stride_limits(robot, design, PAPER_CRAWL_MM),
        "candidates": [c.to_dict() for c in design.candidates],
    }
    if search is not None:
        report["crawler_design"] = search.to_dict()
    return report
