"""Joint CMA-ES search of the crawler's design and its gait (the design side).

The genome is the design genes (:data:`DESIGN_GENES`, each in [0, 1] over its bounds)
followed by the gait genes of :mod:`origami_cad.crawler.gait` (``DIMENSION`` of them). A
candidate's design numbers decode to a :class:`~origami_cad.crawler.design.CrawlerDesign`:

================  ==================  ===================================================
gene              default bounds      what it sets
================  ==================  ===================================================
leg_length        90 .. 125 mm        the legs, hinge to foot; the body is shortened to
                                      keep the robot within the paper's 340 mm at every
                                      fold from the strings' 20 deg floor to the blocker
                                      (at most 180 mm, the built robot's)
leg_hole          6 .. 20 mm          the leg's string holes from the hinge
body_hole         15 .. 45 mm         the body's string holes from the hinge (at most
                                      20 mm short of the body's middle)
blocker_angle     45 .. 60 deg        the blockers (the paper's: up to 60 deg)
crease_thickness  0.4 .. 0.8 mm       the TPU crease layer t, in 0.1 mm layers; the shell
                                      s thins to leave one 0.1 mm layer of infill (shell_for):
                                      a stiffer crease (E t^3 / (12 w)) unfolds the legs
================  ==================  ===================================================

Lengths are rounded to 0.1 mm (as the route files write the holes) and the blocker to
0.1 deg, so a candidate's written files walk exactly the scored crawler. Every candidate
is within the envelope by construction (:func:`body_for_envelope`); each is walked as
``design-gait`` walks a gait (:func:`~origami_cad.crawler.gait.evaluate_gait`) on the
crawler its design genes draw. Units: mm, deg at the edges.
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import functools
import math
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import cma
import numpy as np

from origami_cad._libm import canonical_eigh
from origami_cad.crawler.design import (
    ENVELOPE,
    FLOOR_DEG,
    LAYER,
    MODULE_FRONT,
    CrawlerDesign,
    CrawlerFiles,
    crawler_extent,
    crawler_files,
    crawler_pattern,
    module_centre,
    shell_for,
    write_crawler,
)
from origami_cad.crawler.gait import (
    DIMENSION,
    FAILED,
    P_FLOOR,
    GaitCandidate,
    GaitDesign,
    GaitSettings,
    GaitTerms,
    decode_gait,
    encode_gait,
    evaluate_gait,
    hard_hits,
    settings_score,
)
from origami_cad.crawler.robot import Robot, load_robot, with_gait
from origami_cad.design.search import UnitBox
from origami_cad.errors import DesignError, OrigamiCadError
from origami_cad.parallel import local_pool

__all__ = [
    "BODY_MAX",
    "BODY_MIN",
    "DESIGN_BOUNDS",
    "DESIGN_GENES",
    "CrawlerSearch",
    "body_for_envelope",
    "crawler_robot",
    "decode_design",
    "design_crawler",
    "evaluate_crawler",
    "max_extent",
    "parse_design_bounds",
]

#: The design genes, in genome order.
DESIGN_GENES = ("leg_length", "leg_hole", "body_hole", "blocker_angle", "crease_thickness")
#: Default bounds of each design gene (mm; blocker in deg).
DESIGN_BOUNDS = {
    "leg_length": (90.0, 125.0),
    "leg_hole": (6.0, 20.0),
    "body_hole": (15.0, 45.0),
    "blocker_angle": (45.0, 60.0),
    "crease_thickness": (0.4, 0.8),
}
#: What any bound may be: the legs must carry their module, the blocker is the paper's
#: 60 deg at most, the crease layer is at most 0.9 mm (a 0.6 mm shell is left).
HARD_BOUNDS = {
    "leg_length": (75.0, 200.0),
    "leg_hole": (2.0, 60.0),
    "body_hole": (12.0, 100.0),
    "blocker_angle": (FLOOR_DEG + 5.0, 60.0),
    "crease_thickness": (0.2, 0.9),
}
#: The longest body, mm: the built robot's; and the shortest (the driver module, the
#: adapter and the body's string holes need it).
BODY_MAX, BODY_MIN = 180.0, 100.0


def parse_design_bounds(spec: str | dict | None) -> dict[str, tuple[float, float]]:
    """The design genes' bounds: ``DESIGN_BOUNDS`` with ``spec``'s changes.

    ``spec`` is ``"default"``, or ``"name=low:high,..."`` (names of ``DESIGN_GENES``; mm,
    the blocker in deg), or a dict of ``name: (low, high)``. Raises :class:`DesignError`
    in one line naming the gene and what is wrong (unknown, given twice, low > high,
    outside ``HARD_BOUNDS``), or for an empty ``spec``.
    """
    out = dict(DESIGN_BOUNDS)
    given: dict[str, Any] = {}
    if isinstance(spec, dict):
        given = dict(spec)
    elif isinstance(spec, str) and not spec.strip():
        raise DesignError("design bounds: empty; give 'default' or name=low:high,...")
    elif spec is not None and not isinstance(spec, str):
        raise DesignError(f"design bounds: expected text or a dict, got {spec!r}")
    elif spec and spec.strip() != "default":
        for part in spec.split(","):
            name, sep, rng = part.partition("=")
            low, colon, high = rng.partition(":")
            if not sep or not colon:
                raise DesignError(f"design bounds {part.strip()!r}: expected name=low:high")
            if name.strip() in given:
                raise DesignError(f"design bounds: gene {name.strip()!r} is given twice")
            given[name.strip()] = (low, high)
    for name, pair in given.items():
        if name not in DESIGN_BOUNDS:
            raise DesignError(
                f"design bounds: unknown gene {name!r} (genes: {', '.join(DESIGN_GENES)})"
            )
        try:
            low, high = (float(v) for v in pair)
        except (TypeError, ValueError, OverflowError):
            raise DesignError(f"design bounds {name}: {pair!r} are not two numbers") from None
        hard = HARD_BOUNDS[name]
        if not (math.isfinite(low) and math.isfinite(high) and low <= high):
            raise DesignError(f"design bounds {name}: low {low:g} must not exceed high {high:g}")
        if low < hard[0] or high > hard[1]:
            raise DesignError(
                f"design bounds {name}: {low:g} .. {high:g} is outside {hard[0]:g} .. {hard[1]:g}"
            )
        out[name] = (low, high)
    return out


def body_for_envelope(design: CrawlerDesign, envelope=ENVELOPE) -> float:
    """The longest body (mm, 0.1 mm steps, at most ``BODY_MAX``) that keeps ``design``'s
    robot within ``envelope``'s length at every fold from the floor to the blocker."""
    folds = np.linspace(FLOOR_DEG, design.blocker_angle, 9)
    reach = max(crawler_extent(design, f)[0] for f in folds) - design.body_length
    return min(BODY_MAX, math.floor((envelope[0] - reach) * 10.0 + 1e-6) / 10.0)


