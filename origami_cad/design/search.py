"""CMA-ES search for origami robotic arms: ten independent runs, top designs first.

Genome
------
Every variable is normalised to [0, 1] and bounded with ``cma``'s ``bounds``:
``n + 1`` lengths (linear in ``length_range``) and ``n`` shape angles. A shape
angle may lean either way: ``u < 0.5`` decodes to ``[180 - hi, 180 - lo]``
degrees (backward-leaning legs, turning one way) and ``u >= 0.5`` to
``[lo, hi]`` (forward-leaning, turning the other way), ordered so that the
turn angle of eq. 2 grows monotonically with ``u``: the only jump is across the
forbidden band of small turns (``|beta|`` below ``lo``), where both sides give
small turns, so there is no discontinuity trap.

With ``task.codesign`` one more variable, last, is the inner bias of every
crease, linear in ``[task.bias, task.max_bias]`` mm (:func:`decode_bias`).

Entry flag
----------
``EF_0`` enters eq. 2 only through ``(-1)^EF``; flipping it while replacing
every ``beta_i`` by ``180 - beta_i`` gives exactly the same chain. Both values
are searched as two sub-searches: with ``entry_flag = "both"`` the runs
alternate ``EF_0 = 1, 0, 1, ...``, so the ranking compares the two crease
pattern families (their panels differ, their kinematics can match).

Runs are independent and reproducible: run ``k`` seeds both its
start point and CMA-ES with ``seed + k``; no ``outcmaes/`` files are written.
:func:`run_one` is one such run, a module-level function of picklable
arguments, so the runs can be mapped over any executor.

Bounds
------
The genome is kept in [0, 1] by ``cma``'s own boundary transformation
(``BoxConstraintsLinQuadTransformation``: the identity inside, quadratic near
the bounds, periodic beyond), applied here to the whole population at once
(:class:`UnitBox`) instead of one solution at a time inside ``cma``: the same
numbers, with CMA-ES told the genotypes it sampled, as ``cma`` does with
``bounds``, and its largest step capped at a third of the range, as ``cma``
caps it for bounds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import cma
import numpy as np

from origami_cad._libm import canonical_eigh
from origami_cad.design.fitness import FitnessResult, FitnessTerms, arm_fitness
from origami_cad.design.task import ArmTask, SearchSettings
from origami_cad.pattern.tg import TGDesign

__all__ = [
    "COST_RESOLUTION",
    "FITNESS_TIE",
    "FOLD_RANGE_TIE",
    "ArmDesign",
    "RunResult",
    "UnitBox",
    "canonical_eigh",
    "decode",
    "decode_bias",
    "rank_designs",
    "run_one",
    "ties",
]

#: Designs whose fitness (eq. 5) is within this of the best tie: CMA-ES stops a run
#: within 1e-4 of eq. 5's maximum, so every run that gets there is as good as the
#: others. Between CPUs a run's fitness moves by about 1e-11 (see the module's
#: notes), far below this.
FITNESS_TIE = 1e-3

#: Tied designs whose fold ranges ``p_e`` differ by less than this tie on it too
#: (then the lowest run index wins).
FOLD_RANGE_TIE = 1e-6

#: CMA-ES ranks costs rounded to this (eq. 5 units; the fitness of a perfect arm is
#: 60). A CPU's vectorised kernels change CMA-ES's own arithmetic (numpy's SIMD
#: ``exp``) in the last bits, which moves a cost by about 1e-13; two samples whose
#: costs differ by that little used to swap ranks on one machine and not on another,
#: and the run went elsewhere. Rounded, they are equal on both (and CMA-ES orders equal
#: costs by index), unless a cost lies within 1e-13 of a rounding boundary: about one
#: sample in ten million. ``ftarget`` (1e-4 from the maximum) is far above it.
COST_RESOLUTION = 1e-6


class UnitBox:
    """``cma``'s bound transformation into [0, 1]^N, vectorised over a population.

    The same operations, in the same order, as
    ``cma.transformations.BoxConstraintsLinQuadTransformation.__call__`` with
    bounds ``[0, 1]``, one row per solution (a test checks them against ``cma``).

    Parameters
    ----------
    dimension : int
        Number of variables ``N``.
    """

    def __init__(self, dimension: int) -> None:
        from cma.transformations import BoxConstraintsLinQuadTransformation

        tf = BoxConstraintsLinQuadTransformation([[0.0, 1.0]])
        tf.initialize(dimension)
        self.lb, self.ub, self.al, self.au = tf._lb, tf._ub, tf._al, tf._au

    def __call__(self, genotypes: np.ndarray) -> np.ndarray:
        """Phenotypes in [0, 1] of genotypes ``(P, N)`` (a new array)."""
        y = np.array(genotypes, dtype=float)
        lb = np.broadcast_to(self.lb, y.shape)
        ub = np.broadcast_to(self.ub, y.shape)
        al = np.broadcast_to(self.al, y.shape)
        au = np.broadcast_to(self.au, y.shape)
        idx = (y < lb - 2 * al - (ub - lb) / 2.0) | (y > ub + 2 * au + (ub - lb) / 2.0)
        if idx.any():
            r = 2 * (ub[idx] - lb[idx] + al[idx] + au[idx])  # period
            s = lb[idx] - 2 * al[idx] - (ub[idx] - lb[idx]) / 2.0  # start
            y[idx] -= r * ((y[idx] - s) // r)  # shift
        idx = y > ub + au
        y[idx] -= 2 * (y[idx] - ub[idx] - au[idx])
        idx = y < lb - al
        y[idx] += 2 * (lb[idx] - al[idx] - y[idx])
        idx = y < lb + al
        y[idx] = lb[idx] + (y[idx] - (lb[idx] - al[idx])) ** 2 / 4 / al[idx]
        idx = y > ub - au
        y[idx] = ub[idx] - (y[idx] - (ub[idx] + au[idx])) ** 2 / 4 / au[idx]
        return y


#: the seed given to cma for our seed 0: cma reads 0 as "seed from the clock", and run ``k``
#: of a search is seeded ``seed + k`` <= 2**32 - 2, so this one is used by no other run
CMA_SEED_FOR_ZERO = 2**32 - 1


def cma_seed(seed: int) -> int:
    """The seed passed to ``cma`` for a run seeded ``seed``: itself, but 0 kept reproducible.

    ``cma`` takes a seed of 0 as "from the clock", so ``design-arm --seed 0`` gave a new
    result on every call; 0 maps to :data:`CMA_SEED_FOR_ZERO` instead, every other seed to
    itself (the results of seeds 1 ... are unchanged).

    Examples
    --------
    >>> cma_seed(0) == CMA_SEED_FOR_ZERO, cma_seed(1), cma_seed(7)
    (True, 1, 7)
    """
    return CMA_SEED_FOR_ZERO if seed == 0 else seed


def decode(task: ArmTask, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Decode normalised genomes ``x (D, 2n + 1)`` to lengths (mm) and shape angles (radians)."""
    x = np.clip(np.atleast_2d(np.asarray(x, dtype=float)), 0.0, 1.0)
    n1 = task.vectors
    lo, hi = task.length_range
    lengths = lo + x[:, :n1] * (hi - lo)
    blo, bhi = task.shape_angle_range
    u = x[:, n1 : 2 * n1 - 1]
    back = (180.0 - bhi) + (u / 0.5) * (bhi - blo)
    front = blo + ((u - 0.5) / 0.5) * (bhi - blo)
    beta = np.where(u < 0.5, back, front)
    return lengths, np.radians(beta)


