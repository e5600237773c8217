"""The arm search (:func:`design_arm`) and its winner: eq. 5's ranking checked by the arm's
own strings.

A design ranks by eq. 5 (:func:`~origami_cad.design.search.rank_designs`), but it must
also be folded by the strings that will drive it: every design's route (one onboard
TSA on the base panel, :func:`~origami_cad.design.arm_route.choose_arm_tsa`) is built
and folded by the DCQC model. A design whose route cannot be built, or whose strings
stop short of its fold range's end ``p_e``, is *refused*; the winner is the first
design in rank order that is not refused (a tied one when any is).

When every design is refused, the search still has a result: the winner is eq. 5's
best, :attr:`ArmSearch.all_refused` is true, :meth:`ArmSearch.shortfall` says how far
its strings fold it, and a :class:`~origami_cad.errors.DesignWarning` is issued.

The same rule serves ``origami_cad.design_arm`` in a script and ``origami-cad
design-arm``: both give the same winner.
"""

from __future__ import annotations

import collections.abc
import concurrent.futures as cf
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, overload

from origami_cad._args import Arg, checked
from origami_cad.design.arm_route import ArmStrings, choose_arm_tsa
from origami_cad.design.search import FITNESS_TIE, ArmDesign, rank_designs, run_one, ties
from origami_cad.design.task import ArmTask, SearchSettings, task_to_dict
from origami_cad.errors import DesignError, DesignWarning, warn
from origami_cad.parallel import local_pool, start_context

__all__ = [
    "ARM_TIE_RULE",
    "AT_TOLERANCE",
    "ArmSearch",
    "arm_route_header",
    "choose_arm_winner",
    "design_arm",
]

#: A design's strings must fold it to within this of its ``p_e`` (fold ratio): the
#: tolerance ``drive`` allows a keyframe (``origami_cad.drive.from_model.AT_TOLERANCE``).
AT_TOLERANCE = 1e-3

#: How the winner is chosen, as results.json states it.
ARM_TIE_RULE = (
    "designs within fitness_tolerance of the best tie; of those, the largest "
    "fold range p_e wins (within 1e-6), then the lowest run index; a design whose "
    "route cannot be built or whose strings cannot fold it to p_e is refused and "
    "never wins"
)
_ALL_REFUSED_RULE = (
    "; when every design is refused, eq. 5's best wins and winner_refused says how far "
    "its strings fold it"
)


def arm_route_header(design: ArmDesign) -> str:
    """The comment lines of a designed arm's route file: the commands that read it.

    The ``sequence`` line folds the arm to its ``p_e`` (fold ratio) and back.
    """
    return (
        "# The string route of best.toml (origami-cad design-arm): one onboard TSA on the\n"
        "# base panel twists two strings that run along the arm, parallel to the transition\n"
        "# vectors, through every panel of one row each; sides by the DCQC rule.\n"
        "#   origami-cad route best.toml route.toml -o route        (DCQC)\n"
        "#   origami-cad simulate best.toml route.toml -o sim       (bar-and-hinge)\n"
        "#   origami-cad arm-scene TASK best.toml route.toml -o fig8 (tip against P_end)\n"
        f"#   origami-cad sequence best.toml route.toml -o arm_fold.toml --keyframes 0:0 "
        f"20:{design.fold_ratio_end:.3f} 30:{design.fold_ratio_end:.3f} 40:0\n"
    )


