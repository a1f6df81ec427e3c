"""The ``lazy-smt-team`` planner as registered: the joint lazy SMT planner
(:func:`~plansynth.reach.team.lazy.plan_team_lazy`), for large teams after a plan of
prioritized planning (:func:`~plansynth.reach.team.prioritized.plan_prioritized`) as
its incumbent (a primal heuristic, as MILP solvers run them before branching).

A prioritized plan is a plan of the joint encoding (each earlier robot is a moving
obstacle through its samples: the side it keeps from it during a step is a pair's
side), so it is a plan the lazy loop may return. With it, the loop tries the horizons
below the incumbent's first, each set aside after a few refuted plans, and then the
incumbent's own, where DIS-PLAN proposes the incumbent first. The search stays
complete (a horizon set aside is revisited when the incumbent's fails); only its
order changes. ``incumbent="auto"`` seeds teams of :data:`SEED_MIN_ROBOTS` robots or more,
with at most :data:`SEED_SHARE` of the budget. A team under disturbances is not seeded
(prioritized planning plans no disturbance). The robots' decompositions and bounds
(:func:`~plansynth.reach.team.setup.prepare`) are made once, for the seed and the search.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from typing import Any

from plansynth.budget import Budget, BudgetExhausted
from plansynth.reach.result import ReachStatus
from plansynth.reach.team.lazy import plan_team_lazy
from plansynth.reach.team.options import PrioritizedOptions, TeamLazyOptions
from plansynth.reach.team.prioritized import plan_prioritized
from plansynth.reach.team.problem import TeamProblem
from plansynth.reach.team.result import TeamResult
from plansynth.reach.team.robust import is_disturbed
from plansynth.reach.team.setup import prepare

__all__ = ["run", "SEED_MIN_ROBOTS", "SEED_SHARE"]

#: ``incumbent="auto"`` seeds teams of at least this many robots
SEED_MIN_ROBOTS = 4
#: the share of the budget that the seed may take
SEED_SHARE = 0.7


def run(problem: TeamProblem, budget: Budget, options: TeamLazyOptions, progress: Any = None) -> TeamResult:
    """The registry's entry for ``lazy-smt-team`` (see the module docstring)."""
    seeded = options.incumbent == "prioritized" or (options.incumbent == "auto" and problem.n_robots >= SEED_MIN_ROBOTS)
    if is_disturbed(problem):  # prioritized planning plans no disturbance: no incumbent
        seeded = False
    if not seeded:
        return plan_team_lazy(problem, budget, options, progress)
    t0 = time.perf_counter()
    clock = budget.clock()
    share = None if budget.seconds is None else max(SEED_SHARE * budget.seconds, 0.01)
    L_max = problem.max_horizon if options.max_horizon is None else options.max_horizon
    seed_budget = Budget(seconds=share)
    try:  # the robots' decompositions and bounds, once for the seed and the search
        setup = prepare(problem, L_max, seed_budget.clock())
    except BudgetExhausted:
        setup = None
    seed = plan_prioritized(problem, seed_budget, PrioritizedOptions(max_horizon=L_max), setup=setup)
    spent = time.perf_counter() - t0
    left = clock.remaining()
    rest = Budget(seconds=None if math.isinf(left) else max(left, 0.01))
    found = seed if seed.status is ReachStatus.FOUND else None
    out = plan_team_lazy(problem, rest, options, progress, seed=found, setup=setup)
    counters = {
        **out.counters,
        "seed_seconds": spent,
        "seed_horizon": seed.horizon if seed.status is ReachStatus.FOUND else None,
    }
    timings = {**out.timings, "seed": spent, "total": out.timings.get("total", 0.0) + spent}
    return replace(out, counters=counters, timings=timings, seconds=out.seconds + spent)