def decode_bias(task: ArmTask, x: np.ndarray) -> np.ndarray | None:
    """The co-designed inner bias of each genome, mm (``None`` without ``task.codesign``)."""
    if not task.codesign:
        return None
    x = np.clip(np.atleast_2d(np.asarray(x, dtype=float)), 0.0, 1.0)
    return task.bias + x[:, 2 * task.vectors - 1] * (task.max_bias - task.bias)


@dataclass(frozen=True)
class ArmDesign:
    """One designed arm: the TG design variables, its fitness terms and trajectory.

    Attributes
    ----------
    lengths : tuple of float
        ``l_0 .. l_n``, mm.
    shape_angles : tuple of float
        ``beta_1 .. beta_n``, degrees.
    entry_flag : int
        ``EF_0``.
    fitness : float
        ``f`` of eq. 5.
    terms : FitnessTerms
        The terms of eq. 5.
    tips : ndarray, shape (S, 2)
        ``T_e`` at every sample, mm.
    run, generations : int
        Index of the CMA-ES run and the number of generations it ran.
    history : tuple of float
        Best fitness after each generation.
    fold_ratio_end : float
        ``p_e``: the end of the fold range the printed arm reaches (eq. 6 and
        the legs' kinematics), where ``T_e`` should meet ``P_end``.
    bias : float
        Inner bias of every crease, mm (co-designed, or the task's).
    """

    lengths: tuple[float, ...]
    shape_angles: tuple[float, ...]
    entry_flag: int
    fitness: float
    terms: FitnessTerms
    tips: np.ndarray
    run: int
    generations: int
    history: tuple[float, ...]
    fold_ratio_end: float = 1.0
    bias: float = 3.0

    def tg(self, task: ArmTask, unit_width: float = 36.0, copies: int = 3) -> TGDesign:
        """The design as a :class:`TGDesign` (mm, degrees), ready to fabricate."""
        return TGDesign(
            self.lengths,
            self.shape_angles,
            self.entry_flag,
            unit_width,
            copies,
            start=task.start,
            hypar_base=task.hypar_base,
        )

    def to_dict(self) -> dict[str, Any]:
        """The design for a JSON file (``results.json``), with units in the keys."""
        return {
            "run": self.run,
            "fitness": self.fitness,
            "lengths_mm": list(self.lengths),
            "shape_angles_deg": list(self.shape_angles),
            "entry_flag": self.entry_flag,
            "terms": self.terms.to_dict(),
            "generations": self.generations,
            "fold_ratio_end": self.fold_ratio_end,
            "bias_mm": self.bias,
            "tip_mm": self.tips.tolist(),
            # null: no design of that generation met the task's constraints (-inf inside)
            "best_fitness_per_generation": [h if math.isfinite(h) else None for h in self.history],
        }