def decode_design(bounds: dict[str, tuple[float, float]], u) -> CrawlerDesign:
    """The design of genes ``u (len(DESIGN_GENES),)`` in [0, 1] over ``bounds``.

    Raises :class:`DesignError` when the design cannot be drawn (the legs too long to
    leave a body within the envelope, holes off their panel).
    """
    u = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
    v = {
        n: bounds[n][0] + x * (bounds[n][1] - bounds[n][0])
        for n, x in zip(DESIGN_GENES, u, strict=True)
    }
    t = round(round(v["crease_thickness"] / LAYER) * LAYER, 3)
    d = CrawlerDesign(
        leg_length=round(float(v["leg_length"]), 1),
        leg_hole=round(float(v["leg_hole"]), 1),
        body_hole=15.0,
        blocker_angle=round(float(v["blocker_angle"]), 1),
        crease_thickness=t,
        shell=shell_for(t),
    )
    body = body_for_envelope(d)
    if body < BODY_MIN:
        raise DesignError(
            f"crawler design: legs of {d.leg_length:g} mm leave a body of {body:g} mm within "
            f"the envelope's {ENVELOPE[0]:g} mm, under the {BODY_MIN:g} mm it needs"
        )
    hole = min(round(float(v["body_hole"]), 1), math.floor((body / 2 - 20) * 10) / 10)
    d = dataclasses.replace(d, body_length=body, body_hole=hole)
    cp_leg = module_centre(crawler_pattern(d), "leg_fl")[0] - body / 2.0
    near = math.floor((cp_leg - MODULE_FRONT) * 10.0) / 10.0  # the module's near edge
    return dataclasses.replace(d, leg_hole=min(d.leg_hole, near))


def _rest_gait(cycle: float) -> tuple[np.ndarray, np.ndarray]:
    """Every leg at the strings' floor for one cycle: a placeholder the genes replace."""
    return np.array([0.0, cycle]), np.full((2, 4), P_FLOOR)