@dataclass(frozen=True)
class ArmSearch(collections.abc.Sequence):
    """The designs of an arm search, the winner first, with the winner's strings.

    It is a sequence of :class:`ArmDesign` (``search[0]`` is the winner, then the others
    in eq. 5's rank order), so code written for a ranked list keeps working.

    Attributes
    ----------
    designs : tuple of ArmDesign
        Every feasible design, the winner first.
    strings : ArmStrings or None
        The winner's string route and its DCQC folding (``None``: no design, or the
        strings were not checked).
    refused : dict of int to str
        Run index -> why its design was refused by the string check.
    checked : bool
        Whether the string check ran (``design_arm(..., check_strings=False)``: not).
    """

    designs: tuple[ArmDesign, ...]
    strings: ArmStrings | None = None
    refused: dict[int, str] = field(default_factory=dict)
    checked: bool = True

    @overload
    def __getitem__(self, index: int) -> ArmDesign: ...
    @overload
    def __getitem__(self, index: slice) -> tuple[ArmDesign, ...]: ...
    def __getitem__(self, index):
        return self.designs[index]

    def __len__(self) -> int:
        return len(self.designs)

    def __repr__(self) -> str:
        """One line: the designs, the winner's fitness and run, how far its strings fold."""
        if not self.designs:
            return f"<ArmSearch: no feasible design, {len(self.refused)} refused>"
        best = self.designs[0]
        folded = "" if self.folded_to is None else f", its strings fold to p = {self.folded_to:.3g}"
        return (
            f"<ArmSearch: {len(self.designs)} designs, winner fitness {best.fitness:.4g} "
            f"(run {best.run}){folded}, {len(self.refused)} refused>"
        )

    @property
    def winner(self) -> ArmDesign | None:
        """The winning design (``None`` when no run found a feasible one)."""
        return self.designs[0] if self.designs else None

    @property
    def all_refused(self) -> bool:
        """Whether every design was refused (the winner is then eq. 5's best)."""
        return bool(self.designs) and self.designs[0].run in self.refused

    @property
    def folded_to(self) -> float | None:
        """The fold ratio ``p`` the winner's strings reach (DCQC), ``None`` if not simulated."""
        if self.strings is None or self.strings.result is None:
            return None
        return float(self.strings.result.p[-1])

    def shortfall(self) -> str | None:
        """When every design was refused: one line saying how far the winner's strings fold
        it (fold ratios); ``None`` otherwise."""
        if not self.all_refused:
            return None
        best = self.designs[0]
        return (
            f"every design was refused by its strings; the winner is eq. 5's best, run "
            f"{best.run}: {self.refused[best.run]}"
        )

    def summary(self, runs: int, seconds: float) -> str:
        """One line on the winner of ``runs`` runs that took ``seconds`` (s): eq. 5's fitness,
        its distances to the task's points (mm), ``p_e``, improper states."""
        best = self.designs[0]
        t = best.terms
        return (
            f"best of {runs} runs: run {best.run}, f = {best.fitness:.4f}, "
            f"|T_e(0) - P_start| = {t.d_start:.3g} mm, |T_e(p_e) - P_end| = "
            f"{t.d_end:.3g} mm at p_e = {best.fold_ratio_end:.4f} (the fold limit), "
            f"N = {t.improper_states} ({seconds:.1f} s)"
        )

    def tie_line(self) -> str:
        """Which runs tie for the best (eq. 5 within ``FITNESS_TIE``), and which one won."""
        tied = ties(list(self.designs))
        if len(tied) < 2:
            return f"none (run {self.designs[0].run} alone)"
        runs = ", ".join(
            f"{r.run} (p_e {r.fold_ratio_end:.4f}{', refused' if r.run in self.refused else ''})"
            for r in tied
        )
        if self.all_refused:
            return f"runs {runs}: run {self.designs[0].run} wins by eq. 5 (its strings refuse all)"
        return (
            f"runs {runs}: run {self.designs[0].run} wins with the largest fold range it can "
            "be folded to"
        )

    def to_dict(self, task: ArmTask, settings: SearchSettings, seconds: float) -> dict[str, Any]:
        """results.json: the task, the search time (s), the tie rule and every design."""
        from origami_cad import __version__

        tie: dict[str, Any] = {
            "rule": ARM_TIE_RULE + (_ALL_REFUSED_RULE if self.all_refused else ""),
            "fitness_tolerance": FITNESS_TIE,
            "tied_runs": [r.run for r in ties(list(self.designs))],
            "refused": {str(run): why for run, why in self.refused.items()},
        }
        data: dict[str, Any] = {
            "origami_cad_version": __version__,
            "task": task_to_dict(task, settings),
            "seconds": seconds,
            "tie": tie,
            "designs": [{**r.to_dict(), "refused": self.refused.get(r.run)} for r in self],
        }
        if self.all_refused:
            best = self.designs[0]
            stop = (
                None
                if self.strings is None or self.strings.result is None
                else self.strings.result.stop
            )
            data["winner_refused"] = {
                "run": best.run,
                "why": self.refused[best.run],
                "strings_fold_to_p": self.folded_to,
                "stop": None if stop is None else str(stop),
                "fold_ratio_end": best.fold_ratio_end,
            }
        return data


def _refusal(design: ArmDesign, strings: ArmStrings) -> str | None:
    """Why the string check refuses a design (``None``: accepted)."""
    if strings.error is not None:
        return f"its string route cannot be built: {strings.error}"
    reached = float(strings.result.p[-1])
    if reached < design.fold_ratio_end - AT_TOLERANCE:
        return (
            f"its strings fold it to p = {reached:.4f} only ({strings.result.stop}), short "
            f"of its fold range's end p_e = {design.fold_ratio_end:.4f}"
        )
    return None


