"""The lazy SMT planner (Shoukry et al., CDC 2016, Algorithm 1).

::

    abstraction <- convex decomposition of the free space             (Section III)
    for L = lower bound .. max_horizon:
        loop:
            r_0..r_L <- DIS-PLAN(L)        (SAT; UNSAT -> next L)         (Section IV)
            CON-PLAN(r_0..r_L) -> trajectory: done                     (Section V)
                               -> counterexample: add its clause, loop

The loop talks to the continuous side only through :class:`TheoryChecker`: ``check``
maps a region sequence to :class:`~plansynth.reach.conplan.Feasible` or a
:class:`~plansynth.reach.displan.Conflict` (STYLE.md, point 8). The answer is
``infeasible`` only when every horizon up to ``max_horizon`` was refuted (horizons
below the lower bound are refuted by the bound), and ``unknown`` when the budget (time
or iterations, one iteration = one SAT call and its theory check) runs out.

Lower bound on the horizon: the largest of the region-graph distance from a start
region to a goal region (BFS), the distance to the goal along each axis divided by the
largest displacement per step (one small LP per axis and direction), and the first step
at which the displacement-box relaxation reaches the goal along the region graph
(:func:`~plansynth.reach.conplan.time_windows`, beyond the paper; it also gives DIS-PLAN
a time window per region).

>>> from plansynth.reach.families import maze
>>> r = plan_lazy(maze(1))
>>> r.status.value, r.horizon == len(r.regions) - 1, r.guarantee
('found', True, 'segments')
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Protocol

from plansynth.budget import Budget, Clock
from plansynth.reach.conplan import ConPlan, Feasible, LpBudgetExhausted, LpFailure, physical_lower_bound, time_windows
from plansynth.reach.decompose import Abstraction, abstract
from plansynth.reach.displan import Conflict, DisPlan, RegionGraph, SatOutcome
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.trajectory import Trajectory

__all__ = ["TheoryChecker", "LoopOutcome", "lazy_loop", "plan_lazy"]

ProgressFn = Callable[[int, int], None]  # (horizon, iterations so far)


class TheoryChecker(Protocol):
    """The theory side of the lazy loop (CON-PLAN or any other)."""

    def check(self, regions: Sequence[int]) -> Feasible | Conflict:
        """A trajectory following ``regions`` or a counterexample clause."""
        ...


def plan_lazy(
    problem: ReachProblem,
    budget: Budget = Budget(),
    *,
    abstraction: Abstraction | None = None,
    max_horizon: int | None = None,
    counterexample: str = "zeroprefix",
    segment_safe: bool = True,
    generalize: bool = True,
    minimize: bool = True,
    slack_weights: str = "geometric",
    cardinality: str = "auto",
    lower_bound: bool = True,
    progress: ProgressFn | None = None,
) -> ReachResult:
    """Algorithm 1 on ``problem`` within ``budget``; the trajectory is *not* yet
    validated here (:func:`plansynth.reach.solve` does that).

    ``max_horizon`` overrides the problem's. ``counterexample``, ``generalize`` and
    ``slack_weights`` choose how CON-PLAN explains an infeasible sequence (see
    :mod:`plansynth.reach.conplan`; ``counterexample="zeroprefix", generalize=False,
    slack_weights="uniform"`` is the paper's method as published). ``segment_safe``
    constrains whole segments, not only samples. ``lower_bound=False`` starts at
    horizon 0 without time windows. ``progress(L, iterations)`` is called when a
    horizon starts.
    """
    t_start = time.perf_counter()
    clock = budget.clock()
    L_max = problem.max_horizon if max_horizon is None else int(max_horizon)
    options = {
        "counterexample": counterexample,
        "segment_safe": segment_safe,
        "generalize": generalize,
        "minimize": minimize,
        "slack_weights": slack_weights,
        "cardinality": cardinality,
        "max_horizon": L_max,
        "lower_bound": lower_bound,
        "budget": {"seconds": budget.seconds, "iterations": budget.iterations},
    }
    timings = {"abstraction": 0.0, "bounds": 0.0, "sat": 0.0, "lp": 0.0}
    if abstraction is None:
        t0 = time.perf_counter()
        abstraction = abstract(problem)
        timings["abstraction"] = time.perf_counter() - t0
    graph = RegionGraph.from_abstraction(abstraction)
    counters: dict = {"regions": graph.n_regions, "edges": sum(map(len, graph.adjacency)) // 2}

    t0 = time.perf_counter()
    bfs = graph.horizon_lower_bound()
    phys = physical_lower_bound(problem) if lower_bound else 0
    windows = time_windows(problem, abstraction, L_max) if (lower_bound and math.isfinite(bfs)) else None
    timings["bounds"] = time.perf_counter() - t0
    counters["bfs_bound"] = None if math.isinf(bfs) else int(bfs)
    counters["physical_bound"] = phys
    box = windows.horizon if windows is not None else 0
    counters["box_bound"] = None if math.isinf(box) else int(box)
    if not math.isfinite(bfs) or not math.isfinite(box):
        first = L_max + 1
    else:
        first = int(max(bfs, phys, box)) if lower_bound else 0
    counters["first_horizon"] = first
    guarantee = "segments" if segment_safe else "samples"

    displan = DisPlan(
        graph,
        cardinality=cardinality,
        earliest=windows.earliest if windows is not None else None,
        to_go=windows.to_go if windows is not None else None,
    )
    conplan = ConPlan(problem, abstraction, segment_safe=segment_safe, counterexample=counterexample,
                      generalize=generalize, minimize=minimize, slack_weights=slack_weights, clock=clock)

    def finish(out: LoopOutcome) -> ReachResult:
        st = conplan.stats
        counters.update(
            iterations=clock.iterations,
            sat_calls=displan.sat_calls,
            clauses=displan.clauses,
            window_clauses=displan.window_clauses,
            conflicts=len(displan.conflicts),
            lp_calls=st.lp_calls,
            lp_calls_by_kind=dict(st.by_kind),
            iis_calls=st.iis_calls,
            ray_calls=st.ray_calls,
            certified=st.certified,
            rejected=st.rejected,
            lp_retries=st.retries,
            ipm_fallbacks=st.ipm_fallbacks,
            slack_failures=st.slack_failures,
            horizon=out.horizon,
        )
        timings["highs"] = st.seconds
        timings["total"] = time.perf_counter() - t_start
        displan.delete()
        return ReachResult(
            status=out.status, planner="lazy-smt", seconds=timings["total"], trajectory=out.trajectory,
            regions=out.regions, segment_safe=None, horizon=out.horizon, counters=counters, timings=timings,
            options=options, message=out.message, guarantee=guarantee,
        )

    if first > L_max:
        if math.isinf(bfs):
            why = "the goal regions are not connected to the start regions"
        elif math.isinf(box):
            why = f"no position can reach the goal within {L_max} steps of bounded displacement"
        else:
            why = f"the lower bound on the horizon ({first}) exceeds max_horizon"
        return finish(LoopOutcome(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max}: {why}"))
    return finish(lazy_loop(displan, conplan, range(first, L_max + 1), clock, timings, progress))


@dataclass(frozen=True)
class LoopOutcome:
    """What :func:`lazy_loop` ends with (the horizon as in :class:`ReachResult`)."""

    status: ReachStatus
    horizon: int | None
    message: str
    trajectory: Trajectory | None = None
    regions: tuple[int, ...] | None = None


def lazy_loop(
    displan: DisPlan,
    theory: TheoryChecker,
    horizons: range,
    clock: Clock,
    timings: dict[str, float],
    progress: ProgressFn | None = None,
) -> LoopOutcome:
    """Algorithm 1, the loop: for each horizon L, ask DIS-PLAN for a region sequence,
    ask the theory to realise it, learn its counterexample, until a trajectory is found
    or DIS-PLAN is UNSAT (then the next L). Adds the seconds spent in the SAT solver
    and in the theory to ``timings["sat"]`` and ``timings["lp"]``."""
    L = horizons.start
    try:
        for L in horizons:
            if progress is not None:
                progress(L, clock.iterations)
            while True:
                if clock.exhausted():
                    return LoopOutcome(ReachStatus.UNKNOWN, L, f"budget ran out at horizon {L} after {clock.iterations} iterations")
                clock.tick()
                t0 = time.perf_counter()
                outcome, plan = displan.solve(L, clock)
                timings["sat"] += time.perf_counter() - t0
                if outcome is SatOutcome.INTERRUPTED:
                    return LoopOutcome(ReachStatus.UNKNOWN, L, f"budget ran out in the SAT solver at horizon {L}")
                if outcome is SatOutcome.UNSAT:
                    displan.close(L)
                    break
                assert plan is not None
                t0 = time.perf_counter()
                answer = theory.check(plan)
                timings["lp"] += time.perf_counter() - t0
                if isinstance(answer, Feasible):
                    return LoopOutcome(ReachStatus.FOUND, L, f"found at horizon {L}", answer.trajectory, plan)
                displan.learn(answer)
    except LpBudgetExhausted:
        return LoopOutcome(ReachStatus.UNKNOWN, L, f"budget ran out in the LP solver at horizon {L}")
    except LpFailure as exc:
        return LoopOutcome(ReachStatus.UNKNOWN, L, f"{exc} at horizon {L}")
    top = horizons[-1] if len(horizons) else horizons.start - 1
    return LoopOutcome(ReachStatus.INFEASIBLE, top, f"infeasible: every horizon up to {top} refuted")