def crawler_robot(design: CrawlerDesign, gait=None, folder=None) -> tuple[Robot, CrawlerFiles]:
    """``design``'s crawler, written (into ``folder``, default a temporary one) and read
    back as the robot file would be; its gait ``gait`` (default: the legs at rest)."""
    files = crawler_files(design, gait or _rest_gait(32.0))
    if folder is not None:
        return load_robot(write_crawler(files, folder)), files
    with tempfile.TemporaryDirectory(prefix="crawler_") as tmp:
        robot = load_robot(write_crawler(files, tmp))
    return robot, files


@functools.lru_cache(maxsize=8)
def _cached_robot(design: CrawlerDesign, cycle: float) -> Robot:
    return crawler_robot(design, _rest_gait(cycle))[0]


def evaluate_crawler(bounds: dict, genome, friction: float, settings: GaitSettings) -> GaitTerms:
    """Draw the crawler of ``genome``'s design genes and walk its gait genes' gait at
    ``friction``, scored as :func:`~origami_cad.crawler.gait.evaluate_gait` scores it.

    ``genome`` ``None`` is the start: the built robot's design numbers (within ``bounds``)
    walking the hand gait's genome. A module-level function of picklable arguments; a
    design that cannot be drawn scores ``FAILED`` with why as its hit.
    """
    k = len(DESIGN_GENES)
    try:
        design = decode_design(bounds, np.asarray(genome)[:k])
        robot = _cached_robot(design, settings.cycle)
    except OrigamiCadError as exc:
        return GaitTerms(friction, 0, 0, 0, 0, 0, 0, (f"design refused: {exc}",), FAILED)
    return evaluate_gait(robot, np.asarray(genome)[k:], friction, settings)


@dataclass
class CrawlerSearch:
    """A joint design and gait search's outcome.

    Attributes
    ----------
    gait : GaitDesign
        The candidates as a gait search's (genomes: design genes, then gait genes; the
        ``hand`` candidate is the start: the built robot's numbers and the hand gait's
        genome); ``gait.best`` is the best candidate.
    designs : list of CrawlerDesign or None
        Each candidate's design, in ``gait.candidates``' order (``None``: refused, e.g.
        legs leaving too short a body; such a candidate scores ``FAILED``).
    bounds : dict
        The design genes' bounds.
    """

    gait: GaitDesign
    designs: list[CrawlerDesign | None]
    bounds: dict[str, tuple[float, float]]

    @property
    def best_design(self) -> CrawlerDesign:
        """The best candidate's design."""
        return self.designs[self.gait.candidates.index(self.gait.best)]

    def files(self, header: str | None = None) -> CrawlerFiles:
        """The best crawler's files, its robot file walking the best gait."""
        best = self.gait.best
        return crawler_files(self.best_design, (np.array(best.times), np.array(best.ratios)),
                             header=header)  # fmt: skip

    def robot(self) -> Robot:
        """The best crawler walking the best gait (read back from its files)."""
        best = self.gait.best
        robot = _cached_robot(self.best_design, self.gait.settings.cycle)
        return with_gait(robot, best.times, best.ratios)

    def to_dict(self) -> dict[str, Any]:
        """For ``results.json``: the genes, their bounds, the best design, each candidate's."""
        return {
            "design_genes": list(DESIGN_GENES),
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "envelope_mm": list(ENVELOPE),
            "best_design": self.best_design.to_dict(),
            "best_extent_mm": list(max_extent(self.best_design)),
            "start_design": self.designs[0].to_dict(),
            "candidate_designs": [d.to_dict() if d else None for d in self.designs],
        }


def max_extent(design: CrawlerDesign) -> tuple[float, float, float]:
    """The largest extent (x, y, z) mm over folds from the floor to the blocker."""
    folds = np.linspace(FLOOR_DEG, design.blocker_angle, 9)
    return tuple(float(v) for v in np.array([crawler_extent(design, f) for f in folds]).max(0))


def _strategy(x0, settings: GaitSettings) -> cma.CMAEvolutionStrategy:
    opts = {
        "maxstd": 1.0 / 3.0, "seed": settings.seed + 1, "popsize": settings.popsize,
        "verbose": -9, "verb_log": 0, "verb_disp": 0, "maxiter": settings.generations,
        "CMA_eigenmethod": canonical_eigh,
    }  # fmt: skip
    return cma.CMAEvolutionStrategy(np.asarray(x0, float), settings.sigma0, opts)


