"""The horizon bounds of the lazy planner (:mod:`plansynth.reach.lazy.planner`, whose
docstring describes them; beyond Shoukry et al., CDC 2016, Algorithm 1, which tries
horizons from 0): the first horizon tried and DIS-PLAN's time windows, from the
breadth-first, physical, box and proved bounds and the separator chains, and the
refutation of every horizon up to the maximum when a bound already exceeds it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

from plansynth.reach.abstraction import Abstraction
from plansynth.reach.lazy.bounds import (
    SEPARATOR_MAX_REGIONS,
    ChainBounds,
    chain_gaps,
    physical_lower_bound,
    proved_horizon_bound,
    separator_bounds,
    time_windows,
)
from plansynth.reach.lazy.claims import EXACT_SAMPLES, EXACT_SEGMENTS, not_a_proof
from plansynth.reach.lazy.displan import RegionGraph
from plansynth.reach.lazy.loop import LoopOutcome
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.lazy.transit import GOAL, START, TransitCheck
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachStatus

__all__ = ["HorizonBounds", "chain_bounds", "count_bound", "horizon_bounds", "refuted_by_bounds", "with_chains"]

#: rounds of LP refinement of the critical separator chain (see chain_bounds)
CHAIN_ROUNDS = 4


@dataclass(frozen=True)
class HorizonBounds:
    """The horizon bounds (see the module docstring): each as the counters record it,
    the first horizon tried and DIS-PLAN's time windows (None: no windows)."""

    bfs: float
    physical: int
    box: float
    proved: float
    first: int
    earliest: Sequence[float] | None
    to_go: Sequence[float] | None


def count_bound(bound: float) -> int | None:
    return None if math.isinf(bound) else int(bound)


def horizon_bounds(
    problem: ReachProblem, abstraction: Abstraction, graph: RegionGraph, opts: LazyOptions, L_max: int
) -> HorizonBounds:
    """The lower bounds on the horizon and DIS-PLAN's time windows (module docstring)."""
    bfs = graph.horizon_lower_bound()
    phys = physical_lower_bound(problem) if opts.lower_bound else 0
    windows = (
        time_windows(problem, abstraction, L_max, adjacency=graph.adjacency)
        if (opts.lower_bound and math.isfinite(bfs))
        else None
    )
    proved = proved_horizon_bound(problem, abstraction, L_max, segment_safe=opts.segment_safe)
    box = windows.horizon if windows is not None else 0
    if not math.isfinite(bfs) or not math.isfinite(box):
        first = L_max + 1
    else:
        first = int(max(bfs, phys, box)) if opts.lower_bound else 0
    return HorizonBounds(
        bfs,
        phys,
        box,
        proved,
        first,
        None if windows is None else windows.earliest,
        None if windows is None else windows.to_go,
    )


def with_chains(bounds: HorizonBounds, chain: ChainBounds | None, L_max: int, counters: dict) -> HorizonBounds:
    """``bounds`` raised by the separator chains (when they apply)."""
    if chain is None:
        return bounds
    counters["chain_bound"] = count_bound(chain.horizon)
    first = L_max + 1 if math.isinf(chain.horizon) else max(bounds.first, int(chain.horizon))
    counters["first_horizon"] = first
    return replace(
        bounds,
        first=first,
        earliest=tuple(max(a, b) for a, b in zip(bounds.earliest, chain.earliest)),
        to_go=tuple(max(a, b) for a, b in zip(bounds.to_go, chain.to_go)),
    )