RunResult = ArmDesign


def run_one(
    task: ArmTask,
    settings: SearchSettings,
    run: int,
    progress: Any = None,
) -> ArmDesign:
    """One CMA-ES run (index ``run``), seeded ``settings.seed + run``.

    ``progress``, if given, is a queue-like object receiving
    ``(run, generation, best_fitness)`` after every generation.
    """
    seed = settings.seed + run
    flag = task.entry_flag if task.entry_flag is not None else (1 if run % 2 == 0 else 0)
    rng = np.random.default_rng(seed)
    x0 = rng.uniform(0.15, 0.85, task.dimension)
    opts = {
        # [0, 1] by UnitBox, for the whole population at once; the step cap that
        # cma would derive from these bounds (a third of their range)
        "maxstd": 1.0 / 3.0,
        "seed": cma_seed(seed),
        "verbose": -9,
        "verb_log": 0,
        "verb_disp": 0,
        "maxiter": settings.max_generations,
        "tolfun": 1e-9,
        "tolflatfitness": 50,
        "CMA_eigenmethod": canonical_eigh,
        # eq. 5 cannot exceed 60 + sum(w) / 10 (every distance 0): stop once within
        # 1e-4 of it (the distances are then below 1e-3 mm)
        "ftarget": -(60.0 + float(task.weights.sum()) / 10.0) + 1e-4,
    }
    if settings.popsize:
        opts["popsize"] = settings.popsize
    es = cma.CMAEvolutionStrategy(x0, settings.sigma0, opts)
    box = UnitBox(task.dimension)
    history: list[float] = []
    best_x, best_cost = x0, math.inf
    flags = None
    while not es.stop():
        genotypes = es.ask()
        pop = box(genotypes)
        if flags is None or len(flags) != len(pop):
            flags = np.full(len(pop), flag)
        lengths, beta = decode(task, pop)
        cost = arm_fitness(task, lengths, beta, flags, decode_bias(task, pop)).cost()
        cost = np.round(cost / COST_RESOLUTION) * COST_RESOLUTION
        es.tell(genotypes, cost.tolist())
        k = int(np.argmin(cost))
        if cost[k] < best_cost:
            best_cost, best_x = float(cost[k]), pop[k].copy()
        history.append(-best_cost if best_cost < 1e3 else -math.inf)
        if progress is not None:
            progress.put((run, len(history), history[-1]))
    lengths, beta = decode(task, best_x)
    res: FitnessResult = arm_fitness(task, lengths, beta, [flag], decode_bias(task, best_x))
    return ArmDesign(
        lengths=tuple(float(v) for v in lengths[0]),
        shape_angles=tuple(float(v) for v in np.degrees(beta[0])),
        entry_flag=flag,
        fitness=float(res.fitness[0]),
        terms=res.terms(0),
        tips=res.tips[0],
        run=run,
        generations=len(history),
        history=tuple(history),
        fold_ratio_end=float(res.fold_ratio_end[0]),
        bias=float(res.bias[0]),
    )