def choose_arm_winner(designs: collections.abc.Sequence[ArmDesign], task: ArmTask) -> ArmSearch:
    """The winner of ranked arm designs: the first whose strings fold it over its range.

    Parameters
    ----------
    designs : sequence of ArmDesign
        Ranked by :func:`~origami_cad.design.search.rank_designs` (``design_arm`` does).
    task : ArmTask
        Their task (its unit width, ``[fabrication]`` b, h, t in mm or ``fold_limit``
        in degrees give each design's route).

    Returns
    -------
    ArmSearch
        The designs with the winner first, the winner's strings and the refused designs.
        When every design is refused, the winner is eq. 5's best: a
        :class:`~origami_cad.errors.DesignWarning` says how far its strings fold it.
        Nothing is written.
    """
    ranked = list(designs)
    refused: dict[int, str] = {}
    chosen: dict[int, ArmStrings] = {}
    for design in ranked:
        strings = chosen[design.run] = choose_arm_tsa(design, task, header=arm_route_header(design))
        why = _refusal(design, strings)
        if why is not None:
            refused[design.run] = why
    if not ranked:
        return ArmSearch((), None, refused)
    winner = next((d for d in ranked if d.run not in refused), ranked[0])
    search = ArmSearch(
        (winner, *(d for d in ranked if d is not winner)), chosen[winner.run], refused
    )
    line = search.shortfall()
    if line is not None:
        warn(line, DesignWarning, stacklevel=2)
    return search


@checked(
    DesignError,
    task=Arg("object", types=(ArmTask,), optional=False),
    settings=Arg("object", types=(SearchSettings,), optional=False),
    executor=Arg("object", types=(cf.Executor,)),
    progress=Arg("callable", length=3),
    check_strings=Arg("bool", optional=False),
)
def design_arm(
    task: ArmTask,
    settings: SearchSettings,
    executor: cf.Executor | None = None,
    progress: Callable[[int, int, float], None] | None = None,
    *,
    check_strings: bool = True,
) -> ArmSearch:
    """Run ``settings.runs`` independent CMA-ES searches; best design of each, the winner first.

    Parameters
    ----------
    task : ArmTask
        The design task.
    settings : SearchSettings
        Runs, seed, population size, generations.
    executor : concurrent.futures.Executor, optional
        Where the runs go (a Dask or Ray executor spreads them over a cluster).
        Default: a process pool with one worker per core.
    progress : callable, optional
        ``progress(run, generation, best_fitness)``, called in this process as
        runs advance (only with the default executor or a thread/in-process one
        sharing this process's memory; silent otherwise).
    check_strings : bool
        Fold every design by its own strings and choose the winner by
        :func:`choose_arm_winner` (what ``origami-cad design-arm`` does); ``False``:
        eq. 5's ranking alone, no strings simulated.

    Returns
    -------
    ArmSearch
        A sequence of :class:`ArmDesign`, one per feasible run, ranked by
        :func:`~origami_cad.design.search.rank_designs` (the designs that tie for the
        best fitness first, by fold range then run index) with the winner of the string
        check moved first; the winner's strings and the refused designs. Infeasible
        runs (the chain always hit a prohibited area) are left out; none feasible: an
        empty ``ArmSearch``. When the strings refuse every design, the winner is eq. 5's
        best and a :class:`~origami_cad.errors.DesignWarning` says how far its strings
        fold it.
    """
    own = executor is None
    queue = None
    manager = None
    if own:
        executor = local_pool(settings.runs)
        if progress is not None:
            manager = start_context().Manager()
            queue = manager.Queue()
    elif progress is not None and isinstance(executor, cf.ThreadPoolExecutor):
        queue = _CallbackQueue(progress)
    try:
        futures = [executor.submit(run_one, task, settings, r, queue) for r in range(settings.runs)]
        if manager is not None and queue is not None:
            pending = set(futures)
            while pending:
                _, pending = cf.wait(pending, timeout=0.1)
                _drain(queue, progress)
            _drain(queue, progress)
        results = [f.result() for f in futures]
    finally:
        if own:
            executor.shutdown(wait=True, cancel_futures=True)
        if manager is not None:
            manager.shutdown()
    ranked = rank_designs(results)
    if not check_strings:
        return ArmSearch(tuple(ranked), checked=False)
    return choose_arm_winner(ranked, task)


class _CallbackQueue:
    def __init__(self, callback: Callable[[int, int, float], None]) -> None:
        self.callback = callback

    def put(self, item: tuple[int, int, float]) -> None:
        self.callback(*item)


def _drain(queue: Any, progress: Callable[[int, int, float], None] | None) -> None:
    while True:
        try:
            item = queue.get_nowait()
        except Exception:  # queue.Empty from a manager proxy
            return
        if progress is not None:
            progress(*item)