def refuted_by_bounds(
    problem: ReachProblem, bounds: HorizonBounds, L_max: int, exact: bool, opts: LazyOptions, counters: dict
) -> LoopOutcome:
    """The answer when the bounds alone exceed ``max_horizon``: ``infeasible`` when the
    proved bound does (or the search is exact), else ``unknown`` (no plan through the
    abstraction: not a proof)."""
    proved, bfs, box = bounds.proved, bounds.bfs, bounds.box
    if proved > L_max:
        if (bounds.physical if opts.lower_bound else physical_lower_bound(problem)) >= 1 << 30:
            why = "the dynamics and bounds allow no displacement toward the goal"
        elif math.isinf(proved):
            why = (
                "the goal is not connected to the start in the free space"
                if math.isinf(bfs)
                else "no position reaches the goal by bounded displacements through the free space"
            )
        else:
            why = f"every trajectory needs at least {int(proved)} steps (bounded displacement through the free space)"
        return LoopOutcome(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max}: {why}")
    if math.isinf(bfs):
        why = "the goal regions are not connected to the start regions"
    elif math.isinf(box):
        why = f"no position in the regions reaches the goal within {L_max} steps of bounded displacement"
    else:
        why = f"the region-hop lower bound on the horizon ({bounds.first}) exceeds max_horizon"
    if exact:
        how = EXACT_SEGMENTS if opts.segment_safe else EXACT_SAMPLES
        return LoopOutcome(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max}: {why} ({how})")
    counters["abstraction_refuted"] = L_max
    return LoopOutcome(
        ReachStatus.UNKNOWN,
        L_max,
        f"no plan through the abstraction up to horizon {L_max}: {why}; {not_a_proof(proved)}",
    )


def chain_bounds(
    problem: ReachProblem,
    abstraction: Abstraction,
    graph: RegionGraph,
    transit: TransitCheck | None,
    path: Sequence[int] | None,
) -> ChainBounds | None:
    """The separator chains of :func:`~plansynth.reach.lazy.bounds.separator_bounds` over
    DIS-PLAN's region graph (beyond the paper), or None when they do
    not apply: no multi-step displacement table (integrator chains, whose one-step
    bounds the sweep of :func:`~plansynth.reach.lazy.bounds.time_windows` already
    uses), or more than :data:`~plansynth.reach.lazy.bounds.SEPARATOR_MAX_REGIONS`
    regions. The gaps are those of :func:`~plansynth.reach.lazy.bounds.chain_gaps`,
    raised by the transit layer's LP bound
    (:meth:`~plansynth.reach.lazy.transit.TransitCheck.first_gap`: every smaller gap
    refuted by an LP; exact for a leg out of the start at rest) from the start into the
    guide's first region (``path[1]``; the guide asks for it anyway) and on the legs of
    the chain that gives the horizon bound, for up to :data:`CHAIN_ROUNDS` rounds
    (the chain may move to other legs once these are raised). Each is a lower bound on
    the steps between two samples of a plan through the region graph, as the chains
    need; the transit layer reuses the LPs. Maze-3 with n = 4 random dynamics: horizon
    bound 86 where the sweep gives 17 (no plan below 108); with n = 50, 93 (sweep: 22)."""
    if graph.n_regions > SEPARATOR_MAX_REGIONS:
        return None
    base = chain_gaps(problem, abstraction)
    if base is None:
        return None
    refined: dict[tuple[int, int], int] = {}

    def gap(a: int, b: int) -> int:
        return max(base(a, b), refined.get((a, b), 0))

    if transit is not None and path is not None and len(path) > 1:
        refined[(START, path[1])] = transit.first_gap(START, path[1])
    out = separator_bounds(graph.adjacency, graph.start_regions, graph.goal_regions, gap)
    for _ in range(CHAIN_ROUNDS if transit is not None else 0):
        # (start straight to goal, one region holding both: no leg LP, the box gap stands)
        legs = [
            (a, b) for a, b in zip(out.critical, out.critical[1:]) if (a, b) not in refined and (a, b) != (START, GOAL)
        ]
        if not legs:
            break
        for a, b in legs:
            refined[(a, b)] = transit.first_gap(a, b)
        out = separator_bounds(graph.adjacency, graph.start_regions, graph.goal_regions, gap)
    return out
