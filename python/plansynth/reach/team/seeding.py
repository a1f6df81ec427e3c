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
order changes. ``incumbent="auto"`` seeds a team only where the seed pays
(:func:`seed_pays`: at least :data:`SEED_MIN_ROBOTS` robots, and the robots times the
first horizon at least :data:`SEED_MIN_WORK`), with at most :data:`SEED_SHARE` of the
budget. On a small team the joint search is as quick as prioritized planning, and a
seed adds its time without saving any (four robots in a room, first horizon 17: the
seed took two thirds of the run, and its horizon, 19, was not the least). A team under
disturbances is not seeded (prioritized planning plans no disturbance). The robots'
decompositions and bounds (:func:`~plansynth.reach.team.setup.prepare`) are made once,
for the rule, the seed and the search.
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

__all__ = ["run", "seed_pays", "SEED_MIN_ROBOTS", "SEED_MIN_WORK", "SEED_SHARE"]

#: ``incumbent="auto"`` seeds teams of at least this many robots
SEED_MIN_ROBOTS = 4
#: ... whose robots times first horizon (the joint search's first SAT question's size) is at least this
SEED_MIN_WORK = 100
#: the share of the budget that the seed may take
SEED_SHARE = 0.7


def seed_pays(problem: TeamProblem, first: float) -> bool:
    """Does ``incumbent="auto"`` seed ``problem``, whose first horizon (the robots'
    largest lower bound, :func:`~plansynth.reach.team.setup.prepare`) is ``first``?

    >>> from plansynth.reach.team.families import antipodal, room_corners
    >>> seed_pays(antipodal(8), 17), seed_pays(room_corners(), 17)
    (True, False)
    """
    n = problem.n_robots
    return n >= SEED_MIN_ROBOTS and (math.isinf(first) or n * first >= SEED_MIN_WORK)


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
    try:  # the robots' decompositions and bounds, once for the rule, the seed and the search
        setup = prepare(problem, L_max, seed_budget.clock())
    except BudgetExhausted:
        setup = None
    if options.incumbent == "auto" and setup is not None and not seed_pays(problem, setup.first):
        spent = time.perf_counter() - t0  # (the setup, made here, outside the planner's own time)
        out = plan_team_lazy(problem, _rest(clock), options, progress, setup=setup)
        timings = {**out.timings, "total": out.timings.get("total", 0.0) + spent}
        return replace(out, timings=timings, seconds=out.seconds + spent)
    seed = plan_prioritized(problem, seed_budget, PrioritizedOptions(max_horizon=L_max), setup=setup)
    spent = time.perf_counter() - t0
    found = seed if seed.status is ReachStatus.FOUND else None
    out = plan_team_lazy(problem, _rest(clock), options, progress, seed=found, setup=setup)
    counters = {
        **out.counters,
        "seed_seconds": spent,
        "seed_horizon": seed.horizon if seed.status is ReachStatus.FOUND else None,
    }
    timings = {**out.timings, "seed": spent, "total": out.timings.get("total", 0.0) + spent}
    return replace(out, counters=counters, timings=timings, seconds=out.seconds + spent)


def _rest(clock: Any) -> Budget:
    """What is left of the run's budget."""
    left = clock.remaining()
    return Budget(seconds=None if math.isinf(left) else max(left, 0.01))