def rank_designs(designs: list[ArmDesign]) -> list[ArmDesign]:
    """Feasible designs, best first, by a rule that does not depend on the machine.

    The designs within :data:`FITNESS_TIE` of the best fitness tie (:func:`ties`);
    they come first, ordered by

    1. the largest printable fold range ``p_e`` (``fold_ratio_end``: the arm that
       folds furthest before a crease meets its eq. 6 limit), values within
       :data:`FOLD_RANGE_TIE` counting as equal;
    2. the lowest run index.

    The others follow by decreasing fitness, then run index. A run's design can
    differ from one CPU to another in its last bits (numpy's SIMD sin and cos), which
    used to decide between tied designs; now only differences far larger than those
    bits do. Infeasible designs (fitness not finite) are left out.

    Examples
    --------
    >>> from types import SimpleNamespace as D
    >>> runs = [D(fitness=60.0, fold_ratio_end=0.3, run=0),
    ...         D(fitness=60.0 - 1e-5, fold_ratio_end=0.4, run=1),
    ...         D(fitness=59.0, fold_ratio_end=0.9, run=2)]
    >>> [d.run for d in rank_designs(runs)]
    [1, 0, 2]
    """
    feasible = [r for r in designs if math.isfinite(r.fitness)]
    tied = ties(feasible)  # none when no design is feasible
    chosen = {id(r) for r in tied}  # by identity: designs hold arrays, == is not a bool
    rest = sorted((r for r in feasible if id(r) not in chosen), key=lambda r: (-r.fitness, r.run))
    ordered: list[ArmDesign] = []
    pool = sorted(tied, key=lambda r: r.run)
    while pool:  # the largest p_e, or the first of those within FOLD_RANGE_TIE of it
        top = max(r.fold_ratio_end for r in pool)
        pick = next(r for r in pool if r.fold_ratio_end >= top - FOLD_RANGE_TIE)
        ordered.append(pick)
        pool = [r for r in pool if r is not pick]
    return ordered + rest


def ties(designs: list[ArmDesign]) -> list[ArmDesign]:
    """The designs whose fitness is within :data:`FITNESS_TIE` of the best (in the given order)."""
    finite = [r.fitness for r in designs if math.isfinite(r.fitness)]
    if not finite:
        return []
    best = max(finite)
    return [r for r in designs if math.isfinite(r.fitness) and r.fitness >= best - FITNESS_TIE]