def _start_genome(robot: Robot, bounds: dict) -> np.ndarray:
    """The built robot's design numbers (clipped into ``bounds``) and the robot file's
    gait genome."""
    built = CrawlerDesign()
    u = [(getattr(built, n) - bounds[n][0]) / max(bounds[n][1] - bounds[n][0], 1e-9)
         for n in DESIGN_GENES]  # fmt: skip
    return np.concatenate([np.clip(u, 0.0, 1.0), encode_gait(robot)])


def _candidates(executor, bounds, pop, settings, generation: int):
    jobs = [executor.submit(evaluate_crawler, bounds, x, mu, settings)
            for x in pop for mu in settings.frictions]  # fmt: skip
    done = [j.result() for j in jobs]
    f, k, out, designs = len(settings.frictions), len(DESIGN_GENES), [], []
    for i, x in enumerate(pop):
        terms = tuple(done[i * f : (i + 1) * f])
        try:
            design = decode_design(bounds, x[:k])
            walker = _cached_robot(design, settings.cycle)
            times, ratios = decode_gait(walker, x[k:], settings.cycle)
        except OrigamiCadError:  # refused (scored FAILED): no design, no gait
            design, times, ratios = None, (0.0,), ((P_FLOOR,) * 4,)
        out.append(GaitCandidate(
            0, generation, tuple(float(v) for v in x), tuple(float(t) for t in times),
            tuple(tuple(float(v) for v in row) for row in ratios), terms,
            settings_score(terms, settings), hand=generation == 0,
        ))  # fmt: skip
        designs.append(design)
    return out, designs


def design_crawler(
    robot: Robot,
    settings: GaitSettings | None = None,
    bounds: dict | str | None = None,
    executor: cf.Executor | None = None,
    progress: Callable[[int, int], None] | None = None,
    start=None,
) -> CrawlerSearch:
    """Search the crawler's design genes and its gait together with CMA-ES; returns data.

    Parameters
    ----------
    robot : Robot
        The robot file whose gait is the start (``encode_gait``) and whose friction the
        report uses; the design starts from the built robot's numbers.
    settings : GaitSettings, optional
        As :func:`~origami_cad.crawler.gait.design_gait`'s (``runs`` is ignored: one run).
    bounds : dict or str, optional
        The design genes' bounds (:func:`parse_design_bounds`).
    executor, progress
        As :func:`~origami_cad.crawler.gait.design_gait`'s.
    start : array-like, optional
        The genome CMA-ES starts from and scores first (design genes, then gait genes, in
        [0, 1]; e.g. a previous search's ``results.json`` best ``genome``); default the
        built robot's numbers within ``bounds`` and the robot file's gait.

    Returns
    -------
    CrawlerSearch
        Its best is the best candidate within every limit; the start candidate (the built
        robot's numbers within ``bounds``, the hand gait's genome) is scored first.
    """
    settings = settings or GaitSettings()
    bounds = parse_design_bounds(bounds)
    dim = len(DESIGN_GENES) + DIMENSION
    total, done = settings.popsize * settings.generations + 1, [0]
    own = executor is None
    pool = local_pool(settings.popsize * len(settings.frictions)) if own else executor
    try:
        dim_ok = start is None or len(start) == dim
        if not dim_ok:
            raise DesignError(f"design_crawler: start genome has {len(start)} genes, not {dim}")
        start = _start_genome(robot, bounds) if start is None else np.clip(start, 0.0, 1.0)
        cands, designs = _candidates(pool, bounds, [start], settings, 0)
        done[0] += 1
        if progress is not None:
            progress(done[0], total)
        es, box, history = _strategy(start, settings), UnitBox(dim), []
        for generation in range(1, settings.generations + 1):
            genotypes = es.ask()
            found, ds = _candidates(pool, bounds, box(np.asarray(genotypes)), settings, generation)
            es.tell(genotypes, [-c.score for c in found])
            cands, designs = cands + found, designs + ds
            history.append(max(c.score for c in cands))
            done[0] += len(found)
            if progress is not None:
                progress(done[0], total)
    finally:
        if own:
            pool.shutdown(wait=True, cancel_futures=True)
    clean = [c for c in cands if not hard_hits(c)] or cands
    best = max(clean, key=lambda c: c.score)
    gait = GaitDesign(best, cands, [history], cands[0].terms, cands[0].score, settings)
    return CrawlerSearch(gait, designs, bounds)
